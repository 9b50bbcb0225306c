"""Summary statistics of scores over many configurations (a study), and their tables."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from polyell.capacities import check_capacity
from polyell.comparison.comparison import SCORE_NAMES
from polyell.comparison.labels import QUANTITIES, quantity, set_label
from polyell.comparison.layout import TableLayout
from polyell.comparison.printable import Cell, Label, PrintTable, quantity_label, text_label
from polyell.comparison.tables import Style, render_tables
from polyell.errors import InputError
from polyell.validation import check_frame, check_instance

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "SUMMARY_SCORES",
    "format_summary_table",
    "result_kinds",
    "split_column",
    "summarize",
]

#: Scores summarised over a study by default.
SUMMARY_SCORES = (
    "inscribed_scale",
    "enclosing_scale",
    "coverage",
    "overreach",
    "mvie_ratio",
    "outer_ratio",
    "direction_error_mean",
    "direction_error_max",
    "direction_bias",
    "witness_torque_max",
)
_STATISTICS = ("defined", "mean", "std", "min", "median", "max")


def split_column(column: str) -> tuple[str, str] | None:
    """``(kind, score)`` of a ``<kind>_<score>`` column (a candidate's name may hold '_').

    None for other columns (``configuration``, ``q1``, ``polytope_volume``, ...).
    """
    check_instance("column", column, str, "pass a column name, e.g. 'chiacchio_coverage'.")
    for score in sorted(SCORE_NAMES, key=len, reverse=True):  # coverage_stderr first
        if column.endswith(f"_{score}") and column[: -len(score) - 1] not in ("", "polytope"):
            return column[: -len(score) - 1], score
    return None


def result_kinds(columns: Iterable[str]) -> list[str]:
    """The ellipsoids with ``<kind>_<score>`` columns, in column order (candidates too)."""
    if isinstance(columns, str) or not hasattr(columns, "__iter__"):
        raise InputError("columns", "column names (e.g. frame.columns)", repr(columns)[:80])
    found: list[str] = []
    for column in columns:
        split = split_column(column)
        if split is not None and split[0] not in found:
            found.append(split[0])
    return found


def summarize(results: pd.DataFrame, scores: tuple[str, ...] = SUMMARY_SCORES) -> pd.DataFrame:
    """Statistics per ellipsoid and score over the rows (configurations) of ``results``.

    Parameters
    ----------
    results : DataFrame
        One row per configuration with ``<kind>_<score>`` columns (``Comparison.to_row``).
    scores : tuple of str
        Scores to summarise; those without a column are skipped.

    Returns
    -------
    DataFrame
        Indexed by ``(ellipsoid, score)``, with the columns ``defined`` (how many
        configurations have a finite value), ``mean``, ``std``, ``min``, ``median``,
        ``max``; NaN values (undefined ellipsoids) are left out of the statistics.
    """
    check_frame("results", results, "pass a pandas DataFrame (e.g. the results of pe.sweep).")
    rows = {}
    for kind in result_kinds(results.columns):
        for score in scores:
            column = f"{kind}_{score}"
            if column not in results:
                continue
            values = results[column].astype(float)
            finite = values[values.notna() & (values.abs() != float("inf"))]
            if finite.empty:
                continue
            rows[(kind, score)] = {
                "defined": int(finite.size),
                "mean": finite.mean(),
                "std": finite.std(ddof=1) if finite.size > 1 else 0.0,
                "min": finite.min(),
                "median": finite.median(),
                "max": finite.max(),
            }
    import pandas as pd

    summary = pd.DataFrame.from_dict(rows, orient="index", columns=list(_STATISTICS))
    summary.index = pd.MultiIndex.from_tuples(summary.index, names=["ellipsoid", "score"])
    return summary


def format_summary_table(
    summary: pd.DataFrame,
    style: Style,
    *,
    caption: str | None = None,
    label: str | None = None,
    layout: TableLayout | None = None,
    capacity: str = "acceleration",
) -> str:
    """Render :func:`summarize` output for print, as every table of polyell is written.

    One row per score under a line per set (the sets' labels, ``new (eq. 32/38)``), the
    statistics as columns; shares in percent (``layout.percent``), ``layout.digits``
    significant digits.  A table taller than a page is one LaTeX float per set.

    Parameters
    ----------
    summary : DataFrame
        From :func:`summarize`.
    style : {"latex", "markdown", "csv", "html"}
    caption, label : str, optional
        LaTeX caption and label.
    layout : TableLayout, optional
        Its ``sets`` and ``scores`` (which rows, in that order; the others, e.g. a limit
        quantity, do not apply), ``digits`` and ``percent``; default ``TableLayout()``.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids they are: the sets' labels (a force ``"chiacchio"`` is "with
        gravity", ``"static"`` "no gravity").
    """
    check_frame("summary", summary, "pass summarize(results).")
    capacity = check_capacity(capacity)
    layout = TableLayout() if layout is None else layout
    kinds = list(dict.fromkeys(kind for kind, _ in summary.index))
    scores = list(dict.fromkeys(score for _, score in summary.index))
    if layout.sets is not None:
        kinds = [kind for kind in layout.sets if kind in kinds]
    if layout.scores is not None:
        scores = [score for score in layout.scores if score in scores] or scores
    chosen = [(k, s) for k in kinds for s in scores if (k, s) in summary.index]
    rows = []
    for (kind, score), record in summary.loc[chosen].iterrows():
        known = quantity(str(score), capacity) if str(score) in QUANTITIES else None
        name = (
            quantity_label(known, layout.percent, "")
            if known is not None
            else text_label(str(score))
        )
        shift = 2 if known is not None and known.kind == "share" and layout.percent else 0
        cells = tuple(
            Cell(float(record[column]), count=True)
            if column == "defined"
            else Cell(float(record[column]), shift)
            for column in _STATISTICS
        )
        rows.append(((text_label(set_label(str(kind), capacity), "sets"), name), cells))
    table = PrintTable(
        (Label("set", "set"), Label("score", "score")),
        tuple(Label(column, column) for column in _STATISTICS),
        tuple(rows),
        grouped=True,
    )
    return render_tables([table], style, layout.digits, caption, label)
