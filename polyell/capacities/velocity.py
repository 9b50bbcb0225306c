r"""The velocity capacity: end-effector velocities within the joint velocity limits.

With :math:`\dot q_{min} \le \dot q \le \dot q_{max}` written as :math:`\dot q = \dot q_c
+ L_v u`, :math:`\|u\|_\infty \le 1` (:math:`\dot q_c = (\dot q_{max} + \dot q_{min})/2`,
:math:`L_v = \operatorname{diag}((\dot q_{max} - \dot q_{min})/2)`), the achievable
velocities :math:`\dot x = J \dot q` form the zonotope

.. math::

    P_v = \{ J L_v u + J \dot q_c : \|u\|_\infty \le 1 \},

and the manipulability ellipsoid is the image of the unit ball of normalized joint
velocities, :math:`\{J \dot q_c + J L_v u : \|u\| \le 1\}` (Yoshikawa's, with the limits
as weights; a linear map has no second definition).  It lies inside :math:`P_v` (the ball
lies in the cube); its witness :math:`u = (J L_v)^+ (\dot x - J \dot q_c)` is the smallest
normalized joint velocity that produces :math:`\dot x`.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities.base import InverseSolution, JointLimited, centre_and_half_range
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL
from polyell.inverse import AffineMap
from polyell.models.dynamics import Dynamics
from polyell.models.kinematics import Kinematics
from polyell.validation import check_fraction, check_torque_limits, source_velocity_limits

__all__ = ["VelocityAnalysis"]


class VelocityAnalysis(ZonotopeAnalysis):
    """The achievable end-effector velocities of one robot at one configuration.

    Build it with ``pe.analyze(kin, capacity="velocity", qd_max=..., qd_min=...)``.

    Attributes
    ----------
    dynamics : Kinematics or Dynamics
        ``J`` (m, n) and the task's row names.
    qd_max, qd_min : ndarray, shape (n,)
        Joint velocity limits [rad/s].
    qd_center, half_range : ndarray, shape (n,)
        ``(qd_max + qd_min) / 2`` and the diagonal of ``L_v = diag((qd_max - qd_min) / 2)``.
    M : ndarray, shape (m, n)
        ``J L_v`` [m/s per unit normalized joint velocity].
    xg : ndarray, shape (m,)
        ``J qd_center`` [m/s]: the centre of the polytope and the ellipsoid.
    """

    capacity = "velocity"
    ellipsoid_kinds = ("yoshikawa",)
    kind_notes: ClassVar[dict[str, str]] = {
        "yoshikawa": "the image of the unit ball of normalized joint velocities"
    }
    quantity = "velocities"
    inverse_names = ("qd", "u")
    limit_keywords = ("qd_max", "qd_min")
    limit_description = "joint velocity limits [rad/s]"
    limit_hint = "pass qd_max=[...] (e.g. robot.qd_max, the URDF's velocity limits)."
    in_motion = False
    output_suffix = "_velocity"
    magnitude_names = ("velocities", "J L_v", "J qd_c")
    # its set is the acceleration zonotope of B = I, g = 0, its ellipsoid that one's image
    acceleration_names: ClassVar[dict[str, str]] = {
        "polytope": "polytope",
        "chiacchio": "yoshikawa",
    }

    @classmethod
    def _acceleration_dynamics(cls, dyn: Dynamics) -> Dynamics:
        """A batch with ``B = I``, ``g = 0`` and no bias: ``M = J L_v``, ``x_g = J qd_c``.

        Its image ellipsoid (``"chiacchio"``) is the velocity capacity's ``"yoshikawa"``.
        """
        K, n = len(dyn), dyn.n
        return Dynamics(dyn.J, np.broadcast_to(np.eye(n), (K, n, n)), np.zeros((K, n)))

    @classmethod
    def _robot_limits(
        cls, robot: JointLimited, qd: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The robot's joint velocity limits ``(qd_max, qd_min)`` (``qd`` unused)."""
        return robot.velocity_limits()

    @classmethod
    def _source_limits(
        cls, source: object, upper: ArrayLike | None, lower: ArrayLike | None, n: int
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint velocity limits given, checked, or else ``source.velocity_limits()``."""
        return source_velocity_limits(source, upper, lower, n)

    def __init__(
        self,
        kinematics: Kinematics | Dynamics,
        qd_max: ArrayLike,
        qd_min: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        if not isinstance(kinematics, Kinematics | Dynamics) or kinematics.batch_size is not None:
            raise InputError(
                "dyn",
                "the Jacobian of one configuration: a polyell.Kinematics or Dynamics",
                type(kinematics).__name__
                if not isinstance(kinematics, Dynamics)
                else f"a batch of {kinematics.batch_size}",
                "build one with pe.Kinematics(J) or arm.dynamics(q); call pe.sweep for a batch.",
            )
        self.dynamics = kinematics
        self.qd_max, self.qd_min = check_torque_limits(
            qd_max, qd_min, kinematics.n, names=("qd_max", "qd_min")
        )
        self.qd_center, self.half_range = centre_and_half_range(self.qd_max, self.qd_min)
        J = kinematics.J
        with np.errstate(over="ignore", invalid="ignore", under="ignore"):
            M, xg = J * self.half_range, J @ self.qd_center
        self._set_generators(M, xg, rank_rtol)
        self.affine_rtol = check_fraction("affine_rtol", affine_rtol)

    def __repr__(self) -> str:
        return (
            f"VelocityAnalysis(m={self.m}, n={self.n}, rank={self.rank}, "
            f"center={np.round(self.xg, 6).tolist()})"
        )

    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """``center = J qd_c`` and ``M = J L_v``."""
        return {"center": self.xg, "M": self.M}

    def joint_limits(self) -> dict[str, NDArray[np.float64]]:
        """``qd_max`` and ``qd_min`` [rad/s]."""
        return {"qd_max": self.qd_max, "qd_min": self.qd_min}

    def _build_ellipsoid(self, kind: str) -> Ellipsoid:
        return self._image_ellipsoid(kind)

    def _witness_map(self, kind: str) -> AffineMap:
        """``xd -> u = (J L_v)^+ (xd - J qd_c)``, the minimum-norm normalized velocities."""
        return self._minimum_norm_map()

    def inverse(self, x: ArrayLike, kind: str | None = None) -> InverseSolution:
        """Joint velocities of least normalized norm that produce end-effector velocities.

        Parameters
        ----------
        x : array-like, shape (m,) or (k, m)
            End-effector velocities [m/s or rad/s].
        kind : {"yoshikawa"}, optional
            The only definition of this capacity.

        Returns
        -------
        InverseSolution
            ``(qd, u)`` with ``qd = qd_c + L_v u`` [rad/s] and ``u = (J L_v)^+ (x - J qd_c)``.

        Raises
        ------
        UnreachableAccelerationError
            If ``x`` is off the affine set of a singular configuration.
        """
        self.check_kind("yoshikawa" if kind is None else kind)
        points = self._on_affine_set(self._points(x, "x"), "x")
        u = self._minimum_norm_map()(points)
        return InverseSolution(self.qd_center + u * self.half_range, u)
