"""``compare``: every score of every ellipsoid against the exact polytope, as a table."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities import Analysis, capacity_class
from polyell.comparison.candidates import BUILT_IN_KINDS, Candidate, check_candidates
from polyell.comparison.directions import DirectionSpec, direction_vectors
from polyell.comparison.layout import TableLayout
from polyell.comparison.set_comparison import (
    ScoredSet,
    SetComparison,
    SetScores,
    check_bare_set,
    check_given_ellipsoids,
)
from polyell.comparison.tables import format_comparison_table
from polyell.errors import InputError
from polyell.geometry.directions import directions_in
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.polytope import Polytope
from polyell.models.task import default_task
from polyell.validation import check_array, check_instance, check_integer

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "COMPARED_KINDS",
    "SCORE_NAMES",
    "Comparison",
    "Scores",
    "SetComparison",
    "SetScores",
    "compare",
    "compared_kinds",
]

#: The sampling budget of a share estimate (``cap_union_share``): at least 2, at most 2^22
#: (where three caps meet, ``samples`` directions of r floats per replicate and row).
MIN_SAMPLES, MAX_SAMPLES = 2, 2**22
#: Largest seed (numpy's generators take any non-negative integer; 2^63 - 1 fits every
#: file format a study writes).
MAX_SEED = 2**63 - 1

#: The ellipsoids every comparison of accelerations scores: both definitions, the
#: maximum-volume inscribed one and the minimum-volume enclosing (outer) one; user-defined
#: candidates follow them.  Other capacities: :func:`compared_kinds`.
COMPARED_KINDS = BUILT_IN_KINDS


def compared_kinds(capacity: str = "acceleration") -> tuple[str, ...]:
    """The ellipsoids a comparison of a capacity scores: its own kinds, the MVIE, the outer."""
    return (*capacity_class(capacity).ellipsoid_kinds, "mvie", "outer")


@dataclass(frozen=True)
class Scores(SetScores):
    r"""How well one ellipsoid describes the exact polytope (DESIGN.md section 2).

    The scores of :class:`~polyell.comparison.set_comparison.SetScores` (a bare set's), and
    the witness of the arm's own inverse map.

    Attributes
    ----------
    kind : str
        ``"chiacchio"``, ``"yoshikawa"``, ``"mvie"``, ``"outer"`` or a candidate's name.
    defined : bool
        False where the definition does not exist at this configuration (then every
        score is NaN and ``reason`` says why).
    reason : str
        Why the ellipsoid is undefined; empty otherwise.
    dimension : float
        Its dimension r (rank), equal to the polytope's.
    volume : float
        Volume of the ellipsoid in its affine set [(m/s^2)^r].
    inscribed_scale : float
        Largest k with ``c + k (E - c)`` inside P; >= 1 iff E is inside P; negative when
        even E's centre c lies outside P (no copy of E scaled about c fits: the ellipsoids
        are centred at ``x_g``, which a horizon's joint limits can leave outside the set;
        a candidate centred elsewhere): minus the farthest c lies beyond a facet plane of P,
        in E's reach along that facet's normal.
    enclosing_scale : float
        Smallest k with P inside ``c + k (E - c)``; <= 1 iff E contains P (the outer
        ellipsoid: exactly 1).
    coverage, overreach : float
        ``vol(E & P) / vol(P)`` and ``vol(E \ P) / vol(E)``; for an ellipsoid containing
        P (the outer one) coverage is 1 and overreach ``1 - vol(P) / vol(E)``, how much it
        overstates.
    coverage_stderr, overreach_stderr : float
        Standard errors of those two (0 when exact).
    mvie_ratio : float
        ``vol(E) / vol(E*)`` with E* the maximum-volume inscribed ellipsoid (the inner
        optimum).
    outer_ratio : float
        ``vol(E) / vol(E_outer)`` with E_outer the minimum-volume enclosing ellipsoid (the
        outer optimum).
    direction_error_mean, direction_error_max, direction_error_rms : float
        Mean, max and RMS of ``|hi_E - hi_P| / |hi_P|`` over the directions.  Along a ray
        of an unbounded force set (``hi_P = inf``) the error is its limit, -1: the
        ellipsoid states none of the unbounded reach (such directions are counted).
    direction_bias : float
        Mean of ``(hi_E - hi_P) / |hi_P|`` (> 0: E promises too much).
    feasibility_mismatch : int
        Directions where exactly one of E and P has an empty interval.
    directions_used : int
        Directions that entered the directional statistics.
    witness_torque_max : float
        Max ``|tau_n|_inf`` over E's boundary mapped by the definition's own inverse
        (eq. 26 for yoshikawa, eq. 33/40 for chiacchio, the MVIE, the outer ellipsoid,
        candidates and given ellipsoids); > 1 means that inverse breaks the torque limits
        somewhere on E.
    """

    witness_torque_max: float = np.nan


#: The score attributes, in table order.
SCORE_NAMES = tuple(
    f.name for f in dataclasses.fields(Scores) if f.name not in ("kind", "defined", "reason")
)


class Comparison(ScoredSet):
    """Scores of both ellipsoid definitions, the MVIE, the outer ellipsoid and candidates.

    Build it with :func:`compare`.  ``cmp["chiacchio"]`` is a :class:`Scores`.

    Attributes
    ----------
    analysis : Analysis
    directions : ndarray, shape (k, m)
        The unit directions of the directional statistics.
    kinds : tuple of str
        The scored ellipsoids: :data:`COMPARED_KINDS`, the candidates', then the given
        ellipsoids' names.
    """

    _record = Scores

    def __init__(
        self,
        analysis: Analysis,
        directions: NDArray[np.float64],
        *,
        samples: int = 2**13,
        seed: int = 0,
        mvie: bool = True,
        outer: bool = True,
        candidates: tuple[Candidate, ...] = (),
        ellipsoids: Mapping[str, Ellipsoid] | None = None,
    ) -> None:
        check_instance("analysis", analysis, Analysis, "use pe.compare(pe.analyze(...)).")
        m = analysis.m
        directions = check_array("directions", directions, (None, m), what="unit directions")
        self.analysis = analysis
        self._keep(directions, samples, seed, {"mvie": mvie, "outer": outer}, candidates,
                   ellipsoids)  # fmt: skip
        self.kinds = (*compared_kinds(analysis.capacity), *self._candidates, *self._given)
        self.records = cast(dict[str, Scores], self._score())

    def __getitem__(self, kind: str) -> Scores:
        return cast(Scores, super().__getitem__(kind))

    def __repr__(self) -> str:
        return f"Comparison({self.analysis!r}, directions={len(self.directions)})"

    @property
    def polytope(self) -> Any:  # type: ignore[override]
        """The analysis's exact set (:attr:`Analysis.polytope`)."""
        return self.analysis.polytope

    def _own_ellipsoid(self, kind: str) -> Ellipsoid:
        if kind in self._candidates:
            return self._candidates[kind].ellipsoid(self.analysis)
        return self.analysis.ellipsoid(kind)

    def _found(self, kind: str) -> Ellipsoid | str:
        """The ellipsoid scored under ``kind``, or why it has no scores here."""
        if self._computed.get(kind, True) and getattr(self.polytope, "is_empty", False):
            why = getattr(self.analysis, "empty_reason", None) or (
                "the arm cannot hold itself against gravity within its limits here"
            )
            return f"the exact {self.analysis.capacity} set is empty: {why}."
        return super()._found(kind)

    def _unscorable(self, E: Ellipsoid) -> str:
        P = self.analysis.polytope
        if E.rank > P.dim and isinstance(P, HPolytope):  # a zonotope has its ellipsoids' rank
            cause = (  # a horizon's joint intervals pin joints; else the torques' own edge
                "joints pinned by their limits over the horizon"
                if getattr(self.analysis, "state", None) is not None
                else "gravity alone nearly exhausts some torque range: the set is flat to rounding"
            )
            return (
                f"the exact {self.analysis.capacity} set is {P.dim}-dimensional here "
                f"({cause}), the ellipsoid {E.rank}-dimensional: no section of it to score."
            )
        return ""

    def _witnesses(self, ellipsoids: Mapping[str, Ellipsoid]) -> dict[str, tuple[Any, Any]]:
        witnesses = {}
        for kind, E in ellipsoids.items():
            torques = self.analysis.witness_map(kind)
            witnesses[kind] = (torques.matrix, torques(E.center))
        return witnesses

    def to_row(self) -> dict[str, float]:
        """One flat record of the polytope's numbers and every ``<kind>_<score>``.

        ``polytope_dim``, ``polytope_volume``, the isotropic radii ``polytope_ball_radius``
        (about xg) and ``polytope_origin_radius`` (about the origin), then the column naming
        of study results (e.g. ``chiacchio_coverage``).
        """
        return self._row(SCORE_NAMES)

    def to_frame(self) -> pd.DataFrame:
        """One row per ellipsoid, one column per score (full precision)."""
        import pandas as pd

        frame = pd.DataFrame([r.as_dict() for r in self.records.values()]).set_index("kind")
        frame.attrs["capacity"] = self.analysis.capacity  # for the labels of its tables
        return frame

    def to_long(self) -> pd.DataFrame:
        """The scores in long form, one row per kind (:func:`polyell.to_long`)."""
        from polyell.comparison.long_form import to_long

        return to_long(self.to_row(), capacity=self.analysis.capacity, kinds=self.kinds)

    def to_markdown(self, layout: TableLayout | None = None) -> str:
        """The comparison table in Markdown (rounded, units in the headers).

        ``layout`` chooses the sets, scores, orientation and rounding (default
        ``TableLayout()``); the LaTeX, CSV and HTML forms are
        :func:`~polyell.comparison.tables.format_comparison_table`.
        """
        return format_comparison_table(self, "markdown", layout=layout)

    def to_latex(
        self,
        caption: str | None = None,
        label: str | None = None,
        layout: TableLayout | None = None,
    ) -> str:
        """The comparison table in LaTeX (booktabs), with an optional caption and label."""
        return format_comparison_table(self, "latex", layout=layout, caption=caption, label=label)

    def limits_table(
        self,
        directions: Sequence[DirectionSpec] | None = None,
        *,
        sets: Sequence[str] | None = None,
    ) -> pd.DataFrame:
        """Directional limits of the polytope and every ellipsoid, and their errors.

        Parameters
        ----------
        directions : list, optional
            Names made of the task's rows (``"x"``, ``"-z"``, ``"xy"`` for the unit
            diagonal, ``"x-y"``) or unit vectors
            (:func:`~polyell.comparison.directions.named_direction`).  Default: the task's
            coordinate axes (an interval holds both ends: ``-x`` adds nothing to ``x``).
        sets : list of str, optional
            Among ``"polytope"``, the kinds of :attr:`kinds`; default: the polytope and
            every ellipsoid computed.

        Returns
        -------
        DataFrame
            One row per direction and set (directions first) with the columns
            ``direction``, ``set``, ``defined``, ``lower``, ``upper`` [``unit``],
            ``lower_error``, ``upper_error`` (fractions ``(e - p) / |p|`` against the
            polytope's same end, NaN where either end is missing or the polytope's is 0)
            and ``unit``; see :func:`polyell.limits_table` for several postures and
            :func:`~polyell.comparison.tables.format_limits_table` to print it.

        Examples
        --------
        >>> import numpy as np, polyell as pe
        >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
        >>> q = [np.pi / 2, -np.pi / 2, -np.pi / 2]
        >>> cmp = pe.compare(pe.analyze(arm.dynamics(q), tau_max=[100, 30, 4]), 16)
        >>> table = cmp.limits_table(["x", "-y"], sets=["polytope", "chiacchio"])
        >>> table[["direction", "set"]].values.tolist()
        [['x', 'polytope'], ['x', 'chiacchio'], ['-y', 'polytope'], ['-y', 'chiacchio']]
        """
        from polyell.comparison.limits import limits_frame

        return limits_frame(self, directions, sets=sets)


@overload
def compare(
    analysis: Analysis,
    directions: ArrayLike | int | None = None,
    *,
    samples: int = 2**13,
    seed: int = 0,
    mvie: bool = True,
    outer: bool = True,
    candidates: Sequence[Candidate] = (),
    ellipsoids: Mapping[str, Ellipsoid] | None = None,
    unit: str | None = None,
) -> Comparison: ...


@overload
def compare(
    analysis: Polytope | HPolytope,
    directions: ArrayLike | int | None = None,
    *,
    samples: int = 2**13,
    seed: int = 0,
    mvie: bool = True,
    outer: bool = True,
    candidates: Sequence[Candidate] = (),
    ellipsoids: Mapping[str, Ellipsoid] | None = None,
    unit: str | None = None,
) -> SetComparison: ...


def compare(
    analysis: Analysis | Polytope | HPolytope,
    directions: ArrayLike | int | None = None,
    *,
    samples: int = 2**13,
    seed: int = 0,
    mvie: bool = True,
    outer: bool = True,
    candidates: Sequence[Candidate] = (),
    ellipsoids: Mapping[str, Ellipsoid] | None = None,
    unit: str | None = None,
) -> Comparison | SetComparison:
    """Score the ellipsoids of an analysis, or of any convex set the library builds.

    Of an :class:`Analysis`: both ellipsoid definitions of its capacity, the MVIE, the
    outer ellipsoid, candidates and given ellipsoids, each with its torque (or joint
    velocity) witness: a :class:`Comparison`.  Of a bare set -- a :class:`~polyell.Polytope`
    or :class:`~polyell.HPolytope` such as the sum or intersection of two arms' sets
    (:mod:`polyell.geometry.combine`) or an analysis's polytope on its own -- the MVIE, the
    outer ellipsoid, core-defined candidates and given ellipsoids, with the same scorer:
    a :class:`~polyell.comparison.set_comparison.SetComparison`, whose records
    (:class:`~polyell.comparison.set_comparison.SetScores`) and tables have no witness
    (there is no arm whose joint limits it would test).

    Parameters
    ----------
    analysis : Analysis, Polytope or HPolytope
        From :func:`analyze`, or a non-empty bounded set of dimension >= 1.
    directions : array-like of shape (k, m), list of names, int, or None
        Unit directions for the directional statistics (vectors, or names of the task's
        rows such as ``"x"``, ``"-z"``, ``"xy"``; a bare set reads names against its
        ``task``, else ``x, y, z`` up to three rows), or how many of the default
        deterministic near-uniform set to use.  The default set lies in the polytope's
        affine set (at a singular configuration every other line meets it in one point);
        its default size is 360 in 2-D, 256 in 3-D, 2,000 above
        (:func:`~polyell.geometry.directions.default_direction_count`).
    samples : int, optional
        Sampling budget where an ellipsoid leaves the polytope and two of its caps beyond
        the facets meet (else its coverage is exact): ``samples / 512`` heights per pair of
        caps and replicate, ``samples`` directions where three caps meet
        (:func:`~polyell.comparison.caps.cap_union_share`), from 2 to 2^22.
    seed : int, optional
        Seed of those estimates, a non-negative integer.
    mvie : bool, optional
        Whether to compute the maximum-volume inscribed ellipsoid (a log-det program);
        without it the ``"mvie"`` record and every ``mvie_ratio`` are NaN.
    outer : bool, optional
        Whether to compute the minimum-volume enclosing ellipsoid (the same program on the
        vertices); without it the ``"outer"`` record and every ``outer_ratio`` are NaN.
    candidates : sequence of Candidate, optional
        User-defined ellipsoids, scored after the built-in ones under their names (of a
        bare set: core-defined ones only, centred at the set's ``center`` unless they
        give a centre).
    ellipsoids : mapping of str to Ellipsoid, optional
        Ellipsoids given as they are, scored last under their names (lower-case
        identifiers, not a built-in kind); each must span the set's affine set (rank
        ``P.dim``, centre in its affine hull).  Of an analysis, their witness is the
        capacity's minimum-norm inverse, as the MVIE's.
    unit : str, optional
        The unit of a bare set's coordinates for its tables (e.g. ``"N"``); an analysis
        knows its own (give None).

    Returns
    -------
    Comparison or SetComparison

    Raises
    ------
    InputError
        Naming the argument: ``analysis`` of another type, an empty, unbounded or point
        set; ``directions``, ``candidates``, ``ellipsoids`` (``ellipsoids['name']``),
        ``samples``, ``seed``, ``mvie``, ``outer``, ``unit``.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
    >>> an = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), tau_max=[100, 30, 4])
    >>> cmp = pe.compare(an)
    >>> cmp["chiacchio"].inscribed_scale >= 1.0, cmp["yoshikawa"].witness_torque_max > 1.0
    (True, True)

    A bare set: its MVIE, its outer ellipsoid and an ellipsoid of one's own.

    >>> box = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 2, 2])
    >>> disc = pe.Ellipsoid([0.0, 0.0], np.eye(2), [1.0, 1.0])
    >>> cmp = pe.compare(box, ellipsoids={"disc": disc}, unit="N")
    >>> cmp.kinds, round(cmp["disc"].inscribed_scale, 12), round(cmp["outer"].coverage, 12)
    (('mvie', 'outer', 'disc'), 1.0, 1.0)
    """
    if isinstance(directions, bool | np.bool_):
        raise InputError(
            "directions",
            "unit directions (k, m), a count or None",
            repr(directions),
            "pass a count, e.g. directions=1000, or leave it out for the default",
        )
    samples = check_integer("samples", samples, MIN_SAMPLES, MAX_SAMPLES)
    seed = check_integer("seed", seed, 0, MAX_SEED)
    for name, flag in (("mvie", mvie), ("outer", outer)):
        if not isinstance(flag, bool | np.bool_):
            raise InputError(
                name,
                "True or False",
                repr(flag),
                f"pass {name}=True to compute it or {name}=False to skip it",
            )
    found = check_candidates(candidates)
    if not isinstance(analysis, Analysis):
        P = check_bare_set(analysis)
        if unit is None:
            unit = ""
        if not isinstance(unit, str):
            raise InputError(
                "unit",
                "a unit name (str), e.g. 'N'",
                type(unit).__name__,
                "pass the set's unit as a str, e.g. unit='N', or leave it out",
            )
        for candidate in found:
            if candidate.weighting is not None:
                raise InputError(
                    f"candidates ({candidate.name!r})",
                    "core-defined candidates (a bare set has no arm whose torques a weighting "
                    "would weigh)",
                    "a weighted candidate",
                    "give core= and center=, or compare the analysis itself.",
                )
            candidate.check_sizes(P.ambient_dim, 0)
        given = check_given_ellipsoids(ellipsoids, P, [c.name for c in found])
        return SetComparison(
            P,
            _directions(directions, P, P.task),
            samples=samples,
            seed=seed,
            mvie=bool(mvie),
            outer=bool(outer),
            candidates=found,
            ellipsoids=given,
            unit=unit,
        )
    if unit is not None:
        raise InputError(
            "unit",
            "None for an analysis (it knows its unit)",
            repr(unit)[:80],
            "drop unit=; it names the coordinates of a bare set.",
        )
    for candidate in found:
        candidate.check_sizes(analysis.m, analysis.n)
    taken = [*compared_kinds(analysis.capacity), *(c.name for c in found)]
    given = check_given_ellipsoids(ellipsoids, analysis.polytope, taken)
    return Comparison(
        analysis,
        _directions(directions, analysis.polytope, analysis.task),
        samples=samples,
        seed=seed,
        mvie=bool(mvie),
        outer=bool(outer),
        candidates=found,
        ellipsoids=given,
    )


def _directions(
    directions: ArrayLike | int | None,
    P: Polytope | HPolytope,
    task: Sequence[str] | None,
) -> NDArray[np.float64]:
    """The directions of ``compare``: a count (or None) of the default set, or given ones."""
    if directions is None or isinstance(directions, int | np.integer):
        return directions_in(P.affine_set, None if directions is None else int(directions))
    rows = tuple(task) if task is not None else default_task(P.ambient_dim)
    return np.atleast_2d(direction_vectors(directions, rows, "directions"))
