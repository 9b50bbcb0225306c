"""Two arms on one object: sums and intersections of force polytopes, against brute force.

Support functions add under a Minkowski sum, h_{P1+P2}(d) = h_{P1}(d) + h_{P2}(d) (each by
a linear program over the raw half-spaces of its arm), and its volume is the convex hull's
of all pairwise vertex sums (Qhull); the intersection's directional limits are the
programs over both arms' half-spaces at once.  Tolerances: RTOL_LP (HiGHS).
"""

from __future__ import annotations

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
