"""How a printed table is laid out: which sets and scores, which way round, how many digits.

One small frozen value, :class:`TableLayout`, shared by the API and by a study's
``[output]`` table; the table writers read it.  Besides the choice of rows and columns it
holds what a paper needs of its tables: the labels of sets and scores, captions, siunitx
``S`` columns and the page's text width the LaTeX tables are checked against.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from difflib import get_close_matches
from types import MappingProxyType
from typing import Literal

from polyell.comparison.candidates import BUILT_IN_KINDS, CANDIDATE_NAME
from polyell.comparison.labels import (
    Labels,
    LabelText,
    LabelValue,
    Quantity,
    _label_value,
    check_labels,
    label_text,
    quantity,
    resolve_labels,
)
from polyell.errors import InputError
from polyell.validation import _describe, check_integer

__all__ = [
    "CAPTION_TABLES",
    "LAYOUT_SETS",
    "LIMIT_QUANTITIES",
    "SPLITS",
    "TEXT_WIDTH",
    "TableLayout",
]

#: The sets a table can show besides user-defined candidates: the exact polytope, both
#: ellipsoid definitions, the maximum-volume inscribed and the minimum-volume enclosing one.
LAYOUT_SETS = ("polytope", *BUILT_IN_KINDS, "static")  # "static": a force ellipsoid
#: The quantities of the directional-limits table (its columns), beside the score names of
#: the comparison table: the two ends [task unit] and their errors [-], in order.
LIMIT_QUANTITIES = ("lower", "upper", "lower_error", "upper_error")
#: One table per posture, or one table for all postures.
SPLITS = ("posture", "combined")
#: Significant digits a table may print (a float64 holds 17).
MAX_DIGITS = 17
#: The tables a layout's ``captions`` may name: a points study's two, a sweep's summary and
#: a posture study's choice and its aggregate over random targets.
CAPTION_TABLES = ("comparison", "limits", "summary", "posture_choice", "posture_targets")
#: The text width [pt] of a one-column page: LaTeX's ``article`` class at 10 pt (letter or
#: A4 paper).  Two-column journals: about 240-260 pt (``\columnwidth``).
TEXT_WIDTH = 345.0
#: Widest text width accepted [pt]: about 2 m, beyond any page.
MAX_TEXT_WIDTH = 6000.0


def _names(
    argument: str, value: object, valid: tuple[str, ...], what: str, candidates: bool = False
) -> tuple[str, ...]:
    """A non-empty tuple of distinct strings among ``valid`` (or candidate names)."""
    if isinstance(value, str) or not isinstance(value, list | tuple) or not value:
        raise InputError(
            argument,
            f"a non-empty list of {what}",
            _describe(value),
            f"pass a list, e.g. [{value if isinstance(value, str) and value else valid[0]!r}]",
        )
    for item in value:
        if not isinstance(item, str) or (
            item not in valid and not (candidates and CANDIDATE_NAME.fullmatch(item))
        ):
            close = get_close_matches(str(item), valid, n=1)
            raise InputError(
                argument,
                f"{what} among {list(valid)}" + (" or candidate names" if candidates else ""),
                _describe(item),
                f"did you mean {close[0]!r}?"
                if close
                else f"use one of the names listed, e.g. {valid[0]!r}",
            )
    repeated = sorted({item for item in value if list(value).count(item) > 1})
    if repeated:
        raise InputError(
            argument,
            f"distinct {what}",
            f"{repeated} more than once",
            f"list each name once: drop the repeats of {repeated[0]!r}",
        )
    return tuple(value)


def _captions(value: object) -> Mapping[str, LabelText] | None:
    """``layout.captions``: a read-only mapping of table names to checked captions."""
    if value is None:
        return None
    if not isinstance(value, Mapping):
        raise InputError(
            "layout.captions",
            f"a mapping of table names among {list(CAPTION_TABLES)} to captions",
            _describe(value),
            'e.g. {"limits": "Limits of the Panda along x, y and z."}.',
        )
    checked = {}
    for key, caption in value.items():
        if key not in CAPTION_TABLES:
            close = get_close_matches(str(key), CAPTION_TABLES, n=1)
            raise InputError(
                "layout.captions",
                f"keys among {list(CAPTION_TABLES)}",
                _describe(key),
                f"did you mean {close[0]!r}?"
                if close
                else f"key each caption by a table name listed, e.g. {CAPTION_TABLES[1]!r}",
            )
        checked[key] = _label_value(f"layout.captions[{key!r}]", caption)
    return MappingProxyType(checked)


@dataclass(frozen=True)
class TableLayout:
    r"""The layout of a comparison or directional-limits table.

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
        defaults of both, without the columns that are zero in every row (a quantity
        listed here is shown even then).
    transpose : bool, optional
        Swap each table's default orientation: the comparison table has sets as columns
        and scores as rows, the directional-limits table sets as rows (under each posture
        and direction) and its limits and errors as columns.  Transposed, the limits
        table leaves out the polytope's errors (zero: it is the reference).
    split : {"combined", "posture"}, optional
        One table for all postures, or one table per posture.
    digits : int, optional
        Significant digits of every number, 1 to 17.
    percent : bool, optional
        Fractions (coverage, errors) as percentages (True) or as fractions (False).
    labels : str or mapping, optional
        The names of sets and scores in every format: a mapping from set names
        (``"chiacchio"``, a candidate's name) and score names (``"coverage"``,
        ``"witness_torque_max"``, ``"lower_error"``) to labels -- plain text (escaped in
        LaTeX), or a pair ``(plain, latex)`` whose LaTeX is written as is -- or a preset's
        name (``"chiacchio2000"``: the equation numbers of Chiacchio's paper, for its own
        study).  Units are added to a score's label (``[%]``).  ``None``: one name per set
        that fits any robot (:data:`~polyell.comparison.labels.SET_LABELS`).
    captions : mapping, optional
        Captions by table (``"comparison"``, ``"limits"``, ``"summary"``,
        ``"posture_choice"``, ``"posture_targets"``: :data:`CAPTION_TABLES`), plain text or
        ``(plain, latex)``, used where a table is written without an explicit caption
        (a study's files, ``write_point_tables``, ``write_posture_tables``).  ``None``:
        each writer's default, which does not start with the study's title.
    siunitx : bool, optional
        Number columns as siunitx ``S`` columns (``\usepackage{siunitx}``, version 3):
        bare numbers that siunitx typesets (its minus sign, powers of ten), every header
        and text cell braced, a column of one quantity aligned on the decimal marker.
        False: ``r`` columns, numbers written with a math minus ``$-$`` and
        powers of ten (``6.80$\times 10^{5}$``), no package beyond booktabs.
    text_width : float or None, optional
        The page's text width [pt] a LaTeX table is checked against: a wider table is
        written all the same, with a :class:`UserWarning` that names its width.  Default
        :data:`TEXT_WIDTH` (one-column ``article``); None: no check.

    Raises
    ------
    InputError
        If a field has the wrong type or value (the message names it: ``layout.digits``).

    Examples
    --------
    >>> from polyell.comparison.layout import TableLayout
    >>> TableLayout(sets=("polytope", "chiacchio"), digits=4).percent
    True
    >>> TableLayout(labels={"chiacchio": "DME"}).set_label("chiacchio")
    'DME'
    """

    sets: tuple[str, ...] | None = None
    scores: tuple[str, ...] | None = None
    transpose: bool = False
    split: Literal["posture", "combined"] = "combined"
    digits: int = 3
    percent: bool = True
    labels: Labels = field(default=None)
    captions: Mapping[str, LabelValue] | None = field(default=None)
    siunitx: bool = False
    text_width: float | None = TEXT_WIDTH

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
        for name in ("transpose", "percent", "siunitx"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(
                    f"layout.{name}",
                    "True or False",
                    _describe(getattr(self, name)),
                    f"pass a bool, e.g. pe.TableLayout({name}=True)",
                )
        if self.split not in SPLITS:
            close = get_close_matches(str(self.split), SPLITS, n=1)
            raise InputError(
                "layout.split",
                "'posture' (one table per posture) or 'combined' (one table)",
                _describe(self.split),
                f"did you mean {close[0]!r}?"
                if close
                else "pass split='posture' or split='combined'",
            )
        check_integer("layout.digits", self.digits, 1, MAX_DIGITS)
        object.__setattr__(self, "labels", check_labels(self.labels, "layout.labels"))
        object.__setattr__(self, "captions", _captions(self.captions))
        width = self.text_width
        if width is not None:
            if (
                isinstance(width, bool)
                or not isinstance(width, int | float)
                or not math.isfinite(width)
                or not 0 < width <= MAX_TEXT_WIDTH
            ):
                raise InputError(
                    "layout.text_width",
                    f"a width in pt above 0 and up to {MAX_TEXT_WIDTH:g}, or None (no check)",
                    _describe(width),
                    f"e.g. {TEXT_WIDTH:g} (one-column article) or 252 (a two-column journal).",
                )
            object.__setattr__(self, "text_width", float(width))

    def __hash__(self) -> int:
        labels = self.labels
        if isinstance(labels, Mapping):
            labels = tuple(labels.items())  # type: ignore[assignment]
        captions = tuple(self.captions.items()) if self.captions is not None else None
        fields = (self.sets, self.scores, self.transpose, self.split, self.digits)
        return hash((*fields, self.percent, labels, captions, self.siunitx, self.text_width))

    @property
    def label_map(self) -> Mapping[str, LabelText]:
        """The user's labels by set or score name (a preset expanded); empty: the defaults."""
        return resolve_labels(self.labels)

    def set_label(self, kind: str, capacity: str = "acceleration") -> str:
        """The plain label of a set in this layout's tables (the user's, else the default)."""
        return label_text(kind, capacity, self.labels).plain

    def set_text(self, kind: str, capacity: str = "acceleration") -> LabelText:
        """The label of a set in plain text and, where the user gave it, in LaTeX."""
        return label_text(kind, capacity, self.labels)

    def quantity(self, name: str, capacity: str = "acceleration") -> Quantity:
        """A score or limit quantity as this layout labels it (its unit is added apart)."""
        return quantity(name, capacity, self.labels)

    def caption(self, table: str) -> LabelText | None:
        """The user's caption of ``table`` (a name of :data:`CAPTION_TABLES`), or None."""
        if self.captions is None:
            return None
        found = self.captions.get(table)
        if found is None:
            return None
        return LabelText(*found) if isinstance(found, tuple) else LabelText(found)
