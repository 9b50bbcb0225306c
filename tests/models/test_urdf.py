"""UrdfRobot: against the closed-form planar arm, Pinocchio called directly, and finite
differences of quantities Pinocchio computes by other algorithms."""

from __future__ import annotations

import importlib.metadata
import sys

import numpy as np
import pinocchio as pin
import pytest

import polyell as pe
from reference import PAPER_ARM, PAPER_Q_REDUNDANT, PAPER_TAU_MAX, planar_urdf


def planar_robot(joint_type: str = "revolute", **options) -> pe.UrdfRobot:
    return pe.UrdfRobot(
        planar_urdf(PAPER_ARM, joint_type), "tip", task="planar", gravity=(0, -9.81, 0), **options
    )


@pytest.mark.parametrize("joint_type", ["revolute", "continuous"])
@pytest.mark.parametrize("seed", range(5))
def test_planar_urdf_equals_the_closed_form_arm(joint_type, seed):
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, 3)
    urdf, closed = planar_robot(joint_type).dynamics(q), PAPER_ARM.dynamics(q)
    np.testing.assert_allclose(urdf.J, closed.J, atol=1e-12)
    np.testing.assert_allclose(urdf.B, closed.B, atol=1e-12)
    np.testing.assert_allclose(urdf.g, closed.g, atol=1e-10)


def test_planar_urdf_reproduces_the_paper():
    robot = planar_robot(tau_max=PAPER_TAU_MAX)
    analysis = pe.analyze(robot.dynamics(PAPER_Q_REDUNDANT), robot.tau_max)
    np.testing.assert_allclose(analysis.xg, [0.0, -12.392], atol=5e-4)
    lo, hi = analysis.ellipsoid("chiacchio").limits([1.0, 0.0])
    assert (round(float(lo), 3), round(float(hi), 3)) == (-43.401, 35.284)


def coriolis_from_inertia(arm: pe.PlanarArm, q, qd, h=1e-6):
    """c(q, qd) by Christoffel symbols of the closed-form B, differentiated numerically."""
    n = q.size
    dB = np.array(
        [(arm.dynamics(q + h * e).B - arm.dynamics(q - h * e).B) / (2 * h) for e in np.eye(n)]
    )
    # dB[k, i, j] = dB_ij / dq_k;  c_i = sum_jk (dB_ij/dq_k - 1/2 dB_jk/dq_i) qd_j qd_k
    return np.einsum("kij,j,k->i", dB, qd, qd) - 0.5 * np.einsum("ijk,j,k->i", dB, qd, qd)


def test_moving_robot_adds_coriolis_torques_and_the_velocity_acceleration():
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3)
    robot = planar_robot()
    moving, still = robot.dynamics(q, qd), robot.dynamics(q)
    np.testing.assert_allclose(
        moving.g - still.g, coriolis_from_inertia(PAPER_ARM, q, qd), atol=1e-6
    )
    h = 1e-6
    jdot_qd = (PAPER_ARM.jacobian(q + h * qd) - PAPER_ARM.jacobian(q - h * qd)) / (2 * h) @ qd
    np.testing.assert_allclose(moving.xdd_bias, jdot_qd, atol=1e-6)
    np.testing.assert_array_equal(robot.dynamics(q, np.zeros(3)).xdd_bias, 0.0)
    # The centre moves by the bias; the map M does not change.
    at_rest, in_motion = pe.analyze(still, PAPER_TAU_MAX), pe.analyze(moving, PAPER_TAU_MAX)
    np.testing.assert_allclose(in_motion.M, at_rest.M)
    solution = in_motion.inverse(in_motion.xg)
    np.testing.assert_allclose(moving.J @ solution.qdd + moving.xdd_bias, in_motion.xg, atol=1e-9)


@pytest.mark.parametrize("joint_type", ["revolute", "continuous"])
def test_batched_dynamics_equal_the_closed_form_arm_row_by_row(joint_type):
    rng = np.random.default_rng(7)
    Q, Qd = rng.uniform(-np.pi, np.pi, (6, 3)), rng.uniform(-2, 2, (6, 3))
    Qd[2] = 0.0  # a row at rest among moving ones
    robot = planar_robot(joint_type)
    still, moving, closed = robot.dynamics(Q), robot.dynamics(Q, Qd), PAPER_ARM.dynamics(Q)
    assert still.batch_size == moving.batch_size == 6
    for dyn in (still, moving):
        np.testing.assert_allclose(dyn.J, closed.J, atol=1e-12)
        np.testing.assert_allclose(dyn.B, closed.B, atol=1e-12)
    np.testing.assert_allclose(still.g, closed.g, atol=1e-10)
    np.testing.assert_array_equal(still.xdd_bias, 0.0)
    h = 1e-6
    for q, qd, g, bias in zip(Q, Qd, moving.g - still.g, moving.xdd_bias, strict=True):
        np.testing.assert_allclose(g, coriolis_from_inertia(PAPER_ARM, q, qd), atol=1e-6)
        jdot = (PAPER_ARM.jacobian(q + h * qd) - PAPER_ARM.jacobian(q - h * qd)) / (2 * h)
        np.testing.assert_allclose(bias, jdot @ qd, atol=1e-6)


def test_configuration_vectors_of_continuous_joints():
    robot, q = planar_robot("continuous"), np.array([[0.3, -1.0, 2.5], [0.0, np.pi, -0.5]])
    config = robot.configuration(q)
    assert config.shape == (2, 6)
    np.testing.assert_allclose(config[:, 0::2], np.cos(q), atol=1e-15)
    np.testing.assert_allclose(config[:, 1::2], np.sin(q), atol=1e-15)
    np.testing.assert_array_equal(robot.configuration(q[1]), config[1])


def test_point_payload_adds_its_mass_at_the_tip():
    q = np.array([0.3, -0.7, 1.1])
    plain, loaded = planar_robot(), planar_robot(payload=pe.Payload(mass=1.5))
    d0, d1 = plain.dynamics(q), loaded.dynamics(q)
    J = d0.J  # the tip's (x, y) Jacobian: the payload is a point mass there
    np.testing.assert_allclose(d1.B - d0.B, 1.5 * J.T @ J, atol=1e-12)
    np.testing.assert_allclose(d1.g - d0.g, 1.5 * 9.81 * J[1], atol=1e-10)


@pytest.fixture(scope="module")
def panda() -> pe.UrdfRobot:
    return pe.robots.load("panda")


# Pinocchio's neutral q (zeros) is outside joint 4's limits: evaluated on purpose.
@pytest.mark.filterwarnings("ignore::polyell.JointLimitWarning")
def test_panda_against_pinocchio_called_directly(panda):
    full = pin.buildModelFromUrdf(str(pe.robots.urdf_path("panda")))
    locked = [full.getJointId(n) for n in ("panda_finger_joint1", "panda_finger_joint2")]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    data = model.createData()
    frame = model.getFrameId("panda_hand_tcp")
    for seed in range(3):
        q = pin.randomConfiguration(model) if seed else pin.neutral(model)
        J = pin.computeFrameJacobian(model, data, q, frame, pin.LOCAL_WORLD_ALIGNED)[:3]
        B = pin.crba(model, data, q)
        B = np.triu(B) + np.triu(B, 1).T
        g = pin.rnea(model, data, q, np.zeros(7), np.zeros(7))
        dyn = panda.dynamics(q)
        np.testing.assert_allclose(dyn.J, J, atol=1e-12)
        np.testing.assert_allclose(dyn.B, B, atol=1e-12)
        np.testing.assert_allclose(dyn.g, g, atol=1e-10)


def test_panda_jacobian_and_gravity_by_finite_differences(panda):
    model, data = panda.model, panda.model.createData()
    frame = model.getFrameId("panda_hand_tcp")
    q = np.array([0.1, -0.4, 0.2, -2.0, 0.3, 1.6, 0.5])
    h = 1e-6

    def tip(x):
        pin.framesForwardKinematics(model, data, panda.configuration(x))
        return data.oMf[frame].translation.copy()

    def potential(x):
        return pin.computePotentialEnergy(model, data, panda.configuration(x))

    steps = np.eye(7) * h
    J = np.array([(tip(q + e) - tip(q - e)) / (2 * h) for e in steps]).T
    g = np.array([(potential(q + e) - potential(q - e)) / (2 * h) for e in steps])
    dyn = panda.dynamics(q)
    np.testing.assert_allclose(dyn.J, J, atol=1e-7)
    np.testing.assert_allclose(dyn.g, g, atol=1e-6)
    np.testing.assert_allclose(panda.tau_max, [87, 87, 87, 87, 12, 12, 12])


# q = 0.2 puts joint 4 outside its limits: evaluated on purpose (the rows, not the posture).
@pytest.mark.filterwarnings("ignore::polyell.JointLimitWarning")
def test_task_rows_and_weights(panda):
    q = np.full(7, 0.2)
    six = pe.robots.load(
        "panda", task=["x", "y", "z", "wx", "wy", "wz"], weights=[1, 1, 1, 0.5, 0.5, 0.5]
    )
    full = six.dynamics(q).J
    np.testing.assert_allclose(full[:3], panda.dynamics(q).J)
    angular = pe.robots.load("panda", task="angular").dynamics(q).J
    np.testing.assert_allclose(full[3:], 0.5 * angular)
    assert pe.robots.load("panda", task=[2, "wz"], weights=[1, 1]).m == 2


@pytest.mark.parametrize(
    ("options", "fragment"),
    [
        ({"task": ["x", "wz"]}, "rows that are all linear or all angular"),
        ({"task": "spatial"}, "task: expected one of ['linear', 'angular', 'planar']"),
        ({"task": ["x", "x"]}, "distinct rows"),
        ({"task": ["q"]}, "rows among"),
        ({"weights": [1.0, -1.0, 1.0]}, "weights: expected positive scales"),
        ({"tip": "nose"}, "tip: expected a frame of the robot"),
        ({"locked_joints": ["finger"]}, "locked_joints: expected joint names among"),
        ({"tau_max": [1.0, 2.0]}, "tau_max: expected an array of real numbers with shape (7,)"),
    ],
)
def test_bad_robot_options(options, fragment):
    with pytest.raises(pe.InputError) as info:
        pe.robots.load("panda", **options)
    assert fragment in str(info.value)


def test_bad_urdf_inputs(tmp_path):
    with pytest.raises(pe.InputError, match="an existing URDF file"):
        pe.UrdfRobot(tmp_path / "missing.urdf", "tip")
    with pytest.raises(pe.InputError, match="a valid URDF description"):
        pe.UrdfRobot("<robot name='x'><link></robot>", "tip")
    no_effort = planar_urdf(PAPER_ARM).replace('effort="50"', 'effort="0"')
    with pytest.raises(pe.InputError, match="effort limits in the URDF"):
        pe.UrdfRobot(no_effort, "tip")


# q = 0.1 is outside the limits of some arms (the Panda's joint 4, the Kinova's joint 2).
@pytest.mark.filterwarnings("ignore::polyell.JointLimitWarning")
def test_every_library_arm_loads():
    for name in pe.robots.URDF_ARMS:
        robot = pe.robots.load(name)
        dyn = robot.dynamics(np.full(robot.nq, 0.1))
        assert dyn.J.shape == (3, robot.nq) and np.all(robot.tau_max > 0)
        assert len(robot.joint_names) == robot.nq
    assert pe.robots.load("z1").nq == 6  # gripper locked


def test_missing_extras_name_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pinocchio", None)
    with pytest.raises(pe.MissingDependencyError, match=r"pip install '\.\[robots\]'"):
        pe.UrdfRobot("<robot/>", "tip")
    monkeypatch.undo()

    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", missing)
    with pytest.raises(
        pe.MissingDependencyError, match=r"polyell repository, run pip install '\.\[robots\]'"
    ):
        pe.robots.load("ur5")
    assert pe.robots.load("chiacchio2000").n == 3  # no extra needed
