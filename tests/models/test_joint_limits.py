"""Joint limits a robot carries (issue 21, items 1 and 5): velocity limits, torque-speed curves.

URDF velocity limits are checked against the file's ``<limit velocity=...>`` attributes read
with ElementTree (not through Pinocchio); the torque limits at a velocity against
:meth:`TorqueSpeed.limits` called directly, whose own tests check it against closed forms.
"""

from __future__ import annotations

import pickle
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import polyell as pe
from reference import PAPER_ARM, planar_urdf

DRIVES = pe.TorqueSpeed.linear([120.0, 40.0, 5.0], [3.0, 4.0, 6.0])


def paper_arm(**options) -> pe.PlanarArm:
    return pe.PlanarArm([1.0, 0.8, 0.5], [4.0, 2.0, 0.6], com=[0.5, 0.4, 0.25], **options)


def urdf_velocities(text: str) -> dict[str, float | None]:
    """Each movable joint's velocity attribute, from the XML itself (None where absent)."""
    velocities: dict[str, float | None] = {}
    for joint in ET.fromstring(text).iter("joint"):
        if joint.get("type") == "fixed":
            continue
        limit = joint.find("limit")
        value = None if limit is None else limit.get("velocity")
        velocities[joint.get("name")] = None if value is None else float(value)
    return velocities


def three_speeds_urdf() -> str:
    """The paper's arm as URDF, with velocity limits 1.5, 2.5 and 3.5 rad/s."""
    text = planar_urdf(PAPER_ARM)
    for value in ("1.5", "2.5", "3.5"):
        text = text.replace('velocity="1"', f'velocity="{value}"', 1)
    return text


def urdf_robot(text: str, tmp_path, **options) -> pe.UrdfRobot:
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    return pe.UrdfRobot(path, "tip", task="planar", gravity=(0, -9.81, 0), **options)


# --- planar arms ----------------------------------------------------------------------------


def test_a_planar_arm_carries_its_velocity_limits():
    arm = paper_arm(qd_max=[2.0, 3.0, 4.0])
    np.testing.assert_array_equal(arm.qd_max, [2.0, 3.0, 4.0])
    np.testing.assert_array_equal(arm.qd_min, [-2.0, -3.0, -4.0])
    qd_max, qd_min = arm.velocity_limits()
    np.testing.assert_array_equal(qd_max, [2.0, 3.0, 4.0])
    np.testing.assert_array_equal(qd_min, [-2.0, -3.0, -4.0])
    qd_max[0] = 99.0  # a copy
    assert arm.qd_max[0] == 2.0
    with pytest.raises(ValueError, match="read-only"):
        arm.qd_max[0] = 5.0
    one_way = paper_arm(qd_max=[2.0, 3.0, 4.0], qd_min=[0.0, -1.0, -4.0])
    np.testing.assert_array_equal(one_way.velocity_limits()[1], [0.0, -1.0, -4.0])
    assert "qd_max=[2.0, 3.0, 4.0]" in repr(arm)
    assert paper_arm().qd_max is None and "qd_max" not in repr(paper_arm())


def test_a_planar_arm_without_velocity_limits_says_so():
    with pytest.raises(pe.InputError) as info:
        paper_arm().velocity_limits()
    assert str(info.value) == (
        "qd_max: expected joint velocity limits for every joint, got none given. Fix: pass "
        "qd_max=[...] (rad/s or m/s, one per joint; qd_min defaults to -qd_max)."
    )


@pytest.mark.parametrize(
    ("options", "start"),
    [
        (
            {"qd_max": [2.0, 0.0, 1.0]},
            "qd_max: expected strictly positive upper joint "
            "velocities [rad/s or m/s], got qd_max[1] = 0",
        ),
        ({"qd_max": [2.0, -1.0, 1.0]}, "qd_max: expected strictly positive"),
        ({"qd_max": [2.0, np.nan, 1.0]}, "qd_max: expected finite values"),
        (
            {"qd_max": [2.0, 1.0]},
            "qd_max: expected an array of joint velocities [rad/s or m/s] with shape (3,)",
        ),
        ({"qd_max": 2.0}, "qd_max: expected an array"),
        (
            {"qd_max": [1e200, 1.0, 1.0]},
            "qd_max: expected joint velocity limits of size at most 1e+150",
        ),
        (
            {"qd_max": [2.0, 1.0, 1.0], "qd_min": [-1.0, 1.0, -1.0]},
            "qd_min: expected qd_min < qd_max for every joint [rad/s or m/s], "
            "got qd_min[1] = 1 >= qd_max[1] = 1",
        ),
        ({"qd_max": [2.0, 1.0, 1.0], "qd_min": [-1.0, -1.0]}, "qd_min: expected an array"),
        ({"qd_min": [-1.0, -1.0, -1.0]}, "qd_min: expected qd_min only together with qd_max"),
        ({"tau_min": [-1.0, -1.0, -1.0]}, "tau_min: expected tau_min only together with tau_max"),
        ({"torque_speed": {"tau_stall": [1, 1, 1]}}, "torque_speed: expected a pe.TorqueSpeed"),
        (
            {"torque_speed": pe.TorqueSpeed.linear([1.0], [1.0])},
            "torque_speed: expected a "
            "torque-speed model of 3 joints (one curve per joint of the robot), got one of 1 "
            "joints",
        ),
        (
            {"torque_speed": DRIVES, "tau_max": [100.0, 50.0, 4.0]},
            "tau_max: expected rated torque limits within the stall torques",
        ),
        (
            {"torque_speed": DRIVES, "tau_max": [100.0, 30.0, 4.0], "tau_min": [-100, -30, -6]},
            "tau_min: expected rated torque limits within the stall torques",
        ),
    ],
)
def test_bad_planar_limits_are_refused(options, start):
    with pytest.raises(pe.InputError) as info:
        paper_arm(**options)
    assert str(info.value).startswith(start), str(info.value)


def test_torque_limits_at_a_velocity_are_the_models():
    rated = {"tau_max": [100.0, 30.0, 4.0], "tau_min": [-90.0, -30.0, -3.0]}
    arm = paper_arm(torque_speed=DRIVES, **rated)
    qd = np.array([[1.0, -2.0, 0.0], [-4.0, 5.0, 7.0]])
    for velocity in (qd, qd[1]):
        expected = DRIVES.limits(velocity, rated["tau_max"], rated["tau_min"])
        for got, want in zip(arm.torque_limits(velocity), expected, strict=True):
            np.testing.assert_array_equal(got, want)
    # joint 0 forward at 1 rad/s: 120 (1 - 1/3) = 80 < 100; joint 1 backward at 2: 20
    upper, lower = arm.torque_limits(qd[0])
    np.testing.assert_allclose(upper, [80.0, 30.0, 4.0], rtol=1e-15)
    np.testing.assert_allclose(lower, [-90.0, -20.0, -3.0], rtol=1e-15)
    # at rest, or without qd: the rated limits
    for got in (arm.torque_limits(), arm.torque_limits(np.zeros(3))):
        np.testing.assert_array_equal(got[0], rated["tau_max"])
        np.testing.assert_array_equal(got[1], rated["tau_min"])


def test_torque_limits_without_a_model_or_without_rated_limits():
    arm = paper_arm(tau_max=[100.0, 30.0, 4.0])
    upper, lower = arm.torque_limits(np.ones((4, 3)))  # no curves: rated, per row of a batch
    assert upper.shape == lower.shape == (4, 3)
    np.testing.assert_array_equal(upper, np.tile([100.0, 30.0, 4.0], (4, 1)))
    np.testing.assert_array_equal(lower, -upper)
    upper[0, 0] = 0.0
    assert arm.tau_max[0] == 100.0  # a copy
    with pytest.raises(pe.InputError, match=r"^qd: expected an array of joint velocities"):
        arm.torque_limits([1.0, 2.0])  # checked even where it changes nothing
    curves_only = paper_arm(torque_speed=DRIVES)
    np.testing.assert_array_equal(curves_only.torque_limits()[0], DRIVES.tau_stall)
    np.testing.assert_array_equal(curves_only.torque_limits([3.0, 0.0, 0.0])[0], [0, 40, 5])
    with pytest.raises(pe.InputError) as info:
        paper_arm().torque_limits()
    assert str(info.value).startswith(
        "tau_max: expected torque limits (the robot has none of its own), got None."
    )


def test_the_library_planar_arm_takes_the_limits():
    arm = pe.robots.load("chiacchio2000", qd_max=[2, 2, 3], torque_speed=DRIVES)
    np.testing.assert_array_equal(arm.tau_max, [100.0, 30.0, 4.0])
    np.testing.assert_array_equal(arm.velocity_limits()[1], [-2.0, -2.0, -3.0])
    assert arm.torque_speed is DRIVES
    with pytest.raises(pe.InputError, match=r"^tau_max: expected rated torque limits within"):
        pe.robots.load("chiacchio2000", torque_speed=pe.TorqueSpeed.linear([50, 20, 4], [1] * 3))


# --- URDF robots -----------------------------------------------------------------------------


def test_urdf_velocity_limits_are_the_files(tmp_path):
    text = three_speeds_urdf()
    robot = urdf_robot(text, tmp_path)
    velocities = urdf_velocities(text)
    assert list(velocities) == robot.joint_names
    np.testing.assert_array_equal(robot.qd_max, list(velocities.values()))
    np.testing.assert_array_equal(robot.qd_min, [-1.5, -2.5, -3.5])
    explicit = urdf_robot(text, tmp_path, qd_max=[1.0, 1.0, 1.0], qd_min=[-0.5, 0, -1])
    np.testing.assert_array_equal(explicit.velocity_limits()[1], [-0.5, 0.0, -1.0])
    locked = pe.UrdfRobot(text, "tip", task="planar", locked_joints=["joint1"])
    np.testing.assert_array_equal(locked.qd_max, [velocities["joint0"], velocities["joint2"]])


def test_library_urdf_velocity_limits_are_the_files():
    robot = pe.robots.load("panda")
    velocities = urdf_velocities(pe.robots.urdf_path("panda").read_text())
    np.testing.assert_array_equal(robot.qd_max, [velocities[name] for name in robot.joint_names])
    assert np.all(robot.qd_max > 0)


@pytest.mark.parametrize(
    ("edit", "lacking"),
    [
        # no <limit> on a continuous joint
        (
            lambda text: text.replace(
                '<limit effort="50" velocity="1.5" lower="-10" upper="10"/>', "", 1
            ).replace('type="revolute"', 'type="continuous"', 1),
            "['joint0']",
        ),
        (lambda text: text.replace('velocity="2.5"', 'velocity="0"'), "['joint1']"),
    ],
)
def test_urdf_without_velocity_limits_says_which_joints(tmp_path, edit, lacking):
    text = edit(three_speeds_urdf())
    robot = urdf_robot(text, tmp_path, tau_max=[50.0, 50.0, 50.0])
    assert robot.qd_max is None and robot.qd_min is None
    with pytest.raises(pe.InputError) as info:
        robot.velocity_limits()
    assert str(info.value).startswith(
        f"qd_max: expected joint velocity limits for every joint, got none in the URDF for "
        f"{lacking} (no <limit velocity=...>, or 0). Fix: pass qd_max=[...]"
    )
    given = urdf_robot(text, tmp_path, tau_max=[50.0, 50.0, 50.0], qd_max=[1.0, 2.0, 3.0])
    np.testing.assert_array_equal(given.velocity_limits()[0], [1.0, 2.0, 3.0])
    with pytest.raises(pe.InputError, match=r"^qd_min: expected qd_min only together"):
        urdf_robot(text, tmp_path, tau_max=[50.0, 50.0, 50.0], qd_min=[-1.0, -2.0, -3.0])


def test_a_urdf_joint_without_a_limit_element_has_no_effort_limit_either(tmp_path):
    text = three_speeds_urdf().replace(
        '<limit effort="50" velocity="1.5" lower="-10" upper="10"/>', "", 1
    )
    text = text.replace('type="revolute"', 'type="continuous"', 1)
    with pytest.raises(pe.InputError) as info:  # Pinocchio reads an infinite effort
        urdf_robot(text, tmp_path)
    assert str(info.value) == (
        "tau_max: expected effort limits in the URDF for every joint, got none for "
        "['joint0']. Fix: pass tau_max=[...] explicitly."
    )


def test_urdf_torque_speed_against_its_effort_limits(tmp_path):
    text = three_speeds_urdf()  # effort="50" on every joint
    weak = pe.TorqueSpeed.linear([60.0, 40.0, 60.0], [2.0, 2.0, 2.0])
    with pytest.raises(pe.InputError) as info:
        urdf_robot(text, tmp_path, torque_speed=weak)
    assert str(info.value).startswith(
        "tau_max: expected rated torque limits within the stall torques (-tau_stall <= "
        "tau_min, tau_max <= tau_stall): a drive gives at most its stall torque at rest, got "
        "tau_max[1] = 50 N m against a stall torque of 40 N m."
    )
    robot = urdf_robot(text, tmp_path, torque_speed=weak, tau_max=[40.0, 40.0, 40.0])
    qd = [1.0, -1.5, 0.5]
    for got, want in zip(robot.torque_limits(qd), weak.limits(qd, [40.0] * 3), strict=True):
        np.testing.assert_array_equal(got, want)
    again = pickle.loads(pickle.dumps(robot))
    assert again.torque_speed == weak
    np.testing.assert_array_equal(again.qd_max, robot.qd_max)
    with pytest.raises(pe.InputError, match=r"^torque_speed: expected a torque-speed model of 3"):
        urdf_robot(text, tmp_path, torque_speed=pe.TorqueSpeed.linear([60.0] * 2, [2.0] * 2))
