"""Summary statistics of scores over many configurations (a study), and their tables."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, cast

from polyell.capacities import check_capacity
from polyell.comparison.comparison import SCORE_NAMES
from polyell.comparison.labels import QUANTITIES, quantity
from polyell.comparison.layout import TableLayout
from polyell.comparison.long_form import BUILT_IN_SCORED_KINDS, score_columns
from polyell.comparison.printable import (
    Cell,
    Label,
    PrintTable,
    given_label,
    quantity_label,
    text_label,
)
from polyell.comparison.tables import Style, _caption, render_tables
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


def split_column(column: str, kinds: Sequence[str] | None = None) -> tuple[str, str] | None:
    """``(kind, score)`` of a ``<kind>_<score>`` column, matched exactly, never split.

    The column is ``(kind, score)`` where it equals ``f"{kind}_{score}"`` for one of
    ``kinds`` and a score of :data:`~polyell.comparison.comparison.SCORE_NAMES` (a
    candidate's name may hold ``'_'``).  None for other columns (``configuration``, ``q1``,
    ``polytope_volume``, ...).

    Parameters
    ----------
    column : str
        A column name, e.g. ``"heavy_wrist_coverage"``.
    kinds : sequence of str, optional
        The frame's ellipsoids: :func:`result_kinds` of the frame, or its
        ``attrs["kinds"]`` (:func:`polyell.sweep` records them).  Default: the built-in
        kinds of every capacity; a name that none of them matches is then, for callers
        that hold only names (files written before kinds were recorded), cut before its
        longest score name (:func:`_compatible_split`).
    """
    check_instance("column", column, str, "pass a column name, e.g. 'chiacchio_coverage'.")
    known = BUILT_IN_SCORED_KINDS if kinds is None else _kind_names(kinds)
    exact = {f"{kind}_{score}": (kind, score) for kind in known for score in SCORE_NAMES}
    if column in exact:
        return exact[column]
    return _compatible_split(column) if kinds is None else None


def _compatible_split(column: str) -> tuple[str, str] | None:
    """The rule for names whose kinds are unknown: the prefix before the longest score name.

    Kept for callers that hold only column names without their kinds (a Parquet schema, a
    study's map names); :func:`result_kinds` of a frame whose ``attrs`` record its kinds,
    or ``kinds=``, never uses it.
    """
    for score in sorted(SCORE_NAMES, key=len, reverse=True):  # coverage_stderr first
        if column.endswith(f"_{score}") and column[: -len(score) - 1] not in ("", "polytope"):
            return column[: -len(score) - 1], score
    return None


def _kind_names(kinds: object) -> tuple[str, ...]:
    if isinstance(kinds, str) or not isinstance(kinds, Iterable):
        raise InputError(
            "kinds",
            "a sequence of ellipsoid names (str)",
            repr(kinds)[:80],
            "pass e.g. result_kinds(frame).",
        )
    names = tuple(kinds)
    wrong = [name for name in names if not isinstance(name, str)]
    if wrong:
        raise InputError(
            "kinds",
            "ellipsoid names (str)",
            f"an item {wrong[0]!r}"[:80],
            "pass the names as str, e.g. ('chiacchio', 'mvie') or result_kinds(frame)",
        )
    return names


def result_kinds(
    columns: pd.DataFrame | Iterable[str], kinds: Sequence[str] | None = None
) -> list[str]:
    """The ellipsoids with ``<kind>_<score>`` columns, in column order (candidates too).

    Parameters
    ----------
    columns : DataFrame or iterable of str
        A wide results frame -- the kinds its ``attrs`` record (:func:`polyell.sweep`;
        Parquet keeps them) -- or its column names.
    kinds : sequence of str, optional
        Ellipsoids beyond the built-in ones (the candidates' names), where the frame does
        not record them.

    Returns
    -------
    list of str
        Resolved by :func:`~polyell.comparison.long_form.score_columns`: exact
        ``<kind>_<score>`` names of the recorded kinds, of ``kinds`` and of the built-in
        kinds.  Where neither ``attrs`` nor ``kinds`` name them, the remaining names that
        end in a score (candidates of a frame read back without its kinds) are resolved by
        the rule of :func:`split_column` for bare names; a caller that knows its kinds (a
        study: its capacity's kinds and its candidates) passes them, and no name is split.
    """
    if (isinstance(columns, str) or not hasattr(columns, "__iter__")) and not _is_frame(columns):
        raise InputError(
            "columns",
            "column names (e.g. frame.columns)",
            repr(columns)[:80],
            "pass frame.columns, or a list of names such as ['chiacchio_coverage']",
        )
    found = score_columns(
        columns if _is_frame(columns) else [str(column) for column in columns],
        kinds=None if kinds is None else list(_kind_names(kinds)),
    )
    held = found.kinds
    if found.recorded or kinds is not None or not found.unresolved:
        return held  # the kinds are known: no name is split to guess one
    names = list(cast("pd.DataFrame", columns).columns if _is_frame(columns) else columns)
    extra: dict[str, int] = {}
    for column in found.unresolved:
        split = _compatible_split(column)
        if split is not None:
            extra.setdefault(split[0], names.index(column))
    first = {kind: min(names.index(c) for c in found.columns[kind].values()) for kind in held}
    first.update(extra)
    return sorted(first, key=first.__getitem__)


def _is_frame(value: object) -> bool:
    import pandas as pd

    return isinstance(value, pd.DataFrame)


def summarize(
    results: pd.DataFrame,
    scores: tuple[str, ...] = SUMMARY_SCORES,
    *,
    kinds: Sequence[str] | None = None,
) -> pd.DataFrame:
    """Statistics per ellipsoid and score over the rows (configurations) of ``results``.

    Parameters
    ----------
    results : DataFrame
        One row per configuration with ``<kind>_<score>`` columns (:func:`polyell.sweep`,
        ``Comparison.to_row``).  Its ellipsoids: :func:`result_kinds` (the kinds its
        ``attrs`` record, else the built-in ones matched exactly).
    scores : tuple of str
        Scores to summarise; those without a column are skipped.
    kinds : sequence of str, optional
        Ellipsoids beyond the built-in ones (candidates) of a frame that does not record
        its kinds.

    Returns
    -------
    DataFrame
        Indexed by ``(ellipsoid, score)``, with the columns ``defined`` (how many
        configurations have a finite value), ``mean``, ``std``, ``min``, ``median``,
        ``max``; NaN values (undefined ellipsoids) are left out of the statistics.
    """
    check_frame("results", results, "pass a pandas DataFrame (e.g. the results of pe.sweep).")
    scores = (scores,) if isinstance(scores, str) else scores
    if not isinstance(scores, Sequence) or not all(isinstance(s, str) for s in scores):
        raise InputError(
            "scores",
            "score names (str), e.g. ('coverage', 'volume')",
            f"{type(scores).__name__} {scores!r}"[:80],
            f"pass a tuple of names, e.g. scores={SUMMARY_SCORES[:2]!r}",
        )
    rows = {}
    for kind in result_kinds(results, kinds):
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


#: A standard deviation at most this many units of the last place of the data's largest
#: magnitude is rounding noise (values equal but for their last bits: a scale of
#: 1.0000000000000002 among ones): it is shown as 0.
ROUNDING_ULPS = 64


def exact_spread(std: float, low: float, high: float) -> float:
    """``std``, or 0 where it is below the rounding of values in ``[low, high]``.

    Examples
    --------
    >>> exact_spread(7.8e-16, 1.0, 1.0000000000000002), exact_spread(0.01, 0.9, 1.1)
    (0.0, 0.01)
    """
    scale = max(abs(low), abs(high))
    if math.isfinite(std) and math.isfinite(scale):
        if std <= ROUNDING_ULPS * math.ulp(scale):
            return 0.0
    return std


def format_summary_table(
    summary: pd.DataFrame,
    style: Style,
    *,
    caption: str | tuple[str, str | None] | None = None,
    label: str | None = None,
    layout: TableLayout | None = None,
    capacity: str = "acceleration",
) -> str:
    """Render :func:`summarize` output for print, as every table of polyell is written.

    One row per score under a line per set (the sets' labels: ``layout.labels``), the
    statistics as columns; shares in percent (``layout.percent``), ``layout.digits``
    significant digits.  A table taller than a page is one LaTeX float per set.

    Parameters
    ----------
    summary : DataFrame
        From :func:`summarize`.
    style : {"latex", "markdown", "csv", "html"}
    caption : str or (str, str), optional
        LaTeX caption: plain text, or ``(plain, latex)``; default the layout's
        ``captions["summary"]``, else none.
    label : str, optional
        LaTeX label.
    layout : TableLayout, optional
        Its ``sets`` and ``scores`` (which rows, in that order; the others, e.g. a limit
        quantity, do not apply), ``digits``, ``percent``, ``labels``, ``siunitx`` and
        ``text_width``; default ``TableLayout()``.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids they are: the witness's label (a normalized torque, or a joint
        velocity for velocities).
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
        known = quantity(str(score), capacity, layout.labels) if str(score) in QUANTITIES else None
        name = (
            quantity_label(known, layout.percent, "")
            if known is not None
            else text_label(str(score))
        )
        shift = 2 if known is not None and known.kind == "share" and layout.percent else 0
        shown = {column: float(record[column]) for column in _STATISTICS}
        shown["std"] = exact_spread(shown["std"], shown["min"], shown["max"])
        cells = tuple(
            Cell(shown[column], count=True) if column == "defined" else Cell(shown[column], shift)
            for column in _STATISTICS
        )
        rows.append(((given_label(layout.set_text(str(kind), capacity), "sets"), name), cells))
    table = PrintTable(
        (Label("set", "set"), Label("score", "score")),
        tuple(Label(column, column) for column in _STATISTICS),
        tuple(rows),
        grouped=True,
        mixed=True,  # a row per score
    )
    caption = _caption(caption, layout, "summary")
    return render_tables([table], style, layout.digits, caption, label, layout=layout)
