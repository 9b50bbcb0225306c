"""Properties of the analysis that must hold for every robot and configuration."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.inverse import jacobian_pseudoinverse, weighted_generalized_inverse
from reference import RTOL_EXACT, random_arm_analysis, random_directions, random_problem

seeds = st.integers(0, 2**32 - 1)
full_rank = st.sampled_from([(2, 2), (2, 3), (2, 6), (3, 3), (3, 7), (4, 6)])
any_rank = st.sampled_from([(2, 3, 2), (3, 7, 3), (2, 3, 1), (3, 5, 2), (3, 4, 1)])
asymmetric = st.booleans()


def boundary_points(E: pe.Ellipsoid, k: int, seed: int) -> np.ndarray:
    u = random_directions(seed, k, E.rank)
    return E.center + (u * E.semi_axes) @ E.axes.T


@given(seed=seeds, shape=any_rank, asym=asymmetric)
def test_new_ellipsoid_is_inside_the_polytope(seed, shape, asym):
    analysis = random_problem(seed, shape[0], shape[1], rank=shape[2], asymmetric=asym)
    P, E = analysis.polytope, analysis.ellipsoid("chiacchio")
    assert E.rank == P.dim
    assert np.all(E.support(P.A) <= P.b + P.atol)
    assert np.all(P.contains(boundary_points(E, 50, seed)))


@given(seed=st.integers(0, 10**6))
def test_new_ellipsoid_is_inside_the_polytope_for_real_arms(seed):
    analysis = random_arm_analysis(seed, 3 + seed % 4, singular=seed % 3 == 0)
    P, E = analysis.polytope, analysis.ellipsoid("chiacchio")
    assert np.all(E.support(P.A) <= P.b + P.atol)


@given(seed=seeds, shape=full_rank, asym=asymmetric)
def test_classic_ellipsoid_is_inside_the_new_one(seed, shape, asym):
    analysis = random_problem(seed, *shape, asymmetric=asym)
    classic, new = analysis.ellipsoid("yoshikawa"), analysis.ellipsoid("chiacchio")
    np.testing.assert_array_equal(classic.center, new.center)
    gap = np.linalg.eigvalsh(classic.core - new.core)  # N_classic >= N_new
    assert gap.min() >= -RTOL_EXACT * np.abs(classic.core).max()
    assert np.all(new.contains(boundary_points(classic, 50, seed)))
    assert classic.volume <= new.volume * (1 + RTOL_EXACT)


@given(seed=seeds, m=st.integers(1, 4), asym=asymmetric)
def test_both_ellipsoids_coincide_for_a_square_nonsingular_jacobian(seed, m, asym):
    analysis = random_problem(seed, m, m, asymmetric=asym)
    classic, new = analysis.ellipsoid("yoshikawa"), analysis.ellipsoid("chiacchio")
    np.testing.assert_allclose(
        classic.core, new.core, rtol=1e-8, atol=1e-10 * np.abs(new.core).max()
    )
    np.testing.assert_allclose(classic.semi_axes, new.semi_axes, rtol=1e-8)


@given(seed=seeds, shape=full_rank)
def test_new_core_three_ways_eq29_30_32(seed, shape):
    analysis = random_problem(seed, *shape)
    J, Q = analysis.dynamics.J, analysis.Q
    eq30 = np.linalg.inv(J @ np.linalg.solve(Q, J.T))
    JQ = np.linalg.solve(Q, J.T) @ np.linalg.inv(J @ np.linalg.solve(Q, J.T))  # eq. 31
    eq32 = JQ.T @ Q @ JQ
    M_pinv = np.linalg.pinv(analysis.M)
    eq29 = M_pinv.T @ M_pinv
    core = analysis.ellipsoid("chiacchio").core
    for other in (eq29, eq30, eq32):
        np.testing.assert_allclose(core, other, rtol=1e-7, atol=1e-9 * np.abs(core).max())
    np.testing.assert_allclose(
        weighted_generalized_inverse(J, Q, analysis.rank),
        JQ,
        rtol=1e-7,
        atol=1e-9 * np.abs(JQ).max(),
    )


@given(seed=seeds, shape=any_rank, asym=asymmetric)
def test_new_inverse_maps_the_boundary_to_unit_torques(seed, shape, asym):
    analysis = random_problem(seed, shape[0], shape[1], rank=shape[2], asymmetric=asym)
    xdd = boundary_points(analysis.ellipsoid("chiacchio"), 20, seed)
    solution = analysis.inverse(xdd, kind="chiacchio")
    np.testing.assert_allclose(solution.torque_norm, 1.0, rtol=1e-8)
    np.testing.assert_allclose(
        solution.qdd @ analysis.dynamics.J.T, xdd, atol=1e-8 * np.abs(xdd).max()
    )


@given(seed=seeds, shape=any_rank, asym=asymmetric)
def test_new_inverse_minimises_the_normalized_torque_eq34(seed, shape, asym):
    """Against an independent solution: minimise |L^-1 (B qdd + g - tau_c)| on J qdd = x."""
    analysis = random_problem(seed, shape[0], shape[1], rank=shape[2], asymmetric=asym)
    dyn = analysis.dynamics
    x = boundary_points(analysis.ellipsoid("chiacchio"), 1, seed)[0] * 0.7
    # Parametrise J qdd = x as qdd = q0 + Z w and solve the least-squares problem in w.
    q0 = np.linalg.lstsq(dyn.J, x, rcond=None)[0]
    Z = np.linalg.svd(dyn.J)[2][analysis.rank :].T
    W = dyn.B / analysis.half_range[:, None]
    rhs = -(W @ q0 + (dyn.g - analysis.tau_center) / analysis.half_range)
    w = np.linalg.lstsq(W @ Z, rhs, rcond=None)[0]
    expected = q0 + Z @ w
    qdd, _ = analysis.inverse(x, kind="chiacchio")
    np.testing.assert_allclose(qdd, expected, rtol=1e-7, atol=1e-9 * np.abs(expected).max())


@given(seed=seeds, shape=st.sampled_from([(2, 3, 1), (3, 5, 2), (3, 4, 1), (2, 2, 1)]))
def test_singular_inverse_eq40_equals_the_minimum_norm_torque_eq36(seed, shape):
    analysis = random_problem(seed, shape[0], shape[1], rank=shape[2])
    dyn = analysis.dynamics
    x = boundary_points(analysis.ellipsoid("chiacchio"), 5, seed)
    tau_n = (x - analysis.xg) @ analysis.svd.pinv().T  # eq. 36-37
    expected = np.linalg.solve(
        dyn.B, (analysis.half_range * tau_n - (dyn.g - analysis.tau_center)).T
    ).T  # eq. 12
    qdd, tau = analysis.inverse(x, kind="chiacchio")
    np.testing.assert_allclose(qdd, expected, rtol=1e-7, atol=1e-9 * np.abs(expected).max())
    np.testing.assert_allclose(tau, tau_n, atol=1e-9)


@given(seed=seeds, shape=full_rank)
def test_classic_inverse_is_the_minimum_norm_joint_acceleration_eq26(seed, shape):
    analysis = random_problem(seed, *shape)
    x = random_directions(seed, 4, shape[0]) * 10
    qdd, tau_n = analysis.inverse(x, kind="yoshikawa")
    np.testing.assert_allclose(
        qdd, np.linalg.lstsq(analysis.dynamics.J, x.T, rcond=None)[0].T, rtol=1e-8, atol=1e-10
    )
    dyn = analysis.dynamics
    np.testing.assert_allclose(
        tau_n, (qdd @ dyn.B + dyn.g - analysis.tau_center) / analysis.half_range
    )
    np.testing.assert_allclose(
        jacobian_pseudoinverse(dyn.J), np.linalg.pinv(dyn.J), rtol=1e-8, atol=1e-12
    )


@given(seed=seeds, shape=st.sampled_from([(2, 3), (3, 4), (2, 5)]))
def test_asymmetric_limits_give_the_image_of_the_torque_box(seed, shape):
    """The shift tau = tau_c + L tau_n against mapping the raw torque box directly."""
    analysis = random_problem(seed, *shape, asymmetric=True)
    dyn = analysis.dynamics
    corners = np.array(
        list(itertools.product(*zip(analysis.tau_min, analysis.tau_max, strict=True)))
    )
    images = np.linalg.solve(dyn.B, (corners - dyn.g).T).T @ dyn.J.T  # J B^-1 (tau - g), eq. 7
    hull = ConvexHull(images)
    assert analysis.polytope.volume == pytest.approx(hull.volume, rel=RTOL_EXACT)
    assert len(hull.vertices) == len(analysis.polytope.vertices)
    assert np.all(analysis.polytope.contains(images))


@given(seed=seeds, shape=any_rank)
def test_rank_of_M_is_the_rank_of_J(seed, shape):
    analysis = random_problem(seed, shape[0], shape[1], rank=shape[2])
    assert analysis.rank == np.linalg.matrix_rank(analysis.dynamics.J) == shape[2]
    assert analysis.is_singular == (shape[2] < shape[0])


def test_more_task_rows_than_joints_is_a_permanent_singularity():
    analysis = random_problem(0, 3, 2)
    assert analysis.rank == 2 and analysis.is_singular
    assert analysis.polytope.dim == 2 == analysis.ellipsoid().rank


def test_unreachable_acceleration_is_refused_at_a_singularity():
    analysis = random_problem(1, 2, 3, rank=1)
    off = analysis.xg + analysis.svd.U2[:, 0]
    with pytest.raises(pe.UnreachableAccelerationError, match="project it"):
        analysis.inverse(off)
    projected = analysis.polytope.affine_set.project(off)
    qdd, _ = analysis.inverse(projected)
    np.testing.assert_allclose(analysis.dynamics.J @ qdd, projected, atol=1e-9)


def test_ellipsoids_are_cached_and_kinds_checked():
    analysis = random_problem(2, 2, 3)
    assert analysis.ellipsoid("chiacchio") is analysis.ellipsoid("chiacchio")
    with pytest.raises(pe.InputError, match="kind: expected one of 'chiacchio', 'yoshikawa'"):
        analysis.ellipsoid("classic")
    with pytest.raises(pe.InputError, match="kind"):
        analysis.inverse(analysis.xg, kind="Chiacchio")


@pytest.mark.parametrize(
    ("tau_max", "tau_min", "fragment"),
    [
        ([1.0, 0.0, 2.0], None, "tau_max: expected strictly positive"),
        ([1.0, 2.0, 3.0], [0.0, 2.0, 1.0], "tau_min[1] = 2 >= tau_max[1] = 2"),
        ([1.0, 2.0], None, "tau_max: expected an array of real numbers with shape (3,)"),
        ([1.0, np.nan, 2.0], None, "finite values"),
        ([1.0, 2.0, 3.0], [-1.0, -2.0], "tau_min: expected an array"),
    ],
)
def test_bad_torque_limits(tau_max, tau_min, fragment):
    dyn = pe.Dynamics(np.ones((2, 3)), np.eye(3), np.zeros(3))
    with pytest.raises(pe.InputError) as info:
        pe.analyze(dyn, tau_max=tau_max, tau_min=tau_min)
    assert fragment in str(info.value)


def test_analyze_wants_a_dynamics_object():
    with pytest.raises(pe.InputError, match=r"pe\.Dynamics"):
        pe.analyze({"J": np.eye(2)}, tau_max=[1.0, 1.0])


@pytest.mark.parametrize(
    ("directions", "fragment"),
    [
        ([0.0, 0.0], "zero-length direction"),
        ([[1.0, 1.0]], "unit direction vectors"),
        ([1.0, 0.0, 0.0], "2 coordinates in the last axis"),
        ([np.inf, 0.0], "finite values"),
    ],
)
def test_bad_directions(directions, fragment):
    analysis = random_problem(0, 2, 3)
    for limits in (analysis.polytope.limits, analysis.ellipsoid().limits):
        with pytest.raises(pe.InputError) as info:
            limits(directions)
        assert fragment in str(info.value)


@pytest.mark.parametrize("rtol", [-1e-3, 1.0, float("nan")])
def test_bad_rank_tolerance(rtol):
    dyn = pe.Dynamics(np.ones((2, 3)), np.eye(3), np.zeros(3))
    with pytest.raises(pe.InputError, match="rank_rtol: expected a relative tolerance"):
        pe.analyze(dyn, tau_max=[1.0, 1.0, 1.0], rank_rtol=rtol)


def test_rank_tolerance_decides_near_singular_configurations():
    dyn = pe.Dynamics([[1.0, 0.0], [0.0, 1e-8]], np.eye(2), np.zeros(2))
    assert pe.analyze(dyn, tau_max=[1.0, 1.0]).rank == 2
    coarse = pe.analyze(dyn, tau_max=[1.0, 1.0], rank_rtol=1e-6)
    assert coarse.rank == 1 == coarse.polytope.dim == coarse.ellipsoid().rank
