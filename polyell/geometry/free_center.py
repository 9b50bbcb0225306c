r"""The inscribed and enclosing optimal ellipsoids of an H-polytope, whose centre is free.

A zonotope is symmetric about its centre, so its optimal ellipsoids are centred there
(:mod:`polyell.geometry.mvie`, :mod:`polyell.geometry.outer`).  An H-polytope (the force
capacity's set) has no such centre:

* the maximum-volume inscribed ellipsoid :math:`\{d + C u : \|u\| \le 1\}` solves
  :math:`\max \log\det C` subject to :math:`\|C a_i\| + a_i \cdot d \le b_i`, in
  coordinates where the polytope is of size 1, by the primal-dual interior-point method of
  Zhang and Gao (2003) with a certified duality gap, for K polytopes at once
  (:func:`free_center_mvie_batch`; :func:`free_center_mvie` is a batch of one);
* the minimum-volume enclosing ellipsoid of its vertices :math:`v_i` is the section at
  :math:`t = 1` of the centred one around the lifted points :math:`\pm (v_i, 1)`
  (Todd, *Minimum-Volume Ellipsoids*, 2016, section 2.3), solved by the same certified
  interior-point method as the zonotope's (:func:`~polyell.geometry.logdet.centred_mvee`).

Both results are made exact by construction: the inscribed one is shrunk by its worst
violation (or grown to touch its nearest facet) and the enclosing one grown to its farthest
vertex, so ``inscribed_scale >= 1`` and ``enclosing_scale <= 1`` hold to rounding.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import SolverError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.logdet import centred_mvee_batch

__all__ = [
    "FreeCenterBatch",
    "free_center_mvee",
    "free_center_mvee_batch",
    "free_center_mvie",
    "free_center_mvie_batch",
]


def _frame(P: HPolytope, what: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Refuse empty or unbounded sets; a centre and a whitening frame of the hull.

    Returns the vertices' mean c and a matrix F (m, r) with ``x = c + F y``: y spans the
    hull, and the vertices have unit covariance in y (the programs below then see a round
    set of size 1, however thin or large P is).
    """
    if P.is_empty:
        raise UndefinedEllipsoidError(f"The {what} of an empty set does not exist.")
    if not P.is_bounded:
        raise UndefinedEllipsoidError(
            f"The {what} of an unbounded set does not exist: the set is unbounded along "
            f"{len(P.rays)} ray(s) (see polytope.rays)."
        )
    center = P.vertices.mean(axis=0)
    offsets = (P.vertices - center) @ P.affine_set.basis  # (V, r)
    _, s, Vt = np.linalg.svd(offsets, full_matrices=False)
    r = P.dim
    s = s[:r] / np.sqrt(len(offsets))
    return center, P.affine_set.basis @ (Vt[:r].T * s)


def _point(P: HPolytope, kind: str) -> Ellipsoid:
    return Ellipsoid(P.vertices[0], np.zeros((P.ambient_dim, 0)), np.zeros(0), kind=kind)


#: Default certified gap in log det C of the inscribed ellipsoid (its volume is within a
#: relative MVIE_GAP of the greatest), as for the zonotopes' MVIE.
MVIE_GAP = 1e-8
#: Fraction of the way to the boundary (y, z > 0, b - A d > 0) that a step may go, at
#: least; ``1 - mu`` near the optimum (Zhang and Gao's tau, ``1 - residual`` there).
TO_BOUNDARY = 0.75
#: Neighbourhood of the central path kept by every step: y_i z_i >= NEIGHBOURHOOD * mean.
NEIGHBOURHOOD = 1e-3
#: Step lengths tried, as fractions of the longest step.
_FRACTIONS = 0.8 ** np.arange(30.0)
#: Floor of the centring target mu (Zhang and Gao's minmu, smaller: a 1e-8 gap asks for it).
MIN_MU = 1e-14
#: Iterations without a better certificate after which a problem stops (rounding).
STALL = 8


class FreeCenterBatch(NamedTuple):
    """The solution of :func:`free_center_mvie_batch`.

    Attributes
    ----------
    centers : ndarray, shape (K, r)
        Centres d.
    shapes : ndarray, shape (K, r, r)
        Symmetric positive-definite C: the ellipsoid is ``{d + C u : |u| <= 1}``, inside
        ``{x : A x <= b}`` to rounding (NaN where no iterate was interior).
    gaps : ndarray, shape (K,)
        Certified bounds on ``log det C* - log det C`` (the volume is within a factor
        ``exp(gap)`` of the greatest); ``inf`` where none was found.
    iterations : ndarray of int, shape (K,)
    converged : ndarray of bool, shape (K,)
        ``gaps <= gap``.
    """

    centers: NDArray[np.float64]
    shapes: NDArray[np.float64]
    gaps: NDArray[np.float64]
    iterations: NDArray[np.int_]
    converged: NDArray[np.bool_]


def free_center_mvie_batch(
    A: ArrayLike,
    b: ArrayLike,
    mask: ArrayLike | None = None,
    *,
    gap: float = MVIE_GAP,
    max_iterations: int = 80,
) -> FreeCenterBatch:
    r"""The maximum-volume inscribed ellipsoids of K bounded H-polytopes at once.

    Each solves :math:`\max \log\det C` s.t. :math:`\|C a_i\| + a_i \cdot d \le b_i`.

    Parameters
    ----------
    A : array-like, shape (K, F, r)
        Facet normals, in a well-scaled frame: each polytope of size about 1 with the
        origin inside (e.g. its vertices' mean at 0), so that ``b > 0`` on every row used.
    b : array-like, shape (K, F)
        Offsets.
    mask : array-like of bool, shape (K, F), optional
        The rows to use (polytopes with fewer facets pad with rows marked False); default
        all.
    gap : float, optional
        Target certified bound on ``log det C* - log det C``.
    max_iterations : int, optional

    Returns
    -------
    FreeCenterBatch
        Centres, shapes, certified gaps, iterations and ``converged`` (``gap`` reached).
        A problem whose origin is not strictly inside (a used row with ``b <= 0``) or whose
        normals do not span R^r (unbounded) is returned unconverged, with NaN.

    Notes
    -----
    The primal-dual interior-point method of Y. Zhang and L. Gao, "On numerical solution
    of the maximum volume ellipsoid problem", SIAM J. Optim. 14 (2003) 53-76 (the code
    MaxVolInscribedEllipsoid), run for K problems together.  The rows are scaled to
    :math:`b = 1` (the origin inside) and whitened by :math:`(\sum_i a_i a_i^T)^{-1/2}`
    (the method is affine-invariant, its rounding is not); its unknowns are the centre
    :math:`d`, multipliers :math:`y > 0` and slacks :math:`z > 0`, with :math:`C^2 = (A^T
    Y A)^{-1}` and :math:`h_i = \|C a_i\|`: Newton's method on :math:`A^T (y \circ h) =
    0`, :math:`b - A d - h - z = 0`, :math:`y \circ z = \sigma \mu`, three (F, F) and two
    (r, r) linear solves per problem and iteration (the (F, F) matrix Jacobi-scaled).
    Unlike Zhang and Gao's code (a quadratically shrinking target), the centring
    :math:`\sigma` is Mehrotra's predictor-corrector choice and every step keeps
    :math:`y_i z_i \ge` :data:`NEIGHBOURHOOD` times their mean: without these a slack or
    multiplier crushed to 1e-14 early stalled about 1 in 500 random 6-D force sets short
    of a 1e-8 gap.
    About 6 iterations (at most ~15) reach a gap of 1e-8 on random force sets.

    Certificate (every iterate, exact, not asymptotic).  Conic (Lagrangian) duality gives,
    for any :math:`\lambda \ge 0` with :math:`\sum_i \lambda_i a_i = 0` and any
    :math:`u_i` with :math:`\|u_i\| \le \lambda_i` and :math:`S = \operatorname{sym}
    \sum_i u_i a_i^T \succ 0`, the upper bound :math:`\log\det C^* \le b^T \lambda -
    \log\det S - r` (Boyd and Vandenberghe, *Convex Optimization*, 2004, section 8.4.2
    and chapter 5): :math:`\log\det C + \sum_i (\lambda_i (b_i - a_i \cdot d) - u_i^T C
    a_i) \ge \log\det C` on the feasible set, and its supremum over d and C is that
    bound.  At an iterate take :math:`u_i = \theta y_i C a_i` (then :math:`S = \theta
    C^{-1}`) and :math:`\lambda = y \circ h - Y A (A^T Y A)^{-1} A^T (y \circ h)` (the
    multipliers :math:`\lambda_i = y_i h_i` projected onto :math:`A^T \lambda = 0`),
    :math:`\theta = \min_i \lambda_i / (y_i h_i)`; the primal point is :math:`(d, s C)`
    with :math:`s = \min_i (b_i - a_i \cdot d) / h_i`, feasible.  The gap

    .. math:: \log\det C^* - \log\det (s C) \le b^T \lambda - r - r \log (s \theta)

    tends to 0 (at the optimum :math:`b^T \lambda = \operatorname{tr} (C^2 A^T Y A) = r`,
    :math:`s = \theta = 1`).  The returned C is that of the best certificate, scaled so
    that the largest :math:`(\|C a_i\| + a_i \cdot d) / b_i` is 1: inscribed by
    construction.
    """
    A = np.ascontiguousarray(A, dtype=float)  # one memory layout: one rounding
    b = np.ascontiguousarray(b, dtype=float)
    K, F, r = A.shape
    present = np.ones((K, F), dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    present = present & np.isfinite(b) & np.all(np.isfinite(A), axis=-1)
    present &= np.einsum("Kia,Kia->Ki", A, A) > 0  # a zero row is no constraint
    valid = np.all(~present | (b > 0), axis=1)
    present &= valid[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        scaled = np.where(present[..., None], A / b[..., None], 0.0)  # rows with b = 1
    # Whitened by (sum_i a_i a_i^T)^(-1/2) (Zhang and Gao's first iterate, y = 1): the
    # method is affine-invariant, its rounding is not (a thin set).
    _, singular, Vt = np.linalg.svd(scaled, full_matrices=False)  # no squared condition
    valid &= singular[:, -1] > max(F, r) * np.finfo(float).eps * singular[:, 0]  # spanning
    present &= valid[:, None]
    centers, shapes = np.full((K, r), np.nan), np.full((K, r, r), np.nan)
    gaps, iterations = np.full(K, np.inf), np.zeros(K, dtype=int)
    rows = np.flatnonzero(valid)
    if rows.size:
        T = (np.swapaxes(Vt[rows], 1, 2) / singular[rows][:, None, :]) @ Vt[rows]
        whitened = scaled[rows] @ T
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            best_x, best_m, best_gap, its = _solve(
                _start(whitened, present[rows]), gap, max_iterations
            )
        iterations[rows] = its
        good = np.isfinite(best_gap)
        found = rows[good]
        gaps[found] = best_gap[good]
        x, C = _inscribed(whitened[good], present[found], best_x[good], best_m[good])
        # back: {T x + T C u}, of shape (T C^2 T)^(1/2) (the polar factor of T C)
        T = T[good]
        W, sigma, _ = np.linalg.svd(T @ C)
        C = (W * sigma[:, None, :]) @ np.swapaxes(W, 1, 2)
        x = (T @ x[..., None])[..., 0]
        centers[found], shapes[found] = _inscribed_scale(scaled[found], present[found], x, C)
    return FreeCenterBatch(centers, shapes, gaps, iterations, gaps <= gap)


def free_center_mvie(P: HPolytope, *, gap: float = MVIE_GAP) -> Ellipsoid:
    """The maximum-volume ellipsoid inscribed in a bounded H-polytope, in its affine hull.

    :func:`free_center_mvie_batch` for one problem, in the whitened frame of the hull
    (the vertices' mean at 0, unit covariance).

    Parameters
    ----------
    P : HPolytope
    gap : float, optional
        Target certified bound on ``log det C* - log det C`` (the volume is within a
        factor ``exp(gap)`` of the greatest).

    Raises
    ------
    UndefinedEllipsoidError
        For an empty or unbounded set.
    SolverError
        If the interior-point method does not certify an optimum.
    """
    r = P.dim
    if r == 0:
        return _point(P, "mvie")
    center, F = _frame(P, "maximum-volume inscribed ellipsoid")
    # x = c + F y: facets a_y = F^T a, b_y = b - a . c, normalised
    A = P.A @ F
    norms = np.linalg.norm(A, axis=1)
    keep = norms > 1e-12 * norms.max()  # a normal orthogonal to the hull is no facet
    A, b = A[keep] / norms[keep, None], (P.b[keep] - P.A[keep] @ center) / norms[keep]
    result = free_center_mvie_batch(A[None], b[None], gap=gap)
    if not result.converged[0]:
        raise SolverError(
            f"maximum-volume inscribed ellipsoid: certified optimality gap "
            f"{result.gaps[0]:.3g} after {result.iterations[0]} iterations (target "
            f"{gap:.3g}) on {len(b)} facets in R^{r}."
        )
    y0, shape = result.centers[0], result.shapes[0]
    W, s, _ = np.linalg.svd(F @ shape, full_matrices=False)
    if not np.all(s > 0):
        raise SolverError("maximum-volume inscribed ellipsoid: a degenerate solution.")
    return Ellipsoid(center + F @ y0, W, s, kind="mvie")


def free_center_mvee(P: HPolytope, *, gap: float = MVIE_GAP) -> Ellipsoid:
    """The minimum-volume ellipsoid around a bounded H-polytope (its vertices), in its hull.

    :func:`free_center_mvee_batch` for one problem, in the whitened frame of the hull.

    Raises
    ------
    UndefinedEllipsoidError
        For an empty or unbounded set.
    SolverError
        If the interior-point method does not certify an optimum.
    """
    r = P.dim
    if r == 0:
        return _point(P, "outer")
    center, F = _frame(P, "minimum-volume enclosing ellipsoid")
    y = np.linalg.lstsq(F, (P.vertices - center).T, rcond=None)[0].T  # (V, r), round
    result = free_center_mvee_batch(y[None], np.ones((1, len(y)), dtype=bool), gap=gap)
    if not result.converged[0]:
        raise SolverError(
            f"minimum-volume enclosing ellipsoid: certified optimality gap "
            f"{result.gaps[0]:.3g} after {result.iterations[0]} iterations (target "
            f"{gap:.3g}) on {len(y)} vertices in R^{r}."
        )
    W, s, _ = np.linalg.svd(F @ result.shapes[0], full_matrices=False)
    return Ellipsoid(center + F @ result.centers[0], W, s, kind="outer")


def free_center_mvee_batch(
    points: NDArray[np.float64],
    present: NDArray[np.bool_],
    *,
    gap: float = MVIE_GAP,
) -> FreeCenterBatch:
    """The minimum-volume ellipsoids around K point sets, their centres free, batched.

    Each is the section at ``t = 1`` of the centred one around the lifted points
    ``+-(v_i, 1)`` (Todd, *Minimum-Volume Ellipsoids*, 2016, section 2.3), solved by
    :func:`~polyell.geometry.logdet.centred_mvee_batch` with its certified gap, then grown
    to pass through the farthest point (so that it encloses them to rounding).

    Parameters
    ----------
    points : ndarray, shape (K, V, r)
        The point sets, best of size about 1 about the origin (padded).
    present : ndarray of bool, shape (K, V)
        The points of each set (the others are ignored).
    gap : float, optional
        Target certified gap in ``log det``.

    Returns
    -------
    FreeCenterBatch
        Centres, shapes C (``{d + C u : |u| <= 1}``), gaps; a set whose solution is not
        certified or degenerate has ``converged`` False (and NaN shapes).
    """
    r = points.shape[-1]
    lifted = np.where(
        present[..., None], np.concatenate([points, np.ones((*present.shape, 1))], -1), 0.0
    )
    H, gaps, iterations = centred_mvee_batch(lifted, gap=gap)
    H11, h12, h22 = H[:, :r, :r], H[:, :r, r], H[:, r, r]
    converged = gaps <= gap
    H11 = np.where(converged[:, None, None], H11, np.eye(r))
    h12, h22 = np.where(converged[:, None], h12, 0.0), np.where(converged, h22, 0.0)
    centers = np.asarray(-np.linalg.solve(H11, h12[..., None])[..., 0], dtype=float)
    level = 1.0 - h22 - np.einsum("ki,ki->k", h12, centers)  # (y - y0)^T H11 (y - y0) <= level
    converged &= level > 0
    eigenvalues, eigenvectors = np.linalg.eigh(H11 / np.where(converged, level, 1.0)[:, None, None])
    converged &= np.all(eigenvalues > 0, axis=-1)
    eigenvalues = np.where(converged[:, None], eigenvalues, 1.0)
    offsets = (points - centers[:, None, :]) @ eigenvectors
    reach = np.max(np.where(present, ((offsets**2) @ eigenvalues[..., None])[..., 0], 0.0), axis=1)
    grow = np.maximum(1.0, np.sqrt(reach))  # through the farthest point
    shapes = (eigenvectors * (grow[:, None] / np.sqrt(eigenvalues))[:, None, :]) @ np.swapaxes(
        eigenvectors, 1, 2
    )
    shapes = np.where(converged[:, None, None], shapes, np.nan)
    return FreeCenterBatch(centers, shapes, gaps, iterations, converged)


class _State(NamedTuple):
    """The iterates of the problems still running (k of them)."""

    A: NDArray[np.float64]  # (k, F, r) rows scaled to b = 1, zero where not present
    present: NDArray[np.bool_]  # (k, F)
    x: NDArray[np.float64]  # (k, r) centre
    y: NDArray[np.float64]  # (k, F) multipliers, 0 where not present
    z: NDArray[np.float64]  # (k, F) slacks, 1 where not present
    slack: NDArray[np.float64]  # (k, F) 1 - A x, 1 where not present


def _evaluate(
    A: NDArray[np.float64], present: NDArray[np.bool_], y: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """M = A^T Y A, its inverse C^2, Q = A C^2 A^T and h_i = |C a_i| (1 off the rows)."""
    M = np.swapaxes(A, 1, 2) @ (y[..., None] * A)
    M = 0.5 * (M + np.swapaxes(M, 1, 2))
    E2 = _solve_batch(M, None)
    E2 = 0.5 * (E2 + np.swapaxes(E2, 1, 2))
    Q = A @ E2 @ np.swapaxes(A, 1, 2)
    h = np.sqrt(np.maximum(np.einsum("kii->ki", Q), 0.0))
    return M, E2, Q, np.where(present, h, 1.0)


def _start(A: NDArray[np.float64], present: NDArray[np.bool_]) -> _State:
    """Zhang and Gao's start: d = 0, y = 1 scaled so that max h = 1, z = max(0.1, 1 - h)."""
    k, F, r = A.shape
    y = present.astype(float)
    _, _, _, h = _evaluate(A, present, y)
    t = np.min(np.where(present, 1.0 / h, np.inf), axis=1)
    y = y / (t**2)[:, None]
    h = h * t[:, None]
    z = np.where(present, np.maximum(0.1, 1.0 - h), 1.0)
    return _State(A, present, np.zeros((k, r)), y, z, np.ones((k, F)))


def _certificate(
    state: _State, E2: NDArray[np.float64], h: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The certified bound on log det C* - log det (s C) (the notes of the batch)."""
    A, present, _, y, _, slack = state
    r = A.shape[-1]
    residual = np.swapaxes(A, 1, 2) @ (y * h)[..., None]  # A^T (y h), (k, r, 1)
    correction = (A @ (E2 @ residual))[..., 0]  # a_i^T (A^T Y A)^-1 A^T (y h)
    lam = y * (h - correction)
    theta = np.min(np.where(present, 1.0 - correction / h, np.inf), axis=1)
    s = np.min(np.where(present, slack / h, np.inf), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = lam.sum(axis=1) - r - r * np.log(s * theta)
    bound = np.maximum(bound, 0.0)  # below 0 by rounding only
    return np.where((theta > 0) & (s > 0) & np.isfinite(bound), bound, np.inf)


def _solve(
    state: _State, gap: float, max_iterations: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.int_]]:
    """Iterate every problem until its certificate reaches gap (or stalls).

    Returns the centre and M = A^T Y A (C = M^-1/2) of each problem's best certificate,
    the certificate and the iterations taken.
    """
    k, _, r = state.A.shape
    best_x, best_m = np.zeros((k, r)), np.tile(np.eye(r), (k, 1, 1))
    best_gap, iterations = np.full(k, np.inf), np.zeros(k, dtype=int)
    stalled = np.zeros(k, dtype=int)
    active = np.arange(k)
    while True:
        M, E2, Q, h = _evaluate(state.A, state.present, state.y)
        certified = _certificate(state, E2, h)
        better = certified < best_gap[active]
        improved = active[better]
        best_gap[improved] = certified[better]
        best_x[improved], best_m[improved] = state.x[better], M[better]
        stalled[active] = np.where(better, 0, stalled[active] + 1)
        stop = (certified <= gap) | (stalled[active] >= STALL)
        stop |= iterations[active] >= max_iterations
        if stop.all():
            break
        keep = ~stop
        active = active[keep]
        state = _State(
            state.A[keep],
            state.present[keep],
            state.x[keep],
            state.y[keep],
            state.z[keep],
            state.slack[keep],
        )
        M, E2, Q, h = M[keep], E2[keep], Q[keep], h[keep]
        iterations[active] += 1
        state = _newton(state, M, Q, h)
    return best_x, best_m, best_gap, iterations


def _newton(
    state: _State, M: NDArray[np.float64], Q: NDArray[np.float64], h: NDArray[np.float64]
) -> _State:
    """One predictor-corrector step on Zhang and Gao's equations for every problem.

    Newton's equations for ``A^T (y h) = 0``, ``b - A x - h - z = 0``, ``y z = target``
    (``dh_i / dy_j = -Q_ij^2 / (2 h_i)``), with ``dy = y v``: ``G v = 2 y h (A dx - R23)``,
    ``G = Y (Q o Q) Y + diag(2 y h z)``, ``R23 = R2 - R3 / y``, and ``dx`` from the r
    equations of the first block.  Mehrotra's predictor (target 0) sets the centring
    ``sigma = (mu_aff / mu)^3``; the corrector's step is the longest (to ``TO_BOUNDARY``
    of the boundary y, z, b - A x > 0) that keeps every ``y_i z_i`` at least
    ``NEIGHBOURHOOD`` times their mean.
    """
    A, present, x, y, z, slack = state
    F = A.shape[1]
    count = present.sum(axis=1)
    At = np.swapaxes(A, 1, 2)
    yh = y * h
    R1 = -(At @ yh[..., None])[..., 0]  # (k, r)
    R2 = np.where(present, slack - h - z, 0.0)
    mu = (y * z).sum(axis=1) / count
    G = y[:, :, None] * Q**2 * y[:, None, :]
    diagonal = np.where(present, np.maximum(2.0 * yh * z, 1e-300), 1.0)
    G[:, np.arange(F), np.arange(F)] += diagonal
    # Jacobi scaling (unit diagonal): near the optimum the rows of inactive facets (y -> 0)
    # and of active ones (z -> 0) differ in scale by many orders
    jacobi = 1.0 / np.sqrt(np.einsum("kii->ki", G))
    G *= jacobi[:, :, None] * jacobi[:, None, :]
    U = jacobi[..., None] * _solve_batch(G, (jacobi * 2.0 * yh)[..., None] * A)  # (k, F, r)
    weight = y * (h + z)
    lhs = At @ (weight[..., None] * U) - M

    def direction(R3: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """dx, A dx, v = dy / y and dz for the target residual R3 = target - y z."""
        with np.errstate(divide="ignore", invalid="ignore"):
            R3y = np.where(present, R3 / y, 0.0)
        R23 = R2 - R3y
        u0 = jacobi * _solve_batch(G, (jacobi * 2.0 * yh * R23)[..., None])[..., 0]
        rhs = R1 + (At @ (weight * u0 - y * R23)[..., None])[..., 0]
        dx = _solve_batch(lhs, rhs[..., None])[..., 0]
        v = np.where(present, (U @ dx[..., None])[..., 0] - u0, 0.0)
        return dx, (A @ dx[..., None])[..., 0], v, np.where(present, R3y - z * v, 0.0)

    def to_boundary(
        Adx: NDArray[np.float64], v: NDArray[np.float64], dz: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """The longest step in (0, 1] keeping y, z and b - A x >= 0."""
        with np.errstate(divide="ignore", invalid="ignore"):
            worst = np.maximum(
                np.max(np.where(present, Adx / slack, 0.0), axis=1),
                np.maximum(np.max(-v, axis=1), np.max(np.where(present, -dz / z, 0.0), axis=1)),
            )
        return 1.0 / np.maximum(worst, 1.0)

    _, Adx, v, dz = direction(np.where(present, -y * z, 0.0))  # predictor: target 0
    length = to_boundary(Adx, v, dz)[:, None]
    mu_aff = (y * (1.0 + length * v) * (z + length * dz)).sum(axis=1) / count
    sigma = np.clip(mu_aff / mu, 0.0, 1.0) ** 3
    target = np.maximum(sigma * mu, MIN_MU)
    R3 = np.where(present, target[:, None] - y * z - y * v * dz, 0.0)
    dx, Adx, v, dz = direction(R3)
    longest = np.maximum(TO_BOUNDARY, 1.0 - mu) * to_boundary(Adx, v, dz)
    # the longest of these steps that keeps every y_i z_i >= NEIGHBOURHOOD times their mean
    fraction = np.ones(len(longest))
    todo = np.arange(len(longest))
    for trial in _FRACTIONS:  # most problems take the first
        length = (trial * longest[todo])[:, None]
        products = y[todo] * (1.0 + length * v[todo]) * (z[todo] + length * dz[todo])
        used = present[todo]
        mean = np.where(used, products, 0.0).sum(axis=1) / count[todo]
        inside = np.where(used, products, np.inf).min(axis=1) >= NEIGHBOURHOOD * mean
        fraction[todo] = trial
        todo = todo[~inside]
        if not todo.size:
            break
    step = (longest * fraction)[:, None]
    return _State(
        A,
        present,
        x + step * dx,
        y * (1.0 + step * v),
        z + step * dz,
        np.where(present, slack - step * Adx, 1.0),
    )


def _inscribed(
    A: NDArray[np.float64],
    present: NDArray[np.bool_],
    x: NDArray[np.float64],
    M: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centres and C = s M^-1/2, s making the largest |C a_i| + a_i . x (b = 1) exactly 1."""
    eigenvalues, eigenvectors = np.linalg.eigh(M)
    C = (eigenvectors / np.sqrt(eigenvalues)[:, None, :]) @ np.swapaxes(eigenvectors, 1, 2)
    return _inscribed_scale(A, present, x, C)


def _inscribed_scale(
    A: NDArray[np.float64],
    present: NDArray[np.bool_],
    x: NDArray[np.float64],
    C: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """C symmetrised and scaled so that the largest |C a_i| + a_i . x (b = 1) is 1."""
    C = 0.5 * (C + np.swapaxes(C, 1, 2))
    reach = np.linalg.norm(A @ C, axis=2)
    slack = 1.0 - (A @ x[..., None])[..., 0]
    scale = np.min(np.where(present, slack / np.where(present, reach, 1.0), np.inf), axis=1)
    return x, C * scale[:, None, None]


def _solve_batch(
    matrices: NDArray[np.float64], right: NDArray[np.float64] | None
) -> NDArray[np.float64]:
    """``solve(matrices, right)`` (the inverses if ``right`` is None), for every problem.

    LAPACK refuses a whole batch when one matrix is singular (a problem gone wrong): then
    the pseudo-inverses, NaN for a non-finite matrix, so that the others go on (the
    certificate of the broken problem stops improving and it stops).
    """
    solution: NDArray[np.float64]
    try:
        solved = np.linalg.inv(matrices) if right is None else np.linalg.solve(matrices, right)
        solution = solved.astype(float, copy=False)
    except np.linalg.LinAlgError:
        finite = np.all(np.isfinite(matrices), axis=(1, 2))
        inverse = np.full_like(matrices, np.nan)
        inverse[finite] = np.linalg.pinv(matrices[finite])
        solution = inverse if right is None else inverse @ right
    return solution
