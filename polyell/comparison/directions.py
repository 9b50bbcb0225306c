"""Directions named after the task's rows ("x", "-z", "xy") or given as vectors, labelled.

A directional limit is an interval along a line: the limits along ``-x`` are those along
``x`` negated and swapped, so the default set is one direction per task row, ``+`` only.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.validation import check_directions

__all__ = [
    "DirectionSpec",
    "axis_directions",
    "direction_vectors",
    "has_names",
    "named_direction",
    "resolve_directions",
]

#: A direction as given: a name made of task rows (``"x"``, ``"-z"``, ``"xy"``,
#: ``"x-y"``) or a unit vector of the task's size.
DirectionSpec = str | Sequence[float] | NDArray[np.float64]


def _rows_pattern(task: Sequence[str]) -> re.Pattern[str]:
    """Signed task rows, longest name first (``wx`` before ``x``)."""
    names = sorted(task, key=len, reverse=True)
    return re.compile(r"\s*([+-]?)\s*(" + "|".join(map(re.escape, names)) + r")")


def _name_expected(task: Sequence[str]) -> str:
    rows = ", ".join(task)
    return (
        f"a direction named after the task rows ({rows}), e.g. {task[0]!r}, '-{task[-1]}'"
        + (f", {task[0] + task[1]!r} (the unit diagonal)" if len(task) > 1 else "")
        + f", or a unit vector of {len(task)} entries"
    )


def _from_name(spec: str, task: Sequence[str], argument: str) -> tuple[NDArray[np.float64], str]:
    pattern = _rows_pattern(task)
    terms: list[tuple[str, str]] = []
    position = 0
    text = spec.strip()
    while position < len(text):
        match = pattern.match(text, position)
        if match is None:
            raise InputError(
                argument,
                _name_expected(task),
                repr(spec),
                "name rows of the task, each at most once, with an optional sign.",
            )
        terms.append((match.group(1), match.group(2)))
        position = match.end()
    rows = [row for _, row in terms]
    if not terms or len(set(rows)) != len(rows):
        raise InputError(
            argument,
            _name_expected(task) + ", each row at most once",
            repr(spec),
            "name rows of the task, each at most once, with an optional sign.",
        )
    vector = np.zeros(len(task))
    for sign, row in terms:
        vector[list(task).index(row)] = -1.0 if sign == "-" else 1.0
    label = "".join(
        ("-" if sign == "-" else ("+" if k else "")) + row for k, (sign, row) in enumerate(terms)
    )
    return vector / np.sqrt(len(terms)), label


def _vector_label(vector: NDArray[np.float64]) -> str:
    """``(0.6, 0, 0.8)``: each entry to 4 significant digits."""
    return "(" + ", ".join(f"{value + 0.0:.4g}" for value in vector) + ")"


def named_direction(
    spec: DirectionSpec, task: Sequence[str], argument: str = "direction"
) -> tuple[NDArray[np.float64], str]:
    """A unit direction of the task space and its label.

    Parameters
    ----------
    spec : str or array-like of shape (m,)
        A name made of the task's rows, each at most once with an optional sign: ``"x"``,
        ``"-z"``, ``"xy"`` (the unit diagonal ``(x + y) / sqrt(2)``), ``"x-y"``,
        ``"wz"``; or a unit vector of m entries (to the rounding of
        :func:`polyell.validation.check_directions`).
    task : sequence of str
        The task's row names, ``Dynamics.task`` (e.g. ``("x", "y", "z")``).
    argument : str, optional
        The name errors give the direction (a study file passes its key's path).

    Returns
    -------
    vector : ndarray, shape (m,)
        Unit length.
    label : str
        ``"x"``, ``"-z"``, ``"x+y"`` (signs written out between rows), or the vector's
        entries to 4 significant digits, ``"(0.6, 0, 0.8)"``.

    Raises
    ------
    InputError
        Naming ``argument``: a name with a row the task does not have (or one twice), a
        vector of the wrong size, of non-unit length or with non-finite entries.
    """
    task = _task_rows(task)
    if isinstance(spec, str):
        return _from_name(spec, task, argument)
    if isinstance(spec, bool | int | float | np.number) or spec is None:
        raise InputError(
            argument,
            _name_expected(task),
            repr(spec),
            f"name it, e.g. {task[0]!r}, or give a unit vector of {len(task)} numbers",
        )
    try:
        size = np.shape(spec)
    except ValueError:  # a ragged list
        raise InputError(
            argument,
            _name_expected(task),
            repr(spec)[:80],
            f"give one flat unit vector of {len(task)} numbers, or a name such as {task[0]!r}",
        ) from None
    if len(size) == 1 and size[0] != len(task):
        raise InputError(
            argument,
            f"a unit vector of {len(task)} numbers, one per task row {list(task)}",
            f"{size[0]} numbers",
            f"name it (e.g. {task[0]!r}) or give {len(task)} numbers.",
        )
    vector = check_directions(argument, spec, len(task))
    if vector.ndim != 1:
        raise InputError(
            argument,
            _name_expected(task),
            f"shape {vector.shape}",
            f"give one vector per entry, e.g. list(T) for the rows of a (k, {len(task)}) array T",
        )
    return vector, _vector_label(vector)


def _task_rows(task: object) -> tuple[str, ...]:
    """The task's row names: a non-empty sequence of non-empty strings, or an InputError."""
    rows = () if isinstance(task, str) or not isinstance(task, Iterable) else tuple(task)
    if not rows or not all(isinstance(row, str) and row for row in rows):
        raise InputError(
            "task",
            "the task's row names, such as ('x', 'y', 'z')",
            repr(task)[:80],
            "pass analysis.task (or S.task).",
        )
    return rows


def _plain(directions: object) -> object:
    """A 0-d array of a string (``np.array("z")``) as that string; anything else as is."""
    if isinstance(directions, np.ndarray) and directions.ndim == 0 and directions.dtype.kind == "U":
        return str(directions)
    return directions


def _entries(directions: object) -> list[object] | None:
    """The top-level entries of a list of directions (an array of strings too), else None."""
    if isinstance(directions, np.ndarray):
        return directions.tolist() if directions.dtype.kind in "UO" and directions.ndim else None
    if isinstance(directions, list | tuple):
        return list(directions)
    return None


def has_names(directions: object) -> bool:
    """Whether ``directions`` is a name (``"z"``) or a list holding at least one name.

    The entry points that take unit vectors (``S.limits``, :func:`polyell.limits_along`,
    :func:`polyell.posture_choice`, ``polyell analyze --direction``) read a direction by
    :func:`named_direction` when this is true, and as plain vectors otherwise.
    """
    directions = _plain(directions)
    if isinstance(directions, str):
        return True
    entries = _entries(directions)
    return entries is not None and any(isinstance(entry, str) for entry in entries)


def direction_vectors(
    directions: ArrayLike | Sequence[DirectionSpec], task: Sequence[str], argument: str
) -> NDArray[np.float64]:
    """Unit directions of shape (m,) or (k, m), each given by name or as a vector.

    Parameters
    ----------
    directions : str, array-like of shape (m,) or (k, m), or sequence of both
        One direction (a name such as ``"z"``, or a unit vector), or a list of them in
        which names and vectors may mix (``["x", [0.6, 0.8]]``).
    task : sequence of str
        The task's row names the names are read against.
    argument : str
        The name errors give the directions (``argument[k]`` for the k-th of a list).

    Returns
    -------
    ndarray, shape (m,) or (k, m)
        Unit vectors, as :func:`polyell.validation.check_directions` returns them.

    Raises
    ------
    InputError
        Naming ``argument`` (or ``argument[k]``) for a name with a row the task does not
        have, a vector of the wrong size or not of unit length.

    Examples
    --------
    >>> direction_vectors(["-z", [0.6, 0.8, 0.0]], ("x", "y", "z"), "directions")
    array([[ 0. ,  0. , -1. ],
           [ 0.6,  0.8,  0. ]])
    """
    task = _task_rows(task)
    directions = cast("ArrayLike | Sequence[DirectionSpec]", _plain(directions))
    if isinstance(directions, str):
        return named_direction(directions, task, argument)[0]
    entries = _entries(directions)
    if entries is None or not any(isinstance(entry, str) for entry in entries):
        return check_directions(argument, cast(ArrayLike, directions), len(task))
    vectors = [
        named_direction(cast(DirectionSpec, entry), task, f"{argument}[{k}]")[0]
        for k, entry in enumerate(entries)
    ]
    return np.array(vectors, dtype=float)


def axis_directions(task: Sequence[str]) -> list[tuple[NDArray[np.float64], str]]:
    """The default directions: one per task row, ``+`` only, labelled by the row.

    A line's interval holds both ends (the limits along ``-x`` are those along ``x``
    negated and swapped), so ``x, y, z`` cover the six half-axes.
    """
    task = _task_rows(task)
    return [(row_vector, name) for row_vector, name in zip(np.eye(len(task)), task, strict=True)]


def resolve_directions(
    directions: Sequence[DirectionSpec] | None, task: Sequence[str], argument: str = "directions"
) -> list[tuple[NDArray[np.float64], str]]:
    """Directions of a table as ``(unit vector, label)`` pairs; None: :func:`axis_directions`.

    Raises
    ------
    InputError
        Naming ``argument[k]`` for a bad entry, ``argument`` for an empty or non-list
        value and for two entries with the same label.
    """
    task = _task_rows(task)
    if directions is None:
        return axis_directions(task)
    if isinstance(directions, str) or not isinstance(directions, Sequence | np.ndarray):
        raise InputError(
            argument,
            "a list of directions (names such as 'x', '-z', 'xy', or unit vectors)",
            repr(directions)[:80],
            f"write e.g. {argument}=['x', 'z'].",
        )
    if len(directions) == 0:
        raise InputError(
            argument,
            "at least one direction",
            "an empty list",
            f"list at least one, e.g. {argument}=[{task[0]!r}], or pass None for the task's axes",
        )
    found = [named_direction(spec, task, f"{argument}[{k}]") for k, spec in enumerate(directions)]
    labels = [label for _, label in found]
    repeated = sorted({label for label in labels if labels.count(label) > 1})
    if repeated:
        raise InputError(
            argument,
            "distinct directions",
            f"{repeated} more than once",
            f"list each direction once: drop the repeats of {repeated[0]!r}",
        )
    return found
