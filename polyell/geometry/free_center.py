r"""The inscribed and enclosing optimal ellipsoids of an H-polytope, whose centre is free.

A zonotope is symmetric about its centre, so its optimal ellipsoids are centred there
(:mod:`polyell.geometry.mvie`, :mod:`polyell.geometry.outer`).  An H-polytope (the force
capacity's set) has no such centre:

* the maximum-volume inscribed ellipsoid :math:`\{d + C u : \|u\| \le 1\}` solves
  :math:`\max \log\det C` subject to :math:`\|C a_i\| + a_i \cdot d \le b_i` (cvxpy with
  Clarabel), in coordinates where the polytope is of size 1;
* the minimum-volume enclosing ellipsoid of its vertices :math:`v_i` is the section at
  :math:`t = 1` of the centred one around the lifted points :math:`\pm (v_i, 1)`
  (Todd, *Minimum-Volume Ellipsoids*, 2016, section 2.3), solved by the same certified
  interior-point method as the zonotope's (:func:`~polyell.geometry.logdet.centred_mvee`).

Both results are made exact by construction: the inscribed one is shrunk by its worst
violation (at most the solver's tolerance) and the enclosing one grown to its farthest
vertex, so ``inscribed_scale >= 1`` and ``enclosing_scale <= 1`` hold to rounding.
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import NDArray

from polyell.errors import SolverError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.logdet import centred_mvee

__all__ = ["free_center_mvee", "free_center_mvie"]


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


def free_center_mvie(P: HPolytope) -> Ellipsoid:
    """The maximum-volume ellipsoid inscribed in a bounded H-polytope, in its affine hull.

    Raises
    ------
    UndefinedEllipsoidError
        For an empty or unbounded set.
    SolverError
        If Clarabel does not reach an optimum.
    """
    import cvxpy as cp

    r = P.dim
    if r == 0:
        return _point(P, "mvie")
    center, F = _frame(P, "maximum-volume inscribed ellipsoid")
    # x = c + F y: facets a_y = F^T a, b_y = b - a . c, normalised
    A = P.A @ F
    norms = np.linalg.norm(A, axis=1)
    keep = norms > 1e-12 * norms.max()  # a normal orthogonal to the hull is no facet
    A, b = A[keep] / norms[keep, None], (P.b[keep] - P.A[keep] @ center) / norms[keep]
    C = cp.Variable((r, r), PSD=True)
    d = cp.Variable(r)
    constraints = [cp.norm(C @ A[i]) + A[i] @ d <= b[i] for i in range(len(b))]
    problem = cp.Problem(cp.Maximize(cp.log_det(C)), constraints)
    with warnings.catch_warnings():  # an inaccurate solution is refused below, with a reason
        warnings.simplefilter("ignore")
        try:
            problem.solve(solver=cp.CLARABEL)
        except cp.SolverError as exn:  # pragma: no cover - Clarabel failing on a polytope
            raise SolverError(
                f"maximum-volume inscribed ellipsoid: Clarabel failed ({exn})."
            ) from exn
    if problem.status != cp.OPTIMAL or C.value is None:
        raise SolverError(f"maximum-volume inscribed ellipsoid: Clarabel status {problem.status}.")
    eigenvalues, eigenvectors = np.linalg.eigh(0.5 * (C.value + C.value.T))
    eigenvalues = np.maximum(eigenvalues, 0.0)
    shape = (eigenvectors * eigenvalues) @ eigenvectors.T
    y0 = np.asarray(d.value, dtype=float)
    # Shrink by the worst violation, so that it is inside to rounding.
    slack = b - A @ y0
    reach = np.linalg.norm(A @ shape, axis=1)
    shrink = min(1.0, float(np.min(slack / reach)))
    W, s, _ = np.linalg.svd(F @ shape, full_matrices=False)
    if not np.all(s * shrink > 0):
        raise SolverError("maximum-volume inscribed ellipsoid: a degenerate solution.")
    return Ellipsoid(center + F @ y0, W, shrink * s, kind="mvie")


def free_center_mvee(P: HPolytope) -> Ellipsoid:
    """The minimum-volume ellipsoid around a bounded H-polytope (its vertices), in its hull.

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
    lifted = np.hstack([y, np.ones((len(y), 1))])
    H = centred_mvee(lifted).shape  # {z : z^T H z <= 1} around +-(y_i, 1)
    H11, h12, h22 = H[:r, :r], H[:r, r], H[r, r]
    y0 = -np.linalg.solve(H11, h12)
    level = 1.0 - h22 + float(h12 @ -y0)  # (y - y0)^T H11 (y - y0) <= level
    if not level > 0:
        raise SolverError("minimum-volume enclosing ellipsoid: a degenerate lifted solution.")
    eigenvalues, eigenvectors = np.linalg.eigh(H11 / level)
    offsets = (y - y0) @ eigenvectors
    grow = max(1.0, float(np.sqrt(np.max((offsets**2) @ eigenvalues))))  # through a vertex
    W, s, _ = np.linalg.svd(F @ (eigenvectors * (grow / np.sqrt(eigenvalues))), full_matrices=False)
    return Ellipsoid(center + F @ y0, W, s, kind="outer")
