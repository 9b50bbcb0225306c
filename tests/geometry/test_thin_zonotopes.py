"""Thin but full-rank zonotopes (issue 20; DESIGN.md section 7, "Thin zonotopes").

A zonotope whose ``sigma_min / sigma_max`` is far above the rank threshold (1e-10) is full
dimensional and must keep every facet, its directional limits, radii and membership.  The
references are computed in 50-digit arithmetic by the zonotope formula applied to the
double data itself (:mod:`highprec`, no whitening, nothing shared with polyell), along
paths in the condition number from 1e2 up to 5e9, just above the rank threshold.

Tolerance (stated once, used by every comparison below).  A backward-stable double
computation (the SVD, products, sums) is exact for generators within ``p eps |M|`` of M,
with ``p`` a small multiple of ``max(m, n)``; a perturbation of relative size ``delta``
moves the whitened zonotope ``S^-1 U^T Z``, and with it every facet normal, support value
and line crossing of the thin set, by at most about ``delta * cond`` relative (first
order: the whitening amplifies by ``sigma_max / sigma_min``).  So every relative error is
at most ``C eps cond`` with ``C = 10 m n`` (``p`` and the first-order constants, with a
margin of 10); at cond 5e9 that is still about 1e-4 for the 6-D case, below every defect
this file guards (facets lost, 8 % limits, a 2.7x radius, 1-2 % membership overlap).
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.stats import ortho_group

import highprec
import polyell as pe
from polyell.geometry.directions import sphere_directions
from polyell.geometry.limits import ATOL_RELATIVE
from polyell.studies.batch import batch_rows

EPS = np.finfo(float).eps
CONDITIONS = (1e2, 1e4, 1e6, 1e7, 1e8, 4e8, 1e9, 5e9)
#: (m, n, spread): "geometric" singular values 1 .. 1/cond evenly in log; "one": a single
#: small one (the 2x4 case of the issue has one tiny singular value).
SHAPES = (
    (2, 4, "one"),
    (2, 5, "geometric"),
    (3, 7, "geometric"),
    (3, 6, "one"),
    (6, 9, "geometric"),
)


def thin_generators(m: int, n: int, cond: float, spread: str, seed: int = 0) -> np.ndarray:
    """A seeded (m, n) matrix ``U diag(s) V^T`` with ``s_max / s_min = cond``."""
    rng = np.random.default_rng(seed)
    U = ortho_group.rvs(m, random_state=rng) if m > 1 else np.ones((1, 1))
    V = ortho_group.rvs(n, random_state=rng)[:, :m]
    s = (
        np.geomspace(1.0, 1.0 / cond, m)
        if spread == "geometric"
        else np.r_[np.ones(m - 1), 1 / cond]
    )
    return (U * s) @ V.T


def thin_polytope(m, n, cond, spread, seed=0):
    """The polytope about a centre inside it (``xg = M w``, ``|w|_inf <= 1/2``)."""
    M = thin_generators(m, n, cond, spread, seed)
    w = np.random.default_rng(seed + 1).uniform(-0.5, 0.5, n)
    return pe.Polytope(M, M @ w), M


def tolerance(M: np.ndarray) -> float:
    """``C eps cond`` with ``C = 10 m n`` (module docstring); cond of the double data."""
    m, n = M.shape
    s = np.linalg.svd(M, compute_uv=False)
    return 10 * m * n * EPS * s[0] / s[-1]


def whitened_normals(M: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Unit ``S U^T a`` (50-digit SVD of M) for unit normals ``a`` (F, m): the set's own frame."""
    with mp.workdps(50):
        U, S, _ = mp.svd_r(mp.matrix(M.tolist()))
        frame = mp.diag(S) * U.T  # (m, m)
        out = []
        for a in normals:
            y = frame * mp.matrix([mp.mpf(float(x)) for x in a])
            out.append([float(v) for v in y / mp.norm(y)])
    return np.array(out)


def reference(M):
    """The 50-digit facets as arrays: unit normals (F, m) and half-widths (F,), one per pair."""
    facets = highprec.zonotope_facets(M)
    normals = np.array([[float(x) for x in a] for a, _ in facets])
    return facets, normals, np.array([float(h) for _, h in facets])


CASES = [(m, n, spread, cond) for (m, n, spread) in SHAPES for cond in CONDITIONS]


@pytest.mark.parametrize(("m", "n", "spread", "cond"), CASES)
def test_facets_equal_the_50_digit_zonotope_formula(m, n, spread, cond):
    P, M = thin_polytope(m, n, cond, spread)
    facets, normals, _ = reference(M)
    assert len(facets) == math.comb(n, m - 1)  # general position: every subset a facet
    A, h = P.A, P.b - P.A @ P.center
    assert A.shape == (2 * len(facets), m)
    tol = tolerance(M)
    # The normals of a thin set differ by angles of 1/cond in task space: compare them as
    # the set sees them, mapped to its whitened frame a -> S U^T a / |S U^T a| (50-digit
    # SVD), where distinct facets are well apart.  Pair each reference normal with the
    # closest of P's: all distinct, and equal to the tolerance.
    ours, theirs = whitened_normals(M, A), whitened_normals(M, normals)
    best = np.argmax(ours @ theirs.T, axis=0)
    assert len(set(best.tolist())) == len(facets)
    np.testing.assert_allclose(ours[best], theirs, atol=tol)
    # Each half-space is a supporting one: h equals the support along P's own normal.
    exact = np.array([float(highprec.support(M, a)) for a in A[best]])
    np.testing.assert_allclose(h[best], exact, rtol=tol)


@pytest.mark.parametrize(("m", "n", "spread", "cond"), CASES)
def test_limits_and_ball_radius_equal_the_50_digit_reference(m, n, spread, cond):
    P, M = thin_polytope(m, n, cond, spread)
    facets, _, widths = reference(M)
    U = np.linalg.svd(M)[0]
    rng = np.random.default_rng(7)
    random = rng.normal(size=(6, m))
    T = np.vstack([U.T, random / np.linalg.norm(random, axis=1, keepdims=True)])
    lo, hi = P.limits(T)
    tol = tolerance(M)
    for k, t in enumerate(T):
        lo_ref, hi_ref = (float(x) for x in highprec.halfspace_limits(facets, P.center, t))
        width = hi_ref - lo_ref
        assert abs(lo[k] - lo_ref) <= tol * width and abs(hi[k] - hi_ref) <= tol * width, (k, t)
    assert np.isfinite(P.ball_radius)
    np.testing.assert_allclose(P.ball_radius, widths.min(), rtol=tol)
    np.testing.assert_allclose(P.volume, _volume(M), rtol=tol)


def _volume(M):
    """``2^m sum_{|S| = m} |det M_S|`` in 50 digits, on the double data."""
    from itertools import combinations

    m, n = M.shape
    with mp.workdps(50):
        G = [[mp.mpf(float(x)) for x in row] for row in M]
        total = sum(
            abs(mp.det(mp.matrix([[row[j] for j in S] for row in G])))
            for S in combinations(range(n), m)
        )
        return float(2**m * total)


@pytest.mark.parametrize(("m", "n", "spread", "cond"), CASES)
def test_membership_at_the_tips_is_decided_relative_to_the_set(m, n, spread, cond):
    """Points on the long axis just beyond a tip are refused, just before it accepted.

    The documented slack (:func:`polyell.geometry.limits.facet_slack`) moves each facet out
    by ``ATOL_RELATIVE`` of the set's half-width along its normal plus the rounding floor
    ``(m + n + 2) eps reach``, ``reach = |x| + |xg| + sum |g_i|``.  The facets at a tip meet
    the long axis at a slope of about ``1 / cond``, so along the axis the floor reaches
    ``(m + n + 2) eps cond reach`` beyond the tip: relative to the width w along the axis,
    ``overlap <= ATOL_RELATIVE + (m + n + 2) eps cond reach / w``; refusal is asserted at
    twice that (the slope's geometric factor).  Inside, a point at the 50-digit limit less
    the limits' own tolerance (module docstring) is accepted.
    """
    P, M = thin_polytope(m, n, cond, spread)
    facets, _, _ = reference(M)
    t_long = np.linalg.svd(M)[0][:, 0]
    for t in (t_long, -t_long):
        lo, hi = (float(x) for x in highprec.halfspace_limits(facets, P.center, t))
        width = hi - lo
        reach = 2 * abs(hi) + np.linalg.norm(P.center) + np.linalg.norm(M, axis=0).sum()
        overlap = ATOL_RELATIVE + (m + n + 2) * EPS * cond * reach / width
        beyond = np.array([2 * overlap, 1e-4, 1e-2])  # the old absolute slack: 1-2 %
        assert not P.contains((hi + beyond[:, None] * width) * t).any()
        assert P.contains((hi - tolerance(M) * width) * t)
        assert P.contains(0.5 * (lo + hi) * t)


@pytest.mark.parametrize("cond", (1e2, 1e4))
@pytest.mark.parametrize(("m", "n"), ((2, 5), (3, 6)))
def test_facets_equal_cddlib_where_it_is_well_conditioned(m, n, cond):
    """cddlib's floating-point V-to-H conversion, on a mildly thin set."""
    P, M = thin_polytope(m, n, cond, "geometric", seed=3)
    A_cdd, b_cdd = P.halfspaces("cdd")
    assert A_cdd.shape == P.A.shape
    # Facet by facet, in the set's own frame (see the 50-digit test), to cddlib's accuracy
    # on vertices of condition cond: C eps cond of the module docstring with cddlib's own
    # floating-point pivots, a further factor of the facet count.
    tol = tolerance(M) * len(P.A)
    ours, theirs = whitened_normals(M, P.A), whitened_normals(M, A_cdd)
    best = np.argmax(ours @ theirs.T, axis=0)
    assert len(set(best.tolist())) == len(P.A)
    np.testing.assert_allclose(ours[best], theirs, atol=tol)
    widths = b_cdd - A_cdd @ P.center
    np.testing.assert_allclose((P.b - P.A @ P.center)[best], widths, rtol=tol)


@pytest.mark.parametrize("ratio", (1e-3, 1e-6, 1e-8))
@pytest.mark.parametrize(("m", "n"), ((2, 4), (3, 6)))
def test_closed_form_limits_equal_linear_programs_on_thin_sets(m, n, ratio):
    """Clarabel's certified LP (polytope_limits_lp) against the closed form.

    The LP holds ``a t = M tau + c`` to its feasibility tolerance 1e-12 (absolute, with
    sigma_max = 1 here); a random line crosses the thin set across its width, about
    sigma_min = 1 / cond, so the LP's ends are good to about ``1e-12 cond`` of the width
    (the solver's rounding, eps cond, likewise); with a factor 10 and the closed form's
    own ``C eps cond``, ``10 (1e-12 + eps) cond + C eps cond``.
    """
    P, M = thin_polytope(m, n, 1.0 / ratio, "one", seed=11)
    rng = np.random.default_rng(2)
    T = rng.normal(size=(4, m))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    closed = P.limits(T)
    lp = P.limits(T, method="lp")
    width = closed.hi - closed.lo
    tol = 10 * (1e-12 + EPS) / ratio + tolerance(M)
    assert np.all(np.abs(lp.lo - closed.lo) <= tol * width)
    assert np.all(np.abs(lp.hi - closed.hi) <= tol * width)


def thin_dynamics(K: int, m: int, n: int, seed: int) -> pe.Dynamics:
    """K configurations with B = I, unit torque limits (M = J) and conditions 1e2..5e9."""
    conds = np.geomspace(1e2, 5e9, K)
    J = np.stack([thin_generators(m, n, c, "geometric", seed + k) for k, c in enumerate(conds)])
    rng = np.random.default_rng(seed)
    return pe.Dynamics(
        J=J, B=np.broadcast_to(np.eye(n), (K, n, n)), g=rng.uniform(-0.4, 0.4, (K, n))
    )


@pytest.mark.parametrize(("m", "n"), ((2, 4), (3, 7), (6, 9)))
def test_limits_along_equals_polytope_limits_row_by_row_on_thin_arms(m, n):
    dyn = thin_dynamics(9, m, n, seed=20)
    tau = np.ones(n)
    rng = np.random.default_rng(4)
    T = rng.normal(size=(len(dyn), m))
    T[::2] = np.linalg.svd(dyn.J[::2])[0][:, :, 0]  # every other row: the long axis (tips)
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    along = pe.limits_along(dyn, None, T, tau)["polytope"]
    for k in range(len(dyn)):
        P = pe.analyze(dyn[k], tau).polytope
        lo, hi = P.limits(T[k])
        tol = tolerance(dyn.J[k]) * (hi - lo)  # both exact to it (module docstring)
        assert abs(along.lo[k] - lo) <= tol and abs(along.hi[k] - hi) <= tol, k


@pytest.mark.parametrize(("m", "n"), ((2, 4), (3, 7)))
def test_batched_sweep_rows_equal_compare_on_thin_arms(m, n):
    dyn = thin_dynamics(8, m, n, seed=30)
    tau = np.ones(n)
    frame = pe.sweep(dyn, tau_max=tau, directions=24)
    directions = sphere_directions(24, m)
    assert not batch_rows(dyn, tau, -tau, directions)[1].any()  # every row batched
    columns = ("polytope_volume", "polytope_ball_radius", "polytope_origin_radius")
    for k in range(len(dyn)):
        row = pe.compare(pe.analyze(dyn[k], tau), 24).to_row()
        tol = tolerance(dyn.J[k])
        for name in columns:
            np.testing.assert_allclose(frame[name][k], row[name], rtol=tol, err_msg=f"{name} {k}")
        for name in ("chiacchio_inscribed_scale", "yoshikawa_inscribed_scale"):
            np.testing.assert_allclose(frame[name][k], row[name], rtol=tol, err_msg=f"{name} {k}")
        assert frame["chiacchio_direction_error_max"][k] == pytest.approx(
            row["chiacchio_direction_error_max"], abs=tol
        )
