"""Optimal ellipsoids of H-polytopes (free centre) against closed forms.

A box [c - a, c + a] has the MVIE of semi-axes a about c and the outer ellipsoid of
semi-axes sqrt(m) a; a triangle has the Steiner inellipse (area pi / (3 sqrt 3) times the
triangle's, centred at the centroid) and the Steiner circumellipse (4 pi / (3 sqrt 3) times).
Tolerances: the outer ellipsoid is certified to 1e-8 in log det (so volumes to ~1e-8), the
MVIE comes from Clarabel (1e-8 gaps; volumes to 1e-6; its centre, where log det is flat, to
the square root of the gap: 1e-4 of the set's size).
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
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
    assert inner.volume == pytest.approx(np.pi / (3 * np.sqrt(3)) * area, rel=1e-6)
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
    assert inner.volume == pytest.approx(unit_ball * det * np.prod(half), rel=1e-6)
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
