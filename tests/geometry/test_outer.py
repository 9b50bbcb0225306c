"""The minimum-volume enclosing (outer, Loewner-John) ellipsoid (issue 12, part 2): the
dedicated solver against cvxpy + Clarabel, brute-force vertices, closed forms, John's
theorem and a Monte Carlo estimate of how much it overstates."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.metrics import enclosing_scale
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from polyell.geometry.outer import min_volume_enclosing_ellipsoid
from reference import PAPER_ARM, PAPER_TAU_MAX, random_problem

#: The solver certifies 1e-8 in log det; Clarabel stops at its own tolerances.
RTOL_SOLVERS = 1e-6


def brute_force_enclosing_scale(E: pe.Ellipsoid, P: pe.Polytope) -> float:
    """Max of E's norm over every corner xg + M sigma, sigma in {-1, 1}^n (2^n points)."""
    corners = np.array(list(itertools.product((-1.0, 1.0), repeat=P.generators.shape[1])))
    points = P.center + corners @ P.generators.T
    return float(np.max(np.linalg.norm(((points - E.center) @ E.axes) / E.semi_axes, axis=1)))


@pytest.mark.parametrize(("m", "n"), [(2, 3), (2, 6), (3, 7), (6, 8), (6, 11)])
@pytest.mark.parametrize("seed", range(3))
def test_outer_agrees_with_cvxpy_and_touches_every_way(m, n, seed):
    P = random_problem(seed, m, n).polytope
    E = min_volume_enclosing_ellipsoid(P)
    reference = min_volume_enclosing_ellipsoid(P, method="cvxpy")
    assert E.kind == "outer"
    assert E.volume == pytest.approx(reference.volume, rel=RTOL_SOLVERS)
    # P is inside and touches (against all 2^n corners, not only the enumerated vertices)
    assert brute_force_enclosing_scale(E, P) == pytest.approx(1.0, abs=1e-9)
    assert enclosing_scale(E, P) == pytest.approx(1.0, abs=1e-9)
    for i in range(E.rank):  # shrinking any axis lets a vertex out: minimal
        smaller = E.semi_axes.copy()
        smaller[i] *= 1 - 1e-5
        assert enclosing_scale(pe.Ellipsoid(E.center, E.axes, smaller), P) > 1.0


@pytest.mark.parametrize(("m", "n"), [(2, 4), (3, 5), (3, 7), (6, 9)])
def test_john_inner_and_outer_ellipsoids_sandwich_the_polytope(m, n):
    """MVIE within P within the outer ellipsoid within sqrt(m) times the MVIE."""
    P = random_problem(7, m, n).polytope
    inner, outer = max_volume_inscribed_ellipsoid(P), min_volume_enclosing_ellipsoid(P)
    assert pe.comparison.metrics.inscribed_scale(inner, P) == pytest.approx(1.0, abs=1e-9)
    assert enclosing_scale(inner, P) <= np.sqrt(m) * (1 + 1e-9)
    assert 1.0 < outer.volume / inner.volume <= m ** (m / 2) * (1 + 1e-9)
    assert outer.volume > P.volume > inner.volume


@pytest.mark.parametrize("m", [2, 3, 6])
def test_square_case_is_sqrt_m_times_the_new_ellipsoid(m):
    """n = m: P is a parallelotope (a rotated cube when whitened): the outer ellipsoid is the
    new one scaled by sqrt(m), so the new ellipsoid's outer_ratio is m^(-m/2) exactly."""
    analysis = random_problem(3, m, m)
    cmp = pe.compare(analysis, 16)
    new = analysis.ellipsoid("chiacchio")
    np.testing.assert_allclose(cmp.outer.semi_axes, np.sqrt(m) * new.semi_axes, rtol=1e-12)
    assert cmp["chiacchio"].outer_ratio == pytest.approx(m ** (-m / 2), rel=1e-12)
    # and the general solver agrees once P is seen with one more, zero-length generator
    padded = pe.Polytope(np.column_stack([analysis.M, np.zeros(m)]), analysis.xg)
    assert min_volume_enclosing_ellipsoid(padded).volume == pytest.approx(
        cmp.outer.volume, rel=1e-7
    )


def test_overreach_of_the_outer_ellipsoid_equals_monte_carlo():
    """Its coverage is 1 and its overreach 1 - vol(P)/vol(E), exactly; plain Monte Carlo on
    400,000 uniform points of E agrees within 4 standard errors."""
    analysis = random_problem(11, 3, 6)
    cmp = pe.compare(analysis, 16)
    E, P = cmp.outer, analysis.polytope
    assert cmp["outer"].coverage == 1.0 and cmp["outer"].overreach_stderr == 0.0
    rng = np.random.default_rng(5)
    u = rng.normal(size=(400_000, 3))
    u *= (rng.uniform(size=(len(u), 1)) ** (1 / 3)) / np.linalg.norm(u, axis=1, keepdims=True)
    points = E.center + (u * E.semi_axes) @ E.axes.T
    share = np.mean(np.all(points @ P.A.T <= P.b, axis=1))
    stderr = np.sqrt(share * (1 - share) / len(u))
    assert abs((1 - share) - cmp["outer"].overreach) < 4 * stderr


@pytest.mark.parametrize("d", [1e-3, 1e-6, 1e-9])
def test_outer_next_to_a_singular_configuration(d):
    analysis = pe.analyze(PAPER_ARM.dynamics([0.4, d, d]), tau_max=PAPER_TAU_MAX)
    P = analysis.polytope
    E = min_volume_enclosing_ellipsoid(P)
    s = analysis.svd.singular_values
    atol = max(1e-9, 100 * np.finfo(float).eps * s[0] / s[-1])
    assert enclosing_scale(E, P) == pytest.approx(1.0, abs=atol)
    reference = min_volume_enclosing_ellipsoid(P, method="cvxpy")
    assert E.volume == pytest.approx(reference.volume, rel=RTOL_SOLVERS)


def test_at_a_singular_configuration_the_outer_ellipsoid_is_the_segment():
    analysis = pe.analyze(PAPER_ARM.dynamics([np.pi / 6, 0.0, 0.0]), tau_max=PAPER_TAU_MAX)
    cmp = pe.compare(analysis, 16)
    assert analysis.rank == 1 and cmp["outer"].dimension == 1
    assert cmp.outer.volume == pytest.approx(analysis.polytope.volume, rel=1e-12)
    assert cmp["outer"].outer_ratio == 1.0 and cmp["mvie"].outer_ratio == pytest.approx(1.0)


def test_unknown_method_is_refused():
    with pytest.raises(pe.InputError, match="method"):
        min_volume_enclosing_ellipsoid(random_problem(0, 2, 3).polytope, method="khachiyan")
