"""The uniform quasi-Monte-Carlo counts (the reference of ``cap_union_share``'s tests).

``reference.qmc_count_inside`` skips the facets no point of the ellipsoid can cross and the
points of the largest scaled copy inside the polytope; each replicate's count must equal the
count of testing every point against every facet, for the ellipsoids of every capacity (inside,
partly outside, touching, thin), in 2-D, 3-D and 6-D.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.caps import cap_share, cap_union_share
from polyell.comparison.metrics import overlap
from reference import ball_points, qmc_count_inside, slacks


def all_tested(E: pe.Ellipsoid, A: np.ndarray, slack: np.ndarray, samples: int) -> np.ndarray:
    """Every point against every facet (the estimate's definition)."""
    counts = []
    for ball in ball_points(E.rank, samples, 8, 0):
        offsets = (ball * E.semi_axes) @ E.axes.T
        counts.append(np.count_nonzero(np.all(offsets @ A.T <= slack, axis=1)))
    return np.array(counts)


def analyses(seed: int, count: int):
    rng = np.random.default_rng(seed)
    for trial in range(count):
        m, n = [(2, 4), (3, 7), (6, 7), (3, 3)][trial % 4]
        J = rng.normal(size=(m, n)) * 10.0 ** rng.uniform(-2, 2)
        J[:, 0] *= 10.0 ** rng.uniform(-3, 0)  # some thin sets
        g = rng.normal(size=n) * rng.choice([0.05, 0.5, 2.0])  # weak and strong gravity
        upper = rng.uniform(1.0, 3.0, n)
        lower = -upper * rng.uniform(0.7, 1.0, n)
        capacity = ("force", "acceleration", "velocity")[trial % 3]
        if capacity == "velocity":
            yield pe.analyze(pe.Kinematics(J), capacity=capacity, qd_max=upper, qd_min=lower)
        else:
            yield pe.analyze(pe.Dynamics(J, np.eye(n), g), upper, lower, capacity=capacity)


@pytest.mark.parametrize("samples", [64, 2**13])
def test_pruned_counts_equal_testing_every_point(samples):
    checked = outside = 0
    for an in analyses(samples, 60):
        P = an.polytope
        if getattr(P, "is_empty", False) or not getattr(P, "is_bounded", True):
            continue
        for kind in an.ellipsoid_kinds:
            try:
                E = an.ellipsoid(kind)
            except pe.UndefinedEllipsoidError:
                continue
            for scaled in (E, pe.Ellipsoid(E.center, E.axes, 1.7 * E.semi_axes)):
                slack = slacks(scaled, P)
                counts = qmc_count_inside(scaled.axes, scaled.semi_axes, P.A, slack, samples, 8, 0)
                expected = all_tested(scaled, P.A, slack, samples)
                assert np.array_equal(counts, expected), (an.capacity, kind)
                checked += 1
                outside += int(expected.min() < samples)
    assert checked > 100 and outside > 50  # partly outside ellipsoids were among them


def test_touching_ellipsoid_counts_every_point():
    # The inscribed circle of the square |x|, |y| <= 1 touches all four sides.
    P = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 1, 1])
    E = pe.Ellipsoid([0.0, 0.0], np.eye(2), [1.0, 1.0])
    assert np.array_equal(
        qmc_count_inside(E.axes, E.semi_axes, P.A, slacks(E, P), 256, 8, 0), [256] * 8
    )
    # The circle of radius 1.2 crosses the sides (four caps outside) and not the corners:
    # the caps are disjoint, so the share is exact; the counts agree with it.
    R = 1.2
    big = pe.Ellipsoid([0.0, 0.0], np.eye(2), [R, R])
    caps = 4.0 * (R**2 * np.arccos(1.0 / R) - np.sqrt(R**2 - 1.0))
    shares = overlap(big, P, samples=2**13)
    assert shares.overreach_stderr == 0.0
    assert shares.overreach == pytest.approx(caps / (np.pi * R**2), rel=1e-13)
    counts = qmc_count_inside(big.axes, big.semi_axes, P.A, slacks(big, P), 2**13, 8, 0) / 2**13
    stderr = counts.std(ddof=1) / np.sqrt(8)
    assert abs((1.0 - counts.mean()) - caps / (np.pi * R**2)) <= 5.0 * stderr


def sphere_cap_share(t: float, r: int, digits: int = 30) -> float:
    """Share of the unit r-ball beyond the plane at distance t: a 1-D integral, mpmath."""
    import mpmath

    with mpmath.workdps(digits):  # not the global precision: other tests rely on it
        t = mpmath.mpf(t)
        density = lambda x: (1 - x * x) ** (mpmath.mpf(r - 1) / 2)  # noqa: E731
        return float(mpmath.quad(density, [t, 1]) / mpmath.quad(density, [-1, 1]))


@pytest.mark.parametrize("r", [1, 2, 3, 4, 6])
def test_one_cap_against_its_integral(r):
    for t in (-0.999, -0.6, -1e-3, 0.0, 0.3, 0.9, 0.999999, 1.0 - 1e-9):
        w = np.zeros((1, r))
        w[0, 0] = 1.0  # the facet x_1 <= t in the ball's coordinates (t exactly as given)
        outside = cap_share(w, np.array([t]))
        # summed, not 1 - share: a tiny cap keeps its relative accuracy (7.5e-19 at 1 - 1e-9)
        assert outside == pytest.approx(sphere_cap_share(t, r, 50), rel=1e-12, abs=1e-300)
        # a facet given in other units carries the rounding of t = slack / |w|: relative
        # (r + 1) / 2 * 2 eps |t| / (1 - |t|) in the cap, the share's condition number
        w[0, 0] = 2.5
        bound = (r + 1) * 2.0**-52 * abs(t) / (1.0 - abs(t)) + 1e-12
        outside = cap_share(w, np.array([2.5 * t]))
        assert outside == pytest.approx(sphere_cap_share(t, r, 50), rel=bound, abs=1e-300)


def test_cap_share_closed_forms_and_edges():
    # A ball of radius 1.3 in the cube |x_i| <= 1: six disjoint caps of height 0.3.
    R, h = 1.3, 0.3
    cube = np.vstack([np.eye(3), -np.eye(3)])
    exact = 6.0 * (np.pi * h * h * (3.0 * R - h) / 3.0) / (4.0 / 3.0 * np.pi * R**3)
    assert cap_share(cube * R, np.ones(6)) == pytest.approx(exact, rel=1e-13)
    # units: scaling E and P together changes nothing, down to 1e-300 and up to 1e300,
    # nor does one row at another scale
    for unit in (1e-300, 1e-200, 1e-160, 1e155, 1e300):
        assert cap_share(cube * R * unit, np.ones(6) * unit) == pytest.approx(exact, rel=1e-13)
    mixed = np.array([1e-300, 1.0, 1e200, 1.0, 1.0, 1.0])
    assert cap_share(cube * R * mixed[:, None], mixed) == pytest.approx(exact, rel=1e-13)
    # radius 1.8 > sqrt(3)... caps of neighbouring faces meet beyond the edges: not exact
    assert np.isnan(cap_share(cube * 1.8, np.ones(6)))
    # a facet with E wholly outside; one ignored (+inf); no cap at all; NaN stays NaN
    assert cap_share(np.array([[1.0, 0.0], [0.0, 1.0]]), np.array([0.5, -1.0])) == 1.0
    assert cap_share(np.array([[1.0, 0.0], [0.0, 1.0]]), np.array([np.inf, 2.0])) == 0.0
    assert np.isnan(cap_share(np.array([[1.0, 0.0]]), np.array([np.nan])))
    # batched: one row per ellipsoid
    rows = cap_share(np.stack([cube * R, cube * 1.8]), np.ones((2, 6)))
    assert rows[0] == pytest.approx(exact, rel=1e-13) and np.isnan(rows[1])
    for w, slack in ((np.ones(3), np.ones(3)), (np.ones((2, 3)), np.ones(3))):
        with pytest.raises(pe.InputError, match="reach_vectors"):
            cap_share(w, slack)


@pytest.mark.parametrize("r", [2, 3, 6])
def test_cap_share_against_sampling(r):
    """Random facets around the unit ball: exact shares equal plain Monte Carlo, and no
    sampled point lies beyond two facets where the caps are called disjoint."""
    rng = np.random.default_rng(r)
    x = rng.normal(size=(100_000, r))
    x *= (rng.uniform(size=(len(x), 1)) ** (1.0 / r)) / np.linalg.norm(x, axis=1, keepdims=True)
    exact = estimated = 0
    for _ in range(40):
        F = rng.integers(2, 12)
        W = rng.normal(size=(F, r)) * 10.0 ** rng.uniform(-1, 1, size=(F, 1))
        t = rng.uniform(0.4, 1.5, F)
        slack = t * np.linalg.norm(W, axis=1)
        outside = cap_share(W, slack)
        beyond = (x @ W.T) > slack
        if np.isnan(outside):
            estimated += 1
            continue
        exact += 1
        assert not np.any(beyond.sum(axis=1) > 1)
        sampled = beyond.any(axis=1).mean()
        sigma = np.sqrt(outside * (1.0 - outside) / len(x))  # binomial, under the exact share
        assert abs(outside - sampled) <= 5.0 * sigma + 1e-12
    assert exact >= 5 and estimated >= 5  # both outcomes were tested


def test_an_estimate_is_never_reported_as_exact():
    # A thin set and a disc that reaches past it.  Uniform points of the disc could not
    # tell its coverage (1e-5 of them land in the set); the share outside is the union of
    # the disc's caps, whose overlaps are known exactly here (the caps beyond the long
    # sides nest: no sampled part), so it is exact.  Independently: in (x, Y = y / 1e-6)
    # the set is the zonotope of (1, 0), (0, 1), (0.5, 1) (area 4 (1 + 1 + 0.5) = 10) and
    # the disc the strip |x| <= 0.5 (to 4e-12); the strip holds the full height -2 <= Y <=
    # 2 of the set, area 4: coverage 0.4.
    an = pe.analyze(
        pe.Kinematics([[1.0, 0.0, 0.5], [0.0, 1e-6, 1e-6]]), capacity="velocity", qd_max=np.ones(3)
    )
    disc = pe.Candidate("disc", core=np.eye(2) / 0.25, center=[0.0, 0.0])
    scores = pe.compare(an, mvie=False, outer=False, candidates=[disc])["disc"]
    assert scores.coverage == pytest.approx(0.4, rel=1e-9) and scores.coverage_stderr <= 1e-9
    assert scores.overreach == pytest.approx(1.0 - 0.4 * 1e-5 / (np.pi / 4), rel=1e-12)
    # where overlaps are sampled, a standard error (cap_union_share falls back on half a
    # point when every replicate agrees)
    W, t = np.eye(3), np.full(3, 0.2)
    _, stderr = cap_union_share(W, t)
    assert stderr > 0.0
