"""Property suite of the geometry submodules (issue 33): a PolyellError or a valid result.

Covers what tests/test_properties.py does not: the two-arm sets of
:mod:`polyell.geometry.combine`, and the public helpers of :mod:`polyell.geometry.ellipsoid`,
:mod:`~polyell.geometry.directions`, :mod:`~polyell.geometry.inradius`,
:mod:`~polyell.geometry.mvie`, :mod:`~polyell.geometry.outer` and
:mod:`~polyell.geometry.logdet`.  Valid results are checked against independent
computations (scipy's ConvexHull of the pairwise sums, Monte Carlo membership, brute-force
distances, the closed form of a ball's volume), and under a change of units (a set in mm is
1000 times the set in m: volumes scale by 1000^r).  Every example is seeded (derandomized).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.geometry import directions, ellipsoid, inradius, logdet, mvie, outer
from polyell.geometry.combine import intersection, minkowski_sum
from polyell.geometry.subspace import AffineSubspace

JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3, np.nan]
SPECIAL = [np.nan, np.inf, -np.inf, 0.0, -1.0, 1e-300, 1e300]
SCALES = [1e-12, 1e-3, 1.0, 1e3, 1e12]


def outcome(call: Callable[[], Any], argument: str | None = None) -> Any:
    """The call's result, or None for a PolyellError (naming ``argument`` when given).

    Every warning but ProjectedInputWarning is an error; any other exception fails.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", pe.ProjectedInputWarning)
        try:
            return call()
        except pe.PolyellError as exn:
            if argument is not None and isinstance(exn, pe.InputError):
                assert argument in str(exn), (argument, str(exn))
            return None


def zonotope(rng: np.random.Generator, m: int, n: int, scale: float = 1.0) -> pe.Polytope:
    return pe.Polytope(rng.normal(size=(m, n)) * scale, rng.normal(size=m) * scale)


def hull_set(rng: np.random.Generator, m: int, scale: float = 1.0) -> pe.HPolytope:
    return pe.HPolytope.from_vertices(rng.normal(size=(m + 4, m)) * scale)


def scaled(P: pe.Polytope | pe.HPolytope, c: float) -> pe.Polytope | pe.HPolytope:
    if isinstance(P, pe.Polytope):
        return pe.Polytope(P.generators * c, P.center * c)
    return pe.HPolytope(P.A, P.b * c)


@st.composite
def set_pairs(draw: st.DrawFn, dims: tuple[int, ...] = (2, 3, 4)) -> tuple[Any, Any, int]:
    m = draw(st.sampled_from(dims))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    kinds = draw(st.sampled_from(["ZZ", "ZH", "HZ", "HH"]))
    made = []
    for kind in kinds:
        if kind == "Z":
            made.append(zonotope(rng, m, m + draw(st.integers(0, 2))))
        else:
            made.append(hull_set(rng, m))
    return made[0], made[1], m


# --- geometry.combine


@settings(max_examples=30)
@given(pair=set_pairs())
def test_minkowski_sum_is_the_hull_of_the_pairwise_sums(pair):
    P1, P2, m = pair
    S = minkowski_sum(P1, P2)
    sums = (P1.vertices[:, None, :] + P2.vertices[None, :, :]).reshape(-1, m)
    hull = ConvexHull(sums)
    assert S.is_bounded and S.dim == m
    assert S.volume == pytest.approx(hull.volume, rel=1e-9)
    assert np.all(S.contains(sums))
    # every vertex of the sum is a pairwise sum of vertices
    distance = np.min(np.linalg.norm(S.vertices[:, None, :] - sums[None], axis=2), axis=1)
    assert np.all(distance <= 1e-9 * np.abs(sums).max())
    # support functions add: h_S(a) = h_1(a) + h_2(a), from the vertices of each
    T = directions.sphere_directions(16, m)
    size = np.abs(sums).max()

    def support(V: np.ndarray) -> np.ndarray:
        return (V @ T.T).max(axis=0)

    np.testing.assert_allclose(
        support(S.vertices), support(P1.vertices) + support(P2.vertices), atol=1e-9 * size
    )
    lo, hi = S.limits(T)  # lines through the origin: ends on the boundary of the hull
    for end in (lo, hi):
        ok = ~np.isnan(end)
        on = T[ok] * end[ok, None]
        assert np.all(S.contains(on))
        assert np.all(ConvexHull(np.vstack([sums, on])).volume <= hull.volume * (1 + 1e-9))
    # a point outside the hull is outside the sum
    centre = sums.mean(axis=0)
    far = centre + 1.01 * (hull.points[hull.vertices[0]] - centre) * 2.0
    assert not S.contains(far)


@settings(max_examples=20)
@given(pair=set_pairs(), c=st.sampled_from(SCALES))
def test_minkowski_sum_is_symmetric_and_scales_with_the_units(pair, c):
    P1, P2, m = pair
    S = minkowski_sum(P1, P2)
    assert minkowski_sum(P2, P1).volume == pytest.approx(S.volume, rel=1e-9)
    big = minkowski_sum(scaled(P1, c), scaled(P2, c))
    assert big.volume == pytest.approx(S.volume * c**m, rel=1e-8)
    T = directions.sphere_directions(8, m)
    np.testing.assert_allclose(big.limits(T).hi, c * S.limits(T).hi, rtol=1e-8, atol=0)
    np.testing.assert_allclose(
        big.vertices[np.lexsort(big.vertices.T)],
        c * S.vertices[np.lexsort(S.vertices.T)],
        rtol=1e-8,
        atol=1e-12 * c * np.abs(S.vertices).max(),
    )


@settings(max_examples=25)
@given(pair=set_pairs(), seed=st.integers(0, 2**16))
def test_intersection_holds_the_points_of_both(pair, seed):
    P1, P2, m = pair
    inter = intersection(P1, P2)
    rng = np.random.default_rng(seed)
    box = np.vstack([P1.vertices, P2.vertices])
    low, high = box.min(axis=0), box.max(axis=0)
    points = rng.uniform(low, high, (2000, m))
    both = P1.contains(points) & P2.contains(points)
    if inter.is_empty:
        assert not both.any()
        return
    inside = inter.contains(points)
    # membership agrees (a point within rounding of a boundary may go either way)
    disagree = inside != both
    assert disagree.sum() <= 2, disagree.sum()
    assert np.all(P1.contains(inter.vertices)) and np.all(P2.contains(inter.vertices))
    # Monte Carlo volume against the exact one (a 2000-point estimate: 5 standard errors)
    share = both.mean()
    volume = share * np.prod(high - low)
    error = 5 * np.sqrt(max(share * (1 - share), 1e-4) / len(points)) * np.prod(high - low)
    assert abs(inter.volume - volume) <= error + 1e-12
    assert inter.volume <= min(P1.volume, P2.volume) * (1 + 1e-9)


@settings(max_examples=4)
@given(seed=st.integers(0, 2**16), m=st.sampled_from([5, 6]))
def test_sums_in_five_and_six_dimensions_are_exact_and_fast(seed, m):
    rng = np.random.default_rng(seed)
    P1, P2 = zonotope(rng, m, 7), hull_set(rng, m)
    S = minkowski_sum(P1, P2)
    sums = (P1.vertices[:, None, :] + P2.vertices[None, :, :]).reshape(-1, m)
    if m == 5:  # (Qhull on the pairwise sums in 6-D takes seconds: the supports only)
        assert S.volume == pytest.approx(ConvexHull(sums).volume, rel=1e-8)
    assert np.all(S.contains(sums))
    T = directions.sphere_directions(8, m)
    np.testing.assert_allclose(
        (S.vertices @ T.T).max(axis=0),
        (P1.vertices @ T.T).max(axis=0) + (P2.vertices @ T.T).max(axis=0),
        atol=1e-9 * np.abs(sums).max(),
    )


@settings(max_examples=40)
@given(data=st.data(), m=st.sampled_from([2, 3]))
def test_combine_with_wrong_or_degenerate_arguments(data, m):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    good = zonotope(rng, m, m + 1)
    cases = {
        "junk": data.draw(st.sampled_from(JUNK)),
        "other dimension": zonotope(rng, m + 1, m + 1),
        "segment": pe.Polytope(rng.normal(size=(m, 1)), np.zeros(m)),
        "point": pe.Polytope(np.zeros((m, 1)), rng.normal(size=m)),
        "cone": pe.HPolytope(-np.eye(m), np.zeros(m)),
        "empty": pe.HPolytope(np.vstack([np.eye(m)[:1], -np.eye(m)[:1]]), [-1.0, -1.0]),
        "tiny": zonotope(rng, m, m, 1e-9),
        "huge": zonotope(rng, m, m, 1e9),
    }
    name = data.draw(st.sampled_from(sorted(cases)))
    other = cases[name]
    first = data.draw(st.booleans())
    for function in (minkowski_sum, intersection):
        args = (other, good) if first else (good, other)
        result = outcome(lambda f=function, a=args: f(*a), "P1" if first else "P2")
        if name in ("junk", "other dimension"):
            assert result is None
            continue
        if result is None:
            assert function is minkowski_sum and name in ("segment", "point", "cone")
            continue
        assert np.isfinite(result.volume) and result.volume >= 0
        if result.is_empty:  # the empty set, or sets that miss each other (by an LP)
            A = np.vstack([good.A, other.A, other.A_eq, -other.A_eq])
            b = np.concatenate([good.b, other.b, other.b_eq, -other.b_eq])
            feasible = linprog(np.zeros(m), A, b, bounds=[(None, None)] * m).status == 0
            assert name == "empty" or (function is intersection and not feasible)
            continue
        assert np.all(np.isfinite(result.vertices))
        if function is minkowski_sum:  # the sum holds every pairwise sum
            sums = (good.vertices[:, None, :] + other.vertices[None, :, :]).reshape(-1, m)
            assert np.all(result.contains(sums))
        else:
            assert np.all(good.contains(result.vertices))
            assert np.all(other.contains(result.vertices))


def hexagon() -> pe.HPolytope:
    corners = [[1, 0], [0.5, 0.9], [-0.5, 0.9], [-1, 0], [-0.5, -0.9], [0.5, -0.9]]
    return pe.HPolytope.from_vertices(corners)


def test_intersection_with_a_far_larger_set_is_the_smaller_set():
    # Found by this suite: a hexagon of size 1 and a set of size 1e9 (two arms in units
    # a thousand million times apart) intersected to a triangle outside the hexagon.
    far = pe.HPolytope([[1.0, 0.3], [-1.0, 0.2], [0.0, -1.0]], [1e9, 1e9, 1e9])
    inter = intersection(hexagon(), far)
    assert inter.volume == pytest.approx(2.7, rel=1e-12)
    assert np.all(hexagon().contains(inter.vertices)) and len(inter.vertices) == 6


def test_hpolytope_keeps_its_facets_beside_far_redundant_rows():
    # The walk's tolerance was relative to the largest offset: two redundant rows at 1e9
    # (1e-9 of it: the size of the set) put every row through every point (a triangle of
    # volume 1.8).
    H = hexagon()
    A = np.vstack([H.A, [[1.0, 0.3], [-1.0, 0.2]]])
    b = np.concatenate([H.b, [1e9, 1e9]])
    P = pe.HPolytope(A, b)
    assert P.volume == pytest.approx(2.7, rel=1e-9)
    assert len(P.vertices) == 6 and len(P.b) == 6


def box_and_cuts(rng: np.random.Generator, m: int) -> tuple[np.ndarray, np.ndarray]:
    """A bounded set about a point off the origin: a box cut by 2m random rows."""
    cuts = rng.normal(size=(2 * m, m))
    A = np.vstack([np.eye(m), -np.eye(m), cuts / np.linalg.norm(cuts, axis=1)[:, None]])
    centre = rng.normal(size=m) * rng.choice([0.0, 10.0])
    return A, rng.uniform(0.5, 1.5, len(A)) + A @ centre


def same_rows(A, b, A_ref, b_ref, tol):
    """Each row of (A, b) is one of (A_ref, b_ref) and the other way round."""
    gap = np.abs(A[:, None, :] - A_ref[None, :, :]).max(axis=2)
    gap = gap + np.abs(b[:, None] - b_ref[None, :]) / max(1.0, float(np.abs(b_ref).max()))
    return bool((gap.min(axis=1) <= tol).all() and (gap.min(axis=0) <= tol).all())


@settings(max_examples=40)
@given(
    m=st.integers(2, 6),
    seed=st.integers(0, 2**16),
    exponent=st.integers(3, 15),
    far=st.integers(1, 12),
)
def test_far_redundant_rows_change_nothing(m, seed, exponent, far):
    # Rows 1e3 to 1e15 times the set's size away, up to twice as many as the set's: the
    # vertices, facets and volume of the set without them, to rounding.  (Also found: the
    # Chebyshev centre, solved in units of the median offset, left the set where most rows
    # were far.)
    rng = np.random.default_rng(seed)
    A, b = box_and_cuts(rng, m)
    reference = pe.HPolytope(A, b)
    normals = rng.normal(size=(far, m))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    size = float(np.abs(reference.vertices - reference.center).max()) * np.sqrt(m)
    offsets = normals @ reference.center + 10.0**exponent * size * rng.uniform(1, 3, far)
    P = pe.HPolytope(np.vstack([A, normals]), np.concatenate([b, offsets]))
    assert P.volume == pytest.approx(reference.volume, rel=1e-9)
    assert len(P.vertices) == len(reference.vertices) and len(P.b) == len(reference.b)
    assert same_rows(
        P.vertices,
        np.zeros(len(P.vertices)),
        reference.vertices,
        np.zeros(len(reference.vertices)),
        1e-9 * (size + np.abs(b).max()),
    )
    assert same_rows(P.A, P.b, reference.A, reference.b, 1e-9)


# --- geometry.ellipsoid helpers


@given(r=st.integers(0, 12))
def test_unit_ball_volume_follows_the_recurrence(r):
    V = ellipsoid.unit_ball_volume
    assert V(0) == pytest.approx(1.0) and V(1) == pytest.approx(2.0)
    assert V(r + 2) == pytest.approx(2 * math.pi / (r + 2) * V(r), rel=1e-12)


@given(value=st.sampled_from([-1, 2.5, "3", None, True, np.nan, 10**7, [2]]))
def test_unit_ball_volume_refuses_what_is_no_dimension(value):
    with pytest.raises(pe.InputError, match="r:"):
        ellipsoid.unit_ball_volume(value)


@given(m=st.integers(1, 6), seed=st.integers(0, 2**16), data=st.data())
def test_canonical_axes_keep_the_ellipsoid(m, seed, data):
    rng = np.random.default_rng(seed)
    r = data.draw(st.integers(1, m))
    U = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :r]
    s = rng.uniform(0.1, 3.0, r)
    axes, semi = ellipsoid.canonical_axes(U, s)
    assert np.all(np.diff(semi) <= 0)
    np.testing.assert_allclose((axes * semi**2) @ axes.T, (U * s**2) @ U.T, atol=1e-12)
    pivots = axes[np.argmax(np.abs(axes), axis=0), np.arange(r)]
    assert np.all(pivots > 0)
    broken = data.draw(st.sampled_from([*JUNK, s[:-1] if r > 1 else s[None], U[0]]))
    which = data.draw(st.sampled_from(["axes", "semi_axes"]))
    arguments = {"axes": U, "semi_axes": s, which: broken}
    result = outcome(lambda: ellipsoid.canonical_axes(**arguments), which)
    if result is not None:  # an accepted value is a consistent pair
        assert result[0].shape[-1] == result[1].shape[-1]


@settings(max_examples=30)
@given(m=st.integers(1, 6), seed=st.integers(0, 2**16), c=st.sampled_from(SCALES))
def test_ellipsoid_from_core_round_trips_and_scales(m, seed, c):
    rng = np.random.default_rng(seed)
    Q = np.linalg.qr(rng.normal(size=(m, m)))[0]
    s = rng.uniform(0.2, 3.0, m) * c
    N = (Q / s**2) @ Q.T
    center = rng.normal(size=m) * c
    E = pe.Ellipsoid.from_core(center, N)
    np.testing.assert_allclose(np.sort(E.semi_axes), np.sort(s), rtol=1e-9)
    assert E.volume == pytest.approx(ellipsoid.unit_ball_volume(m) * np.prod(s), rel=1e-9)
    # support function: a . c + sqrt(a^T N^-1 a)
    a = directions.sphere_directions(5, m) if m > 1 else np.array([[1.0], [-1.0]])
    expected = a @ center + np.sqrt(np.einsum("ka,ab,kb->k", a, (Q * s**2) @ Q.T, a))
    np.testing.assert_allclose(E.support(a), expected, rtol=1e-9, atol=1e-12 * c)


@given(data=st.data(), m=st.integers(1, 4))
def test_ellipsoid_from_core_refuses_bad_cores(data, m):
    core = np.eye(m)
    which = data.draw(st.sampled_from(["center", "core"]))
    value = data.draw(
        st.sampled_from(
            [*JUNK, -np.eye(m), np.zeros((m, m)), np.full((m, m), np.nan), np.eye(m + 1)]
        )
    )
    arguments = {"center": np.zeros(m), "core": core, which: value}
    E = outcome(lambda: pe.Ellipsoid.from_core(arguments["center"], arguments["core"]))
    if E is not None:
        assert np.all(np.isfinite(E.semi_axes)) and np.all(E.semi_axes > 0)


# --- geometry.directions


@given(k=st.integers(1, 64), r=st.integers(0, 6))
def test_sphere_directions_are_unit_and_deterministic(k, r):
    T = directions.sphere_directions(k, r)
    assert T.shape == ((0, 0) if r == 0 else ((2, 1) if r == 1 else (k, r)))
    if r:
        np.testing.assert_allclose(np.linalg.norm(T, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_array_equal(T, directions.sphere_directions(k, r))
    assert directions.default_direction_count(r) >= (0 if r == 0 else 2)


@given(value=st.sampled_from([-1, 2.5, "3", None, True, np.nan, 10**6, [2], np.zeros(3)]))
def test_direction_helpers_refuse_what_is_no_dimension(value):
    with pytest.raises(pe.InputError, match="r:"):
        directions.sphere_directions(4, value)
    with pytest.raises(pe.InputError, match="r:"):
        directions.default_direction_count(value)


@given(m=st.integers(1, 6), seed=st.integers(0, 2**16), data=st.data())
def test_directions_in_lie_in_the_set(m, seed, data):
    rng = np.random.default_rng(seed)
    r = data.draw(st.integers(0, m))
    basis = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :r]
    normals = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :0]
    affine = AffineSubspace(point=np.zeros(m), basis=basis, normals=normals)
    k = data.draw(st.sampled_from([None, 1, 7, 0, -1, 2.5, "x"]))
    T = outcome(lambda: directions.directions_in(affine, k), "directions")
    if T is None:
        assert not (isinstance(k, int) and (k >= 1 or (k == 0 and r == 0)))
        return
    assert T.shape[1] == m
    if r:
        np.testing.assert_allclose(np.linalg.norm(T, axis=1), 1.0, rtol=1e-12)
        residual = T - (T @ basis) @ basis.T
        assert np.abs(residual).max() <= 1e-12
    junk = data.draw(st.sampled_from(JUNK))
    assert outcome(lambda: directions.directions_in(junk), "affine_set") is None


# --- geometry.inradius


@settings(max_examples=25)
@given(m=st.integers(2, 5), seed=st.integers(0, 2**16), c=st.sampled_from(SCALES))
def test_origin_radius_is_the_distance_to_the_boundary(m, seed, c):
    rng = np.random.default_rng(seed)
    K = 4
    U = np.linalg.qr(rng.normal(size=(K, m, m)))[0]
    s = rng.uniform(0.3, 2.0, (K, m))
    center = rng.normal(size=(K, m)) * rng.uniform(0.0, 1.2, (K, 1)) * s.min(axis=1)[:, None]
    radius = inradius.ellipsoid_origin_radius(center, U, s)
    assert radius.shape == (K,) and np.all(radius >= 0) and np.all(np.isfinite(radius))
    # brute force: the nearest of many boundary points; dense enough in 2-D and 3-D to
    # bound the distance from below too (a sampled minimum overstates it by O(spacing^2))
    u = directions.sphere_directions(20000, m)
    tight = {2: 1e-5, 3: 1e-2}.get(m)
    for k in range(K):
        boundary = center[k] + (u * s[k]) @ U[k].T
        nearest = np.linalg.norm(boundary, axis=1).min()
        inside = np.linalg.norm((-center[k] @ U[k]) / s[k]) <= 1
        if not inside:
            assert radius[k] == 0
            continue
        assert radius[k] <= nearest * (1 + 1e-9)
        if tight is not None:
            assert radius[k] >= nearest * (1 - tight)
        ball = radius[k] * (1 - 1e-9) * u  # the ball of that radius is inside
        assert np.all(np.linalg.norm(((ball - center[k]) @ U[k]) / s[k], axis=1) <= 1)
    # units: the radius in mm is 1000 times the radius in m
    np.testing.assert_allclose(
        inradius.ellipsoid_origin_radius(center * c, U, s * c), radius * c, rtol=1e-9
    )


@given(data=st.data())
def test_origin_radius_refuses_bad_arrays_and_marks_unknown_ones(data):
    center, axes, semi = np.zeros((2, 2)), np.stack([np.eye(2)] * 2), np.ones((2, 2))
    which = data.draw(st.sampled_from(["center", "axes", "semi_axes"]))
    value = data.draw(st.sampled_from([*JUNK[:-1], np.zeros(2), np.ones((3, 2)), -np.ones((2, 2))]))
    arguments = {"center": center, "axes": axes, "semi_axes": semi, which: value}
    result = outcome(lambda: inradius.ellipsoid_origin_radius(**arguments), which)
    if result is not None:
        assert np.all(np.isnan(result) | (result >= 0))
    unknown = center.copy()
    unknown[1, 0] = np.nan  # an unknown ellipsoid: NaN, not a radius
    radius = inradius.ellipsoid_origin_radius(unknown, axes, semi)
    assert radius[0] == pytest.approx(1.0) and np.isnan(radius[1])


# --- geometry.mvie, geometry.outer, geometry.logdet


@settings(max_examples=25)
@given(
    m=st.integers(2, 4),
    extra=st.integers(0, 3),
    seed=st.integers(0, 2**16),
    c=st.sampled_from(SCALES),
    hull=st.booleans(),
)
def test_mvie_inside_and_outer_around_and_both_scale(m, extra, seed, c, hull):
    rng = np.random.default_rng(seed)
    P = hull_set(rng, m) if hull else zonotope(rng, m, m + extra)
    inner = mvie.max_volume_inscribed_ellipsoid(P)
    around = outer.min_volume_enclosing_ellipsoid(P)
    u = rng.normal(size=(256, m))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    on_inner = inner.center + (u * inner.semi_axes) @ inner.axes.T
    shrink = inner.center + (1 - 1e-7) * (on_inner - inner.center)
    assert np.all(P.contains(shrink))
    assert np.all(around.contains(P.vertices))
    assert inner.volume <= P.volume * (1 + 1e-9) <= around.volume * (1 + 1e-8)
    big = scaled(P, c)
    assert mvie.max_volume_inscribed_ellipsoid(big).volume == pytest.approx(
        inner.volume * c**m, rel=1e-6
    )
    assert outer.min_volume_enclosing_ellipsoid(big).volume == pytest.approx(
        around.volume * c**m, rel=1e-6
    )


@given(data=st.data())
def test_optimum_ellipsoids_refuse_what_is_no_set(data):
    P = pe.Polytope([[1.0, 0.5, 0.2], [0.0, 1.0, -0.4]], [0.0, 0.0])
    value = data.draw(st.sampled_from(JUNK))
    for function in (mvie.max_volume_inscribed_ellipsoid, outer.min_volume_enclosing_ellipsoid):
        assert outcome(lambda f=function: f(value), "P") is None
        method = data.draw(st.sampled_from([*JUNK, np.array(["logdet"]), "LOGDET"]))
        assert outcome(lambda f=function, v=method: f(P, v), "method") is None
    assert outcome(lambda: outer.whitened_vertices(value), "P") is None
    assert outcome(lambda: mvie.log_det_shape(np.eye(2), value, "x"), "method") is None
    X = data.draw(st.sampled_from([*JUNK, -np.eye(2), np.eye(3), np.array([[1.0, 2.0], [0, 1]])]))
    assert outcome(lambda: mvie.ellipsoid_from_shape(P, X, 0.5, "mvie"), "X") is None
    assert outcome(lambda: mvie.ellipsoid_from_shape(value, np.eye(2), 0.5, "m"), "P") is None


@settings(max_examples=30)
@given(r=st.integers(1, 5), seed=st.integers(0, 2**16), c=st.sampled_from(SCALES))
def test_centred_mvee_encloses_touches_and_scales(r, seed, c):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(r + 3 + rng.integers(0, 6), r))
    result = logdet.centred_mvee(points)
    X = result.shape
    assert 0 <= result.gap <= 1e-8
    values = np.einsum("ia,ab,ib->i", points, X, points)
    assert values.max() == pytest.approx(1.0, abs=1e-12)
    assert np.all(np.linalg.eigvalsh(X) > 0)
    # a point set in mm: the shape of the ellipsoid in (1/mm)^2
    bigger = logdet.centred_mvee(points * c).shape
    np.testing.assert_allclose(bigger * c**2, X, rtol=1e-6, atol=1e-9 * np.abs(X).max())
    # the batch gives the same
    shapes, gaps, _ = logdet.centred_mvee_batch(points[None])
    np.testing.assert_allclose(shapes[0], X, rtol=1e-12)
    assert gaps[0] == result.gap


@given(data=st.data())
def test_centred_mvee_refuses_bad_points(data):
    points = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    value = data.draw(
        st.sampled_from(
            [*JUNK, np.zeros((3, 2)), np.ones((3, 2)), np.full((3, 2), np.inf), points[None]]
        )
    )
    result = outcome(lambda: logdet.centred_mvee(value))
    if result is not None:
        assert np.all(np.isfinite(result.shape))
    batch = outcome(lambda: logdet.centred_mvee_batch(value))
    if batch is not None:
        shapes, gaps, _ = batch
        good = gaps <= 1e-8
        assert np.all(np.isfinite(shapes[good]))
    option = data.draw(st.sampled_from(["gap", "max_iterations"]))
    bad = data.draw(st.sampled_from([*JUNK, -1.0, 0, np.inf, 50]))
    result = outcome(lambda: logdet.centred_mvee(points, **{option: bad}), option)
    number = isinstance(bad, int | float) and not isinstance(bad, bool)
    if option == "gap":
        valid = number and 0 < bad < np.inf
    else:
        valid = isinstance(bad, int) and not isinstance(bad, bool) and bad >= 0
    if not valid:
        assert result is None
    elif result is not None:
        assert result.gap <= (bad if option == "gap" else 1e-8)
