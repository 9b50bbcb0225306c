"""Two arms on one object: sums and intersections of force polytopes, against brute force.

Support functions add under a Minkowski sum, h_{P1+P2}(d) = h_{P1}(d) + h_{P2}(d) (each by
a linear program over the raw half-spaces of its arm), and its volume is the convex hull's
of all pairwise vertex sums (Qhull); the intersection's directional limits are the
programs over both arms' half-spaces at once.  Tolerances: RTOL_LP (HiGHS).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.geometry.combine import intersection, minkowski_sum
from reference import RTOL_LP, random_directions, random_problem


def force(seed: int, m: int = 3, n: int = 7) -> pe.Analysis:
    return random_problem(seed, m, n, asymmetric=True, gravity=0.05, capacity="force")


def raw(an: pe.Analysis) -> tuple[np.ndarray, np.ndarray]:
    """tau_min <= J^T h + g <= tau_max as A h <= b, from the arm's own matrices."""
    J, g = an.dynamics.J, an.dynamics.g
    return np.vstack([J.T, -J.T]), np.concatenate([an.tau_max - g, g - an.tau_min])


def support(A: np.ndarray, b: np.ndarray, d: np.ndarray) -> float:
    result = linprog(-d, A, b, bounds=[(None, None)] * len(d), method="highs")
    assert result.status == 0
    return float(-result.fun)


@pytest.mark.parametrize(("m", "n"), [(2, 3), (3, 7)])
def test_minkowski_sum_of_two_arms(m, n):
    first, second = force(1, m, n), force(2, m, n)
    S = minkowski_sum(first.polytope, second.polytope)
    sums = (first.polytope.vertices[:, None] + second.polytope.vertices[None]).reshape(-1, m)
    assert S.volume == pytest.approx(ConvexHull(sums).volume, rel=1e-9)
    for d in random_directions(3, 10, m):
        expected = support(*raw(first), d) + support(*raw(second), d)
        reached = float(np.max(S.vertices @ d))
        assert reached == pytest.approx(expected, rel=RTOL_LP, abs=RTOL_LP)
    # the comparator's metrics score it like any set
    from polyell.comparison.metrics import inscribed_scale

    E = first.ellipsoid("chiacchio")
    assert inscribed_scale(E, S) >= inscribed_scale(E, first.polytope) - 1e-9


def test_intersection_of_two_arms():
    first, second = force(3), force(4)
    both = intersection(first.polytope, second.polytope)
    A = np.vstack([raw(first)[0], raw(second)[0]])
    b = np.concatenate([raw(first)[1], raw(second)[1]])
    T = random_directions(5, 10, 3)
    limits = both.limits(T)
    for t, lo, hi in zip(T, limits.lo, limits.hi, strict=True):
        A_line = (A @ t)[:, None]
        ends = []
        for sign in (1.0, -1.0):
            result = linprog([sign], A_line, b, bounds=[(None, None)], method="highs")
            ends.append(np.nan if result.status == 2 else result.x[0])
        assert lo == pytest.approx(ends[0], abs=RTOL_LP * 100, nan_ok=True)
        assert hi == pytest.approx(ends[1], abs=RTOL_LP * 100, nan_ok=True)
    assert np.isfinite(limits.hi).sum() >= 5


def test_disjoint_sets_intersect_in_an_empty_set_and_sums_with_it_are_empty():
    box = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]], [1.0, 1.0, 1.0, 1.0])
    far = pe.HPolytope(box.A, box.b + np.array([-5.0, 5.0, 0.0, 0.0]))  # x in [-6, -4]
    empty = intersection(box, far)
    assert empty.is_empty and empty.volume == 0
    assert minkowski_sum(box, empty).is_empty
    zonotope = pe.Polytope([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], center=[0.0, 0.0])
    total = minkowski_sum(zonotope, box)
    assert total.volume == pytest.approx(zonotope.volume + 4 + 2 * (2 * 2 + 2 * 2), rel=1e-9)


def test_sets_of_different_task_spaces_or_unbounded_ones_are_refused():
    plane = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]], [1, 1, 1, 1])
    space = force(5).polytope
    with pytest.raises(pe.InputError, match="P2: expected a set of the same 2-dimensional"):
        minkowski_sum(plane, space)
    with pytest.raises(pe.InputError, match="different task spaces"):
        intersection(plane, space)
    slab = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0]], [1.0, 1.0])
    with pytest.raises(pe.InputError, match="P2: expected a bounded set"):
        minkowski_sum(plane, slab)
    assert not intersection(plane, slab).is_empty
    with pytest.raises(pe.InputError, match="P1"):
        minkowski_sum("box", plane)


# --- issue 33: sums beyond 3-D, at the speed of their vertex counts -----------------------


def pairwise_hull(P1, P2):
    """Qhull on every sum of two vertices: the reference hull of a sum (up to 5-D)."""
    sums = (P1.vertices[:, None] + P2.vertices[None]).reshape(-1, P1.ambient_dim)
    return sums, ConvexHull(sums)


def same_points(found, expected, atol):
    distance = np.abs(found[:, None, :] - expected[None, :, :]).max(axis=2)
    return bool((distance.min(axis=0) <= atol).all() and (distance.min(axis=1) <= atol).all())


@pytest.mark.parametrize(("m", "n"), [(4, 5), (4, 7), (5, 7)])
def test_sums_of_two_arms_beyond_3d(m, n):
    """SolverError before (the hull of the pairwise sums, then its half-spaces again)."""
    first, second = force(1, m, n), force(2, m, n)
    S = minkowski_sum(first.polytope, second.polytope)
    sums, hull = pairwise_hull(first.polytope, second.polytope)
    scale = float(np.abs(sums).max())
    assert len(S.vertices) == len(hull.vertices)
    assert same_points(S.vertices, sums[hull.vertices], 1e-12 * scale)
    assert S.volume == pytest.approx(hull.volume, rel=1e-9)
    for d in random_directions(4, 10, m):
        expected = support(*raw(first), d) + support(*raw(second), d)
        assert float(np.max(S.vertices @ d)) == pytest.approx(expected, rel=RTOL_LP, abs=RTOL_LP)
    # every facet: the offset is the sum of the arms' supports along its normal
    for a, b in list(zip(S.A, S.b, strict=True))[:: max(1, len(S.b) // 20)]:
        expected = support(*raw(first), a) + support(*raw(second), a)
        assert b == pytest.approx(expected, rel=RTOL_LP, abs=RTOL_LP)


def test_a_6d_sum_of_two_7_joint_arms():
    """Did not return in 20-25 minutes (Qhull on 11,520 pairwise sums, then cddlib); a few
    seconds now.  Against HiGHS: the supports add, and in generic directions the sum's
    maximiser is the sum of the arms' (HiGHS's vertex solutions)."""
    from scipy.spatial import cKDTree

    m, n = 6, 7
    first, second = force(1, m, n), force(2, m, n)
    S = minkowski_sum(first.polytope, second.polytope)
    sums = (first.polytope.vertices[:, None] + second.polytope.vertices[None]).reshape(-1, m)
    scale = float(np.abs(sums).max())
    distance, _ = cKDTree(sums).query(S.vertices)
    assert distance.max() <= 1e-12 * scale  # every vertex is a sum of vertices
    rng = np.random.default_rng(6)
    for d in rng.standard_normal((60, m)):
        ends = [
            linprog(-d, *raw(arm), bounds=[(None, None)] * m, method="highs-ds")
            for arm in (first, second)
        ]
        assert float(np.max(S.vertices @ d)) == pytest.approx(
            -ends[0].fun - ends[1].fun, rel=RTOL_LP, abs=RTOL_LP
        )
        assert np.abs(S.vertices - (ends[0].x + ends[1].x)).max(axis=1).min() <= 1e-7 * scale
    for a, b in list(zip(S.A, S.b, strict=True))[:: len(S.b) // 30]:
        assert b == pytest.approx(support(*raw(first), a) + support(*raw(second), a), rel=RTOL_LP)
    # each facet holds m affinely independent vertices
    slack = S.b[None, :] - S.vertices @ S.A.T
    for on in (slack <= 1e-9 * scale).T[:: len(S.b) // 50]:
        face = S.vertices[on]
        assert np.linalg.matrix_rank(face - face[0], tol=1e-9 * scale) == m - 1


def zonotope_volume(G):
    from itertools import combinations

    m = G.shape[0]
    return 2.0**m * sum(
        abs(np.linalg.det(G[:, list(s)])) for s in combinations(range(G.shape[1]), m)
    )


def test_two_zonotopes_add_to_the_zonotope_of_both_generators():
    """Two 6-D acceleration zonotopes of 7-joint arms: 14 generators, 4760 vertices."""
    from math import comb

    m, n = 6, 7
    first, second = random_problem(1, m, n), random_problem(2, m, n)
    P1, P2 = first.polytope, second.polytope
    S = minkowski_sum(P1, P2)
    G = np.hstack([P1.generators, P2.generators])
    c = P1.center + P2.center
    assert len(S.vertices) == 2 * sum(comb(2 * n - 1, i) for i in range(m))  # general position
    assert len(S.b) == 2 * comb(2 * n, m - 1)
    assert S.volume == pytest.approx(zonotope_volume(G), rel=1e-9)
    for d in random_directions(8, 20, m):
        assert float(np.max(S.vertices @ d)) == pytest.approx(
            c @ d + np.abs(G.T @ d).sum(), rel=1e-12
        )
    assert np.allclose(S.center, c)


@pytest.mark.parametrize("m", [3, 4])
def test_a_zonotope_plus_a_force_set(m):
    zonotope, forces = random_problem(3, m, 6).polytope, force(4, m, 7).polytope
    S = minkowski_sum(zonotope, forces)
    sums, hull = pairwise_hull(zonotope, forces)
    assert same_points(S.vertices, sums[hull.vertices], 1e-12 * float(np.abs(sums).max()))
    assert S.volume == pytest.approx(hull.volume, rel=1e-9)


@pytest.mark.parametrize("m", [2, 3, 4, 5])
def test_parallel_edges_a_set_and_itself(m):
    """P + P = 2 P: every edge of one is parallel to an edge of the other (both move)."""
    P = force(5, m, m + 3).polytope
    S = minkowski_sum(P, P)
    assert same_points(S.vertices, 2 * P.vertices, 1e-12 * float(np.abs(P.vertices).max()))
    assert S.volume == pytest.approx(2.0**m * P.volume, rel=1e-9)
    box = pe.HPolytope(np.vstack([np.eye(m), -np.eye(m)]), np.ones(2 * m))
    other = pe.HPolytope(box.A, np.arange(1.0, 2 * m + 1))  # [-(m + 1 + i), 1 + i]
    boxes = minkowski_sum(box, other)  # a box: every corner of the added intervals
    ends = zip(-(2.0 + m + np.arange(m)), 2.0 + np.arange(m), strict=True)
    corners = np.array(list(itertools.product(*ends)))
    assert same_points(boxes.vertices, corners, 1e-12)
    assert boxes.volume == pytest.approx(np.prod(4.0 + m + 2 * np.arange(m)), rel=1e-12)


def test_a_lower_dimensional_summand_and_a_sum_of_sums():
    """A zonotope of rank 2 in 3-D (a singular configuration) plus a force set, and sums of
    those results (whose vertices came from the walk, or from the zonotope's closed form)."""
    flat = random_problem(6, 3, 2).polytope
    assert flat.dim == 2
    forces = force(7, 3, 7).polytope
    S = minkowski_sum(flat, forces)
    sums, hull = pairwise_hull(flat, forces)
    assert same_points(S.vertices, sums[hull.vertices], 1e-12 * float(np.abs(sums).max()))
    assert S.volume == pytest.approx(hull.volume, rel=1e-9)
    zonotopes = minkowski_sum(random_problem(8, 3, 4).polytope, flat)  # edges not kept
    for first, second in [(S, forces), (zonotopes, S)]:
        total = minkowski_sum(first, second)
        sums, hull = pairwise_hull(first, second)
        assert same_points(total.vertices, sums[hull.vertices], 1e-12 * float(np.abs(sums).max()))
        assert total.volume == pytest.approx(hull.volume, rel=1e-9)


@pytest.mark.parametrize("size", [1e-3, 1e-6, 1e-9])
def test_a_small_set_at_a_large_sets_corner_is_cut_at_the_corner(size):
    """A set far smaller than the other, straddling its corner, is not 'inside' it to the
    larger set's tolerance: the intersection is the quarter inside (a 1e-6 box at a 1e3
    box's corner came back whole, four times its volume)."""
    box = np.vstack([np.eye(2), -np.eye(2)])
    big = pe.geometry.HPolytope(box, np.full(4, 1e3))
    small = pe.geometry.HPolytope(box, np.r_[1e3 + size, 1e3 + size, size - 1e3, size - 1e3])
    for P in (intersection(big, small), intersection(small, big)):
        assert P.volume == pytest.approx(size**2, rel=1e-4)
        np.testing.assert_array_less(P.vertices, 1e3 + 1e-12 * 1e3)
