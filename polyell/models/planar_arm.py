"""Closed-form kinematics and dynamics of a planar serial arm in a vertical plane."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.models.dynamics import Dynamics
from polyell.models.joint_limits import JointLimits, check_torque_speed
from polyell.models.torque_speed import TorqueSpeed
from polyell.validation import (
    array_ndim,
    check_array,
    check_torque_limits,
    check_velocity_limits,
)

__all__ = ["PlanarArm"]


#: Largest joint angle [rad]: the rounding of an angle of size a is about a * 1.1e-16, so
#: below 1e6 rad its sine and cosine keep 10 digits.
MAX_ANGLE = 1e6
#: Link parameters [SI units] within ``10^+-MAX_PARAMETER_EXPONENT``: the inertia
#: ``m l^2`` and the gravity torques ``m g l`` of n links stay finite.
MAX_PARAMETER_EXPONENT = 50


def _bounded(name: str, array: NDArray[np.float64]) -> NDArray[np.float64]:
    """Refuse parameters beyond ``10^MAX_PARAMETER_EXPONENT`` (or non-zero ones below 1/that)."""
    size = np.abs(array)
    high = 10.0**MAX_PARAMETER_EXPONENT
    bad = np.flatnonzero((size > high) | ((size > 0) & (size < 1.0 / high)))
    if bad.size:
        where = f"{name}[{bad[0]}]" if array.ndim else name
        raise InputError(
            name,
            f"values of size within 1e-{MAX_PARAMETER_EXPONENT}..1e{MAX_PARAMETER_EXPONENT} "
            "(SI units), so that inertias and gravity torques stay representable",
            f"{where} = {np.ravel(array)[bad[0]]:.3g}",
            "give the link parameters in metres, kilograms and kg m^2.",
        )
    return array


def _positive(name: str, value: ArrayLike, n: int | None = None) -> NDArray[np.float64]:
    array = _bounded(name, check_array(name, value, (n,)))
    bad = np.flatnonzero(array <= 0)
    if bad.size:
        raise InputError(
            name,
            "strictly positive values",
            f"{name}[{bad[0]}] = {array[bad[0]]:g}",
            "lengths, masses and inertias of real links are positive.",
        )
    return array


class PlanarArm(JointLimits):
    r"""An n-link planar arm with revolute joints moving in a vertical plane.

    Gravity acts along :math:`-y`; joint angles are relative (joint i turns link i
    with respect to link i-1, the first from the :math:`x` axis); the task is the
    end-effector position :math:`(x, y)`.  Link :math:`i` has its centre of mass on
    its axis at distance ``com[i]`` from joint i.  With absolute angles
    :math:`\theta_i = q_1 + \dots + q_i`, the centre of mass of link i is at
    :math:`p_i = \sum_{j<i} l_j u(\theta_j) + l_{c,i} u(\theta_i)`,
    :math:`u(\theta) = (\cos\theta, \sin\theta)`, and

    .. math::

        B = \sum_i m_i J_{p_i}^T J_{p_i} + I_i J_{o_i}^T J_{o_i}, \qquad
        g = \sum_i m_i g_0 J_{p_i}^T e_y,

    with :math:`J_{o_i} = (1, \dots, 1, 0, \dots, 0)` (i ones).

    Parameters
    ----------
    lengths : array-like, shape (n,)
        Link lengths [m].
    masses : array-like, shape (n,)
        Link masses [kg].
    com : array-like, shape (n,), optional
        Distance of each link's centre of mass from its joint [m]; default mid-link.
    inertia : array-like, shape (n,), optional
        Moment of inertia of each link about its centre of mass [kg m^2]; default
        ``m l^2 / 12`` (a uniform rod, i.e. ``m l^2 / 3`` about the joint axis).
    gravity : float, optional
        Magnitude of the gravitational acceleration along :math:`-y` [m/s^2].
    tau_max, tau_min : array-like, shape (n,), optional
        The joint torque limits [N m] the robot carries with it (used by studies and
        the command line when no limits are given); ``tau_min`` defaults to ``-tau_max``.
    qd_max, qd_min : array-like, shape (n,), optional
        Joint velocity limits [rad/s], a box ``qd_min < qd_max`` (usually
        ``qd_min <= 0 < qd_max``); ``qd_min`` defaults to
        ``-qd_max`` (:meth:`velocity_limits`).
    torque_speed : TorqueSpeed, optional
        The joints' torque-speed curves: :meth:`torque_limits` gives the torque limits
        at a joint velocity.  Its stall torques must hold ``tau_max`` and ``tau_min``.

    Examples
    --------
    The arm of Chiacchio (2000), section 6:

    >>> import numpy as np, polyell as pe
    >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
    >>> dyn = arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2])
    >>> dyn.J.shape, dyn.B.shape
    ((2, 3), (3, 3))
    """

    def __init__(
        self,
        lengths: Sequence[float] | ArrayLike,
        masses: Sequence[float] | ArrayLike,
        com: Sequence[float] | ArrayLike | None = None,
        inertia: Sequence[float] | ArrayLike | None = None,
        gravity: float = 9.81,
        tau_max: ArrayLike | None = None,
        tau_min: ArrayLike | None = None,
        qd_max: ArrayLike | None = None,
        qd_min: ArrayLike | None = None,
        torque_speed: TorqueSpeed | None = None,
    ) -> None:
        self.lengths = _positive("lengths", lengths)
        n = self.lengths.size
        if n == 0:
            raise InputError(
                "lengths",
                "at least one link",
                "an empty sequence",
                "give one length [m] per link, e.g. lengths=[1.0, 0.8, 0.5]",
            )
        self.masses = _positive("masses", masses, n)
        self.com = (
            0.5 * self.lengths if com is None else _bounded("com", check_array("com", com, (n,)))
        )
        self.inertia = (
            self.masses * self.lengths**2 / 12.0
            if inertia is None
            else _bounded("inertia", check_array("inertia", inertia, (n,)))
        )
        if np.any(self.inertia < 0):
            raise InputError(
                "inertia",
                "non-negative inertias",
                f"{self.inertia}",
                "give each link's inertia about its centre of mass [kg m^2] as a value >= 0, "
                "or leave inertia out for thin rods (m l^2 / 12)",
            )
        self.gravity = float(_bounded("gravity", check_array("gravity", gravity, ())))
        self.tau_max: NDArray[np.float64] | None = None
        self.tau_min: NDArray[np.float64] | None = None
        if tau_max is not None:
            self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, n)
        elif tau_min is not None:
            raise InputError(
                "tau_min", "tau_min only together with tau_max", "tau_min alone", "give both."
            )
        self.qd_max: NDArray[np.float64] | None = None
        self.qd_min: NDArray[np.float64] | None = None
        if qd_max is not None:
            self.qd_max, self.qd_min = check_velocity_limits(qd_max, qd_min, n)
            self.qd_max.flags.writeable = self.qd_min.flags.writeable = False
        elif qd_min is not None:
            raise InputError(
                "qd_min", "qd_min only together with qd_max", "qd_min alone", "give both."
            )
        self.torque_speed = check_torque_speed(torque_speed, n, self.tau_max, self.tau_min)
        for array in (self.lengths, self.masses, self.com, self.inertia):
            array.flags.writeable = False

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.lengths.size)

    def __repr__(self) -> str:
        limits = None if self.tau_max is None else self.tau_max.tolist()
        return (
            f"PlanarArm(lengths={self.lengths.tolist()}, masses={self.masses.tolist()}, "
            f"com={self.com.tolist()}, inertia={self.inertia.tolist()}, "
            f"gravity={self.gravity}, tau_max={limits}"
            + ("" if self.qd_max is None else f", qd_max={self.qd_max.tolist()}")
            + ("" if self.torque_speed is None else f", torque_speed={self.torque_speed!r}")
            + ")"
        )

    def _check_q(self, q: ArrayLike, batch: bool = False) -> NDArray[np.float64]:
        shape = ("K", self.n) if batch and array_ndim(q) == 2 else (self.n,)
        angles = check_array("q", q, shape, what="joint angles [rad]")
        if angles.size and np.max(np.abs(angles)) > MAX_ANGLE:
            raise InputError(
                "q",
                f"joint angles of size at most {MAX_ANGLE:g} rad (their sines and cosines "
                "then keep 10 digits)",
                f"an angle of {angles.flat[np.argmax(np.abs(angles))]:.3g} rad",
                "reduce the angles modulo 2 pi.",
            )
        return angles

    def forward_kinematics(self, q: ArrayLike) -> NDArray[np.float64]:
        """End-effector position [m], shape (2,), at joint angles ``q`` [rad]."""
        theta = np.cumsum(self._check_q(q))
        return np.array([self.lengths @ np.cos(theta), self.lengths @ np.sin(theta)])

    def jacobian(self, q: ArrayLike) -> NDArray[np.float64]:
        """End-effector position Jacobian [m/rad], shape (2, n)."""
        return self._point_jacobians(self._check_q(q))[0]

    def _point_jacobians(
        self, q: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Jacobians of the end effector (..., 2, n) and of each centre of mass (..., n, 2, n)."""
        theta = np.cumsum(q, axis=-1)
        # d u(theta_j) / d q_k = u'(theta_j) for k <= j, with u' = (-sin, cos), so a point
        # sum_j w_j u(theta_j) has Jacobian column k = sum_{j >= k} w_j u'(theta_j).
        du = np.stack([-np.sin(theta), np.cos(theta)], axis=-2)  # column j is u'(theta_j)
        suffix_sum = np.tri(self.n)  # [j, k] = 1 where j >= k
        tip = (du * self.lengths) @ suffix_sum
        # Centre of mass i: weights l_j for j < i, com_i for j = i, 0 beyond.
        weights = np.tril(np.broadcast_to(self.lengths, (self.n, self.n)), -1)
        weights[np.diag_indices(self.n)] = self.com
        com = np.einsum("...aj,ij,jk->...iak", du, weights, suffix_sum)
        return tip, com

    def dynamics(self, q: ArrayLike) -> Dynamics:
        """Jacobian, inertia matrix and gravity torques at ``q``.

        Parameters
        ----------
        q : array-like, shape (n,) or (K, n)
            Relative joint angles [rad]; a 2-D array gives a batched :class:`Dynamics`.

        Returns
        -------
        Dynamics
            ``J`` (2, n) [m/rad], ``B`` (n, n) [kg m^2], ``g`` (n,) [N m] (with a leading
            K for a batch).
        """
        q = self._check_q(q, batch=True)
        tip, com = self._point_jacobians(q)
        angular = np.tri(self.n)  # row i: ones for joints 1..i
        B = np.einsum("i,...iak,...ial->...kl", self.masses, com, com)
        B += np.einsum("i,ik,il->kl", self.inertia, angular, angular)
        g = self.gravity * np.einsum("i,...ik->...k", self.masses, com[..., 1, :])
        return Dynamics(J=tip, B=B, g=g, task=("x", "y"))
