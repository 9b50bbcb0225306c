"""Property suite of the study helpers (issue 33): a PolyellError or a valid result.

Configuration sets (:mod:`polyell.studies.configurations`: grids, seeded random sets and
the uniform draws behind them, with wide boxes and rows read in any order), the named
directions of :mod:`polyell.comparison.directions` read against tasks of 1 to 6 rows, and
the posture choice over targets given what is no robot.  Seeded (derandomized).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell.comparison import directions as named
from polyell.models.task import default_task
from polyell.studies import configurations as conf

JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3, np.nan]


def outcome(call: Callable[[], Any], argument: str | None = None) -> Any:
    """The call's result, or None for a PolyellError (naming ``argument`` when given)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return call()
        except pe.PolyellError as exn:
            if argument is not None and isinstance(exn, pe.InputError):
                assert argument in str(exn), (argument, str(exn))
            return None


# --- configurations


@settings(max_examples=30)
@given(
    n=st.integers(1, 6),
    count=st.integers(0, 50),
    seed=st.integers(0, 2**16),
    scale=st.sampled_from([1e-300, 1.0, 1e300, 1.7e308]),
)
def test_uniform_rows_lie_in_their_box(n, count, seed, scale):
    rng = np.random.default_rng(seed)
    low = -rng.uniform(0.1, 1.0, n) * scale
    high = rng.uniform(0.1, 1.0, n) * scale
    rows = conf.uniform_rows(np.random.default_rng(seed), low, high, count)
    assert rows.shape == (count, n) and np.all(np.isfinite(rows))
    assert np.all((rows >= low) & (rows <= high))
    same = conf.uniform_rows(np.random.default_rng(seed), low, high, count)
    np.testing.assert_array_equal(rows, same)  # seeded


@given(data=st.data())
def test_uniform_rows_refuse_wrong_arguments(data):
    arguments: dict[str, Any] = {
        "rng": np.random.default_rng(0),
        "low": np.zeros(2),
        "high": np.ones(2),
        "count": 3,
    }
    name = data.draw(st.sampled_from(sorted(arguments)))
    arguments[name] = data.draw(
        st.sampled_from([*JUNK, np.array([np.inf, 0.0]), np.array([2.0, 2.0]), np.zeros(3)])
    )
    rows = outcome(lambda: conf.uniform_rows(**arguments), name)
    if rows is not None:  # only a valid replacement gets through
        assert rows.shape[0] == arguments["count"] and np.all(np.isfinite(rows))
        assert np.all((rows >= arguments["low"]) & (rows <= arguments["high"]))


@settings(max_examples=30)
@given(
    data=st.data(),
    n=st.integers(1, 4),
    count=st.integers(1, 9000),
    seed=st.integers(0, 2**20),
)
def test_random_configurations_are_the_same_whatever_rows_are_read(data, n, count, seed):
    low, high = -np.arange(1.0, n + 1), np.arange(1.0, n + 1)
    configurations = pe.random_configurations(count, low, high, seed)
    start = data.draw(st.integers(0, count - 1))
    stop = data.draw(st.integers(start + 1, count))
    part = configurations.rows(start, stop)
    whole = configurations.rows(0, count)
    np.testing.assert_array_equal(part, whole[start:stop])
    assert np.all((whole >= low) & (whole <= high))
    arm = pe.PlanarArm(np.ones(n), np.ones(n))
    inside = np.asarray(pe.random_configurations(arm, min(count, 50), seed))
    assert inside.shape == (min(count, 50), n) and np.all(np.abs(inside) <= np.pi)


@given(
    axes=st.lists(
        st.one_of(
            st.floats(-3, 3),
            st.tuples(st.floats(-3, 3), st.floats(-3, 3), st.integers(1, 5)),
            st.lists(st.floats(-3, 3), min_size=1, max_size=4),
            st.sampled_from(JUNK),
            st.tuples(st.floats(-3, 3), st.floats(-3, 3), st.sampled_from([0, -1, 2.5])),
        ),
        min_size=1,
        max_size=4,
    )
)
def test_grids_are_products_of_their_axes(axes):
    grid = outcome(lambda: pe.grid(*axes))
    if grid is None:
        return
    rows = np.asarray(grid)
    sizes = [a.size for a in grid.axes]
    assert rows.shape == (int(np.prod(sizes)), len(axes)) and np.all(np.isfinite(rows))
    if all(len(np.unique(values)) == values.size for values in grid.axes):  # a product
        assert len(np.unique(rows, axis=0)) == len(rows)
    for j, values in enumerate(grid.axes):
        assert set(rows[:, j]) <= set(values)
    assert np.array_equal(rows[-1], [values[-1] for values in grid.axes])  # last fastest


# --- named directions


@settings(max_examples=40)
@given(m=st.integers(1, 6), data=st.data())
def test_named_directions_are_unit_rows(m, data):
    task = default_task(m)
    row = data.draw(st.sampled_from(task))
    sign = data.draw(st.sampled_from(["", "-"]))
    vector, label = named.named_direction(sign + row, task)
    expected = np.eye(m)[task.index(row)] * (-1 if sign else 1)
    np.testing.assert_array_equal(vector, expected)
    assert label == sign + row
    pairs = named.resolve_directions([row, sign + row] if sign else [row], task)
    assert [label for _, label in pairs] == ([row, sign + row] if sign else [row])
    axes = named.axis_directions(task)
    np.testing.assert_array_equal(np.array([v for v, _ in axes]), np.eye(m))
    vectors = named.direction_vectors([row, np.eye(m)[0]], task, "directions")
    assert vectors.shape == (2, m)
    np.testing.assert_allclose(np.linalg.norm(vectors, axis=1), 1.0)


@given(
    task=st.sampled_from([*JUNK, (), ("x", ""), ("x", 3), "xy"]),
    function=st.sampled_from(["named", "vectors", "axes", "resolve"]),
)
def test_named_directions_refuse_what_is_no_task(task, function):
    call = {
        "named": lambda: named.named_direction("x", task),
        "vectors": lambda: named.direction_vectors("x", task, "d"),
        "axes": lambda: named.axis_directions(task),
        "resolve": lambda: named.resolve_directions(None, task),
    }[function]
    assert outcome(call, "task") is None


@given(spec=st.sampled_from([*JUNK, "", "q", "x+", "xx", "-", [0.6, 0.8, 0.0], [1.0, 1.0]]))
def test_named_direction_refuses_or_gives_a_unit_vector(spec):
    result = outcome(lambda: named.named_direction(spec, ("x", "y")), "direction")
    if result is not None:
        vector, label = result
        assert vector.shape == (2,) and abs(np.linalg.norm(vector) - 1) < 1e-12
        assert isinstance(label, str) and label


# --- posture choice over targets


@given(robot=st.sampled_from([*JUNK, pe.PlanarArm, np.zeros(3)]))
def test_posture_choice_over_targets_refuses_what_is_no_robot(robot):
    call = lambda: pe.posture_choice_over_targets(robot, count=2, direction="x")  # noqa: E731
    assert outcome(call, "robot") is None
