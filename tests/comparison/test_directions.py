"""Directions named after the task's rows, or given as vectors, and their labels."""

from __future__ import annotations

import numpy as np
import pytest

from polyell.comparison.directions import axis_directions, named_direction, resolve_directions
from polyell.errors import InputError

XYZ = ("x", "y", "z")
ANGULAR = ("x", "y", "z", "wx", "wy", "wz")


@pytest.mark.parametrize(
    ("spec", "task", "vector", "label"),
    [
        ("x", XYZ, [1, 0, 0], "x"),
        ("-z", XYZ, [0, 0, -1], "-z"),
        ("+y", XYZ, [0, 1, 0], "y"),
        ("xy", XYZ, [1, 1, 0], "x+y"),
        ("x-y", XYZ, [1, -1, 0], "x-y"),
        (" -x - y + z ", XYZ, [-1, -1, 1], "-x-y+z"),
        ("wx", ANGULAR, [0, 0, 0, 1, 0, 0], "wx"),
        ("xwz", ANGULAR, [1, 0, 0, 0, 0, 1], "x+wz"),
        ("z", ("x", "z"), [0, 1], "z"),
    ],
)
def test_named_directions_are_unit_vectors_of_the_named_rows(spec, task, vector, label):
    found, name = named_direction(spec, task)
    expected = np.asarray(vector, float) / np.linalg.norm(vector)
    np.testing.assert_allclose(found, expected, rtol=0, atol=1e-16)
    assert name == label
    assert named_direction(name, task)[1] == label  # a label names the same direction


def test_a_vector_is_checked_and_labelled_by_its_entries():
    vector, label = named_direction([0.6, 0.0, -0.8], XYZ)
    np.testing.assert_allclose(vector, [0.6, 0.0, -0.8], rtol=0, atol=2e-16)  # renormalised
    assert label == "(0.6, 0, -0.8)"


@pytest.mark.parametrize(
    ("spec", "fragment"),
    [
        ("q", r"task rows \(x, y, z\)"),
        ("xx", "each row at most once"),
        ("", "each row at most once"),
        ("x*y", "task rows"),
        ([1.0, 1.0, 0.0], "unit"),
        ([1.0, 0.0], "a unit vector of 3 numbers"),
        ([np.nan, 0.0, 1.0], "finite"),
        (3, "task rows"),
        (None, "task rows"),
    ],
)
def test_a_bad_direction_names_its_argument(spec, fragment):
    with pytest.raises(InputError, match=fragment) as info:
        named_direction(spec, XYZ, "points[0].directions[2]")
    assert info.value.argument == "points[0].directions[2]"


def test_the_default_is_one_direction_per_task_row():
    found = axis_directions(("x", "z"))
    assert [label for _, label in found] == ["x", "z"]
    np.testing.assert_array_equal([v for v, _ in found], np.eye(2))
    assert [label for _, label in resolve_directions(None, ANGULAR)] == list(ANGULAR)


def test_a_list_of_directions_names_the_bad_entry():
    with pytest.raises(InputError) as info:
        resolve_directions(["x", "w"], XYZ)
    assert info.value.argument == "directions[1]"
    with pytest.raises(InputError, match="more than once"):
        resolve_directions(["x", "+x"], XYZ)
    with pytest.raises(InputError, match="at least one"):
        resolve_directions([], XYZ)
    with pytest.raises(InputError, match="a list of directions"):
        resolve_directions("x", XYZ)
    rows = resolve_directions(np.eye(3)[:2], XYZ)  # the rows of an array
    assert [label for _, label in rows] == ["(1, 0, 0)", "(0, 1, 0)"]
