r"""LaTeX of printed tables: booktabs rules, numbers typeset as mathematics, units in headers.

Two kinds of number columns (:attr:`TableLayout.siunitx <polyell.TableLayout>`):

* ``r`` columns (the default, no package beyond booktabs): a number is written with a
  math minus and a power of ten, ``$-$112``, ``6.80$\times 10^{5}$`` (never the hyphen of
  ``-112`` or the ``6.80e+05`` of a program's output);
* siunitx ``S`` columns (``\usepackage{siunitx}``): a number is bare (``-112``,
  ``6.80e5``) and siunitx typesets its minus and its power of ten; every header and every
  text cell (``n/a``, ``empty``, ``12.3 $\pm$ 0.05``, infinities) is braced, as siunitx
  requires of what it must not parse.  A column of one quantity gets a ``table-format``
  computed from its numbers, so that they align on the decimal marker; a column of unlike
  quantities (a row per score, :attr:`PrintTable.mixed`) is set flush right without
  alignment (siunitx 3: ``table-alignment-mode=none``).

Headers that may break are stacked in a nested ``tabular`` (no package needed).  The
document needs ``\usepackage{booktabs}``.

Each table's width is estimated from the metrics of Computer Modern (the default fonts)
at its size; a table wider than the layout's text width is written all the same, with a
warning that names both widths (:func:`table_width`).
"""

from __future__ import annotations

import os
import re
import sys
import warnings
from collections.abc import Sequence
from dataclasses import replace

from polyell.comparison.labels import LabelText, check_markup
from polyell.comparison.latex_text import check_latex_label, check_text, escape_latex
from polyell.comparison.printable import _NUMBER, Cell, Label, PrintTable, estimate_parts
from polyell.errors import InputError, TableWidthWarning

__all__ = [
    "PAGE_LINES",
    "SMALL_ROWS",
    "at_posture",
    "estimate_text",
    "latex_cell",
    "latex_number",
    "latex_tables",
    "table_width",
    "text_width",
]


def _stacked(label: Label, align: str) -> str:
    """A header: its LaTeX, or its lines in a nested tabular aligned like its column."""
    if len(label.lines) < 2:
        return label.latex
    # "\\{}": a line starting with "[" (a unit) is text, not the optional argument of \\
    inner = r"\\{}".join(label.lines)
    return rf"\begin{{tabular}}[b]{{@{{}}{align}@{{}}}}{inner}\end{{tabular}}"


def latex_number(text: str, siunitx: bool = False) -> str:
    r"""A number as LaTeX: ``-6.80e+05`` -> ``$-$6.80$\times 10^{5}$``; siunitx: ``-6.80e5``.

    ``text`` is a number as the tables round it (``-112``, ``0.500``, ``1.00e-07``);
    anything else is returned unchanged.

    Examples
    --------
    >>> latex_number("-112"), latex_number("6.80e+05"), latex_number("-1.0e-07", True)
    ('$-$112', '6.80$\\times 10^{5}$', '-1.0e-7')
    """
    match = _NUMBER.fullmatch(text)
    if match is None:
        return text
    sign, mantissa, _, exponent = match.groups()
    if siunitx:
        return f"{sign}{mantissa}" + (f"e{int(exponent)}" if exponent else "")
    power = rf"$\times 10^{{{int(exponent)}}}$" if exponent else ""
    return ("$-$" if sign else "") + mantissa + power


def estimate_text(value: str, stderr: float, shift: int = 0) -> str:
    r"""An estimate and its standard error in LaTeX, the error at the value's last digit.

    :func:`~polyell.comparison.printable.estimate_parts` in LaTeX: ``{60.7 $\pm$ 0.3}``,
    ``{(1.23 $\pm$ 0.05)$\times 10^{-5}$}``, ``{60.7 $\pm$ \textless{}0.1}``.  Without
    it, a tiny error written in a power of ten of its own (``5.2$\times 10^{-5}$``) widened
    a force comparison table to about 363 pt, past a one-column page.

    Examples
    --------
    >>> estimate_text("60.7", 5.2e-7, 2), estimate_text("74.3", 0.0026, 2)
    ('{60.7 $\\pm$ \\textless{}0.1}', '{74.3 $\\pm$ 0.3}')
    >>> estimate_text("1.23e-05", 4.6e-7)
    '{(1.23 $\\pm$ 0.05)$\\times 10^{-5}$}'
    """
    parts = estimate_parts(value, stderr, shift)
    if parts is None:
        return f"{{{latex_number(value)}}}"
    number, error, below, power = parts
    if power is None and number == "0":
        return f"{{0 $\\pm$ {latex_number(error)}}}"
    shown = (r"\textless{}" if below else "") + error
    body = f"{'$-$' if number.startswith('-') else ''}{number.lstrip('-')} $\\pm$ {shown}"
    if power is not None:
        return f"{{({body})$\\times 10^{{{power}}}$}}"
    return f"{{{body}}}"


def latex_cell(cell: Cell, digits: int, siunitx: bool = False) -> str:
    r"""A cell: a number as :func:`latex_number` writes it; anything else braced.

    A braced cell is text to an ``S`` column of siunitx and prints as it is in an ``r``
    column: an estimate with its standard error (``{12.3 $\pm$ 0.1}``,
    :func:`estimate_text`), the infinities, ``n/a`` and ``empty``.
    """
    number = cell.number(digits)
    if cell.has_error():
        return estimate_text(number, cell.stderr, cell.shift)
    if number in ("inf", "-inf"):
        return r"{$\infty$}" if number == "inf" else r"{$-\infty$}"
    if _NUMBER.fullmatch(number):
        return latex_number(number, siunitx)
    return "{" + escape_latex(number, "cell") + "}"


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
#: The gap on each side of a column [pt] (``\tabcolsep``).
TABCOLSEP = 4.0
#: The options of an ``S`` column whose rows are unlike quantities (a row per score):
#: siunitx formats each number (its minus, its power of ten) and sets it flush right.
UNALIGNED = "table-alignment-mode=none,table-number-alignment=right"


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


def _size(body_lines: int) -> str:
    return r"\small" if body_lines <= SMALL_ROWS else r"\footnotesize"


# ---- widths ------------------------------------------------------------------------------

#: Widths of Computer Modern Roman characters [em] (cmr10.tfm); others count 0.5 em.
_EM = {
    **dict.fromkeys("!',.:;[]`il", 0.2778),
    **dict.fromkeys("fj", 0.3056),
    "-": 0.3333,
    " ": 0.3333,
    "I": 0.3611,
    **dict.fromkeys("()t", 0.3889),
    "r": 0.3917,
    "s": 0.3944,
    **dict.fromkeys("cez", 0.4444),
    **dict.fromkeys("?", 0.4722),
    "J": 0.5139,
    **dict.fromkeys("kqvxy", 0.5278),
    **dict.fromkeys("Sbdhnpu", 0.5556),
    "Z": 0.6111,
    "L": 0.625,
    "F": 0.6528,
    **dict.fromkeys("EP", 0.6806),
    "B": 0.7083,
    **dict.fromkeys("CTw", 0.7222),
    "R": 0.7361,
    **dict.fromkeys("AHNUVXY", 0.75),
    "D": 0.7639,
    **dict.fromkeys("&+=@KOQ<>", 0.7778),
    "G": 0.7847,
    **dict.fromkeys("#%m", 0.8333),
    "M": 0.9167,
    "W": 1.0278,
    "|": 0.2778,
}
#: Widths [em] of the commands a table writes (the glyph each prints).
_COMMAND_EM = {
    "times": 0.7778,
    "pm": 0.7778,
    "infty": 1.0,
    "textless": 0.7778,
    "textgreater": 0.7778,
    "textbar": 0.2778,
    "textbackslash": 0.5,
    "textdegree": 0.4,
    "itshape": 0.0,
    "tilde": 0.0,
    "max": 1.5,
    "min": 1.3,
}
#: Points per em of each size of the article class at 10 pt (cmr10, cmr9, cmr8: the
#: smaller designs are relatively wider).
SIZE_EM = {r"\normalsize": 10.0, r"\small": 9.25, r"\footnotesize": 8.5}
_TOKEN = re.compile(r"\$[^$]*\$|\\[A-Za-z]+\*?(?:\{\})?|\\.|[{}]|.", re.S)
_MATH_TOKEN = re.compile(r"\^\{[^{}]*\}|\^.|_\{[^{}]*\}|_.|\\[A-Za-z]+|\\.|[{} ]|.", re.S)


def _math_em(tex: str) -> float:
    width = 0.0
    for token in _MATH_TOKEN.findall(tex):
        if token[0] in "^_":
            width += 0.7 * _math_em(token[1:].strip("{}"))
        elif token.startswith("\\"):
            width += _COMMAND_EM.get(token[1:], 0.5 if token[1:].isalpha() else 0.3)
        elif token in "+-=":
            width += 0.7778
        elif token not in "{} ":
            width += _EM.get(token, 0.5)
    return width


def text_width(tex: str) -> float:
    """The estimated width [em] of one line of LaTeX text (as a table cell holds).

    From the widths of Computer Modern; mathematics counted symbol by symbol, super- and
    subscripts at 70 %.  An estimate, within a few percent for the tables polyell writes.
    """
    width = 0.0
    for token in _TOKEN.findall(tex):
        if token.startswith("$"):
            width += _math_em(token[1:-1])
        elif token.startswith("\\"):
            name = token[1:].removesuffix("{}")
            if name.isalpha():
                width += _COMMAND_EM.get(name, 0.5)
            elif name == " ":
                width += 0.3333
            elif name == ",":
                width += 0.1667
            else:
                width += _EM.get(name, 0.5)
        elif token not in "{}":
            width += _EM.get(token, 0.5)
    return width


def table_width(lines: Sequence[str]) -> float:
    r"""The estimated width [pt] of a table float as :func:`latex_tables` writes it.

    Parameters
    ----------
    lines : sequence of str
        The float's lines (``\begin{table}`` to ``\end{table}``).

    Returns
    -------
    float
        The tabular's natural width: each column's widest cell plus ``\tabcolsep`` on
        either side, widened where a spanning header or a posture line is wider.
    """
    given = lines
    rows = list(given) if isinstance(given, Sequence) and not isinstance(given, str) else []
    start = next(
        (k for k, line in enumerate(rows) if str(line).startswith(r"\begin{tabular}{")), None
    )
    if start is None or not all(isinstance(line, str) for line in rows):
        raise InputError(
            "lines",
            "the lines (str) of a table float, one of them \\begin{tabular}{...}",
            f"{type(given).__name__} {given!r}"[:120],
            "pass the float's text split in lines, e.g. table_width(latex.splitlines())",
        )
    lines = rows
    size = next((line for line in lines if line in SIZE_EM), r"\normalsize")
    em = SIZE_EM[size]
    spec = re.findall(r"S\[[^\]]*\]|[lrcS]", lines[start][len(r"\begin{tabular}{") : -1])
    aligned = [column.startswith("S[table-format=") for column in spec]
    widths = [0.0] * len(spec)
    spans: list[tuple[int, int, float]] = []
    for line in lines[start + 1 :]:
        if line.startswith((r"\toprule", r"\midrule", r"\bottomrule", r"\cmidrule", r"\end")):
            continue
        cells = re.split(r"(?<!\\)&", line.removesuffix(r" \\").removeprefix("{}"))
        column = 0
        for cell in cells:
            cell = cell.strip()
            multi = _MULTICOLUMN.fullmatch(cell)
            if multi is not None:
                span = int(multi.group(1))
                spans.append((column, span, _cell_em(multi.group(2))))
                column += span
                continue
            if column < len(widths) and not (aligned[column] and _bare(cell)):
                widths[column] = max(widths[column], _cell_em(cell))
            column += 1
    for j, column in enumerate(spec):  # siunitx reserves its table-format's width
        widths[j] = max(widths[j], _format_em(column))
    total = [w * em * ESTIMATE_MARGIN + 2 * TABCOLSEP for w in widths]
    for first, span, content in spans:  # a spanning cell wider than its columns widens them
        inner = content * em + (0.0 if span == len(spec) else 2 * TABCOLSEP)
        covered = sum(total[first : first + span])
        if inner > covered:
            total[first + span - 1] += inner - covered
    return sum(total)


#: The estimates run about 1 % short of pdfLaTeX's widths (kerning, rounding): scaled up.
#: Measured against pdfLaTeX for the default and transposed tables of the Panda and the
#: paper's arm, ``r`` and ``S`` columns: within 2 % (tests/comparison/test_paper_tables.py).
ESTIMATE_MARGIN = 1.01
_FORMAT = re.compile(r"S\[table-format=(-?)([0-9]+)\.([0-9]+)(?:e(-?)([0-9]+))?\]")


def _bare(cell: str) -> bool:
    """A bare number of an ``S`` column (its width is the column format's)."""
    return _NUMBER.fullmatch(cell.strip()) is not None


def _format_em(column: str) -> float:
    """The width [em] siunitx reserves for an ``S`` column's ``table-format`` (0 for others)."""
    match = _FORMAT.fullmatch(column)
    if match is None:
        return 0.0
    sign, integer, decimals, exponent_sign, exponent = match.groups()
    width = 0.7778 * bool(sign) + 0.5 * int(integer)
    width += 0.2778 + 0.5 * int(decimals) if int(decimals) else 0.0
    if exponent:  # "\times 10^{-ee}" between medium spaces
        width += 0.4444 + 0.7778 + 1.0 + 0.7 * (0.7778 * bool(exponent_sign) + 0.5 * int(exponent))
    return width


_MULTICOLUMN = re.compile(r"\\multicolumn\{(\d+)\}\{(?:[^{}]|\{\})*\}\{(.*)\}")
_STACK = re.compile(r"\{?\\begin\{tabular\}\[b\]\{@\{\}[lcr]@\{\}\}(.*)\\end\{tabular\}\}?")


def _cell_em(cell: str) -> float:
    if _bare(cell) and "e" in cell:  # a number siunitx typesets: "\times" between spaces
        return text_width(latex_number(cell.strip())) + 0.4444
    if _bare(cell):
        return text_width(latex_number(cell.strip()))
    stack = _STACK.fullmatch(cell)
    if stack is not None:
        return max(text_width(line) for line in stack.group(1).split(r"\\{}"))
    if cell.startswith("{") and cell.endswith("}"):
        cell = cell[1:-1]
    return text_width(cell)


# ---- siunitx -----------------------------------------------------------------------------


def _table_format(cells: Sequence[str]) -> str:
    """The ``table-format`` of siunitx for a column's bare numbers: ``-3.2e-1`` (sign, digits)."""
    sign = integer = decimals = exponent = 0
    negative_exponent = False
    for cell in cells:
        match = _NUMBER.fullmatch(cell)
        if match is None:
            continue
        minus, mantissa, fraction, power = match.groups()
        sign = max(sign, len(minus))
        integer = max(integer, len(mantissa.partition(".")[0]))
        decimals = max(decimals, len(fraction or ""))
        if power is not None:
            negative_exponent |= power.startswith("-")
            exponent = max(exponent, len(str(abs(int(power)))))
    text = f"{'-' if sign else ''}{max(integer, 1)}.{decimals}"
    if exponent:
        text += f"e{'-' if negative_exponent else ''}{exponent}"
    return text


# ---- tables ------------------------------------------------------------------------------


def at_posture(text: str, posture: str) -> str:
    """A caption naming its posture: ``Limits.`` -> ``Limits at posture ready.``.

    The caption's final period moves after the posture; a caption with a comma gets
    ``, at posture ready.`` (its last clause is not read as the posture's).

    Examples
    --------
    >>> at_posture("Limits.", "ready"), at_posture("Limits of x, y and z", "low")
    ('Limits at posture ready.', 'Limits of x, y and z, at posture low.')
    """
    body = text.rstrip()
    body = body[:-1] if body.endswith(".") else body
    return f"{body}{',' if ',' in body else ''} at posture {posture}."


def _caption_tex(caption: LabelText, title: str) -> str:
    latex = caption.latex if caption.latex is not None else escape_latex(caption.plain, "caption")
    if title:
        latex = at_posture(latex, escape_latex(title, "posture"))
    return latex


def _table(
    table: PrintTable,
    digits: int,
    caption: LabelText | None,
    label: str | None,
    siunitx: bool,
    size: str | None = None,
) -> list[str]:
    grouped = table.grouped and len(table.stub) > 1
    postures = len({labels[0].plain for labels, _ in table.rows}) if grouped else 0
    lines = [
        r"\begin{table}",
        r"\centering",
        size or _size(len(table.rows) + postures),
        rf"\setlength{{\tabcolsep}}{{{TABCOLSEP:g}pt}}",
    ]
    if caption is not None:
        lines.append(rf"\caption{{{_caption_tex(caption, table.title)}}}")
    if label is not None:
        lines.append(rf"\label{{{check_latex_label(label)}}}")
    stub = table.stub[1:] if grouped else table.stub
    s, c = len(stub), len(table.columns)
    body = [[latex_cell(cell, digits, siunitx) for cell in cells] for _, cells in table.rows]
    if siunitx and table.mixed:  # formatted, not aligned: rows of unlike quantities
        number_spec = f"S[{UNALIGNED}]" * c
    elif siunitx:
        formats = [_table_format([row[j] for row in body]) for j in range(c)]
        number_spec = "".join(f"S[table-format={f}]" for f in formats)
    else:
        number_spec = "r" * c
    lines += [rf"\begin{{tabular}}{{{'l' * s}{number_spec}}}", r"\toprule"]

    def head(text: str) -> str:  # siunitx must not parse a header
        return "{" + text + "}" if siunitx else text

    if table.groups:
        spans, rules, start = [], [], s + 1
        for group, span in table.groups:
            spans.append(rf"\multicolumn{{{span}}}{{c}}{{{_stacked(group, 'c')}}}")
            rules.append(rf"\cmidrule(lr){{{start}-{start + span - 1}}}")
            start += span
        lines.append(_row([""] * s + spans))
        lines.append(" ".join(rules))
    header = [_stacked(h, "l") for h in stub] + [head(_stacked(h, "r")) for h in table.columns]
    lines += [_row(header), r"\midrule"]
    previous: tuple[str, ...] = ()
    for (labels, _), cells in zip(table.rows, body, strict=True):
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
        lines.append(_row(shown + cells))
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return lines


_KEY = re.compile(r"[^A-Za-z0-9:._/+-]")


def _check_caption(caption: object) -> LabelText | None:
    if caption is None:
        return None
    if isinstance(caption, tuple):
        plain, latex = caption
        latex = None if latex is None else check_markup("caption", latex)
        return LabelText(check_text("caption", plain), latex)
    return LabelText(check_text("caption", caption))


def latex_tables(
    tables: Sequence[PrintTable],
    digits: int,
    caption: str | tuple[str, str | None] | None = None,
    label: str | None = None,
    *,
    siunitx: bool = False,
    text_width: float | None = None,
    name: tuple[str, str] = ("Table", "tab:table"),
) -> str:
    r"""The tables as LaTeX ``table`` floats, one after the other.

    Parameters
    ----------
    tables : sequence of PrintTable
    digits : int
        Significant digits.
    caption : str or (str, str), optional
        Plain text (escaped), or ``(plain, latex)`` with the LaTeX written as is; a table
        of one posture among several adds ``at posture <posture>`` (:func:`at_posture`).
    label : str, optional
        A ``\label`` key; a table of one posture among several adds ``-<posture>``
        (characters a key cannot hold become ``-``).
    siunitx : bool, optional
        ``S`` columns (bare numbers, braced headers and text), or ``r`` columns.
    text_width : float, optional
        The page's text width [pt]: a table estimated wider in ``\small`` is set in
        ``\footnotesize``, and one wider still is written with a ``UserWarning`` naming
        both widths.  None: no check (the size follows the number of rows alone).
    name : (str, str), optional
        The caption and the label key of a table of one posture among several when none
        is given (``("Directional limits", "tab:limits")``): each such float names its
        posture in both, ``Directional limits at posture ready.``, ``tab:limits-ready``.

    A combined table of several postures longer than :data:`PAGE_LINES` body lines
    (three postures of five directions in the directional-limits table) is written as
    one float per posture, as ``split="posture"`` would: one float cannot be taller than
    a page.  Each of them names its posture in its caption and label.
    """
    if label is not None:
        check_latex_label(label)
    checked = _check_caption(caption)
    tables = [part for table in tables for part in _page_parts(table)]
    several = len(tables) > 1 and any(table.title for table in tables)
    if several:  # every float names its posture, whether a caption or label was given
        checked = checked if checked is not None else LabelText(name[0])
        label = label if label is not None else check_latex_label(name[1])
    parts = []
    for table in tables:
        own_label = label
        if label is not None and len(tables) > 1:
            own_label = f"{label}-{_KEY.sub('-', table.title)}"[:200]
        lines = _table(table, digits, checked, own_label, siunitx)
        if text_width is not None:
            if r"\small" in lines[:3] and table_width(lines) > text_width:  # a size smaller
                lines = _table(table, digits, checked, own_label, siunitx, r"\footnotesize")
            _check_width(lines, text_width, own_label, checked, table.title)
        parts.append("\n".join(lines) + "\n")
    return "\n".join(parts)


def _check_width(
    lines: list[str], width: float, label: str | None, caption: LabelText | None, title: str
) -> None:
    """Warn where a table is estimated wider than the text width (it would overflow)."""
    found = table_width(lines)
    if found <= width:
        return
    if label:
        name = f"'{label}'"
    elif caption is not None:
        name = f"captioned {caption.plain[:40]!r}" + ("..." if len(caption.plain) > 40 else "")
    else:
        name = f"of {title!r}" if title else "without a label or caption"
    warnings.warn(
        f"The LaTeX table {name} is about {found:.0f} pt wide, {found - width:.0f} pt wider "
        f"than the text width {width:g} pt: it will overflow the page. Fix: leave out sets "
        "or scores (TableLayout(sets=..., scores=...); a study's [output] sets, scores), "
        "shorten labels (labels=...), keep the default orientation (transpose=False), or set "
        "text_width to your page's (None, a study's text_width = false: no check).",
        TableWidthWarning,
        stacklevel=_outside_polyell(),
    )


def _outside_polyell() -> int:
    """The ``stacklevel`` of the first caller outside polyell (where a warning points)."""
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep
    frame, level = sys._getframe(1), 1  # the warning's caller (level 1), then its callers
    while frame.f_back is not None and os.path.abspath(frame.f_code.co_filename).startswith(
        package
    ):
        frame, level = frame.f_back, level + 1
    return level
