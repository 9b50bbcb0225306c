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
