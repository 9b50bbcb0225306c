"""pe.self_motion: configurations with the task coordinates of q0 (issue 22, item 1).

Independent checks: the planar arm's end point by its own closed form (sums of cosines),
its 1-D self-motion against the closed form of DESIGN.md section 7 (the end-link angle
phi parameterises it: the wrist at x0 - l3 u(phi), then 2-R inverse kinematics), and the
Panda's tip by Pinocchio's forward kinematics called here.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import polyell as pe
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR

ARM = pe.robots.load("chiacchio2000")
LENGTHS = np.array([1.0, 0.8, 0.5])
PANDA_Q0 = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])


def tip(q: np.ndarray) -> np.ndarray:
    """The planar arm's end point, written out: sum of l_i u(theta_i)."""
    theta = np.cumsum(q, axis=-1)
    return np.stack([(LENGTHS * np.cos(theta)).sum(-1), (LENGTHS * np.sin(theta)).sum(-1)], -1)


def wrapped(difference: np.ndarray) -> np.ndarray:
    return (difference + np.pi) % (2 * np.pi) - np.pi


@pytest.fixture(scope="module")
def paper_motion() -> pe.SelfMotion:
    return pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=300)


def test_paper_arm_keeps_the_task_point(paper_motion):
    x0 = tip(PAPER_Q_REDUNDANT)
    np.testing.assert_allclose(x0, [0.8, 0.5], atol=1e-15)
    error = np.abs(tip(paper_motion.configurations) - x0).max()
    assert error <= 1e-9
    assert paper_motion.residual <= 1e-9
    assert paper_motion.residual == pytest.approx(error, abs=1e-15)
    assert paper_motion.configurations.shape == (300, 3)
    np.testing.assert_array_equal(paper_motion.target, x0)


def test_paper_arm_traces_one_closed_loop(paper_motion):
    """The loop closes once (traced one way), with no duplicate posture."""
    assert paper_motion.closed and paper_motion.stops == ("closed",)
    assert paper_motion.dimension == 1 and paper_motion.method == "trace"
    q = paper_motion.configurations
    gaps = np.linalg.norm(wrapped(q[:, None, :] - q[None, :, :]), axis=-1)
    gaps[np.diag_indices(len(q))] = np.inf
    spacing = paper_motion.length / len(q)
    assert gaps.min() > 0.5 * spacing  # no duplicates, however the loop is cut
    np.testing.assert_allclose(np.diff(paper_motion.position), spacing, rtol=1e-12)


def test_paper_arm_matches_the_closed_form(paper_motion):
    """Every sample is the 2-R solution for the wrist at x0 - l3 u(phi), on q0's branch.

    |x0| = 0.943 > l3 + |l1 - l2|: every phi is reachable and the two elbow branches are
    two separate loops; the trace covers q0's whole loop (every phi) and never the other.
    """
    q = paper_motion.configurations
    phi = np.cumsum(q, axis=1)[:, 2]
    x0 = np.array([0.8, 0.5])
    wrist = x0 - LENGTHS[2] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    l1, l2 = LENGTHS[:2]
    cos_q2 = ((wrist**2).sum(1) - l1**2 - l2**2) / (2 * l1 * l2)
    elbow = np.sign(np.sin(PAPER_Q_REDUNDANT[1]))  # q0's branch
    q2 = elbow * np.arccos(cos_q2)
    q1 = np.arctan2(wrist[:, 1], wrist[:, 0]) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    q3 = phi - q1 - q2
    np.testing.assert_allclose(wrapped(q[:, 0] - q1), 0.0, atol=1e-9)
    np.testing.assert_allclose(wrapped(q[:, 1] - q2), 0.0, atol=1e-9)
    np.testing.assert_allclose(wrapped(q[:, 2] - q3), 0.0, atol=1e-9)
    # the whole circle of phi, evenly: no gap wider than a few sample spacings
    angles = np.sort(np.mod(phi, 2 * np.pi))
    gaps = np.diff(np.concatenate([angles, [angles[0] + 2 * np.pi]]))
    assert gaps.max() < 10 * 2 * np.pi / len(q)


def test_panda_position_task_random_walk():
    panda = pe.robots.load("panda")
    motion = pe.self_motion(panda, PANDA_Q0, count=40, seed=7)
    assert motion.dimension == 4 and motion.method == "random walk"
    import pinocchio as pin

    data = panda.model.createData()
    frame = panda.model.getFrameId("panda_hand_tcp")

    def position(q):
        pin.framesForwardKinematics(panda.model, data, panda.configuration(q))
        return np.array(data.oMf[frame].translation)

    x0 = position(PANDA_Q0)
    errors = [np.abs(position(q) - x0).max() for q in motion.configurations]
    assert max(errors) <= 1e-9 and motion.residual <= 1e-9
    low, high = panda.position_limits
    assert np.all(motion.configurations >= low) and np.all(motion.configurations <= high)
    # spread over the 4-D manifold: the steps, each in the null space of J at its start
    # (to first order), go along all four of its directions alike; no posture repeats
    steps = np.diff(motion.configurations, axis=0)
    along = []
    for q, dq in zip(motion.configurations[:-1], steps, strict=True):
        null = np.linalg.svd(panda.dynamics(q).J)[2][3:]
        along.append(np.linalg.norm(null @ dq) / np.linalg.norm(dq))
    assert np.median(along) > 0.9
    s = np.linalg.svd(steps @ np.linalg.svd(panda.dynamics(PANDA_Q0).J)[2][3:].T, compute_uv=False)
    assert s[-1] > 0.2 * s[0]
    assert np.linalg.norm(steps, axis=1).min() > 0
    again = pe.self_motion(panda, PANDA_Q0, count=40, seed=7)
    np.testing.assert_array_equal(again.configurations, motion.configurations)
    other = pe.self_motion(panda, PANDA_Q0, count=40, seed=8)
    assert not np.allclose(other.configurations, motion.configurations)


def test_panda_pose_task_traced_to_the_joint_limits():
    panda = pe.robots.load("panda", task=["x", "y", "z", "wx", "wy", "wz"], weights=[1] * 6)
    motion = pe.self_motion(panda, PANDA_Q0, count=30)
    assert motion.dimension == 1 and not motion.closed
    assert motion.stops == ("joint limit", "joint limit")
    p0, R0, _ = panda.tip_kinematics(PANDA_Q0)
    for q in motion.configurations:
        p, R, _ = panda.tip_kinematics(q)
        np.testing.assert_allclose(p, p0, atol=1e-9)
        np.testing.assert_allclose(R, R0, atol=1e-9)
    low, high = panda.position_limits
    ends = motion.configurations[[0, -1]]
    # each end sits at a joint limit, to the trace's resolution (step / 1024)
    reach = np.minimum(np.abs(ends - low), np.abs(ends - high)).min(axis=1)
    assert np.all(reach < 0.01)


def test_tip_kinematics_jacobian_is_the_dynamics_one():
    panda = pe.robots.load("panda")
    _, _, J = panda.tip_kinematics(PANDA_Q0)
    np.testing.assert_array_equal(J, panda.dynamics(PANDA_Q0).J)


# --- bad input ----------------------------------------------------------------------------


def test_singular_q0_is_refused():
    with pytest.raises(pe.InputError, match="q0: expected a non-singular"):
        pe.self_motion(ARM, PAPER_Q_SINGULAR)


def test_q0_off_the_limits_is_refused():
    panda = pe.robots.load("panda")
    q = PANDA_Q0.copy()
    q[3] = 0.5  # panda_joint4 lies in [-3.07, -0.07]
    with pytest.raises(pe.InputError, match=r"q0\[3\] = 0.5 outside"):
        pe.self_motion(panda, q)


def test_non_redundant_arms_are_refused():
    two_links = pe.PlanarArm(lengths=[1.0, 1.0], masses=[1.0, 1.0])
    with pytest.raises(pe.InputError, match="robot: expected a redundant arm") as info:
        pe.self_motion(two_links, [0.3, 0.4])
    assert info.value.fix
    ur5 = pe.robots.load("ur5", task=["x", "y", "z", "wx", "wy", "wz"], weights=[1] * 6)
    with pytest.raises(pe.InputError, match="6 joints for 6 task rows"):
        pe.self_motion(ur5, [0.1, -1.0, 1.0, -1.0, 1.0, 0.2])


def test_partial_orientation_is_refused():
    panda = pe.robots.load("panda", task=["x", "y", "wz"], weights=[1, 1, 1])
    with pytest.raises(pe.InputError, match="robot: expected a task with coordinates"):
        pe.self_motion(panda, PANDA_Q0)


def test_other_robots_are_refused():
    with pytest.raises(pe.InputError, match=r"robot: expected a pe\.PlanarArm"):
        pe.self_motion(ARM.dynamics(PAPER_Q_REDUNDANT), PAPER_Q_REDUNDANT)


@given(st.one_of(st.integers(max_value=0), st.integers(min_value=100_001), st.floats(), st.none()))
def test_bad_counts_are_refused(count):
    with pytest.raises(pe.InputError) as info:
        pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=count)
    assert info.value.argument == "count"


@given(
    st.one_of(
        st.floats(max_value=0.0),
        st.floats(min_value=0.0, max_value=1e-9, exclude_max=True),  # too small to move q
        st.floats(min_value=1.0, exclude_min=True),
        st.booleans(),
        st.text(max_size=3),
    )
)
def test_bad_steps_are_refused(step):
    with pytest.raises(pe.InputError) as info:
        pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=3, step=step)
    assert info.value.argument == "step"


@pytest.mark.parametrize("q0", [[0.1, 0.2], [0.1, 0.2, 0.3, 0.4], [0.1, np.nan, 0.3]])
def test_bad_q0_is_refused(q0):
    with pytest.raises(pe.InputError) as info:
        pe.self_motion(ARM, q0)
    assert info.value.argument == "q0"


@pytest.mark.parametrize("unit", [1e-9, 1e-3, 1e3, 1e6])
def test_the_self_motion_does_not_depend_on_the_unit_of_length(unit):
    """Lengths in any unit trace the same joint angles (issue 33: an absolute residual
    refused kilometres given in millimetres and accepted anything at nanometres)."""
    q0 = [np.pi / 2, -np.pi / 2, -np.pi / 2]
    lengths = np.array([1.0, 0.8, 0.5])
    reference = pe.self_motion(pe.PlanarArm(lengths=lengths, masses=[4.0, 2.0, 0.6]), q0, count=20)
    scaled = pe.self_motion(
        pe.PlanarArm(lengths=lengths * unit, masses=[4.0, 2.0, 0.6]), q0, count=20
    )
    np.testing.assert_allclose(scaled.configurations, reference.configurations, atol=1e-12)
    assert scaled.residual <= 1e-12 * unit


@pytest.mark.parametrize("eps", [1e-3, 1e-4])
def test_a_loop_smaller_than_the_step_is_traced_at_its_own_scale(eps):
    """Near the stretched arm the self-motion is a loop of some 5 eps rad: with the
    default step of 0.01 its points zig-zagged and its length read 0.03 whatever eps. It
    is traced again at a tenth of its extent: its length is the closed polyline's through
    its samples (to 1 %) and at most pi times its diameter (0.03 was twice that at 1e-3)."""
    arm = pe.robots.load("chiacchio2000")
    motion = pe.self_motion(arm, [0.3, eps, eps], count=60)
    C = motion.configurations
    polyline = np.linalg.norm(np.diff(np.vstack([C, C[:1]]), axis=0), axis=1).sum()
    diameter = np.linalg.norm(C[:, None] - C[None], axis=-1).max()
    assert motion.length == pytest.approx(polyline, rel=1e-2)
    assert motion.length <= np.pi * diameter
    assert np.all(np.diff(motion.position) > 0) and motion.position[-1] < motion.length


def test_a_loop_below_the_tracers_resolution_is_refused_by_name():
    arm = pe.robots.load("chiacchio2000")
    with pytest.raises(pe.InputError, match=r"^q0: .*shrinks to a point.*Fix: "):
        pe.self_motion(arm, [0.3, 1e-7, 1e-7], count=20)
