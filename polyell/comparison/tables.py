r"""Paper-ready tables of scores: Markdown and LaTeX (booktabs), rounded, with units.

Every string that reaches a table (captions, titles, ellipsoid and candidate names, row
labels, units, cells) is plain text, escaped in one place: :func:`escape_latex` for LaTeX,
:func:`escape_markdown` for Markdown.  Only the fixed LaTeX labels of :data:`SCORE_ROWS`
are written as markup.  A LaTeX table needs ``\usepackage{booktabs}``; it is UTF-8 text
(pdfLaTeX's default input encoding; LuaLaTeX and XeLaTeX take any character).
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Literal

import numpy as np

from polyell.errors import InputError

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "ELLIPSOID_LABELS",
    "PERCENT_SCORES",
    "SCORE_ROWS",
    "check_latex_label",
    "check_text",
    "ellipsoid_label",
    "escape_latex",
    "escape_markdown",
    "format_scores_table",
    "latex_unit",
    "render_table",
    "score_display",
]

#: Column headers of the ellipsoids.
ELLIPSOID_LABELS = {
    "chiacchio": "new (eq. 32/38)",
    "yoshikawa": "classic (eq. 27)",
    "mvie": "MVIE",
    "outer": "outer (min. volume)",
}


def ellipsoid_label(kind: str) -> str:
    """The column header of an ellipsoid (plain text); a candidate's is its name."""
    return ELLIPSOID_LABELS.get(kind, kind)


#: Characters with a meaning in LaTeX text, and how each is written to print as itself
#: (``<``, ``>`` and ``|`` print other glyphs in the default OT1 font encoding).
_LATEX_SPECIAL = {
    "\\": r"\textbackslash{}",
    "{": r"\{",
    "}": r"\}",
    "$": r"\$",
    "&": r"\&",
    "%": r"\%",
    "#": r"\#",
    "_": r"\_",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
    "<": r"\textless{}",
    ">": r"\textgreater{}",
    "|": r"\textbar{}",
    "±": r"$\pm$",
    "\N{MULTIPLICATION SIGN}": r"$\times$",
}
# Greek letters as math symbols, so that names like "tau_max" typed as Greek compile with
# pdfLaTeX too (its UTF-8 support has no Greek); other characters are written as UTF-8.
_GREEK = "alpha beta gamma delta epsilon zeta eta theta iota kappa lamda mu nu xi pi rho sigma "
_GREEK += "tau upsilon phi chi psi omega"
for _name in _GREEK.split():
    _command = "lambda" if _name == "lamda" else _name
    _LATEX_SPECIAL[unicodedata.lookup(f"GREEK SMALL LETTER {_name}")] = rf"$\{_command}$"
    if _name in ("gamma", "delta", "theta", "lamda", "xi", "pi", "sigma", "upsilon", "phi"):
        _LATEX_SPECIAL[unicodedata.lookup(f"GREEK CAPITAL LETTER {_name}")] = (
            rf"$\{_command.capitalize()}$"
        )
for _name in ("psi", "omega"):
    _LATEX_SPECIAL[unicodedata.lookup(f"GREEK CAPITAL LETTER {_name}")] = (
        rf"$\{_name.capitalize()}$"
    )
_LATEX_SPECIAL["\N{MICRO SIGN}"] = r"$\mu$"
_LATEX_SPECIAL["\N{DEGREE SIGN}"] = r"\textdegree{}"
_LATEX_SPECIAL_RE = re.compile("|".join(re.escape(c) for c in _LATEX_SPECIAL))
_WHITESPACE = re.compile(r"\s+")


def check_text(argument: str, text: object) -> str:
    """Check text written into a table or a file header; whitespace runs become one space.

    Line breaks and tabs are collapsed, so one string stays on one line (one cell, one
    header line).

    Raises
    ------
    InputError
        For a non-string, for control characters other than whitespace, and for
        characters UTF-8 cannot encode (lone surrogates): none of them can be printed.
    """
    if not isinstance(text, str):
        raise InputError(argument, "a string", type(text).__name__)
    text = _WHITESPACE.sub(" ", text)
    bad = sorted({c for c in text if unicodedata.category(c) in ("Cc", "Cs")})
    if bad:
        raise InputError(
            argument,
            "printable text",
            f"{text[:60]!r} with the control or surrogate characters {bad}",
            "remove them.",
        )
    return text


def escape_latex(text: object, argument: str = "text") -> str:
    r"""Plain text as LaTeX that prints it: ``coverage [%]`` -> ``coverage [\%]``.

    Every character with a meaning in LaTeX (``\ { } $ & % # _ ~ ^ < > |``) is written as
    the command that prints it, so no user string can end a cell, start a comment or run
    a command (``\input{...}`` prints as text).  Whitespace runs become one space.

    Raises
    ------
    InputError
        Through :func:`check_text`.
    """
    clean = check_text(argument, text)
    return _LATEX_SPECIAL_RE.sub(lambda match: _LATEX_SPECIAL[match.group()], clean)


def escape_markdown(text: object, argument: str = "text") -> str:
    r"""Plain text as one Markdown table cell: ``|`` and ``\`` escaped, one line."""
    clean = check_text(argument, text)
    return clean.replace("\\", "\\\\").replace("|", r"\|")


_LABEL = re.compile(r"[A-Za-z0-9:._/+-]{1,200}")


def check_latex_label(label: object) -> str:
    r"""Check the key of a LaTeX ``\label``: letters, digits and ``: . _ / + -``."""
    if not isinstance(label, str) or not _LABEL.fullmatch(label):
        raise InputError(
            "label",
            "a LaTeX label key of letters, digits and ': . _ / + -' (up to 200)",
            repr(label),
            "use a key such as 'tab:scores'.",
        )
    return label


_POWER = re.compile(r"\^(-?[0-9]+|[A-Za-z])")


def latex_unit(unit: object, power: str = "1") -> str:
    r"""A unit as LaTeX text, its powers as superscripts: ``m/s^2`` -> ``m/s$^{2}$``.

    ``power`` other than ``"1"`` raises the whole unit: ``(m/s$^{2}$)$^{3}$``.
    """
    text = check_text("unit", unit)
    parts = _POWER.split(text)  # text, power, text, power, ..., text
    written = "".join(
        escape_latex(part, "unit") if i % 2 == 0 else f"$^{{{part}}}$"
        for i, part in enumerate(parts)
    )
    return written if power == "1" else f"({written})$^{{{power}}}$"


def _significant(value: float) -> str:
    return f"{value:.4g}"


def _percent(value: float) -> str:
    return f"{round(100.0 * value, 2) + 0.0:.2f}"  # + 0.0: a rounded -0.0 shows as 0.00


def _count(value: float) -> str:
    return f"{int(value)}"


#: (score, plain-text label, LaTeX markup of that label, formatter, standard-error column
#: or None).  ``{u}`` stands for the volume unit (escaped where it is filled in).
SCORE_ROWS: tuple[tuple[str, str, str, Callable[[float], str], str | None], ...] = (
    ("dimension", "dimension r", "dimension $r$", _count, None),
    ("volume", "volume [{u}]", "volume [{u}]", _significant, None),
    ("inscribed_scale", "inscribed scale", "inscribed scale", _significant, None),
    ("enclosing_scale", "enclosing scale", "enclosing scale", _significant, None),
    ("coverage", "coverage [%]", r"coverage [\%]", _percent, "coverage_stderr"),
    ("overreach", "overreach [%]", r"overreach [\%]", _percent, "overreach_stderr"),
    ("mvie_ratio", "volume / MVIE volume", "volume / MVIE volume", _significant, None),
    ("outer_ratio", "volume / outer volume", "volume / outer volume", _significant, None),
    (
        "direction_error_mean",
        "direction error, mean [%]",
        r"dir.\ error, mean [\%]",
        _percent,
        None,
    ),
    ("direction_error_max", "direction error, max [%]", r"dir.\ error, max [\%]", _percent, None),
    ("direction_error_rms", "direction error, RMS [%]", r"dir.\ error, RMS [\%]", _percent, None),
    ("direction_bias", "direction bias [%]", r"dir.\ bias [\%]", _percent, None),
    ("feasibility_mismatch", "feasibility mismatches", "feasibility mismatches", _count, None),
    (
        "witness_torque_max",
        "witness max abs(tau_n)",
        r"witness $\max \|\tilde\tau\|_\infty$",
        _significant,
        None,
    ),
)


#: Scores shown in percent wherever they are shown (tables, summaries, figures); the
#: data (Scores, CSV, Parquet, JSON) keep them as fractions.
PERCENT_SCORES = frozenset(row[0] for row in SCORE_ROWS if row[3] is _percent)


def score_display(score: str) -> tuple[str, float]:
    """The label and the factor a score is displayed with: ``("coverage [%]", 100.0)``."""
    name = score.replace("_", " ")
    return (f"{name} [%]", 100.0) if score in PERCENT_SCORES else (name, 1.0)


def _cell(row: pd.Series, score: str, fmt: Callable[[float], str], stderr: str | None) -> str:
    r"""One cell as plain text (``±`` is written as ``$\pm$`` in LaTeX)."""
    if not bool(row.get("defined", True)):
        return "n/a"
    try:
        value = float(row[score])
        error = float(row[stderr]) if stderr is not None else 0.0
    except (KeyError, TypeError, ValueError):
        raise InputError(
            "frame", f"a number in the column {score!r}", repr(row.get(score))[:60]
        ) from None
    if not np.isfinite(value):
        return "n/a" if np.isnan(value) else ("inf" if value > 0 else "-inf")
    text = fmt(value)
    if error > 0 and np.isfinite(error):
        text += f" ± {fmt(error)}"
    return text


def format_scores_table(
    frame: pd.DataFrame,
    dimension: int | None,
    style: Literal["markdown", "latex"],
    *,
    unit: str = "m/s^2",
    caption: str | None = None,
    label: str | None = None,
) -> str:
    """Render scores with one column per ellipsoid and one row per score.

    Parameters
    ----------
    frame : DataFrame
        Scores, indexed by ellipsoid kind, as from ``Comparison.to_frame``.
    dimension : int or None
        Dimension r of the polytope (the power of the volume unit); None for a table
        mixing dimensions (the unit is then written with the power ``r``).
    style : {"markdown", "latex"}
    unit : str, optional
        The acceleration unit.
    caption, label : str, optional
        LaTeX caption and label.
    """
    unit = check_text("unit", unit)
    power = "r" if dimension is None else str(dimension)
    volume_unit = unit if power == "1" else f"({unit})^{power}"
    names = [plain.format(u=volume_unit) for _, plain, _, _, _ in SCORE_ROWS]
    markup = {
        name: row[2].format(u=latex_unit(unit, power))
        for name, row in zip(names, SCORE_ROWS, strict=True)
    }
    cells = [
        [_cell(record, score, fmt, stderr) for _, record in frame.iterrows()]
        for score, _, _, fmt, stderr in SCORE_ROWS
    ]
    import pandas as pd

    columns = [ellipsoid_label(str(kind)) for kind in frame.index]
    table = pd.DataFrame(cells, index=names, columns=columns, dtype=object)
    return render_table(table, style, caption, label, markup=markup)


def render_table(
    table: pd.DataFrame,
    style: Literal["markdown", "latex"],
    caption: str | None = None,
    label: str | None = None,
    *,
    markup: Mapping[str, str] | None = None,
) -> str:
    """Render a table of preformatted strings: Markdown, or LaTeX with booktabs rules.

    The index is the first (left-aligned) column, every other column is right-aligned.
    Every header, row label, cell and the caption are plain text, escaped here (the one
    place tables are escaped); ``markup`` maps a row label to trusted LaTeX written instead.

    Parameters
    ----------
    table : DataFrame
        Strings (or values shown with ``str``); index: the row labels.
    style : {"markdown", "latex"}
    caption : str, optional
        LaTeX caption (plain text, escaped); Markdown tables have none.
    label : str, optional
        LaTeX label key (:func:`check_latex_label`).
    markup : mapping of str to str, optional
        LaTeX of some row labels (the fixed score labels), written as is.

    Raises
    ------
    InputError
        For a style other than the two, a caption or label that cannot be written, or text
        with control characters (:func:`check_text`).
    """
    if style not in ("markdown", "latex"):
        raise InputError("style", "'markdown' or 'latex'", repr(style))
    header = ["score" if style == "markdown" else "", *map(str, table.columns)]
    body = [
        [str(name), *map(str, values)]
        for name, values in zip(table.index, table.to_numpy().tolist(), strict=True)
    ]
    if style == "markdown":
        return _markdown(header, body)
    markup = markup or {}
    lines = [r"\begin{table}", r"\centering"]
    if caption is not None:
        lines.append(rf"\caption{{{escape_latex(caption, 'caption')}}}")
    if label is not None:
        lines.append(rf"\label{{{check_latex_label(label)}}}")
    lines += [rf"\begin{{tabular}}{{l{'r' * table.shape[1]}}}", r"\toprule"]
    lines.append(" & ".join(escape_latex(text, "column") for text in header) + r" \\")
    lines.append(r"\midrule")
    for name, *cells in body:
        first = markup.get(name) or escape_latex(name, "row")
        lines.append(" & ".join([first, *(escape_latex(c, "cell") for c in cells)]) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return "\n".join(lines) + "\n"


def _markdown(header: list[str], body: list[list[str]]) -> str:
    """A GitHub Markdown table, the first column left-aligned and the others right-aligned."""
    rows = [[escape_markdown(text, "cell") for text in row] for row in [header, *body]]
    widths = [max(3, *(len(row[i]) for row in rows)) for i in range(len(header))]
    rule = [":" + "-" * (widths[0] - 1)] + ["-" * (w - 1) + ":" for w in widths[1:]]
    lines = [
        "| "
        + " | ".join(
            text.ljust(width) if i == 0 else text.rjust(width)
            for i, (text, width) in enumerate(zip(row, widths, strict=True))
        )
        + " |"
        for row in rows
    ]
    lines.insert(1, "| " + " | ".join(rule) + " |")
    return "\n".join(lines) + "\n"
