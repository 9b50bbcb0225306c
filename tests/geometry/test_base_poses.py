"""Two arms whose bases differ: ``in_frame`` and the sum of rotated sets, against brute force.

The brute force: each set's vertices mapped by the pose (``R v`` for forces, the wrench
adjoint for wrenches), every pairwise sum, their hull by scipy's ConvexHull, and the
support function ``max_v d . v`` of those points in many directions.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy.spatial import ConvexHull
from scipy.stats import special_ortho_group

import polyell as pe
from polyell.geometry.combine import ROTATION_ATOL, in_frame, intersection, minkowski_sum
from reference import random_problem

Array = NDArray[np.float64]


def rotation(seed: int, k: int) -> Array:
    return np.asarray(special_ortho_group.rvs(k, random_state=seed), dtype=float)


def skew(p: Array) -> Array:
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def adjoint(R: Array, p: Array) -> Array:
    """The wrench adjoint on rows (f, mu): mu about the common origin picks up p x R f."""
    return np.block([[R, np.zeros((3, 3))], [skew(p) @ R, R]])


def unit_directions(seed: int, k: int, m: int) -> Array:
    D = np.random.default_rng(seed).normal(size=(k, m))
    return D / np.linalg.norm(D, axis=1)[:, None]


def support(points: Array, D: Array) -> Array:
    return np.asarray((points @ D.T).max(axis=0))


def same_normals(ours: Array, qhull: Array, atol: float = 1e-7) -> bool:
    """Whether two lists of unit normals hold the same directions (Qhull's repeat per simplex)."""
    from scipy.spatial import cKDTree

    near_ours, _ = cKDTree(ours).query(qhull)
    near_qhull, _ = cKDTree(qhull).query(ours)
    return bool(near_ours.max() < atol and near_qhull.max() < atol)


def force_set(seed: int, m: int, n: int) -> pe.HPolytope:
    """A random arm's force set, gravity well within the limits: bounded, not empty."""
    P = random_problem(seed, m, n, gravity=0.3, capacity="force").polytope
    assert isinstance(P, pe.HPolytope) and P.is_bounded and not P.is_empty
    return P


def check_sum_against_brute_force(
    S: pe.HPolytope, points: Array, seed: int, *, volume: bool = True
) -> None:
    """S is the hull of ``points`` (the pairwise sums): support, vertices, facets, volume."""
    scale = float(np.abs(points).max())
    D = unit_directions(seed, 400, points.shape[1])
    truth = support(points, D)
    # support functions, from S's vertices and from its facets' supporting points
    np.testing.assert_allclose(support(S.vertices, D), truth, rtol=0, atol=1e-9 * scale)
    # every pairwise sum is inside S's half-spaces and each facet touches one
    slack = S.b[:, None] - S.A @ points.T
    assert slack.min() >= -1e-9 * scale
    np.testing.assert_allclose(slack.min(axis=1), 0.0, atol=1e-9 * scale)
    # every vertex of S is a point of the hull: at most its support in every direction
    assert np.all(S.vertices @ D.T <= truth + 1e-9 * scale)
    # the same facets as Qhull's hull of the sums, none missing, none extra
    hull = ConvexHull(points)
    normals = hull.equations[:, :-1] / np.linalg.norm(hull.equations[:, :-1], axis=1)[:, None]
    assert same_normals(S.A, normals)
    if volume:
        np.testing.assert_allclose(S.volume, hull.volume, rtol=1e-9)


# --- in_frame on one set --------------------------------------------------------------------


@pytest.mark.parametrize(("m", "n", "seed"), [(2, 3, 1), (3, 4, 2), (3, 3, 3), (6, 6, 4)])
def test_a_rotated_force_set_is_the_rotated_vertices(m: int, n: int, seed: int) -> None:
    P = force_set(seed, m, n)
    R = rotation(seed + 10, min(m, 3))
    T = R if m < 6 else adjoint(R, np.zeros(3))
    Q = in_frame(P, R)
    D = unit_directions(seed, 300, m)
    scale = float(np.abs(P.vertices).max())
    np.testing.assert_allclose(
        support(Q.vertices, D), support(P.vertices @ T.T, D), atol=1e-9 * scale
    )
    np.testing.assert_allclose(Q.volume, P.volume, rtol=1e-12)
    np.testing.assert_allclose(Q.center, T @ P.center, atol=1e-12 * scale)
    # membership: a point of P, moved, is in Q; a point outside, moved, is not
    inside = P.vertices.mean(axis=0)
    outside = P.vertices[0] + 0.05 * (P.vertices[0] - inside)
    assert bool(Q.contains(T @ inside)) and not bool(Q.contains(T @ outside))


def test_a_rotated_zonotope_stays_a_zonotope() -> None:
    rng = np.random.default_rng(5)
    Z = pe.Polytope(rng.normal(size=(3, 5)), rng.normal(size=3))
    R = rotation(6, 3)
    Y = in_frame(Z, R)
    assert isinstance(Y, pe.Polytope)
    np.testing.assert_allclose(Y.generators, R @ Z.generators, atol=1e-15)
    np.testing.assert_allclose(Y.volume, Z.volume, rtol=1e-12)


def test_a_wrench_set_moves_by_the_adjoint() -> None:
    """mu_common = R mu + p x (R f): checked on the vertices and on one wrench by hand."""
    P = force_set(7, 6, 6)
    R, p = rotation(8, 3), np.array([0.4, -0.3, 1.2])
    W = in_frame(P, R, p)
    Ad = adjoint(R, p)
    D = unit_directions(9, 300, 6)
    scale = float(np.abs(P.vertices @ Ad.T).max())
    np.testing.assert_allclose(
        support(W.vertices, D), support(P.vertices @ Ad.T, D), atol=1e-9 * scale
    )
    np.testing.assert_allclose(W.volume, P.volume, rtol=1e-9)  # det Ad = 1
    # a pure force of 1 N along the base x axis, applied 1 m along the common y axis,
    # about the common origin: its moment is y x (R e_x)
    R0, p0 = np.eye(3), np.array([0.0, 1.0, 0.0])
    np.testing.assert_allclose(adjoint(R0, p0) @ np.r_[1.0, 0, 0, 0, 0, 0], [1, 0, 0, 0, 0, -1])


def test_a_planar_wrench_turns_about_its_normal() -> None:
    """Rows (x, y, wz): a 2 x 2 rotation and an in-plane translation."""
    P = force_set(11, 3, 4)
    P.task = ("x", "y", "wz")
    a = 0.7
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    p = np.array([0.5, -1.5])
    W = in_frame(P, R, p)
    assert W.task == ("x", "y", "wz")
    f = P.vertices[:, :2] @ R.T
    mz = P.vertices[:, 2] + p[0] * f[:, 1] - p[1] * f[:, 0]
    moved = np.column_stack([f, mz])
    D = unit_directions(12, 300, 3)
    np.testing.assert_allclose(
        support(W.vertices, D), support(moved, D), atol=1e-9 * np.abs(moved).max()
    )


def test_a_set_that_is_not_bounded_keeps_its_rays() -> None:
    """A half-plane strip, unbounded along y in the base frame: along R e_y after."""
    P = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0]], [1.0, 1.0])
    a = 0.3
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    Q = in_frame(P, R)
    assert not Q.is_bounded
    along = R @ np.array([0.0, 1.0])
    assert np.all(np.isinf(Q.limits(np.array([along, -along])).hi))
    np.testing.assert_allclose(Q.limits(R @ np.array([1.0, 0.0])).hi, 1.0, atol=1e-12)


# --- two arms: the sum of rotated sets --------------------------------------------------


@pytest.mark.parametrize(("m", "n1", "n2", "seed"), [(2, 3, 4, 20), (3, 4, 5, 21), (3, 3, 4, 22)])
def test_sum_of_two_rotated_force_sets_is_the_hull_of_rotated_vertex_sums(
    m: int, n1: int, n2: int, seed: int
) -> None:
    P1, P2 = force_set(seed, m, n1), force_set(seed + 100, m, n2)
    R1, R2 = rotation(seed + 1, m), rotation(seed + 2, m)
    S = minkowski_sum(in_frame(P1, R1), in_frame(P2, R2))
    points = ((P1.vertices @ R1.T)[:, None, :] + (P2.vertices @ R2.T)[None, :, :]).reshape(-1, m)
    check_sum_against_brute_force(S, points, seed)
    # and it differs from the sum with both bases aligned (the poses matter)
    aligned = minkowski_sum(P1, P2)
    D = unit_directions(seed, 50, m)
    assert np.abs(support(aligned.vertices, D) - support(S.vertices, D)).max() > 1e-3


def test_sum_of_two_wrench_sets_at_two_base_poses_6d() -> None:
    """Two 6-joint arms' wrench sets (parallelotopes in 6-D), each moved by its adjoint."""
    P1, P2 = force_set(30, 6, 6), force_set(31, 6, 6)
    R1, R2 = rotation(32, 3), rotation(33, 3)
    p1, p2 = np.array([0.5, 0.0, 0.2]), np.array([-0.5, 0.1, 0.2])
    S = minkowski_sum(in_frame(P1, R1, p1), in_frame(P2, R2, p2))
    V1, V2 = P1.vertices @ adjoint(R1, p1).T, P2.vertices @ adjoint(R2, p2).T
    points = (V1[:, None, :] + V2[None, :, :]).reshape(-1, 6)
    check_sum_against_brute_force(S, points, 34)


def test_intersection_of_rotated_sets_is_checked_pointwise() -> None:
    P1, P2 = force_set(40, 3, 4), force_set(41, 3, 4)
    R1, R2 = rotation(42, 3), rotation(43, 3)
    Q1, Q2 = in_frame(P1, R1), in_frame(P2, R2)
    both = intersection(Q1, Q2)
    rng = np.random.default_rng(44)
    low = np.minimum(Q1.vertices.min(axis=0), Q2.vertices.min(axis=0))
    high = np.maximum(Q1.vertices.max(axis=0), Q2.vertices.max(axis=0))
    x = rng.uniform(low, high, size=(4000, 3))
    # membership in each rotated set, decided in its own base frame with P's half-spaces
    in1 = np.all((x @ R1) @ P1.A.T <= P1.b, axis=1)
    in2 = np.all((x @ R2) @ P2.A.T <= P2.b, axis=1)
    assert np.array_equal(both.contains(x), in1 & in2)


# --- refused input -----------------------------------------------------------------------


def test_not_a_rotation_is_refused() -> None:
    P = force_set(50, 3, 4)
    with pytest.raises(pe.InputError, match="rotation") as caught:
        in_frame(P, np.diag([1.0, 1.0, 1.001]))
    assert caught.value.argument == "rotation"
    with pytest.raises(pe.InputError, match="reflection"):
        in_frame(P, np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(pe.InputError, match=r"shape|\(3, 3\)"):
        in_frame(P, np.eye(2))
    with pytest.raises(pe.InputError):
        in_frame(P, [[np.nan, 0, 0], [0, 1, 0], [0, 0, 1]])
    # within the tolerance: taken as the nearest rotation
    nearly = rotation(51, 3) + 0.1 * ROTATION_ATOL
    assert in_frame(P, nearly).volume == pytest.approx(P.volume, rel=1e-12)


def test_a_translation_of_a_force_set_is_refused() -> None:
    P = force_set(52, 3, 4)
    with pytest.raises(pe.InputError, match="free vectors") as caught:
        in_frame(P, np.eye(3), [0.0, 0.0, 1.0])
    assert caught.value.argument == "translation"


def test_rows_the_pose_does_not_map_onto_themselves_are_refused() -> None:
    P = force_set(53, 3, 4)
    turn = rotation(54, 2)
    with pytest.raises(pe.InputError) as caught:  # wx turns into wy, which the set lacks
        in_frame(P, turn, task=("x", "y", "wx"))
    assert caught.value.argument == "rotation"
    with pytest.raises(pe.InputError, match="x1"):
        in_frame(force_set(56, 4, 5), np.eye(3))  # rows x1..x4: no frame
    with pytest.raises(pe.InputError) as caught:
        in_frame("P", np.eye(3))  # type: ignore[call-overload]
    assert caught.value.argument == "P"
    four = force_set(57, 4, 5)  # rows x, y, z, wz: p x f has wx and wy parts
    with pytest.raises(pe.InputError) as caught:
        in_frame(four, np.eye(3), [0.0, 0.0, 1.0], task=("x", "y", "z", "wz"))
    assert caught.value.argument == "translation"
    a = 0.4  # a turn about z maps x, y, z, wz onto themselves
    Rz = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    turned = in_frame(four, Rz, task=("x", "y", "z", "wz"))
    T = np.eye(4)
    T[:3, :3] = Rz
    D = unit_directions(58, 100, 4)
    np.testing.assert_allclose(
        support(turned.vertices, D), support(four.vertices @ T.T, D), atol=1e-9 * four.extent
    )
    with pytest.raises(pe.InputError) as caught:  # a turn about x moves wz into wy
        in_frame(four, Rz[[2, 0, 1]][:, [2, 0, 1]], task=("x", "y", "z", "wz"))
    assert caught.value.argument == "rotation"
