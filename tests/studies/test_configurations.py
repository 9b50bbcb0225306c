"""Lazy configuration sets: seeded random boxes of any width, grids."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.studies.configurations import uniform_rows

BIG = np.finfo(float).max


@pytest.mark.parametrize("seed", [0, 1, 2**40])
def test_uniform_rows_are_numpys_draws_where_the_box_width_is_finite(seed):
    rng = np.random.default_rng(seed)
    low, high = rng.uniform(-10, 0, 4), rng.uniform(0, 10, 4)
    expected = np.random.default_rng(seed + 1).uniform(low, high, (50, 4))
    np.testing.assert_array_equal(
        uniform_rows(np.random.default_rng(seed + 1), low, high, 50), expected
    )


@pytest.mark.parametrize(
    ("low", "high"),
    [([-1e308, 0.0], [1e308, 1.0]), ([-BIG, -BIG], [BIG, -BIG]), ([-BIG, 5.0], [BIG, 5.0])],
)
def test_a_box_wider_than_the_largest_float_is_sampled_within_it(low, high):
    low, high = np.array(low), np.array(high)
    rows = pe.random_configurations(5000, low, high, seed=3).rows(0, 5000)
    assert np.all(np.isfinite(rows)) and np.all((rows >= low) & (rows <= high))
    # The halved box, doubled: exactly numpy's draws in [low / 2, high / 2], times 2.
    halved = 2.0 * np.random.default_rng([3, 0]).uniform(low / 2, high / 2, (4096, 2))
    np.testing.assert_array_equal(rows[:4096], halved)
    spans = (low < 0) & (high > 0)  # both signs drawn there: the box is not collapsed
    assert np.all((rows[:, spans] < 0).any(axis=0) & (rows[:, spans] > 0).any(axis=0))


# --- issue 24: a robot's joint limits by default, numpy arrays ---------------------------


def test_random_configurations_of_a_robot_lie_in_its_urdf_joint_limits():
    panda = pe.robots.load("panda")
    rows = np.asarray(pe.random_configurations(panda, 2000, 7))
    # the joint limits read independently, from the URDF's XML
    import xml.etree.ElementTree as ET

    root = ET.parse(pe.robots.urdf_path("panda")).getroot()
    limits = {
        joint.get("name"): (
            float(joint.find("limit").get("lower")),
            float(joint.find("limit").get("upper")),
        )
        for joint in root.iter("joint")
        if joint.get("type") == "revolute"
    }
    low = np.array([limits[f"panda_joint{i}"][0] for i in range(1, 8)])
    high = np.array([limits[f"panda_joint{i}"][1] for i in range(1, 8)])
    assert rows.shape == (2000, 7)
    assert np.all((rows >= low) & (rows <= high))
    # uniform over the whole range: every joint comes within 1 % of both ends
    margin = 0.01 * (high - low)
    assert np.all(rows.min(axis=0) < low + margin) and np.all(rows.max(axis=0) > high - margin)
    # the same rows as the explicit box with the same seed (today's signature still works)
    np.testing.assert_array_equal(rows, np.asarray(pe.random_configurations(2000, low, high, 7)))


def test_a_robot_without_limits_samples_every_joint_in_minus_pi_pi():
    arm = pe.robots.load("chiacchio2000")
    rows = np.asarray(pe.random_configurations(arm, count=500, seed=1))
    expected = np.random.default_rng([1, 0]).uniform(-np.pi, np.pi, (4096, 3))[:500]
    np.testing.assert_array_equal(rows, expected)
    wrist = pe.random_configurations(arm, 300, seed=1, high=[np.pi, np.pi, 0.0])
    assert np.all(np.asarray(wrist)[:, 2] <= 0.0)


@pytest.mark.parametrize(
    ("call", "fragment"),
    [
        (lambda arm: pe.random_configurations(arm), "missing a required argument: 'count'"),
        (lambda arm: pe.random_configurations(arm, 3, low=[0.0]), "low: expected"),
        (lambda arm: pe.random_configurations(5, [0.0]), "random_configurations(robot, count"),
        (lambda arm: pe.random_configurations(arm, 0), "count: expected"),
        (lambda arm: pe.studies.configurations.joint_bounds("panda"), "robot: expected a robot"),
    ],
)
def test_wrong_calls_are_refused_by_name(call, fragment):
    with pytest.raises(pe.InputError) as info:
        call(pe.robots.load("chiacchio2000"))
    assert fragment in str(info.value)


def test_asarray_of_a_configuration_set_is_its_rows():
    random = pe.random_configurations(10_000, [-1.0, 0.0], [1.0, 2.0], seed=4)
    rows = np.asarray(random)
    assert rows.shape == (10_000, 2) and rows.dtype == np.float64
    np.testing.assert_array_equal(rows[5000:5010], random.rows(5000, 5010))
    assert np.asarray(random, dtype=np.float32).dtype == np.float32
    grid = pe.grid(0.5, (0.0, 1.0, 3), [1.0, 2.0])
    expected = [[0.5, a, b] for a in (0.0, 0.5, 1.0) for b in (1.0, 2.0)]  # last fastest
    np.testing.assert_array_equal(np.array(grid), expected)
    with pytest.raises(ValueError, match="cannot be viewed without a copy"):
        np.array(grid, copy=False)


def test_a_set_too_large_for_memory_is_refused_with_the_way_to_read_it():
    huge = pe.random_configurations(2**40, [0.0] * 7, [1.0] * 7)
    with pytest.raises(pe.InputError, match=r"\.rows\(start, stop\)"):
        np.asarray(huge)
