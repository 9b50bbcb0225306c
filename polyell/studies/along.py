r"""Directional limits along a path: one direction per configuration, vectorised.

A planner asks, for each configuration of a path and the path's tangent there, which
accelerations along the tangent the arm can produce: the interval of the polytope (15) and
of each ellipsoid (24).  :func:`limits_along` answers for a whole batch at once, equal row by
row to ``analyze(dyn[k]).polytope.limits(t_k)`` and ``.ellipsoid(kind).limits(t_k)``.

The polytope's facets are those of :class:`~polyell.Polytope`, enumerated in the whitened
coordinates of the SVD :math:`M = U S V^T` (:func:`~polyell.studies.block_sets.facets`).
The ellipsoids are evaluated from factors, never from their cores: with the same SVD,
:math:`M^+ = V S^{-1} U^T`, so the new ellipsoid
:math:`\{x : \|M^+ (x - \ddot x_g)\| \le 1\}` gives :math:`p = S^{-1} U^T t`; the classic one,
:math:`\{x : \|F (x - \ddot x_g)\| \le 1\}` with :math:`F = L^{-1} B J^+` and
:math:`J^+ = Q_J R_J^{-T}`, gives :math:`p = F t`.  Configurations at or near a singular
one (within the sweep's rank band) take the per-configuration path.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities import (
    ELLIPSOID_KINDS,
    Analysis,
    analyze,
    capacity_class,
    check_capacity,
    joint_limits_of,
    state_of,
)
from polyell.capacities.horizon import (
    JointHorizon,
    horizon_block,
    line_limits,
    moving_dynamics,
    refuse_without_horizon,
    robot_horizon,
)
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.comparison.directions import direction_vectors
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.limits import (
    DirectionalLimits,
    facet_slack,
    parallel_slopes,
    rounding_floor,
    snap_to_zero,
    unit_ball_interval,
)
from polyell.geometry.subspace import RANK_RTOL
from polyell.models.dynamics import Dynamics
from polyell.studies.batch import BatchOptions, block_sets, block_size
from polyell.validation import (
    check_array,
    check_fraction,
)

__all__ = ["limits_along"]

Array = NDArray[np.float64]
SETS = ("polytope", *ELLIPSOID_KINDS)


def limits_along(
    source: Any,
    configurations: ArrayLike | None,
    directions: ArrayLike,
    tau_max: ArrayLike | None = None,
    tau_min: ArrayLike | None = None,
    *,
    capacity: str = "acceleration",
    qd_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    rank_rtol: float = RANK_RTOL,
    horizon: float | None = None,
    qd: ArrayLike | None = None,
    q_min: ArrayLike | None = None,
    q_max: ArrayLike | None = None,
    braking: ArrayLike | None = None,
) -> dict[str, DirectionalLimits]:
    """What a capacity's set and ellipsoids allow along one unit direction per configuration.

    Parameters
    ----------
    source : robot or Dynamics
        A robot (``PlanarArm``, ``UrdfRobot``) with ``configurations``, or a batched
        :class:`~polyell.Dynamics` (then ``configurations`` is None).
    configurations : array-like, shape (K, n), or None
        Joint configurations [rad].
    directions : array-like, shape (K, m), or sequence of K names or vectors
        One unit task direction per configuration (e.g. a path's tangents); each may be a
        name of the task rows (:func:`~polyell.comparison.directions.named_direction`:
        ``["z"] * K``, ``["x", "-z", "xy", ...]``), read against ``dyn.task``.
    tau_max, tau_min : array-like, shape (n,), optional
        Torque limits of the acceleration and force capacities; default the robot's own.
    capacity : {"acceleration", "velocity", "force"}, optional
        Accelerations [m/s^2] (default), end-effector velocities [m/s] or static forces [N]
        along the directions, as :func:`polyell.analyze` defines them.
    qd_max, qd_min : array-like, shape (n,), optional
        Joint velocity limits of the velocity capacity [rad/s]; default the robot's own.
    rank_rtol : float, optional
        As in :func:`polyell.analyze`: a relative tolerance in [0, 1).
    horizon : float, optional
        A control period [s] (accelerations, a robot ``source``): the polytope's limits
        become those of the accelerations that also keep every joint within its position
        and velocity limits over the period, from the state ``(configurations, qd)``, as
        ``analyze(..., horizon=)`` defines them
        (:class:`~polyell.capacities.horizon.HorizonAnalysis`); the ellipsoids ignore those
        limits.  Where no joint's interval cuts the set the limits are the closed form;
        elsewhere a batched dual simplex (:func:`~polyell.capacities.horizon.line_limits`).
    qd : array-like, shape (K, n), optional
        Joint velocities of the state with ``horizon`` [rad/s]; default 0 (at rest).  The
        dynamics then include the Coriolis and centrifugal torques and ``Jdot qdot``.
    q_min, q_max, braking : array-like, shape (n,), optional
        With ``horizon``: the position limits (default the robot's ``position_limits``) and
        the braking decelerations of viability (default none); the velocity limits are
        ``qd_max``, ``qd_min`` (default the robot's own).

    Returns
    -------
    dict of str to DirectionalLimits
        ``"polytope"`` and each ellipsoid kind of the capacity (``chiacchio`` and
        ``yoshikawa`` for accelerations): ``(lo, hi)`` of shape (K,), NaN where the line
        misses the set or an ellipsoid is undefined (the classic one at singular
        configurations); infinite along a ray of an unbounded force set.

    Notes
    -----
    Accelerations and velocities are computed a block of configurations at once (a
    velocity set is the zonotope of ``B = I``, ``g = 0`` and the joint velocity limits,
    its ellipsoid that zonotope's image of the unit ball); forces, and configurations at
    or near a singular one, one at a time.  Every row equals
    ``analyze(...).polytope.limits(t)`` and ``.ellipsoid(kind).limits(t)``.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> q = [[np.pi / 2, -np.pi / 2, -np.pi / 2], [0.3, 0.2, 0.1]]
    >>> out = pe.limits_along(arm, q, [[1.0, 0.0], [0.0, 1.0]])
    >>> np.round(out["polytope"].hi, 3)
    array([53.7  , 13.034])
    """
    capacity = check_capacity(capacity)
    cls = capacity_class(capacity)
    rank_rtol = check_fraction("rank_rtol", rank_rtol)
    state = None
    refuse_without_horizon(horizon, qd=qd, q_min=q_min, q_max=q_max, braking=braking)
    if horizon is not None:
        state = _state(source, configurations, qd, horizon, q_min, q_max, qd_min, qd_max, braking)
        state_of(cls, horizon)  # refuses a capacity without a horizon
        qd_max = qd_min = None
    upper, lower = joint_limits_of(capacity, tau_max, tau_min, qd_max, qd_min)
    dyn, upper, lower = _inputs(source, configurations, upper, lower, cls, state)
    if isinstance(directions, str):  # one name for a batch: which count was meant?
        raise InputError(
            "directions",
            f"one unit direction per configuration ({len(dyn)}): unit vectors of shape "
            f"({len(dyn)}, {dyn.m}) or a list of {len(dyn)} names of the task rows "
            f"{list(dyn.task)}",
            f"the single name {directions!r}",
            f"repeat it, e.g. directions=[{directions!r}] * {len(dyn)}.",
        )
    T = direction_vectors(directions, dyn.task, "directions")
    if T.ndim != 2 or len(T) != len(dyn):
        raise InputError(
            "directions",
            f"one unit direction per configuration, shape ({len(dyn)}, {dyn.m})",
            f"shape {T.shape}",
            f"give {len(dyn)} directions, e.g. an array of shape ({len(dyn)}, {dyn.m}) such as "
            f"np.tile(t, ({len(dyn)}, 1)) for one vector t, or [{dyn.task[0]!r}] * {len(dyn)}.",
        )
    sets = ("polytope", *cls.ellipsoid_kinds)
    lo = {name: np.full(len(dyn), np.nan) for name in sets}
    hi = {name: np.full(len(dyn), np.nan) for name in sets}
    size = 8 * block_size(dyn.m, dyn.n)  # no (rows, facets, directions) arrays here
    for start in range(0, len(dyn), size):
        rows = slice(start, start + size)
        part = dyn[rows]
        scalar = np.ones(len(part), dtype=bool)  # forces: one configuration at a time
        if issubclass(cls, ZonotopeAnalysis):  # a block at once, as acceleration zonotopes
            part = cls._acceleration_dynamics(part)
            block_lo = {name: np.full(len(part), np.nan) for name in SETS}
            block_hi = {name: np.full(len(part), np.nan) for name in SETS}
            scalar = _block(part, upper, lower, T[rows], rank_rtol, block_lo, block_hi, cls)
            for name, target in cls.acceleration_names.items():
                lo[target][rows], hi[target][rows] = block_lo[name], block_hi[name]
            if state is not None:  # the polytope cut by the joints' intervals
                scalar |= _cut_rows(part, state[rows], upper, lower, T[rows], lo, hi, start)
        for k in np.flatnonzero(scalar) + start:  # forces, (near-)singular: the exact path
            limits = {} if state is None else {"state": state[int(k)]}
            analysis = analysis_within(dyn[int(k)], capacity, upper, lower, rank_rtol, **limits)
            lo["polytope"][k], hi["polytope"][k] = analysis.polytope.limits(T[k])
            for kind in sets[1:]:
                try:
                    lo[kind][k], hi[kind][k] = analysis.ellipsoid(kind).limits(T[k])
                except UndefinedEllipsoidError:
                    lo[kind][k] = hi[kind][k] = np.nan
    return {name: DirectionalLimits(lo[name], hi[name]) for name in sets}


def analysis_within(
    dyn: Dynamics,
    capacity: str,
    upper: Array,
    lower: Array,
    rank_rtol: float,
    state: JointHorizon | None = None,
) -> Any:
    """``polyell.analyze`` of one configuration within a capacity's checked joint limits.

    With a checked ``state``, the set within its joint limits over its horizon.
    """
    if state is not None:
        return state_of(capacity_class(capacity), state.horizon)(
            dyn, upper, lower, state=state, rank_rtol=rank_rtol
        )
    limits = capacity_class(capacity).limit_arguments(upper, lower)
    return analyze(dyn, capacity=capacity, rank_rtol=rank_rtol, **limits)


def _state(
    source: Any,
    configurations: ArrayLike | None,
    qd: ArrayLike | None,
    horizon: float,
    q_min: ArrayLike | None,
    q_max: ArrayLike | None,
    qd_min: ArrayLike | None,
    qd_max: ArrayLike | None,
    braking: ArrayLike | None,
) -> JointHorizon:
    """The checked states (K, n) of ``limits_along(..., horizon=)``, limits the robot's."""
    if not hasattr(source, "dynamics") or configurations is None:
        raise InputError(
            "source",
            "a robot with configurations (the positions of the states) with horizon=",
            type(source).__name__,
            "pass the robot and its configurations, e.g. limits_along(panda, q, T, "
            "horizon=0.001, qd=qd).",
        )
    q = check_array("configurations", configurations, ("K", source.n))
    template = robot_horizon(source, horizon, q_min, q_max, qd_min, qd_max, braking)
    return template.at(q, np.zeros_like(q) if qd is None else qd)


def _cut_rows(
    dyn: Dynamics,
    state: JointHorizon,
    upper: Array,
    lower: Array,
    T: Array,
    lo: dict[str, Array],
    hi: dict[str, Array],
    start: int,
) -> NDArray[np.bool_]:
    """The polytope's limits of the rows of a block whose joint intervals cut the set.

    Batched dual simplex (:func:`~polyell.capacities.horizon.line_limits`); returns the
    rows it leaves (degenerate cycling) to the exact path.
    """
    block = horizon_block(dyn, state, upper, lower)
    rows = np.flatnonzero(block.cut)
    W, a0 = block.W[rows], block.a0[rows]
    M = dyn.J[rows] @ W
    xg = dyn.xdd_bias[rows] + np.einsum("kmn,kn->km", dyn.J[rows], a0)
    a, b, unresolved = line_limits(M, xg, W, a0, block.lo[rows], block.hi[rows], T[rows])
    lo["polytope"][rows + start], hi["polytope"][rows + start] = a, b
    left = np.zeros(len(dyn), dtype=np.bool_)
    left[rows[unresolved]] = True
    return left


def _inputs(
    source: Any,
    configurations: ArrayLike | None,
    upper: Any,
    lower: Any,
    capacity: type[Analysis],
    state: JointHorizon | None = None,
) -> tuple[Dynamics, Array, Array]:
    """The batched dynamics and the capacity's checked joint limits (given or the robot's)."""
    if isinstance(source, Dynamics):
        if source.batch_size is None or configurations is not None:
            raise InputError(
                "source",
                "a batched Dynamics without configurations, or a robot with them",
                "a single Dynamics" if source.batch_size is None else "both",
                "pass a batched robot.dynamics(q) of a (K, n) q with configurations=None, "
                "or the robot and q, e.g. limits_along(robot, q, directions)."
                if source.batch_size is None
                else "drop the configurations, e.g. limits_along(dyn, None, directions), "
                "or pass the robot instead of its Dynamics.",
            )
        dyn = source
    elif hasattr(source, "dynamics"):
        if configurations is None:
            raise InputError(
                "configurations",
                "a (K, n) array of joint angles",
                "None",
                f"pass the joint angles [rad] as an array of shape (K, {source.n}), "
                f"e.g. limits_along(robot, q, directions) with q.shape == (K, {source.n}).",
            )
        q = check_array("configurations", configurations, ("K", source.n))
        if len(q) == 0:
            raise InputError(
                "configurations",
                "at least one configuration",
                "none",
                f"pass at least one row of {source.n} joint angles, "
                f"e.g. configurations=[[0.0] * {source.n}].",
            )
        dyn = source.dynamics(q) if state is None else moving_dynamics(source, q, state.qd)
    else:
        raise InputError(
            "source",
            "a robot or a batched pe.Dynamics",
            type(source).__name__,
            "pass a robot, e.g. pe.robots.load('chiacchio2000'), with its configurations, "
            "or its batched robot.dynamics(q) with configurations=None.",
        )
    return (dyn, *capacity._source_limits(source, upper, lower, dyn.n))


def _block(
    dyn: Dynamics,
    upper: Array,
    lower: Array,
    T: Array,
    rank_rtol: float,
    lo: dict[str, Array],
    hi: dict[str, Array],
    capacity: type[ZonotopeAnalysis],
) -> NDArray[np.bool_]:
    """Fill the full-rank rows of one block (K,); return the rows left to the exact path.

    The sets are the sweep's (:func:`~polyell.studies.batch.block_sets`: accelerations, or
    the velocities of ``B = I``, ``g = 0`` and the joint velocity limits).
    """
    options = BatchOptions(rank_rtol=rank_rtol, capacity=capacity.capacity)
    sets, scalar = block_sets(dyn.J, dyn.B, dyn.g, dyn.xdd_bias, upper, lower, options)
    if sets is None:
        return scalar
    rows, T, xg = sets.rows, T[sets.rows], sets.xg
    m, n = sets.M.shape[1:]
    # The polytope: each facet pair +-a bounds a.(lambda t) to [a.xg - h, a.xg + h]; a line
    # that misses P but meets it grown by the slack of Polytope.limits touches it.
    h = sets.offsets
    reach = np.linalg.norm(xg, axis=-1) + sets.size
    slope = np.einsum("kcm,km->kc", sets.normals, T)
    centre = np.einsum("kcm,km->kc", sets.normals, xg)
    floor = rounding_floor(2.0 * reach[:, None], m + n + 2)  # the origin on a facet: 0
    slack = facet_slack(h, 2.0 * reach[:, None], m + n + 2)
    parallel = parallel_slopes(slack, 2.0 * reach[:, None])  # along a facet to its slack
    a, b = _line_in_pairs(slope, centre, h, floor, parallel)
    missed = a > b
    if missed.any():
        loose = h[missed] + slack[missed]
        touch = np.zeros_like(missed)
        ends = _line_in_pairs(slope[missed], centre[missed], loose, 0.0, parallel[missed])
        touch[missed] = np.less_equal(*ends)
        a, b = np.where(touch, 0.5 * (a + b), a), np.where(touch, 0.5 * (a + b), b)
    empty = a > b
    lo["polytope"][rows], hi["polytope"][rows] = (
        np.where(empty, np.nan, a),
        np.where(empty, np.nan, b),
    )
    # The ellipsoids {xg + U diag(s) u}: the line in the unit ball of u (eq. 23-24).
    for kind in SETS[1:]:
        axes, semi, _, _ = sets.ellipsoids[kind]
        p = np.einsum("kmr,km->kr", axes, T) / semi
        w = np.einsum("kmr,km->kr", axes, xg) / semi
        lo[kind][rows], hi[kind][rows] = unit_ball_interval(p, w)
    return scalar


def _line_in_pairs(
    slope: Array, centre: Array, h: Array, floor: Array | float, parallel: Array
) -> tuple[Array, Array]:
    """``[a, b]``, (K,): the line ``lambda t`` in the facet pairs ``|a_i . x - a_i . xg| <= h_i``.

    ``slope`` ``a_i . t``, ``centre`` ``a_i . xg`` and ``h``, all (K, C); ``a > b`` when the
    line misses them (NaN, from a 0/0, also counts as missing).  Offsets ``centre -+ h``
    within ``floor`` of 0 are 0 (:func:`~polyell.geometry.limits.snap_to_zero`); slopes
    within ``parallel`` (K, C) of 0 run along the pair
    (:func:`~polyell.geometry.limits.parallel_slopes`).
    """
    offsets = snap_to_zero(centre - h, floor), snap_to_zero(centre + h, floor)
    with np.errstate(divide="ignore", invalid="ignore"):
        ends = np.stack([offsets[0] / slope, offsets[1] / slope])  # (2, K, C)
    # along the pair: no bound, or an empty line if the origin is beyond the pair
    along = np.abs(slope) <= parallel
    inside = (offsets[0] <= 0.0) & (offsets[1] >= 0.0)
    lower_end = np.where(along, np.where(inside, -np.inf, np.inf), ends.min(0))
    upper_end = np.where(along, np.where(inside, np.inf, -np.inf), ends.max(0))
    return lower_end.max(axis=1), upper_end.min(axis=1)
