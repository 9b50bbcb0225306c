"""Capacities: what an arm can do at a configuration, as a set and as ellipsoids.

One interface (:class:`~polyell.capacities.base.Analysis`) and a registry of three
capacities -- accelerations (the paper), velocities and static forces -- built by
:func:`analyze`.
"""

from __future__ import annotations

from typing import Any

from numpy.typing import ArrayLike

from polyell.capacities.acceleration import ELLIPSOID_KINDS, AccelerationAnalysis, check_dynamics
from polyell.capacities.base import Analysis, InverseSolution
from polyell.capacities.force import ForceAnalysis
from polyell.capacities.horizon import HorizonAnalysis, JointHorizon, joint_horizon
from polyell.capacities.velocity import VelocityAnalysis
from polyell.errors import InputError
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL
from polyell.models.dynamics import warn_rated_limits_in_motion

__all__ = [
    "CAPACITIES",
    "ELLIPSOID_KINDS",
    "AccelerationAnalysis",
    "Analysis",
    "ForceAnalysis",
    "HorizonAnalysis",
    "InverseSolution",
    "VelocityAnalysis",
    "analyze",
    "capacity_class",
    "check_capacity",
    "joint_limits_of",
    "state_of",
    "takes_horizon",
]

_REGISTRY: dict[str, type[Analysis]] = {
    cls.capacity: cls for cls in (AccelerationAnalysis, VelocityAnalysis, ForceAnalysis)
}
#: The capacities :func:`analyze` knows, in table order.
CAPACITIES: tuple[str, ...] = tuple(_REGISTRY)
#: The capacities that take a horizon (``analyze(..., horizon=dt)``): their set within the
#: joint position and velocity limits over the next control period.
_WITHIN_HORIZON: dict[type[Analysis], type[HorizonAnalysis]] = {
    AccelerationAnalysis: HorizonAnalysis
}


def check_capacity(capacity: object, argument: str = "capacity") -> str:
    """Return ``capacity`` if it is a registered name, else raise an InputError."""
    if not isinstance(capacity, str) or capacity not in _REGISTRY:
        from difflib import get_close_matches

        close = get_close_matches(str(capacity), CAPACITIES, n=1)
        raise InputError(
            argument,
            "one of " + ", ".join(repr(c) for c in CAPACITIES),
            repr(capacity),
            f"did you mean {close[0]!r}?" if close else "accelerations are the default.",
        )
    return capacity


def capacity_class(capacity: str) -> type[Analysis]:
    """The :class:`Analysis` subclass of a capacity name."""
    return _REGISTRY[check_capacity(capacity)]


def analyze(
    dyn: Any,
    tau_max: ArrayLike | None = None,
    tau_min: ArrayLike | None = None,
    *,
    capacity: str = "acceleration",
    qd_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    rank_rtol: float = RANK_RTOL,
    affine_rtol: float = AFFINE_RTOL,
    horizon: float | None = None,
    q: ArrayLike | None = None,
    qd: ArrayLike | None = None,
    q_min: ArrayLike | None = None,
    q_max: ArrayLike | None = None,
    braking: ArrayLike | None = None,
) -> Any:
    """Analyze one capacity of a robot at one configuration.

    Parameters
    ----------
    dyn : Dynamics or Kinematics
        Jacobian, inertia and gravity torques at the configuration (the velocity capacity
        needs only the Jacobian: a :class:`~polyell.Kinematics` will do).
    tau_max : array-like, shape (n,)
        Upper torque limits [N m] (acceleration and force capacities).
    tau_min : array-like, shape (n,), optional
        Lower torque limits [N m]; default ``-tau_max``.
    capacity : {"acceleration", "velocity", "force"}
        ``"acceleration"`` (the paper's: the zonotope of eq. 15 and both dynamic
        manipulability ellipsoids), ``"velocity"`` (the zonotope ``{J qd}`` of the joint
        velocity box and its manipulability ellipsoid) or ``"force"`` (the static force
        polytope ``{h : tau_min <= J^T h + g <= tau_max}`` and three force ellipsoids).
    qd_max, qd_min : array-like, shape (n,)
        Joint velocity limits [rad/s] of the velocity capacity, or of the horizon
        (``qd_min`` default ``-qd_max``).
    rank_rtol : float, optional
        Relative tolerance of the rank decision (singular values at or below
        ``rank_rtol * sigma_max`` are zero); default :data:`~polyell.RANK_RTOL`.
    affine_rtol : float, optional
        At a singular configuration, how far (relative) a direction or a point may be off
        the affine set and still count as in it (rounded input, projected with a
        :class:`~polyell.ProjectedInputWarning`); default :data:`~polyell.AFFINE_RTOL`.
    horizon : float, optional
        A control period ``dt`` [s] (accelerations only): the set becomes the accelerations
        that also keep every joint within its position limits ``q_min``, ``q_max`` at every
        instant of the period and within its velocity limits ``qd_min``, ``qd_max`` at its
        end, from the state ``q``, ``qd``
        (:class:`~polyell.capacities.horizon.HorizonAnalysis`).  None (default): the set
        without them.
    q, qd : array-like, shape (n,)
        The joint positions [rad or m] and velocities [rad/s or m/s] of the state, with
        ``horizon`` (``dyn`` must be the dynamics at that state, ``qd`` included).
    q_min, q_max : array-like, shape (n,)
        Joint position limits, with ``horizon``.
    braking : float or array-like, shape (n,), optional
        With ``horizon``: the deceleration [rad/s^2] each joint can still brake with after
        the period; the set then also keeps every joint able to stop before its position
        limit (viability, Del Prete 2018).

    Returns
    -------
    Analysis
        :class:`~polyell.capacities.AccelerationAnalysis`, ``VelocityAnalysis`` or
        ``ForceAnalysis`` (``HorizonAnalysis`` with ``horizon``); ``analysis.capacity``
        says which.

    Raises
    ------
    InputError
        For an unknown capacity, missing or misplaced limits (velocity limits for an
        acceleration analysis, torque limits for a velocity one), or bad matrices.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
    >>> an = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), tau_max=[100, 30, 4])
    >>> np.round(an.xg, 3) + 0.0  # + 0.0 shows a rounded -0.0 as 0.0
    array([  0.   , -12.392])
    >>> force = pe.analyze(arm.dynamics([0.3, 0.6, 0.9]), [100, 30, 4], capacity="force")
    >>> force.capacity, force.ellipsoid_kinds
    ('force', ('chiacchio', 'yoshikawa', 'static'))
    """
    cls = capacity_class(capacity)
    state = None
    if horizon is not None or q is not None or qd is not None:
        state = _state(cls, horizon, dyn, q, qd, q_min, q_max, qd_min, qd_max, braking)
        qd_max = qd_min = None  # the horizon's
    upper, lower = joint_limits_of(cls.capacity, tau_max, tau_min, qd_max, qd_min)
    if upper is None:
        raise InputError(
            cls.limit_keywords[0],
            f"{cls.limit_description} for the {cls.capacity} capacity",
            "none",
            cls.limit_hint,
        )
    if state is not None:
        analysis: Analysis = state_of(cls, horizon)(
            dyn, upper, lower, state=state, rank_rtol=rank_rtol, affine_rtol=affine_rtol
        )
    else:
        analysis = cls(dyn, upper, lower, rank_rtol=rank_rtol, affine_rtol=affine_rtol)
    return warn_rated_limits_in_motion(analysis)  # a moving robot given its rated limits


def takes_horizon(capacity: str) -> bool:
    """Whether a capacity takes ``analyze(..., horizon=)`` (accelerations)."""
    return capacity_class(capacity) in _WITHIN_HORIZON


def state_of(cls: type[Analysis], horizon: object) -> type[HorizonAnalysis]:
    """The class of a capacity's set within the joint limits over a horizon.

    Raises an InputError naming ``horizon`` for a capacity that takes none.
    """
    if cls not in _WITHIN_HORIZON:
        raise InputError(
            "horizon",
            "a horizon only for "
            + ", ".join(repr(c.capacity) for c in _WITHIN_HORIZON)
            + " (the joint limits over a control period bound accelerations)",
            f"horizon={horizon!r} with capacity={cls.capacity!r}",
            "leave horizon out.",
        )
    return _WITHIN_HORIZON[cls]


def _state(
    cls: type[Analysis],
    horizon: object,
    dyn: Any,
    q: ArrayLike | None,
    qd: ArrayLike | None,
    q_min: ArrayLike | None,
    q_max: ArrayLike | None,
    qd_min: ArrayLike | None,
    qd_max: ArrayLike | None,
    braking: ArrayLike | None,
) -> JointHorizon:
    """The checked state and limits of ``analyze(..., horizon=)``."""
    if horizon is None:
        raise InputError(
            "q" if q is not None else "qd",
            "a state (q, qd) only with a horizon",
            "a state without horizon=",
            "pass horizon=dt [s] (e.g. 0.001), or leave q and qd out: dyn holds the state.",
        )
    state_of(cls, horizon)
    n = check_dynamics(dyn, cls.capacity).n  # before the state: its shapes need n
    return joint_horizon(
        horizon,
        n,
        q=q,
        qd=qd,
        q_min=q_min,
        q_max=q_max,
        qd_min=qd_min,
        qd_max=qd_max,
        braking=braking,
    )


def joint_limits_of(
    capacity: str,
    tau_max: ArrayLike | None,
    tau_min: ArrayLike | None,
    qd_max: ArrayLike | None,
    qd_min: ArrayLike | None,
) -> tuple[ArrayLike | None, ArrayLike | None]:
    """The limits a capacity takes, ``(upper, lower)``; the other kind refused if given.

    Velocities take ``qd_max``, ``qd_min``; accelerations and forces ``tau_max``,
    ``tau_min`` (the arguments of :func:`analyze` and :func:`polyell.sweep`).
    """
    if capacity == "velocity":
        if tau_max is not None or tau_min is not None:
            raise InputError(
                "tau_max" if tau_max is not None else "tau_min",
                "no torque limits for the velocity capacity",
                "torque limits",
                "pass the joint velocity limits as qd_max= (and qd_min=).",
            )
        return qd_max, qd_min
    if qd_max is not None or qd_min is not None:
        raise InputError(
            "qd_max" if qd_max is not None else "qd_min",
            f"no joint velocity limits for the {capacity} capacity",
            "joint velocity limits",
            "pass capacity='velocity' for velocities.",
        )
    return tau_max, tau_min
