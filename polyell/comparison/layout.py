"""How a table is laid out for print: which sets and scores, orientation, split, rounding."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from polyell.errors import InputError

__all__ = ["SPLITS", "TableLayout"]

#: The values of :attr:`TableLayout.split`.
SPLITS = ("combined", "posture")
#: Significant digits a table may show: 1 up to 17 (every double round-trips at 17).
MIN_DIGITS, MAX_DIGITS = 1, 17


def _names(field: str, value: object) -> tuple[str, ...] | None:
    """None, or a non-empty tuple of distinct non-empty strings."""
    if value is None:
        return None
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise InputError(
            f"layout.{field}",
            "None (all) or a list of names",
            repr(value)[:80],
            f"write e.g. {field}=['chiacchio', 'yoshikawa'] (a list, not one string).",
        )
    names = tuple(value)
    if not names or not all(isinstance(name, str) and name for name in names):
        raise InputError(
            f"layout.{field}", "a non-empty list of non-empty strings", repr(value)[:80]
        )
    if len(set(names)) != len(names):
        raise InputError(f"layout.{field}", "distinct names", repr(value)[:80])
    return names


@dataclass(frozen=True)
class TableLayout:
    """The layout of a printed table (LaTeX, Markdown, CSV, HTML).

    Attributes
    ----------
    sets : tuple of str or None
        The sets shown, in this order: ``"polytope"`` (the directional-limits table only;
        the reference the comparison table scores against), ``"chiacchio"``,
        ``"yoshikawa"``, ``"mvie"``, ``"outer"`` and candidates' names.  None: every set
        the comparison computed.
    scores : tuple of str or None
        The quantities shown.  Names of :data:`polyell.SCORE_NAMES` choose the rows of the
        comparison table; ``"lower"``, ``"upper"``, ``"lower_error"``, ``"upper_error"``
        the columns of the directional-limits table.  A table none of whose quantities is
        listed shows its defaults.  None: the defaults of both.
    transpose : bool
        Swap each table's default orientation: the comparison table has sets as columns
        and scores as rows, the directional-limits table sets as rows (under each
        posture and direction) and its limits and errors as columns.
    split : {"combined", "posture"}
        One table for every posture, or one table per posture.
    digits : int
        Significant digits of every number shown (1 to 17); counts are whole numbers.
    percent : bool
        Shares and relative errors in percent (True) or as fractions (False).

    Raises
    ------
    InputError
        Naming the field (``layout.digits``, ...) for a value of the wrong type or range.
    """

    sets: tuple[str, ...] | None = None
    scores: tuple[str, ...] | None = None
    transpose: bool = False
    split: Literal["combined", "posture"] = "combined"
    digits: int = 3
    percent: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "sets", _names("sets", self.sets))
        object.__setattr__(self, "scores", _names("scores", self.scores))
        for field in ("transpose", "percent"):
            if not isinstance(getattr(self, field), bool):
                raise InputError(f"layout.{field}", "True or False", repr(getattr(self, field)))
        if self.split not in SPLITS:
            raise InputError(
                "layout.split",
                "'combined' (one table) or 'posture' (one table per posture)",
                repr(self.split)[:80],
            )
        digits = self.digits
        if isinstance(digits, bool) or not isinstance(digits, int):
            raise InputError("layout.digits", "a whole number of significant digits", repr(digits))
        if not MIN_DIGITS <= digits <= MAX_DIGITS:
            raise InputError(
                "layout.digits",
                f"{MIN_DIGITS} to {MAX_DIGITS} significant digits",
                repr(digits),
                "3 suits most papers; 17 shows every digit of a double.",
            )
