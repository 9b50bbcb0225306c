r"""Paper-ready tables: the comparison table and the directional-limits table, in every format.

The tables are laid out by a :class:`~polyell.comparison.layout.TableLayout` (sets, scores,
orientation, one table or one per posture, significant digits, percent or fractions) and
written by one writer per format from the same :class:`~polyell.comparison.printable.PrintTable`,
so LaTeX, Markdown, CSV and HTML show the same labels (:mod:`~polyell.comparison.labels`:
one name per set that fits any robot, or the layout's ``labels``), units and numbers.
Every string that reaches a table is plain text, escaped where it is written
(:mod:`~polyell.comparison.latex_text`), but the LaTeX a user gives with a label or a
caption, ``(plain, latex)``, checked to stay within its cell.  A LaTeX table needs
``\usepackage{booktabs}`` (and ``siunitx`` with ``TableLayout(siunitx=True)``); one wider
than the layout's ``text_width`` is written with a warning that names its width
(:mod:`~polyell.comparison.write_latex`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Literal, TypeAlias

from polyell.comparison.labels import (
    ELLIPSOID_LABELS,
    QUANTITIES,
    Labels,
    ellipsoid_label,
    quantity,
    set_label,
)
from polyell.comparison.latex_text import (
    check_latex_label,
    check_text,
    escape_latex,
    escape_markdown,
    latex_unit,
    markdown_line,
)
from polyell.comparison.layout import TableLayout
from polyell.comparison.printable import PrintTable
from polyell.errors import InputError
from polyell.validation import check_frame, check_instance

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

    from polyell.comparison.comparison import Comparison

__all__ = [
    "ELLIPSOID_LABELS",
    "PERCENT_SCORES",
    "STYLES",
    "Caption",
    "check_latex_label",
    "check_text",
    "ellipsoid_label",
    "escape_latex",
    "escape_markdown",
    "format_comparison_table",
    "format_limits_table",
    "format_scores_table",
    "latex_unit",
    "render_tables",
    "score_display",
    "set_label",
]

#: The caption and the label key of a float of one posture of the limits table, or of
#: the comparison table, when none is given (``... at posture ready.``, ``...-ready``).
LIMITS_NAME = ("Directional limits", "tab:limits")
COMPARISON_NAME = ("Scores of each ellipsoid", "tab:comparison")

#: The formats a table is written in.
STYLES = ("latex", "markdown", "csv", "html")
Style = Literal["latex", "markdown", "csv", "html"]
#: A caption: plain text (escaped in LaTeX), or ``(plain, latex)`` with the LaTeX as is.
Caption: TypeAlias = str | tuple[str, str | None]

#: Scores shown in percent wherever they are shown (tables, summaries, figures) when a
#: layout asks for percent (the default); the data (Scores, CSV of the data, Parquet,
#: JSON) keep them as fractions.
PERCENT_SCORES = frozenset(name for name, q in QUANTITIES.items() if q.kind == "share")


def score_display(
    score: str, capacity: str = "acceleration", labels: Labels = None
) -> tuple[str, float]:
    """The label and the factor a score is displayed with: ``("coverage [%]", 100.0)``.

    The label is the tables' (:func:`~polyell.comparison.labels.quantity` of the
    capacity and ``labels``: a layout's), without the volume's unit; a score without one
    is its name with spaces.
    """
    check_instance("score", score, str, "pass a score name, e.g. 'coverage'.")
    known = score in QUANTITIES
    name = quantity(score, capacity, labels).plain if known else score.replace("_", " ")
    return (f"{name} [%]", 100.0) if score in PERCENT_SCORES else (name, 1.0)


def _layout(layout: object) -> TableLayout:
    if layout is None:
        return TableLayout()
    if not isinstance(layout, TableLayout):
        raise InputError(
            "layout", "a polyell TableLayout", type(layout).__name__, "pass TableLayout(...)."
        )
    return layout


def render_tables(
    tables: Sequence[PrintTable],
    style: Style,
    digits: int,
    caption: Caption | None = None,
    label: str | None = None,
    *,
    layout: TableLayout | None = None,
    name: tuple[str, str] = ("Table", "tab:table"),
) -> str:
    r"""Write laid-out tables in one format (LaTeX floats, Markdown, CSV or HTML).

    Parameters
    ----------
    tables : sequence of PrintTable
    style : {"latex", "markdown", "csv", "html"}
    digits : int
        Significant digits.
    caption : str or (str, str), optional
        Plain text, or ``(plain, latex)``: LaTeX's caption (its own markup); HTML's and
        Markdown's (a line above the table) are the plain text.  CSV has none.
    label : str, optional
        LaTeX ``\label`` key.
    layout : TableLayout, optional
        Its ``siunitx`` (``S`` columns) and ``text_width`` (the width a LaTeX table is
        checked against); default ``TableLayout()``.
    name : (str, str), optional
        The caption and label key of LaTeX floats of one posture among several when
        none is given (each float names its posture:
        :func:`~polyell.comparison.write_latex.latex_tables`).

    Raises
    ------
    InputError
        For a style other than :data:`STYLES`, a caption or label that cannot be written.
    """
    layout = _layout(layout)
    if style == "latex":
        from polyell.comparison.write_latex import latex_tables

        return latex_tables(
            tables,
            digits,
            caption,
            label,
            siunitx=layout.siunitx,
            text_width=layout.text_width,
            name=name,
        )
    if style == "markdown":
        from polyell.comparison.write_markdown import markdown_tables

        plain = caption[0] if isinstance(caption, tuple) else caption
        text = "" if plain is None else f"{markdown_line(plain, 'caption')}\n\n"
        return text + markdown_tables(tables, digits)
    if style == "csv":
        from polyell.comparison.write_csv import csv_tables

        return csv_tables(tables)
    if style == "html":
        from polyell.comparison.write_html import html_tables

        plain = caption[0] if isinstance(caption, tuple) else caption
        return html_tables(tables, digits, None if plain is None else check_text("caption", plain))
    raise InputError(
        "style",
        f"one of {list(STYLES)}",
        repr(style)[:80],
        "pass one of the styles listed, e.g. style='markdown'",
    )


def _caption(caption: Caption | None, layout: TableLayout, table: str) -> Caption | None:
    """The caption given, else the layout's caption of ``table`` (None: no caption)."""
    if caption is not None:
        return caption
    own = layout.caption(table)
    return None if own is None else (own.plain, own.latex)


def format_scores_table(
    frame: pd.DataFrame,
    dimension: int | None,
    style: Style,
    *,
    unit: str = "m/s^2",
    caption: Caption | None = None,
    label: str | None = None,
    layout: TableLayout | None = None,
) -> str:
    """Render the scores of one posture: by default one column per set, one row per score.

    Parameters
    ----------
    frame : DataFrame
        Scores, indexed by ellipsoid kind, as from ``Comparison.to_frame``.
    dimension : int or None
        Dimension r of the polytope (the power of the volume unit); None for a table
        mixing dimensions (the unit is then written with the power ``r``).
    style : {"latex", "markdown", "csv", "html"}
    unit : str, optional
        The task's unit.
    caption : str or (str, str), optional
        LaTeX and HTML caption: plain text, or ``(plain, latex)``; default the layout's
        ``captions["comparison"]``, else none.
    label : str, optional
        LaTeX label.
    layout : TableLayout, optional
        Sets, scores, orientation, rounding and labels (default ``TableLayout()``).
    """
    check_frame("frame", frame, "pass comparison.to_frame().")
    from polyell.comparison.print_scores import scores_print_tables

    layout = _layout(layout)
    unit = check_text("unit", unit)
    tables = scores_print_tables({"": frame}, layout, {"": unit}, {"": dimension})
    caption = _caption(caption, layout, "comparison")
    return render_tables(tables, style, layout.digits, caption, label, layout=layout)


def format_comparison_table(
    comparisons: Comparison | Mapping[str, Comparison],
    style: Style,
    *,
    layout: TableLayout | None = None,
    caption: Caption | None = None,
    label: str | None = None,
) -> str:
    r"""The comparison table of one or several postures, laid out for print.

    Parameters
    ----------
    comparisons : Comparison or mapping of str to Comparison
        One comparison, or comparisons by posture name (in this order).
    style : {"latex", "markdown", "csv", "html"}
    layout : TableLayout, optional
        Default ``TableLayout()``: one table, a column per ellipsoid, a row per score
        under each posture (the row groups keep the table one column wide for any
        number of postures).
    caption : str or (str, str), optional
        Caption: plain text (escaped), or ``(plain, latex)`` with the LaTeX written as is
        (a table per posture adds the posture's name); default the layout's
        ``captions["comparison"]``, else none.
    label : str, optional
        LaTeX ``\label`` key (a table per posture adds the posture's name).

    Returns
    -------
    str

    Raises
    ------
    InputError
        Naming the layout's field (``layout.sets``, ``layout.scores``) or the argument.
    """
    from polyell.comparison.limits import posture_comparisons
    from polyell.comparison.print_scores import scores_print_tables

    layout = _layout(layout)
    named = posture_comparisons(comparisons)
    tables = scores_print_tables(
        {name: c.to_frame() for name, c in named.items()},
        layout,
        {name: c.analysis.unit() for name, c in named.items()},
        {name: c.analysis.polytope.dim for name, c in named.items()},
    )
    caption = _caption(caption, layout, "comparison")
    return render_tables(
        tables, style, layout.digits, caption, label, layout=layout, name=COMPARISON_NAME
    )


def format_limits_table(
    frame: pd.DataFrame,
    style: Style,
    *,
    layout: TableLayout | None = None,
    caption: Caption | None = None,
    label: str | None = None,
) -> str:
    r"""The directional-limits table (:func:`polyell.limits_table`) laid out for print.

    Parameters
    ----------
    frame : DataFrame
        From :func:`polyell.limits_table` or ``Comparison.limits_table``.
    style : {"latex", "markdown", "csv", "html"}
    layout : TableLayout, optional
        Default ``TableLayout()``: one table, a row per posture, direction and set, the
        lower and upper limits [task unit] and their errors against the polytope [%] as
        columns, each posture a heading over its rows; ``transpose=True``: a row per
        posture and direction, each set a group of columns.  In LaTeX, a table taller
        than a page (:data:`~polyell.comparison.write_latex.PAGE_LINES` body lines, as
        three postures of five directions) is one float per posture, as
        ``split="posture"`` gives: each names its posture in its caption (``Directional
        limits at posture ready.``, or the caption given with ``at posture ready``) and
        its label (``tab:limits-ready``, or the label given with ``-ready``).
    caption : str or (str, str), optional
        Caption: plain text (escaped), or ``(plain, latex)`` with the LaTeX written as is;
        default the layout's ``captions["limits"]``, else none.
    label : str, optional
        LaTeX ``\label`` key.
    """
    from polyell.comparison.print_limits import limits_print_tables

    layout = _layout(layout)
    tables = limits_print_tables(frame, layout)
    caption = _caption(caption, layout, "limits")
    return render_tables(
        tables, style, layout.digits, caption, label, layout=layout, name=LIMITS_NAME
    )
