r"""The static force capacity: end-effector forces within the torque limits, with gravity.

At rest, an end-effector force (or moment) :math:`h` needs the joint torques
:math:`\tau = J^T h + g`.  With :math:`\tau = \tau_c + L \tilde\tau`,
:math:`\|\tilde\tau\|_\infty \le 1`, write :math:`A = L^{-1} J^T` (n, m) and
:math:`c = L^{-1} (g - \tau_c)`; the forces the arm can exert form the H-polytope

.. math::

    P_f = \{ h : \|A h + c\|_\infty \le 1 \}
        = \{ h : A h \le 1 - c,\ -A h \le 1 + c \}

(2n half-spaces in :math:`R^m`).  At a singular posture it is unbounded along
:math:`\operatorname{Ker} J^T`; it is empty when gravity alone needs more torque than the
joints have along a direction no end-effector force can help.

Its ellipsoids, from the SVD :math:`J L^{-1} = U_1 S V_1^T` (so :math:`A = V_1 S U_1^T`):

* ``"chiacchio"``, the static-consistent one with gravity, :math:`\{h : \|A h + c\| \le
  1\}`.  With :math:`h_0 = -A^+ c` and :math:`c_\perp = (I - A A^+) c` (the part of the
  gravity load no end-effector force can balance),
  :math:`\|A h + c\|^2 = \|A (h - h_0)\|^2 + \|c_\perp\|^2`, so it is the ellipsoid of
  centre :math:`h_0`, axes :math:`U_1` and semi-axes :math:`\rho / S` with
  :math:`\rho = \sqrt{1 - \|c_\perp\|^2}`.  It lies inside :math:`P_f` because
  :math:`\|\cdot\|_\infty \le \|\cdot\|_2`.
* ``"yoshikawa"``, the classic one: the unit ball of normalized torques through the
  unweighted pseudo-inverse, :math:`\{(J^T)^+ (\tau_c + L u - g) : \|u\| \le 1\}`, centred
  at :math:`-(J^T)^+ (g - \tau_c)`.
* ``"static"``, what capacity libraries compute today: :math:`\{h : \|L^{-1} J^T h\| \le
  1\}`, centred at 0, gravity ignored (axes :math:`U_1`, semi-axes :math:`1 / S`).

The torque a force needs is unique, so every ellipsoid has the same witness,
:math:`\tilde\tau = A h + c`: more than 1 in the infinity norm means the ellipsoid promises
a force the arm cannot exert.
"""

from __future__ import annotations

from functools import cached_property
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities.acceleration import check_dynamics
from polyell.capacities.base import Analysis, InverseSolution, centre_and_half_range
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL, rank_revealing_svd
from polyell.inverse import AffineMap
from polyell.models.dynamics import Dynamics
from polyell.models.kinematics import Kinematics
from polyell.validation import (
    check_fraction,
    check_magnitudes,
    check_torque_limits,
    magnitude_limit,
)

__all__ = ["ForceAnalysis", "force_terms"]


#: The smallest largest entry of a Jacobian the force set is computed from: below, its
#: pseudo-inverse (the classic force ellipsoid) overflows.  The set itself depends on J, g
#: and the limits together, so it is refused, not rescaled.
SMALLEST_JACOBIAN = 1e-290


def force_terms(
    J: NDArray[np.float64],
    g: NDArray[np.float64],
    tau_center: NDArray[np.float64],
    half_range: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``A^T = J L^-1`` (..., m, n) and ``c = L^-1 (g - tau_c)`` (..., n), checked.

    One configuration or a batch (the sweep's).  Raises :class:`InputError` where the
    forces or gravity's share of the limits are not representable.
    """
    size = np.max(np.abs(J), axis=(-2, -1)) if J.size else np.zeros(J.shape[:-2])
    if np.any((size > 0) & (size < SMALLEST_JACOBIAN)):  # its pseudo-inverse overflows
        raise InputError(
            "dyn.J",
            f"a Jacobian with entries of at least {SMALLEST_JACOBIAN:.0e} (or zero)",
            f"largest entries down to {np.min(np.where(size > 0, size, np.inf)):.3g}",
            "give J, g and the torque limits in units of moderate size (m, N m).",
        )
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        M = J / half_range  # J L^-1 = A^T
        c = (g - tau_center) / half_range
    # forces are about 1 / |J L^-1| and gravity's share c is a number: no relative test
    check_magnitudes(M, np.zeros(M.shape[:-1]), quantity=("forces", "J L^-1", "(none)"))
    if not np.all(np.isfinite(c)) or np.abs(c).max() > 10.0 ** magnitude_limit(1):
        raise InputError(
            "dyn.g",
            "gravity torques of the size of the torque limits (within 1e140 of them)",
            f"L^-1 (g - tau_c) up to {np.abs(c).max():.3g}",
            "give g and the torque limits in the same units (N m).",
        )
    return M, c


class ForceAnalysis(Analysis):
    """The end-effector forces a robot at rest can exert at one configuration.

    Build it with ``pe.analyze(dyn, tau_max, tau_min, capacity="force")``.

    Attributes
    ----------
    dynamics : Dynamics
        ``J`` (m, n) and the gravity torques ``g`` (n,) (``B`` is not used).
    tau_max, tau_min, tau_center, half_range : ndarray, shape (n,)
        Torque limits, their midpoint and ``diag(L)`` [N m].
    A : ndarray, shape (n, m)
        ``L^-1 J^T`` [per N]: normalized torque per unit force.
    c : ndarray, shape (n,)
        ``L^-1 (g - tau_c)``: the normalized torques gravity needs.
    center : ndarray, shape (m,)
        ``h0 = -A^+ c`` [N]: the force of least normalized torque residual, the centre of
        the ``"chiacchio"`` ellipsoid.
    """

    capacity = "force"
    ellipsoid_kinds = ("chiacchio", "yoshikawa", "static")
    kind_notes: ClassVar[dict[str, str]] = {
        "chiacchio": "the static-consistent one with gravity, |L^-1 (J^T h + g - tau_c)| <= 1",
        "yoshikawa": "the unit torque ball through the unweighted pseudo-inverse of J^T",
        "static": "|L^-1 J^T h| <= 1, centred at 0, gravity ignored",
    }
    quantity = "forces"
    inverse_names = ("tau", "tau_n")
    output_suffix = "_force"
    rank_matrix = "J"
    unique_inverse = True  # the torque a force needs is unique
    dynamics: Dynamics

    def __init__(
        self,
        dynamics: object,
        tau_max: ArrayLike,
        tau_min: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        if isinstance(dynamics, Kinematics):
            raise InputError(
                "dyn",
                "dynamics with gravity torques g for the force capacity",
                "a Kinematics (a Jacobian alone)",
                "pass pe.Dynamics(J, B, g) or arm.dynamics(q); use g = 0 to ignore gravity.",
            )
        dynamics = check_dynamics(dynamics, "force")
        self.dynamics = dynamics
        self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, dynamics.n)
        self.tau_center, self.half_range = centre_and_half_range(self.tau_max, self.tau_min)
        M, self.c = force_terms(dynamics.J, dynamics.g, self.tau_center, self.half_range)
        self.A: NDArray[np.float64] = M.T
        # The rank is J's: the set is unbounded only along Ker J^T.  M = J L^-1 is
        # ill-conditioned where the torque ranges differ by orders of magnitude, but that
        # makes the set thin across the narrow range's rows, not infinite along the others.
        kinematic = np.linalg.svd(dynamics.J, compute_uv=False)
        rank_rtol = check_fraction("rank_rtol", rank_rtol)
        rank = int(np.count_nonzero(kinematic > rank_rtol * kinematic[0])) if kinematic[0] else 0
        self.svd = rank_revealing_svd(M, rank_rtol, rank=rank)
        self.affine_rtol = check_fraction("affine_rtol", affine_rtol)
        svd = self.svd
        along = svd.V1.T @ self.c  # the part of c that forces can balance, in V_1
        self._center: NDArray[np.float64] = -svd.U1 @ (along / svd.sigma)
        self.c_perp: NDArray[np.float64] = self.c - svd.V1 @ along

    def __repr__(self) -> str:
        return (
            f"ForceAnalysis(m={self.m}, n={self.n}, rank={self.rank}, "
            f"center={np.round(self.center, 6).tolist()})"
        )

    @property
    def center(self) -> NDArray[np.float64]:
        """``h0 = -A^+ c`` [N]: the force of least normalized torque residual."""
        return self._center

    @property
    def rank(self) -> int:
        """Numerical rank of ``J`` (decided on ``J``, the rank of ``J L^-1`` as well)."""
        return self.svd.rank

    @cached_property
    def polytope(self) -> HPolytope:
        """The exact force polytope ``{h : |A h + c|_inf <= 1}`` (unbounded or empty, said)."""
        # In torques, tau_min <= J^T h + g <= tau_max: a row is negligible when its joint's
        # column of J is (no force loads it), not when its torque range is wide.
        J, g = self.dynamics.J, self.dynamics.g
        A = np.vstack([J.T, -J.T])
        b = np.concatenate([self.tau_max - g, g - self.tau_min])
        polytope = HPolytope(A, b, center=self.center, rank=self.rank)  # lines: Ker J^T
        polytope.affine_rtol = self.affine_rtol
        return polytope

    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """``A = L^-1 J^T``, ``c = L^-1 (g - tau_c)``, the centre ``h0`` and ``c_perp``."""
        return {"A": self.A, "c": self.c, "center": self.center, "c_perp": self.c_perp}

    def joint_limits(self) -> dict[str, NDArray[np.float64]]:
        """``tau_max`` and ``tau_min`` [N m]."""
        return {"tau_max": self.tau_max, "tau_min": self.tau_min}

    def _require_bounded(self, kind: str) -> None:
        if self.is_singular:
            raise UndefinedEllipsoidError(
                f"The force ellipsoid {kind!r} is undefined at this singular posture: rank J "
                f"= {self.rank} < m = {self.m}, so forces along Ker(J^T) need no torque and "
                "the force polytope is unbounded along them (see polytope.rays); there the "
                "gravity-consistent and static ellipsoids would be infinite cylinders and "
                "the classic one flat."
            )
        if self.polytope.is_empty:
            raise UndefinedEllipsoidError(
                f"The force ellipsoid {kind!r} is undefined here: the force set is empty (the "
                "arm cannot hold itself against gravity within its torque limits), so no "
                "ellipsoid describes it."
            )

    def _build_ellipsoid(self, kind: str) -> Ellipsoid:
        self._require_bounded(kind)
        svd = self.svd
        if kind == "static":
            return Ellipsoid(np.zeros(self.m), svd.U1, 1.0 / svd.sigma, kind=kind)
        if kind == "chiacchio":
            margin = 1.0 - float(self.c_perp @ self.c_perp)
            if not margin > 0.0:
                raise UndefinedEllipsoidError(
                    "The force ellipsoid 'chiacchio' is empty at this posture: the part of "
                    "the gravity torques that no end-effector force can balance has "
                    f"normalized norm |c_perp| = {np.sqrt(1.0 - margin):.4g} >= 1, so no "
                    "ball of normalized torques about it fits the limits."
                )
            return Ellipsoid(self.center, svd.U1, np.sqrt(margin) / svd.sigma, kind=kind)
        # yoshikawa: h = (J^T)^+ (tau_c + L u - g), |u| <= 1.
        pseudo_inverse = np.linalg.pinv(self.dynamics.J.T)
        center = -pseudo_inverse @ (self.dynamics.g - self.tau_center)
        U, s, _ = np.linalg.svd(pseudo_inverse * self.half_range, full_matrices=False)
        return Ellipsoid(center, U, s, kind=kind)

    def witness_map(self, kind: str) -> AffineMap:
        """``h -> tau_n = A h + c`` (the torque a force needs is unique), about ``h0``."""
        return AffineMap(self.A, self.center, self.c_perp)

    def inverse(self, x: ArrayLike, kind: str | None = None) -> InverseSolution:
        """The joint torques that exert end-effector forces at rest.

        Parameters
        ----------
        x : array-like, shape (m,) or (k, m)
            End-effector forces [N] (moments [N m] for an angular task).
        kind : str, optional
            Any of :attr:`ellipsoid_kinds`: the torque ``J^T h + g`` is unique, so every
            definition has the same inverse.

        Returns
        -------
        InverseSolution
            ``(tau, tau_n)``: ``tau = J^T h + g`` [N m] and ``tau_n = L^-1 (tau - tau_c)``.
        """
        if kind is not None:
            self.check_kind(kind)
        h = self._points(x, "h")
        tau_n = self.witness_map("chiacchio")(h)
        return InverseSolution(self.tau_center + tau_n * self.half_range, tau_n)
