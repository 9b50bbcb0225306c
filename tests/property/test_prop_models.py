"""Property suite of the robot models (issue 33): a PolyellError or a valid result.

:mod:`polyell.models` beyond what tests/test_properties.py draws (PlanarArm's parameters,
TorqueSpeed): the task-row helpers, PlanarArm's kinematics against finite differences and
under a change of units (lengths in mm: positions and the Jacobian 1000 times those in m,
the same joint angles), Dynamics and Kinematics given broken arguments, ``self_motion`` in
any unit, the joint limits of a robot and ``check_motion_limits``.  Seeded (derandomized).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell.models import task as rows
from polyell.models.dynamics import MotionLimits, check_motion_limits
from polyell.models.joint_limits import check_torque_speed

JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3, np.nan]
SPECIAL = [np.nan, np.inf, -np.inf, 0.0, -1.0, 1e-300, 1e300]
SCALES = [1e-6, 1e-3, 1.0, 1e3, 1e6]
CAPACITIES = ["acceleration", "velocity", "force"]


def outcome(
    call: Callable[[], Any],
    argument: str | tuple[str, ...] | None = None,
    allowed: type[Warning] | None = None,
) -> Any:
    """The call's result, or None for a PolyellError (naming ``argument`` when given).

    Warnings are errors, but ``allowed`` (a warning the function issues on purpose).
    """
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        if allowed is not None:
            warnings.simplefilter("ignore", allowed)
        try:
            return call()
        except pe.PolyellError as exn:
            if argument is not None and isinstance(exn, pe.InputError):
                names = (argument,) if isinstance(argument, str) else argument
                assert any(f"{name}" in str(exn) for name in names), (argument, str(exn))
            return None


def broken(data: st.DataObject, value: Any) -> Any:
    """A broken copy of an array: a special entry, a wrong shape, or junk."""
    how = data.draw(st.sampled_from(["special", "shape", "junk"]))
    if how == "junk":
        return data.draw(st.sampled_from(JUNK))
    array = np.array(value, dtype=float)
    if how == "shape":
        return data.draw(st.sampled_from([array[..., :-1], array[None], array.T[..., None]]))
    array.flat[data.draw(st.integers(0, array.size - 1))] = data.draw(st.sampled_from(SPECIAL))
    return array


# --- polyell.models.task


@given(m=st.integers(0, 9), capacity=st.sampled_from(CAPACITIES), tex=st.booleans())
def test_task_rows_are_named_labelled_and_united(m, capacity, tex):
    task = rows.default_task(m)
    assert len(task) == m == len(set(task)) and all(isinstance(r, str) and r for r in task)
    assert rows.check_task(None, m) == task == rows.check_task(list(task), m)
    for row in task:
        label = rows.row_label(row, capacity)
        assert label.startswith("$") and label.endswith("$")
    if m:
        unit = rows.task_unit(task, tex, capacity)
        kinds = {row in rows.ANGULAR_ROWS for row in task}
        assert (unit == "weighted units") == (len(kinds) > 1)


@given(
    function=st.sampled_from(["default_task", "check_task", "row_label", "task_unit"]),
    value=st.sampled_from([*JUNK, "", ["x", ""], ["x", "x"], -1, 10**9, "bogus"]),
    which=st.integers(0, 2),
)
def test_task_helpers_refuse_wrong_arguments(function, value, which):
    calls = {
        "default_task": (("m", lambda: rows.default_task(value)),),
        "check_task": (
            ("task", lambda: rows.check_task(value, 2)),
            ("m", lambda: rows.check_task(("x", "y"), value)),
        ),
        "row_label": (
            ("row", lambda: rows.row_label(value)),
            ("capacity", lambda: rows.row_label("x", value)),
        ),
        "task_unit": (
            ("task", lambda: rows.task_unit(value)),
            ("tex", lambda: rows.task_unit(("x",), value)),
            ("capacity", lambda: rows.task_unit(("x",), False, value)),
        ),
    }[function]
    argument, call = calls[which % len(calls)]
    result = outcome(call, argument)
    if result is not None:  # an accepted value gives what the function promises
        assert isinstance(result, str | tuple)
        if isinstance(result, tuple):
            assert all(isinstance(r, str) and r for r in result)


# --- polyell.PlanarArm


@settings(max_examples=30)
@given(
    n=st.integers(1, 6),
    seed=st.integers(0, 2**16),
    c=st.sampled_from(SCALES),
    mass=st.sampled_from(SCALES),
)
def test_planar_arm_kinematics_and_units(n, seed, c, mass):
    rng = np.random.default_rng(seed)
    lengths, masses = rng.uniform(0.2, 1.5, n), rng.uniform(0.5, 10.0, n)
    q = rng.uniform(-np.pi, np.pi, n)
    arm = pe.PlanarArm(lengths, masses)
    x, J = arm.forward_kinematics(q), arm.jacobian(q)
    # the Jacobian is the derivative of the position (central differences)
    h = 1e-6
    for i in range(n):
        step = np.eye(n)[i] * h
        difference = (arm.forward_kinematics(q + step) - arm.forward_kinematics(q - step)) / 2 / h
        np.testing.assert_allclose(J[:, i], difference, atol=1e-8)
    # the tip is at most the reach away, the absolute angles add up
    assert np.linalg.norm(x) <= lengths.sum() * (1 + 1e-12)
    theta = np.cumsum(q)
    np.testing.assert_allclose(
        x, [lengths @ np.cos(theta), lengths @ np.sin(theta)], atol=1e-12 * lengths.sum()
    )
    # lengths in mm: positions and J in mm; masses in g: B and g in g (gravity the same)
    other = pe.PlanarArm(lengths * c, masses * mass)
    np.testing.assert_allclose(other.forward_kinematics(q), c * x, rtol=1e-12, atol=1e-15 * c)
    np.testing.assert_allclose(other.jacobian(q), c * J, rtol=1e-12, atol=1e-15 * c)
    dyn, big = arm.dynamics(q), other.dynamics(q)
    np.testing.assert_allclose(big.B, mass * c**2 * dyn.B, rtol=1e-10, atol=1e-14 * mass * c**2)
    np.testing.assert_allclose(big.g, mass * c * dyn.g, rtol=1e-10, atol=1e-12 * mass * c)
    np.testing.assert_allclose(dyn.B, dyn.B.T, atol=0)
    assert np.all(np.linalg.eigvalsh(dyn.B) > 0)


@given(data=st.data(), n=st.integers(1, 4))
def test_planar_arm_methods_with_broken_angles(data, n):
    arm = pe.PlanarArm(np.linspace(0.5, 1.0, n), np.ones(n))
    q = data.draw(st.sampled_from([None, "shape"]))
    value = broken(data, np.full(n, 0.3)) if q == "shape" else data.draw(st.sampled_from(JUNK))
    for method in ("forward_kinematics", "jacobian", "dynamics"):
        result = outcome(lambda m=method: getattr(arm, m)(value), "q")
        if result is not None:
            arrays = [result.J, result.B, result.g] if method == "dynamics" else [result]
            assert all(np.all(np.isfinite(np.asarray(a))) for a in arrays)


# --- pe.Dynamics and pe.Kinematics


@given(data=st.data(), m=st.integers(1, 6), n=st.integers(1, 7))
def test_dynamics_and_kinematics_with_any_argument_broken(data, m, n):
    rng = np.random.default_rng(data.draw(st.integers(0, 2**16)))
    Q = np.linalg.qr(rng.normal(size=(n, n)))[0]
    arguments: dict[str, Any] = {
        "J": rng.normal(size=(m, n)),
        "B": (Q * rng.uniform(0.5, 5.0, n)) @ Q.T,
        "g": rng.normal(size=n),
        "xdd_bias": None,
        "task": None,
    }
    name = data.draw(st.sampled_from([*arguments, "none"]))
    if name == "task":
        arguments[name] = data.draw(
            st.sampled_from([*JUNK, rows.default_task(m), ["q"] * m, list("abcdefgh")[:m]])
        )
    elif name == "xdd_bias":
        arguments[name] = broken(data, np.zeros(m))
    elif name != "none":
        arguments[name] = broken(data, arguments[name])
    # (a J of three axes is a batch: then B and g are refused for its shape)
    names = (name, "J", "B", "g") if name in ("J", "B", "g") else name
    dyn = outcome(lambda: pe.Dynamics(**arguments), None if name == "none" else names)
    if dyn is not None:
        assert (dyn.m, dyn.n) == (m, n) and len(dyn.task) == m
        assert np.all(np.isfinite(dyn.J)) and np.all(np.isfinite(dyn.B))
        np.testing.assert_allclose(dyn.B, dyn.B.T, atol=0)
    kin = outcome(lambda: pe.Kinematics(arguments["J"], arguments["task"]))
    if kin is not None:
        assert (kin.m, kin.n) == (np.shape(kin.J)) and np.all(np.isfinite(kin.J))


# --- pe.self_motion


@settings(max_examples=4)  # (each traces two closed self-motions: about a second)
@given(seed=st.integers(0, 2**16), c=st.sampled_from([1e-9, 1e-3, 1e3, 1e9]))
def test_self_motion_does_not_depend_on_the_units(seed, c):
    rng = np.random.default_rng(seed)
    lengths, masses = rng.uniform(0.3, 1.2, 3), rng.uniform(0.5, 5.0, 3)
    q0 = rng.uniform(-2.5, 2.5, 3)
    q0[1:] = np.where(np.abs(q0[1:]) < 0.3, 0.3, q0[1:])  # away from the straight arm
    arm, scaled = pe.PlanarArm(lengths, masses), pe.PlanarArm(lengths * c, masses)
    one = outcome(lambda: pe.self_motion(arm, q0, 12))
    other = outcome(lambda: pe.self_motion(scaled, q0, 12))
    assert (one is None) == (other is None)
    if one is None:
        return
    np.testing.assert_allclose(other.configurations, one.configurations, atol=1e-7)
    tip = arm.forward_kinematics(q0)
    for q in one.configurations:  # every posture keeps the tip
        assert np.linalg.norm(arm.forward_kinematics(q) - tip) <= 1e-9 * lengths.sum()
    assert other.residual <= 1e-9 * c * lengths.sum()


@given(data=st.data())
def test_self_motion_with_any_argument_broken(data):
    arm = pe.robots.load("chiacchio2000")
    arguments: dict[str, Any] = {"q0": [0.3, 0.5, -0.4], "count": 5, "seed": 0, "step": None}
    name = data.draw(st.sampled_from([*arguments, "robot", "none"]))
    robot: Any = arm
    if name == "robot":
        robot = data.draw(st.sampled_from([*JUNK, pe.PlanarArm([1.0, 1.0], [1.0, 1.0])]))
    elif name == "q0":
        arguments[name] = broken(data, arguments[name])
    elif name != "none":
        arguments[name] = data.draw(st.sampled_from([*JUNK, 0, -1, 10**9, 2.0, 1e-300]))
    motion = outcome(lambda: pe.self_motion(robot, **arguments))
    if motion is not None:
        Q = motion.configurations
        assert Q.shape == (arguments["count"], 3) and np.all(np.isfinite(Q))
        tip = arm.forward_kinematics(np.asarray(arguments["q0"], dtype=float))
        assert max(np.linalg.norm(arm.forward_kinematics(q) - tip) for q in Q) <= 1e-8


# --- joint limits of a robot


@settings(max_examples=30)
@given(data=st.data(), n=st.integers(1, 4), seed=st.integers(0, 2**16))
def test_joint_limits_of_a_robot(data, n, seed):
    rng = np.random.default_rng(seed)
    tau = rng.uniform(1.0, 50.0, n)
    drives = pe.TorqueSpeed.linear(tau * 1.5, rng.uniform(1.0, 10.0, n))
    options: dict[str, Any] = {"tau_max": tau, "qd_max": rng.uniform(1.0, 5.0, n)}
    options["torque_speed"] = data.draw(st.sampled_from([None, drives]))
    name = data.draw(st.sampled_from(["tau_max", "tau_min", "qd_max", "qd_min", "none"]))
    if name != "none":
        base = options.get(name)
        options[name] = broken(data, -tau if base is None else base)
    arm = outcome(lambda: pe.PlanarArm(np.ones(n), np.ones(n), **options))
    if arm is None:
        return
    qd = data.draw(st.sampled_from([None, "zero", "random", "broken"]))
    value = {
        None: None,
        "zero": np.zeros(n),
        "random": rng.uniform(-3, 3, (3, n)),
        "broken": broken(data, np.ones(n)),
    }[qd]
    limits = outcome(lambda: arm.torque_limits(value), "qd")
    if limits is not None:
        upper, lower = limits
        assert upper.shape == lower.shape and np.all(lower < upper)
        assert np.all(upper <= arm.tau_max) and np.all(lower >= arm.tau_min)
    velocity = outcome(arm.velocity_limits)
    if velocity is not None:
        assert np.all(velocity[1] < velocity[0])


@given(value=st.sampled_from([*JUNK, pe.TorqueSpeed.linear([1.0], [1.0])]), n=st.integers(1, 3))
def test_check_torque_speed_refuses_what_is_no_model_of_the_joints(value, n):
    result = outcome(lambda: check_torque_speed(value, n, None, None), "torque_speed")
    assert result is None or (value is None and result is None) or result.n == n


@given(data=st.data())
def test_check_motion_limits_with_any_argument_broken(data):
    motion = MotionLimits([2.0], [50.0], [-100.0], [100.0], [-100.0], ["j1"])
    dyn = pe.Dynamics([[1.0]], [[1.0]], [0.0], motion=motion)
    arguments: dict[str, Any] = {"dynamics": dyn, "tau_max": [40.0], "tau_min": [-40.0]}
    name = data.draw(st.sampled_from([*arguments, "none"]))
    if name == "dynamics":
        arguments[name] = data.draw(st.sampled_from(JUNK))
    elif name != "none":
        arguments[name] = broken(data, arguments[name])
    # inf is no limit: beyond the derated ones, a warning (issued on purpose)
    outcome(lambda: check_motion_limits(**arguments), name, pe.DeratingWarning)
    with pytest.warns(pe.DeratingWarning, match="j1"):
        check_motion_limits(dyn, [100.0], [-100.0])
