"""Round-3 attack regressions for HPolytope and the two-arm sums (seeded, independent checks)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.geometry import combine
from polyell.geometry.combine import intersection, minkowski_sum
from polyell.geometry.hpolytope import require_drawable

BOX_A = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]


def _embedded(rng: np.random.Generator, m: int, k: int):
    """A random k-polytope embedded in R^m by a frame: rows with equality pairs, and its
    rows (Ak, bk) in frame coordinates y = F^T (x - c)."""
    U = np.linalg.qr(rng.normal(size=(m, m)))[0]
    F, N = U[:, :k], U[:, k:]
    c = rng.normal(size=m)
    V = rng.normal(size=(12, k))
    if k == 1:
        Ak, bk = np.array([[1.0], [-1.0]]), np.array([V.max(), -V.min()])
        volume = float(V.max() - V.min())
    else:
        hull = ConvexHull(V)
        Ak, bk = hull.equations[:, :-1], -hull.equations[:, -1]
        volume = float(hull.volume)
    A = np.vstack([Ak @ F.T, N.T, -N.T])
    b = np.r_[bk + Ak @ F.T @ c, N.T @ c, -N.T @ c]
    return A, b, Ak, bk, F, c, volume


def _chebyshev_radius(A: np.ndarray, b: np.ndarray) -> float:
    norms = np.linalg.norm(A, axis=1)
    k = A.shape[1]
    res = linprog(
        np.r_[np.zeros(k), -1.0],
        np.hstack([A, norms[:, None]]),
        b,
        bounds=[(None, None)] * k + [(0, None)],
        method="highs",
    )
    assert res.status == 0
    return float(res.x[-1])


# --- 1. the centre of a flat set is the Chebyshev centre within its affine hull ----------


def test_segment_centre_is_its_midpoint():
    P = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 0, 0])
    assert P.dim == 1
    np.testing.assert_allclose(P.center, [0.0, 0.0], atol=1e-12)
    assert P.ball_radius == pytest.approx(1.0, rel=1e-12)
    Q = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [4, 0, 2, -2])  # [0, 4] x {2}
    np.testing.assert_allclose(Q.center, [2.0, 2.0], atol=1e-12)
    assert Q.ball_radius == pytest.approx(2.0, rel=1e-12)


def test_embedded_polytopes_ball_radius_and_volume_match_their_frame():
    """24 of 26 such sets had ball_radius 0 (the centre on a vertex); 5-D in R^6 raised a
    raw ValueError in volume.  Checked against linprog's Chebyshev radius and Qhull's
    volume in frame coordinates."""
    rng = np.random.default_rng(4)
    for m in (3, 4, 5, 6):
        for k in range(1, m):
            A, b, Ak, bk, F, c, volume = _embedded(rng, m, k)
            P = pe.HPolytope(A, b)
            assert P.dim == k
            assert P.volume == pytest.approx(volume, rel=1e-8)
            radius = _chebyshev_radius(Ak, bk)
            assert P.ball_radius == pytest.approx(radius, rel=1e-6), (m, k)
            assert P.contains(P.center)
            # the centre's own ball in frame coordinates: its least distance to a row
            y = F.T @ (P.center - c)
            least = float(((bk - Ak @ y) / np.linalg.norm(Ak, axis=1)).min())
            assert least == pytest.approx(radius, rel=1e-6)


def test_compare_of_a_flat_hpolytope_matches_the_zonotope():
    arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6], com=[0.5, 0.4, 0.25])
    Z = pe.analyze(arm.dynamics([np.pi / 6, 0, 0]), tau_max=[100, 30, 4]).polytope
    assert Z.dim == 1
    H = pe.HPolytope(np.vstack([Z.A, Z.A_eq, -Z.A_eq]), np.r_[Z.b, Z.b_eq, -Z.b_eq])
    assert H.dim == 1
    assert H.ball_radius == pytest.approx(Z.volume / 2, rel=1e-9)
    np.testing.assert_allclose(H.center, Z.center, atol=1e-9 * np.linalg.norm(Z.center))


# --- 2. a flat pointed cone keeps its apex ----------------------------------------------


@pytest.mark.parametrize(
    ("A", "b", "apex"),
    [
        ([[-1, 0], [0, 1], [0, -1]], [0, 0, 0], [0, 0]),  # ray x >= 0, y = 0
        ([[-1, 0], [0, 1], [0, -1]], [-2, 1, -1], [2, 1]),  # ray x >= 2, y = 1
        ([[-1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], [0, 0, 1, -1], [0, 0, 1]),  # quadrant
    ],
)
def test_flat_pointed_cone_has_its_apex(A, b, apex):
    P = pe.HPolytope(A, b)
    assert not P.is_bounded
    assert len(P.vertices) == 1
    np.testing.assert_allclose(P.vertices[0], apex, atol=1e-12)
    # brute force: every generated point conv(V) + cone(R) satisfies the rows
    rng = np.random.default_rng(0)
    x = P.vertices[0] + rng.uniform(0, 5, size=(200, len(P.rays))) @ P.rays
    assert (np.asarray(A) @ x.T <= np.asarray(b, float)[:, None] + 1e-9).all()


def test_half_plane_in_r3_has_a_point():
    P = pe.HPolytope([[-1, 0, 0], [0, 0, 1], [0, 0, -1]], [0, 0, 0])
    assert P.dim == 2
    assert len(P.vertices) == 1
    np.testing.assert_allclose(P.vertices[0][[0, 2]], [0.0, 0.0], atol=1e-12)


# --- 3. sets touching along a face: flatness by the rounding of the offsets ------------


def test_boxes_sharing_an_edge_meet_in_a_segment():
    box = pe.HPolytope(BOX_A, [1, 1, 1, 1])
    np.testing.assert_array_equal(box.b, [1.0, 1.0, 1.0, 1.0])  # the rows as given
    other = pe.HPolytope(BOX_A, [3, -1, 1, 1])
    for S in (
        intersection(box, other),
        pe.HPolytope(BOX_A * 2, [1 + 4.5e-16, 1, 1, 1, 3, -1, 1, 1]),
    ):
        assert S.dim == 1
        assert S.volume == pytest.approx(2.0, rel=1e-12)
        lim = S.limits([1.0, 0.0])
        assert float(lim.lo) == pytest.approx(1.0) and float(lim.hi) == pytest.approx(1.0)


def test_a_thin_slab_above_rounding_stays_solid():
    S = pe.HPolytope(BOX_A * 2, [1, 1, 1, 1, 3, -(1 - 1e-9), 1, 1])
    assert S.dim == 2
    assert S.volume == pytest.approx(2e-9, rel=1e-6)


def test_cubes_sharing_a_face_meet_in_a_square():
    A = np.vstack([np.eye(3), -np.eye(3)])
    c1 = pe.HPolytope(A, np.ones(6))
    c2 = pe.HPolytope(A, [3, 1, 1, -1, 1, 1])
    S = intersection(c1, c2)
    assert S.dim == 2
    assert S.volume == pytest.approx(4.0, rel=1e-12)


# --- 4. from_vertices at extreme scales: refused like the constructor ------------------


@pytest.mark.parametrize("scale", [1e-160, 1e-200, 1e-300, 1e160, 1e200, 1e300])
def test_from_vertices_refuses_unrepresentable_scales(scale):
    V = (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]) + 0.2) * scale
    with pytest.raises(pe.InputError, match="vertices"):
        pe.HPolytope.from_vertices(V)


@pytest.mark.parametrize("scale", [1e-60, 1e60])
def test_from_vertices_at_large_but_representable_scales(scale):
    V = (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]) + 0.2) * scale
    P = pe.HPolytope.from_vertices(V)
    assert P.volume == pytest.approx(0.5 * scale * scale, rel=1e-12)
    t = np.array([1.0, 1.0]) / np.sqrt(2)
    lim = P.limits(t)
    assert float(lim.lo) == pytest.approx(0.2 * np.sqrt(2) * scale, rel=1e-12)
    assert float(lim.hi) == pytest.approx(0.7 * np.sqrt(2) * scale, rel=1e-12)


# --- 5. argument checks ------------------------------------------------------------------


def test_rank_zero_is_refused():
    with pytest.raises(pe.InputError, match="rank"):
        pe.HPolytope(BOX_A, [1, 1, 1, 1], rank=0)


@pytest.mark.parametrize("x", ["ab", [1j, 0], None, [np.nan, 0], [1], [[1, 2, 3]]])
def test_facet_slacks_checks_its_points(x):
    box = pe.HPolytope(BOX_A, [1, 1, 1, 1])
    with pytest.raises(pe.InputError, match="x"):
        box.facet_slacks(x)


def test_facet_slacks_values():
    box = pe.HPolytope(BOX_A, [1, 1, 2, 1])
    x = np.random.default_rng(1).normal(size=(5, 2))
    np.testing.assert_allclose(box.facet_slacks(x), box.b - x @ box.A.T, atol=1e-14)


# --- 7. the hull fallback of a sum keeps the hull's vertices ---------------------------


def test_sum_fallback_uses_the_hull_vertices(monkeypatch):
    """The fallback (a tangent cone too close to call) enumerated the hull's 1238 facets
    again, which failed here (SolverError: cddlib and Qhull); it keeps the hull's vertices."""

    def ambiguous(*args, **kwargs):
        raise combine._Ambiguous

    rng = np.random.default_rng(3)
    P1 = pe.HPolytope.from_vertices(rng.normal(size=(14, 6)))
    P2 = pe.HPolytope.from_vertices(rng.normal(size=(14, 6)) * [1, 2, 1, 3, 1, 1])
    P1, P2 = pe.HPolytope(P1.A, P1.b), pe.HPolytope(P2.A, P2.b)
    monkeypatch.setattr(combine, "_sum_graph", ambiguous)
    S = minkowski_sum(P1, P2)
    sums = (P1.vertices[:, None] + P2.vertices[None]).reshape(-1, 6)
    hull = ConvexHull(sums)
    assert S.volume == pytest.approx(hull.volume, rel=1e-9)
    assert len(S.vertices) == len(hull.vertices)


# --- 8. the drawing refusal fits any set -------------------------------------------------


def test_require_drawable_message_fits_a_users_set():
    ray = pe.HPolytope([[-1, 0], [0, 1], [0, -1]], [0, 0, 0])
    with pytest.raises(pe.InputError, match="bound it first") as info:
        require_drawable(ray, "set")
    assert "draw another posture" not in str(info.value)
    empty = pe.HPolytope([[1, 0], [-1, 0]], [-1, 0])
    with pytest.raises(pe.InputError, match="nothing to draw"):
        require_drawable(empty, "set")


# --- 6. a far smaller summand: its faces to its own size ---------------------------------


def test_sum_with_a_much_smaller_set_keeps_the_increment():
    """A cube of half-width 1e-8 added to a random 3-D polytope: the volume increment was
    off by up to 40% (the small cube's faces decided to the sum's tolerance, one point);
    checked against Qhull on the pairwise sums."""
    rng = np.random.default_rng(3)
    for _ in range(4):
        P1 = pe.HPolytope.from_vertices(rng.normal(size=(20, 3)))
        P2 = pe.HPolytope(np.vstack([np.eye(3), -np.eye(3)]), np.full(6, 1e-8))
        S = minkowski_sum(P1, P2)
        sums = (P1.vertices[:, None] + P2.vertices[None]).reshape(-1, 3)
        increment = ConvexHull(sums).volume - P1.volume
        assert S.volume - P1.volume == pytest.approx(increment, rel=1e-4)
