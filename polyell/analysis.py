r"""Analysis of one configuration: the map from normalized torques to accelerations.

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

import warnings
from functools import cached_property
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from polyell.errors import (
    InputError,
    ProjectedInputWarning,
    UndefinedEllipsoidError,
    UnreachableAccelerationError,
)
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import (
    AFFINE_RTOL,
    RANK_RTOL,
    RankRevealingSVD,
    rank_revealing_svd,
)
from polyell.inverse import AffineMap, InverseMaps, chiacchio_maps, classic_maps
from polyell.models.dynamics import Dynamics
from polyell.validation import (
    check_fraction,
    check_magnitudes,
    check_points,
    check_torque_limits,
)

__all__ = ["ELLIPSOID_KINDS", "Analysis", "InverseSolution", "analyze"]

EllipsoidKind = Literal["chiacchio", "yoshikawa"]
#: The ellipsoid definitions: the new one (eq. 32/38) and the classic one (eq. 27).
ELLIPSOID_KINDS: tuple[EllipsoidKind, ...] = ("chiacchio", "yoshikawa")


class InverseSolution(NamedTuple):
    """Joint accelerations and normalized torques that realize task accelerations.

    Unpacks as ``qdd, tau_n = solution``.

    Attributes
    ----------
    qdd : ndarray, shape (..., n)
        Joint accelerations [rad/s^2].
    tau_n : ndarray, shape (..., n)
        Normalized joint torques (eq. 10); the torque limits hold iff
        ``|tau_n|_inf <= 1``.
    """

    qdd: NDArray[np.float64]
    tau_n: NDArray[np.float64]

    @property
    def torque_norm(self) -> NDArray[np.float64]:
        """Euclidean norm of ``tau_n``; at most 1 on the ellipsoid of the same definition."""
        return np.linalg.norm(self.tau_n, axis=-1)

    @property
    def within_limits(self) -> NDArray[np.bool_]:
        """Whether every torque respects its limits (``|tau_n|_inf <= 1``, to 1e-9)."""
        return np.max(np.abs(self.tau_n), axis=-1) <= 1.0 + 1e-9


def _check_kind(kind: object) -> EllipsoidKind:
    if not isinstance(kind, str) or kind not in ELLIPSOID_KINDS:
        raise InputError(
            "kind",
            f"one of {', '.join(repr(k) for k in ELLIPSOID_KINDS)}",
            repr(kind),
            "'chiacchio' is the new definition (eq. 32/38), 'yoshikawa' the classic (eq. 27).",
        )
    return kind


class Analysis:
    """Everything about the achievable accelerations of one robot at one configuration.

    Build it with :func:`analyze`.

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

    def __init__(
        self,
        dynamics: Dynamics,
        tau_max: ArrayLike,
        tau_min: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        if not isinstance(dynamics, Dynamics):
            raise InputError(
                "dyn",
                "a polyell.Dynamics",
                type(dynamics).__name__,
                "build one with pe.Dynamics(J, B, g) or arm.dynamics(q).",
            )
        if dynamics.batch_size is not None:
            raise InputError(
                "dyn",
                "the dynamics of one configuration",
                f"a batch of {dynamics.batch_size}",
                "analyze dyn[k] for one of them, or call pe.sweep for the whole batch.",
            )
        self.dynamics = dynamics
        self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, dynamics.n)
        if tau_min is None:  # symmetric limits: exactly what the general formulas give
            self.tau_center, self.half_range = np.zeros(dynamics.n), self.tau_max.copy()
        else:
            self.tau_center = 0.5 * (self.tau_max + self.tau_min)
            self.half_range = 0.5 * (self.tau_max - self.tau_min)
        J, B = dynamics.J, dynamics.B
        self._gravity_bias = dynamics.g - self.tau_center
        # One Cholesky solve (B is positive definite, checked by Dynamics) gives
        # B^-1 J^T, hence J B^-1 = (B^-1 J^T)^T since B is symmetric.
        _, solved, info = lapack.dposv(B, J.T)
        if info != 0:  # pragma: no cover - Dynamics has already factorised B
            raise InputError(
                "dyn.B", "a positive-definite inertia matrix", f"LAPACK dposv info={info}"
            )
        J_Binv = solved.T
        # Entries near 1e308 may overflow here: check_magnitudes refuses inf and NaN.
        with np.errstate(over="ignore", invalid="ignore", under="ignore"):
            self.M: NDArray[np.float64] = J_Binv * self.half_range
            self.xg: NDArray[np.float64] = dynamics.xdd_bias - J_Binv @ self._gravity_bias
        check_magnitudes(self.M, self.xg)
        self.svd: RankRevealingSVD = rank_revealing_svd(self.M, rank_rtol)
        self.affine_rtol = check_fraction("affine_rtol", affine_rtol)
        self._ellipsoids: dict[str, Ellipsoid] = {}
        self._inverse_maps: dict[str, InverseMaps] = {}

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

    @property
    def rank(self) -> int:
        """Numerical rank of ``M`` (equal to that of J)."""
        return self.svd.rank

    @property
    def is_singular(self) -> bool:
        """True at a singular configuration (``rank M < m``, section 5)."""
        return self.rank < self.dynamics.m

    @cached_property
    def polytope(self) -> Polytope:
        """The exact acceleration polytope (eq. 15)."""
        polytope = Polytope(self.M, self.xg, svd=self.svd)
        polytope.affine_rtol = self.affine_rtol
        return polytope

    def ellipsoid(self, kind: EllipsoidKind = "chiacchio") -> Ellipsoid:
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
        kind = _check_kind(kind)
        if kind not in self._ellipsoids:
            if kind == "chiacchio":
                ellipsoid = Ellipsoid(self.xg, self.svd.U1, self.svd.sigma, kind=kind)
            else:
                # N = J^+T Q J^+ = F^T F with F = L^-1 B J^+: the SVD of F gives the axes
                # without squaring the condition number, as an eigendecomposition of N would.
                F = self.torque_map(kind).matrix
                _, s, Vt = np.linalg.svd(F, full_matrices=False)
                ellipsoid = Ellipsoid(self.xg, Vt.T, 1.0 / s, kind=kind)
            ellipsoid.affine_rtol = self.affine_rtol
            self._ellipsoids[kind] = ellipsoid
        return self._ellipsoids[kind]

    def _require_classic(self) -> None:
        if self.is_singular:
            raise UndefinedEllipsoidError(
                f"The classic (Yoshikawa) ellipsoid, eq. (27), needs J J^T invertible, but "
                f"rank J = {self.rank} < m = {self.dynamics.m} at this singular "
                "configuration, so J^+ = J^T (J J^T)^-1 does not exist. Use "
                "kind='chiacchio', which is defined here (eq. 38)."
            )

    def _maps(self, kind: EllipsoidKind) -> InverseMaps:
        """The joint and torque maps of a definition's inverse, built once."""
        kind = _check_kind(kind)
        if kind not in self._inverse_maps:
            dyn, bias = self.dynamics, self._gravity_bias
            if kind == "yoshikawa":
                self._require_classic()
                maps = classic_maps(dyn.J, dyn.B, self.half_range, bias, self.xg)
            else:
                maps = chiacchio_maps(dyn.B, self.half_range, bias, self.xg, self.svd.pinv())
            self._inverse_maps[kind] = maps
        return self._inverse_maps[kind]

    def joint_map(self, kind: EllipsoidKind = "chiacchio") -> AffineMap:
        """The affine inverse map ``xdd -> qdd`` of a definition (eq. 26 or 33/40).

        Written about the centre ``xg`` (see :class:`~polyell.inverse.AffineMap`).

        Raises
        ------
        UndefinedEllipsoidError
            For ``"yoshikawa"`` at a singular configuration.
        """
        return self._maps(kind).joint

    def torque_map(self, kind: EllipsoidKind = "chiacchio") -> AffineMap:
        """The affine map ``xdd -> tau_n`` of a definition's inverse (eq. 26 or 33/40, then 10).

        ``tau_n = L^-1 (B qdd + g - tau_c)``, written about the centre ``xg`` with its value
        there computed without cancellation (the new definition's is exactly 0).
        """
        return self._maps(kind).torque

    def inverse(self, xdd: ArrayLike, kind: EllipsoidKind = "chiacchio") -> InverseSolution:
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
        x = check_points("xdd", xdd, self.dynamics.m)
        if _check_kind(kind) == "chiacchio" and self.is_singular:
            affine_set = self.polytope.affine_set
            if not np.all(affine_set.near(x, self.affine_rtol)):
                distance = np.max(affine_set.distance(x))
                raise UnreachableAccelerationError(
                    f"xdd: expected accelerations in the affine set xg + Im(M) of dimension "
                    f"{self.rank}, got one at distance {distance:.3g} from it (more than "
                    f"affine_rtol = {self.affine_rtol:g} relative); no joint acceleration "
                    "produces it at this singular configuration. Fix: project it with "
                    "analysis.polytope.affine_set.project(xdd)."
                )
            moved = np.max(affine_set.distance(x))
            if moved > self.polytope.atol:
                warnings.warn(
                    f"xdd: taken as rounded and projected onto the affine set of this "
                    f"singular configuration (distance {moved:.3g}); eq. (40) maps the "
                    "projection.",
                    ProjectedInputWarning,
                    stacklevel=2,
                )
            x = affine_set.project(x)
        return InverseSolution(self.joint_map(kind)(x), self.torque_map(kind)(x))


def analyze(
    dyn: Dynamics,
    tau_max: ArrayLike,
    tau_min: ArrayLike | None = None,
    *,
    rank_rtol: float = RANK_RTOL,
    affine_rtol: float = AFFINE_RTOL,
) -> Analysis:
    """Analyze the achievable accelerations of a robot at rest at one configuration.

    Parameters
    ----------
    dyn : Dynamics
        Jacobian, inertia and gravity torques at the configuration.
    tau_max : array-like, shape (n,)
        Upper torque limits [N m].
    tau_min : array-like, shape (n,), optional
        Lower torque limits [N m]; default ``-tau_max``.
    rank_rtol : float, optional
        Relative tolerance of the rank decision (singular values of M at or below
        ``rank_rtol * sigma_max`` are zero); default :data:`~polyell.RANK_RTOL`.
    affine_rtol : float, optional
        At a singular configuration, how far (relative) a direction or a point may be off
        the affine set ``xg + Im(M)`` and still count as in it (rounded input, projected
        with a :class:`~polyell.ProjectedInputWarning`); default
        :data:`~polyell.AFFINE_RTOL`.  Shared by the polytope, the ellipsoids and
        :meth:`Analysis.inverse`.

    Returns
    -------
    Analysis

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6])
    >>> an = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), tau_max=[100, 30, 4])
    >>> np.round(an.xg, 3) + 0.0  # + 0.0 shows a rounded -0.0 as 0.0
    array([  0.   , -12.392])
    """
    return Analysis(dyn, tau_max, tau_min, rank_rtol=rank_rtol, affine_rtol=affine_rtol)
