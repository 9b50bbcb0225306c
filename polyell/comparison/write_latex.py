r"""LaTeX of printed tables: booktabs rules, siunitx-friendly cells, units in the headers.

Every number column is ``r``; a cell is a bare number (``-1.23``, ``4.5e-07``) that an
``S`` column of siunitx parses as well, and any other cell (``n/a``, ``empty``,
``12.3 $\pm$ 0.05``, infinities) is braced, which both column types print as text:
replace ``r`` by ``S`` in the column specification to align on the decimal marker.
Headers that may break are stacked in a nested ``tabular`` (no package needed).  The
document needs ``\usepackage{booktabs}``.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from polyell.comparison.latex_text import check_latex_label, escape_latex
from polyell.comparison.printable import Cell, Label, PrintTable

__all__ = ["latex_cell", "latex_tables"]


def _stacked(label: Label, align: str) -> str:
    """A header: its LaTeX, or its lines in a nested tabular aligned like its column."""
    if len(label.lines) < 2:
        return label.latex
    return rf"\begin{{tabular}}[b]{{@{{}}{align}@{{}}}}" + r"\\".join(label.lines) + r"\end{tabular}"


def latex_cell(cell: Cell, digits: int) -> str:
    """A number as is; anything else braced (text to siunitx's ``S`` columns)."""
    number = cell.number(digits)
    if cell.has_error():
        return f"{{{number} $\\pm$ {cell.error(digits)}}}"
    if number in ("inf", "-inf"):
        return r"{$\infty$}" if number == "inf" else r"{$-\infty$}"
    if _NUMBER.fullmatch(number):
        return number
    return "{" + escape_latex(number, "cell") + "}"


_NUMBER = re.compile(r"-?[0-9]+(\.[0-9]+)?(e[+-][0-9]+)?")


def _table(table: PrintTable, digits: int, caption: str | None, label: str | None) -> list[str]:
    lines = [r"\begin{table}", r"\centering"]
    if caption is not None:
        lines.append(rf"\caption{{{escape_latex(caption, 'caption')}}}")
    if label is not None:
        lines.append(rf"\label{{{check_latex_label(label)}}}")
    s, c = len(table.stub), len(table.columns)
    lines += [rf"\begin{{tabular}}{{{'l' * s}{'r' * c}}}", r"\toprule"]
    if table.groups:
        spans, rules, start = [], [], s + 1
        for group, span in table.groups:
            spans.append(rf"\multicolumn{{{span}}}{{c}}{{{_stacked(group, 'c')}}}")
            rules.append(rf"\cmidrule(lr){{{start}-{start + span - 1}}}")
            start += span
        lines.append(" & ".join([""] * s + spans) + r" \\")
        lines.append(" ".join(rules))
    header = [_stacked(h, "l") for h in table.stub] + [_stacked(h, "r") for h in table.columns]
    lines += [" & ".join(header) + r" \\", r"\midrule"]
    previous: tuple[str, ...] = ()
    for labels, cells in table.rows:
        plain = tuple(label.plain for label in labels)
        if s > 1 and previous and plain[0] != previous[0]:
            lines.append(r"\midrule")  # a new posture (or direction)
        shown = []
        for k, label in enumerate(labels):
            repeated = k < s - 1 and plain[: k + 1] == previous[: k + 1]
            shown.append("" if repeated else label.latex)
        previous = plain
        lines.append(" & ".join(shown + [latex_cell(cell, digits) for cell in cells]) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return lines


_KEY = re.compile(r"[^A-Za-z0-9:._/+-]")


def latex_tables(
    tables: Sequence[PrintTable],
    digits: int,
    caption: str | None = None,
    label: str | None = None,
) -> str:
    """The tables as LaTeX ``table`` floats, one after the other.

    Parameters
    ----------
    tables : sequence of PrintTable
    digits : int
        Significant digits.
    caption : str, optional
        Plain text (escaped); a table of one posture adds ``(<posture>)``.
    label : str, optional
        A ``\label`` key; a table of one posture among several adds ``-<posture>``
        (characters a key cannot hold become ``-``).
    """
    if label is not None:
        check_latex_label(label)
    parts = []
    for table in tables:
        title = f" ({table.title})" if table.title else ""
        own_caption = None if caption is None else caption + title
        own_label = label
        if label is not None and len(tables) > 1:
            own_label = f"{label}-{_KEY.sub('-', table.title)}"[:200]
        parts.append("\n".join(_table(table, digits, own_caption, own_label)) + "\n")
    return "\n".join(parts)
