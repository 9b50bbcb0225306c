"""Numerical edge cases: near-singular postures, ill-conditioned inertia, torque scales,
strong gravity, square Jacobians, large arms, and frame invariance."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.stats import special_ortho_group

import polyell as pe
from polyell.geometry.zonotope import corner_vertices
from reference import random_directions, random_problem, random_spd

ARM = pe.robots.load("chiacchio2000")
SCORES = ("inscribed_scale", "coverage", "direction_error_mean", "witness_torque_max")


def scores(analysis: pe.Analysis, directions=64) -> dict[str, float]:
    """The scores, checked for sanity: finite, and directional ones NaN only where no
    direction has both intervals (a thin ellipsoid can miss every line through 0)."""
    cmp = pe.compare(analysis, directions, mvie=False)
    for kind in ("chiacchio", "yoshikawa"):
        record = cmp[kind]
        if not record.defined:  # the classic ellipsoid at a singularity
            continue
        for name in ("volume", "inscribed_scale", "coverage", "overreach", "witness_torque_max"):
            assert np.isfinite(getattr(record, name)), (kind, name)
        assert np.isfinite(record.direction_error_mean) == (record.directions_used > 0)
    return {f"{k}_{s}": getattr(cmp[k], s) for k in ("chiacchio", "yoshikawa") for s in SCORES}


def same(a: float, b: float, rel: float) -> bool:
    return (np.isnan(a) and np.isnan(b)) or a == pytest.approx(b, rel=rel, abs=1e-10)


def test_scores_stay_finite_and_settle_as_the_arm_stretches():
    """q2 = q3 = eps -> 0: every score finite while the rank is 2, and converging."""
    history = []
    for eps in 10.0 ** -np.arange(1, 8):
        analysis = pe.analyze(ARM.dynamics([0.4, eps, eps]), ARM.tau_max)
        assert analysis.rank == 2
        history.append(scores(analysis))
    for name in history[0]:
        steps = np.abs(np.diff([h[name] for h in history]))
        assert steps[-1] <= 1e-3 * max(1.0, abs(history[-1][name])), name  # settled


def test_the_rank_decision_is_shared_at_the_threshold():
    # sigma_min / sigma_max of M shrinks like eps: find both sides of RANK_RTOL = 1e-10.
    for eps, rank in ((1e-6, 2), (1e-13, 1)):
        analysis = pe.analyze(ARM.dynamics([0.4, eps, 0.0]), ARM.tau_max)
        assert analysis.rank == rank == analysis.polytope.dim == analysis.ellipsoid().rank
        assert (rank == 1) == analysis.is_singular
        assert np.isfinite(scores(analysis)["chiacchio_coverage"])


@pytest.mark.parametrize("seed", range(4))
def test_ill_conditioned_inertia(seed):
    rng = np.random.default_rng(seed)
    B = random_spd(rng, 5, condition=1e8)
    J = rng.normal(size=(3, 5))
    tau = rng.uniform(1, 10, 5)
    analysis = pe.analyze(pe.Dynamics(J, B, 0.3 * tau * rng.normal(size=5)), tau)
    P, E = analysis.polytope, analysis.ellipsoid("chiacchio")
    assert np.all(E.support(P.A) <= P.b + 1e-9 * np.abs(P.b).max())
    T = random_directions(seed, 8, 3)
    closed, lp = P.limits(T), P.limits(T, method="lp")
    np.testing.assert_allclose(closed.hi, lp.hi, rtol=1e-6, atol=1e-6 * np.abs(P.b).max())
    scores(analysis, T)  # sane, even where the classic ellipsoid is a sliver


@pytest.mark.parametrize("scale", [1e-3, 1e-1, 1e2, 1e4])
def test_torque_scale_scales_the_sets_and_leaves_the_scores(scale):
    dyn = ARM.dynamics([0.3, 0.9, -0.4])
    base = pe.analyze(dyn, ARM.tau_max)
    scaled = pe.analyze(pe.Dynamics(dyn.J, dyn.B, scale * dyn.g), scale * ARM.tau_max)
    np.testing.assert_allclose(scaled.M, scale * base.M, rtol=1e-12)
    np.testing.assert_allclose(scaled.polytope.volume, scale**2 * base.polytope.volume, rtol=1e-10)
    after = scores(scaled)
    for name, value in scores(base).items():
        assert same(after[name], value, 1e-8), name


def test_gravity_that_takes_the_origin_out_of_the_polytope():
    dyn = ARM.dynamics([0.3, 0.9, -0.4])
    analysis = pe.analyze(pe.Dynamics(dyn.J, dyn.B, 40.0 * dyn.g), ARM.tau_max)
    P = analysis.polytope
    assert not P.contains([0.0, 0.0])
    T = random_directions(1, 200, 2)
    lo, hi = P.limits(T)
    assert np.isnan(lo).any() and not np.isnan(lo).all()
    assert np.all((lo > 0) | (hi < 0) | np.isnan(lo))  # no interval holds a = 0
    record = pe.compare(analysis, T, mvie=False)["chiacchio"]
    assert record.directions_used + record.feasibility_mismatch <= len(T)


def test_task_dimension_equal_to_the_number_of_joints():
    arm = pe.PlanarArm(lengths=[1.0, 0.7], masses=[2.0, 1.0], tau_max=[40.0, 15.0])
    analysis = pe.analyze(arm.dynamics([0.5, 1.2]), arm.tau_max)
    cmp = pe.compare(analysis, mvie=False)
    for name in SCORES:
        assert getattr(cmp["chiacchio"], name) == pytest.approx(
            getattr(cmp["yoshikawa"], name), rel=1e-9
        )


@pytest.mark.parametrize("n", [12, 20])
def test_large_arms_use_the_zonotope_path(n):
    analysis = random_problem(n, 3, n)
    P = analysis.polytope
    assert P.A.shape[0] == 2 * n * (n - 1) // 2  # one pair of facets per pair of generators
    # In general position a 3-D zonotope has 2 [C(n-1, 0) + C(n-1, 1) + C(n-1, 2)] vertices.
    assert len(P.vertices) == 2 * (1 + (n - 1) + (n - 1) * (n - 2) // 2)
    T = random_directions(n, 4, 3)
    closed, lp = P.limits(T), P.limits(T, method="lp")
    np.testing.assert_allclose(closed.hi, lp.hi, rtol=1e-8, atol=1e-8 * np.abs(P.b).max())
    if n > 16:  # the 2^n corner enumeration is refused; the zonotope path above is not
        with pytest.raises(pe.InputError, match="at most 16 columns"):
            corner_vertices(P.generators)


@given(seed=st.integers(0, 2**32 - 1), m=st.sampled_from([2, 3]))
def test_rotating_the_task_frame_rotates_every_set_and_keeps_every_score(seed, m):
    analysis = random_problem(seed, m, 5, asymmetric=True)
    R = special_ortho_group.rvs(m, random_state=seed)
    dyn = analysis.dynamics
    rotated = pe.analyze(pe.Dynamics(R @ dyn.J, dyn.B, dyn.g), analysis.tau_max, analysis.tau_min)
    np.testing.assert_allclose(rotated.xg, R @ analysis.xg, atol=1e-9)
    assert rotated.polytope.volume == pytest.approx(analysis.polytope.volume, rel=1e-9)
    np.testing.assert_allclose(
        np.sort(np.linalg.norm(rotated.polytope.vertices, axis=1)),
        np.sort(np.linalg.norm(analysis.polytope.vertices, axis=1)),
        rtol=1e-9,
    )
    T = random_directions(seed, 16, m)
    before, after = scores(analysis, T), scores(rotated, T @ R.T)
    for name, value in before.items():
        assert same(after[name], value, 1e-7), name
