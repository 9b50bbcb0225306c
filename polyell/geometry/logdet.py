r"""The centred minimum-volume enclosing ellipsoid: the log-det program behind the MVIE.

For points :math:`c_1, \dots, c_N` spanning :math:`\mathbb{R}^r`, the smallest ellipsoid
:math:`\{y : y^T X y \le 1\}` centred at the origin that contains every :math:`\pm c_i`
solves

.. math::

    \max_{X \succ 0} \ \log\det X \quad \text{s.t.} \quad c_i^T X c_i \le 1 ,

the D-optimal design problem.  Read with :math:`c_i = a_i / h_i` for the facet pairs
:math:`\pm a_i^T y \le h_i` of a centrally symmetric polytope, the same X is the shape of
its maximum-volume inscribed ellipsoid :math:`\{X^{1/2} u : \|u\| \le 1\}` (polarity).

The constraints are linear in X, so a log-barrier Newton method in the
:math:`r (r + 1) / 2` entries of X converges in a few dozen small steps, and its dual
certificate bounds the distance to the optimum.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.errors import SolverError

__all__ = ["CentredEllipsoid", "centred_mvee"]


class CentredEllipsoid(NamedTuple):
    """The solution of :func:`centred_mvee`.

    Attributes
    ----------
    shape : ndarray, shape (r, r)
        Symmetric positive-definite ``X``: the ellipsoid is ``{y : y^T X y <= 1}``.
    gap : float
        Certified bound on ``log det X* - log det X`` (X* the exact optimum): the
        volume of ``{y : y^T X y <= 1}`` is within a factor ``exp(gap / 2)`` of the least.
    iterations : int
        Newton steps taken.
    """

    shape: NDArray[np.float64]
    gap: float
    iterations: int


@lru_cache(maxsize=8)
def _symmetric_basis(r: int) -> NDArray[np.float64]:
    """Basis ``E_k`` (d, r, r) of the symmetric matrices, d = r (r + 1) / 2."""
    rows, cols = np.triu_indices(r)
    basis = np.zeros((rows.size, r, r))
    basis[np.arange(rows.size), rows, cols] = 1.0
    basis[np.arange(rows.size), cols, rows] = 1.0
    basis.flags.writeable = False
    return basis


def centred_mvee(
    points: NDArray[np.float64], *, gap: float = 1e-8, max_iterations: int = 500
) -> CentredEllipsoid:
    r"""The minimum-volume ellipsoid centred at 0 that contains the points and their negatives.

    Parameters
    ----------
    points : ndarray, shape (N, r)
        Points spanning R^r (each with its negative).  Best scaled so that the answer is
        of order 1 (the MVIE whitens first, see :mod:`polyell.geometry.mvie`).
    gap : float, optional
        Target bound on the optimality gap in ``log det X``.
    max_iterations : int, optional
        Newton steps allowed in all.

    Returns
    -------
    CentredEllipsoid
        ``X`` scaled so that ``max_i c_i^T X c_i = 1`` exactly (it touches the points),
        with its certified gap.

    Raises
    ------
    SolverError
        If the points do not span R^r or the method does not reach ``gap``.

    Notes
    -----
    Path following on :math:`-t \log\det X - \sum_i \log(1 - c_i^T X c_i)` by damped
    Newton steps, t growing by a factor 16 per stage from a feasible multiple of the
    identity.  After each stage the central path's duals :math:`\lambda_i = 1 / (t s_i)`
    (slacks :math:`s_i`) give an upper bound on the optimum by Lagrangian duality; the
    returned gap is that bound minus ``log det X``, not an estimate.  The method stops at
    ``gap``, or where rounding (slacks of order 1 / t) stops the certificate improving.
    """
    count, r = points.shape
    basis = _symmetric_basis(r)
    # Phi[i, k] = c_i^T E_k c_i: the constraints read Phi x <= 1 in the coordinates x of X.
    Phi = np.einsum("ia,kab,ib->ik", points, basis, points)
    # X = alpha I (x = alpha trace(E_k)), strictly feasible.
    x = (0.5 / np.max(np.einsum("ia,ia->i", points, points))) * np.einsum("kaa->k", basis)
    t = float(count)
    best = CentredEllipsoid(np.eye(r), np.inf, 0)
    iterations = 0
    for iterations in range(1, max_iterations + 1):
        X = np.einsum("k,kab->ab", x, basis)
        slack = 1.0 - Phi @ x
        X_inv_E = np.linalg.inv(X) @ basis  # (d, r, r)
        gradient = -t * np.einsum("kaa->k", X_inv_E) + Phi.T @ (1.0 / slack)
        hessian = t * np.einsum("kab,lba->kl", X_inv_E, X_inv_E) + (Phi.T / slack**2) @ Phi
        try:
            step = -np.linalg.solve(hessian, gradient)
        except np.linalg.LinAlgError as exn:
            raise SolverError(
                f"centred_mvee: singular Newton system; the points do not span R^{r}."
            ) from exn
        decrement = float(-gradient @ step)
        if decrement <= 1e-6:  # centred for this t: certify, then move along the path
            shape, certified = _certify(x, basis, Phi, points, slack, t)
            if certified < best.gap:
                best = CentredEllipsoid(shape, certified, iterations)
            # Done at the target, or when rounding (slacks of order 1 / t) starts to spoil
            # the dual estimate: the certificate no longer improves.
            if certified <= gap or certified > best.gap:
                break
            t *= 16.0
            continue
        # Damped Newton (the barrier is self-concordant): no function values, which lose
        # their last digits to the factor t; halve only to stay strictly feasible.
        alpha = 1.0 if decrement <= 0.0625 else 1.0 / (1.0 + np.sqrt(decrement))
        while True:
            trial = x + alpha * step
            if np.min(1.0 - Phi @ trial) > 0 and _is_positive_definite(
                np.einsum("k,kab->ab", trial, basis)
            ):
                break
            alpha *= 0.5
            if alpha < 1e-12:
                raise SolverError("centred_mvee: the Newton step cannot stay feasible.")
        x = trial
    if best.gap <= gap:
        return best
    raise SolverError(
        f"centred_mvee: certified optimality gap {best.gap:.3g} after {iterations} Newton "
        f"steps (target {gap:.3g}) on {count} points in R^{r}."
    )


def _is_positive_definite(X: NDArray[np.float64]) -> bool:
    try:
        np.linalg.cholesky(X)
    except np.linalg.LinAlgError:
        return False
    return True


def _certify(
    x: NDArray[np.float64],
    basis: NDArray[np.float64],
    Phi: NDArray[np.float64],
    points: NDArray[np.float64],
    slack: NDArray[np.float64],
    t: float,
) -> tuple[NDArray[np.float64], float]:
    r"""The best feasible X at hand, scaled to touch the points, and its certified gap.

    Any :math:`\lambda \ge 0` bounds the optimum: :math:`\log\det X^* \le -\log\det W
    - r \log(r / \sum_i \lambda_i)` with :math:`W = \sum_i \lambda_i c_i c_i^T`
    (Lagrangian duality, with the best scaling of :math:`\lambda`).  The duals are the
    central path's :math:`1 / (t s_i)`, also with those of clearly inactive constraints
    set to zero (they only add N / t to the gap); each gives a candidate ``X = W^-1`` (the
    optimality condition) beside the primal iterate.
    """
    r = points.shape[1]
    duals = 1.0 / (t * slack)
    candidates = [np.einsum("k,kab->ab", x, basis)]
    upper = np.inf
    for threshold in (np.inf, 1e-2, 1e-4, 1e-6):
        kept = np.where(slack <= threshold, duals, 0.0)
        W = (points.T * kept) @ points
        sign, logdet_W = np.linalg.slogdet(W)
        if sign <= 0:
            continue
        upper = min(upper, -logdet_W - r * np.log(r / kept.sum()))
        candidates.append(np.linalg.inv(W))
    best, best_logdet = candidates[0], -np.inf
    for X in candidates:
        X = 0.5 * (X + X.T)
        if not _is_positive_definite(X):
            continue
        X /= np.max(np.einsum("ia,ab,ib->i", points, X, points))
        logdet = np.linalg.slogdet(X)[1]
        if logdet > best_logdet:
            best, best_logdet = X, logdet
    return best, float(upper - best_logdet)
