r"""The acceleration capacity: the map from normalized torques to accelerations (the paper).

With torque limits :math:`\tau_{min} \le \tau \le \tau_{max}` written as
:math:`\tau = \tau_c + L \tilde\tau`, :math:`\|\tilde\tau\|_\infty \le 1`
(:math:`\tau_c = (\tau_{max} + \tau_{min})/2`, :math:`L = \operatorname{diag}((\tau_{max}
- \tau_{min})/2)`: the paper's "suitable transformation" after eq. 9), the achievable
accelerations are :math:`\ddot x = M \tilde\tau + \ddot x_g` (eq. 13) with

.. math::

    M = J B^{-1} L \quad (14), \qquad
    \ddot x_g = -J B^{-1} (g - \tau_c) \quad (8), \qquad
    Q = B L^{-2} B \quad (20).
"""

from __future__ import annotations

from typing import ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from polyell.cached import cached_property
from polyell.capacities.base import InverseSolution, centre_and_half_range
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL
from polyell.inverse import AffineMap, InverseMaps, chiacchio_maps, classic_maps
from polyell.models.dynamics import Dynamics
from polyell.validation import check_fraction, check_torque_limits

__all__ = ["ELLIPSOID_KINDS", "AccelerationAnalysis", "EllipsoidKind", "check_dynamics"]

EllipsoidKind = Literal["chiacchio", "yoshikawa"]
#: The ellipsoid definitions: the new one (eq. 32/38) and the classic one (eq. 27).
ELLIPSOID_KINDS: tuple[EllipsoidKind, ...] = ("chiacchio", "yoshikawa")


def check_dynamics(dynamics: object, capacity: str) -> Dynamics:
    """The dynamics of one configuration, or an InputError naming ``dyn``."""
    if not isinstance(dynamics, Dynamics):
        raise InputError(
            "dyn",
            "a polyell.Dynamics",
            type(dynamics).__name__,
            f"the {capacity} capacity needs J, B and g: build them with pe.Dynamics(J, B, g) "
            "or arm.dynamics(q).",
        )
    if dynamics.batch_size is not None:
        raise InputError(
            "dyn",
            "the dynamics of one configuration",
            f"a batch of {dynamics.batch_size}",
            "analyze dyn[k] for one of them, or call pe.sweep for the whole batch.",
        )
    return dynamics


class AccelerationAnalysis(ZonotopeAnalysis):
    """Everything about the achievable accelerations of one robot at one configuration.

    Build it with ``pe.analyze(dyn, tau_max, tau_min)`` (``capacity="acceleration"``, the
    default).

    Attributes
    ----------
    dynamics : Dynamics
        ``J`` (m, n), ``B`` (n, n), ``g`` (n,).
    tau_max, tau_min : ndarray, shape (n,)
        Torque limits [N m].
    tau_center : ndarray, shape (n,)
        ``tau_c = (tau_max + tau_min) / 2`` [N m].
    half_range : ndarray, shape (n,)
        Diagonal of ``L = diag((tau_max - tau_min) / 2)`` [N m].
    M : ndarray, shape (m, n)
        Eq. (14), ``J B^-1 L`` [m/s^2 per unit normalized torque].
    xg : ndarray, shape (m,)
        Eq. (8) with the shift, ``-J B^-1 (g - tau_c)`` [m/s^2], plus ``Jdot qdot`` for a
        moving robot: the common centre of the polytope and the ellipsoids.
    svd : RankRevealingSVD
        Eq. (35); its rank decision is shared by the polytope, the ellipsoids and the
        inverse maps.
    """

    capacity = "acceleration"
    ellipsoid_kinds = ELLIPSOID_KINDS
    kind_notes: ClassVar[dict[str, str]] = {
        "chiacchio": "the new definition (eq. 32/38)",
        "yoshikawa": "the classic one (eq. 27)",
    }
    quantity = "accelerations"
    inverse_names = ("qdd", "tau_n")
    paper = True
    output_suffix = ""
    polytope_label = "polytope"
    point_symbol = "xdd"
    centre_label = "centre xg"
    centre_label_tex = r"centre $\ddot x_g$"
    dynamics: Dynamics

    def __init__(
        self,
        dynamics: Dynamics,
        tau_max: ArrayLike,
        tau_min: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        dynamics = check_dynamics(dynamics, "acceleration")
        self.dynamics = dynamics
        self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, dynamics.n)
        self.tau_center, self.half_range = centre_and_half_range(self.tau_max, self.tau_min)
        J, B = dynamics.J, dynamics.B
        self._gravity_bias = dynamics.g - self.tau_center
        # One Cholesky solve (B is positive definite, checked by Dynamics) gives
        # B^-1 J^T, hence J B^-1 = (B^-1 J^T)^T since B is symmetric.
        _, solved, info = lapack.dposv(B, J.T)
        if info != 0:  # pragma: no cover - Dynamics has already factorised B
            raise InputError(
                "dyn.B",
                "a positive-definite inertia matrix",
                f"LAPACK dposv info={info}",
                "pass the robot's inertia matrix B(q), e.g. from robot.dynamics(q), symmetric "
                "positive definite",
            )
        J_Binv = solved.T
        # Entries near 1e308 may overflow here: check_magnitudes refuses inf and NaN.
        with np.errstate(over="ignore", invalid="ignore", under="ignore"):
            M = J_Binv * self.half_range
            xg = dynamics.xdd_bias - J_Binv @ self._gravity_bias
        if not M.any() and dynamics.J.any() and self.half_range.any():
            raise InputError(  # J B^-1 L is 0 only for J = 0: its entries underflowed
                "dyn or tau_max",
                "a Jacobian, inertia and torque limits whose accelerations M = J B^-1 L "
                "are representable",
                "M = 0 from a non-zero J and torque range (below 1e-308: underflow)",
                "give J, B and the torque limits in units of moderate size (m, kg m^2, N m).",
            )
        self._set_generators(M, xg, rank_rtol)
        self.affine_rtol = check_fraction("affine_rtol", affine_rtol)
        self._inverse_maps: dict[str, InverseMaps] = {}

    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """``xg`` (eq. 8) and ``M`` (eq. 14)."""
        return {"xg": self.xg, "M": self.M}

    def joint_limits(self) -> dict[str, NDArray[np.float64]]:
        """``tau_max`` and ``tau_min`` [N m]."""
        return {"tau_max": self.tau_max, "tau_min": self.tau_min}

    def __repr__(self) -> str:
        return (
            f"Analysis(m={self.dynamics.m}, n={self.dynamics.n}, rank={self.rank}, "
            f"xg={np.round(self.xg, 6).tolist()})"
        )

    @cached_property
    def Q(self) -> NDArray[np.float64]:
        """Eq. (20), ``B L^-2 B``, shape (n, n)."""
        B = self.dynamics.B
        scaled = B / self.half_range[:, None]  # L^-1 B, then Q = (L^-1 B)^T (L^-1 B)
        return scaled.T @ scaled

    def ellipsoid(self, kind: str | None = "chiacchio") -> Ellipsoid:
        """A dynamic manipulability ellipsoid centred at ``xg``.

        Parameters
        ----------
        kind : {"chiacchio", "yoshikawa"}
            ``"chiacchio"``: the new definition, core ``(J Q^-1 J^T)^-1 = M^+T M^+``
            (eq. 29/30/32), and ``U_1 Sigma^-2 U_1^T`` at singular configurations (eq. 38),
            where it degenerates into the affine set of the polytope.
            ``"yoshikawa"``: the classic definition, core ``J^+T Q J^+`` (eq. 27).

        Raises
        ------
        UndefinedEllipsoidError
            For ``"yoshikawa"`` at a singular configuration, where ``J J^T`` is singular.
        InputError
            For an unknown ``kind``.
        """
        return super().ellipsoid(kind)

    def _build_ellipsoid(self, kind: str) -> Ellipsoid:
        if kind == "chiacchio":
            return self._image_ellipsoid(kind)
        # N = J^+T Q J^+ = F^T F with F = L^-1 B J^+: the SVD of F gives the axes
        # without squaring the condition number, as an eigendecomposition of N would.
        F = self.torque_map(kind).matrix
        _, s, Vt = np.linalg.svd(F, full_matrices=False)
        return Ellipsoid(self.xg, Vt.T, 1.0 / s, kind=kind)

    def _require_classic(self) -> None:
        if self.is_singular:
            raise UndefinedEllipsoidError(
                f"The classic (Yoshikawa) ellipsoid, eq. (27), needs J J^T invertible, but "
                f"rank J = {self.rank} < m = {self.dynamics.m} at this singular "
                "configuration, so J^+ = J^T (J J^T)^-1 does not exist. Use "
                "kind='chiacchio', which is defined here (eq. 38)."
            )

    def _maps(self, kind: str) -> InverseMaps:
        """The joint and torque maps of a definition's inverse, built once."""
        kind = self.check_kind(kind)
        if kind not in self._inverse_maps:
            dyn, bias = self.dynamics, self._gravity_bias
            if kind == "yoshikawa":
                self._require_classic()
                maps = classic_maps(dyn.J, dyn.B, self.half_range, bias, self.xg)
            else:
                maps = chiacchio_maps(dyn.B, self.half_range, bias, self.xg, self.svd.pinv())
            self._inverse_maps[kind] = maps
        return self._inverse_maps[kind]

    def joint_map(self, kind: str = "chiacchio") -> AffineMap:
        """The affine inverse map ``xdd -> qdd`` of a definition (eq. 26 or 33/40).

        Written about the centre ``xg`` (see :class:`~polyell.inverse.AffineMap`).

        Raises
        ------
        UndefinedEllipsoidError
            For ``"yoshikawa"`` at a singular configuration.
        """
        return self._maps(kind).joint

    def torque_map(self, kind: str = "chiacchio") -> AffineMap:
        """The affine map ``xdd -> tau_n`` of a definition's inverse (eq. 26 or 33/40, then 10).

        ``tau_n = L^-1 (B qdd + g - tau_c)``, written about the centre ``xg`` with its value
        there computed without cancellation (the new definition's is exactly 0).
        """
        return self._maps(kind).torque

    def inverse(self, xdd: ArrayLike, kind: str | None = "chiacchio") -> InverseSolution:
        """Joint accelerations and normalized torques that produce ``xdd``.

        Parameters
        ----------
        xdd : array-like, shape (m,) or (k, m)
            Task accelerations [m/s^2].
        kind : {"chiacchio", "yoshikawa"}
            ``"chiacchio"``: eq. (33), or eq. (40)-(41) at singular configurations (the
            minimum normalized-torque solution, eq. 34).  ``"yoshikawa"``: eq. (26),
            ``qdd = J^+ xdd`` (minimum joint-acceleration norm, no gravity term).

        Returns
        -------
        InverseSolution
            ``(qdd, tau_n)`` with ``tau_n = L^-1 (B qdd + g - tau_c)``.

        Raises
        ------
        UnreachableAccelerationError
            If ``xdd`` is off the affine set ``xg + Im(M)`` of a singular configuration: no
            joint acceleration produces it.
        UndefinedEllipsoidError
            For ``"yoshikawa"`` at a singular configuration.
        """
        kind = self.check_kind("chiacchio" if kind is None else kind)
        x = self._points(xdd, "xdd")
        if kind == "chiacchio":
            x = self._on_affine_set(x, "xdd")
        return InverseSolution(self.joint_map(kind)(x), self.torque_map(kind)(x))

    def _witness_map(self, kind: str) -> AffineMap:
        """``xdd -> tau_n`` by the classic inverse for ``"yoshikawa"``, else eq. 33/40."""
        return self.torque_map("yoshikawa" if kind == "yoshikawa" else "chiacchio")
