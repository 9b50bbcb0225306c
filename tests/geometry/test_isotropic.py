"""Isotropic capability: the largest balls about xg and about the origin inside P (issue 12),
against an independent bisection on points of spheres and the facets' own geometry."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis, random_problem


def sphere(centre: np.ndarray, radius: float, basis: np.ndarray, k: int = 4000) -> np.ndarray:
    rng = np.random.default_rng(3)
    u = rng.normal(size=(k, basis.shape[1]))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return centre + radius * u @ basis.T


def bisected_radius(P: pe.Polytope, centre: np.ndarray) -> float:
    """Largest r with every sampled sphere point inside P (an upper bound, to sampling)."""
    basis = P.affine_set.basis
    lo, hi = 0.0, 10.0 * float(np.abs(P.b).max())
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if P.contains(sphere(centre, mid, basis)).all() else (lo, mid)
    return lo


@pytest.mark.parametrize(("seed", "m", "n", "rank"), [(0, 2, 3, 2), (1, 3, 5, 3), (2, 3, 4, 2)])
def test_ball_about_the_centre(seed, m, n, rank):
    P = random_problem(seed, m, n, rank=rank).polytope
    r = P.ball_radius
    assert bisected_radius(P, P.center) >= r * (1 - 1e-9)  # the ball is inside
    # and no larger one is: the nearest facet's foot point lies on the boundary
    i = int(np.argmin(P.b - P.A @ P.center))
    foot = P.center + r * P.A[i]
    assert P.contains(foot) and not P.contains(P.center + (r * (1 + 1e-6)) * P.A[i])


def test_ball_about_the_origin_and_the_paper_arm():
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    P = analysis.polytope
    r = P.origin_radius
    assert 0 < r < P.ball_radius + np.linalg.norm(P.center)
    assert bisected_radius(P, np.zeros(2)) == pytest.approx(r, rel=1e-3)
    # the limits along any direction contain [-r, r]
    T = np.random.default_rng(5).normal(size=(200, 2))
    lo, hi = P.limits(T / np.linalg.norm(T, axis=1, keepdims=True))
    assert np.all(lo <= -r * (1 - 1e-9)) and np.all(hi >= r * (1 - 1e-9))
    singular = paper_analysis(PAPER_Q_SINGULAR).polytope  # a segment through the origin
    # the polytope's interval along the segment is [-103.81, 85.574] (README): its short end
    assert singular.origin_radius == pytest.approx(85.574, abs=5e-4)


def test_origin_outside_is_nan():
    weak = pe.analyze(pe.robots.load("chiacchio2000").dynamics([0.4, 0.1, 0.1]), [8.0, 3.0, 1.0])
    assert not weak.polytope.contains([0.0, 0.0])
    assert np.isnan(weak.polytope.origin_radius) and weak.polytope.ball_radius > 0


def test_sweep_columns_equal_the_polytope():
    arm = pe.robots.load("chiacchio2000")
    q = pe.grid(0.4, (-np.pi, np.pi, 5), (-np.pi, np.pi, 5)).rows(0, 25)
    frame = pe.sweep(arm, q, [8.0, 3.0, 1.0], directions=8)
    for k in range(25):
        P = pe.analyze(arm.dynamics(q[k]), [8.0, 3.0, 1.0]).polytope
        np.testing.assert_allclose(frame["polytope_ball_radius"][k], P.ball_radius, rtol=1e-9)
        np.testing.assert_allclose(
            frame["polytope_origin_radius"][k], P.origin_radius, rtol=1e-9, equal_nan=True
        )
    assert (
        frame["polytope_origin_radius"].isna().any()
        and frame["polytope_origin_radius"].notna().any()
    )
