"""TorqueSpeed: torque limits of joints in motion (issue 21, item 5).

The linear model is checked against its closed form written out here, the tabulated one
against scipy's piecewise-linear interpolation and against the linear model it tabulates,
and the bounds' properties (within the rated limits, the derated side falling with speed
to 0 and never below, the braking side constant, mirror symmetry) with seeded hypothesis
draws.  Tolerances: both models evaluate ``c(s) = t_j + (s - s_j) (t_{j+1} - t_j) /
(s_{j+1} - s_j)`` in floating point, a few roundings of quantities no larger than the stall
torque, so they agree with any other evaluation to ``ULPS * eps * tau_stall``.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.interpolate import interp1d

import polyell as pe

EPS = float(np.finfo(float).eps)
#: Roundings of a linear interpolation (a difference, a quotient, a product, a sum) and of
#: the closed form it is compared with, each at most half an ulp of the stall torque.
ULPS = 8

STALL = np.array([100.0, 30.0, 4.0])
NO_LOAD = np.array([4.0, 6.0, 8.0])


def closed_form(qd: np.ndarray, stall: np.ndarray, no_load: np.ndarray) -> np.ndarray:
    """tau_stall (1 - |qd| / qd_no_load), not below 0: the motoring side's bound."""
    return np.maximum(0.0, stall * (1.0 - np.abs(qd) / no_load))


def assert_close(actual, expected, scale) -> None:
    np.testing.assert_allclose(actual, expected, rtol=0, atol=ULPS * EPS * np.max(scale))


# --- the linear model: its closed form ----------------------------------------------------


@pytest.mark.parametrize(
    ("qd", "upper", "lower"),
    [
        # joint 0 forward at half its no-load speed, joint 1 backward at half, joint 2 still
        ([2.0, -3.0, 0.0], [50.0, 30.0, 4.0], [-100.0, -15.0, -4.0]),
        # a quarter and three quarters of the no-load speeds, opposite signs
        ([-1.0, 4.5, -2.0], [100.0, 7.5, 4.0], [-75.0, -30.0, -3.0]),
        # at the no-load speeds: the derated side is 0
        ([4.0, -6.0, 8.0], [0.0, 30.0, 0.0], [-100.0, 0.0, -4.0]),
        # past them: still 0, not negative
        ([10.0, -100.0, 1e6], [0.0, 30.0, 0.0], [-100.0, 0.0, -4.0]),
        # a tiny speed: derated by a tiny amount
        ([1e-12, -1e-12, 0.0], [100.0 - 25e-12, 30.0, 4.0], [-100.0, -30.0 + 5e-12, -4.0]),
    ],
)
def test_linear_limits_are_the_closed_form_at_hand_picked_speeds(qd, upper, lower):
    drives = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    got_upper, got_lower = drives.limits(qd)
    assert_close(got_upper, upper, STALL)
    assert_close(got_lower, lower, STALL)
    # The same from the closed form written generally: derated on the side of the motion.
    qd = np.asarray(qd)
    motoring = closed_form(qd, STALL, NO_LOAD)
    assert_close(got_upper, np.where(qd > 0, motoring, STALL), STALL)
    assert_close(got_lower, np.where(qd < 0, -motoring, -STALL), STALL)
    assert np.all(got_upper >= 0) and np.all(got_lower <= 0)


def test_rated_limits_cap_the_curve_and_keep_the_braking_side():
    drives = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    tau_max, tau_min = np.array([80.0, 20.0, 3.0]), np.array([-60.0, -25.0, -4.0])
    # joint 0 forward at 1 rad/s: the curve gives 75 < 80; at 0.5 rad/s it gives 87.5 > 80
    for speed, expected in ((1.0, 75.0), (0.5, 80.0)):
        upper, lower = drives.limits([speed, -1.0, 6.0], tau_max, tau_min)
        assert_close(upper, [expected, 20.0, 1.0], STALL)  # joint 2: 4 (1 - 6/8) = 1
        # joint 1 backward at 1 rad/s: the curve gives 25 = -tau_min: still 25
        assert_close(lower, [-60.0, -25.0, -4.0], STALL)
    upper, lower = drives.limits([0.0, -3.0, 0.0], tau_max, tau_min)
    assert_close(upper, tau_max, STALL)
    assert_close(lower, [-60.0, -15.0, -4.0], STALL)  # joint 1: 30 (1 - 3/6) = 15 < 25
    # tau_min defaults to -tau_max, both to +-tau_stall
    np.testing.assert_array_equal(drives.limits(np.zeros(3), tau_max)[1], -tau_max)
    np.testing.assert_array_equal(drives.limits(np.zeros(3)), (STALL, -STALL))


def test_attributes_of_a_linear_model():
    drives = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    assert drives.kind == "linear" and drives.n == 3
    np.testing.assert_array_equal(drives.tau_stall, STALL)
    np.testing.assert_array_equal(drives.qd_no_load, NO_LOAD)
    np.testing.assert_array_equal(drives.max_speed, np.inf)
    np.testing.assert_array_equal(drives.speeds, np.stack([np.zeros(3), NO_LOAD], axis=1))
    np.testing.assert_array_equal(drives.torques, np.stack([STALL, np.zeros(3)], axis=1))
    assert_close(drives.motoring([-2.0, 3.0, 9.0]), [50.0, 15.0, 0.0], STALL)


# --- the tabulated model --------------------------------------------------------------------


def test_a_table_of_the_linear_model_gives_its_limits():
    rng = np.random.default_rng(7)
    linear = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    speeds = np.linspace(0.0, 1.0, 9)[None, :] * NO_LOAD[:, None]  # one row per joint
    table = pe.TorqueSpeed.table(speeds, closed_form(speeds, STALL[:, None], NO_LOAD[:, None]))
    qd = rng.uniform(-1.5, 1.5, (200, 3)) * NO_LOAD  # both signs, past the no-load speeds
    qd[:10] = 0.0
    qd[10:20] = speeds[:, 3] * rng.choice([-1, 1], 3)  # on the table's speeds exactly
    rated = (np.array([90.0, 30.0, 3.5]), np.array([-100.0, -20.0, -4.0]))
    for limits in ((), rated):
        for got, expected in zip(
            table.limits(qd, *limits), linear.limits(qd, *limits), strict=True
        ):
            assert_close(got, expected, STALL)
    np.testing.assert_array_equal(table.qd_no_load, NO_LOAD)
    np.testing.assert_array_equal(table.tau_stall, STALL)


def test_a_table_with_one_row_of_speeds_for_all_joints():
    speeds = [0.0, 1.0, 2.0, 4.0]
    torques = [[10.0, 8.0, 5.0, 0.0], [3.0, 3.0, 1.0, 1.0]]
    table = pe.TorqueSpeed.table(speeds, torques)
    assert table.speeds.shape == (2, 4) and table.kind == "table"
    np.testing.assert_array_equal(table.qd_no_load, [4.0, np.inf])
    np.testing.assert_array_equal(table.max_speed, [np.inf, 4.0])
    qd = np.array([[0.5, -0.5], [-1.5, 1.5], [3.0, -3.0], [7.0, -4.0]])
    reference = np.stack(
        [
            interp1d(speeds, row, bounds_error=False, fill_value=0.0)(np.abs(qd[:, i]))
            for i, row in enumerate(torques)
        ],
        axis=1,
    )
    assert_close(table.motoring(qd), reference, 10.0)
    upper, lower = table.limits(qd)
    assert_close(upper, np.where(qd > 0, reference, [10.0, 3.0]), 10.0)
    assert_close(lower, np.where(qd < 0, -reference, [-10.0, -3.0]), 10.0)


def test_a_table_is_not_extrapolated_past_its_last_speed_unless_it_ends_at_zero():
    table = pe.TorqueSpeed.table([0.0, 1.0, 2.0], [[10.0, 8.0, 0.0], [3.0, 2.0, 1.0]])
    assert table.limits([50.0, 2.0])[0].tolist() == [0.0, 1.0]  # joint 0: no-load, then 0
    with pytest.raises(pe.InputError) as info:
        table.limits([[0.0, 1.0], [0.0, -2.5]])
    message = str(info.value)
    assert message.startswith("qd: expected speeds within the tabulated curve")
    assert "|qd[1, 1]| = 2.5" in message and "extend the table" in message
    with pytest.raises(pe.InputError, match=r"^speed: .*\|speed\[1\]\| = 3"):
        table.motoring([0.0, 3.0])


# --- properties -----------------------------------------------------------------------------


@st.composite
def drives_and_rated(draw):
    """A linear or tabulated model of 1-4 joints, rated limits within it (or none), a qd."""
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    n = draw(st.integers(1, 4))
    scale = draw(st.sampled_from([1e-3, 1.0, 1e3]))
    stall = rng.uniform(0.5, 2.0, n) * scale
    if draw(st.booleans()):
        drives = pe.TorqueSpeed.linear(stall, rng.uniform(0.5, 5.0, n))
    else:
        k = draw(st.integers(2, 6))
        speeds = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 2.0, k - 1))])
        falls = np.sort(rng.uniform(0.0, 1.0, (n, k - 1)), axis=1)[:, ::-1]
        torques = stall[:, None] * np.concatenate([np.ones((n, 1)), falls], axis=1)
        if draw(st.booleans()):
            torques[:, -1] = 0.0  # ends at its no-load speed
        drives = pe.TorqueSpeed.table(speeds, torques)
    rated = ()
    if draw(st.booleans()):
        upper = stall * rng.uniform(0.2, 1.0, n)
        rated = (upper, -stall * rng.uniform(0.2, 1.0, n))
    reach = np.where(np.isfinite(drives.max_speed), drives.max_speed, 2 * drives.speeds[:, -1])
    qd = rng.uniform(-1.0, 1.0, (8, n)) * reach
    qd[rng.uniform(size=(8, n)) < 0.2] = 0.0
    return drives, rated, qd


@given(problem=drives_and_rated(), factor=st.floats(1.0, 3.0))
def test_the_limits_are_within_the_rated_ones_and_derated_only_along_the_motion(problem, factor):
    drives, rated, qd = problem
    rated_upper, rated_lower = rated or (drives.tau_stall, -drives.tau_stall)
    upper, lower = drives.limits(qd, *rated)
    assert upper.shape == lower.shape == qd.shape
    assert np.all(lower < upper)
    assert np.all(upper <= rated_upper) and np.all(lower >= rated_lower)
    assert np.all(upper >= 0) and np.all(lower <= 0)  # rated limits around 0: never negative
    # The braking side, and both sides at rest, are the rated limits exactly.
    np.testing.assert_array_equal(np.where(qd <= 0, upper, rated_upper), rated_upper + 0 * qd)
    np.testing.assert_array_equal(np.where(qd >= 0, lower, rated_lower), rated_lower + 0 * qd)
    # The derated side is the curve, capped by the rated limit.
    curve = drives.motoring(qd)
    np.testing.assert_array_equal(upper[qd > 0], np.minimum(rated_upper + 0 * qd, curve)[qd > 0])
    np.testing.assert_array_equal(lower[qd < 0], np.maximum(rated_lower + 0 * qd, -curve)[qd < 0])
    # Faster in the same direction never gives more torque along the motion.
    faster = qd * factor
    if np.all(np.abs(faster) <= drives.max_speed):
        up_fast, low_fast = drives.limits(faster, *rated)
        assert np.all(up_fast <= upper) and np.all(low_fast >= lower)
    # A batch is its rows.
    for k in range(len(qd)):
        row = drives.limits(qd[k], *rated)
        np.testing.assert_array_equal(row[0], upper[k])
        np.testing.assert_array_equal(row[1], lower[k])


@given(problem=drives_and_rated())
def test_reversing_the_motion_mirrors_symmetric_limits(problem):
    drives, rated, qd = problem
    symmetric = rated[:1]  # tau_min = -tau_max, or none (+-tau_stall)
    upper, lower = drives.limits(qd, *symmetric)
    back_upper, back_lower = drives.limits(-qd, *symmetric)
    np.testing.assert_array_equal(back_upper, -lower)
    np.testing.assert_array_equal(back_lower, -upper)


@given(problem=drives_and_rated())
def test_the_curve_is_scipys_piecewise_linear_interpolation(problem):
    drives, _, qd = problem
    for i in range(drives.n):
        last = drives.torques[i, -1]
        reference = interp1d(
            drives.speeds[i], drives.torques[i], bounds_error=last > 0, fill_value=0.0
        )(np.abs(qd[:, i]))
        assert_close(drives.motoring(qd)[:, i], reference, drives.tau_stall[i])
        # non-increasing in the speed, from the stall torque down to 0
        s = np.linspace(0.0, min(drives.max_speed[i], 3 * drives.speeds[i, -1]), 101)
        values = drives.motoring(np.outer(s, np.ones(drives.n)))[:, i]
        assert values[0] == drives.tau_stall[i]
        assert np.all(np.diff(values) <= 0) and np.all(values >= 0)


# --- shapes and objects ---------------------------------------------------------------------


def test_batch_shapes():
    drives = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    for qd in (np.zeros(3), np.zeros((1, 3)), np.ones((5, 3)), np.empty((0, 3))):
        upper, lower = drives.limits(qd, [50.0, 20.0, 2.0])
        assert upper.shape == lower.shape == qd.shape
        assert upper.dtype == lower.dtype == np.float64
        assert upper.flags.writeable and lower.flags.writeable


def test_the_object_is_immutable_and_pickles_and_prints_as_its_constructor():
    for drives in (
        pe.TorqueSpeed.linear(STALL, NO_LOAD),
        pe.TorqueSpeed.table([0, 1, 2], [[10, 5, 0], [3, 2, 1]]),
        pe.TorqueSpeed.table([[0, 1], [0, 3]], [[10, 0], [3, 2]]),
    ):
        with pytest.raises(AttributeError, match="immutable"):
            drives._torques = np.zeros((3, 2))  # type: ignore[misc]
        with pytest.raises(ValueError, match="read-only"):
            drives.torques[0, 0] = 1.0
        again = pickle.loads(pickle.dumps(drives))
        assert again == drives and hash(again) == hash(drives)
        assert eval(repr(drives), {"TorqueSpeed": pe.TorqueSpeed}) == drives
    assert pe.TorqueSpeed.linear([1.0], [2.0]) != pe.TorqueSpeed.table([0, 2], [[1, 0]])
    with pytest.raises(pe.InputError, match=r"^TorqueSpeed: expected one of its constructors"):
        pe.TorqueSpeed([1.0], [2.0])


def test_the_inputs_are_copied():
    stall, no_load = STALL.copy(), NO_LOAD.copy()
    drives = pe.TorqueSpeed.linear(stall, no_load)
    stall[0], no_load[0] = 1.0, 1.0
    np.testing.assert_array_equal(drives.tau_stall, STALL)
    np.testing.assert_array_equal(drives.qd_no_load, NO_LOAD)


# --- refusals -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("stall", "no_load", "start"),
    [
        (
            [100.0, -1.0],
            [1.0, 1.0],
            "tau_stall: expected strictly positive values [N m], got tau_stall[1] = -1",
        ),
        ([100.0, 0.0], [1.0, 1.0], "tau_stall: expected strictly positive"),
        ([100.0, np.nan], [1.0, 1.0], "tau_stall: expected finite values"),
        ([np.inf], [1.0], "tau_stall: expected finite values"),
        ([1e200], [1.0], "tau_stall: expected values of size at most 1e+150 N m"),
        ([], [], "tau_stall: expected one stall torque per joint"),
        ([[1.0]], [1.0], "tau_stall: expected an array of stall torques [N m] with shape (k,)"),
        ("x", [1.0], "tau_stall: expected an array"),
        (None, [1.0], "tau_stall: expected an array"),
        (
            [1.0, 2.0],
            [1.0],
            "tau_stall, qd_no_load: expected one stall torque and one no-load speed per joint",
        ),
        ([1.0], [[1.0]], "qd_no_load: expected an array of no-load speeds [rad/s] with shape"),
        ([1.0], [0.0], "qd_no_load: expected strictly positive values [rad/s]"),
        ([1.0], [-2.0], "qd_no_load: expected strictly positive values"),
        ([1.0], [np.nan], "qd_no_load: expected finite values"),
        ([1.0], [1e200], "qd_no_load: expected values of size at most 1e+150 rad/s"),
    ],
)
def test_bad_linear_models_are_refused(stall, no_load, start):
    with pytest.raises(pe.InputError) as info:
        pe.TorqueSpeed.linear(stall, no_load)
    assert str(info.value).startswith(start)


@pytest.mark.parametrize(
    ("speeds", "torques", "start"),
    [
        ([0, 1], [10, 0], "torques: expected an array of torques [N m], one row per joint"),
        ([0], [[10]], "torques: expected one row per joint (at least one), each with at least 2"),
        ([], np.empty((0, 2)), "torques: expected one row per joint"),
        ([0, 1, 2], [[10, 0]], "speeds: expected an array of speeds [rad/s] with shape (2,)"),
        ([[0, 1]], [[10, 0], [5, 0]], "speeds: expected an array of speeds [rad/s], one row"),
        (
            [1, 2],
            [[10, 0]],
            "speeds: expected each curve starting at speed 0 (its stall torque), got a first "
            "speed of 1 for joint 0",
        ),
        (
            [[0, 1], [0.5, 1]],
            [[10, 0], [5, 0]],
            "speeds: expected each curve starting at speed 0 (its stall torque), got a first "
            "speed of 0.5 for joint 1",
        ),
        (
            [0, 1, 1],
            [[10, 5, 0]],
            "speeds: expected strictly increasing speeds along each "
            "curve, got 1 then 1 (joint 0, entries 1 and 2)",
        ),
        ([0, 2, 1], [[10, 5, 0]], "speeds: expected strictly increasing"),
        ([0, np.nan], [[10, 0]], "speeds: expected finite values"),
        ([0, 1e200], [[10, 0]], "speeds: expected speeds of size at most 1e+150"),
        ([0, 1], [[10, -1]], "torques: expected non-negative torques"),
        (
            [0, 1],
            [[0, 0]],
            "torques: expected a positive stall torque (the first entry of "
            "each row), got torques[0, 0] = 0",
        ),
        (
            [0, 1, 2],
            [[10, 5, 0], [3, 4, 0]],
            "torques: expected torques that do not increase "
            "with speed along each row, got 3 then 4 N m (joint 1, entries 0 and 1)",
        ),
        ([0, 1], [[10, np.inf]], "torques: expected finite values"),
        ([0, 1], [[1e200, 0]], "torques: expected torques of size at most 1e+150 N m"),
        ([0, 1], [[10, 0], [5]], "torques: expected an array of torques"),
    ],
)
def test_bad_tables_are_refused(speeds, torques, start):
    with pytest.raises(pe.InputError) as info:
        pe.TorqueSpeed.table(speeds, torques)
    assert str(info.value).startswith(start), str(info.value)


@pytest.mark.parametrize(
    ("qd", "rated", "start"),
    [
        (
            [1.0, 1.0],
            (),
            "qd: expected an array of joint velocities [rad/s or m/s] with shape (3,)",
        ),
        (
            np.zeros((2, 2)),
            (),
            "qd: expected an array of joint velocities [rad/s or m/s] with shape (K, 3)",
        ),
        (np.zeros((1, 1, 3)), (), "qd: expected an array"),
        ([0.0, np.nan, 0.0], (), "qd: expected finite values"),
        ([0.0, 0.0, np.inf], (), "qd: expected finite values"),
        ("fast", (), "qd: expected an array"),
        (None, (), "qd: expected an array"),
        (
            np.zeros(3),
            (None, [-1.0, -1.0, -1.0]),
            "tau_min: expected tau_min only together with tau_max",
        ),
        (
            np.zeros(3),
            ([120.0, 30.0, 4.0],),
            "tau_max: expected rated torque limits within the stall torques",
        ),
        (
            np.zeros(3),
            ([100.0, 30.0, 4.0], [-100.0, -30.5, -4.0]),
            "tau_min: expected rated "
            "torque limits within the stall torques (-tau_stall <= tau_min, tau_max <= "
            "tau_stall): a drive gives at most its stall torque at rest, got tau_min[1] = -30.5 "
            "N m against a stall torque of 30 N m",
        ),
        (
            np.zeros(3),
            ([10.0, 10.0, 1.0], [10.0, -10.0, -1.0]),
            "tau_min: expected tau_min < tau_max for every joint",
        ),
        (np.zeros(3), ([10.0, -1.0, 1.0],), "tau_max: expected strictly positive symmetric"),
        (np.zeros(3), ([10.0, 10.0],), "tau_max: expected an array"),
        # rated limits that exclude 0: joint 0 forward at 3.5 rad/s gives 12.5 < 20 N m
        (
            [3.5, 0.0, 0.0],
            ([50.0, 10.0, 1.0], [20.0, -10.0, -1.0]),
            "qd: expected joint "
            "velocities at which every joint keeps a torque range of positive width, got qd[0] "
            "= 3.5, where joint 0 gives at most 12.5 N m in the direction of motion, against "
            "rated limits [20, 50] N m",
        ),
        (
            [[0.0, 0.0, 0.0], [0.0, 0.0, -8.0]],
            ([50.0, 10.0, 0.0], [-50.0, -10.0, -2.0]),
            "qd: expected joint velocities at which every joint keeps a torque range of positive "
            "width, got qd[1, 2] = -8",
        ),
    ],
)
def test_bad_limits_calls_are_refused(qd, rated, start):
    drives = pe.TorqueSpeed.linear(STALL, NO_LOAD)
    with pytest.raises(pe.InputError) as info:
        drives.limits(qd, *rated)
    assert str(info.value).startswith(start), str(info.value)
