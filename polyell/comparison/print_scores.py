"""The comparison table laid out for print: scores of each set at one or several postures."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from polyell.comparison.labels import QUANTITIES, Quantity
from polyell.comparison.layout import TableLayout
from polyell.comparison.limits import LIMIT_QUANTITIES
from polyell.comparison.printable import (
    Cell,
    Label,
    PrintTable,
    given_label,
    quantity_label,
    text_label,
)
from polyell.errors import InputError

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "DEFAULT_SCORES",
    "check_scores",
    "scores_print_tables",
    "single_unit",
    "zero_everywhere",
]

#: The comparison table's rows by default: every score with a label.
DEFAULT_SCORES = tuple(name for name in QUANTITIES if name not in LIMIT_QUANTITIES)


def check_scores(layout: TableLayout, defaults: Sequence[str]) -> list[Quantity]:
    """The quantities a table shows: those of ``layout.scores`` among ``defaults``.

    Every name must be a known quantity (of this table or of the other); a layout naming
    none of this table's quantities gets ``defaults``.
    """
    if layout.scores is None:
        return [QUANTITIES[name] for name in defaults]
    unknown = [name for name in layout.scores if name not in QUANTITIES]
    if unknown:
        raise InputError(
            "layout.scores",
            f"names among {list(QUANTITIES)}",
            repr(unknown),
            "check the spelling (scores are named as in polyell.SCORE_NAMES).",
        )
    chosen = [QUANTITIES[name] for name in layout.scores if name in defaults]
    return chosen or [QUANTITIES[name] for name in defaults]


def single_unit(units: Mapping[str, str], layout: TableLayout) -> str:
    """The unit shared by every posture of a combined table (InputError otherwise)."""
    found = sorted(set(units.values()))
    if len(found) > 1 and layout.split == "combined":
        raise InputError(
            "layout.split",
            "'posture' for postures in different units (one table cannot head them)",
            f"'combined' with the units {found}",
            "set split='posture'.",
        )
    return found[0] if found else ""


def _cell(row: pd.Series, quantity: Quantity, percent: bool) -> Cell:
    """One score of one set, as data; NaN where the set is undefined."""
    if not bool(row.get("defined", True)):
        return Cell(math.nan)
    try:
        value = float(row[quantity.name])
        stderr = float(row[quantity.stderr]) if quantity.stderr in row.index else 0.0
    except (KeyError, TypeError, ValueError):
        raise InputError(
            "frame",
            f"a number in the column {quantity.name!r}",
            repr(row.get(quantity.name))[:60],
            f"pass frames from Comparison.to_frame(), with a number (or NaN) in {quantity.name!r}",
        ) from None
    shift = 2 if quantity.kind == "share" and percent else 0
    return Cell(value, shift, stderr, count=quantity.kind == "count")


def _sets(frames: Mapping[str, pd.DataFrame], layout: TableLayout) -> list[str]:
    """The ellipsoids shown: ``layout.sets`` (the polytope left out: it is the reference)."""
    present = list(dict.fromkeys(str(kind) for frame in frames.values() for kind in frame.index))
    if layout.sets is None:

        def computed(kind: str) -> bool:
            return not all(
                str(frame.loc[kind].get("reason", "")).startswith("not computed")
                for frame in frames.values()
                if kind in frame.index
            )

        return [kind for kind in present if computed(kind)]
    unknown = [
        kind
        for kind in layout.sets
        if kind != "polytope" and not all(kind in frame.index for frame in frames.values())
    ]
    if unknown:
        raise InputError(
            "layout.sets",
            f"sets among {['polytope', *present]}",
            repr(unknown),
            "check the spelling; a candidate is named as in pe.Candidate.",
        )
    return [kind for kind in layout.sets if kind != "polytope"]


def zero_everywhere(values: Sequence[float]) -> bool:
    """True for a column that is 0 in every row where it has a number (and has one).

    Such a column says nothing a table needs (``feasibility mismatches`` of every set,
    the errors of the polytope against itself): a layout without chosen ``scores``
    leaves it out.
    """
    numbers = [value for value in values if not math.isnan(value)]
    return bool(numbers) and all(value == 0 for value in numbers)


def _anywhere(frames: Mapping[str, pd.DataFrame], kinds: Sequence[str], name: str) -> bool:
    """True if some set at some posture has a number for the score ``name``."""
    return any(
        name in frame.columns and frame.loc[list(kinds), name].notna().any()
        for frame in frames.values()
    )


def _zero_column(frames: Mapping[str, pd.DataFrame], kinds: Sequence[str], q: Quantity) -> bool:
    """Whether the count or share ``q`` is 0 for every set shown at every posture.

    Only counts (mismatches) and shares (errors, overreach) are left out so: a volume or
    a scale of 0 is a result.
    """
    if q.kind not in ("count", "share"):
        return False
    values = [_cell(frame.loc[kind], q, False).value for frame in frames.values() for kind in kinds]
    return zero_everywhere(values)


def scores_print_tables(
    frames: Mapping[str, pd.DataFrame],
    layout: TableLayout,
    units: Mapping[str, str],
    dimensions: Mapping[str, int | None],
) -> list[PrintTable]:
    """The comparison table(s) of :func:`~polyell.comparison.tables.format_scores_table`.

    Parameters
    ----------
    frames : mapping of str to DataFrame
        Per posture name (``""`` for an unnamed one), the scores indexed by set
        (``Comparison.to_frame``).
    layout : TableLayout
    units : mapping of str to str
        Per posture, the task's unit (``m/s^2``).
    dimensions : mapping of str to int or None
        Per posture, the polytope's dimension (the volume's power); None: ``r``.

    Returns
    -------
    list of PrintTable
        One, or one per posture (``layout.split == "posture"``).
    """
    kinds = _sets(frames, layout)
    capacity = next(iter(frames.values())).attrs.get("capacity", "acceleration") if frames else ""
    capacity = capacity or "acceleration"
    quantities = [layout.quantity(q.name, capacity) for q in check_scores(layout, DEFAULT_SCORES)]
    if layout.scores is None:  # the defaults: not a ratio to an optimum no one computed
        quantities = [q for q in quantities if _anywhere(frames, kinds, q.name)]
        # not a count or share that is zero for every set at every posture, whether a
        # row (the default orientation) or a column (transposed): as in the summary
        quantities = [q for q in quantities if not _zero_column(frames, kinds, q)]
    unit = single_unit(units, layout)
    split = layout.split == "posture"
    named = not split and any(frames)
    sets = tuple(given_label(layout.set_text(kind, capacity), "sets") for kind in kinds)
    posture_stub = (Label("posture", "posture"),) if named else ()
    tables = []
    groups = [{name: frame} for name, frame in frames.items()] if split else [dict(frames)]
    for group in groups:
        rows = []
        powers = {_power(dimensions.get(name)) for name in group}
        common_power = powers.pop() if len(powers) == 1 else "r"
        for name, frame in group.items():
            stub = (text_label(name, "posture"),) if named else ()
            power = _power(dimensions.get(name))
            if layout.transpose:
                for kind, label in zip(kinds, sets, strict=True):
                    record = frame.loc[kind]
                    cells = tuple(_cell(record, q, layout.percent) for q in quantities)
                    rows.append(((*stub, label), cells))
            else:
                for q in quantities:
                    label = quantity_label(q, layout.percent, units.get(name, unit), power)
                    cells = tuple(_cell(frame.loc[kind], q, layout.percent) for kind in kinds)
                    rows.append(((*stub, label), cells))
        if layout.transpose:
            stub_head = (*posture_stub, Label("set", "set"))
            columns = tuple(
                quantity_label(q, layout.percent, unit, common_power) for q in quantities
            )
        else:
            stub_head = (*posture_stub, Label("score", "score"))
            columns = sets
        title = next(iter(group)) if split else ""
        mixed = not layout.transpose  # a row per score: a column mixes quantities
        tables.append(
            PrintTable(stub_head, columns, tuple(rows), title=title, grouped=named, mixed=mixed)
        )
    return tables


def _power(dimension: int | None) -> str:
    """The volume's power in a unit: the set's dimension, else ``r``.

    ``r`` where it is unknown, mixed, or the set is empty (of no dimension: its volume 0
    has no unit of its own).
    """
    return str(dimension) if dimension is not None and dimension > 0 else "r"
