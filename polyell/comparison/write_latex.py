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
from dataclasses import replace

from polyell.comparison.latex_text import check_latex_label, check_text, escape_latex
from polyell.comparison.printable import Cell, Label, PrintTable

__all__ = ["latex_cell", "latex_tables"]


def _stacked(label: Label, align: str) -> str:
    """A header: its LaTeX, or its lines in a nested tabular aligned like its column."""
    if len(label.lines) < 2:
        return label.latex
    # "\\{}": a line starting with "[" (a unit) is text, not the optional argument of \\
    inner = r"\\{}".join(label.lines)
    return rf"\begin{{tabular}}[b]{{@{{}}{align}@{{}}}}{inner}\end{{tabular}}"


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


def _row(cells: list[str]) -> str:
    r"""One row; ``{}`` before a first cell starting with "[", which ``\\`` would take."""
    line = " & ".join(cells) + r" \\"
    return "{}" + line if line.startswith("[") else line


#: Body lines (rows and posture lines) up to which a table is set in ``\small``; a longer
#: one is set in ``\footnotesize``.  With narrower gaps between columns (``\tabcolsep``
#: 4pt), as journals print tables, the default layouts of up to three postures then fit
#: the width and the height of a one-column article page (tests/comparison/test_print_fit.py).
SMALL_ROWS = 40


#: Body lines beyond which a table of several postures is set as one float per posture:
#: a float cannot break across pages, and ``\footnotesize`` fits about 50 lines on one.
PAGE_LINES = 48


def _page_parts(table: PrintTable) -> list[PrintTable]:
    """The table, or one table per posture where it would not fit the page's height."""
    postures = list(dict.fromkeys(labels[0].plain for labels, _ in table.rows))
    if not table.grouped or len(table.rows) + len(postures) <= PAGE_LINES or len(postures) < 2:
        return [table]
    return [
        replace(
            table,
            stub=table.stub[1:],
            rows=tuple(
                (labels[1:], cells) for labels, cells in table.rows if labels[0].plain == name
            ),
            title=name,
            grouped=False,
        )
        for name in postures
    ]


def _preamble(body_lines: int) -> list[str]:
    size = r"\small" if body_lines <= SMALL_ROWS else r"\footnotesize"
    return [size, r"\setlength{\tabcolsep}{4pt}"]


def _table(table: PrintTable, digits: int, caption: str | None, label: str | None) -> list[str]:
    grouped = table.grouped and len(table.stub) > 1
    postures = len({labels[0].plain for labels, _ in table.rows}) if grouped else 0
    lines = [r"\begin{table}", r"\centering", *_preamble(len(table.rows) + postures)]
    if caption is not None:
        lines.append(rf"\caption{{{escape_latex(caption, 'caption')}}}")
    if label is not None:
        lines.append(rf"\label{{{check_latex_label(label)}}}")
    stub = table.stub[1:] if grouped else table.stub
    s, c = len(stub), len(table.columns)
    lines += [rf"\begin{{tabular}}{{{'l' * s}{'r' * c}}}", r"\toprule"]
    if table.groups:
        spans, rules, start = [], [], s + 1
        for group, span in table.groups:
            spans.append(rf"\multicolumn{{{span}}}{{c}}{{{_stacked(group, 'c')}}}")
            rules.append(rf"\cmidrule(lr){{{start}-{start + span - 1}}}")
            start += span
        lines.append(_row([""] * s + spans))
        lines.append(" ".join(rules))
    header = [_stacked(h, "l") for h in stub] + [_stacked(h, "r") for h in table.columns]
    lines += [_row(header), r"\midrule"]
    previous: tuple[str, ...] = ()
    for labels, cells in table.rows:
        plain = tuple(label.plain for label in labels)
        if grouped and plain[:1] != previous[:1]:
            if previous:
                lines.append(r"\midrule")
            # the posture above its rows, across the table
            lines.append(rf"\multicolumn{{{s + c}}}{{@{{}}l}}{{\itshape {labels[0].latex}}} \\")
            previous = plain[:1]
        elif not grouped and s > 1 and previous and plain[0] != previous[0]:
            lines.append(r"\midrule")
        own = labels[1:] if grouped else labels
        start = 1 if grouped else 0
        shown = [
            "" if k < s - 1 and plain[: start + k + 1] == previous[: start + k + 1] else label.latex
            for k, label in enumerate(own)
        ]
        previous = plain
        lines.append(_row(shown + [latex_cell(cell, digits) for cell in cells]))
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return lines


_KEY = re.compile(r"[^A-Za-z0-9:._/+-]")


def latex_tables(
    tables: Sequence[PrintTable],
    digits: int,
    caption: str | None = None,
    label: str | None = None,
) -> str:
    r"""The tables as LaTeX ``table`` floats, one after the other.

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

    A combined table of several postures longer than :data:`PAGE_LINES` body lines
    (three postures of five directions in the directional-limits table) is written as
    one float per posture, as ``split="posture"`` would: one float cannot be taller than
    a page.
    """
    if label is not None:
        check_latex_label(label)
    if caption is not None:
        caption = check_text("caption", caption)
    tables = [part for table in tables for part in _page_parts(table)]
    parts = []
    for table in tables:
        title = f" ({table.title})" if table.title else ""
        own_caption = None if caption is None else caption + title
        own_label = label
        if label is not None and len(tables) > 1:
            own_label = f"{label}-{_KEY.sub('-', table.title)}"[:200]
        parts.append("\n".join(_table(table, digits, own_caption, own_label)) + "\n")
    return "\n".join(parts)
