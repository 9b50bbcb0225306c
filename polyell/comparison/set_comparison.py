r"""``compare`` of a bare set: the ellipsoids of any convex set the library builds, scored.

A set built without an arm -- the sum or the intersection of two arms' force sets
(:mod:`polyell.geometry.combine`), a set rotated into a common frame
(:func:`~polyell.geometry.combine.in_frame`), an analysis's polytope taken on its own --
has no ellipsoid definitions of its own and no joint quantities: :func:`polyell.compare`
scores its maximum-volume inscribed ellipsoid, its minimum-volume enclosing (outer) one and
any ellipsoids the caller gives, with the one scorer of :mod:`polyell.comparison.scores`
(:func:`score_records`, shared with the comparison of an analysis).  The torque (or joint
velocity) witness needs an arm's inverse map: a set's records have no such field
(:class:`SetScores`), and its tables no such column.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.candidates import CANDIDATE_NAME, Candidate
from polyell.comparison.directional import statistics
from polyell.comparison.directions import DirectionSpec, resolve_directions
from polyell.comparison.layout import TableLayout
from polyell.comparison.metrics import check_same_affine_set
from polyell.comparison.scores import ellipsoid_of, set_of, shape_scores
from polyell.errors import InputError, SolverError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.limits import DirectionalLimits
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from polyell.geometry.outer import min_volume_enclosing_ellipsoid
from polyell.geometry.polytope import Polytope
from polyell.models.task import default_task
from polyell.storage import write_text_atomically
from polyell.validation import check_instance

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "SET_KINDS",
    "SET_SCORE_NAMES",
    "ScoredSet",
    "SetComparison",
    "SetScores",
    "check_bare_set",
    "check_given_ellipsoids",
    "score_records",
]

#: The ellipsoids every comparison of a bare set scores; given ellipsoids follow them.
SET_KINDS = ("mvie", "outer")

#: Names a given ellipsoid may not take (the built-in kinds of every capacity, the
#: columns of a table).
_RESERVED = ("chiacchio", "yoshikawa", "static", "mvie", "outer", "polytope", "configuration")

Array = NDArray[np.float64]


@dataclass(frozen=True)
class SetScores:
    r"""How well one ellipsoid describes a convex set (DESIGN.md section 2), without an arm.

    The scores of :class:`~polyell.Scores` but the witness (which needs an arm's inverse
    map); ``pe.compare`` of a bare set returns these.

    Attributes
    ----------
    kind : str
        ``"mvie"``, ``"outer"``, a given ellipsoid's or a candidate's name.
    defined : bool
        False where the ellipsoid does not exist here (a solver without a certified
        optimum, a candidate missing a lower-dimensional set, ``mvie=False``): then every
        score is NaN (counts 0) and ``reason`` says why.
    reason : str
        Why the ellipsoid is undefined; empty otherwise.
    dimension : float
        Its dimension r (rank), equal to the set's.
    volume : float
        Volume of the ellipsoid in its affine set [task unit^r].
    inscribed_scale : float
        Largest k with ``c + k (E - c)`` inside P; >= 1 iff E is inside P; negative when
        even E's centre c lies outside P (no copy of E scaled about c fits, e.g. a
        candidate centred elsewhere): minus the farthest c lies beyond a facet plane of
        P, in E's reach along that facet's normal.
    enclosing_scale : float
        Smallest k with P inside ``c + k (E - c)``; <= 1 iff E contains P.
    coverage, overreach : float
        ``vol(E & P) / vol(P)`` and ``vol(E \ P) / vol(E)``.
    coverage_stderr, overreach_stderr : float
        Standard errors of those two (0 when exact).
    mvie_ratio, outer_ratio : float
        ``vol(E) / vol(E*)`` and ``vol(E) / vol(E_outer)`` (NaN when that optimum is not
        computed).
    direction_error_mean, direction_error_max, direction_error_rms : float
        Mean, max and RMS of ``|hi_E - hi_P| / |hi_P|`` over the directions.
    direction_bias : float
        Mean of ``(hi_E - hi_P) / |hi_P|`` (> 0: E promises too much).
    feasibility_mismatch : int
        Directions where exactly one of E and P has an empty interval.
    directions_used : int
        Directions that entered the directional statistics.
    """

    kind: str
    defined: bool = True
    reason: str = ""
    dimension: float = np.nan
    volume: float = np.nan
    inscribed_scale: float = np.nan
    enclosing_scale: float = np.nan
    coverage: float = np.nan
    coverage_stderr: float = np.nan
    overreach: float = np.nan
    overreach_stderr: float = np.nan
    mvie_ratio: float = np.nan
    outer_ratio: float = np.nan
    direction_error_mean: float = np.nan
    direction_error_max: float = np.nan
    direction_error_rms: float = np.nan
    direction_bias: float = np.nan
    feasibility_mismatch: int = 0
    directions_used: int = 0

    def as_dict(self) -> dict[str, Any]:
        """The record as a plain dictionary (JSON-friendly except for NaN)."""
        return dataclasses.asdict(self)


#: The scores that count directions (integers).
_COUNTS = ("feasibility_mismatch", "directions_used")

#: The score attributes of a bare set, in table order (no witness).
SET_SCORE_NAMES = tuple(
    f.name for f in dataclasses.fields(SetScores) if f.name not in ("kind", "defined", "reason")
)


def score_records(
    P: Polytope | HPolytope,
    ellipsoids: Mapping[str, Ellipsoid],
    directions: Array,
    hi_p: DirectionalLimits,
    samples: int,
    seed: int,
    witnesses: Mapping[str, tuple[Array, Array]] | None = None,
) -> dict[str, dict[str, Any]]:
    """Every score of every ellipsoid against one set: the array scorer's batch of one.

    Parameters
    ----------
    P : Polytope or HPolytope
        The exact set (not empty).
    ellipsoids : mapping of str to Ellipsoid
        The ellipsoids by kind, each in ``P``'s affine set (``"mvie"`` and ``"outer"``,
        where present, are the denominators of the volume ratios).
    directions : ndarray, shape (k, m)
        Unit directions of the directional statistics.
    hi_p : DirectionalLimits
        ``P.limits(directions)``.
    samples, seed : int
        The budget and seed of a coverage estimate (:func:`~polyell.comparison.scores.shares`).
    witnesses : mapping of str to (ndarray (n, m), ndarray (n,)), optional
        Per kind, the witness map's matrix ``W`` and ``W c + w`` at the centre; without
        it (a bare set) the records have no ``witness_torque_max``.

    Returns
    -------
    dict of str to dict of str to float or int
        Per kind, the fields of :class:`SetScores` (and ``witness_torque_max`` with
        ``witnesses``), counts as int.
    """
    if not ellipsoids:
        return {}
    batch = {}
    for kind, E in ellipsoids.items():
        if witnesses is None:
            batch[kind] = ellipsoid_of(E)
        else:
            batch[kind] = ellipsoid_of(E, *witnesses[kind])
    records, _ = shape_scores(set_of(P), batch, samples, seed)
    found: dict[str, dict[str, Any]] = {}
    for kind, E in ellipsoids.items():
        hi_e = E.limits(directions)
        records[kind] |= statistics(
            hi_e.hi[None], hi_e.feasible[None], hi_p.hi[None], hi_p.feasible[None]
        )
        if witnesses is None:
            del records[kind]["witness_torque_max"]  # no arm: no witness
        found[kind] = {
            name: int(column[0]) if name in _COUNTS else float(column[0])
            for name, column in records[kind].items()
        }
    return found


def check_bare_set(P: object, argument: str = "analysis") -> Polytope | HPolytope:
    """A set ``compare`` can score: a non-empty, bounded Polytope or HPolytope of dim >= 1.

    Raises
    ------
    InputError
        Naming ``argument``: another type, an empty, unbounded or point set.
    """
    if not isinstance(P, Polytope | HPolytope):
        raise InputError(
            argument,
            "a pe.Analysis (from pe.analyze) or a set the library builds "
            "(pe.Polytope, pe.HPolytope)",
            type(P).__name__,
            "pass pe.analyze(...) or a set such as pe.geometry.combine.minkowski_sum(P1, P2).",
        )
    if isinstance(P, HPolytope) and P.is_empty:
        raise InputError(
            argument,
            "a non-empty set (there is nothing to inscribe an ellipsoid in)",
            "an empty HPolytope (no point satisfies all its half-spaces)",
            "check the half-spaces; the intersection of two arms' sets is empty when no "
            "force is within both.",
        )
    if isinstance(P, HPolytope) and not P.is_bounded:
        ray = np.round(P.rays[0], 6).tolist()
        raise InputError(
            argument,
            "a bounded set (the MVIE, the outer ellipsoid, coverage and overreach need a "
            "finite volume)",
            f"an HPolytope unbounded along {len(P.rays)} ray(s), e.g. {ray}",
            "compare the force analysis itself (pe.compare(analysis) scores its ellipsoids "
            "along the rays), or intersect the set with a bounded one "
            "(pe.geometry.combine.intersection) first.",
        )
    if P.dim < 1:
        raise InputError(
            argument,
            "a set of dimension 1 or more",
            "a single point (dimension 0)",
            "a point has no shape to describe with an ellipsoid.",
        )
    return P


def check_given_ellipsoids(
    ellipsoids: object,
    P: Polytope | HPolytope,
    taken: Sequence[str] = (),
) -> dict[str, Ellipsoid]:
    """Validate ``ellipsoids=``: a mapping of new lower-case names to ellipsoids in P's affine set.

    Parameters
    ----------
    ellipsoids : mapping of str to Ellipsoid, or None
    P : Polytope or HPolytope
        The set they are scored against.
    taken : sequence of str
        Names already used (the candidates', a capacity's kinds).

    Raises
    ------
    InputError
        Naming ``ellipsoids`` or ``ellipsoids['name']``.
    """
    if ellipsoids is None:
        return {}
    if not isinstance(ellipsoids, Mapping):
        raise InputError(
            "ellipsoids",
            "a mapping of name to pe.Ellipsoid",
            type(ellipsoids).__name__,
            "write e.g. ellipsoids={'mine': pe.Ellipsoid(center, axes, semi_axes)}.",
        )
    found: dict[str, Ellipsoid] = {}
    for name, E in ellipsoids.items():
        if not isinstance(name, str) or not CANDIDATE_NAME.fullmatch(name):
            raise InputError(
                "ellipsoids",
                "names that are lower-case identifiers: a letter, then up to 31 letters, "
                "digits or '_'",
                repr(name)[:80],
                "rename it to a lower-case identifier, e.g. 'heavy_wrist'",
            )
        if name in _RESERVED or name in taken:
            raise InputError(
                "ellipsoids",
                f"names other than {', '.join(map(repr, (*_RESERVED, *taken)))}",
                repr(name),
                "rename it (each name is the prefix of its result columns).",
            )
        argument = f"ellipsoids[{name!r}]"
        if not isinstance(E, Ellipsoid):
            raise InputError(
                argument,
                "a pe.Ellipsoid",
                type(E).__name__,
                "wrap it as pe.Ellipsoid(center, axes, semi_axes) or pe.Ellipsoid.from_core(c, N)",
            )
        if E.ambient_dim != P.ambient_dim:
            raise InputError(
                argument,
                f"an ellipsoid of the set's {P.ambient_dim}-dimensional space",
                f"one of a {E.ambient_dim}-dimensional space",
                f"give it a center of length {P.ambient_dim} and axes of shape "
                f"({P.ambient_dim}, r), in the set's coordinates",
            )
        try:
            check_same_affine_set(E, P)
        except InputError as exn:
            raise InputError(
                argument,
                exn.expected,
                exn.got,
                f"give an ellipsoid of rank {P.dim} centred in the set's affine hull.",
            ) from None
        found[name] = E
    return found


class ScoredSet:
    """What every comparison has: records by kind, optimal ellipsoids, limits and a CSV.

    Subclasses set :attr:`polytope`, :attr:`directions` and :attr:`records` and define
    ``to_frame``: :class:`SetComparison` (a bare set) and
    :class:`~polyell.comparison.comparison.Comparison` (an analysis's set).
    """

    polytope: Polytope | HPolytope
    directions: Array
    records: Mapping[str, SetScores]
    kinds: tuple[str, ...]
    #: The record of one kind's scores.
    _record: type[SetScores] = SetScores

    def _keep(
        self,
        directions: Array,
        samples: int,
        seed: int,
        optima: dict[str, bool],
        candidates: tuple[Candidate, ...],
        ellipsoids: Mapping[str, Ellipsoid] | None,
    ) -> None:
        """Hold what the scores are computed from (the subclasses' constructors)."""
        self.directions = directions
        self._samples = samples
        self._seed = seed
        self._computed = optima
        self._candidates = {c.name: c for c in candidates}
        self._given = dict(ellipsoids or {})

    def ellipsoid(self, kind: str) -> Ellipsoid:
        """The ellipsoid scored under ``kind`` (raises where it is undefined)."""
        check_instance("kind", kind, str, f"pass one of the names {list(self.kinds)}.")
        if kind == "mvie":
            return self.mvie
        if kind == "outer":
            return self.outer
        if kind in self._given:
            return self._given[kind]
        return self._own_ellipsoid(kind)

    def _own_ellipsoid(self, kind: str) -> Ellipsoid:
        """A candidate's ellipsoid, or one the subclass defines (else an InputError)."""
        raise NotImplementedError

    def _found(self, kind: str) -> Ellipsoid | str:
        """The ellipsoid scored under ``kind``, or why it has no scores here."""
        if not self._computed.get(kind, True):
            return f"not computed ({kind}=False)"
        try:
            E = self.ellipsoid(kind)
        except (UndefinedEllipsoidError, SolverError) as exn:
            # A score that cannot be computed here is reported, never raised: a sweep's
            # other configurations must not depend on it.
            return str(exn)
        why = self._unscorable(E)
        if why:
            return why
        check_same_affine_set(E, self.polytope)
        return E

    def _unscorable(self, E: Ellipsoid) -> str:
        """Why ``E`` has no section of the set to score; empty where it has one."""
        return ""

    def _witnesses(
        self, ellipsoids: Mapping[str, Ellipsoid]
    ) -> dict[str, tuple[Array, Array]] | None:
        """Per kind, the witness map's ``W`` and ``W c + w`` (None: no arm, no witness)."""
        return None

    def _score(self) -> dict[str, SetScores]:
        """Every kind's scores: the array scorer's batch of one."""
        found = {kind: self._found(kind) for kind in self.kinds}
        ellipsoids = {kind: E for kind, E in found.items() if isinstance(E, Ellipsoid)}
        records = (
            score_records(
                self.polytope,
                ellipsoids,
                self.directions,
                self.polytope_limits,
                self._samples,
                self._seed,
                self._witnesses(ellipsoids),
            )
            if ellipsoids
            else {}
        )
        return {
            kind: self._record(kind=kind, defined=False, reason=E)
            if isinstance(E, str)
            else self._record(kind=kind, **records[kind])
            for kind, E in found.items()
        }

    def _row(self, names: Sequence[str]) -> dict[str, float]:
        """The polytope's numbers, then ``<kind>_<score>`` for the scores ``names``."""
        P = self.polytope
        row: dict[str, float] = {
            "polytope_dim": float(P.dim),
            "polytope_volume": P.volume,
            "polytope_ball_radius": P.ball_radius,
            "polytope_origin_radius": P.origin_radius,
        }
        for kind, record in self.records.items():
            row.update({f"{kind}_{name}": float(getattr(record, name)) for name in names})
        return row

    def __getitem__(self, kind: str) -> SetScores:
        if not isinstance(kind, str) or kind not in self.records:
            raise InputError(
                "kind",
                f"one of {list(self.records)}",
                repr(kind),
                f"use one of the kinds listed, e.g. cmp[{next(iter(self.records), 'mvie')!r}]",
            )
        return self.records[kind]

    @cached_property
    def mvie(self) -> Ellipsoid:
        """The maximum-volume inscribed ellipsoid (the ceiling for inscribed ellipsoids)."""
        return max_volume_inscribed_ellipsoid(self.polytope)

    @cached_property
    def outer(self) -> Ellipsoid:
        """The minimum-volume enclosing ellipsoid (the floor for enclosing ones)."""
        return min_volume_enclosing_ellipsoid(self.polytope)

    @cached_property
    def polytope_limits(self) -> DirectionalLimits:
        """Directional limits of the set on :attr:`directions`."""
        return self.polytope.limits(self.directions)

    def to_frame(self) -> pd.DataFrame:
        """One row per ellipsoid, one column per score (full precision)."""
        raise NotImplementedError

    def to_csv(self, path: str | os.PathLike[str] | None = None) -> str:
        """The scores at full precision as CSV; also written to ``path`` if given.

        The file is written atomically (a temporary name, then renamed): a failed write
        (a full disk) leaves any earlier file whole.  ``pandas.read_csv(path,
        index_col="kind")`` reads back the same columns and values.

        Raises
        ------
        InputError
            If ``path`` is not a file name.
        StorageError
            If the file cannot be written (a missing folder, a name too long, a full disk).
        """
        buffer = io.StringIO()
        # Text fields quoted: a reason holding a bare carriage return (which the csv module
        # leaves unquoted with "\n" line ends) would otherwise split its row in two.
        self.to_frame().to_csv(buffer, quoting=csv.QUOTE_NONNUMERIC)
        text = buffer.getvalue()
        if path is not None:
            if not isinstance(path, str | os.PathLike):
                raise InputError(
                    "path",
                    "a file name (str or Path)",
                    type(path).__name__,
                    "pass e.g. path='scores.csv', or leave it out to get the text only",
                )
            write_text_atomically(Path(path), text)
        return text


class SetComparison(ScoredSet):
    """Scores of the MVIE, the outer ellipsoid and given ellipsoids against a bare set.

    Build it with :func:`polyell.compare` of a set.  ``cmp["mvie"]`` is a
    :class:`SetScores`.  There is no arm behind the set: no ellipsoid definitions
    (``chiacchio``, ``yoshikawa``, ``static``) and no witness column.

    Attributes
    ----------
    polytope : Polytope or HPolytope
        The set scored against.
    directions : ndarray, shape (k, m)
        The unit directions of the directional statistics.
    kinds : tuple of str
        The scored ellipsoids: ``"mvie"``, ``"outer"``, the candidates', then the given
        ellipsoids' names.
    records : dict of str to SetScores
    unit : str
        The unit of the set's coordinates, for tables (``compare(..., unit="N")``); ``""``
        unless given, which the table headers write as ``units``.
    """

    def __init__(
        self,
        polytope: Polytope | HPolytope,
        directions: Array,
        *,
        samples: int = 2**13,
        seed: int = 0,
        mvie: bool = True,
        outer: bool = True,
        candidates: tuple[Candidate, ...] = (),
        ellipsoids: Mapping[str, Ellipsoid] | None = None,
        unit: str = "",
    ) -> None:
        self.polytope = polytope
        self.unit = unit
        self._keep(directions, samples, seed, {"mvie": mvie, "outer": outer}, candidates,
                   ellipsoids)  # fmt: skip
        self.kinds = (*SET_KINDS, *self._candidates, *self._given)
        self.records: dict[str, SetScores] = self._score()

    def __repr__(self) -> str:
        return f"SetComparison({self.polytope!r}, directions={len(self.directions)})"

    def _own_ellipsoid(self, kind: str) -> Ellipsoid:
        if kind in self._candidates:
            return self._candidates[kind].section(self.polytope)
        raise InputError(
            "kind",
            f"one of {list(self.kinds)}",
            repr(kind),
            f"use one of the kinds listed, e.g. ellipsoid({self.kinds[0]!r})",
        )

    def to_row(self) -> dict[str, float]:
        """One flat record: ``polytope_dim``, ``polytope_volume``, the radii, ``<kind>_<score>``.

        As ``Comparison.to_row`` without the witness columns.
        """
        return self._row(SET_SCORE_NAMES)

    def to_frame(self) -> pd.DataFrame:
        """One row per ellipsoid, one column per score (full precision, no witness column)."""
        import pandas as pd

        return pd.DataFrame([r.as_dict() for r in self.records.values()]).set_index("kind")

    def _table(self, style: str, layout: TableLayout | None, **kwargs: Any) -> str:
        from polyell.comparison.tables import format_scores_table

        return format_scores_table(
            self.to_frame(),
            self.polytope.dim,
            style,  # type: ignore[arg-type]
            unit=self.unit or "units",  # (no unit given: "volume [(units)^2]")
            layout=layout,
            **kwargs,
        )

    def to_markdown(self, layout: TableLayout | None = None) -> str:
        """The comparison table in Markdown (rounded; :attr:`unit` in the headers).

        The scores of :class:`SetScores` (no witness row), one column per ellipsoid;
        ``layout`` chooses sets, scores, orientation and rounding (default
        ``TableLayout()``).
        """
        return self._table("markdown", layout)

    def to_latex(
        self,
        caption: str | None = None,
        label: str | None = None,
        layout: TableLayout | None = None,
    ) -> str:
        """The comparison table in LaTeX (booktabs), with an optional caption and label."""
        return self._table("latex", layout, caption=caption, label=label)

    def limits_table(
        self,
        directions: Sequence[DirectionSpec] | None = None,
        *,
        sets: Sequence[str] | None = None,
    ) -> pd.DataFrame:
        """Directional limits of the set and every ellipsoid, and their errors.

        As ``Comparison.limits_table``: names are read against the set's ``task`` (``x, y,
        z`` up to three rows, the rows of a frame for six); the ``unit`` column holds
        :attr:`unit`.
        """
        from polyell.comparison.limits import _limit_rows

        P = self.polytope
        found = resolve_directions(directions, P.task or default_task(P.ambient_dim))
        return _limit_rows(self, found, sets, self.unit)
