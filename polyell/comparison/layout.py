"""How a printed table is laid out: which sets and scores, which way round, how many digits.

One small frozen value, :class:`TableLayout`, shared by the API and by a study's
``[output]`` table; the table writers read it.
"""

from __future__ import annotations

from dataclasses import dataclass
from difflib import get_close_matches
from typing import Literal

from polyell.comparison.candidates import BUILT_IN_KINDS, CANDIDATE_NAME
from polyell.errors import InputError
from polyell.validation import _describe, check_integer

__all__ = ["LAYOUT_SETS", "LIMIT_QUANTITIES", "SPLITS", "TableLayout"]

#: The sets a table can show besides user-defined candidates: the exact polytope, both
#: ellipsoid definitions, the maximum-volume inscribed and the minimum-volume enclosing one.
LAYOUT_SETS = ("polytope", *BUILT_IN_KINDS, "static")  # "static": a force ellipsoid
#: The quantities of the directional-limits table (its columns), beside the score names of
#: the comparison table.
LIMIT_QUANTITIES = ("lower", "upper", "lower_error", "upper_error")
#: One table per posture, or one table for all postures.
SPLITS = ("posture", "combined")
#: Significant digits a table may print (a float64 holds 17).
MAX_DIGITS = 17


def _names(
    argument: str, value: object, valid: tuple[str, ...], what: str, candidates: bool = False
) -> tuple[str, ...]:
    """A non-empty tuple of distinct strings among ``valid`` (or candidate names)."""
    if isinstance(value, str) or not isinstance(value, list | tuple) or not value:
        raise InputError(argument, f"a non-empty list of {what}", _describe(value))
    for item in value:
        if not isinstance(item, str) or (
            item not in valid and not (candidates and CANDIDATE_NAME.fullmatch(item))
        ):
            close = get_close_matches(str(item), valid, n=1)
            raise InputError(
                argument,
                f"{what} among {list(valid)}" + (" or candidate names" if candidates else ""),
                _describe(item),
                f"did you mean {close[0]!r}?" if close else "",
            )
    repeated = sorted({item for item in value if list(value).count(item) > 1})
    if repeated:
        raise InputError(argument, f"distinct {what}", f"{repeated} more than once")
    return tuple(value)


@dataclass(frozen=True)
class TableLayout:
    """The layout of a comparison or directional-limits table.

    Parameters
    ----------
    sets : tuple of str, optional
        The sets shown, in this order: among ``"polytope"``, ``"chiacchio"``,
        ``"yoshikawa"``, ``"mvie"``, ``"outer"`` and candidate names (lower-case
        identifiers); ``None``: every set the comparison holds.
    scores : tuple of str, optional
        The quantities shown: names of :data:`polyell.SCORE_NAMES` choose the rows of the
        comparison table, :data:`LIMIT_QUANTITIES` the columns of the directional-limits
        table; a table none of whose quantities is listed shows its defaults.  ``None``: the
        defaults of both.
    transpose : bool, optional
        Swap each table's default orientation: the comparison table has sets as columns
        and scores as rows, the directional-limits table sets as rows (under each posture
        and direction) and its limits and errors as columns.
    split : {"combined", "posture"}, optional
        One table for all postures, or one table per posture.
    digits : int, optional
        Significant digits of every number, 1 to 17.
    percent : bool, optional
        Fractions (coverage, errors) as percentages (True) or as fractions (False).

    Raises
    ------
    InputError
        If a field has the wrong type or value (the message names it: ``layout.digits``).

    Examples
    --------
    >>> from polyell.comparison.layout import TableLayout
    >>> TableLayout(sets=("polytope", "chiacchio"), digits=4).percent
    True
    """

    sets: tuple[str, ...] | None = None
    scores: tuple[str, ...] | None = None
    transpose: bool = False
    split: Literal["posture", "combined"] = "combined"
    digits: int = 3
    percent: bool = True

    def __post_init__(self) -> None:
        if self.sets is not None:
            object.__setattr__(
                self, "sets", _names("layout.sets", self.sets, LAYOUT_SETS, "set names", True)
            )
        if self.scores is not None:
            from polyell.comparison.comparison import SCORE_NAMES  # (it imports this module)

            valid = (*SCORE_NAMES, *LIMIT_QUANTITIES)
            scores = _names("layout.scores", self.scores, valid, "score names")
            object.__setattr__(self, "scores", scores)
        for name in ("transpose", "percent"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"layout.{name}", "True or False", _describe(getattr(self, name)))
        if self.split not in SPLITS:
            close = get_close_matches(str(self.split), SPLITS, n=1)
            raise InputError(
                "layout.split",
                "'posture' (one table per posture) or 'combined' (one table)",
                _describe(self.split),
                f"did you mean {close[0]!r}?" if close else "",
            )
        check_integer("layout.digits", self.digits, 1, MAX_DIGITS)
