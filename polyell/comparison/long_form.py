"""Results in long (tidy) form: one row per configuration, capacity and ellipsoid.

:func:`polyell.sweep` returns one wide row per configuration, the scores of every ellipsoid
side by side as ``<kind>_<score>`` columns (``chiacchio_coverage``, ``heavy_wrist_volume``).
:func:`to_long` turns such a frame -- or several capacities' frames -- into one row per
``(configuration, capacity, kind)`` with one column per score, the form ``groupby``,
``seaborn`` and ``plotnine`` take; :func:`to_wide` gives the wide frame back exactly.

The ellipsoids of a frame come from its structure, never from splitting column names at
``"_"`` (a candidate's name may hold underscores): the kinds a sweep records in
``frame.attrs`` (:func:`wide_attrs`; pandas keeps them in Parquet files), the names passed
as ``kinds=``, and the built-in kinds of the capacity, each matched as exact
``<kind>_<score>`` names over :data:`~polyell.comparison.comparison.SCORE_NAMES`
(:func:`score_columns`).
"""

from __future__ import annotations

import copy
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from polyell.capacities import CAPACITIES, capacity_class, check_capacity
from polyell.comparison.comparison import SCORE_NAMES, compared_kinds
from polyell.errors import InputError

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "BUILT_IN_SCORED_KINDS",
    "LONG_LEVELS",
    "ScoreColumns",
    "score_columns",
    "to_long",
    "to_wide",
    "wide_attrs",
]

#: The index levels of a long frame; a sweep of several robots adds ``"robot"`` in front.
LONG_LEVELS = ("configuration", "capacity", "kind")
#: The column of a sweep of several robots (:func:`polyell.sweep`), an index level when long.
ROBOT = "robot"
#: Every kind a comparison of some capacity scores, in table order.
BUILT_IN_SCORED_KINDS: tuple[str, ...] = tuple(
    dict.fromkeys(kind for capacity in CAPACITIES for kind in compared_kinds(capacity))
)
#: Columns of the polytope itself (``polytope_volume``): per configuration, never a kind's.
_POLYTOPE = "polytope_"
#: Where :func:`to_long` keeps what :func:`to_wide` needs to give the wide frame back.
_WIDE = "wide"


def wide_attrs(capacity: str, kinds: Sequence[str], scores: Sequence[str]) -> dict[str, Any]:
    """What a wide results frame records of its structure in ``DataFrame.attrs``.

    :func:`polyell.sweep` sets them on the frames it returns and writes (Parquet keeps
    ``attrs``; CSV does not).  Lists, not tuples: they read back equal from Parquet.

    Parameters
    ----------
    capacity : str
        The capacity scored (:data:`polyell.CAPACITIES`).
    kinds : sequence of str
        The ellipsoids with ``<kind>_<score>`` columns, in column order (candidates too).
    scores : sequence of str
        The score names of those columns (:data:`polyell.SCORE_NAMES`), in column order.

    Returns
    -------
    dict
        ``{"capacity": capacity, "kinds": [...], "scores": [...]}``.

    Examples
    --------
    >>> wide_attrs("force", ("chiacchio", "heavy_wrist"), ("coverage",))
    {'capacity': 'force', 'kinds': ['chiacchio', 'heavy_wrist'], 'scores': ['coverage']}
    """
    return {
        "capacity": check_capacity(capacity),
        "kinds": _names("kinds", kinds),
        "scores": _score_names("scores", scores),
    }


@dataclass(frozen=True)
class ScoreColumns:
    """The ``<kind>_<score>`` columns of a wide frame, resolved from its structure.

    Attributes
    ----------
    capacity : str or None
        The frame's capacity: its ``attrs``, the one passed, or the one whose own
        ellipsoids the columns hold exactly; None where none of these settles it.
    columns : dict of str to dict of str to str
        ``columns[kind][score]`` is the column of that ellipsoid's score; kinds in the order
        of their first column, scores in :data:`~polyell.comparison.comparison.SCORE_NAMES`
        order.
    recorded : bool
        True where the kinds are known from the frame's ``attrs`` or the ``kinds``
        argument, False where only the built-in kinds were matched.
    unresolved : tuple of str
        Columns that end in ``_<score>`` for a score name but are no resolved kind's (a
        candidate's, without its name); ``polytope_*`` columns are the polytope's own.
    """

    capacity: str | None
    columns: dict[str, dict[str, str]]
    recorded: bool
    unresolved: tuple[str, ...]

    @property
    def kinds(self) -> list[str]:
        """The ellipsoids with columns, in the order of their first column."""
        return list(self.columns)

    @property
    def scores(self) -> list[str]:
        """The scores of any kind's columns, in ``SCORE_NAMES`` order."""
        held = {score for by_score in self.columns.values() for score in by_score}
        return [score for score in SCORE_NAMES if score in held]


def score_columns(
    frame: pd.DataFrame | Iterable[str],
    *,
    kinds: Sequence[str] | str | None = None,
    capacity: str | None = None,
) -> ScoreColumns:
    """Which columns of a wide frame are which ellipsoid's scores, without splitting names.

    A column is ``(kind, score)`` only where it is exactly ``f"{kind}_{score}"`` for a kind
    known from the structure of the results and a score of
    :data:`~polyell.comparison.comparison.SCORE_NAMES`:

    1. the kinds in ``frame.attrs["kinds"]`` (:func:`polyell.sweep` records them,
       :func:`wide_attrs`), then those in ``kinds``;
    2. else the built-in kinds of the capacity (of every capacity where it is unknown),
       then those in ``kinds``.

    Parameters
    ----------
    frame : DataFrame or iterable of str
        A wide frame (its ``attrs`` are used) or its column names.
    kinds : sequence of str, optional
        Ellipsoids beyond the built-in ones, e.g. the candidates' names of a frame read
        back without its ``attrs`` (from CSV); one name alone is a sequence of one.
    capacity : str, optional
        The frame's capacity where its ``attrs`` do not record it.

    Returns
    -------
    ScoreColumns

    Raises
    ------
    InputError
        If ``kinds`` or ``capacity`` is malformed, ``capacity`` contradicts the frame's
        ``attrs``, or the ``attrs`` are malformed.  (A name of ``kinds`` without columns
        is not an error here: a frame of some columns holds some kinds.)

    Examples
    --------
    >>> found = score_columns(["q1", "chiacchio_coverage", "my_arm_coverage"],
    ...                       kinds=["my_arm"])
    >>> found.columns
    {'chiacchio': {'coverage': 'chiacchio_coverage'}, 'my_arm': {'coverage': 'my_arm_coverage'}}
    """
    import pandas as pd

    attrs: Mapping[str, Any] = {}
    if isinstance(frame, pd.DataFrame):
        attrs, names = frame.attrs, [str(column) for column in frame.columns]
    elif isinstance(frame, str | bytes) or not isinstance(frame, Iterable):
        raise InputError(
            "frame",
            "a wide results DataFrame or its column names",
            f"{type(frame).__name__} {frame!r}"[:120],
            "pass e.g. the frame pe.sweep returns, or frame.columns.",
        )
    else:
        names = list(frame)
        wrong = [name for name in names if not isinstance(name, str)]
        if wrong:
            raise InputError(
                "frame",
                "column names (str)",
                f"a column {wrong[0]!r}"[:120],
                "pass the names as str, e.g. [str(name) for name in names]",
            )
    extra = [] if kinds is None else _names("kinds", kinds)
    recorded_capacity = (
        check_capacity(attrs["capacity"], "frame.attrs['capacity']")
        if "capacity" in attrs
        else None
    )
    if capacity is not None:
        capacity = check_capacity(capacity)
        if recorded_capacity is not None and recorded_capacity != capacity:
            raise InputError(
                "capacity",
                f"the frame's own capacity, {recorded_capacity!r} (its attrs['capacity'])",
                repr(capacity),
                "leave capacity out, or pass the frame of that capacity.",
            )
    capacity = recorded_capacity if capacity is None else capacity
    recorded = _names("frame.attrs['kinds']", attrs["kinds"]) if "kinds" in attrs else None
    if recorded is not None:
        known = [*recorded, *extra]
    else:
        built_in = compared_kinds(capacity) if capacity is not None else BUILT_IN_SCORED_KINDS
        known = [*built_in, *extra]
    exact = {f"{kind}_{score}": (kind, score) for kind in known for score in SCORE_NAMES}
    found: dict[str, dict[str, str]] = {}
    unresolved: list[str] = []
    for name in names:
        if name in exact:
            kind, score = exact[name]
            found.setdefault(kind, {})[score] = name
        elif not name.startswith(_POLYTOPE) and any(name.endswith(f"_{s}") for s in SCORE_NAMES):
            unresolved.append(name)
    columns = {
        kind: {score: found[kind][score] for score in SCORE_NAMES if score in found[kind]}
        for kind in found
    }
    if capacity is None:
        capacity = _capacity_of(columns)
    return ScoreColumns(capacity, columns, recorded is not None or bool(extra), tuple(unresolved))


def to_long(
    frames: Any,
    *,
    kinds: Sequence[str] | str | None = None,
    capacity: str | None = None,
) -> pd.DataFrame:
    """Wide results in long (tidy) form: one row per configuration, capacity and kind.

    Parameters
    ----------
    frames : DataFrame, dict or sequence of DataFrames
        A wide results frame (:func:`polyell.sweep`; ``pd.DataFrame`` of
        ``Comparison.to_row()`` records), one ``Comparison.to_row()`` record, several
        capacities' frames as a sequence (each with its ``attrs["capacity"]``) or as a dict
        ``{capacity: frame}``.
    kinds : sequence of str, optional
        Ellipsoids beyond the built-in ones -- the candidates' names -- for a frame read
        back without its ``attrs`` (CSV); :func:`score_columns` says how columns are
        matched.
    capacity : str, optional
        The capacity of one frame whose ``attrs`` do not record it; default: the capacity
        whose own ellipsoids the columns hold (``static_*``: forces, ``yoshikawa_*`` alone:
        velocities, ``chiacchio_*`` and ``yoshikawa_*``: accelerations).

    Returns
    -------
    DataFrame
        Indexed by ``(configuration, capacity, kind)`` (a sweep of several robots:
        ``(robot, configuration, capacity, kind)``), each configuration's kinds together
        in column order, the capacities in the order given.  ``configuration`` is the
        frame's ``configuration`` column, or its index where it has none (``to_row``
        records).  The columns: one per score the frame holds, in
        :data:`~polyell.SCORE_NAMES` order (NaN where a kind lacks that score), then the
        per-configuration columns (``q1``.., ``t``, ``per_row``, ``polytope_*`` and any
        other column that is no kind's), repeated on each kind's row as
        :func:`pandas.wide_to_long` keeps its id columns: ``long.xs("chiacchio",
        level="kind")`` is one row per configuration again.  ``attrs["wide"]`` holds, per
        capacity, what :func:`to_wide` needs to give the wide frame back exactly (column
        order, dtypes, ``attrs``, index).

    Raises
    ------
    InputError
        If a column ends in a score name but is no known kind's (pass ``kinds=``), a
        per-configuration column is named like a score or an index level, the
        configurations repeat, the capacity cannot be told, or a capacity comes twice.

    Examples
    --------
    >>> import polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> wrist = pe.Candidate("heavy_wrist", weighting=[[1, 0, 0], [0, 1, 0], [0, 0, 4]])
    >>> frame = pe.sweep(arm, [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]], candidates=[wrist])
    >>> long = pe.to_long(frame)
    >>> list(long.index.names)
    ['configuration', 'capacity', 'kind']
    >>> list(long.index.unique("kind"))
    ['chiacchio', 'yoshikawa', 'heavy_wrist']
    >>> bool(long.loc[(1, "acceleration", "heavy_wrist"), "coverage"]
    ...      == frame.heavy_wrist_coverage[1])
    True
    >>> pe.to_wide(long).equals(frame)
    True
    """
    import pandas as pd

    pieces = _pieces(frames, capacity)
    blocks: list[pd.DataFrame] = []
    meta: dict[str, Any] = {}
    with_robot: set[bool] = set()
    for argument, frame, key in pieces:
        block, capacity_of, record = _long_block(argument, frame, key, kinds)
        if capacity_of in meta:
            raise InputError(
                "frames",
                "one frame per capacity",
                f"two {capacity_of} frames",
                "concatenate a capacity's frames first (pd.concat, with a 'robot' column "
                "where they are different robots' configurations).",
            )
        meta[capacity_of] = record
        blocks.append(block)
        with_robot.add(ROBOT in block.index.names)
    extra = [] if kinds is None else _names("kinds", kinds)
    held_kinds = {pair[0] for record in meta.values() for pair in record["kinds"].values()}
    missing = [kind for kind in extra if kind not in held_kinds]
    if missing:
        raise InputError(
            "kinds",
            "names of ellipsoids with <kind>_<score> columns in the frame",
            f"{missing[0]!r}, with no column such as {missing[0]}_coverage",
            "check the spelling against the frame's columns.",
        )
    if len(with_robot) > 1:
        raise InputError(
            "frames",
            "frames that all have a 'robot' column, or none",
            "some with one and some without",
            "give each frame its robot column (frame.assign(robot=name)) or none.",
        )
    long = blocks[0] if len(blocks) == 1 else pd.concat(blocks)
    held = set(long.columns)
    scores = [score for score in SCORE_NAMES if score in held]
    per = [column for block in blocks for column in block.columns if column not in SCORE_NAMES]
    order = [*scores, *dict.fromkeys(per)]
    if list(long.columns) != order:  # (one frame: in order already, no copy)
        long = long[order]
    long.attrs = {_WIDE: meta}
    return long


def to_wide(long: pd.DataFrame, *, capacity: str | None = None) -> pd.DataFrame:
    """The wide frame of one capacity back from its long form (:func:`to_long`).

    Parameters
    ----------
    long : DataFrame
        From :func:`to_long`: indexed by ``(configuration, capacity, kind)`` (with
        ``robot`` in front for several robots), or with those as columns (a long frame
        read back from CSV).
    capacity : str, optional
        Which capacity's frame, where ``long`` holds several.

    Returns
    -------
    DataFrame
        One row per configuration, in their order of appearance, ``<kind>_<score>``
        columns.  With the ``attrs["wide"]`` :func:`to_long` writes (Parquet keeps them):
        exactly the frame given to :func:`to_long` -- its columns in their order, their
        dtypes, its ``attrs`` and its index (a frame with a ``configuration`` column gets
        back its ``RangeIndex``; another index is reset to one).  Without them: the
        ``robot`` and ``configuration`` columns, the per-configuration columns, then every
        ``<kind>_<score>`` column kind by kind, with :func:`wide_attrs`; of a long frame of
        several capacities, the columns all NaN in this capacity's rows are left out (the
        other capacities' own).

    Raises
    ------
    InputError
        If ``long`` is not a long frame (levels, unique index), ``capacity`` is not one of
        it (or is missing with several), or its ``attrs["wide"]`` names columns it lacks.

    Examples
    --------
    >>> import pandas as pd, polyell as pe
    >>> frame = pd.DataFrame({"configuration": [0, 1], "q1": [0.1, 0.2],
    ...                       "chiacchio_coverage": [0.5, 0.6],
    ...                       "yoshikawa_coverage": [0.3, 0.4]})
    >>> long = pe.to_long(frame, capacity="acceleration")
    >>> long["coverage"].tolist()
    [0.5, 0.3, 0.6, 0.4]
    >>> pe.to_wide(long).equals(frame)
    True
    """
    import pandas as pd

    long = _as_long(long)
    records = long.attrs.get(_WIDE, {}) if isinstance(long.attrs.get(_WIDE), dict) else {}
    held = [str(c) for c in long.index.unique("capacity")] or list(records)  # or no rows
    if not held:
        raise InputError(
            "long",
            "a long frame with rows, or the attrs['wide'] pe.to_long writes",
            "an empty frame without them",
            "pass the frame pe.to_long returned.",
        )
    if capacity is None:
        if len(held) != 1:
            raise InputError(
                "capacity",
                f"one of {held} (the long frame holds several)",
                "None",
                f"pass capacity={held[0]!r}, or loop over long.index.unique('capacity').",
            )
        capacity = str(held[0])
    elif not isinstance(capacity, str) or capacity not in held:
        raise InputError(
            "capacity",
            f"one of the long frame's capacities {held}",
            repr(capacity),
            f"pass one of those, e.g. capacity={held[0]!r}",
        )
    record = records.get(capacity)
    if isinstance(record, dict) and not {"columns", "dtypes", "attrs", "kinds"} <= set(record):
        raise InputError(
            "long.attrs['wide']",
            "the record pe.to_long writes (columns, dtypes, attrs of the wide frame)",
            f"keys {sorted(record)}"[:120],
            "pass the frame pe.to_long returned, or delete long.attrs['wide'].",
        )
    present = capacity in long.index.unique("capacity")  # (or no rows)
    part = long.xs(capacity, level="capacity") if present else long.droplevel("capacity")
    part.attrs = {}  # (pandas copies attrs along every step below)
    if len(held) > 1 and record is None:  # the other capacities' own columns are not this one's
        part = part.dropna(axis=1, how="all")
    keys = part.index.droplevel("kind")
    first = ~keys.duplicated()
    order = keys[first]
    starts = np.flatnonzero(first)
    base = part.iloc[starts]
    kind_codes, kind_names = pd.factorize(part.index.get_level_values("kind"))
    kinds = [str(kind) for kind in kind_names]
    width = len(kinds)
    # As to_long lays it out: each configuration's kinds together, in one order.
    regular = (
        width > 0
        and len(part) == len(order) * width
        and np.array_equal(starts, np.arange(0, len(part), width))
        and np.array_equal(kind_codes, np.tile(np.arange(width), len(order)))
    )
    scores = [column for column in part.columns if column in SCORE_NAMES]
    per = [column for column in part.columns if column not in SCORE_NAMES]
    product = {f"{kind}_{score}": (kind, score) for kind in kinds for score in scores}
    by_kind: dict[str, pd.DataFrame] = {}

    def of_kind(kind: str, score: str, name: str) -> pd.Series:
        if score not in part.columns or (kind not in kinds and len(part)):
            raise InputError(
                "long",
                f"a long frame holding the {kind!r} rows and the {score!r} column of the "
                f"wide column {name!r} it came from",
                f"kinds {kinds} and columns {list(long.columns)[:6]}"[:200],
                "pass the frame pe.to_long returned (a kind or score was dropped).",
            )
        if regular:
            return part[score].iloc[kinds.index(kind) :: width]
        if kind not in by_kind:
            mask = kind_codes == (kinds.index(kind) if kind in kinds else -2)
            rows = part[mask]
            rows.index = keys[mask]
            by_kind[kind] = rows if rows.index.equals(order) else rows.reindex(order)
        return by_kind[kind][score]

    level_names = list(keys.names) if isinstance(keys, pd.MultiIndex) else [keys.name]
    levels = {name: order.get_level_values(name) for name in level_names}
    if record is None:
        names = [*level_names, *per]
        names += [f"{kind}_{score}" for kind in kinds for score in scores]
        record = {"columns": names, "dtypes": {}, "attrs": wide_attrs(capacity, kinds, scores)}
        record["configuration"] = "column"
    else:
        product = {name: (str(pair[0]), str(pair[1])) for name, pair in record["kinds"].items()}
    data: dict[str, Any] = {}
    for name in record["columns"]:
        if name in levels and (name == ROBOT or record.get("configuration") == "column"):
            values = pd.Series(levels[name], name=name)
        elif name in per:
            values = base[name].reset_index(drop=True)
        elif name in product:
            values = of_kind(*product[name], name).reset_index(drop=True)
        else:
            raise InputError(
                "long",
                f"a long frame holding the column {name!r} of the wide frame it came from",
                f"columns {list(long.columns)[:8]}",
                "pass the frame to_long returned (a kind or score was dropped).",
            )
        dtype = record["dtypes"].get(name)
        if dtype is not None and str(values.dtype) != dtype:
            try:
                values = values.astype(dtype)
            except (TypeError, ValueError) as exn:  # e.g. NaN of a missing row into int64
                raise InputError(
                    "long",
                    f"values of column {name!r} that fit its wide dtype {dtype}",
                    f"{values.dtype} ({exn.__class__.__name__}: {str(exn)[:80]})",
                    "pass the frame pe.to_long returned (rows were dropped?).",
                ) from None
        data[name] = values
    wide = pd.DataFrame(data, columns=record["columns"])
    wide.index = _wide_index(record, levels.get("configuration"), len(wide))
    wide.attrs = copy.deepcopy(record["attrs"])
    return wide


# -- helpers -------------------------------------------------------------------------------


def _shown(key: Any) -> str:
    """An index key as a user writes it: ``(0, 'force', 'static')``, not ``np.int64(0)``."""
    if isinstance(key, tuple):
        return "(" + ", ".join(_shown(item) for item in key) + ")"
    return repr(key.item() if isinstance(key, np.generic) else key)


def _names(argument: str, value: object) -> list[str]:
    """A list of distinct non-empty names from a sequence of str (one str: a list of one)."""
    if isinstance(value, str):
        value = [value]
    if isinstance(value, bytes) or not isinstance(value, Sequence | np.ndarray):
        raise InputError(
            argument,
            "a sequence of names (str)",
            f"{type(value).__name__} {value!r}"[:120],
            "pass e.g. ['heavy_wrist'].",
        )
    names = list(value)
    wrong = [name for name in names if not isinstance(name, str) or not name]
    if wrong:
        raise InputError(
            argument,
            "non-empty names (str)",
            f"an item {wrong[0]!r}"[:120],
            "drop that item or name it with a non-empty str, e.g. ['heavy_wrist']",
        )
    if "polytope" in names:
        raise InputError(
            argument,
            "ellipsoid names ('polytope' is the exact set's: its columns are per configuration)",
            "'polytope'",
            "leave 'polytope' out and list only ellipsoids, e.g. ['heavy_wrist']",
        )
    return list(dict.fromkeys(names))


def _score_names(argument: str, value: object) -> list[str]:
    names = _names(argument, value)
    unknown = [name for name in names if name not in SCORE_NAMES]
    if unknown:
        raise InputError(
            argument,
            f"score names among {list(SCORE_NAMES)}",
            repr(unknown[0]),
            f"drop {unknown[0]!r} or use one of the names listed, e.g. 'coverage'",
        )
    return names


def _capacity_of(columns: Mapping[str, Any]) -> str | None:
    """The capacity whose own ellipsoids are exactly the built-in non-optimal kinds held."""
    own = {kind for kind in columns if kind in BUILT_IN_SCORED_KINDS} - {"mvie", "outer"}
    matching = [c for c in CAPACITIES if set(capacity_class(c).ellipsoid_kinds) == own]
    return matching[0] if len(matching) == 1 else None


def _pieces(frames: Any, capacity: str | None) -> list[tuple[str, pd.DataFrame, str | None]]:
    """``(argument, frame, capacity)`` for each frame given to :func:`to_long`."""
    import pandas as pd

    if isinstance(frames, pd.DataFrame):
        return [("frames", frames, capacity)]
    several = "pass capacity= only with one frame; several: a dict {capacity: frame}."
    if isinstance(frames, Mapping):
        if frames and all(isinstance(v, pd.DataFrame) for v in frames.values()):
            if capacity is not None:
                raise InputError("capacity", "None with a dict of frames", repr(capacity), several)
            return [
                (f"frames[{key!r}]", frame, check_capacity(key, f"frames key {key!r}"))
                for key, frame in frames.items()
            ]
        plain = not any(isinstance(v, pd.DataFrame | pd.Series) for v in frames.values())
        if frames and plain and all(isinstance(k, str) for k in frames):  # one to_row()
            try:
                return [("frames", pd.DataFrame([dict(frames)]), capacity)]
            except (TypeError, ValueError) as exn:  # pragma: no cover - pandas takes scalars
                raise InputError(
                    "frames",
                    "a to_row() record",
                    str(exn)[:120],
                    "pass the dict Comparison.to_row() returns, one scalar per column",
                ) from None
    if isinstance(frames, Sequence) and not isinstance(frames, str | bytes) and frames:
        if all(isinstance(frame, pd.DataFrame) for frame in frames):
            if capacity is not None and len(frames) > 1:
                raise InputError("capacity", "None with several frames", repr(capacity), several)
            return [(f"frames[{i}]", frame, capacity) for i, frame in enumerate(frames)]
    raise InputError(
        "frames",
        "a wide results DataFrame (pe.sweep), a Comparison.to_row() record, or several "
        "capacities' frames (a list, or a dict {capacity: frame})",
        f"{type(frames).__name__} {frames!r}"[:120],
        "pass e.g. the frame pe.sweep returns, or {'acceleration': frame, 'velocity': frame2}",
    )


def _long_block(
    argument: str, frame: pd.DataFrame, capacity: str | None, kinds: Any
) -> tuple[pd.DataFrame, str, dict[str, Any]]:
    """One wide frame in long form, its capacity and what :func:`to_wide` needs of it."""
    import pandas as pd

    names = list(frame.columns)
    wrong = [name for name in names if not isinstance(name, str)]
    if wrong:
        raise InputError(
            argument,
            "column names (str)",
            f"a column {wrong[0]!r}"[:120],
            "rename the columns to str, e.g. frame.rename(columns=str)",
        )
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise InputError(
            argument,
            "distinct column names",
            f"{repeated[0]!r} more than once",
            "drop the repeats, e.g. frame.loc[:, ~frame.columns.duplicated()]",
        )
    try:
        layout = score_columns(frame, kinds=kinds, capacity=capacity)
    except InputError as exn:
        if exn.argument.startswith("frame"):  # a malformed attrs: say which frame
            raise InputError(
                exn.argument.replace("frame", argument, 1), exn.expected, exn.got, exn.fix
            ) from None
        raise
    if layout.unresolved:
        shown = ", ".join(repr(name) for name in layout.unresolved[:3])
        more = f" and {len(layout.unresolved) - 3} more" if len(layout.unresolved) > 3 else ""
        raise InputError(
            argument,
            "columns that are a known kind's <kind>_<score> or per configuration",
            f"{shown}{more}: named like a score of an ellipsoid it does not know",
            "pass kinds=[...] with the candidates' names (the built-in kinds are matched "
            "without it), or keep the frame's attrs: pe.sweep records its kinds there and "
            "Parquet keeps them; or rename a column that is not a score",
        )
    if not layout.columns:
        raise InputError(
            argument,
            "a wide results frame with <kind>_<score> columns (e.g. chiacchio_coverage)",
            f"columns {names[:6]}",
            "pass the frame pe.sweep returns.",
        )
    if layout.capacity is None:
        raise InputError(
            "capacity",
            "the capacity of a frame whose attrs do not record it",
            f"None, and the kinds {layout.kinds} do not tell",
            "pass capacity='acceleration', 'velocity' or 'force'.",
        )
    capacity = layout.capacity
    used = {column for by_score in layout.columns.values() for column in by_score.values()}
    keys = [name for name in (ROBOT, "configuration") if name in names]
    per = [name for name in names if name not in used and name not in keys]
    clash = [name for name in per if name in SCORE_NAMES or name in LONG_LEVELS]
    if clash:
        raise InputError(
            argument,
            "per-configuration columns not named like a score or an index level",
            f"a column {clash[0]!r}",
            "rename it (frame.rename(columns=...)).",
        )
    count, kinds_held = len(frame), layout.kinds
    width = len(kinds_held)
    if "configuration" in names:
        configuration = pd.Index(frame["configuration"])
    else:
        configuration = pd.Index(frame.index)
    key = pd.MultiIndex.from_arrays(
        [frame[ROBOT], configuration] if ROBOT in names else [configuration]
    )
    if key.has_duplicates:
        at = key[key.duplicated()][0]
        raise InputError(
            argument,
            "one row per configuration" + (" and robot" if ROBOT in names else ""),
            f"configuration {_shown(at if ROBOT in names else at[0])} more than once",
            "a sweep of several robots keeps its 'robot' column; concatenated frames: "
            "renumber their configurations.",
        )
    scores = _stacked_scores(frame, layout, count, width)
    rows = np.repeat(np.arange(count), width)
    configuration_columns = frame[per].take(rows).reset_index(drop=True)
    codes, levels = [], []
    for values in [frame[ROBOT], configuration] if ROBOT in names else [configuration]:
        held, unique = pd.factorize(values)
        codes.append(np.repeat(held, width))
        levels.append(pd.Index(unique))
    codes += [np.zeros(count * width, dtype=np.intp), np.tile(np.arange(width), count)]
    levels += [pd.Index([capacity]), pd.Index(kinds_held)]
    index = pd.MultiIndex(
        levels=levels,
        codes=codes,
        names=[ROBOT, *LONG_LEVELS] if ROBOT in names else list(LONG_LEVELS),
        verify_integrity=False,
    )
    block = pd.concat([scores, configuration_columns], axis=1)
    block.index = index
    range_of = frame.index if isinstance(frame.index, pd.RangeIndex) else None
    record = {
        "columns": names,
        "dtypes": {name: str(frame[name].dtype) for name in names},
        "attrs": copy.deepcopy(dict(frame.attrs)),
        "kinds": {
            column: [kind, score]
            for kind, by_score in layout.columns.items()
            for score, column in by_score.items()
        },
        "configuration": "column" if "configuration" in names else "index",
        "index_name": frame.index.name,
        "range": None if range_of is None else [range_of.start, range_of.stop, range_of.step],
    }
    return block, capacity, record


def _stacked_scores(
    frame: pd.DataFrame, layout: ScoreColumns, count: int, width: int
) -> pd.DataFrame:
    """The score columns of the kinds' rows: row ``i * width + j`` is kind j at row i."""
    import pandas as pd

    kinds, scores = layout.kinds, layout.scores
    names = [[layout.columns[kind].get(score) for score in scores] for kind in kinds]
    dtypes = {frame[name].dtype for row in names for name in row if name is not None}
    complete = all(name is not None for row in names for name in row)
    if complete and len(dtypes) == 1 and isinstance(next(iter(dtypes)), np.dtype):
        # the common case (every kind every score, one numpy dtype): one copy, laid out
        # as pandas keeps a block (a score's values contiguous)
        cube = np.empty((len(scores), count, width), dtype=next(iter(dtypes)))
        for j, row in enumerate(names):
            for i, name in enumerate(row):
                cube[i, :, j] = frame[name].to_numpy()
        flat = cube.reshape(len(scores), count * width).T
        return pd.DataFrame(flat, columns=scores, copy=False)
    interleave = (np.arange(count * width) % width) * count + np.arange(count * width) // width
    data: dict[str, Any] = {}
    for i, score in enumerate(scores):
        parts = [
            frame[row[i]].reset_index(drop=True)
            if row[i] is not None
            else pd.Series(np.full(count, np.nan))
            for row in names
        ]
        stacked = pd.concat(parts, ignore_index=True) if width > 1 else parts[0]
        data[score] = stacked.take(interleave).reset_index(drop=True)
    return pd.DataFrame(data, columns=scores, index=pd.RangeIndex(count * width))


def _as_long(value: object) -> pd.DataFrame:
    """A long frame, checked: levels ([robot,] configuration, capacity, kind), unique."""
    import pandas as pd

    if not isinstance(value, pd.DataFrame):
        raise InputError(
            "long",
            "a long results DataFrame (pe.to_long)",
            f"{type(value).__name__}"[:80],
            "pass the frame pe.to_long returned.",
        )
    long: pd.DataFrame = value
    names = list(long.index.names)
    if names not in (list(LONG_LEVELS), [ROBOT, *LONG_LEVELS]):
        levels = [ROBOT, *LONG_LEVELS] if ROBOT in long.columns else list(LONG_LEVELS)
        if not set(levels) <= set(long.columns):
            raise InputError(
                "long",
                "a frame indexed by (configuration, capacity, kind), as pe.to_long returns "
                "(or with those columns)",
                f"index levels {names} and columns {list(long.columns)[:6]}",
                "pass the frame pe.to_long returned.",
            )
        attrs = long.attrs
        long = long.set_index(levels)
        long.attrs = attrs
    if long.index.has_duplicates:
        at = long.index[long.index.duplicated()][0]
        raise InputError(
            "long",
            "one row per (configuration, capacity, kind)",
            f"{_shown(at)} twice",
            "drop the repeated rows, e.g. long[~long.index.duplicated()]",
        )
    return long


def _wide_index(record: Mapping[str, Any], configuration: Any, count: int) -> pd.Index:
    """The wide frame's index: its configurations (to_row frames) or its RangeIndex."""
    import pandas as pd

    name, span = record.get("index_name"), record.get("range")
    kept = None if span is None else pd.RangeIndex(*span, name=name)  # the frame's own
    if kept is not None and len(kept) != count:
        kept = None
    if record.get("configuration") == "index":
        index = pd.Index(configuration, name=name)
        return kept if kept is not None and index.equals(kept) else index
    return pd.RangeIndex(count, name=name) if kept is None else kept
