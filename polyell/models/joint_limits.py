"""The joint limits a robot model carries: torques (rated, and at a velocity) and velocities."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.models.torque_speed import TorqueSpeed
from polyell.validation import _describe, array_ndim, check_array

__all__ = ["JointLimits", "check_torque_speed"]


def check_torque_speed(
    torque_speed: object,
    n: int,
    tau_max: NDArray[np.float64] | None,
    tau_min: NDArray[np.float64] | None,
) -> TorqueSpeed | None:
    """Check a robot's torque-speed model: a :class:`TorqueSpeed` of ``n`` joints.

    Its stall torques must hold the robot's rated limits (``tau_max``, ``tau_min``, when
    given): :meth:`TorqueSpeed.limits` refuses them otherwise, naming the limit.
    """
    if torque_speed is None:
        return None
    if not isinstance(torque_speed, TorqueSpeed):
        raise InputError(
            "torque_speed",
            "a pe.TorqueSpeed (TorqueSpeed.linear(tau_stall, qd_no_load) or "
            "TorqueSpeed.table(speeds, torques))",
            _describe(torque_speed),
            "e.g. torque_speed=pe.TorqueSpeed.linear(tau_stall=[...], qd_no_load=[...]).",
        )
    if torque_speed.n != n:
        raise InputError(
            "torque_speed",
            f"a torque-speed model of {n} joints (one curve per joint of the robot)",
            f"one of {torque_speed.n} joints",
            f"give one curve per joint, e.g. pe.TorqueSpeed.linear(tau_stall, qd_no_load) "
            f"with {n} values in each",
        )
    if tau_max is not None:
        torque_speed.limits(np.zeros(n), tau_max, tau_min)
    return torque_speed


class JointLimits:
    """The joint limits of a robot model (a mixin of PlanarArm and UrdfRobot).

    Attributes
    ----------
    tau_max, tau_min : ndarray, shape (n,), or None
        Rated torque limits [N m] (None: the robot has none of its own).
    qd_max, qd_min : ndarray, shape (n,), or None
        Joint velocity limits [rad/s or m/s], a box ``qd_min < qd_max`` (usually
        ``qd_min <= 0 < qd_max``; None: unknown).
    torque_speed : TorqueSpeed or None
        The joints' torque-speed curves (None: the torque limits do not depend on the
        velocity).
    """

    tau_max: NDArray[np.float64] | None
    tau_min: NDArray[np.float64] | None
    qd_max: NDArray[np.float64] | None
    qd_min: NDArray[np.float64] | None
    torque_speed: TorqueSpeed | None
    #: Why ``qd_max`` is None, for the message of :meth:`velocity_limits`.
    _no_velocity_limits: str = "none given"

    @property
    def n(self) -> int:
        """Number of joints."""
        raise NotImplementedError

    def torque_limits(
        self, qd: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Upper and lower joint torque limits, at rest or at the joint velocity ``qd``.

        Parameters
        ----------
        qd : array-like, shape (n,) or (K, n), optional
            Joint velocities [rad/s or m/s]; with a :attr:`torque_speed` model, the
            limits are derated at ``qd`` (:meth:`TorqueSpeed.limits`).

        Returns
        -------
        tau_max, tau_min : ndarray, shape (n,), or (K, n) for a batch of ``qd``
            [N m]: the rated limits when ``qd`` is None or the robot has no
            torque-speed model (repeated along a batch), else the limits at ``qd``.
            A robot with a torque-speed model and no rated limits of its own has
            ``+-tau_stall`` as rated limits.

        Raises
        ------
        InputError
            If the robot has no torque limits at all, or ``qd`` is of a wrong shape, not
            finite, or past a tabulated curve (:meth:`TorqueSpeed.limits`).
        """
        if self.tau_max is None and self.torque_speed is None:
            raise InputError(
                "tau_max",
                "torque limits (the robot has none of its own)",
                "None",
                "pass tau_max=[...] (N m, one per joint) or a torque_speed model to the robot.",
            )
        if self.torque_speed is not None and qd is not None:
            return self.torque_speed.limits(qd, self.tau_max, self.tau_min)
        if self.tau_max is None or self.tau_min is None:
            assert self.torque_speed is not None
            upper, lower = self.torque_speed.tau_stall, -self.torque_speed.tau_stall
        else:
            upper, lower = self.tau_max, self.tau_min
        if qd is None:
            return upper.copy(), lower.copy()
        shape = ("K", self.n) if array_ndim(qd) == 2 else (self.n,)
        velocity = check_array("qd", qd, shape, what="joint velocities [rad/s or m/s]")
        return (
            np.broadcast_to(upper, velocity.shape).copy(),
            np.broadcast_to(lower, velocity.shape).copy(),
        )

    def velocity_limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Upper and lower joint velocity limits ``(qd_max, qd_min)``, shape (n,) each.

        Raises
        ------
        InputError
            If the robot has none (``qd_max`` not given, or missing or zero in its URDF
            for some joint: the message names them).
        """
        if self.qd_max is None or self.qd_min is None:
            raise InputError(
                "qd_max",
                "joint velocity limits for every joint",
                self._no_velocity_limits,
                "pass qd_max=[...] (rad/s or m/s, one per joint; qd_min defaults to -qd_max).",
            )
        return self.qd_max.copy(), self.qd_min.copy()
