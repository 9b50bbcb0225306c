"""The quasi-Monte-Carlo counts of ``overlap``: pruned work, the same counts as testing all.

``_count_inside`` skips the facets no point of the ellipsoid can cross and the points of
the largest scaled copy inside the polytope; each replicate's count must equal the count of
testing every point against every facet, for the ellipsoids of every capacity (inside,
partly outside, touching, thin), in 2-D, 3-D and 6-D.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.metrics import _ball_points, _count_inside, _slacks, overlap


def all_tested(E: pe.Ellipsoid, A: np.ndarray, slack: np.ndarray, samples: int) -> np.ndarray:
    """Every point against every facet (the estimate's definition)."""
    counts = []
    for ball in _ball_points(E.rank, samples, 8, 0):
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
                slack = _slacks(scaled, P)
                counts = _count_inside(scaled.axes, scaled.semi_axes, P.A, slack, samples, 8, 0)
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
        _count_inside(E.axes, E.semi_axes, P.A, _slacks(E, P), 256, 8, 0), [256] * 8
    )
    # The circle of radius 1.2 crosses the sides (four caps outside) and not the corners.
    R = 1.2
    big = pe.Ellipsoid([0.0, 0.0], np.eye(2), [R, R])
    caps = 4.0 * (R**2 * np.arccos(1.0 / R) - np.sqrt(R**2 - 1.0))
    shares = overlap(big, P, samples=2**13)
    assert shares.overreach_stderr > 0.0
    assert abs(shares.overreach - caps / (np.pi * R**2)) <= 5.0 * shares.overreach_stderr
