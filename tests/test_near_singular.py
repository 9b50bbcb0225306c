"""Numbers along paths into a singular configuration, against 80-digit references.

The paper's arm at q = (0.4, d, d) is singular at d = 0 (stretched); for d from 1e-3 down to
1e-9 M keeps full rank with sigma_min / sigma_max from 6e-4 down to 6e-10.  A double
computation is then right to ``eps * kappa`` relative (kappa = sigma_max / sigma_min: the data
themselves carry that error); the tolerance allows ``RTOL_FACTOR`` times that.  Anything
computed through the core N (condition kappa^2) misses it by orders of magnitude: at d = 1e-9
eq. (24) through N was wrong by 85 % (issue 15).
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import polyell as pe
from highprec import (
    chiacchio_core,
    ellipsoid_limits,
    planar_model,
    planar_polytope_limits,
    yoshikawa_core,
)
from reference import PAPER_ARM, PAPER_TAU_MAX, random_directions

EPS = np.finfo(float).eps
RTOL_FACTOR = 100.0
PATH = [10.0**-e for e in range(3, 10)]
DIRECTIONS = random_directions(7, 6, 2)


def _near_singular(d: float) -> tuple[pe.Analysis, float]:
    q = [0.4, d, d]
    an = pe.analyze(PAPER_ARM.dynamics(q), tau_max=PAPER_TAU_MAX)
    s = an.svd.singular_values
    return an, float(s[0] / s[-1])


def _assert_close(computed, reference, kappa: float) -> None:
    computed = np.asarray(computed, dtype=float)
    reference = np.array([float(x) for x in reference])
    tolerance = RTOL_FACTOR * EPS * kappa
    np.testing.assert_allclose(computed, reference, rtol=tolerance, atol=0)


@pytest.mark.parametrize("d", PATH)
@pytest.mark.parametrize("kind", ["chiacchio", "yoshikawa"])
def test_ellipsoid_limits_match_80_digits(d: float, kind: str) -> None:
    an, kappa = _near_singular(d)
    assert an.rank == 2
    M, xg, J, B = planar_model(PAPER_ARM, [0.4, d, d], PAPER_TAU_MAX)
    core = chiacchio_core(M) if kind == "chiacchio" else yoshikawa_core(J, B, PAPER_TAU_MAX)
    lo, hi = an.ellipsoid(kind).limits(DIRECTIONS)
    for t, lo_t, hi_t in zip(DIRECTIONS, lo, hi, strict=True):
        _assert_close([lo_t, hi_t], ellipsoid_limits(core, xg, t), kappa)


@pytest.mark.parametrize("d", PATH)
def test_polytope_limits_match_80_digits(d: float) -> None:
    an, kappa = _near_singular(d)
    M, xg, _, _ = planar_model(PAPER_ARM, [0.4, d, d], PAPER_TAU_MAX)
    lo, hi = an.polytope.limits(DIRECTIONS)
    for t, lo_t, hi_t in zip(DIRECTIONS, lo, hi, strict=True):
        _assert_close([lo_t, hi_t], planar_polytope_limits(M, xg, t), kappa)


@pytest.mark.parametrize("d", PATH)
def test_new_ellipsoid_stays_inside_the_polytope(d: float) -> None:
    """E_chiacchio is the image of the torque ball, so inside P along every direction."""
    an, kappa = _near_singular(d)
    T = random_directions(3, 200, 2)
    lo_e, hi_e = an.ellipsoid("chiacchio").limits(T)
    lo_p, hi_p = an.polytope.limits(T)
    slack = RTOL_FACTOR * EPS * kappa * np.maximum(np.abs(lo_p), np.abs(hi_p))
    assert np.all(hi_e <= hi_p + slack) and np.all(lo_e >= lo_p - slack)
    assert pe.compare(an, mvie=False)["chiacchio"].inscribed_scale >= 1 - 1e-9


def test_reference_is_exact_at_eighty_digits() -> None:
    """The reference itself: the paper's eq. (14) matrix M at q = (pi/2, -pi/2, -pi/2)."""
    M, xg, _, _ = planar_model(PAPER_ARM, [np.pi / 2, -np.pi / 2, -np.pi / 2], PAPER_TAU_MAX)
    an = pe.analyze(PAPER_ARM.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), tau_max=PAPER_TAU_MAX)
    np.testing.assert_allclose(np.array(M.tolist(), dtype=float), an.M, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(np.array(xg.tolist(), dtype=float)[:, 0], an.xg, atol=1e-12)
    assert mp.mp.dps == 15  # the reference leaves mpmath's global precision alone
