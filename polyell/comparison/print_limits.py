"""The directional-limits table laid out for print, from :func:`~polyell.limits_table`'s frame."""

from __future__ import annotations

from typing import TYPE_CHECKING

from polyell.comparison.labels import Quantity
from polyell.comparison.layout import TableLayout
from polyell.comparison.limits import LIMIT_COLUMNS, LIMIT_QUANTITIES
from polyell.comparison.print_scores import check_scores, single_unit, zero_everywhere
from polyell.comparison.printable import (
    EMPTY,
    MISSING,
    REFERENCE,
    Cell,
    Label,
    PrintTable,
    direction_label,
    given_label,
    quantity_label,
    text_label,
)
from polyell.errors import InputError

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = ["limits_print_tables"]


def _check_frame(frame: pd.DataFrame) -> None:
    import pandas as pd

    missing = [c for c in LIMIT_COLUMNS if c not in getattr(frame, "columns", ())]
    if not isinstance(frame, pd.DataFrame) or missing:
        raise InputError(
            "frame",
            f"a directional-limits table with the columns {list(LIMIT_COLUMNS)}",
            f"{type(frame).__name__} without {missing}",
            "make it with pe.limits_table or Comparison.limits_table.",
        )


def _cell(row: pd.Series, quantity: Quantity, percent: bool, kind: str = "") -> Cell:
    defined = bool(row["defined"])
    value = float(row[quantity.name])
    if quantity.kind == "share" and kind == "polytope":  # the reference: no error of its own
        return Cell(float("nan"), missing=REFERENCE)
    if quantity.kind == "share":
        return Cell(value, 2 if percent else 0)
    return Cell(value, missing=EMPTY if defined else MISSING)


def _sets(frame: pd.DataFrame, layout: TableLayout) -> list[str]:
    present = list(dict.fromkeys(frame["set"]))
    if layout.sets is None:
        return present
    unknown = [kind for kind in layout.sets if kind not in present]
    if unknown:
        raise InputError(
            "layout.sets",
            f"sets among {present}",
            repr(unknown),
            "check the spelling, or compute the set (mvie=True, outer=True, candidates).",
        )
    return list(layout.sets)


def limits_print_tables(frame: pd.DataFrame, layout: TableLayout) -> list[PrintTable]:
    """The directional-limits table(s) to print.

    Default orientation: one row per (posture,) direction and set, the limits and their
    errors as columns (the polytope's errors blank, :data:`REFERENCE`: it is the
    reference, 0 by definition); transposed: one row per (posture and) direction, each set a group
    of columns -- the polytope's without its errors (zero: it is the reference).  With
    the default quantities (``layout.scores`` None) a column that is zero in every row
    is left out.

    Parameters
    ----------
    frame : DataFrame
        From :func:`~polyell.limits_table` or ``Comparison.limits_table``.
    layout : TableLayout
        ``scores`` among ``lower``, ``upper``, ``lower_error``, ``upper_error`` choose
        the columns (default: all four); ``labels`` name the sets and the quantities.

    Returns
    -------
    list of PrintTable
        One, or one per posture (``layout.split == "posture"``).
    """
    _check_frame(frame)
    kinds = _sets(frame, layout)
    capacity = frame.attrs.get("capacity", "acceleration")
    quantities = [layout.quantity(q.name, capacity) for q in check_scores(layout, LIMIT_QUANTITIES)]
    has_posture = "posture" in frame.columns
    postures = list(dict.fromkeys(frame["posture"])) if has_posture else [""]
    units = {
        str(name): str(part["unit"].iloc[0])
        for name, part in (frame.groupby("posture", sort=False) if has_posture else [("", frame)])
    }
    unit = single_unit(units, layout)
    split = layout.split == "posture"
    named = has_posture and not split
    set_labels = {kind: given_label(layout.set_text(kind, capacity), "sets") for kind in kinds}
    shown = frame[frame["set"].isin(kinds)]
    drop = layout.scores is None  # the defaults: no error column that is zero everywhere
    if layout.transpose:  # a group of columns per set: (set, quantity) columns
        columns_of = {
            kind: [
                q
                for q in quantities
                if not (kind == "polytope" and q.kind == "share")  # its errors: zero
                and not (drop and _zero(shown, q, kind))
            ]
            for kind in kinds
        }
        kinds = [kind for kind in kinds if columns_of[kind]] or kinds[:1]
        columns_of = {kind: columns_of[kind] or quantities[:1] for kind in kinds}
        column_quantities = [(kind, q) for kind in kinds for q in columns_of[kind]]
        groups = tuple((set_labels[kind], len(columns_of[kind])) for kind in kinds)
    else:
        if drop:
            quantities = [q for q in quantities if not _zero(shown, q)]
        column_quantities = [("", q) for q in quantities]
        groups = ()
    columns = tuple(quantity_label(q, layout.percent, unit) for _, q in column_quantities)
    stub = (
        *((Label("posture", "posture"),) if named else ()),
        Label("direction", "direction"),
        *(() if layout.transpose else (Label("set", "set"),)),
    )
    tables = []
    for chosen in [[p] for p in postures] if split else [postures]:
        rows = []
        for posture in chosen:
            part = frame[frame["posture"] == posture] if has_posture else frame
            first = (text_label(str(posture), "posture"),) if named else ()
            for direction in dict.fromkeys(part["direction"]):
                at = part[part["direction"] == direction].set_index("set")
                label = direction_label(str(direction))
                if layout.transpose:
                    cells = tuple(
                        _cell(at.loc[kind], q, layout.percent, kind)
                        for kind, q in column_quantities
                    )
                    rows.append(((*first, label), cells))
                    continue
                for kind in kinds:
                    cells = tuple(
                        _cell(at.loc[kind], q, layout.percent, kind) for _, q in column_quantities
                    )
                    rows.append(((*first, label, set_labels[kind]), cells))
        title = str(chosen[0]) if split else ""
        tables.append(PrintTable(stub, columns, tuple(rows), groups, title, grouped=named))
    return tables


def _zero(frame: pd.DataFrame, quantity: Quantity, kind: str | None = None) -> bool:
    """Whether the errors ``quantity`` are zero in every row of ``frame`` (of ``kind``).

    Only errors are left out so: a limit of 0 is a result.
    """
    if quantity.kind != "share":
        return False
    rows = frame if kind is None else frame[frame["set"] == kind]
    return zero_everywhere([float(value) for value in rows[quantity.name]])
