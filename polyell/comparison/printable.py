r"""A table ready to print, whatever the format: labels, cells and how numbers are written.

The builders (:mod:`~polyell.comparison.print_scores`, :mod:`~polyell.comparison.print_limits`)
fill a :class:`PrintTable`; the writers (LaTeX, Markdown, CSV, HTML) only lay it out, so
that every format shows the same labels, units and numbers.

Numbers are rounded to significant digits in decimal, from the exact binary value: a
percentage is the fraction's digits with the decimal point moved two places (never
``100 * x`` in floating point, which could round differently or overflow).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from decimal import ROUND_HALF_EVEN, Decimal, localcontext

from polyell.comparison.labels import LabelText, Quantity
from polyell.comparison.latex_text import escape_latex, latex_direction, latex_unit, unit_power

__all__ = [
    "EMPTY",
    "MISSING",
    "REFERENCE",
    "Cell",
    "Label",
    "PrintTable",
    "decimal_text",
    "direction_label",
    "estimate_parts",
    "given_label",
    "quantity_label",
    "rounded_text",
    "text_label",
]

#: Shown where a set is undefined or a quantity cannot be computed.
MISSING = "n/a"
#: Shown where a directional limit does not exist (the line misses the set).
EMPTY = "empty"
#: Shown for the reference against itself (the polytope's own errors: 0 by definition).
REFERENCE = ""


@dataclass(frozen=True)
class Label:
    """A header or row label: plain text, its LaTeX, and the LaTeX lines of a stacked header.

    Attributes
    ----------
    plain : str
        The text Markdown, CSV and HTML show (``"lower [m/s^2]"``).
    latex : str
        The same in LaTeX (escaped, or the trusted markup of :mod:`labels`).
    lines : tuple of str
        The LaTeX split where a narrow column header may break (``"lower"``,
        ``"[m/s$^{2}$]"``); empty: one line.
    """

    plain: str
    latex: str
    lines: tuple[str, ...] = ()


def text_label(plain: str, argument: str = "label") -> Label:
    """A label of plain text (a posture's or a candidate's name): escaped for LaTeX.

    A set's label with a parenthesis (``outer (min. volume)``) may break before it.
    """
    head, sep, tail = plain.partition(" (")
    lines = (escape_latex(head, argument), escape_latex("(" + tail, argument)) if sep else ()
    return Label(plain, escape_latex(plain, argument), lines)


def direction_label(plain: str, argument: str = "directions") -> Label:
    """A direction's name as a label: its signs a math minus in LaTeX (``$-$z``)."""
    return Label(plain, latex_direction(plain, argument))


def given_label(text: LabelText, argument: str = "label") -> Label:
    """A label as a user or the defaults give it: escaped plain text, or the user's LaTeX.

    Plain text may break before a parenthesis (:func:`text_label`); the user's LaTeX is
    written on one line, as given.
    """
    if text.latex is not None:
        return Label(text.plain, text.latex)
    return text_label(text.plain, argument)


def quantity_label(quantity: Quantity, percent: bool, unit: str, power: str = "1") -> Label:
    """A quantity's label with its unit in brackets: ``coverage [%]``, ``lower [m/s^2]``.

    Parameters
    ----------
    quantity : Quantity
    percent : bool
        Shares in percent (``[%]``) or as fractions (no unit).
    unit : str
        The task's unit (``m/s^2``); used by ``"task"`` and ``"volume"`` quantities.
    power : str
        The volume's power (``"3"``, or ``"r"`` for a table mixing dimensions).
    """
    if quantity.kind == "share":
        units = ("%", r"\%") if percent else ("", "")
    elif quantity.kind == "task":
        units = (unit, latex_unit(unit))
    elif quantity.kind == "volume":
        units = (unit_power(unit, power), latex_unit(unit, power))
    else:
        units = ("", "")
    if not units[0]:
        return Label(quantity.plain, quantity.latex)
    return Label(
        f"{quantity.plain} [{units[0]}]",
        f"{quantity.latex} [{units[1]}]",
        (quantity.latex, f"[{units[1]}]"),
    )


def _exact(value: float, shift: int) -> Decimal:
    """The exact decimal value of ``value * 10**shift``."""
    with localcontext() as context:
        context.prec = 1000  # more digits than any double has
        return Decimal(value).scaleb(shift)


def _g(number: Decimal, precision: int, keep_zeros: bool = False) -> str:
    """A finite decimal as Python's ``g`` writes it: without trailing zeros, or with them.

    Fixed notation if ``1e-4 <= |x| < 10**precision``, else e-notation.  ``keep_zeros``:
    the digits of ``number`` as they are (a rounded value keeps its significant zeros).
    """
    if number == 0:
        return "0"
    if not keep_zeros:
        number = number.normalize()
    exponent = number.adjusted()
    if -4 <= exponent < precision:
        return format(number, "f")
    sign, digits, _ = number.as_tuple()
    mantissa = str(digits[0]) + ("." + "".join(map(str, digits[1:])) if len(digits) > 1 else "")
    return f"{'-' if sign else ''}{mantissa}e{exponent:+03d}"


def rounded_text(value: float, digits: int, shift: int = 0) -> str:
    """``value * 10**shift`` to ``digits`` significant digits (round half to even, exact).

    Every number shows its ``digits`` significant digits, trailing zeros included
    (``58.0``, ``1.00``, ``0.500`` for 3): a column reads at one precision, as a journal
    table does.  ``inf``, ``-inf`` and ``nan`` for non-finite values; 0 for both zeros.
    """
    if not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    exact = _exact(value, shift)
    if exact == 0:
        return "0"
    with localcontext() as context:
        context.prec = digits
        context.rounding = ROUND_HALF_EVEN
        rounded = +exact
        # exactly ``digits`` significant digits: 0.5 -> 0.500 (exact; padding only)
        context.prec = digits + 2
        rounded = rounded.quantize(Decimal(1).scaleb(rounded.adjusted() - digits + 1))
        return _g(rounded, digits, keep_zeros=True)


def decimal_text(value: float, shift: int = 0) -> str:
    """``value * 10**shift`` at full precision, exactly.

    The shortest decimal that reads back as ``value`` (``repr``), its point moved by
    ``shift`` places.
    """
    if not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if value == 0:
        return "0"
    return _g(Decimal(repr(value)).scaleb(shift), 17)


#: A number as :func:`rounded_text` writes it: sign, mantissa, fraction, exponent.
_NUMBER = re.compile(r"(-?)([0-9]+(?:\.([0-9]+))?)(?:e([+-]?[0-9]+))?")


def estimate_parts(
    value: str, stderr: float, shift: int = 0
) -> tuple[str, str, bool, int | None] | None:
    """An estimate's digits and its standard error at the value's last digit.

    ``value`` is the estimate as a table rounds it (``60.7``, ``1.23e-05``); the standard
    error ``stderr * 10**shift`` is written at most to that last digit, with at most 2
    significant digits (round half to even), and in the value's power of ten.  An error
    below half a unit of that digit is "less than one unit" (``below``): the digits shown
    are the estimate's to within rounding.  A value of 0 has no last digit: its error keeps
    2 significant digits.

    Returns
    -------
    (number, error, below, power) or None
        The value's sign and mantissa, the error's digits (in ``10**power`` where
        ``power`` is not None), whether it is an upper bound; None where ``value`` is not a
        number or the error not positive and finite.

    Examples
    --------
    >>> estimate_parts("60.7", 5.2e-7, 2), estimate_parts("1.23e-05", 4.6e-7)
    (('60.7', '0.1', True, None), ('1.23', '0.05', False, -5))
    """
    match = _NUMBER.fullmatch(value)
    error = Decimal(repr(stderr)).scaleb(shift)
    if match is None or not error.is_finite() or error <= 0:
        return None
    sign, mantissa, fraction, exponent = match.groups()
    if Decimal(mantissa) == 0:  # no last digit: the error to 2 significant digits
        return "0", rounded_text(stderr, 2, shift), False, None
    power = int(exponent) if exponent else 0
    last = power - len(fraction or "")  # the value's last digit: 10**last
    step = max(last, error.adjusted() - 1)  # at most 2 significant digits of the error
    with localcontext() as context:
        context.rounding = ROUND_HALF_EVEN
        rounded = error.quantize(Decimal(1).scaleb(step))
    if rounded == 0:
        shown = format(Decimal(1).scaleb(last - power), f".{max(power - last, 0)}f")
    else:
        shown = format(rounded.scaleb(-power), f".{max(power - step, 0)}f")
    return sign + mantissa, shown, rounded == 0, power if exponent else None


@dataclass(frozen=True)
class Cell:
    """One number of a table, as data: shown rounded, written to CSV in full.

    Attributes
    ----------
    value : float
        The quantity (a share as a fraction).
    shift : int
        Decimal places the point moves when shown: 2 for a share in percent, else 0.
    stderr : float
        Standard error of an estimate, in the units of ``value``; 0: exact.
    count : bool
        A whole number (shown without rounding).
    missing : str
        Shown where ``value`` is NaN: :data:`MISSING`, :data:`EMPTY` or :data:`REFERENCE`.
    """

    value: float
    shift: int = 0
    stderr: float = 0.0
    count: bool = False
    missing: str = MISSING

    def number(self, digits: int) -> str:
        """The value as shown (no standard error)."""
        if math.isnan(self.value):
            return self.missing
        if self.count and math.isfinite(self.value):
            return str(int(self.value))
        return rounded_text(self.value, digits, self.shift)

    def has_error(self) -> bool:
        """Whether the cell shows a standard error (estimated, finite, positive)."""
        return math.isfinite(self.value) and math.isfinite(self.stderr) and self.stderr > 0

    def text(self, digits: int) -> str:
        """The value and, if estimated, ``± error``: what Markdown and HTML show.

        The error as LaTeX writes it (:func:`estimate_parts`): ``60.7 ± 0.3``,
        ``(1.23 ± 0.05)e-05``, ``60.7 ± <0.1``.
        """
        number = self.number(digits)
        parts = estimate_parts(number, self.stderr, self.shift) if self.has_error() else None
        if parts is None:
            return number
        value, error, below, power = parts
        body = f"{value} ± {'<' if below else ''}{error}"
        return body if power is None else f"({body})e{power:+03d}"

    def exact(self) -> str:
        """The value at full precision (CSV): :func:`decimal_text`, or the missing text."""
        if math.isnan(self.value):
            return self.missing
        if self.count and math.isfinite(self.value):
            return str(int(self.value))
        return decimal_text(self.value, self.shift)


@dataclass(frozen=True)
class PrintTable:
    """A table to print.

    Attributes
    ----------
    stub : tuple of Label
        The headers of the row-label columns (``posture``, ``direction``, ``set``).
    columns : tuple of Label
        The headers of the number columns.
    rows : tuple of (tuple of Label, tuple of Cell)
        Each row's labels (one per stub column) and cells (one per number column).
    groups : tuple of (Label, int)
        Headers spanning consecutive number columns (a set over its limits), in order,
        covering every column; empty: none.
    title : str
        What the table is of (a posture's name for a table per posture); may be empty.
    grouped : bool
        Whether LaTeX prints the first stub column (the posture) as a row spanning the
        table above its rows rather than as a column (a narrower table).
    mixed : bool
        Whether each number column holds several quantities (a row per score): siunitx
        then formats its numbers without aligning them on the decimal marker, which would
        reserve the widest integer part and the longest fraction of any row.
    """

    stub: tuple[Label, ...]
    columns: tuple[Label, ...]
    rows: tuple[tuple[tuple[Label, ...], tuple[Cell, ...]], ...]
    groups: tuple[tuple[Label, int], ...] = field(default=())
    title: str = ""
    grouped: bool = False
    mixed: bool = False

    def group_of(self) -> list[str]:
        """The plain label of each number column's group ('' without groups)."""
        if not self.groups:
            return [""] * len(self.columns)
        return [label.plain for label, span in self.groups for _ in range(span)]
