r"""Accelerations within the joint position and velocity limits over one control period.

The paper's set (eq. 15) assumes the arm far from its joint limits.  At a state
:math:`(q, \dot q)`, with the joint accelerations held over the next control period
:math:`\Delta t`, the joint velocity must end within its limits and the position stay within
its range at every instant (DESIGN.md section 8):

.. math::

    \dot q_{min} \le \dot q + \ddot q\, \Delta t \le \dot q_{max}, \qquad
    q_{min} \le q + \dot q\, t + \ddot q\, t^2 / 2 \le q_{max}
    \quad (0 \le t \le \Delta t),

optionally with viability (Del Prete, IEEE RA-L 2018): at the end of the period the joint
can still stop before its position limit braking at :math:`\ddot q_{brake}`.  Per joint each
condition is an interval of :math:`\ddot q` in closed form (:func:`acceleration_interval`),
so the feasible joint accelerations are the torque parallelotope
:math:`\{B^{-1}(\tau - g)\}` cut by a box.  In the normalized torques ``u`` of eq. (13),

.. math::

    \ddot x = M u + \ddot x_g, \qquad \|u\|_\infty \le 1, \qquad
    \ddot q_{lo} - a_0 \le W u \le \ddot q_{hi} - a_0,

with :math:`W = B^{-1} L` and :math:`a_0 = -B^{-1}(g - \tau_c)`.  Where the box holds the
whole parallelotope the set is the zonotope of eq. (15), unchanged; otherwise its vertices are
the images of the vertices of the cut cube (cddlib, n-D) and its facets their hull.  The
ellipsoids are the acceleration capacity's: they ignore the position and velocity limits,
which is what comparing them with this set measures.  Directional limits are the facets'
closed form for one configuration and a batched dual simplex
(:func:`~polyell.geometry.bounded_lp.dual_simplex`) for a path (:func:`line_limits`).
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, QhullError

from polyell.cached import cached_property
from polyell.capacities.acceleration import AccelerationAnalysis
from polyell.capacities.base import centre_and_half_range
from polyell.errors import InputError, SolverError
from polyell.geometry.bounded_lp import INFEASIBLE, OPTIMAL, UNRESOLVED, dual_simplex
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL, RankRevealingSVD
from polyell.models.dynamics import Dynamics
from polyell.validation import array_ndim, as_floats, check_array

__all__ = [
    "HorizonAnalysis",
    "HorizonBlock",
    "JointHorizon",
    "acceleration_interval",
    "check_horizon",
    "cutting_joints",
    "horizon_block",
    "joint_horizon",
    "joint_map",
    "line_limits",
    "moving_dynamics",
    "refuse_without_horizon",
    "robot_horizon",
]

Array = NDArray[np.float64]

#: The longest horizon [s]: a control period (beyond, t^2 / 2 of the position bound loses
#: the digits of the limits).
MAX_HORIZON = 1e3
#: A joint's interval cuts the torque set when the set reaches beyond it by more than this
#: share of the set's own reach along that joint (below it the cut changes nothing that
#: floating point can show, and the zonotope, exact, is kept).
CUT_RTOL = 1e-12


@dataclass(frozen=True)
class JointHorizon:
    """A joint state, its position and velocity limits, and the control period.

    Build it with :func:`joint_horizon` (checked); one state (arrays of shape (n,)) or a
    batch (K, n) of states with shared limits.

    Attributes
    ----------
    horizon : float
        The control period ``dt`` [s], positive.
    q, qd : ndarray, shape (n,) or (K, n)
        Joint positions [rad or m] and velocities [rad/s or m/s].
    q_min, q_max : ndarray, shape (n,)
        Joint position limits (``-inf`` and ``inf`` for a joint that turns freely).
    qd_min, qd_max : ndarray, shape (n,)
        Joint velocity limits.
    braking : ndarray, shape (n,), or None
        Viability: the deceleration [rad/s^2 or m/s^2] each joint can still brake with
        after the period; None: no viability condition.
    """

    horizon: float
    q: Array
    qd: Array
    q_min: Array
    q_max: Array
    qd_min: Array
    qd_max: Array
    braking: Array | None = None

    def interval(self) -> tuple[Array, Array]:
        """``(qdd_lo, qdd_hi)``: :func:`acceleration_interval` of this state."""
        return acceleration_interval(
            self.horizon,
            self.q,
            self.qd,
            self.q_min,
            self.q_max,
            self.qd_min,
            self.qd_max,
            self.braking,
        )

    def arguments(self) -> dict[str, Any]:
        """The keyword arguments of ``pe.analyze(..., horizon=)`` for this (one) state."""
        names = ("horizon", "q", "qd", "q_min", "q_max", "qd_min", "qd_max", "braking")
        return {name: getattr(self, name) for name in names}

    def at(self, q: ArrayLike, qd: ArrayLike) -> JointHorizon:
        """The same limits and horizon at other states ``q``, ``qd`` (n,) or (K, n), checked."""
        n = len(self.q_min)
        shape: tuple[str | int, ...] = ("K", n) if array_ndim(q) == 2 else (n,)
        positions = check_array("q", q, shape, what="joint positions [rad or m]")
        velocities = check_array("qd", qd, positions.shape, what="joint velocities [rad/s]")
        return replace(self, q=positions, qd=velocities)

    def __getitem__(self, index: int | slice) -> JointHorizon:
        """One state (an int) or a sub-batch (a slice) of a batch."""
        return JointHorizon(
            self.horizon,
            self.q[index],
            self.qd[index],
            self.q_min,
            self.q_max,
            self.qd_min,
            self.qd_max,
            self.braking,
        )


def joint_horizon(
    horizon: object,
    n: int,
    *,
    q: ArrayLike | None,
    qd: ArrayLike | None,
    q_min: ArrayLike | None,
    q_max: ArrayLike | None,
    qd_min: ArrayLike | None,
    qd_max: ArrayLike | None,
    braking: ArrayLike | None = None,
) -> JointHorizon:
    """A checked :class:`JointHorizon` of ``n`` joints (``q``, ``qd`` one state or a batch).

    Raises
    ------
    InputError
        Naming the argument: a horizon that is not a positive finite number of seconds,
        ``q`` without ``qd`` or the reverse, missing limits, limits of another length,
        ``q_min >= q_max``, ``qd_min > qd_max``, or a braking deceleration that is not
        positive.
    """
    dt = check_horizon("horizon", horizon)
    if q is None or qd is None:
        missing = "q" if q is None else "qd"
        raise InputError(
            missing,
            "the joint positions q and velocities qd of the state with horizon=",
            "q without qd" if qd is None and q is not None else f"{missing}=None",
            "pass both, e.g. horizon=0.001, q=q, qd=qd (qd = 0 at rest).",
        )
    shape: tuple[str | int, ...] = ("K", n) if array_ndim(q) == 2 else (n,)
    positions = check_array("q", q, shape, what="joint positions [rad or m]")
    velocities = check_array("qd", qd, positions.shape, what="joint velocities [rad/s or m/s]")
    derived = qd_min is None  # -qd_max: what is wrong with it is qd_max's
    limits: dict[str, NDArray[np.float64]] = {}
    for name, value in (("q_min", q_min), ("q_max", q_max), ("qd_max", qd_max), ("qd_min", qd_min)):
        if name == "qd_min" and derived:
            limits[name] = -limits["qd_max"]
            continue
        if value is None:
            raise InputError(
                name,
                f"the joint {'position' if name[1] == '_' else 'velocity'} limits with horizon=",
                "none",
                "pass q_min=, q_max=, qd_max= (qd_min default -qd_max), or use "
                "robot.analyze(q, qd, horizon=dt), which takes the robot's own.",
            )
        if name.startswith("q_") and _numeric(value):  # a joint that turns freely: inf
            bound = np.asarray(value, dtype=float)
            free = np.isinf(bound) & (np.sign(bound) == (1 if name == "q_max" else -1))
            limits[name] = check_array(name, np.where(free, 0.0, bound), (n,), what="joint limits")
            limits[name][free] = bound[free]
        else:
            limits[name] = check_array(name, value, (n,), what="joint limits")
    for low, high, strict in (("q_min", "q_max", True), ("qd_min", "qd_max", False)):
        bad = limits[low] >= limits[high] if strict else limits[low] > limits[high]
        if bad.any():
            j = int(np.flatnonzero(bad)[0])
            if low == "qd_min" and derived:
                raise InputError(
                    "qd_max",
                    "qd_max >= 0 for every joint (qd_min defaults to -qd_max)",
                    f"joint {j + 1}: qd_max = {limits[high][j]:g}",
                    "give speeds as positive limits, or pass qd_min= as well.",
                )
            raise InputError(
                low,
                f"{low} {'<' if strict else '<='} {high} for every joint",
                f"joint {j + 1}: {low} = {limits[low][j]:g}, {high} = {limits[high][j]:g}",
                "check the order of the limits.",
            )
    brake = None
    if braking is not None:
        scalar = _numeric(braking) and np.ndim(braking) == 0
        brake = check_array("braking", np.full(n, braking) if scalar else braking, (n,))
        if not (brake > 0).all():
            raise InputError(
                "braking",
                "positive decelerations [rad/s^2], one per joint or one for all",
                f"{brake.tolist()}"[:200],
                "leave it out for no viability condition.",
            )
    return JointHorizon(
        dt,
        positions,
        velocities,
        limits["q_min"],
        limits["q_max"],
        limits["qd_min"],
        limits["qd_max"],
        brake,
    )


def refuse_without_horizon(horizon: object, **given: object) -> None:
    """An InputError naming the first of ``given`` that is set while ``horizon`` is None."""
    if horizon is None:
        for name, value in given.items():
            if value is not None:
                raise InputError(
                    name,
                    f"{name} only with a horizon (a state's joint limits over a period)",
                    f"{name} without horizon=",
                    "pass horizon=dt [s], or leave it out.",
                )


def robot_horizon(
    robot: Any,
    horizon: object,
    q_min: ArrayLike | None = None,
    q_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    qd_max: ArrayLike | None = None,
    braking: ArrayLike | None = None,
) -> JointHorizon:
    """A robot's horizon template (at q = qd = 0; :meth:`JointHorizon.at` moves it).

    The limits given, or the robot's own: ``robot.position_limits`` (none for a robot
    without, a :class:`~polyell.PlanarArm`: its joints turn freely) and
    ``robot.velocity_limits()``; ``qd_min`` defaults to ``-qd_max`` (:func:`joint_horizon`).
    """
    n = int(robot.n)
    if q_min is None and q_max is None:  # a robot without limits turns freely (a planar arm)
        free = (np.full(n, -np.inf), np.full(n, np.inf))
        q_min, q_max = getattr(robot, "position_limits", free)
    if qd_max is None and qd_min is None and getattr(robot, "qd_max", None) is not None:
        qd_max, qd_min = robot.velocity_limits()
    zero = np.zeros(n)
    return joint_horizon(
        horizon,
        n,
        q=zero,
        qd=zero,
        q_min=q_min,
        q_max=q_max,
        qd_min=qd_min,
        qd_max=qd_max,
        braking=braking,
    )


def moving_dynamics(robot: Any, q: Array, qd: Array) -> Dynamics:
    """``robot.dynamics(q, qd)``: with the velocity terms where the joints move.

    Raises an InputError naming ``qd`` for moving states of a robot whose dynamics take
    no velocities (a :class:`~polyell.PlanarArm`).
    """
    if not qd.any():
        return robot.dynamics(q)
    if "qd" not in inspect.signature(robot.dynamics).parameters:
        raise InputError(
            "qd",
            "joint velocities only for a robot whose dynamics take them (UrdfRobot)",
            f"moving states of a {type(robot).__name__}",
            "leave qd out (at rest), or load the robot from its URDF.",
        )
    return robot.dynamics(q, qd)


def _numeric(value: object) -> bool:
    """Whether ``value`` converts to a float array (else check_array says why not)."""
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def check_horizon(name: str, horizon: object) -> float:
    """``horizon`` as a positive finite float, or an InputError naming ``name``."""
    if isinstance(horizon, bool) or not isinstance(horizon, int | float | np.integer | np.floating):
        raise InputError(
            name,
            "a control period in seconds, e.g. 0.001",
            repr(horizon),
            "pass the period as a number of seconds, e.g. 0.001 for a 1 kHz controller",
        )
    value = float(horizon)
    if not (math.isfinite(value) and 0.0 < value <= MAX_HORIZON):
        raise InputError(
            name,
            f"a positive control period in seconds, at most {MAX_HORIZON:g}",
            repr(horizon),
            "leave it out (None) for the set without joint position and velocity limits.",
        )
    return value


def acceleration_interval(
    horizon: float,
    q: Array,
    qd: Array,
    q_min: Array,
    q_max: Array,
    qd_min: Array,
    qd_max: Array,
    braking: Array | None = None,
) -> tuple[Array, Array]:
    r"""The joint accelerations that keep each joint within its limits over the horizon.

    For a constant :math:`\ddot q` over :math:`[0, \Delta t]`: the velocity
    :math:`\dot q + \ddot q \Delta t` within its limits at the end, the position
    :math:`q + \dot q t + \ddot q t^2/2` within its range at every instant (the end point,
    and, for a joint decelerating towards a limit, the apex of the parabola when it falls
    inside the horizon), and with ``braking`` the joint able to stop before its limit
    after the period (viability).

    Parameters
    ----------
    horizon : float
        ``dt`` [s].
    q, qd : ndarray, shape (n,) or (K, n)
        The state.
    q_min, q_max, qd_min, qd_max : ndarray, shape (n,)
        The limits.
    braking : ndarray, shape (n,), optional
        The deceleration each joint can brake with after the period.

    Returns
    -------
    lo, hi : ndarray, the shape of ``q``
        The interval; ``lo > hi`` (or ``-inf``/``inf`` ends crossing) where no acceleration
        keeps the joint within its limits: a position outside its range, or one that the
        velocity reaches within the horizon whatever the joint does.
    """
    dt = check_horizon("horizon", horizon)
    q, qd, q_min, q_max, qd_min, qd_max = _interval_arrays(
        q=q, qd=qd, q_min=q_min, q_max=q_max, qd_min=qd_min, qd_max=qd_max
    )
    if braking is not None:
        braking = _interval_arrays(braking=braking)[0]
    hi = np.minimum((qd_max - qd) / dt, _upper_position_bound(q_max - q, qd, dt, braking))
    lo = np.maximum((qd_min - qd) / dt, -_upper_position_bound(q - q_min, -qd, dt, braking))
    return lo, hi


def _interval_arrays(**arrays: object) -> list[Array]:
    """The arguments of :func:`acceleration_interval` as float arrays of one joint count.

    NaN is refused (an interval of NaN ends would read as empty); infinite limits are
    allowed (a continuous joint).
    """
    values = [as_floats(name, value) for name, value in arrays.items()]
    n = {np.shape(value)[-1] if np.ndim(value) else None for value in values}
    for name, value in zip(arrays, values, strict=True):
        if np.ndim(value) not in (1, 2) or len(n) != 1 or np.isnan(value).any():
            raise InputError(
                name,
                "an array of one value per joint, shape (n,) or (K, n), without NaN",
                f"shape {np.shape(value)}" + (" with NaN" if np.isnan(value).any() else ""),
                "pass q, qd and the limits with the same number of joints, e.g. "
                "acceleration_interval(0.001, q, qd, *robot.position_limits, qd_min, qd_max)",
            )
    return values


def _upper_position_bound(room: Array, qd: Array, dt: float, braking: Array | None) -> Array:
    r"""The largest :math:`a` with :math:`\dot q t + a t^2 / 2 \le D` (``room``) over the horizon.

    Over :math:`t` the bound :math:`2 (D - \dot q t) / t^2` is a parabola in :math:`1/t`,
    smallest at the apex :math:`t = 2 D / \dot q` when that is within the horizon (then
    :math:`-\dot q^2 / (2 D)`) and at :math:`t = \Delta t` otherwise.  With ``braking`` b,
    the end state must also allow a stop: :math:`p + v^2/(2b) \le D` for an end velocity
    :math:`v > 0`, whose largest :math:`v` is a root taken without cancellation.  A
    negative ``room`` (the joint beyond its limit) gives ``-inf``.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        end = 2.0 * (room - qd * dt) / dt**2
        apex = np.where(room > 0, -qd * qd / (2.0 * room), -np.inf)
        bound = np.where((qd > 0) & (qd * dt >= 2.0 * room), apex, end)
        if braking is not None:
            # v = qd + a dt ends the period at p = (qd + v) dt / 2: v^2 + b dt v + 2 b c <= 0
            # with c = qd dt / 2 - D; its larger root, for c < 0 (else v <= 0: the end point).
            c = 0.5 * qd * dt - room
            b = braking
            v = -4.0 * b * c / (b * dt + np.sqrt((b * dt) ** 2 - 8.0 * b * c))
            bound = np.where(c < 0, np.minimum(bound, (v - qd) / dt), bound)
    return np.where(room < 0, -np.inf, bound)


class HorizonAnalysis(AccelerationAnalysis):
    """The accelerations of one configuration within its joint limits over a horizon.

    Build it with ``pe.analyze(dyn, tau_max, tau_min, horizon=dt, q=q, qd=qd, q_min=...,
    q_max=..., qd_max=...)`` or ``robot.analyze(q, qd, horizon=dt)``.  Everything of
    :class:`~polyell.capacities.AccelerationAnalysis` (``M``, ``xg``, the ellipsoids and
    their inverses), with :attr:`polytope` the set within the joint limits.

    Attributes
    ----------
    state : JointHorizon
        The state, the limits and the horizon.
    qdd_lo, qdd_hi : ndarray, shape (n,)
        The joint accelerations the position and velocity limits allow
        (:func:`acceleration_interval`) [rad/s^2].
    W, a0 : ndarray, shape (n, n) and (n,)
        The joint accelerations ``a0 + W u`` of the normalized torques ``u`` of eq. (13):
        ``W = B^-1 L``, ``a0 = -B^-1 (g - tau_c)`` [rad/s^2].
    cut : ndarray of bool, shape (n,)
        The joints whose interval cuts the torque-limited set (none: the zonotope of
        eq. 15 is the set).
    empty_reason : str or None
        Why no acceleration is feasible; None when some is.

    Parameters
    ----------
    dynamics : Dynamics
        The robot's matrices at the state (``qd`` included: ``robot.dynamics(q, qd)``).
    tau_max, tau_min : array-like, shape (n,)
        Torque limits [N m] (``tau_min`` default ``-tau_max``).
    state : JointHorizon
        The state, its limits and the horizon (:func:`joint_horizon`).
    rank_rtol, affine_rtol : float, optional
        As in :func:`polyell.analyze`.
    """

    #: Not the paper's set (eq. 15): reports name the capacity and print every matrix.
    paper = False

    def __init__(
        self,
        dynamics: Dynamics,
        tau_max: ArrayLike,
        tau_min: ArrayLike | None = None,
        *,
        state: JointHorizon,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        super().__init__(dynamics, tau_max, tau_min, rank_rtol=rank_rtol, affine_rtol=affine_rtol)
        if state.q.ndim != 1:
            raise InputError(
                "q",
                f"one state, shape ({self.n},)",
                f"shape {state.q.shape}",
                "analyze one configuration at a time, e.g. q=q[0] and qd=qd[0] for the first row",
            )
        self.state = state
        self.qdd_lo, self.qdd_hi = state.interval()
        self.W, self.a0 = joint_map(dynamics.B, self.half_range, self._gravity_bias)
        self.cut = cutting_joints(self.W, self.a0, self.qdd_lo, self.qdd_hi)
        self._reason = _joint_reason(state, self.qdd_lo, self.qdd_hi)

    @property
    def empty_reason(self) -> str | None:
        """Why no acceleration is feasible (the set is empty); None when some is."""
        self.polytope  # noqa: B018 (decides the torques' part of it)
        return self._reason

    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """``xg`` (eq. 8), ``M`` (eq. 14) and the joint interval ``qdd_lo``, ``qdd_hi``."""
        return {**super().matrices(), "qdd_lo": self.qdd_lo, "qdd_hi": self.qdd_hi}

    @cached_property
    def polytope(self) -> Polytope | HPolytope:  # type: ignore[override]
        """The accelerations within the torque limits and the joint limits over the horizon.

        The zonotope of eq. (15) where no joint's interval cuts it; else the hull of its
        support points (:func:`cut_set`, an :class:`~polyell.HPolytope`), empty (with
        :attr:`empty_reason`) where no torque gives an acceleration within the interval.
        """
        if self._reason is None and not self.cut.any():
            return super().polytope
        polytope = None
        if self._reason is None:
            polytope = cut_set(self.M, self.xg, self.W, self.a0, self.qdd_lo, self.qdd_hi, self.svd)
        if polytope is None:
            self._reason = self._reason or (
                "the torque limits give no joint acceleration within the interval "
                "[qdd_lo, qdd_hi] that keeps the joints within their position and velocity "
                "limits over the horizon"
            )
            polytope = _empty(self.m)
        polytope.affine_rtol = self.affine_rtol
        polytope.task = self.task
        return polytope


def joint_map(B: Array, half_range: Array, bias: Array) -> tuple[Array, Array]:
    """``W = B^-1 L`` and ``a0 = -B^-1 (g - tau_c)``: the joint accelerations of ``u``.

    One configuration (n, n) or a batch (K, n, n).
    """
    L = np.broadcast_to(half_range[..., None, :] * np.eye(B.shape[-1]), B.shape)
    solved = np.linalg.solve(B, np.concatenate([L, -bias[..., :, None]], axis=-1))
    return solved[..., :-1], solved[..., -1]


class HorizonBlock(NamedTuple):
    """A block of K states within their limits over a horizon (:func:`horizon_block`).

    Attributes
    ----------
    W, a0 : ndarray, shape (K, n, n) and (K, n)
        The joint accelerations ``a0 + W u`` of the normalized torques ``u``.
    lo, hi : ndarray, shape (K, n)
        The joint intervals (:func:`acceleration_interval`).
    cut : ndarray of bool, shape (K,)
        The rows whose intervals cut the torque set, or leave no acceleration: the rows
        whose set is not the zonotope of eq. (15).
    """

    W: Array
    a0: Array
    lo: Array
    hi: Array
    cut: NDArray[np.bool_]


def horizon_block(dyn: Dynamics, state: JointHorizon, upper: Array, lower: Array) -> HorizonBlock:
    """The joint maps and intervals of a batch ``dyn`` at the states ``state`` (K, n)."""
    lo, hi = state.interval()
    center, half_range = centre_and_half_range(upper, lower)
    W, a0 = joint_map(dyn.B, half_range, dyn.g - center)
    cut = cutting_joints(W, a0, lo, hi).any(axis=1) | ~(lo <= hi).all(axis=1)
    return HorizonBlock(W, a0, lo, hi, np.asarray(cut, dtype=np.bool_))


def cutting_joints(W: Array, a0: Array, lo: Array, hi: Array) -> NDArray[np.bool_]:
    """Which joints' intervals cut the parallelotope ``a0 + W u``, shape of ``a0``.

    The parallelotope reaches ``a0 -+ sum_j |W_ij|`` along joint i; the interval cuts it
    when it ends inside that reach by more than :data:`CUT_RTOL` of it.
    """
    reach = np.abs(W).sum(axis=-1)
    slack = CUT_RTOL * (reach + np.abs(a0))
    return (a0 + reach > hi + slack) | (a0 - reach < lo - slack)


def _joint_reason(state: JointHorizon, lo: Array, hi: Array) -> str | None:
    """Why the joint interval is empty (the first joint that has none), or None."""
    empty = ~(lo <= hi)
    if not empty.any():
        return None
    j = int(np.flatnonzero(empty)[0])
    q, low, high = state.q[j], state.q_min[j], state.q_max[j]
    if not low <= q <= high:
        side, excess = ("below", low - q) if q < low else ("above", q - high)
        return (
            f"joint {j + 1} is at q = {q:.6g}, {excess:.3g} {side} its limits "
            f"[{low:.6g}, {high:.6g}]"
        )
    return (
        f"no acceleration of joint {j + 1} keeps it within its limits over the horizon "
        f"{state.horizon:g} s (q = {q:.6g}, qd = {state.qd[j]:.6g}: it reaches a limit "
        "whatever it does)"
    )


def _empty(m: int) -> HPolytope:
    """The empty set of R^m, as half-spaces ``x_1 <= -1``, ``-x_1 <= -1``."""
    A = np.zeros((2, m))
    A[0, 0], A[1, 0] = 1.0, -1.0
    return HPolytope(A, [-1.0, -1.0])


#: A support point beyond a facet of the hull built so far by more than this share of the
#: hull's extent is a new vertex (:func:`cut_set`); closer, the facet is the set's.
SUPPORT_RTOL = 1e-11
#: A set is flat along a direction where its support points lie within this share of the
#: zonotope's reach of one another (:func:`cut_set`): a joint pinned by its interval.
FLAT_RTOL = 1e-9
#: Rounds of :func:`cut_set` at most (each adds every vertex beyond the current facets).
MAX_ROUNDS = 64


def cut_set(
    M: Array, xg: Array, W: Array, a0: Array, lo: Array, hi: Array, svd: RankRevealingSVD
) -> HPolytope | None:
    r"""The set :math:`\{\ddot x_g + M u : |u|_\infty \le 1, lo \le a_0 + W u \le hi\}`.

    Its hull is grown from support points (linear programs over the cut cube, a batch per
    round, :func:`support_points`): start from the points along the axes of its affine set,
    then ask every facet of the hull so far (each normal once: the hull only grows) for the
    set's support point along its normal; a point beyond the facet is a new vertex, and when
    none is, every facet of the hull supports the set, so the hull is the set (the convex
    hull method of Lassez and Lassez, 1992). The vertices are LP vertices, solved from n
    rows each: exact to rounding. In the coordinates of the set's affine hull (flat where M
    is singular, or where the intervals pin joints so that the rest cannot span the task),
    found the same way: the support along each normal of the points' hull, both ways, until
    none leaves it.

    Returns
    -------
    HPolytope, or None where the cut cube is empty.
    """
    m = M.shape[0]
    frame = svd.U1  # the set lies in xg + Im(M)
    r = frame.shape[1]
    if r == 0:
        points = np.zeros((1, 0))
        if _support(M, W, a0, lo, hi, np.zeros((1, m)))[1][0] == INFEASIBLE:
            return None
    else:
        axes = np.vstack([np.eye(r), -np.eye(r)]) @ frame.T  # task directions (2r, m)
        u, status = _support(M, W, a0, lo, hi, axes)
        if (status == INFEASIBLE).any():
            return None
        points = (u @ M.T) @ frame  # the support points in the frame's coordinates
    # The affine hull of the points is the set's once the support along each of its
    # normals, both ways, lies on it (else that support point is added and it grows).
    size = float(np.abs(M).sum(axis=1).max(initial=0.0))  # the zonotope's reach
    for _ in range(r + 1):
        origin = points.mean(axis=0)
        _, sigma, Vt = np.linalg.svd(points - origin, full_matrices=True)
        flat = int(np.count_nonzero(sigma > FLAT_RTOL * size))
        if flat == r:
            break
        normals = Vt[flat:]  # (r - flat, r) in the frame's coordinates
        u, _ = _support(M, W, a0, lo, hi, np.vstack([normals, -normals]) @ frame.T)
        found = (u @ M.T) @ frame
        off = np.abs((found - origin) @ normals.T).max(axis=1) > FLAT_RTOL * size
        if not off.any():
            break
        points = np.vstack([points, found[off]])
    inner = Vt[:flat].T  # (r, flat): the points' own affine set in the frame
    basis = frame @ inner  # (m, flat) in the task space
    x0 = xg + frame @ origin
    z = (points - origin) @ inner
    if flat >= 2:
        z = _grow_hull(M, W, a0, lo, hi, basis, frame @ origin, z)
        normals, offsets, corners = _facets(z)
        z = z[corners]  # the vertices (counter-clockwise in 2-D)
        if flat == m:  # full-dimensional: facets and vertices known and certified
            center = z.mean(axis=0)
            A = normals @ basis.T
            return HPolytope._from_enumeration(
                A, offsets + A @ x0, x0 + z @ basis.T, x0 + basis @ center,
                (z - center, basis, np.ones(m)),
            )  # fmt: skip
    elif flat == 1:
        normals, offsets = np.array([[1.0], [-1.0]]), np.array([z.max(), -z.min()])
    else:  # one point: the origin where it lies there to the rounding of the reach
        normals, offsets = np.zeros((0, 0)), np.zeros(0)
        if np.linalg.norm(x0) <= FLAT_RTOL * size:
            x0 = np.zeros(m)
    complement = np.linalg.svd(basis, full_matrices=True)[0][:, flat:] if flat < m else None
    rows, bounds = [normals @ basis.T], [offsets + normals @ basis.T @ x0]
    if complement is not None:
        rows += [complement.T, -complement.T]
        bounds += [complement.T @ x0, -(complement.T @ x0)]
    center = x0 + basis @ z.mean(axis=0)
    return HPolytope(np.vstack(rows), np.concatenate(bounds), center=center)


def _convex_hull(z: Array) -> ConvexHull:
    """Qhull's hull of points, again allowing wide merges where its merges fail.

    Nearly degenerate points in 5-D and 6-D can make Qhull's merges fail; with ``Q12`` the
    support queries of :func:`cut_set` then certify the facets.  A SolverError if that fails
    too.
    """
    try:
        return ConvexHull(z)
    except QhullError:
        pass
    try:
        return ConvexHull(z, qhull_options="Qc Qx Q12")
    except QhullError as error:
        raise SolverError(
            f"the hull of {len(z)} support points in {z.shape[1]}-D failed in Qhull "
            f"({str(error).splitlines()[0]}); report this configuration."
        ) from None


def _facets(z: Array) -> tuple[Array, Array, NDArray[np.int_]]:
    """The hull of points: its distinct facet planes ``a . z <= b`` and its vertices' indices.

    Qhull's triangles of one facet share its plane to rounding: planes equal to 1e-9 (of the
    unit normal, and of the offset relative to the points' extent) are one.
    """
    hull = _convex_hull(z)
    equations = hull.equations
    extent = float(np.abs(z).max(initial=0.0)) or 1.0
    keys = np.round(np.hstack([equations[:, :-1], equations[:, -1:] / extent]), 9)
    _, first = np.unique(keys, axis=0, return_index=True)
    planes = equations[np.sort(first)]
    return planes[:, :-1], -planes[:, -1], hull.vertices


def _grow_hull(
    M: Array, W: Array, a0: Array, lo: Array, hi: Array, basis: Array, shift: Array, z: Array
) -> Array:
    """The points ``z`` of :func:`cut_set` grown until every facet supports the set.

    ``z = basis^T (M u - shift)``: coordinates about ``xg + shift`` in the columns of
    ``basis`` (m, flat).
    """
    asked: set[bytes] = set()  # the normals queried so far (rounded, as queried)
    for _ in range(MAX_ROUNDS):
        hull = _convex_hull(z)
        normals = np.unique(np.round(hull.equations[:, :-1], 12), axis=0)
        # A facet whose normal was queried before: the same LP, the same support point,
        # then added or not beyond it, and the hull has only grown since: it supports the
        # set still (asking again gave the same answer: no new vertex).
        keys = [row.tobytes() for row in normals]
        new = np.array([key not in asked for key in keys], dtype=bool)
        asked.update(keys)
        normals = normals[new]
        if not len(normals):
            return z
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        u, _ = _support(M, W, a0, lo, hi, normals @ basis.T)
        found = (u @ M.T - shift) @ basis  # the support points, (F, flat)
        facets = (z @ normals.T).max(axis=0)
        beyond = (found * normals).sum(axis=1) > facets + SUPPORT_RTOL * np.ptp(z, axis=0).max()
        if not beyond.any():
            return z
        z = np.vstack([z, found[beyond]])
    raise SolverError(
        f"the cut acceleration set's hull did not close in {MAX_ROUNDS} rounds of support "
        "queries; report this configuration."
    )


def _support(
    M: Array, W: Array, a0: Array, lo: Array, hi: Array, directions: Array
) -> tuple[Array, NDArray[np.int_]]:
    """The support points ``u`` (k, n) of the cut cube along task ``directions`` (k, m).

    :func:`~polyell.geometry.bounded_lp.dual_simplex` from the cube's own support point;
    a problem it leaves (degenerate cycling) is solved by HiGHS.
    """
    k, n = len(directions), W.shape[0]
    norms = np.linalg.norm(W, axis=1)
    norms = np.where(norms > 0, norms, 1.0)
    G = np.broadcast_to(np.vstack([np.eye(n), W / norms[:, None]]), (k, 2 * n, n))
    lower = np.broadcast_to(np.concatenate([-np.ones(n), (lo - a0) / norms]), (k, 2 * n))
    upper = np.broadcast_to(np.concatenate([np.ones(n), (hi - a0) / norms]), (k, 2 * n))
    d = directions @ M
    basis = np.broadcast_to(np.arange(n), (k, n))
    answer = dual_simplex(d, G, lower, upper, basis, np.where(d >= 0, 1.0, -1.0))
    u, status = answer.u, answer.status
    for i in np.flatnonzero(status == UNRESOLVED):
        result = linprog(
            -d[i],
            A_ub=np.vstack([G[i], -G[i]]),
            b_ub=np.concatenate([upper[i], -lower[i]]),
            bounds=[(None, None)] * n,
            method="highs",
        )
        status[i] = OPTIMAL if result.status == 0 else INFEASIBLE
        if result.status == 0:
            u[i] = result.x
    return u, status


def line_limits(
    M: Array, xg: Array, W: Array, a0: Array, lo: Array, hi: Array, T: Array
) -> tuple[Array, Array, NDArray[np.bool_]]:
    r"""The interval ``{s : s t in the set}`` for K cut sets at once (batched dual simplex).

    Along the line :math:`s t`: :math:`E (M u + \ddot x_g) = 0` for an orthonormal
    complement E of t, and :math:`s = t \cdot (M u + \ddot x_g)`, maximised and minimised
    over the cut cube (:func:`~polyell.geometry.bounded_lp.dual_simplex`, started from the
    cube's support point).

    Parameters
    ----------
    M : ndarray, shape (K, m, n)
    xg : ndarray, shape (K, m)
    W : ndarray, shape (K, n, n)
    a0 : ndarray, shape (K, n)
    lo, hi : ndarray, shape (K, n)
        The joint intervals (:func:`acceleration_interval`; an empty one gives NaN).
    T : ndarray, shape (K, m)
        Unit directions.

    Returns
    -------
    lo, hi : ndarray, shape (K,)
        NaN where the line misses the set.
    unresolved : ndarray of bool, shape (K,)
        Rows the simplex left (cycling, a near-singular complement): for the exact path.
    """
    K, _, n = M.shape
    Q = np.linalg.qr(T[:, :, None], mode="complete")[0]
    E = np.swapaxes(Q[:, :, 1:], 1, 2)  # (K, m-1, m)
    EM, Ex = E @ M, -np.einsum("kim,km->ki", E, xg)
    w_norm, e_norm = np.linalg.norm(W, axis=2), np.linalg.norm(EM, axis=2)
    scale = np.linalg.norm(M, axis=(1, 2))
    unresolved = (e_norm <= 1e-9 * scale[:, None]).any(axis=1) | (w_norm <= 0).any(axis=1)
    w_norm, e_norm = np.where(w_norm > 0, w_norm, 1.0), np.where(e_norm > 0, e_norm, 1.0)
    G = np.concatenate(
        [np.broadcast_to(np.eye(n), (K, n, n)), W / w_norm[..., None], EM / e_norm[..., None]],
        axis=1,
    )
    ones = np.ones((K, n))
    lower = np.concatenate([-ones, (lo - a0) / w_norm, Ex / e_norm], axis=1)
    upper = np.concatenate([ones, (hi - a0) / w_norm, Ex / e_norm], axis=1)
    d = np.einsum("kmn,km->kn", M, T)
    both = np.concatenate([d, -d])
    side = np.where(both >= 0, 1.0, -1.0)
    basis = np.broadcast_to(np.arange(n), (2 * K, n))
    G, lower, upper = (np.concatenate([a, a]) for a in (G, lower, upper))
    answer = dual_simplex(both, G, lower, upper, basis, side)
    offset = np.einsum("km,km->k", T, xg)
    value = np.einsum("kn,kn->k", both, answer.u)
    top, bottom = offset + value[:K], offset - value[K:]
    status = answer.status.reshape(2, K)
    unresolved = unresolved | ((status != OPTIMAL) & (status != INFEASIBLE)).any(axis=0)
    missed = (status == INFEASIBLE).any(axis=0) | ~(lo <= hi).all(axis=1)
    return np.where(missed, np.nan, bottom), np.where(missed, np.nan, top), unresolved
