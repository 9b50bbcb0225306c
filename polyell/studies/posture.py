r"""Which posture? Choosing a redundant arm's posture by an ellipsoid, against the polytope.

A redundant arm reaches one task point in a continuum of postures (its self-motion,
:func:`polyell.self_motion`); an ellipsoid index picks the posture that maximises it.
:func:`posture_choice` measures, over a set of postures, every index of every set --
the exact polytope (the truth), both ellipsoid definitions, the MVIE, the outer ellipsoid
and user candidates -- and says how much of the truth each index's pick loses
(DESIGN.md section 7).  The criteria, each the larger the better:

* ``"limit"``: :math:`\min(-lo, hi)` of the interval :math:`[lo, hi]` of accelerations
  along the task direction d, what is available both ways (0 when the interval misses the
  origin: gravity alone pushes the arm along d);
* ``"radius"``: the radius of the largest ball about the origin inside the set, the
  acceleration available in every direction from rest (0 when the origin is outside, and
  at a singular posture, where the set is flat);
* ``"volume"``: the set's m-dimensional volume [(task unit)^m] (0 at a singular posture).

The batch path is :func:`polyell.studies.batch.block_sets` (the sets of a sweep, computed
once) with :func:`polyell.limits_along` for the intervals of the polytope and both
definitions; postures the batch does not cover (singular or near it, an uncertified MVIE)
take the scalar path of :func:`polyell.analyze`.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities import capacity_class, check_capacity, joint_limits_of, state_of
from polyell.capacities.horizon import horizon_block, refuse_without_horizon, robot_horizon
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.comparison.candidates import Candidate, check_candidates
from polyell.comparison.directions import named_direction
from polyell.comparison.latex_text import unit_power
from polyell.comparison.scores import polytope_columns
from polyell.errors import InputError, SolverError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid, unit_ball_volume
from polyell.geometry.inradius import ellipsoid_origin_radius
from polyell.geometry.limits import line_interval_in_ellipsoids
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from polyell.geometry.outer import min_volume_enclosing_ellipsoid
from polyell.geometry.subspace import RANK_RTOL
from polyell.models.self_motion import SelfMotion
from polyell.studies.along import analysis_within, limits_along
from polyell.studies.batch import BatchOptions, block_sets, block_size
from polyell.validation import (
    check_array,
    check_directions,
    check_fraction,
    check_frame,
    check_points,
)

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = ["CRITERIA", "QUANTITIES", "PostureChoice", "choice_table", "posture_choice"]

Array = NDArray[np.float64]

#: The criteria of a choice, each the larger the better.
CRITERIA = ("limit", "radius", "volume")
#: The per-posture quantities of each set: the interval along d, then the criteria.
QUANTITIES = ("lo", "hi", *CRITERIA)
#: The columns of a choice table (with the postures, ``q1 .. qn`` follow ``picked``; with
#: the unit, ``unit`` follows ``true_best``).
TABLE_COLUMNS = ("picked", "true_at_pick", "true_best", "regret", "spearman", "kendall")
#: Fewest postures a choice compares (a rank correlation needs two).
MIN_POSTURES = 2


@dataclass(frozen=True, repr=False)
class PostureChoice:
    """Every index of every set over a set of postures, and what choosing by each costs.

    Attributes
    ----------
    table : DataFrame
        Indexed by (kind, criterion), kind in ``polytope`` (the truth), ``chiacchio``,
        ``yoshikawa``, ``mvie``, ``outer`` and the candidates' names (those computed),
        criterion in :data:`CRITERIA`.  Columns: ``picked`` (the row of
        ``configurations`` the index maximises; <NA> if it is undefined everywhere),
        ``q1`` .. ``qn`` (that posture's joint positions [rad, or m for a prismatic joint];
        NaN without a pick), ``true_at_pick`` (the polytope's value of the criterion there),
        ``true_best`` (its maximum over the postures), ``unit`` (theirs: :attr:`unit` for
        ``limit`` and ``radius``, its m-th power ``(unit)^m`` for ``volume``), ``regret``
        (``1 - true_at_pick / true_best``, in [0, 1]; 0 when the truth is 0 everywhere or
        the pick is the best, an unbounded force set's infinite volume included; 1 for a
        finite pick beside it),
        ``spearman`` and ``kendall`` (rank correlations of the index with the truth over
        the postures where both are defined; NaN when either is constant).
    values : DataFrame
        One row per posture; columns (kind, quantity), quantity in :data:`QUANTITIES`:
        ``lo``, ``hi`` (the interval along d, NaN if empty or undefined), ``limit``,
        ``radius``, ``volume`` (NaN where the set is undefined: the classic ellipsoid at
        a singular posture, an MVIE the solver could not certify).
    direction : ndarray, shape (m,)
        The unit task direction d.
    configurations : ndarray, shape (k, n)
        The postures [rad or m].
    unit : str
        The capacity's task unit (``m/s^2`` or ``rad/s^2`` for accelerations, ``m/s`` or
        ``rad/s`` for velocities, ``N`` or ``N m`` for forces, or ``weighted units``): the
        unit of the limit and the radius; the volume's is its m-th power (the table's
        ``unit`` column).
    """

    table: pd.DataFrame
    values: pd.DataFrame
    direction: Array
    configurations: Array
    unit: str

    def __repr__(self) -> str:
        """A line: the capacity, the postures, the sets, the direction and the unit."""
        kinds = list(dict.fromkeys(self.values.columns.get_level_values(0)))
        direction = np.array2string(np.asarray(self.direction), precision=4, separator=", ")
        capacity = self.table.attrs.get("capacity", "acceleration")
        k, n = np.shape(self.configurations)
        return (
            f"PostureChoice(capacity={capacity!r}, postures={k}, joints={n}, "
            f"sets={kinds}, direction={direction}, unit={self.unit!r})"
        )


def _check_flag(name: str, value: object) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise InputError(name, "True or False", repr(value), f"pass {name}=True or {name}=False.")
    return bool(value)


def check_direction(direction: ArrayLike, m: int) -> Array:
    """A unit task direction of m entries (the rule of every direction in polyell).

    As ``Polytope.limits``: a vector of unit length (to
    :data:`~polyell.validation.DIRECTION_NORM_RTOL`), refused otherwise with the fix.
    """
    d = check_points("direction", direction, m)
    if d.ndim != 1:
        raise InputError(
            "direction",
            f"one task direction of {m} entries",
            f"shape {d.shape}",
            "give one vector, e.g. [1, 0], or a name of the task rows such as 'x'.",
        )
    unit: Array = check_directions("direction", d, m)
    return unit


def posture_choice(
    robot: Any,
    configurations: ArrayLike | SelfMotion,
    tau_max: ArrayLike | None = None,
    tau_min: ArrayLike | None = None,
    *,
    direction: ArrayLike,
    mvie: bool = True,
    outer: bool = True,
    candidates: Sequence[Candidate] = (),
    rank_rtol: float = RANK_RTOL,
    capacity: str = "acceleration",
    qd_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    horizon: float | None = None,
    q_min: ArrayLike | None = None,
    q_max: ArrayLike | None = None,
    braking: ArrayLike | None = None,
    progress: bool = False,
) -> PostureChoice:
    """Which posture each index picks, and how much of the truth (the polytope) it loses.

    Parameters
    ----------
    robot : PlanarArm or UrdfRobot
        Anything with ``dynamics(q)`` for a (k, n) batch (and its own torque limits when
        none are given).
    configurations : array-like, shape (k, n), or SelfMotion
        The postures to choose from [rad or m], at least 2, e.g. from
        :func:`polyell.self_motion`.
    tau_max, tau_min : array-like, shape (n,), optional
        Torque limits [N m]; default the robot's own.
    direction : str or array-like, shape (m,)
        The task direction d of the ``"limit"`` criterion: the accelerations exactly along
        d, ``{t d}`` with no sideways part, that the set holds (its interval [lo, hi] on
        that line, as ``Polytope.limits``), not how far the set reaches along d.  A name of
        the robot's task rows (:func:`~polyell.comparison.directions.named_direction`:
        ``"x"``, ``"-z"``, ``"xy"`` the unit diagonal, ``"wz"``), or a unit vector of m
        entries (refused otherwise, as by ``Polytope.limits``).
    mvie, outer : bool, optional
        Whether to include the maximum-volume inscribed and the minimum-volume enclosing
        ellipsoids (a batched log-det program each).
    candidates : sequence of Candidate, optional
        User-defined ellipsoids, under their names.
    rank_rtol : float, optional
        As in :func:`polyell.analyze`.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose sets and ellipsoids choose (:func:`polyell.analyze`): accelerations
        (default), end-effector velocities (the zonotope of the joint velocity box and its
        ellipsoid ``"yoshikawa"``, Yoshikawa's manipulability) or static forces (the
        H-polytope and ``"chiacchio"``, ``"yoshikawa"``, ``"static"``).  Velocities are
        computed a block of postures at once (the acceleration zonotope of ``B = I``,
        ``g = 0``), forces one posture at a time.
    qd_max, qd_min : array-like, shape (n,), optional
        Joint velocity limits of the velocity capacity, or of the horizon [rad/s]; default
        the robot's own.
    horizon : float, optional
        A control period [s] (accelerations): the truth is the set of accelerations that
        also keep every joint, at rest in the posture, within its position limits over
        the period (and its velocity limits at its end), as ``analyze(..., horizon=)``
        defines it; the ellipsoids ignore those limits.  Postures whose set they cut are
        computed one at a time.
    q_min, q_max, braking : array-like, shape (n,), optional
        With ``horizon``: position limits (default the robot's ``position_limits``) and the
        braking decelerations of viability (default none).
    progress : bool, optional
        A progress bar on standard error (tqdm), one step per posture scored, named after
        the capacity (``acceleration: scoring postures``), as :func:`polyell.sweep`'s.

    Returns
    -------
    PostureChoice
        The choice table and the per-posture values.

    Raises
    ------
    InputError
        For a robot without dynamics, configurations of the wrong shape or fewer than 2,
        a direction of the wrong size or zero, a name with a row the task does not have
        (the message lists the rows), torque limits that do not fit, a flag that
        is not a bool, candidates that do not fit the arm.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> motion = pe.self_motion(arm, [np.pi / 2, -np.pi / 2, -np.pi / 2], count=60)
    >>> choice = pe.posture_choice(arm, motion, direction=[1.0, 0.0], mvie=False, outer=False)
    >>> float(choice.table.loc[("polytope", "limit"), "regret"])
    0.0
    """
    if not hasattr(robot, "dynamics") or not hasattr(robot, "n"):
        raise InputError(
            "robot",
            "a robot with dynamics (pe.PlanarArm, pe.UrdfRobot)",
            type(robot).__name__,
            "load one with pe.robots.load('chiacchio2000') or pe.UrdfRobot(...).",
        )
    rank_rtol = check_fraction("rank_rtol", rank_rtol)
    mvie, outer = _check_flag("mvie", mvie), _check_flag("outer", outer)
    progress = _check_flag("progress", progress)
    if isinstance(configurations, SelfMotion):
        configurations = configurations.configurations
    q = check_array("configurations", configurations, ("K", robot.n), what="joint positions")
    if len(q) < MIN_POSTURES:
        raise InputError(
            "configurations",
            f"at least {MIN_POSTURES} postures to choose from",
            f"{len(q)}",
            "sample the self-motion with pe.self_motion(robot, q0, count=...).",
        )
    capacity = check_capacity(capacity)
    cls = capacity_class(capacity)
    state, within = None, cast(dict[str, Any], {})
    refuse_without_horizon(horizon, q_min=q_min, q_max=q_max, braking=braking)
    if horizon is not None:  # at rest in each posture
        state_of(cls, horizon)
        state = robot_horizon(robot, horizon, q_min, q_max, qd_min, qd_max, braking)
        state = state.at(q, np.zeros_like(q))
        within = state.arguments()
        del within["q"]  # (the postures themselves)
        qd_max = qd_min = None
    upper, lower = joint_limits_of(capacity, tau_max, tau_min, qd_max, qd_min)
    dyn = robot.dynamics(q)
    upper, lower = cls._source_limits(robot, upper, lower, dyn.n)
    if isinstance(direction, str):  # a name of the task rows: "x", "-z", "xy"
        d = named_direction(direction, dyn.task, "direction")[0]
    else:
        d = check_direction(direction, dyn.m)
    found = check_candidates(candidates)
    for candidate in found:
        candidate.check_sizes(dyn.m, dyn.n)
    definitions = cls.ellipsoid_kinds
    kinds = ["polytope", *definitions]
    kinds += [name for name, on in (("mvie", mvie), ("outer", outer)) if on]
    kinds += [candidate.name for candidate in found]
    K, m = len(dyn), dyn.m
    values = {kind: {name: np.full(K, np.nan) for name in QUANTITIES} for kind in kinds}

    limits = cls.limit_arguments(upper, lower)
    T = np.broadcast_to(d, (K, m))
    with posture_bar(K, f"{capacity}: scoring postures", progress) as bar:
        if state is None:
            along = limits_along(dyn, None, T, capacity=capacity, rank_rtol=rank_rtol, **limits)
        else:
            along = limits_along(robot, q, T, rank_rtol=rank_rtol, **limits, **within)
        for kind in ("polytope", *definitions):
            values[kind]["lo"][:], values[kind]["hi"][:] = along[kind]
        scalar = np.ones(K, dtype=bool)  # forces: one posture at a time
        block = False
        if issubclass(cls, ZonotopeAnalysis):  # a block at once, as acceleration zonotopes
            block = True
            scalar[:] = False
            _block_values(
                dyn, upper, lower, d, cls, found, values, scalar, mvie, outer, rank_rtol, bar
            )
        if state is not None:  # a set cut by the joints' intervals: one posture at a time
            scalar |= horizon_block(dyn, state, upper, lower).cut
        rows = np.flatnonzero(scalar)
        if block and len(rows):  # postures the batch left over: scored again, one by one
            bar.total += len(rows)
            bar.refresh()
        for k in rows:
            at = None if state is None else state[int(k)]
            analysis = analysis_within(dyn[int(k)], capacity, upper, lower, rank_rtol, at)
            _scalar_row(analysis, d, found, kinds, values, int(k))
            bar.update(1)
    defined = {kind: ~np.isnan(values[kind]["volume"]) for kind in kinds}
    for kind in kinds:
        lo, hi = values[kind]["lo"], values[kind]["hi"]
        with np.errstate(invalid="ignore"):
            limit = np.maximum(np.fmin(-lo, hi), 0.0)
        # an empty interval (NaN): nothing available; an unbounded one stays inf
        values[kind]["limit"] = np.where(
            defined[kind], np.where(np.isnan(limit), 0.0, limit), np.nan
        )
    import pandas as pd

    frame = pd.DataFrame(
        {(kind, name): values[kind][name] for kind in kinds for name in QUANTITIES}
    )
    frame.columns = pd.MultiIndex.from_tuples(frame.columns, names=["kind", "quantity"])
    frame.index.name = "posture"
    from polyell.models.task import task_unit

    unit = task_unit(dyn.task, capacity=capacity)
    table = choice_table(frame, configurations=q, unit=unit, dimension=m)
    frame.attrs["capacity"] = table.attrs["capacity"] = capacity  # the sets' labels
    q.flags.writeable = False
    d.flags.writeable = False
    return PostureChoice(table, frame, d, q, unit)


def _block_values(
    dyn: Any,
    upper: Array,
    lower: Array,
    d: Array,
    capacity: type[ZonotopeAnalysis],
    candidates: tuple[Candidate, ...],
    values: dict[str, dict[str, Array]],
    scalar: NDArray[np.bool_],
    mvie: bool,
    outer: bool,
    rank_rtol: float,
    bar: Any = None,
) -> None:
    """Radius and volume (and the intervals of the other ellipsoids) by the batch path.

    A velocity set is the acceleration zonotope of ``B = I``, ``g = 0`` and the joint
    velocity limits; its ellipsoid ``"yoshikawa"`` is that zonotope's ``"chiacchio"``.
    Marks in ``scalar`` the postures left to the scalar path.
    """
    K, m, n = len(dyn), dyn.m, dyn.n
    names = {kind: name for kind, name in capacity.acceleration_names.items() if kind != "polytope"}
    dyn = capacity._acceleration_dynamics(dyn)
    B, g, bias = dyn.B, dyn.g, dyn.xdd_bias
    options = BatchOptions(
        mvie=mvie, outer=outer, vertices=outer, candidates=candidates, rank_rtol=rank_rtol
    )
    size = block_size(m, n, outer)
    for start in range(0, K, size):
        block = slice(start, start + size)
        sets, flagged = block_sets(
            dyn.J[block], B[block], g[block], bias[block], upper, lower, options
        )
        scalar[block] = flagged
        if bar is not None:
            bar.update(len(dyn.J[block]))
        if sets is None:
            continue
        rows = sets.rows + start
        radius = polytope_columns(sets.as_set_batch())["polytope_origin_radius"]
        values["polytope"]["radius"][rows] = np.where(np.isnan(radius), 0.0, radius)
        values["polytope"]["volume"][rows] = sets.volume
        for kind, (axes, semi, _, center) in sets.ellipsoids.items():
            if kind in ("chiacchio", "yoshikawa") and kind not in names:
                continue  # the acceleration classic ellipsoid of a velocity zonotope
            name = names.get(kind, kind)
            centre = sets.xg if center is None else center
            certified = ~np.isnan(semi).any(axis=-1)
            scalar[rows[~certified]] = True  # (an MVIE the batch could not certify)
            ok = rows[certified]
            c, U, s = centre[certified], axes[certified], semi[certified]
            values[name]["radius"][ok] = ellipsoid_origin_radius(c, U, s)
            values[name]["volume"][ok] = unit_ball_volume(m) * np.prod(s, axis=-1)
            if kind not in names:  # the definitions' intervals come from limits_along
                lo, hi = line_interval_in_ellipsoids(c, U, s, d[None])
                values[name]["lo"][ok], values[name]["hi"][ok] = lo[:, 0], hi[:, 0]


def posture_bar(total: int, what: str, progress: bool, unit: str = " postures") -> Any:
    """A progress bar on standard error: ``total`` steps of ``what``, off without ``progress``.

    As :func:`polyell.sweep`'s (tqdm); a posture study shows it unless ``--quiet``.
    """
    from tqdm import tqdm

    return tqdm(total=total, desc=what, unit=unit, disable=not progress)


def _scalar_row(
    analysis: Any,
    d: Array,
    candidates: tuple[Candidate, ...],
    kinds: list[str],
    values: dict[str, dict[str, Array]],
    k: int,
) -> None:
    """Radius, volume (and intervals beyond the definitions) of one posture's analysis."""
    P = analysis.polytope
    m = P.ambient_dim
    full = P.dim == m
    radius = P.origin_radius
    values["polytope"]["radius"][k] = radius if full and radius == radius else 0.0
    values["polytope"]["volume"][k] = P.volume if full else 0.0
    for kind in kinds[1:]:
        try:
            E = _ellipsoid(analysis, kind, candidates)
        except (UndefinedEllipsoidError, SolverError):
            for name in QUANTITIES:
                values[kind][name][k] = np.nan
            continue
        if kind not in analysis.ellipsoid_kinds:
            values[kind]["lo"][k], values[kind]["hi"][k] = E.limits(d)
        if E.rank == m:
            values[kind]["radius"][k] = ellipsoid_origin_radius(
                E.center[None], E.axes[None], E.semi_axes[None]
            )[0]
            values[kind]["volume"][k] = E.volume
        else:  # flat: no ball and no m-dimensional volume
            values[kind]["radius"][k] = values[kind]["volume"][k] = 0.0


def _ellipsoid(analysis: Any, kind: str, candidates: tuple[Candidate, ...]) -> Ellipsoid:
    if kind in analysis.ellipsoid_kinds:
        return analysis.ellipsoid(kind)
    if kind == "mvie":
        return max_volume_inscribed_ellipsoid(analysis.polytope)
    if kind == "outer":
        return min_volume_enclosing_ellipsoid(analysis.polytope)
    return next(c for c in candidates if c.name == kind).ellipsoid(analysis)


def criterion_units(unit: str, dimension: int) -> dict[str, str]:
    """The unit of each criterion's values: the task's, and its m-th power for the volume.

    >>> criterion_units("m/s^2", 3)
    {'limit': 'm/s^2', 'radius': 'm/s^2', 'volume': '(m/s^2)^3'}
    """
    volume = unit_power(unit, dimension)
    return {"limit": unit, "radius": unit, "volume": volume}


def choice_table(
    values: pd.DataFrame,
    *,
    configurations: ArrayLike | None = None,
    unit: str | None = None,
    dimension: int | None = None,
) -> pd.DataFrame:
    """The choice table of per-posture values (the ``values`` of a :class:`PostureChoice`).

    Parameters
    ----------
    values : DataFrame
        One row per posture, columns (kind, criterion) with at least the ``polytope``'s.
    configurations : array-like, shape (k, n), optional
        The postures of ``values``' rows: the table then gives the picked posture's joint
        positions, columns ``q1`` .. ``qn`` after ``picked``.
    unit : str, optional
        The task's unit (:attr:`PostureChoice.unit`): the table then has a ``unit`` column
        after ``true_best``, the unit of each row's values (:func:`criterion_units`).
    dimension : int, optional
        With ``unit``: the task's dimension m, the power of the volume's unit.

    Returns
    -------
    DataFrame
        Indexed by (kind, criterion), the columns of :attr:`PostureChoice.table`.
    """
    check_frame("values", values, "pass choice.values of pe.posture_choice.")
    q = None
    if configurations is not None:
        q = check_array(
            "configurations", configurations, (len(values), "n"), what="joint positions"
        )
    units = None
    if unit is not None:
        if not isinstance(unit, str) or not unit:
            raise InputError(
                "unit",
                "the task's unit, such as 'm/s^2'",
                repr(unit)[:80],
                "pass the choice's unit (PostureChoice.unit), or leave unit out.",
            )
        if isinstance(dimension, bool) or not isinstance(dimension, int | np.integer):
            raise InputError(
                "dimension",
                "the task's dimension m (an integer)",
                repr(dimension),
                "pass the task's number of rows, e.g. dimension=2.",
            )
        if dimension < 1:
            raise InputError(
                "dimension",
                "the task's dimension m, at least 1",
                repr(dimension),
                "pass the task's number of rows, e.g. dimension=2.",
            )
        units = criterion_units(unit, int(dimension))
    import pandas as pd
    from scipy import stats

    kinds = list(dict.fromkeys(values.columns.get_level_values(0)))
    records = []
    for kind in kinds:
        for criterion in CRITERIA:
            index = values[(kind, criterion)].to_numpy(dtype=float)
            truth = values[("polytope", criterion)].to_numpy(dtype=float)
            best = float(np.nanmax(truth))
            if np.isnan(index).all():
                picked, at_pick, regret = pd.NA, np.nan, np.nan
            else:
                picked = int(np.nanargmax(index))
                at_pick = float(truth[picked])
                # at the best (an unbounded set's inf too): 0; beside an inf best: 1
                regret = 0.0 if at_pick == best or not best > 0 else 1.0 - at_pick / best
            both = ~np.isnan(index) & ~np.isnan(truth)
            with warnings.catch_warnings():  # a constant index or truth: NaN, said in the doc
                warnings.simplefilter("ignore", stats.ConstantInputWarning)
                warnings.simplefilter("ignore", RuntimeWarning)
                if both.sum() >= 2:
                    spearman = float(stats.spearmanr(index[both], truth[both]).statistic)
                    kendall = float(stats.kendalltau(index[both], truth[both]).statistic)
                else:
                    spearman = kendall = np.nan
            records.append((kind, criterion, picked, at_pick, best, regret, spearman, kendall))
    table = pd.DataFrame.from_records(records, columns=["kind", "criterion", *TABLE_COLUMNS])
    table["picked"] = table["picked"].astype("Int64")
    if q is not None:  # the picked posture's joint positions, beside its row number
        rows = table["picked"].to_numpy(dtype=float, na_value=np.nan)
        joints = np.full((len(table), q.shape[1]), np.nan)
        chosen = ~np.isnan(rows)
        joints[chosen] = q[rows[chosen].astype(int)]
        at = table.columns.get_loc("picked") + 1
        for j in range(q.shape[1]):
            table.insert(at + j, f"q{j + 1}", joints[:, j])
    if units is not None:
        at = table.columns.get_loc("true_best") + 1
        table.insert(at, "unit", [units[criterion] for criterion in table["criterion"]])
    return table.set_index(["kind", "criterion"])
