r"""Inverse maps: the joint accelerations and torques behind a task-space acceleration.

Each ellipsoid definition comes with its own solution of :math:`J \ddot q = \ddot x`:

* classic (Yoshikawa), eq. (26): :math:`\ddot q = J^\dagger \ddot x`, the minimum-norm
  joint acceleration, :math:`J^\dagger = J^T (J J^T)^{-1}`;
* new (Chiacchio), eq. (33) and, at singular configurations, eq. (40):
  :math:`\ddot q = J_Q^\# \ddot x - (I - J_Q^\# J) B^{-1} (g - \tau_c)` with the
  weighted generalized inverse :math:`J_Q^\# = Q^{-1/2} (J Q^{-1/2})^\#` of eq. (41),
  equal to :math:`J_Q^\dagger = Q^{-1} J^T (J Q^{-1} J^T)^{-1}` (eq. 31) when J has
  full rank.  It solves eq. (34): the minimum normalized-torque norm.  It is evaluated as
  :math:`J_Q^\# = B^{-1} L M^\#` (eq. 39), from the SVD of M, which keeps its digits for
  ill-conditioned inertias; :func:`weighted_generalized_inverse` is eq. (41) literally.

The normalized torque is :math:`\tilde\tau = L^{-1} (B \ddot q + g - \tau_c)` (eq. 10,
12 with the shift for asymmetric limits).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "AffineMap",
    "chiacchio_joint_map",
    "classic_joint_map",
    "jacobian_pseudoinverse",
    "torque_map",
    "weighted_generalized_inverse",
]


class AffineMap(NamedTuple):
    """The map ``x -> matrix @ x + offset``, applied to points of shape (..., m)."""

    matrix: NDArray[np.float64]
    offset: NDArray[np.float64]

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Apply the map to points ``x`` of shape (..., m)."""
        return x @ self.matrix.T + self.offset

    def after_shift(self, shift: NDArray[np.float64]) -> AffineMap:
        """The map ``x -> self(x - shift)``."""
        return AffineMap(self.matrix, self.offset - self.matrix @ shift)


def jacobian_pseudoinverse(J: NDArray[np.float64]) -> NDArray[np.float64]:
    """``J^+ = J^T (J J^T)^-1`` (eq. 26), shape (n, m); J must have full row rank.

    Computed from the SVD of J (``V S^-1 U^T``), not from ``J J^T``, whose condition number
    is the square of J's: near a singularity that would cost half the digits.
    """
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    pinv: NDArray[np.float64] = (Vt.T / s) @ U.T
    return pinv


def _symmetric_power(Q: NDArray[np.float64], power: float) -> NDArray[np.float64]:
    eigenvalues, eigenvectors = np.linalg.eigh(Q)
    return (eigenvectors * eigenvalues**power) @ eigenvectors.T


def weighted_generalized_inverse(
    J: NDArray[np.float64], Q: NDArray[np.float64], rank: int
) -> NDArray[np.float64]:
    """``J_Q^# = Q^-1/2 (J Q^-1/2)^#`` (eq. 41), shape (n, m).

    Parameters
    ----------
    J : ndarray, shape (m, n)
        Jacobian.
    Q : ndarray, shape (n, n)
        Weight ``B L^-2 B`` (eq. 20), symmetric positive definite.
    rank : int
        Rank of J, decided once for the analysis; the generalized inverse keeps that many
        singular values (eq. 37).
    """
    Q_inv_sqrt = _symmetric_power(Q, -0.5)
    U, s, Vt = np.linalg.svd(J @ Q_inv_sqrt, full_matrices=False)
    return Q_inv_sqrt @ ((Vt[:rank].T / s[:rank]) @ U[:, :rank].T)


def classic_joint_map(J: NDArray[np.float64]) -> AffineMap:
    """Eq. (26): ``qdd = J^+ xdd``; J must have full row rank."""
    return AffineMap(jacobian_pseudoinverse(J), np.zeros(J.shape[1]))


def chiacchio_joint_map(
    J: NDArray[np.float64],
    B: NDArray[np.float64],
    half_range: NDArray[np.float64],
    gravity_bias: NDArray[np.float64],
    M_pinv: NDArray[np.float64],
) -> AffineMap:
    """Eq. (33)/(40): ``qdd = J_Q^# xdd - (I - J_Q^# J) B^-1 (g - tau_c)``.

    Evaluated as eq. (39) with ``J_Q^# = B^-1 L M^#`` (eq. 36 and 12: with
    ``Q = (L^-1 B)^T (L^-1 B)`` the Q-weighted minimum-norm solution of ``J qdd = y`` is
    ``B^-1 L M^# y``).  This uses the SVD of M (condition number that of M) instead of
    ``Q^-1/2`` (that of M squared), so it stays accurate for ill-conditioned inertias; it
    equals :func:`weighted_generalized_inverse` (eq. 41) where both are accurate.

    Parameters
    ----------
    J, B : ndarray
        Jacobian (m, n), inertia (n, n).
    half_range : ndarray, shape (n,)
        Diagonal of L.
    gravity_bias : ndarray, shape (n,)
        ``g - tau_c`` [N m].
    M_pinv : ndarray, shape (n, m)
        The generalized inverse of M at the analysis' rank (eq. 37).
    """
    JQ = np.asarray(np.linalg.solve(B, half_range[:, None] * M_pinv), dtype=np.float64)
    free_fall = np.linalg.solve(B, gravity_bias)
    return AffineMap(JQ, JQ @ (J @ free_fall) - free_fall)


def torque_map(
    joint_map: AffineMap,
    B: NDArray[np.float64],
    gravity_bias: NDArray[np.float64],
    half_range: NDArray[np.float64],
) -> AffineMap:
    """Compose a joint map with ``tau_n = L^-1 (B qdd + g - tau_c)`` (eq. 10, 12).

    The torque limits hold iff ``|tau_n|_inf <= 1``.
    """
    return AffineMap(
        (B @ joint_map.matrix) / half_range[:, None],
        (B @ joint_map.offset + gravity_bias) / half_range,
    )
