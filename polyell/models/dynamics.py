"""The dynamic quantities of a robot at one configuration (at rest, or moving).

A robot in motion whose drives derate (a :class:`~polyell.TorqueSpeed` model) gives its
:class:`Dynamics` a :class:`MotionLimits`: the joint velocities and the torque limits the
drives give there.  :func:`check_motion_limits` warns (:class:`~polyell.DeratingWarning`)
when an analysis of such a Dynamics is given torque limits beyond those.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import DeratingWarning, InputError
from polyell.models.task import check_task
from polyell.validation import array_ndim, as_floats, check_array, check_spd

__all__ = [
    "MOTION_LIMIT_RTOL",
    "Dynamics",
    "MotionLimits",
    "check_motion_limits",
    "warn_rated_limits_in_motion",
]

#: How far (relative to ``1 + |rated limit|``) a torque limit may exceed the derated one
#: before :func:`check_motion_limits` warns: rounding, not a slip.
MOTION_LIMIT_RTOL = 1e-9

_AnalysisT = TypeVar("_AnalysisT")


@dataclass(frozen=True, init=False)
class MotionLimits:
    r"""The joint velocities of a :class:`Dynamics` and the torque limits of its drives there.

    :meth:`~polyell.UrdfRobot.dynamics` attaches one (``dyn.motion``) when the robot has a
    torque-speed model and moves (``qd != 0``): an analysis with torque limits beyond
    ``tau_max``, ``tau_min`` then warns (:func:`check_motion_limits`).

    Parameters
    ----------
    qd : array-like, shape (n,) or (K, n)
        Joint velocities [rad/s or m/s].
    tau_max, tau_min : array-like, same shape as ``qd``
        Upper and lower torque limits the drives give at ``qd`` [N m or N] (derated in the
        direction of motion: :meth:`~polyell.TorqueSpeed.limits`).
    rated_max, rated_min : array-like, shape (n,)
        The robot's rated torque limits (at rest) [N m or N].
    joints : sequence of str
        The n joint names, for messages.

    Raises
    ------
    InputError
        On mismatched shapes or non-finite entries.
    """

    qd: NDArray[np.float64]
    tau_max: NDArray[np.float64]
    tau_min: NDArray[np.float64]
    rated_max: NDArray[np.float64]
    rated_min: NDArray[np.float64]
    joints: tuple[str, ...]

    def __init__(
        self,
        qd: ArrayLike,
        tau_max: ArrayLike,
        tau_min: ArrayLike,
        rated_max: ArrayLike,
        rated_min: ArrayLike,
        joints: Sequence[str],
    ) -> None:
        shape = ("K", "n") if array_ndim(qd) == 2 else ("n",)
        velocity = check_array("qd", qd, shape, what="joint velocities [rad/s or m/s]")
        n = velocity.shape[-1]
        arrays = {
            "qd": velocity,
            "tau_max": check_array("tau_max", tau_max, velocity.shape, what="torques [N m]"),
            "tau_min": check_array("tau_min", tau_min, velocity.shape, what="torques [N m]"),
            "rated_max": check_array("rated_max", rated_max, (n,), what="torques [N m]"),
            "rated_min": check_array("rated_min", rated_min, (n,), what="torques [N m]"),
        }
        names = tuple(str(name) for name in joints)
        if len(names) != n:
            raise InputError(
                "joints",
                f"{n} joint names",
                f"{len(names)}: {list(names)}"[:200],
                f"pass one name per column of qd ({n}), e.g. joints=robot.joint_names",
            )
        for name, array in arrays.items():
            array.flags.writeable = False
            object.__setattr__(self, name, array)
        object.__setattr__(self, "joints", names)

    def __getitem__(self, index: int | slice) -> MotionLimits:
        """One configuration (an int) or a sub-batch (a slice) of a batch."""
        return MotionLimits(
            self.qd[index],
            self.tau_max[index],
            self.tau_min[index],
            self.rated_max,
            self.rated_min,
            self.joints,
        )


@dataclass(frozen=True, init=False)
class Dynamics:
    r"""Jacobian, inertia and gravity torques of a manipulator at one configuration.

    These are the inputs of the paper's eq. (4)-(8) for a robot at rest
    (:math:`\dot q = 0`, no contact force): :math:`\ddot x = J \ddot q` and
    :math:`\tau = B \ddot q + g`.  For a robot in motion (beyond the paper, eq. 2-3),
    :math:`\ddot x = J \ddot q + \dot J \dot q` and :math:`\tau = B \ddot q + c + g`:
    pass :math:`c + g` as ``g`` and :math:`\dot J \dot q` as ``xdd_bias``.

    A batch of configurations (for :func:`polyell.sweep`) stacks the arrays along a first
    axis: ``J`` (K, m, n), ``B`` (K, n, n), ``g`` (K, n), ``xdd_bias`` (K, m).

    Parameters
    ----------
    J : array-like, shape (m, n)
        Task Jacobian (rows all linear [m/rad] or all angular [1]).  More rows than
        joints (``m > n``) is allowed: the sets are then degenerate (rank at most n).
    B : array-like, shape (n, n)
        Joint-space inertia matrix [kg m^2], symmetric positive definite.
    g : array-like, shape (n,)
        Gravity torques [N m] (plus Coriolis and centrifugal torques for a moving robot).
    xdd_bias : array-like, shape (m,), optional
        Velocity-product acceleration ``Jdot qdot`` [m/s^2]; zero (default) at rest.
    task : sequence of str, optional
        Names of the m task rows (``x y z`` linear, ``wx wy wz`` angular), used for axis
        labels and units; default :func:`~polyell.models.task.default_task`.
    motion : MotionLimits, optional
        For a robot in motion whose drives derate: its joint velocities and the torque
        limits of its drives there (set by :meth:`~polyell.UrdfRobot.dynamics`); an
        analysis given larger torque limits warns.  None (default): nothing known.

    Raises
    ------
    InputError
        On mismatched shapes, non-finite entries, an inertia matrix that is not
        symmetric positive definite, or a ``motion`` of other joints or another batch.

    Examples
    --------
    >>> import polyell as pe
    >>> dyn = pe.Dynamics(J=[[1.0, 0.5]], B=[[2.0, 0.1], [0.1, 1.0]], g=[3.0, 1.0])
    >>> dyn.m, dyn.n
    (1, 2)
    """

    J: NDArray[np.float64]
    B: NDArray[np.float64]
    g: NDArray[np.float64]
    xdd_bias: NDArray[np.float64]
    task: tuple[str, ...]
    motion: MotionLimits | None = field(default=None, compare=False, repr=False)

    def __init__(
        self,
        J: ArrayLike,
        B: ArrayLike,
        g: ArrayLike,
        xdd_bias: ArrayLike | None = None,
        task: Sequence[str] | None = None,
        *,
        motion: MotionLimits | None = None,
    ) -> None:
        shape = ("K", "m", "n") if array_ndim(J) == 3 else ("m", "n")
        jacobian = check_array("J", J, shape, what="Jacobian entries")
        *batch, m, n = jacobian.shape
        if m == 0 or n == 0:
            raise InputError(
                "J",
                "at least one task row and one joint",
                f"shape {jacobian.shape}",
                "pass a Jacobian of shape (m, n) with m, n >= 1, e.g. J=[[1.0, 0.5]]",
            )
        object.__setattr__(self, "J", jacobian)
        object.__setattr__(self, "B", check_spd("B", B, n, tuple(batch)))
        object.__setattr__(self, "g", check_array("g", g, (*batch, n)))
        bias = (
            np.zeros((*batch, m))
            if xdd_bias is None
            else check_array("xdd_bias", xdd_bias, (*batch, m))
        )
        object.__setattr__(self, "xdd_bias", bias)
        object.__setattr__(self, "task", check_task(task, m))
        if motion is not None:
            if not isinstance(motion, MotionLimits):
                raise InputError(
                    "motion",
                    "a MotionLimits (set by robot.dynamics(q, qd)) or None",
                    f"{type(motion).__name__}",
                    "leave it out: a robot in motion sets it.",
                )
            if motion.qd.shape != (*batch, n):
                raise InputError(
                    "motion",
                    f"joint velocities of shape {(*batch, n)} (one row per configuration)",
                    f"shape {motion.qd.shape}",
                    "pass the motion of the same configurations, e.g. "
                    "robot.dynamics(q, qd).motion, or leave motion out",
                )
        object.__setattr__(self, "motion", motion)
        for array in (self.J, self.B, self.g, self.xdd_bias):
            array.flags.writeable = False

    @property
    def m(self) -> int:
        """Task-space dimension."""
        return int(self.J.shape[-2])

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.J.shape[-1])

    @property
    def batch_size(self) -> int | None:
        """Number K of configurations in a batch, None for a single configuration."""
        return int(self.J.shape[0]) if self.J.ndim == 3 else None

    def __len__(self) -> int:
        if self.batch_size is None:
            raise TypeError("a single-configuration Dynamics has no length")
        return self.batch_size

    def __getitem__(self, index: int | slice) -> Dynamics:
        """One configuration (an int) or a sub-batch (a slice) of a batch."""
        if self.batch_size is None:
            raise InputError(
                "index",
                "a batched Dynamics (J of shape (K, m, n))",
                "a single one",
                "use this Dynamics as it is (it is one configuration), or index a batch, "
                "e.g. robot.dynamics(Q)[0] for Q of shape (K, n)",
            )
        return Dynamics(
            self.J[index],
            self.B[index],
            self.g[index],
            self.xdd_bias[index],
            self.task,
            motion=None if self.motion is None else self.motion[index],
        )


def _limits_like(name: str, value: ArrayLike, shape: tuple[int, ...]) -> NDArray[np.float64]:
    """Torque limits as floats of ``shape`` (or broadcast to it), NaN refused; inf is no limit."""
    array = as_floats(name, value)
    try:
        array = np.broadcast_to(array, shape)
    except ValueError:
        raise InputError(
            name,
            f"torque limits of shape {shape}",
            f"shape {array.shape}",
            f"pass one limit per joint, shape {shape}, or one number for all, e.g. {name}=100.0",
        ) from None
    if np.isnan(array).any():
        raise InputError(
            name,
            "torque limits without NaN",
            f"{array}"[:120],
            "replace each NaN by the joint's limit [N m], or by np.inf where it has none",
        )
    return array


def check_motion_limits(
    dynamics: object, tau_max: ArrayLike, tau_min: ArrayLike, *, stacklevel: int = 1
) -> None:
    """Warn if torque limits exceed what a moving robot's drives give at its velocities.

    A :class:`Dynamics` of a robot in motion with a torque-speed model carries
    ``dynamics.motion`` (:class:`MotionLimits`); torque limits above its ``tau_max`` or
    below its ``tau_min`` for some joint (beyond :data:`MOTION_LIMIT_RTOL`) give a set
    that is too large: a :class:`~polyell.DeratingWarning` names the joints, the limits
    given and those at ``qd``.  Nothing happens for a Dynamics without ``motion`` (at
    rest, no torque-speed model, built by hand).

    Parameters
    ----------
    dynamics : Dynamics or Kinematics
        The robot's quantities at the configuration (one, or a batch of K).
    tau_max, tau_min : array-like, shape (n,), or (K, n) for a batch
        The torque limits of the analysis [N m], checked already.
    stacklevel : int, optional
        Which frame the warning names, as :func:`warnings.warn`'s but counted from the
        caller of this function (1: the line that called it).

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> motion = MotionLimits([2.0], [50.0], [-100.0], [100.0], [-100.0], ["j1"])
    >>> dyn = pe.Dynamics([[1.0]], [[1.0]], [0.0], motion=motion)
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     check_motion_limits(dyn, [100.0], [-100.0])
    >>> caught[0].category.__name__, caught[0].message.joints
    ('DeratingWarning', ('j1',))
    """
    motion = getattr(dynamics, "motion", None)
    if not isinstance(motion, MotionLimits):
        return
    upper, lower = (
        _limits_like(name, value, motion.tau_max.shape)
        for name, value in (("tau_max", tau_max), ("tau_min", tau_min))
    )
    tol = MOTION_LIMIT_RTOL * (1.0 + np.maximum(abs(motion.rated_max), abs(motion.rated_min)))
    over = upper - motion.tau_max > tol  # (n,) or (K, n)
    under = motion.tau_min - lower > tol
    if not (over.any() or under.any()):
        return
    batch = motion.qd.ndim == 2
    rows = len(motion.qd) if batch else 1
    over2, under2 = np.atleast_2d(over), np.atleast_2d(under)
    qd2, upper2, lower2 = np.atleast_2d(motion.qd), np.atleast_2d(upper), np.atleast_2d(lower)
    derated_upper, derated_lower = np.atleast_2d(motion.tau_max), np.atleast_2d(motion.tau_min)
    parts, joints = [], []
    for j, name in enumerate(motion.joints):
        for side, bad, given, derated, bound in (
            ("tau_max", over2[:, j], upper2[:, j], derated_upper[:, j], "at most"),
            ("tau_min", under2[:, j], lower2[:, j], derated_lower[:, j], "at least"),
        ):
            if not bad.any():
                continue
            excess = np.where(bad, np.abs(given - derated), -np.inf)
            k = int(np.argmax(excess))
            where = f"row {k}, " if batch else ""
            count = f" (in {int(bad.sum())} of {rows} configurations)" if batch else ""
            parts.append(
                f"{name} ({where}qd = {qd2[k, j]:.4g} rad/s): {side} = {given[k]:.4g} N m, its "
                f"drive gives {bound} {derated[k]:.4g} N m there{count}"
            )
            if name not in joints:
                joints.append(name)
    rated = bool(
        np.allclose(upper, motion.rated_max, rtol=1e-12, atol=0.0)
        and np.allclose(lower, motion.rated_min, rtol=1e-12, atol=0.0)
    )
    argument = " and ".join(
        side for side, bad in (("tau_max", over), ("tau_min", under)) if bad.any()
    )
    message = (
        f"{argument}: torque limits beyond what the drives give at the joint velocities qd "
        f"of this robot in motion (its torque-speed model derates the torque in the "
        f"direction of motion): {'; '.join(parts)}. "
        + (
            "These are the robot's rated limits (at rest): "
            if rated
            else "The limits given exceed the derated ones: "
        )
        + "the set is too large. Fix: analyse with the limits at qd, "
        "pe.analyze(robot.dynamics(q, qd), *robot.torque_limits(qd)), or robot.analyze(q, qd)."
    )
    warnings.warn(DeratingWarning(message, tuple(joints)), stacklevel=stacklevel + 1)


def warn_rated_limits_in_motion(analysis: _AnalysisT) -> _AnalysisT:
    """Check an analysis's torque limits against its robot's drives in motion; return it.

    The hook of :func:`polyell.analyze`: for a capacity that depends on the motion
    (``in_motion``: accelerations, forces) whose ``dynamics`` carries
    :class:`MotionLimits`, :func:`check_motion_limits` on the analysis's torque limits
    (the warning names the caller of ``analyze``).  Other analyses pass unchanged.

    Parameters
    ----------
    analysis : Analysis
        A new analysis (``analysis.dynamics``, ``analysis.joint_limits()``).

    Returns
    -------
    Analysis
        ``analysis`` itself.
    """
    subject: Any = analysis
    if getattr(type(subject), "in_motion", False):
        limits = subject.joint_limits()
        if "tau_max" in limits and "tau_min" in limits:
            check_motion_limits(
                subject.dynamics, limits["tau_max"], limits["tau_min"], stacklevel=3
            )
    return analysis
