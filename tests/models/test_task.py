"""Task rows' units (issue 33, "Trust, round 3"): an empty task is bad input, not a unit."""

from __future__ import annotations

import pytest

import polyell as pe
from polyell.models.task import task_unit


@pytest.mark.parametrize("empty", [(), [], iter(())])
@pytest.mark.parametrize("capacity", ["acceleration", "velocity", "force"])
def test_an_empty_task_has_no_unit(empty, capacity):
    """It returned "weighted units" (the unit of a task mixing linear and angular rows)."""
    with pytest.raises(pe.InputError, match="task") as info:
        task_unit(empty, capacity=capacity)
    assert info.value.argument == "task"
    assert "empty task" in str(info.value)


@pytest.mark.parametrize(
    ("task", "capacity", "tex", "unit"),
    [
        (("x",), "acceleration", False, "m/s^2"),
        (("x", "z"), "acceleration", True, r"m/s$^2$"),
        (("wx", "wy", "wz"), "velocity", False, "rad/s"),
        (("x", "y", "z"), "force", False, "N"),
        (("wz",), "force", False, "N m"),
        (("x", "y", "z", "wx", "wy", "wz"), "acceleration", False, "weighted units"),
        (["x", "wz"], "force", True, "weighted units"),
    ],
)
def test_units_of_tasks(task, capacity, tex, unit):
    assert task_unit(task, tex, capacity) == unit


def test_a_set_of_one_row_has_its_unit():
    """Every task that reaches task_unit from a set has a row at least (Dynamics refuses none)."""
    import numpy as np

    with pytest.raises(pe.InputError, match="J"):
        pe.Dynamics(np.zeros((0, 2)), np.eye(2), np.zeros(2))
    analysis = pe.analyze(pe.Dynamics(np.ones((1, 2)), np.eye(2), np.zeros(2)), [1.0, 1.0])
    assert analysis.unit() == "m/s^2"
