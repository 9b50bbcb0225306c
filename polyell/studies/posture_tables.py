r"""The choice table of a posture study as LaTeX (booktabs), Markdown and CSV.

Every text that reaches a table is escaped by the one escaping place of the package
(:func:`~polyell.comparison.tables.escape_latex`,
:func:`~polyell.comparison.tables.escape_markdown`); the LaTeX needs
``\usepackage{booktabs}``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

from polyell.comparison.tables import escape_latex, escape_markdown
from polyell.errors import InputError
from polyell.storage import write_text_atomically

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["POSTURE_TABLE_STEM", "format_posture_table", "write_posture_tables"]

#: File names of the written tables: ``<stem>.tex``, ``<stem>.md``, ``<stem>.csv``.
POSTURE_TABLE_STEM = "posture_choice"
#: Display names of the kinds (a candidate keeps its own name).
KIND_LABELS = {
    "polytope": "polytope (truth)",
    "chiacchio": "new (eq. 32/38)",
    "yoshikawa": "classic (eq. 27)",
    "mvie": "MVIE",
    "outer": "outer (min. volume)",
}


#: How an undefined cell prints.
MISSING = "n/a"


def _number(value: object, kind: str) -> str:
    """A cell: a posture index, a percentage, a correlation or a value (4 significant)."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return MISSING
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return MISSING  # pandas' <NA>
    if math.isnan(number):
        return MISSING
    if kind == "index":
        return str(int(number))
    if kind == "percent":
        return f"{100.0 * number:.1f} %"
    if kind == "correlation":
        return f"{number:+.3f}"
    return f"{number:.4g}"


#: The columns shown, their header and their format.
_COLUMNS = {
    "picked": ("posture picked", "index"),
    "true_at_pick": ("truth at pick", "value"),
    "true_best": ("best truth", "value"),
    "regret": ("regret", "percent"),
    "spearman": ("Spearman", "correlation"),
    "kendall": ("Kendall", "correlation"),
    "median_regret": ("median regret", "percent"),
    "worst_regret": ("worst regret", "percent"),
    "mean_regret": ("mean regret", "percent"),
    "median_spearman": ("median Spearman", "correlation"),
    "median_kendall": ("median Kendall", "correlation"),
    "targets": ("targets", "index"),
}


def _cells(table: pd.DataFrame) -> tuple[list[str], list[list[str]]]:
    if table.index.nlevels != 2:
        raise InputError(
            "table",
            "a choice table indexed by (kind, criterion)",
            f"an index of {table.index.nlevels} levels",
            "pass PostureChoice.table or PostureChoiceOverTargets.summary.",
        )
    columns = [c for c in table.columns if c in _COLUMNS]
    if not columns:
        raise InputError("table", f"columns among {list(_COLUMNS)}", f"{list(table.columns)}")
    header = ["index", "criterion", *(_COLUMNS[c][0] for c in columns)]
    body = []
    for (kind, criterion), row in table.iterrows():
        cells = [KIND_LABELS.get(str(kind), str(kind)), str(criterion)]
        body.append(cells + [_number(row[c], _COLUMNS[c][1]) for c in columns])
    return header, body


def format_posture_table(
    table: pd.DataFrame, style: str, title: str = "", label: str | None = None
) -> str:
    """A choice table as ``"latex"`` (booktabs, a ``table`` float) or ``"markdown"`` text.

    Parameters
    ----------
    table : DataFrame
        :attr:`PostureChoice.table` or :attr:`PostureChoiceOverTargets.summary`.
    style : {"latex", "markdown"}
    title : str, optional
        The LaTeX caption, or a Markdown heading line (plain text, escaped).
    label : str, optional
        A LaTeX label (letters, digits and ``:-_.``).
    """
    header, body = _cells(table)
    if style == "markdown":
        lines = [f"**{escape_markdown(title, 'title')}**", ""] if title else []
        lines.append("| " + " | ".join(escape_markdown(h, "column") for h in header) + " |")
        lines.append("| :-- | :-- | " + " | ".join("--:" for _ in header[2:]) + " |")
        for row in body:
            lines.append("| " + " | ".join(escape_markdown(c, "cell") for c in row) + " |")
        return "\n".join(lines) + "\n"
    if style != "latex":
        raise InputError("style", "'latex' or 'markdown'", repr(style))
    lines = [r"\begin{table}", r"\centering"]
    if title:
        lines.append(rf"\caption{{{escape_latex(title, 'title')}}}")
    if label is not None:
        if (
            not isinstance(label, str)
            or not label
            or any(not (c.isascii() and (c.isalnum() or c in ":-_.")) for c in label)
        ):
            raise InputError("label", "letters, digits and :-_. only", repr(label))
        lines.append(rf"\label{{{label}}}")
    lines += [rf"\begin{{tabular}}{{ll{'r' * (len(header) - 2)}}}", r"\toprule"]
    lines.append(" & ".join(escape_latex(h, "column") for h in header) + r" \\")
    lines.append(r"\midrule")
    previous = None
    for row in body:
        first = escape_latex(row[0], "row") if row[0] != previous else ""
        previous = row[0]
        lines.append(" & ".join([first, *(escape_latex(c, "cell") for c in row[1:])]) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return "\n".join(lines) + "\n"


def write_posture_tables(
    table: pd.DataFrame,
    folder: str | os.PathLike[str],
    title: str = "Posture choice",
    *,
    label: str | None = None,
    stem: str = POSTURE_TABLE_STEM,
) -> dict[str, Path]:
    """Write a choice table as ``<stem>.tex``, ``<stem>.md`` and ``<stem>.csv`` in ``folder``.

    Parameters
    ----------
    table : DataFrame
        :attr:`PostureChoice.table` or :attr:`PostureChoiceOverTargets.summary`.
    folder : str or Path
        An existing folder.
    title : str, optional
        The LaTeX caption and the Markdown heading.
    label : str, optional
        The LaTeX label.
    stem : str, optional
        The file names' stem.

    Returns
    -------
    dict of str to Path
        ``{"latex": ..., "markdown": ..., "csv": ...}``.  The CSV holds the full-precision
        values (regret as a fraction).

    Raises
    ------
    InputError
        For a table of another shape, a folder that does not exist, a stem with a path
        separator, text that cannot be written.
    """
    if not isinstance(folder, str | os.PathLike) or not Path(folder).is_dir():
        raise InputError("folder", "an existing folder", repr(folder), "create it first.")
    if not isinstance(stem, str) or not stem or "/" in stem or "\\" in stem or stem[0] == ".":
        raise InputError("stem", "a file name without a path", repr(stem))
    texts = {
        "latex": format_posture_table(table, "latex", title, label),
        "markdown": format_posture_table(table, "markdown", title),
        "csv": table.to_csv(),
    }
    paths = {}
    for style, suffix in (("latex", ".tex"), ("markdown", ".md"), ("csv", ".csv")):
        paths[style] = write_text_atomically(Path(folder) / f"{stem}{suffix}", texts[style])
    return paths
