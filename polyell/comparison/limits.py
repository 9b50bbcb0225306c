"""The directional-limits table: each set's interval along named directions, and its error.

One tidy row per (posture, direction, set): the polytope's interval (the truth), each
ellipsoid's, and each end's relative error against the polytope's,
``(e - p) / |p|`` (:func:`~polyell.comparison.metrics.relative_error`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.directions import DirectionSpec, resolve_directions
from polyell.comparison.layout import LIMIT_QUANTITIES
from polyell.comparison.metrics import relative_error
from polyell.errors import InputError
from polyell.validation import check_instance

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

    from polyell.comparison.comparison import Comparison
    from polyell.comparison.set_comparison import ScoredSet

__all__ = [
    "LIMIT_COLUMNS",
    "LIMIT_QUANTITIES",
    "limits_frame",
    "limits_table",
    "posture_comparisons",
    "table_sets",
]

#: Columns of :func:`limits_table` (``posture`` first in the multi-posture form).
LIMIT_COLUMNS = ("direction", "set", "defined", *LIMIT_QUANTITIES, "unit")

#: Directions as accepted per posture: one list for all, or a list per posture name.
Directions = Sequence[DirectionSpec] | Mapping[str, Sequence[DirectionSpec] | None] | None


def table_sets(comparison: ScoredSet, sets: str | Sequence[str] | None, argument: str) -> list[str]:
    """The sets of a table: ``"polytope"`` and the comparison's kinds, checked.

    None gives the polytope and every kind the comparison computed (an MVIE or outer
    ellipsoid turned off with ``mvie=False`` / ``outer=False`` is left out); one name is
    that set alone.
    """
    from polyell.comparison.set_comparison import ScoredSet  # (a circle at import time)

    check_instance("comparison", comparison, ScoredSet, "pass pe.compare(analysis).")
    available = ["polytope", *comparison.kinds]
    if sets is None:
        return [
            kind
            for kind in available
            if kind == "polytope" or "not computed" not in comparison[kind].reason
        ]
    sets = [sets] if isinstance(sets, str) else sets
    if not isinstance(sets, Sequence) or not all(isinstance(kind, str) for kind in sets):
        raise InputError(
            argument,
            f"a set's name or a list of names among {available}",
            f"{type(sets).__name__} {sets!r}"[:80],
            f"pass names from the list, e.g. {argument}=['polytope', '{available[-1]}'].",
        )
    unknown = [kind for kind in sets if kind not in available]
    if unknown:
        raise InputError(
            argument,
            f"sets among {available}",
            repr(unknown),
            f"pass names from the list, e.g. {argument}=['polytope', '{available[-1]}'].",
        )
    return list(sets)


def limits_frame(
    comparison: Comparison,
    directions: Sequence[DirectionSpec] | None = None,
    *,
    sets: Sequence[str] | None = None,
    argument: str = "directions",
) -> pd.DataFrame:
    """:meth:`Comparison.limits_table <polyell.Comparison.limits_table>` (see there)."""
    from polyell.comparison.comparison import Comparison  # (a circle at import time)

    check_instance("comparison", comparison, Comparison, "pass pe.compare(analysis).")
    found = resolve_directions(directions, comparison.analysis.task, argument)
    frame = _limit_rows(comparison, found, sets, comparison.analysis.unit())
    frame.attrs["capacity"] = comparison.analysis.capacity  # for the labels of its tables
    return frame


def _limit_rows(
    comparison: ScoredSet,
    found: Sequence[tuple[NDArray[np.float64], str]],
    sets: Sequence[str] | None,
    unit: str,
) -> pd.DataFrame:
    """The rows of a limits table: each set's interval along the ``found`` directions."""
    import pandas as pd

    kinds = table_sets(comparison, sets, "sets")
    T = np.array([vector for vector, _ in found])
    polytope = comparison.polytope.limits(T)
    columns = {}
    for kind in kinds:
        defined = kind == "polytope" or comparison[kind].defined
        if not defined:
            lo = hi = np.full(len(T), np.nan)
        elif kind == "polytope":
            lo, hi = polytope
        else:
            lo, hi = comparison.ellipsoid(kind).limits(T)
        errors = relative_error(lo, polytope.lo), relative_error(hi, polytope.hi)
        columns[kind] = (defined, lo, hi, *errors)
    rows = [
        (label, kind, defined, lo[k], hi[k], lo_error[k], hi_error[k], unit)
        for k, (_, label) in enumerate(found)
        for kind, (defined, lo, hi, lo_error, hi_error) in columns.items()
    ]
    frame = pd.DataFrame(rows, columns=list(LIMIT_COLUMNS))
    return frame.astype({quantity: float for quantity in LIMIT_QUANTITIES})


def posture_comparisons(
    comparisons: Comparison | Mapping[str, Comparison],
) -> dict[str, Comparison]:
    """Comparisons by posture name, checked; one comparison is the posture ``""``.

    Raises
    ------
    InputError
        Naming ``comparisons`` (or ``comparisons['home']``) for anything else.
    """
    from polyell.comparison.comparison import Comparison

    if isinstance(comparisons, Comparison):
        return {"": comparisons}
    if not isinstance(comparisons, Mapping) or not comparisons:
        raise InputError(
            "comparisons",
            "a Comparison or a non-empty mapping of posture name to Comparison",
            type(comparisons).__name__,
            "call pe.compare at each posture, e.g. {'home': cmp1, 'reach': cmp2}.",
        )
    for name, comparison in comparisons.items():
        if not isinstance(name, str) or not name or not isinstance(comparison, Comparison):
            raise InputError(
                f"comparisons[{name!r}]",
                "a Comparison from pe.compare under a non-empty posture name",
                type(comparison).__name__,
                "key each pe.compare result by a posture name, e.g. {'home': pe.compare(an)}",
            )
    capacities = {name: c.analysis.capacity for name, c in comparisons.items()}
    if len(set(capacities.values())) > 1:  # one table: one set of ellipsoids, one unit
        first = next(iter(capacities.values()))
        other = next(name for name, capacity in capacities.items() if capacity != first)
        raise InputError(
            f"comparisons[{other!r}]",
            f"comparisons of one capacity in one table (the first is {first!r})",
            f"the {capacities[other]!r} capacity",
            "make one table per capacity.",
        )
    return dict(comparisons)


def limits_table(
    comparisons: Comparison | Mapping[str, Comparison],
    directions: Directions = None,
    *,
    sets: Sequence[str] | None = None,
) -> pd.DataFrame:
    """Directional limits of the polytope and every ellipsoid at one or several postures.

    Parameters
    ----------
    comparisons : Comparison or mapping of str to Comparison
        One comparison, or comparisons by posture name (``{"home": cmp1, "reach": cmp2}``;
        the names become the ``posture`` column, in this order).
    directions : list or mapping, optional
        The directions (:func:`~polyell.comparison.directions.named_direction`: ``"x"``,
        ``"-z"``, ``"xy"``, unit vectors), the same list for every posture, or a mapping
        from posture name to its list (a posture it leaves out, or maps to None, gets the
        default).  Default: the task's coordinate axes (``x, y, z`` for a 3-D position
        task; an interval holds both ends, so ``-x`` adds nothing).
    sets : list of str, optional
        ``"polytope"``, ``"chiacchio"``, ``"yoshikawa"``, ``"mvie"``, ``"outer"`` and
        candidates' names, in the order wanted.  Default: the polytope and every
        ellipsoid computed.

    Returns
    -------
    DataFrame
        Long form, one row per (posture,) direction and set, in that order, with the
        columns ``posture`` (several postures only), ``direction`` (label), ``set``,
        ``defined`` (False where the ellipsoid does not exist at this posture: the classic
        one at a singular posture), ``lower`` and ``upper`` [``unit``] (NaN where the line
        misses the set), ``lower_error`` and ``upper_error`` (fractions, ``(e - p) / |p|``
        against the polytope's same end; NaN where an end is missing or the polytope's is
        0; 0 for the polytope), and ``unit`` (``m/s^2``, ``rad/s^2`` or ``weighted
        units``, from the task).

    Raises
    ------
    InputError
        For a direction the task cannot have (naming ``directions[k]`` or
        ``directions['home'][k]``), an unknown set, or comparisons that are not.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
    >>> an = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), tau_max=[100, 30, 4])
    >>> table = pe.limits_table({"paper": pe.compare(an, 16)}, ["x", "xy"])
    >>> list(table.columns)[:4], len(table)
    (['posture', 'direction', 'set', 'defined'], 10)
    """
    import pandas as pd

    single = not isinstance(comparisons, Mapping)
    named = posture_comparisons(comparisons)
    per_posture = isinstance(directions, Mapping)
    if per_posture:
        unknown = [name for name in directions if name not in named]  # type: ignore[union-attr]
        if unknown:
            raise InputError(
                "directions",
                f"directions of the postures {list(named)}",
                f"{unknown}",
                "pass a list of directions, e.g. ['x', 'xy'], with a single Comparison"
                if single
                else f"key directions by those posture names, e.g. {{{next(iter(named))!r}: "
                "['x', 'xy']}",
            )
    frames = []
    for name, comparison in named.items():
        wanted = directions.get(name) if per_posture else directions  # type: ignore[union-attr]
        argument = f"directions[{name!r}]" if per_posture else "directions"
        frame = limits_frame(comparison, wanted, sets=sets, argument=argument)  # type: ignore[arg-type]
        if not single:
            frame.insert(0, "posture", name)
        frames.append(frame)
    table = pd.concat(frames, ignore_index=True)
    capacities = {frame.attrs.get("capacity") for frame in frames}
    if len(capacities) == 1:
        table.attrs["capacity"] = capacities.pop()
    return table
