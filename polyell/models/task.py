"""Names and units of the task-space rows: what axis labels, tables, text and JSON call them.

A row is linear (``x``, ``y``, ``z``) or angular (``wx``, ``wy``, ``wz``); its unit depends
on the capacity: accelerations in m/s^2 or rad/s^2, velocities in m/s or rad/s, forces in N
or moments in N m.  A task mixing both needs weights (see :class:`~polyell.UrdfRobot`), and
its sets are then in weighted units.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from polyell.errors import InputError
from polyell.validation import check_integer

__all__ = ["ANGULAR_ROWS", "LINEAR_ROWS", "check_task", "default_task", "row_label", "task_unit"]

LINEAR_ROWS = ("x", "y", "z")
ANGULAR_ROWS = ("wx", "wy", "wz")
#: Most rows a task may have (a name per row; far beyond any robot).
MAX_TASK_ROWS = 10_000
_UNITS = {
    "acceleration": {"linear": ("m/s^2", r"m/s$^2$"), "angular": ("rad/s^2", r"rad/s$^2$")},
    "velocity": {"linear": ("m/s", "m/s"), "angular": ("rad/s", "rad/s")},
    "force": {"linear": ("N", "N"), "angular": ("N m", "N m")},
}
#: TeX symbols of a row's quantity per capacity: linear row ``x``, angular row ``wx``.
_SYMBOLS = {
    "acceleration": (r"\ddot {}", r"\dot\omega"),
    "velocity": (r"\dot {}", r"\omega"),
    "force": ("f", r"\mu"),
}


def default_task(m: int) -> tuple[str, ...]:
    """Row names assumed for an unlabelled Jacobian of m rows.

    ``x, y, z`` up to three rows (linear, as the paper's), the six rows of a frame
    Jacobian for m = 6, and ``x1 .. xm`` (linear) otherwise.
    """
    m = check_integer("m", m, 0, MAX_TASK_ROWS)
    if m <= 3:
        return LINEAR_ROWS[:m]
    if m == 6:
        return LINEAR_ROWS + ANGULAR_ROWS
    return tuple(f"x{i + 1}" for i in range(m))


def check_task(task: Sequence[str] | None, m: int) -> tuple[str, ...]:
    """Validate row names: m distinct non-empty strings (default :func:`default_task`)."""
    m = check_integer("m", m, 0, MAX_TASK_ROWS)
    if task is None:
        return default_task(m)
    usable = not isinstance(task, str) and isinstance(task, Iterable)
    rows = tuple(task) if usable else ()
    if not usable or not all(isinstance(row, str) and row for row in rows):
        example = repr(default_task(m)) if m <= 6 else f"('x1', 'x2', ..., 'x{m}')"
        raise InputError(
            "task",
            f"{m} row names such as ('x', 'z')",
            repr(task)[:80],
            f"pass the {m} names as a tuple of non-empty str, e.g. {example}, "
            "or None for these defaults",
        )
    if len(rows) != m or len(set(rows)) != m:
        raise InputError(
            "task",
            f"{m} distinct row names, one per row of J",
            repr(rows),
            "name every task row once, e.g. ('x', 'z') for a vertical plane.",
        )
    return rows


def _check_capacity(capacity: object) -> None:
    if not isinstance(capacity, str) or capacity not in _UNITS:
        raise InputError(
            "capacity",
            f"one of {tuple(_UNITS)}",
            repr(capacity)[:80],
            "use one of the names listed, e.g. capacity='acceleration'",
        )


def _kind(row: str) -> str:
    return "angular" if row in ANGULAR_ROWS else "linear"


def task_unit(task: Sequence[str], tex: bool = False, capacity: str = "acceleration") -> str:
    """The unit of a task's quantity, or ``weighted units`` when linear and angular rows mix.

    ``m/s^2`` and ``rad/s^2`` (acceleration), ``m/s`` and ``rad/s`` (velocity), ``N`` and
    ``N m`` (force).

    Raises
    ------
    InputError
        If ``task`` is not a sequence of one row name or more (an empty task has no unit),
        ``tex`` is not a bool or ``capacity`` is unknown.
    """
    _check_capacity(capacity)
    if not isinstance(tex, bool):
        raise InputError(
            "tex",
            "True or False",
            repr(tex)[:80],
            "pass tex=True for a LaTeX unit (m/s$^2$), tex=False for plain text (m/s^2)",
        )
    if isinstance(task, str) or not isinstance(task, Iterable):
        raise InputError(
            "task",
            "a sequence of row names such as ('x', 'z')",
            repr(task)[:80],
            "pass the row names as a tuple, e.g. ('x', 'z'), not one str",
        )
    rows = list(task)
    if not rows:  # no quantity, hence no unit (a set has one row at least)
        raise InputError(
            "task",
            "at least one row name such as ('x', 'z')",
            "an empty task",
            "name the task's rows.",
        )
    if not all(isinstance(row, str) and row for row in rows):
        raise InputError(
            "task",
            "non-empty row names such as ('x', 'z')",
            repr(rows)[:80],
            "name every row with a non-empty str, e.g. ('x', 'z')",
        )
    kinds = {_kind(row) for row in rows}
    if len(kinds) != 1:
        return "weighted units"
    return _UNITS[capacity][kinds.pop()][int(tex)]


def row_label(row: str, capacity: str = "acceleration") -> str:
    r"""A TeX axis label for a row: ``$\ddot x$`` for x, ``$\dot\omega_x$`` for wx.

    Velocities read ``$\dot x$`` and ``$\omega_x$``, forces ``$f_x$`` and ``$\mu_x$``.
    """
    _check_capacity(capacity)
    if not isinstance(row, str) or not row:
        raise InputError(
            "row",
            "a non-empty row name such as 'x' or 'wz'",
            repr(row)[:80],
            "pass one row's name as a str, e.g. row_label('x') or row_label('wz')",
        )
    linear, angular = _SYMBOLS[capacity]
    if row in ANGULAR_ROWS:
        return rf"${angular}_{row[1]}$"
    if linear == "f":
        return rf"$f_{{{row}}}$"
    symbol = linear.format(row[0])
    return rf"${symbol}_{{{row[1:]}}}$" if len(row) > 1 else rf"${symbol}$"
