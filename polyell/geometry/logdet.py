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

__all__ = ["CentredEllipsoid", "centred_mvee", "centred_mvee_batch"]


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
    :func:`centred_mvee_batch` for one problem (the same arithmetic as in a sweep).
    """
    shapes, gaps, iterations = centred_mvee_batch(
        points[None], gap=gap, max_iterations=max_iterations
    )
    if not gaps[0] <= gap:
        count, r = points.shape
        raise SolverError(
            f"centred_mvee: certified optimality gap {gaps[0]:.3g} after {iterations[0]} "
            f"Newton steps (target {gap:.3g}) on {count} points in R^{r}."
        )
    return CentredEllipsoid(shapes[0], float(gaps[0]), int(iterations[0]))


#: Growth of the barrier parameter t per stage of the path following.
T_GROWTH = 200.0
#: Newton decrement below which a point counts as centred for its t.
CENTRED = 1e-6


def centred_mvee_batch(
    points: NDArray[np.float64], *, gap: float = 1e-8, max_iterations: int = 500
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int_]]:
    r""":func:`centred_mvee` for K problems at once, vectorised over the batch.

    Parameters
    ----------
    points : ndarray, shape (K, N, r)
        K point sets (zero rows are allowed: no constraint).
    gap : float, optional
        Target bound on each optimality gap in ``log det X``.
    max_iterations : int, optional
        Newton steps allowed in all.

    Returns
    -------
    shapes : ndarray, shape (K, r, r)
        Each ``X`` scaled to touch its points (NaN where no feasible X was found).
    gaps : ndarray, shape (K,)
        Certified gaps; above ``gap`` (or NaN) where the method did not converge: the
        caller decides (a sweep reports such rows as undefined).
    iterations : ndarray of int, shape (K,)
        Newton steps taken by each problem.

    Notes
    -----
    Path following on :math:`-t \log\det X - \sum_i \log(1 - c_i^T X c_i)` in the
    :math:`r (r + 1) / 2` entries of X, from a feasible multiple of the identity, with t
    growing by :data:`T_GROWTH` per stage; Newton steps with a backtracking line search,
    never shorter than the damped step :math:`1 / (1 + \lambda)` that self-concordance
    guarantees (function values lose digits to the factor t).  At the end of each stage
    the central path's duals bound the optimum (Lagrangian duality, see
    :func:`_certify`); a problem stops at ``gap``, or when its certificate stops
    improving (rounding).
    """
    K, count, r = points.shape
    basis = _symmetric_basis(r)
    flat = basis.reshape(-1, r * r)  # (d, r^2): X = (x @ flat).reshape(r, r)
    trace = np.einsum("kaa->k", basis)
    Phi = np.einsum("Kia,kab,Kib->Kik", points, basis, points)  # constraints: Phi x <= 1
    norms = np.einsum("Kia,Kia->Ki", points, points).max(axis=1)
    x = (0.5 / np.where(norms > 0, norms, 1.0))[:, None] * trace  # X = alpha I, feasible
    t = np.full(K, 10.0 * count)
    shapes, gaps = np.full((K, r, r), np.nan), np.full(K, np.inf)
    iterations = np.zeros(K, dtype=int)
    active = np.arange(K)
    for _ in range(max_iterations):
        if active.size == 0:
            break
        iterations[active] += 1
        xa, Pa, ta = x[active], Phi[active], t[active]
        slack = 1.0 - (Pa @ xa[..., None])[..., 0]
        X_inv = np.linalg.inv((xa @ flat).reshape(-1, r, r))
        # tr(X^-1 E_k) and tr(X^-1 E_k X^-1 E_l) = vec(E_k) . (X^-1 kron X^-1) vec(E_l)
        kron = (X_inv[:, :, None, :, None] * X_inv[:, None, :, None, :]).reshape(-1, r * r, r * r)
        PaT = np.swapaxes(Pa, 1, 2)
        gradient = -ta[:, None] * (X_inv.reshape(-1, r * r) @ flat.T)
        gradient += (PaT @ (1.0 / slack)[..., None])[..., 0]
        hessian = ta[:, None, None] * (flat @ kron @ flat.T)
        hessian += PaT @ (Pa * slack[..., None] ** -2)
        try:
            step = -np.linalg.solve(hessian, gradient[..., None])[..., 0]
        except np.linalg.LinAlgError as exn:
            raise SolverError(
                f"centred_mvee: singular Newton system; the points do not span R^{r}."
            ) from exn
        decrement = -np.einsum("Kk,Kk->K", gradient, step)
        centred = decrement <= CENTRED
        done = np.zeros(active.size, dtype=bool)
        if centred.any():
            c = np.flatnonzero(centred)
            shape, certified = _certify(xa[c], basis, points[active[c]], slack[c], ta[c])
            better = certified < gaps[active[c]]
            shapes[active[c[better]]] = shape[better]
            gaps[active[c[better]]] = certified[better]
            done[c] = (certified <= gap) | ~better  # at the target, or rounding stalls it
            t[active[c]] *= T_GROWTH
        move = np.flatnonzero(~centred)
        if move.size:
            x[active[move]] = _line_search(
                xa[move], step[move], decrement[move], Pa[move], ta[move], basis, slack[move]
            )
        active = active[~done]
    return shapes, gaps, iterations


#: Step lengths tried by the line search, longest first (then the damped length).
_STEPS = 0.5 ** np.arange(12)


def _line_search(
    x: NDArray[np.float64],
    step: NDArray[np.float64],
    decrement: NDArray[np.float64],
    Phi: NDArray[np.float64],
    t: NDArray[np.float64],
    basis: NDArray[np.float64],
    slack: NDArray[np.float64],
) -> NDArray[np.float64]:
    r"""Backtracking (Armijo) along Newton steps, accepting the damped step when reached.

    The barrier is analytic along a step: with :math:`\mu_j` the eigenvalues of
    :math:`L^{-1} \Delta X L^{-T}` (:math:`X = L L^T`) and :math:`a = \Phi \, \Delta x`,
    :math:`f(\alpha) - f(0) = -t \sum_j \log(1 + \alpha \mu_j) - \sum_i \log(1 - \alpha
    a_i / s_i)`, finite exactly where the step stays feasible; so every trial length is
    evaluated at once, without factorising a trial X.
    """
    r = basis.shape[1]
    X = (x @ basis.reshape(-1, r * r)).reshape(-1, r, r)
    dX = (step @ basis.reshape(-1, r * r)).reshape(-1, r, r)
    L_inv = np.linalg.inv(np.linalg.cholesky(X))
    mu = np.linalg.eigvalsh(L_inv @ dX @ np.swapaxes(L_inv, 1, 2))  # (K, r)
    ratio = (Phi @ step[..., None])[..., 0] / slack  # (K, N)
    damped = 1.0 / (1.0 + np.sqrt(decrement))

    def accepted(steps: NDArray[np.float64], rows: NDArray[np.int_]) -> NDArray[np.bool_]:
        """Which lengths ``steps`` (k, S) of the problems ``rows`` pass (k, S)."""
        alpha = steps[:, :, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            det_term = np.log1p(alpha * mu[rows, None, :]).sum(axis=-1)
            barrier = np.log1p(-alpha * ratio[rows, None, :]).sum(axis=-1)
        change = -t[rows, None] * det_term - barrier  # NaN or inf where infeasible
        feasible = np.isfinite(change) & (np.min(mu[rows], axis=1)[:, None] * steps > -1)
        enough = change <= -0.01 * steps * decrement[rows, None]
        return feasible & (enough | (steps <= damped[rows, None]))

    everyone = np.arange(len(x))
    length = np.where(accepted(np.ones((len(x), 1)), everyone)[:, 0], 1.0, np.nan)
    rest = np.flatnonzero(np.isnan(length))  # the full step failed: the whole ladder
    if rest.size:
        steps = np.concatenate(
            [np.broadcast_to(_STEPS, (rest.size, _STEPS.size)), damped[rest, None]], axis=1
        )
        accept = accepted(steps, rest)
        first = np.argmax(accept, axis=1)  # the longest accepted length (0 if none: a stall)
        length[rest] = np.where(accept.any(axis=1), steps[np.arange(rest.size), first], 0.0)
    return x + length[:, None] * step


def _certify(
    x: NDArray[np.float64],
    basis: NDArray[np.float64],
    points: NDArray[np.float64],
    slack: NDArray[np.float64],
    t: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""The best feasible X at hand for each problem, scaled to touch, and its certified gap.

    Any :math:`\lambda \ge 0` bounds the optimum: :math:`\log\det X^* \le -\log\det W
    - r \log(r / \sum_i \lambda_i)` with :math:`W = \sum_i \lambda_i c_i c_i^T`
    (Lagrangian duality, with the best scaling of :math:`\lambda`).  The duals are the
    central path's :math:`1 / (t s_i)`, also with those of clearly inactive constraints
    set to zero (they only add N / t to the gap); each gives a candidate ``X = W^-1`` (the
    optimality condition) beside the primal iterate.

    Parameters
    ----------
    x : ndarray, shape (K, d)
    basis : ndarray, shape (d, r, r)
    points : ndarray, shape (K, N, r)
    slack : ndarray, shape (K, N)
    t : ndarray, shape (K,)

    Returns
    -------
    shapes : ndarray, shape (K, r, r)
    gaps : ndarray, shape (K,)
    """
    K, _, r = points.shape
    with np.errstate(divide="ignore"):  # a slack of 0 (rounding): an infinite dual, unused
        duals = 1.0 / (t[:, None] * slack)
    candidates = [np.einsum("Kk,kab->Kab", x, basis)]
    upper = np.full(K, np.inf)
    for threshold in (np.inf, 1e-4):
        kept = np.where(slack <= threshold, duals, 0.0)
        W = np.einsum("Kia,Ki,Kib->Kab", points, kept, points)
        sign, logdet_W = np.linalg.slogdet(W)
        valid = sign > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            bound = -logdet_W - r * np.log(r / kept.sum(axis=1))
        upper = np.where(valid, np.minimum(upper, bound), upper)
        inverse = np.linalg.inv(np.where(valid[:, None, None], W, np.eye(r)))
        candidates.append(np.where(valid[:, None, None], inverse, np.nan))
    best, best_logdet = np.full((K, r, r), np.nan), np.full(K, -np.inf)
    for X in candidates:
        X = 0.5 * (X + np.swapaxes(X, 1, 2))
        finite = np.isfinite(X).all(axis=(1, 2))
        X = np.where(finite[:, None, None], X, np.eye(r))
        positive = finite & (np.linalg.eigvalsh(X)[:, 0] > 0)
        X = X / np.einsum("Kia,Kab,Kib->Ki", points, X, points).max(axis=1)[:, None, None]
        logdet = np.where(positive, np.linalg.slogdet(X)[1], -np.inf)
        improve = logdet > best_logdet
        best = np.where(improve[:, None, None], X, best)
        best_logdet = np.where(improve, logdet, best_logdet)
    return best, upper - best_logdet
