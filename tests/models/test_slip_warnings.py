"""Small slips that used to pass silently (issue 32): warnings, and the derated analysis.

* Joint positions outside a URDF's limits (joint angles in degrees, most often) warn with a
  ``pe.JointLimitWarning`` naming the joints, once per call.  The limits the tests expect
  are read from the URDF's XML here (not through Pinocchio).
* A robot in motion whose drives derate, analysed with its rated torque limits, warns with
  a ``pe.DeratingWarning``; ``robot.analyze(q, qd)`` analyses it with the limits at ``qd``.
  Its z limits are checked against an independent computation: the linear torque-speed
  curve evaluated by hand, the map from torques to the tip's acceleration by Pinocchio's
  articulated-body algorithm (ABA, not the inertia matrix polyell inverts) and a linear
  program over the torque box (``scipy.optimize.linprog``).
"""

from __future__ import annotations

import pickle
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import linprog

import polyell as pe
import polyell.capacities
import polyell.capacities.acceleration
import polyell.capacities.base
import polyell.capacities.force
import polyell.models.self_motion
from polyell.models.dynamics import MotionLimits, check_motion_limits, warn_rated_limits_in_motion
from reference import PAPER_ARM, planar_urdf

PANDA = pe.robots.load("panda")
#: A Panda posture within its limits (radians).
Q = np.array([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8])
#: Joint velocities [rad/s]: joint 2 forward, joint 4 backward, joint 6 forward.
QD = np.array([0.0, 1.2, 0.0, -1.5, 0.0, 2.0, 0.0])
STALL = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0])
NO_LOAD = np.array([2.5, 2.5, 2.5, 2.5, 3.0, 3.0, 3.0])
DRIVES = pe.TorqueSpeed.linear(STALL, NO_LOAD)
#: Relative tolerance of the LP's limits against polyell's closed form: both solve the
#: same small, well-scaled problem (7 torques of size <= 87 N m) to about 1e-12.
RTOL = 1e-8


#: Whether the hooks outside this change's files are in (see the skip reasons).
def urdf_limits(name: str) -> dict[str, tuple[float, float]]:
    """``{joint: (lower, upper)}`` of the revolute and prismatic joints, from the XML."""
    root = ET.parse(pe.robots.urdf_path(name)).getroot()
    limits = {}
    for joint in root.iter("joint"):
        limit = joint.find("limit")
        if joint.get("type") in ("revolute", "prismatic") and limit is not None:
            limits[joint.get("name")] = (float(limit.get("lower")), float(limit.get("upper")))
    return limits


PANDA_LIMITS = urdf_limits("panda")


def outside(q: np.ndarray) -> list[str]:
    """The Panda joints whose value in q is outside the XML's limits."""
    names = [f"panda_joint{i + 1}" for i in range(7)]
    return [
        n
        for n, v in zip(names, q, strict=True)
        if not PANDA_LIMITS[n][0] <= v <= PANDA_LIMITS[n][1]
    ]


def caught(category: type[Warning], call) -> list[warnings.WarningMessage]:
    """The warnings of ``category`` that ``call()`` issues (every one: filter "always")."""
    with warnings.catch_warnings(record=True) as records:
        warnings.simplefilter("always")
        call()
    return [r for r in records if issubclass(r.category, category)]


# --- joint limits -------------------------------------------------------------------------


def test_the_warnings_are_polyell_warnings():
    for category in (pe.JointLimitWarning, pe.DeratingWarning, pe.ProjectedInputWarning):
        assert issubclass(category, pe.PolyellWarning) and issubclass(category, UserWarning)
        assert category.__name__ in pe.__all__
    assert "PolyellWarning" in pe.__all__


def test_degrees_on_the_panda_warn_naming_the_joints():
    q = np.rad2deg(Q)  # the slip: degrees where radians are expected (joint 4 at -114.6)
    expected = outside(q)
    assert expected == ["panda_joint2", "panda_joint4", "panda_joint6", "panda_joint7"]
    with pytest.warns(pe.JointLimitWarning) as records:
        PANDA.dynamics(q)
    assert len(records) == 1
    warning = records[0].message
    assert warning.joints == tuple(expected) and warning.degrees
    text = str(warning)
    assert text.startswith("q: expected joint positions within the robot's limits")
    for name in expected:
        assert name in text
    for name in ("panda_joint1", "panda_joint3", "panda_joint5"):
        assert name not in text
    # joint 4: the value and how far below its lower limit, from the XML's limits
    low4 = PANDA_LIMITS["panda_joint4"][0]
    assert f"panda_joint4 = {q[3]:.6g} rad ({low4 - q[3]:.4g} rad below" in text
    assert "look like degrees" in text and "np.deg2rad" in text
    assert records[0].filename == __file__  # the caller's line, not polyell's


def test_a_small_slip_warns_without_the_degrees_hint():
    q = Q.copy()
    q[3] = 0.0  # joint 4 of the Panda stops at -0.0698 rad: 0 is just outside
    records = caught(pe.JointLimitWarning, lambda: PANDA.dynamics(q))
    assert len(records) == 1
    assert records[0].message.joints == ("panda_joint4",) and not records[0].message.degrees
    assert "degrees" not in str(records[0].message)
    high4 = PANDA_LIMITS["panda_joint4"][1]
    assert f"{0.0 - high4:.4g} rad above its range" in str(records[0].message)


def test_within_the_limits_nothing_warns():
    low, high = PANDA.position_limits
    np.testing.assert_array_equal(low, [PANDA_LIMITS[f"panda_joint{i + 1}"][0] for i in range(7)])
    batch = pe.random_configurations(500, low, high, seed=32).rows(0, 500)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails the test
        PANDA.dynamics(Q)
        PANDA.dynamics(batch)
        PANDA.dynamics(Q, QD)
        PANDA.tip_kinematics(Q)
        PANDA.dynamics(np.stack([low, high]))  # exactly at the limits
        PANDA.dynamics(np.stack([low - 1e-6, high + 1e-6]))  # within the tolerance


def test_a_batch_warns_once():
    low, high = PANDA.position_limits
    batch = pe.random_configurations(1000, low, high, seed=33).rows(0, 1000)
    rows = np.random.default_rng(33).choice(1000, size=10, replace=False)
    batch[rows, 3] = 0.3  # joint 4 above its upper limit in 10 rows
    records = caught(pe.JointLimitWarning, lambda: PANDA.dynamics(batch))
    assert len(records) == 1
    text = str(records[0].message)
    assert "panda_joint4 in 10 of 1000 configurations" in text
    assert f"row {rows.min()}," in text  # the worst row: all are 0.3, the first is named
    assert records[0].message.joints == ("panda_joint4",)


def urdf_velocity_limits(name: str) -> dict[str, float]:
    """``{joint: velocity}`` of the revolute and prismatic joints, from the XML."""
    root = ET.parse(pe.robots.urdf_path(name)).getroot()
    return {
        joint.get("name"): float(joint.find("limit").get("velocity"))
        for joint in root.iter("joint")
        if joint.get("type") in ("revolute", "prismatic") and joint.find("limit") is not None
    }


def test_velocities_in_degrees_per_second_warn_naming_the_joints():
    """The slip of issue 32's new user: qd = 30 deg/s typed as 30 (rad/s) on two joints."""
    limits = urdf_velocity_limits("panda")
    qd = np.zeros(7)
    qd[[0, 3]] = 30.0
    records = caught(pe.JointLimitWarning, lambda: PANDA.dynamics(Q, qd))
    assert len(records) == 1
    warning = records[0].message
    assert warning.joints == ("panda_joint1", "panda_joint4") and warning.degrees
    text = str(warning)
    assert text.startswith("qd: expected joint velocities within the robot's velocity limits")
    assert f"panda_joint4 = 30 rad/s (beyond its limits [{-limits['panda_joint4']:.6g}, " in text
    assert "degrees per second" in text and "np.deg2rad(qd)" in text
    assert records[0].filename == __file__
    # robot.analyze and a batch: one warning each, the rows counted
    assert len(caught(pe.JointLimitWarning, lambda: PANDA.analyze(Q, qd))) == 1
    batch = np.tile(QD, (50, 1))
    batch[[4, 9], 5] = -3.0  # joint 6 beyond -2.61 rad/s in 2 rows: a slip, not degrees
    records = caught(pe.JointLimitWarning, lambda: PANDA.dynamics(np.tile(Q, (50, 1)), batch))
    assert len(records) == 1 and not records[0].message.degrees
    assert "panda_joint6 in 2 of 50 states (worst: row 4, qd = -3 rad/s" in str(records[0].message)
    assert "degrees" not in str(records[0].message)


def test_velocities_at_the_limits_do_not_warn():
    qd_max, qd_min = PANDA.velocity_limits()
    limits = urdf_velocity_limits("panda")
    np.testing.assert_array_equal(qd_max, [limits[f"panda_joint{i + 1}"] for i in range(7)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        PANDA.dynamics(np.tile(Q, (2, 1)), np.stack([qd_max, qd_min]))
        PANDA.dynamics(Q, qd_max * (1 + 1e-9))  # within the tolerance
        PANDA.dynamics(Q, 100.0 * qd_max, check_limits=False)  # probing on purpose


def test_continuous_joints_never_warn():
    continuous = pe.UrdfRobot(planar_urdf(PAPER_ARM, "continuous"), "tip", task="planar")
    far = np.array([100.0, -720.0, 1e4])  # many turns: a continuous joint has no limits
    assert not caught(pe.JointLimitWarning, lambda: continuous.dynamics(far))
    assert not caught(pe.JointLimitWarning, lambda: continuous.dynamics(np.stack([far, -far])))
    assert not caught(pe.JointLimitWarning, lambda: continuous.tip_kinematics(far))
    # the same arm with revolute joints (limits +-10 rad in the URDF) warns
    revolute = pe.UrdfRobot(planar_urdf(PAPER_ARM, "revolute"), "tip", task="planar")
    records = caught(pe.JointLimitWarning, lambda: revolute.dynamics(far))
    assert len(records) == 1 and records[0].message.joints == ("joint0", "joint1", "joint2")


def test_a_prismatic_joint_gets_no_degrees_hint():
    slider = pe.UrdfRobot(planar_urdf(PAPER_ARM, "prismatic"), "tip", task="planar")
    records = caught(pe.JointLimitWarning, lambda: slider.dynamics([12.0, 0.0, 0.0]))
    assert len(records) == 1 and not records[0].message.degrees
    assert "joint0 = 12 m (2 m above its range [-10, 10])" in str(records[0].message)


def test_the_warnings_filters_are_respected():
    q = np.rad2deg(Q)
    with warnings.catch_warnings(record=True) as records:
        warnings.simplefilter("always")
        warnings.simplefilter("ignore", pe.JointLimitWarning)
        PANDA.dynamics(q)
    assert not records
    with warnings.catch_warnings():
        warnings.simplefilter("error", pe.PolyellWarning)
        with pytest.raises(pe.JointLimitWarning, match="look like degrees"):
            PANDA.dynamics(q)


def test_tip_kinematics_warns_unless_asked_not_to():
    q = np.rad2deg(Q)
    records = caught(pe.JointLimitWarning, lambda: PANDA.tip_kinematics(q))
    assert len(records) == 1 and records[0].filename == __file__
    assert not caught(pe.JointLimitWarning, lambda: PANDA.tip_kinematics(q, check_limits=False))
    assert not caught(pe.JointLimitWarning, lambda: PANDA.dynamics(q, check_limits=False))


def test_a_batch_checked_once_then_evaluated_in_chunks():
    batch = np.stack([Q, np.rad2deg(Q), Q, np.rad2deg(Q)])
    records = caught(pe.JointLimitWarning, lambda: PANDA.check_positions(batch))
    assert len(records) == 1 and records[0].filename == __file__
    assert "panda_joint4 in 2 of 4 configurations (worst: row 1," in str(records[0].message)
    chunks = [lambda i=i: PANDA.dynamics(batch[i : i + 2], check_limits=False) for i in (0, 2)]
    assert not any(caught(pe.JointLimitWarning, chunk) for chunk in chunks)
    assert not caught(pe.JointLimitWarning, lambda: PANDA.check_positions(Q))
    with pytest.raises(pe.InputError, match="q: expected an array of joint positions"):
        PANDA.check_positions(Q[:3])


def test_the_warning_pickles_with_its_attributes():
    records = caught(pe.JointLimitWarning, lambda: PANDA.dynamics(np.rad2deg(Q)))
    copy = pickle.loads(pickle.dumps(records[0].message))
    assert str(copy) == str(records[0].message)


def test_self_motion_probing_the_limits_does_not_warn():
    panda = pe.robots.load("panda", task=["x", "y", "z", "wx", "wy", "wz"], weights=[1] * 6)
    q0 = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
    records = caught(pe.JointLimitWarning, lambda: pe.self_motion(panda, q0, count=30))
    assert not records


# --- torque limits in motion --------------------------------------------------------------


def derated_by_hand(qd: np.ndarray, rated_max: np.ndarray, rated_min: np.ndarray):
    """The linear DC-drive derating, written out: the side along the motion falls."""
    curve = np.maximum(0.0, STALL * (1.0 - np.abs(qd) / NO_LOAD))
    upper = np.where(qd > 0, np.minimum(rated_max, curve), rated_max)
    lower = np.where(qd < 0, np.maximum(rated_min, -curve), rated_min)
    return upper, lower


def z_limits_by_lp(robot: pe.UrdfRobot, q, qd, upper, lower) -> tuple[float, float]:
    """The limits along +z: the range of a with (0, 0, a) achievable, by ABA and linprog.

    The tip's acceleration is affine in the torques: its value at tau = 0 and its slopes
    come from Pinocchio's forward dynamics (ABA) and the frame's classical acceleration.
    The linear programs keep x and y at 0 and minimise and maximise z over the torque box.
    """
    model = robot.model
    data = model.createData()
    frame = model.getFrameId("panda_hand_tcp")
    q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)

    def acceleration(tau: np.ndarray) -> np.ndarray:
        qdd = pin.aba(model, data, q, qd, tau)
        pin.forwardKinematics(model, data, q, qd, qdd)
        pin.updateFramePlacements(model, data)
        world = pin.LOCAL_WORLD_ALIGNED
        return np.array(pin.getFrameClassicalAcceleration(model, data, frame, world).linear)

    n = robot.nq
    a0 = acceleration(np.zeros(n))
    slopes = np.stack([acceleration(np.eye(n)[j]) - a0 for j in range(n)], axis=1)  # (3, n)
    bounds = list(zip(lower, upper, strict=True))
    along = {"A_eq": slopes[:2], "b_eq": -a0[:2], "bounds": bounds, "method": "highs"}
    low = linprog(slopes[2], **along)
    high = linprog(-slopes[2], **along)
    assert low.status == 0 and high.status == 0
    return a0[2] + low.fun, a0[2] - high.fun


@pytest.fixture(scope="module")
def moving():
    robot = pe.robots.load("panda", torque_speed=DRIVES)
    return robot, robot.dynamics(Q, QD)


def test_the_dynamics_of_a_moving_robot_carry_the_derated_limits(moving):
    robot, dyn = moving
    upper, lower = derated_by_hand(QD, robot.tau_max, robot.tau_min)
    assert isinstance(dyn.motion, MotionLimits)
    np.testing.assert_allclose(dyn.motion.tau_max, upper, rtol=1e-14)
    np.testing.assert_allclose(dyn.motion.tau_min, lower, rtol=1e-14)
    np.testing.assert_array_equal(dyn.motion.qd, QD)
    assert robot.dynamics(Q).motion is None  # at rest
    assert robot.dynamics(Q, np.zeros(7)).motion is None
    assert PANDA.dynamics(Q, QD).motion is None  # no torque-speed model
    batch = robot.dynamics(np.stack([Q, Q]), np.stack([QD, -QD]))
    np.testing.assert_array_equal(batch[1].motion.qd, -QD)


def test_rated_limits_on_a_moving_robot_warn(moving):
    robot, dyn = moving
    upper, lower = derated_by_hand(QD, robot.tau_max, robot.tau_min)
    expected = tuple(
        name
        for name, up, lo, r_up, r_lo in zip(
            robot.joint_names, upper, lower, robot.tau_max, robot.tau_min, strict=True
        )
        if up < r_up or lo > r_lo
    )
    assert expected == ("panda_joint2", "panda_joint4", "panda_joint6")
    analysis = pe.analyze(dyn, robot.tau_max, robot.tau_min)
    records = caught(pe.DeratingWarning, lambda: warn_rated_limits_in_motion(analysis))
    assert len(records) == 1
    warning = records[0].message
    assert warning.joints == expected
    text = str(warning)
    assert text.startswith("tau_max and tau_min: torque limits beyond what the drives give")
    assert "rated limits" in text and "robot.torque_limits(qd)" in text
    assert "robot.analyze(q, qd)" in text
    assert (
        f"panda_joint2 (qd = 1.2 rad/s): tau_max = 87 N m, its drive gives at most {upper[1]:.4g}"
        in text
    )
    # the same check on the arrays
    records = caught(
        pe.DeratingWarning, lambda: check_motion_limits(dyn, robot.tau_max, robot.tau_min)
    )
    assert len(records) == 1 and records[0].filename == __file__


def test_derated_limits_or_rest_do_not_warn(moving):
    robot, dyn = moving
    derated = pe.analyze(dyn, *robot.torque_limits(QD))
    tighter = pe.analyze(dyn, *(0.5 * np.array(robot.torque_limits(QD))))
    at_rest = pe.analyze(robot.dynamics(Q), robot.tau_max, robot.tau_min)
    no_model = pe.analyze(PANDA.dynamics(Q, QD), PANDA.tau_max, PANDA.tau_min)
    velocity = pe.analyze(dyn, capacity="velocity", qd_max=robot.qd_max)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for analysis in (derated, tighter, at_rest, no_model, velocity):
            warn_rated_limits_in_motion(analysis)
        robot.analyze(Q, QD)
        robot.analyze(Q, QD, capacity="force")
        robot.analyze(Q)


def test_a_batch_in_motion_warns_once(moving):
    robot, _ = moving
    batch = robot.dynamics(np.stack([Q] * 4), np.stack([QD, 0 * QD, -QD, 0.5 * QD]))
    records = caught(
        pe.DeratingWarning, lambda: check_motion_limits(batch, robot.tau_max, robot.tau_min)
    )
    assert len(records) == 1
    text = str(records[0].message)
    # joint 2 moves forward in rows 0 and 3 (its tau_max derated), backward in row 2
    assert "panda_joint2 (row 0, qd = 1.2 rad/s): tau_max = 87 N m" in text
    assert "there (in 2 of 4 configurations)" in text
    assert "panda_joint2 (row 2, qd = -1.2 rad/s): tau_min = -87 N m" in text


def test_pe_analyze_warns_with_rated_limits_in_motion(moving):
    robot, dyn = moving
    with pytest.warns(pe.DeratingWarning, match="panda_joint2") as records:
        pe.analyze(dyn, robot.tau_max, robot.tau_min)
    assert len(records) == 1 and records[0].filename == __file__
    with pytest.warns(pe.DeratingWarning):
        pe.analyze(dyn, robot.tau_max, robot.tau_min, capacity="force")
    assert not caught(pe.DeratingWarning, lambda: pe.analyze(dyn, *robot.torque_limits(QD)))


def test_robot_analyze_in_motion_gives_the_derated_set(moving):
    robot, dyn = moving
    upper, lower = derated_by_hand(QD, robot.tau_max, robot.tau_min)
    derated = robot.analyze(Q, QD)
    np.testing.assert_allclose(derated.tau_max, upper, rtol=1e-14)
    np.testing.assert_allclose(derated.tau_min, lower, rtol=1e-14)
    z = [0.0, 0.0, 1.0]
    lo, hi = (float(v) for v in derated.polytope.limits(z))
    lp_lo, lp_hi = z_limits_by_lp(robot, Q, QD, upper, lower)
    assert lo == pytest.approx(lp_lo, rel=RTOL) and hi == pytest.approx(lp_hi, rel=RTOL)
    # the rated set (what pe.analyze with robot.tau_max silently gave) is larger
    rated = pe.analyze(dyn, robot.tau_max, robot.tau_min)
    rated_lo, rated_hi = (float(v) for v in rated.polytope.limits(z))
    lp_rated = z_limits_by_lp(robot, Q, QD, robot.tau_max, robot.tau_min)
    assert rated_lo == pytest.approx(lp_rated[0], rel=RTOL)
    assert rated_hi == pytest.approx(lp_rated[1], rel=RTOL)
    assert rated_lo < lo - 1.0 or rated_hi > hi + 1.0  # by more than 1 m/s^2
    assert rated_lo <= lo and hi <= rated_hi
    # at rest, robot.analyze is the rated analysis
    still = robot.analyze(Q)
    np.testing.assert_array_equal(still.tau_max, robot.tau_max)


def test_robot_analyze_refuses_motion_for_velocities(moving):
    robot, _ = moving
    velocity = robot.analyze(Q, capacity="velocity")
    np.testing.assert_array_equal(velocity.qd_max, robot.qd_max)
    with pytest.raises(pe.InputError, match="qd: expected no joint velocities for the velocity"):
        robot.analyze(Q, QD, capacity="velocity")
    with pytest.raises(pe.InputError, match="capacity"):
        robot.analyze(Q, QD, capacity="speed")
    with pytest.raises(pe.InputError, match="qd: expected an array of joint velocities"):
        robot.analyze(Q, QD[:3])
    with pytest.raises(pe.InputError, match=r"q: expected the joint positions of one config"):
        robot.analyze(np.stack([Q, Q]), np.stack([QD, QD]))
    tolerant = robot.analyze(Q, QD, rank_rtol=1e-9, affine_rtol=1e-7)
    assert tolerant.affine_rtol == 1e-7
