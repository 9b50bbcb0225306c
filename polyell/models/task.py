"""Names and units of the task-space rows: what axis labels, tables, text and JSON call them.

A row is linear (``x``, ``y``, ``z``: accelerations in m/s^2) or angular (``wx``, ``wy``,
``wz``: angular accelerations in rad/s^2).  A task mixing both needs weights (see
:class:`~polyell.UrdfRobot`), and its sets are then in weighted units.
"""

from __future__ import annotations

from collections.abc import Sequence

from polyell.errors import InputError

__all__ = ["ANGULAR_ROWS", "LINEAR_ROWS", "check_task", "default_task", "row_label", "task_unit"]

LINEAR_ROWS = ("x", "y", "z")
ANGULAR_ROWS = ("wx", "wy", "wz")
_UNITS = {"linear": ("m/s^2", r"m/s$^2$"), "angular": ("rad/s^2", r"rad/s$^2$")}


def default_task(m: int) -> tuple[str, ...]:
    """Row names assumed for an unlabelled Jacobian of m rows.

    ``x, y, z`` up to three rows (linear, as the paper's), the six rows of a frame
    Jacobian for m = 6, and ``x1 .. xm`` (linear) otherwise.
    """
    if m <= 3:
        return LINEAR_ROWS[:m]
    if m == 6:
        return LINEAR_ROWS + ANGULAR_ROWS
    return tuple(f"x{i + 1}" for i in range(m))


def check_task(task: Sequence[str] | None, m: int) -> tuple[str, ...]:
    """Validate row names: m distinct non-empty strings (default :func:`default_task`)."""
    if task is None:
        return default_task(m)
    if isinstance(task, str) or not all(isinstance(row, str) and row for row in task):
        raise InputError("task", f"{m} row names such as ('x', 'z')", repr(task))
    rows = tuple(task)
    if len(rows) != m or len(set(rows)) != m:
        raise InputError(
            "task",
            f"{m} distinct row names, one per row of J",
            repr(rows),
            "name every task row once, e.g. ('x', 'z') for a vertical plane.",
        )
    return rows


def _kind(row: str) -> str:
    return "angular" if row in ANGULAR_ROWS else "linear"


def task_unit(task: Sequence[str], tex: bool = False) -> str:
    """The acceleration unit of a task: m/s^2, rad/s^2, or ``weighted units`` when mixed."""
    kinds = {_kind(row) for row in task}
    if len(kinds) != 1:
        return "weighted units"
    return _UNITS[kinds.pop()][int(tex)]


def row_label(row: str) -> str:
    r"""A TeX axis label for a row: ``$\ddot x$`` for x, ``$\dot\omega_x$`` for wx."""
    if row in ANGULAR_ROWS:
        return rf"$\dot\omega_{row[1]}$"
    return rf"$\ddot {row[0]}_{{{row[1:]}}}$" if len(row) > 1 else rf"$\ddot {row}$"
