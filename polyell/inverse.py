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
    "InverseMaps",
    "chiacchio_maps",
    "classic_maps",
    "classic_terms",
    "jacobian_pseudoinverse",
    "weighted_generalized_inverse",
]


class AffineMap(NamedTuple):
    """The map ``x -> matrix @ (x - base) + value``, applied to points of shape (..., m).

    Written about a base point (the centre ``xg`` of the sets) with its value there
    computed directly, not as ``matrix @ x + offset``: when the sets are small against
    their distance from the origin (weak torques against gravity), ``matrix @ x`` and the
    offset nearly cancel and their difference would keep none of its digits.
    """

    matrix: NDArray[np.float64]
    base: NDArray[np.float64]
    value: NDArray[np.float64]

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Apply the map to points ``x`` of shape (..., m)."""
        return (x - self.base) @ self.matrix.T + self.value


class InverseMaps(NamedTuple):
    """A definition's inverse: ``xdd -> qdd`` and ``xdd -> tau_n`` (eq. 10), both affine."""

    joint: AffineMap
    torque: AffineMap


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


def classic_maps(
    J: NDArray[np.float64],
    B: NDArray[np.float64],
    half_range: NDArray[np.float64],
    gravity_bias: NDArray[np.float64],
    xg: NDArray[np.float64],
) -> InverseMaps:
    """Eq. (26), ``qdd = J^+ (xdd - Jdot qdot)``, and its torques; J of full row rank.

    About the centre ``xg = Jdot qdot - J f`` (``f = B^-1 (g - tau_c)``, the free fall):
    ``qdd = J^+ (xdd - xg) - J^+ J f`` and ``tau_n = L^-1 B J^+ (xdd - xg) + L^-1 B V_2
    V_2^T f``, with ``V_2`` an orthonormal basis of ``Ker J``: the torque at the centre is
    that of the null-space part of the free fall, which eq. (26) leaves out (exactly 0 for
    a non-redundant arm, where ``Ker J = {0}``).

    Parameters
    ----------
    J, B : ndarray
        Jacobian (m, n), inertia (n, n).
    half_range : ndarray, shape (n,)
        Diagonal of L.
    gravity_bias : ndarray, shape (n,)
        ``g - tau_c`` [N m].
    xg : ndarray, shape (m,)
        Centre of the sets (eq. 8 with ``Jdot qdot``).
    """
    pinv, free_fall, at_center = classic_terms(J, B, half_range, gravity_bias)
    joint = AffineMap(pinv, xg, -(pinv @ (J @ free_fall)))
    torque = AffineMap((B @ pinv) / half_range[:, None], xg, at_center)
    return InverseMaps(joint, torque)


def classic_terms(
    J: NDArray[np.float64],
    B: NDArray[np.float64],
    half_range: NDArray[np.float64],
    gravity_bias: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``J^+``, the free fall ``f = B^-1 (g - tau_c)`` and eq. (26)'s torque at the centre.

    The torque at the centre, ``L^-1 B V_2 V_2^T f``, is computed from the null-space basis
    ``V_2`` of the SVD of J, never as a difference of large terms (see :func:`classic_maps`).
    Leading axes are a batch (the sweep's path).

    Parameters
    ----------
    J : ndarray, shape (..., m, n)
    B : ndarray, shape (..., n, n)
    half_range, gravity_bias : ndarray, shape (..., n)

    Returns
    -------
    pinv : ndarray, shape (..., n, m)
    free_fall, at_center : ndarray, shape (..., n)
    """
    m = J.shape[-2]
    U, s, Vt = np.linalg.svd(J, full_matrices=True)
    pinv = (np.swapaxes(Vt[..., :m, :], -1, -2) / s[..., None, :]) @ np.swapaxes(U, -1, -2)
    free_fall = np.asarray(np.linalg.solve(B, gravity_bias[..., None])[..., 0], dtype=float)
    null = Vt[..., m:, :]  # V_2^T
    null_part = np.einsum("...jn,...j->...n", null, np.einsum("...jn,...n->...j", null, free_fall))
    at_center = np.einsum("...ij,...j->...i", B, null_part) / half_range
    return pinv, free_fall, at_center


def chiacchio_maps(
    B: NDArray[np.float64],
    half_range: NDArray[np.float64],
    gravity_bias: NDArray[np.float64],
    xg: NDArray[np.float64],
    M_pinv: NDArray[np.float64],
) -> InverseMaps:
    """Eq. (33)/(40): ``qdd = J_Q^# xdd - (I - J_Q^# J) B^-1 (g - tau_c)``, and its torques.

    Evaluated as eq. (39) with ``J_Q^# = B^-1 L M^#`` (eq. 36 and 12: with
    ``Q = (L^-1 B)^T (L^-1 B)`` the Q-weighted minimum-norm solution of ``J qdd = y`` is
    ``B^-1 L M^# y``).  This uses the SVD of M (condition number that of M) instead of
    ``Q^-1/2`` (that of M squared), so it stays accurate for ill-conditioned inertias; it
    equals :func:`weighted_generalized_inverse` (eq. 41) where both are accurate.  About
    the centre ``xg`` it reads ``qdd = J_Q^# (xdd - xg) - B^-1 (g - tau_c)`` and
    ``tau_n = M^# (xdd - xg)``: the minimum-norm normalized torque, exactly 0 at the centre.

    Parameters
    ----------
    B : ndarray, shape (n, n)
        Inertia.
    half_range : ndarray, shape (n,)
        Diagonal of L.
    gravity_bias : ndarray, shape (n,)
        ``g - tau_c`` [N m].
    xg : ndarray, shape (m,)
        Centre of the sets (eq. 8 with ``Jdot qdot``).
    M_pinv : ndarray, shape (n, m)
        The generalized inverse of M at the analysis' rank (eq. 37).
    """
    JQ = np.asarray(np.linalg.solve(B, half_range[:, None] * M_pinv), dtype=np.float64)
    free_fall = np.asarray(np.linalg.solve(B, gravity_bias), dtype=np.float64)
    joint = AffineMap(JQ, xg, -free_fall)
    torque = AffineMap(M_pinv, xg, np.zeros(B.shape[0]))
    return InverseMaps(joint, torque)
