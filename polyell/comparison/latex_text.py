r"""Plain text written into LaTeX and Markdown: checked, escaped, units with superscripts.

Every string that reaches a table (captions, titles, set and candidate names, row labels,
units, cells) is plain text, escaped here: :func:`escape_latex` for LaTeX,
:func:`escape_markdown` for Markdown.  Text is UTF-8 (pdfLaTeX's default input encoding;
LuaLaTeX and XeLaTeX take any character).
"""

from __future__ import annotations

import re
import unicodedata

from polyell.errors import InputError

__all__ = [
    "check_latex_label",
    "check_text",
    "escape_latex",
    "escape_markdown",
    "latex_direction",
    "latex_unit",
    "markdown_line",
    "markdown_text",
    "unit_power",
]


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
        raise InputError(
            argument,
            "a string",
            type(text).__name__,
            "pass the text as a str, e.g. 'Limits of the Panda'",
        )
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


#: An ``&`` that would start an HTML entity (``&lt;``, ``&#60;``) where Markdown is rendered.
_ENTITY = re.compile(r"&(?=#?[A-Za-z0-9]+;)")


#: Characters with a meaning inline in (GitHub) Markdown: a cell's ``|``, the escape itself,
#: emphasis, strike-through, code and maths, and a ``]`` that would close a link's text
#: (``[a](b)``, ``[a][b]``; a unit's ``[m/s^2]`` stays as it is).  Each is written with a
#: backslash, which prints it.
_MARKDOWN_SPECIAL = re.compile(r"([\\|*_~`$]|\](?=[(\[]))")
#: A line's start that makes it a heading, a quote, a list item or a rule: its marker.
_BLOCK_START = re.compile(r"^( ?\d{0,9})([#>+=.)-])")


def escape_markdown(text: object, argument: str = "text") -> str:
    r"""Plain text as one Markdown table cell or line, printed as it is.

    ``\ | * _ ~ ` $`` and a ``]`` before ``(`` or ``[`` are escaped with a backslash (no
    cell ends, no emphasis, strike-through, code, maths or link starts); ``<`` and ``>``
    are written as entities, and ``&`` where it would start one (``&lt;``): a label such
    as ``<script>`` shows as text, never as live HTML where the Markdown is rendered.
    """
    clean = check_text(argument, text)
    return markdown_text(_MARKDOWN_SPECIAL.sub(r"\\\1", clean))


def markdown_line(text: object, argument: str = "text") -> str:
    """Plain text as a Markdown paragraph of its own (a caption), printed as it is.

    :func:`escape_markdown`, and a marker that would make the line a heading, a quote, a
    list item or a rule (``# ``, ``> ``, ``- ``, ``+ ``, ``= ``, ``1. ``, ``1) ``) escaped.
    """
    return _BLOCK_START.sub(r"\1\\\2", escape_markdown(text, argument))


def markdown_text(text: str) -> str:
    """Plain text in Markdown without live HTML.

    ``<`` and ``>`` as entities (no tag opens), and ``&`` where it would start one
    (``&amp;`` shows as itself).
    """
    return _ENTITY.sub("&amp;", text).replace("<", "&lt;").replace(">", "&gt;")


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

    ``power`` other than ``"1"`` raises the whole unit: ``(m/s$^{2}$)$^{3}$``, and a
    unit of one symbol without parentheses: ``N$^{3}$``.
    """
    text = check_text("unit", unit)
    parts = _POWER.split(text)  # text, power, text, power, ..., text
    written = "".join(
        escape_latex(part, "unit") if i % 2 == 0 else f"$^{{{part}}}$"
        for i, part in enumerate(parts)
    )
    if power == "1":
        return written
    return (
        f"{written}$^{{{power}}}$" if _SIMPLE_UNIT.fullmatch(text) else f"({written})$^{{{power}}}$"
    )


#: A unit that takes a power without parentheses: one symbol (``N``, ``rad``), no ``/``,
#: space or power of its own.
_SIMPLE_UNIT = re.compile(r"[A-Za-z\N{MICRO SIGN}]+")


def unit_power(unit: str, power: str | int) -> str:
    """A unit raised to a power as plain text: ``N^3``, ``(m/s^2)^3``; ``unit`` at power 1.

    Parentheses only where the unit is compound (a ``/``, a space, a power of its own).

    Examples
    --------
    >>> unit_power("N", 3), unit_power("m/s^2", 3), unit_power("N m", "r"), unit_power("m", 1)
    ('N^3', '(m/s^2)^3', '(N m)^r', 'm')
    """
    if str(power) == "1":
        return unit
    return f"{unit}^{power}" if _SIMPLE_UNIT.fullmatch(unit) else f"({unit})^{power}"


_SIGN = re.compile(r"(?<![A-Za-z0-9])-(?=[A-Za-z0-9.])")


def latex_direction(name: object, argument: str = "direction") -> str:
    r"""A direction's name as LaTeX, its signs as math minus: ``-z`` -> ``$-$z``.

    A hyphen that starts the name or a number in it (``-xy``, ``(0.6, -0.8)``) is a sign;
    one inside a word (``pick-up``) stays a hyphen.

    Examples
    --------
    >>> latex_direction("-z"), latex_direction("[0.6, -0.8]"), latex_direction("pick-up")
    ('$-$z', '[0.6, $-$0.8]', 'pick-up')
    """
    return _SIGN.sub("$-$", escape_latex(name, argument))
