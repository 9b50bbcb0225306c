r"""Numbers of polyell's LaTeX tables read back as plain text, for tests/latex_check.py.

polyell writes a negative number with a math minus and a power of ten in mathematics
(``$-$6.80$\times 10^{5}$``, :func:`polyell.comparison.write_latex.latex_number`);
the parser of latex_check reads plain numbers.  :func:`plain_numbers` rewrites those two
forms only -- written independently of the code under test -- so that every other ``$``
still fails the parser's check of escapes: escaped user text never holds ``$-$`` (a user's
``$`` is written ``\$``).
"""

from __future__ import annotations

import re

from latex_check import ParsedTable, parse_table, parse_tables

#: A power of ten as polyell writes it after a mantissa.
POWER = re.compile(r"\$\\times 10\^\{(-?[0-9]+)\}\$")
#: A math minus before a number.
MINUS = re.compile(r"\$-\$(?=[0-9])")


def plain_numbers(tex: str) -> str:
    r"""``$-$6.80$\times 10^{5}$`` -> ``-6.80e5`` everywhere in ``tex``."""
    return MINUS.sub("-", POWER.sub(r"e\1", tex))


def parse(tex: str) -> ParsedTable:
    """:func:`latex_check.parse_table` of a table with polyell's typeset numbers."""
    return parse_table(plain_numbers(tex))


def parse_all(tex: str) -> list[ParsedTable]:
    """:func:`latex_check.parse_tables` of tables with polyell's typeset numbers."""
    return parse_tables(plain_numbers(tex))


def pdf_pattern(cell: str) -> str:
    r"""A regular expression for a plain cell as ``pdftotext`` reads the typeset text.

    ``-6.80e5`` is typeset with a minus sign and a multiplication sign, which pdftotext
    reads as ``\N{MINUS SIGN}6.80\N{MULTIPLICATION SIGN}105`` (the superscript inline):
    the pattern takes either minus and the power's digits after ``10``.  A cell of
    several words (``12.3 0.05``) is matched word by word.
    """
    minus = "[-\N{MINUS SIGN}]"
    words = []
    for word in cell.split():
        number = re.fullmatch(r"(-?)([0-9.]+)(?:e([+-]?)0*([0-9]+))?", word)
        if number is None:
            words.append(re.escape(word))
            continue
        sign, mantissa, power_sign, power = number.groups()
        pattern = (minus if sign else "") + re.escape(mantissa)
        if power is not None:
            pattern += r"\s*\N{MULTIPLICATION SIGN}\s*10\s*" + (minus if power_sign == "-" else "")
            pattern += power
        words.append(pattern)
    return r"\s+".join(words)
