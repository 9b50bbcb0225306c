"""Rounded input at singular configurations: one tolerance, AFFINE_RTOL (issue 11).

At q = (pi/6, 0, 0) the polytope and the new ellipsoid are segments on the line through the
origin with direction t = (-1/2, sqrt(3)/2).  Users type t and points to 5-7 digits.
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import polyell as pe
from reference import PAPER_Q_SINGULAR, RTOL_LP, assert_printed, paper_analysis

EXACT = np.array([-0.5, np.sqrt(3.0) / 2.0])
IN_SET = {"polytope": (-103.81, 85.574), "chiacchio": (-70.922, 52.690)}


@pytest.fixture(scope="module")
def singular():
    return paper_analysis(PAPER_Q_SINGULAR)


def sets(an):
    return {"polytope": an.polytope, "chiacchio": an.ellipsoid("chiacchio")}


def rotated(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([c * EXACT[0] - s * EXACT[1], s * EXACT[0] + c * EXACT[1]])


@pytest.mark.parametrize("typed", [[-0.5, 0.8660254], [-0.5, 0.866025], [-0.50000, 0.86603]])
def test_a_typed_direction_gets_the_interval_of_the_segment(singular, typed):
    t = np.array(typed) / np.linalg.norm(typed)
    for name, S in sets(singular).items():
        with pytest.warns(pe.ProjectedInputWarning, match="projected"):
            lo, hi = S.limits(t)
        assert_printed([lo, hi], "{} {}".format(*IN_SET[name]).replace("52.69 ", "52.690 "))


def test_lp_agrees_with_the_closed_form_on_a_typed_direction(singular):
    t = np.array([-0.5, 0.8660254]) / np.linalg.norm([-0.5, 0.8660254])
    P = singular.polytope
    with pytest.warns(pe.ProjectedInputWarning):
        closed = P.limits(t)
    with pytest.warns(pe.ProjectedInputWarning):
        lp = P.limits(t, method="lp")
    np.testing.assert_allclose(lp, closed, rtol=RTOL_LP)


@pytest.mark.parametrize("angle", [1e-12, 1e-9, 1e-7, 1e-5, 0.9e-4, 1.1e-4, 1e-3, 0.1])
def test_limits_converge_without_a_jump_beyond_the_tolerance(singular, angle):
    """Inside the tolerance the interval is the segment's, and its ends count as members
    (within AFFINE_RTOL of the set); beyond it the exact single point (the origin)."""
    t = rotated(angle)
    for name, S in sets(singular).items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pe.ProjectedInputWarning)
            lo, hi = S.limits(t)
        if angle < pe.AFFINE_RTOL:
            np.testing.assert_allclose([lo, hi], S.limits(EXACT), rtol=1e-12)
            assert np.all(S.contains(np.outer([lo, hi], t)))
        else:
            assert lo == hi == 0.0  # the line crosses the segment's line at the origin
            assert not np.any(S.contains(np.outer(IN_SET[name], t)))


def test_polytope_and_ellipsoids_decide_alike(singular):
    rng = np.random.default_rng(3)
    angles = np.geomspace(1e-10, 1e-2, 40) * rng.choice([-1, 1], 40)
    decisions = []
    for S in sets(singular).values():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pe.ProjectedInputWarning)
            lo, hi = S.limits(np.array([rotated(a) for a in angles]))
        decisions.append(hi > lo)  # an interval, not a single point
    assert np.array_equal(decisions[0], decisions[1])
    assert decisions[0].sum() == np.count_nonzero(np.abs(angles) < pe.AFFINE_RTOL)


def test_the_papers_printed_points(singular):
    assert singular.polytope.contains([35.46095, -61.42016])
    with pytest.warns(pe.ProjectedInputWarning):
        qdd, tau_n = singular.inverse([35.461, -61.420])  # eq. (40), printed to 3 decimals
    # The printed point is itself off by up to 5e-4 per entry: qdd within 2e-3 of the
    # paper's (computed from the unrounded point), tau_n to its printed digits.
    np.testing.assert_allclose(qdd, [-49.417, 172.961, -364.223], atol=2e-3)
    assert_printed(tau_n, "-0.1771 0.5182 -0.8367")


def test_a_point_clearly_off_the_set_is_unreachable(singular):
    with pytest.raises(pe.UnreachableAccelerationError, match="affine_rtol"):
        singular.inverse([35.5, -61.0])


def test_the_tolerance_is_the_users(singular):
    strict = pe.analyze(singular.dynamics, singular.tau_max, affine_rtol=1e-12)
    lo, hi = strict.polytope.limits(np.array([-0.5, 0.8660254]) / np.linalg.norm([-0.5, 0.8660254]))
    assert lo == hi == 0.0
    assert not strict.polytope.contains([35.46095, -61.42016])
    with pytest.raises(pe.InputError, match="affine_rtol"):
        pe.analyze(singular.dynamics, singular.tau_max, affine_rtol=2.0)


def test_readme_singular_example_prints_the_segment():
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "polyell.cli",
            "analyze",
            "--q",
            "pi/6,0,0",
            "--direction=-0.5,0.8660254",
            "--no-mvie",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "[-70.922, 52.69]" in result.stdout and "[-103.81, 85.574]" in result.stdout
    assert "polyell: note: directions" in result.stderr and "Traceback" not in result.stderr


# --- Issue 20: one rule for rounded input, stated once (validation.ROUNDED_INPUT_RTOL).


def typed(vector: np.ndarray, digits: int) -> list[float]:
    """The vector as a user types it: each component to ``digits`` significant digits."""
    return [float(f"{x:.{digits - 1}e}") for x in vector]


def test_the_direction_norm_and_the_affine_set_share_one_tolerance():
    from polyell.validation import DIRECTION_NORM_RTOL, ROUNDED_INPUT_RTOL

    assert pe.AFFINE_RTOL == DIRECTION_NORM_RTOL == ROUNDED_INPUT_RTOL
    # A number typed to 5 significant digits is off by at most half a unit in its fifth
    # digit: 5e-5 relative (a leading 1); the rule leaves a factor 2 above that.
    assert ROUNDED_INPUT_RTOL >= 2 * 0.5e-4


@pytest.mark.parametrize("digits", [5, 6, 7])
@pytest.mark.parametrize("angle", [0.1, 1.0, 2.0, 2.5, 4.0])
def test_a_direction_typed_to_5_to_7_digits_is_accepted_unnormalised(digits, angle):
    """Typed (not renormalised) directions: accepted, renormalised, limits within the
    rounding of the input (relative 1e-4 bound on the direction, times the interval's
    sensitivity, at most |x|/|hi| per unit of angle: 1e-3 here)."""
    analysis = paper_analysis(np.array([0.3, 0.7, -0.4]))
    exact = np.array([np.cos(angle), np.sin(angle)])
    t = typed(exact, digits)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = analysis.polytope.limits(t)
        E = analysis.ellipsoid("chiacchio").limits(t)
    want = analysis.polytope.limits(exact)
    np.testing.assert_allclose([got.lo, got.hi], [want.lo, want.hi], rtol=1e-3)
    assert np.isfinite(E.hi)


@pytest.mark.parametrize("digits", [5, 6, 7])
def test_a_direction_typed_to_5_to_7_digits_at_a_singular_configuration(singular, digits):
    t = typed(EXACT, digits)
    for name, S in sets(singular).items():
        with pytest.warns(pe.ProjectedInputWarning, match="projected"):
            lo, hi = S.limits(t)
        assert_printed([lo, hi], "{} {}".format(*IN_SET[name]).replace("52.69 ", "52.690 "))


def test_a_refused_norm_is_printed_in_full():
    P = paper_analysis(np.array([0.3, 0.7, -0.4])).polytope
    with pytest.raises(pe.InputError, match=r"norm 1\.0003 \(1 \+ 0\.0003\)"):
        P.limits([1.0003, 0.0])
    with pytest.raises(pe.InputError, match=r"norm 0\.9 \(1 - 0\.1\)"):
        P.limits([0.9, 0.0])


def test_a_force_direction_typed_along_a_line_of_the_set_is_the_line():
    """Issue 33: at a singular posture the force set is a line along Ker J^T; a direction
    typed to a few digits along it has infinite limits (with a warning), as rounded input
    has for an affine set, not those of a line 1e-5 off it (1e6 N and more)."""
    arm = pe.robots.load("chiacchio2000")
    P = pe.analyze(arm.dynamics([np.pi / 6, 0.0, 0.0]), arm.tau_max, capacity="force").polytope
    line = P.rays[0]
    for digits in (4, 5, 7, 9):
        t = np.round(line, digits)
        t /= np.linalg.norm(t)
        with pytest.warns(pe.ProjectedInputWarning, match="line"):
            lo, hi = P.limits(t)
        assert lo == -np.inf and hi == np.inf
    # beyond affine_rtol a direction is the user's own: large, finite limits, no warning
    off = np.array([line[0] - 1e-2 * line[1], line[1] + 1e-2 * line[0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lo, hi = P.limits(off / np.linalg.norm(off))
    assert np.isfinite([lo, hi]).all() and hi - lo > 100 * P.half_widths.max(initial=1.0)
