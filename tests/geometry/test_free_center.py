"""Optimal ellipsoids of H-polytopes (free centre) against closed forms.

A box [c - a, c + a] has the MVIE of semi-axes a about c and the outer ellipsoid of
semi-axes sqrt(m) a; a triangle has the Steiner inellipse (area pi / (3 sqrt 3) times the
triangle's, centred at the centroid) and the Steiner circumellipse (4 pi / (3 sqrt 3) times).
Tolerances: both optima are certified to 1e-8 in log det (so volumes to ~1e-8); a centre,
where log det is flat, is known to about the square root of the gap: 1e-4 of the set's size.

The inscribed one (free centre) is the batched interior-point method of
:func:`~polyell.geometry.free_center.free_center_mvie_batch`, checked below against cvxpy +
Clarabel (SCS where Clarabel reports an inaccurate optimum), closed forms (boxes and
simplices), its own certificate and its inscription by construction.
"""

from __future__ import annotations

import math
import subprocess
import sys
import warnings

import numpy as np
import pytest

import polyell as pe
from polyell.geometry.free_center import _frame, free_center_mvie, free_center_mvie_batch
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from polyell.geometry.outer import min_volume_enclosing_ellipsoid

AFFINE = np.array([[2.0, 0.7], [0.3, 0.5]])  # a shear: affine maps keep both optima


def triangle(seed: int) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=(3, 2)) * 10.0 + [100.0, -50.0]


@pytest.mark.parametrize("seed", range(4))
def test_steiner_ellipses_of_a_triangle(seed):
    V = triangle(seed)
    P = pe.HPolytope.from_vertices(V)
    (a, b), (c, d) = V[1] - V[0], V[2] - V[0]
    area = 0.5 * abs(a * d - b * c)
    inner, outer = max_volume_inscribed_ellipsoid(P), min_volume_enclosing_ellipsoid(P)
    assert inner.volume == pytest.approx(np.pi / (3 * np.sqrt(3)) * area, rel=1e-8)
    assert outer.volume == pytest.approx(4 * np.pi / (3 * np.sqrt(3)) * area, rel=1e-7)
    size = np.ptp(V, axis=0).max()
    np.testing.assert_allclose(inner.center, V.mean(axis=0), rtol=0, atol=1e-4 * size)
    np.testing.assert_allclose(outer.center, V.mean(axis=0), rtol=0, atol=1e-4 * size)
    # inside and around by construction (shrunk / grown by the solver's residual)
    from polyell.comparison.metrics import enclosing_scale, inscribed_scale

    assert inscribed_scale(inner, P) >= 1.0 - 1e-12
    assert enclosing_scale(outer, P) <= 1.0 + 1e-12


@pytest.mark.parametrize("m", [2, 3])
def test_box_after_a_shear(m):
    half = np.array([1.0, 3.0, 0.2][:m])
    A = np.vstack([np.eye(m), -np.eye(m)])
    shear = np.eye(m)
    shear[:2, :2] = AFFINE
    center = np.arange(1.0, m + 1.0) * 7
    # the box {|y| <= half} mapped by x = center + shear y: A_x = A shear^-1
    inverse = np.linalg.inv(shear)
    P = pe.HPolytope(A @ inverse, np.concatenate([half, half]) + A @ inverse @ center)
    inner, outer = max_volume_inscribed_ellipsoid(P), min_volume_enclosing_ellipsoid(P)
    unit_ball = pe.Ellipsoid(np.zeros(m), np.eye(m), np.ones(m)).volume
    det = abs(np.linalg.det(shear))
    assert inner.volume == pytest.approx(unit_ball * det * np.prod(half), rel=1e-8)
    assert outer.volume == pytest.approx(unit_ball * det * np.prod(np.sqrt(m) * half), rel=1e-7)
    np.testing.assert_allclose(inner.center, center, rtol=0, atol=1e-4 * 6 * half.max())


def test_unbounded_and_empty_sets_have_no_optimal_ellipsoid():
    slab = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0]], [1.0, 1.0])
    assert not slab.is_bounded
    with pytest.raises(pe.UndefinedEllipsoidError, match="unbounded"):
        max_volume_inscribed_ellipsoid(slab)
    with pytest.raises(pe.UndefinedEllipsoidError, match="unbounded"):
        min_volume_enclosing_ellipsoid(slab)
    empty = pe.HPolytope([[1.0], [-1.0]], [1.0, -2.0])
    assert empty.is_empty
    with pytest.raises(pe.UndefinedEllipsoidError, match="empty"):
        max_volume_inscribed_ellipsoid(empty)


# --- the batched free-centre MVIE ------------------------------------------------------

#: log det against cvxpy: relative (absolute near 0); Clarabel's own accuracy is ~1e-8.
LOGDET_RTOL = 1e-7
#: Centres and shapes against cvxpy (log det is flat at the optimum: sqrt of the gaps).
SHAPE_ATOL = 1e-4


def force_set(rng, m, n):
    """{h : |L^-1 (J^T h + g)|_inf <= 1} for a random J (m, n), limits L and gravity g.

    |g / L| < 1/2: the origin is inside, about 1/2 from every facet (a well-scaled frame).
    """
    J = rng.normal(size=(m, n))
    L = rng.uniform(0.5, 2.0, size=n)
    g = rng.uniform(-0.5, 0.5, size=n) * L
    rows = J.T / L[:, None]
    return np.vstack([rows, -rows]), np.concatenate([1 - g / L, 1 + g / L])


def box(rng, r):
    half = rng.uniform(0.3, 2.0, size=r)
    center = rng.uniform(-0.5, 0.5, size=r) * half
    A = np.vstack([np.eye(r), -np.eye(r)])
    return A, np.concatenate([half + center, half - center]), half, center


def simplex(rng, r):
    """A random simplex as {x : A x <= b} about its centroid (at the origin), its vertices."""
    V = rng.normal(size=(r + 1, r))
    V -= V.mean(axis=0)
    A, b = [], []
    for i in range(r + 1):
        others = np.delete(V, i, axis=0)
        normal = np.linalg.svd(np.hstack([others, np.ones((r, 1))]))[2][-1]
        a, c = normal[:r], -normal[r]  # a . x = c through the others
        sign = 1.0 if a @ V[i] < c else -1.0
        A.append(sign * a)
        b.append(sign * c)
    return np.array(A), np.array(b), V


def reference(A, b):
    """cvxpy's optimum: (status, log det C, d, C); Clarabel, or SCS if Clarabel is inaccurate."""
    import cvxpy as cp

    r = A.shape[1]
    for solver, options in [
        (cp.CLARABEL, {}),
        (cp.SCS, {"eps_abs": 1e-10, "eps_rel": 1e-10, "max_iters": 200_000}),
    ]:
        C, d = cp.Variable((r, r), PSD=True), cp.Variable(r)
        constraints = [cp.norm(C @ A[i]) + A[i] @ d <= b[i] for i in range(len(b))]
        problem = cp.Problem(cp.Maximize(cp.log_det(C)), constraints)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            problem.solve(solver=solver, **options)
        if problem.status == cp.OPTIMAL:
            return solver, float(np.linalg.slogdet(C.value)[1]), d.value, C.value
    raise AssertionError("neither Clarabel nor SCS reached an optimum")


def stack(problems):
    """Pad (A, b) pairs to one batch with a mask."""
    F = max(len(b) for _, b in problems)
    r = problems[0][0].shape[1]
    A, b, mask = (
        np.zeros((len(problems), F, r)),
        np.ones((len(problems), F)),
        np.zeros((len(problems), F), dtype=bool),
    )
    for k, (a, c) in enumerate(problems):
        A[k, : len(c)], b[k, : len(c)], mask[k, : len(c)] = a, c, True
    return A, b, mask


def violation(A, b, d, C):
    """max_i (|C a_i| + a_i . d - b_i) / b_i: <= 0 inside, 0 touching."""
    return np.max((np.linalg.norm(A @ C, axis=1) + A @ d - b) / b)


def assert_agrees(result, k, A, b):
    solver, logdet, d, C = reference(A, b)
    ours = np.linalg.slogdet(result.shapes[k])[1]
    assert abs(ours - logdet) <= LOGDET_RTOL * max(1.0, abs(logdet)), (solver, ours, logdet)
    # certified: ours is within its gap of the optimum, which cvxpy's cannot exceed by more
    # than cvxpy's own tolerance
    assert ours >= logdet - result.gaps[k] - 1e-7 * max(1.0, abs(logdet))
    np.testing.assert_allclose(result.centers[k], d, rtol=0, atol=SHAPE_ATOL)
    np.testing.assert_allclose(result.shapes[k], 0.5 * (C + C.T), rtol=0, atol=SHAPE_ATOL)


@pytest.mark.parametrize(("m", "n"), [(2, 3), (3, 7), (6, 7)])
def test_batch_agrees_with_cvxpy_on_force_sets(m, n):
    rng = np.random.default_rng(100 * m + n)
    problems = [force_set(rng, m, n) for _ in range(8)]
    result = free_center_mvie_batch(*stack(problems))
    assert result.converged.all()
    assert np.all(result.gaps <= 1e-8)
    for k, (A, b) in enumerate(problems):
        assert_agrees(result, k, A, b)


@pytest.mark.parametrize("r", [2, 3, 4, 5, 6])
def test_batch_agrees_with_cvxpy_on_boxes_and_simplices(r):
    rng = np.random.default_rng(r)
    problems = [box(rng, r)[:2] for _ in range(2)] + [simplex(rng, r)[:2] for _ in range(2)]
    result = free_center_mvie_batch(*stack(problems))  # 2r and r + 1 rows: a mask
    assert result.converged.all()
    for k, (A, b) in enumerate(problems):
        assert_agrees(result, k, A, b)


def test_solves_the_force_sets_clarabel_reports_inaccurate():
    """30 random 6x7 force sets in the whitened frame of the former cvxpy path: Clarabel
    reports 'optimal_inaccurate' on about a third; ours certifies every one, and agrees with
    SCS (to 1e-10) on those."""
    import cvxpy as cp

    rng = np.random.default_rng(0)
    inaccurate = 0
    for _ in range(30):
        P = pe.HPolytope(*force_set(rng, 6, 7))
        center, F = _frame(P, "test")
        A = P.A @ F
        norms = np.linalg.norm(A, axis=1)
        A, b = A / norms[:, None], (P.b - P.A @ center) / norms
        C, d = cp.Variable((6, 6), PSD=True), cp.Variable(6)
        problem = cp.Problem(
            cp.Maximize(cp.log_det(C)),
            [cp.norm(C @ A[i]) + A[i] @ d <= b[i] for i in range(len(b))],
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            problem.solve(solver=cp.CLARABEL)
        result = free_center_mvie_batch(A[None], b[None])
        assert result.converged[0] and result.gaps[0] <= 1e-8
        assert violation(A, b, result.centers[0], result.shapes[0]) <= 1e-14
        if problem.status != cp.OPTIMAL:
            inaccurate += 1
            assert problem.status == cp.OPTIMAL_INACCURATE
            solver, _, _, _ = reference(A, b)  # SCS
            assert solver == cp.SCS
            assert_agrees(result, 0, A, b)
        free_center_mvie(P)  # the scalar path certifies it too (a SolverError otherwise)
    assert inaccurate >= 2  # the seed holds such cases (3 of 30 with the facets as given)


@pytest.mark.parametrize("r", [1, 2, 3, 4, 5, 6])
def test_box_touches_every_face(r):
    rng = np.random.default_rng(10 + r)
    problems = [box(rng, r) for _ in range(3)]
    result = free_center_mvie_batch(*stack([(A, b) for A, b, _, _ in problems]), gap=1e-10)
    assert result.converged.all() and np.all(result.gaps <= 1e-10)
    for k, (A, b, half, center) in enumerate(problems):
        np.testing.assert_allclose(result.shapes[k], np.diag(half), rtol=0, atol=1e-6)
        np.testing.assert_allclose(result.centers[k], center, rtol=0, atol=1e-6)
        assert np.linalg.slogdet(result.shapes[k])[1] == pytest.approx(
            np.log(half).sum(), abs=1e-10
        )
        reach = np.linalg.norm(A @ result.shapes[k], axis=1) + A @ result.centers[k]
        np.testing.assert_allclose(reach, b, rtol=1e-6)  # every face touched


@pytest.mark.parametrize("r", [2, 3, 4, 5, 6])
def test_simplex_volume_ratio(r):
    """vol(MVIE) / vol(simplex) = omega_r r! / (r^(r/2) (r + 1)^((r + 1)/2)) (affine image
    of the regular simplex's inscribed ball), pi / (3 sqrt 3) for a triangle; centred at
    the centroid."""
    rng = np.random.default_rng(20 + r)
    problems = [simplex(rng, r) for _ in range(4)]
    result = free_center_mvie_batch(*stack([(A, b) for A, b, _ in problems]))
    ball = np.pi ** (r / 2) / math.gamma(r / 2 + 1)
    ratio = ball * math.factorial(r) / (r ** (r / 2) * (r + 1) ** ((r + 1) / 2))
    if r == 2:
        assert ratio == pytest.approx(np.pi / (3 * np.sqrt(3)), rel=1e-15)
    for k, (_, _, V) in enumerate(problems):
        volume = abs(np.linalg.det(V[1:] - V[0])) / math.factorial(r)
        ellipsoid = ball * abs(np.linalg.det(result.shapes[k]))
        assert ellipsoid / volume == pytest.approx(ratio, rel=1e-8)
        np.testing.assert_allclose(result.centers[k], 0.0, rtol=0, atol=1e-4)


def test_inscribed_by_construction_and_batch_rows_equal_single_calls():
    rng = np.random.default_rng(7)
    problems = [force_set(rng, 3, 7) for _ in range(20)] + [force_set(rng, 3, 4) for _ in range(10)]
    problems += [box(rng, 3)[:2] for _ in range(5)] + [simplex(rng, 3)[:2] for _ in range(5)]
    A, b, mask = stack(problems)
    A[~mask] = rng.normal(size=(np.count_nonzero(~mask), 3)) * 1e3  # padding is ignored
    b[~mask] = -1.0
    result = free_center_mvie_batch(A, b, mask)
    assert result.converged.all()
    for k, (a, c) in enumerate(problems):
        # inside to rounding, and touching
        assert -1e-14 <= violation(a, c, result.centers[k], result.shapes[k]) <= 1e-14
        C = result.shapes[k]
        np.testing.assert_array_equal(C, C.T)
        assert np.all(np.linalg.eigvalsh(C) > 0)
        # the same iterations; equal up to the rounding of the last steps (padding and batch
        # size change BLAS's summation order; the last Newton systems are ill-conditioned)
        single = free_center_mvie_batch(a[None], c[None])
        assert single.iterations[0] == result.iterations[k]
        np.testing.assert_allclose(single.shapes[0], C, rtol=0, atol=1e-8)
        np.testing.assert_allclose(single.centers[0], result.centers[k], rtol=0, atol=1e-8)
        assert single.converged[0]


def test_thin_box():
    A = np.vstack([np.eye(2), -np.eye(2)])
    b = np.array([0.7, 2e-6, 0.3, 1e-6])  # [-0.3, 0.7] x [-1e-6, 2e-6]
    result = free_center_mvie_batch(A[None], b[None])
    assert result.converged[0]
    np.testing.assert_allclose(
        np.sort(np.linalg.eigvalsh(result.shapes[0])), [1.5e-6, 0.5], rtol=1e-8
    )
    np.testing.assert_allclose(result.centers[0], [0.2, 0.5e-6], rtol=1e-8)
    assert violation(A, b, result.centers[0], result.shapes[0]) <= 1e-14
    # through the H-polytope (whitened by its vertices): the box 1 x 1e-6
    P = pe.HPolytope(A, np.array([1.0, 1e-6, 0.0, 0.0]))  # [0, 1] x [0, 1e-6]
    E = free_center_mvie(P, gap=1e-10)
    np.testing.assert_allclose(np.sort(E.semi_axes), [0.5e-6, 0.5], rtol=1e-8)
    np.testing.assert_allclose(E.center, [0.5, 0.5e-6], rtol=1e-8)


def test_many_facets_and_redundant_rows():
    rng = np.random.default_rng(72)
    normals = rng.normal(size=(72, 6))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    A, b = normals, rng.uniform(0.5, 1.5, size=72)
    result = free_center_mvie_batch(A[None], b[None])
    assert result.converged[0]
    assert_agrees(result, 0, A, b)
    # redundant rows: repeated, scaled, loose (far outside): the same optimum
    F, g = force_set(rng, 6, 7)
    redundant = (
        np.vstack([F, 3.0 * F[:5], F[5:9], F[:4]]),
        np.concatenate([g, 3.0 * g[:5], g[5:9], g[:4] + 5.0]),
    )
    result = free_center_mvie_batch(*stack([(F, g), redundant]))
    assert result.converged.all()
    np.testing.assert_allclose(result.shapes[1], result.shapes[0], rtol=0, atol=1e-4)
    np.testing.assert_allclose(result.centers[1], result.centers[0], rtol=0, atol=1e-4)
    logdets = np.linalg.slogdet(result.shapes)[1]
    assert logdets[1] == pytest.approx(logdets[0], abs=2e-8)


def test_problems_without_an_interior_origin_or_bounds_are_unconverged():
    square = np.vstack([np.eye(2), -np.eye(2)])
    A = np.stack([square, square, square[[0, 2, 1, 3]]])
    b = np.array([[1.0, 1.0, 1.0, -0.1], [1.0, 1.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0]])
    mask = np.array([[True] * 4, [True] * 4, [False, True, True, False]])  # a cone (unbounded)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # and no overflow
        result = free_center_mvie_batch(A, b, mask)
    assert result.converged.tolist() == [False, True, False]
    assert np.isnan(result.shapes[0]).all() and np.isinf(result.gaps[0])
    np.testing.assert_allclose(result.shapes[1], np.eye(2), atol=1e-8)


def test_the_scalar_path_needs_no_cvxpy():
    code = (
        "import sys, numpy as np, polyell as pe\n"
        "from polyell.geometry.free_center import free_center_mvie\n"
        "P = pe.HPolytope.from_vertices(np.random.default_rng(0).normal(size=(9, 4)))\n"
        "E = free_center_mvie(P)\n"
        "assert 'cvxpy' not in sys.modules and 'clarabel' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
