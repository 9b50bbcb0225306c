r"""Many small linear programs with two-sided rows at once: a batched dual simplex.

Each of K problems is

.. math::

    \max_u \; d \cdot u \quad \text{subject to} \quad l \le G u \le h,

with ``n`` unknowns and ``R >= n`` rows, some of them equalities (``l = h``).  A *basis* is
``n`` rows held at one of their bounds, ``G_S u = b_S``; it is dual feasible when
``d = G_S^T y`` with ``y_i >= 0`` for a row at its upper bound and ``y_i <= 0`` at its lower
one (an equality's multiplier is free).  From a dual feasible basis the dual simplex brings
in the most violated row and drops the basis row that keeps the multipliers' signs (the
ratio test), until every row holds (optimal) or no basis row can leave (the rows admit no
``u``: the problem is infeasible).  Every iteration is a handful of array operations over the
problems still running, never a loop over them.

The caller supplies the first basis.  For the acceleration sets of
:mod:`polyell.capacities.horizon` the unit cube's rows give it for free: ``u = sign(d)``,
multipliers ``|d|``, the zonotope's support point.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = ["INFEASIBLE", "OPTIMAL", "UNRESOLVED", "BoundedLP", "dual_simplex"]

#: Status of a problem: solved, proven infeasible, or left (iteration cap, tiny pivots).
OPTIMAL, INFEASIBLE, UNRESOLVED = 0, 1, 2
#: A row holds when it is within this of its bound (rows of unit norm, relative to
#: ``1 + |bound|``), and a pivot counts when it is at least this share of the largest.
FEASIBILITY_RTOL = 1e-11
PIVOT_RTOL = 1e-9


class BoundedLP(NamedTuple):
    """The answers of :func:`dual_simplex`.

    Attributes
    ----------
    u : ndarray, shape (K, n)
        The maximisers (NaN where the status is not :data:`OPTIMAL`).
    status : ndarray of int, shape (K,)
        :data:`OPTIMAL`, :data:`INFEASIBLE` or :data:`UNRESOLVED`.
    iterations : int
        Iterations of the longest-running problem.
    """

    u: NDArray[np.float64]
    status: NDArray[np.int_]
    iterations: int


@np.errstate(all="ignore")  # finished and singular rows may divide by zero
def dual_simplex(
    d: NDArray[np.float64],
    G: NDArray[np.float64],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
    basis: NDArray[np.int_],
    side: NDArray[np.float64],
    *,
    max_iterations: int | None = None,
) -> BoundedLP:
    """Maximise ``d . u`` subject to ``lower <= G u <= upper``, K problems at once.

    Parameters
    ----------
    d : ndarray, shape (K, n)
        Objectives.
    G : ndarray, shape (K, R, n)
        Constraint rows, best of unit norm (the tolerances are absolute in their units).
    lower, upper : ndarray, shape (K, R)
        Finite bounds, ``lower <= upper``; equal for an equality row.
    basis : ndarray of int, shape (K, n)
        Indices of n rows with ``G_S`` invertible whose multipliers ``G_S^-T d`` have the
        signs of ``side``: a dual feasible start.
    side : ndarray, shape (K, n)
        +1 where a basis row is at its upper bound, -1 at its lower bound.
    max_iterations : int, optional
        Default ``4 R``; a problem still running then is :data:`UNRESOLVED` (degenerate
        cycling), for the caller to solve another way.

    Returns
    -------
    BoundedLP
    """
    K, R, n = G.shape
    cap = 4 * R if max_iterations is None else max_iterations
    u = np.full((K, n), np.nan)
    status = np.full(K, UNRESOLVED)
    # The problems still running, compacted as they finish (kept while most still run).
    index = np.arange(K)
    G, d, lower, upper = G[index], d[index], lower[index], upper[index]
    basis, side = basis[index], side[index].astype(float)
    fixed = lower == upper
    tolerance = FEASIBILITY_RTOL * (1.0 + np.maximum(np.abs(lower), np.abs(upper)))
    inverse = np.linalg.inv(np.take_along_axis(G, basis[:, :, None], axis=1))
    live = np.ones(K, dtype=bool)  # not yet finished (finished ones are dropped in bulk)
    iterations = 0
    while live.any() and iterations < cap:  # finished rows ride along until dropped
        iterations += 1
        k = np.arange(len(index))
        bounds = np.where(
            side > 0, np.take_along_axis(upper, basis, 1), np.take_along_axis(lower, basis, 1)
        )
        x = np.einsum("kij,kj->ki", inverse, bounds)
        rows = np.einsum("krn,kn->kr", G, x)
        above, below = rows - upper, lower - rows
        violation = np.maximum(above, below) - tolerance
        violation[k[:, None], basis] = -np.inf  # the basis rows hold by construction
        entering = np.argmax(violation, axis=1)
        worst = violation[k, entering]
        done = live & (worst <= 0) & np.isfinite(x).all(axis=1)  # NaN: a singular basis
        u[index[done]], status[index[done]] = x[done], OPTIMAL
        sigma = np.where(above[k, entering] > below[k, entering], 1.0, -1.0)
        alpha = np.einsum("kji,kj->ki", inverse, G[k, entering])  # G_j = alpha^T G_S
        y = np.einsum("kji,kj->ki", inverse, d)  # the multipliers, G_S^T y = d
        pull = sigma[:, None] * side * alpha
        eligible = ~fixed[k[:, None], basis]
        eligible &= pull > PIVOT_RTOL * np.abs(alpha).max(axis=1, keepdims=True)
        ratio = np.where(eligible, np.maximum(side * y, 0.0) / pull, np.inf)
        leaving = np.argmin(ratio, axis=1)
        stuck = live & ~eligible.any(axis=1) & ~done & np.isfinite(worst)
        status[index[stuck]] = INFEASIBLE
        # Row `entering` replaces row `leaving`: the inverse by a rank-one update,
        # G_S'^-1 = G_S^-1 - G_S^-1 e_p (alpha - e_p)^T / alpha_p.
        pivot = alpha[k, leaving]
        column = inverse[k, :, leaving]
        step = alpha / pivot[:, None]
        step[k, leaving] -= 1.0 / pivot
        inverse -= column[:, :, None] * step[:, None, :]
        basis[k, leaving] = entering
        side[k, leaving] = sigma
        live &= ~(done | stuck | ~np.isfinite(worst))
        if live.sum() < 0.75 * len(live):
            keep = live
            live = live[keep]
            index, G, d, lower, upper = index[keep], G[keep], d[keep], lower[keep], upper[keep]
            basis, side, fixed, tolerance = basis[keep], side[keep], fixed[keep], tolerance[keep]
            inverse = inverse[keep]
    return BoundedLP(u, status, iterations)
