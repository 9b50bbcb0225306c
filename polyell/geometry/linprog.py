r"""Directional limits of the acceleration polytope by linear programming (the reference).

For a unit direction :math:`t`, the achievable accelerations along it are

.. math::

    \{ a : a t = M \tilde\tau + \ddot x_g,\ \|\tilde\tau\|_\infty \le 1 \},

an interval whose ends are two linear programs in :math:`(a, \tilde\tau)`.  They are
solved with cvxpy and the Clarabel interior-point solver, directly in the space of
normalized torques, so they share nothing with the closed form built on the facets.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from polyell.errors import MissingDependencyError, SolverError, install_hint

__all__ = ["CLARABEL_SETTINGS", "polytope_limits_lp"]

#: Clarabel tolerances tight enough for a 1e-8 relative comparison.
CLARABEL_SETTINGS = {
    "tol_gap_abs": 1e-12,
    "tol_gap_rel": 1e-12,
    "tol_feas": 1e-12,
    "tol_infeas_abs": 1e-12,
    "tol_infeas_rel": 1e-12,
    "tol_ktratio": 1e-10,
    "max_iter": 500,
}


def polytope_limits_lp(
    M: NDArray[np.float64], center: NDArray[np.float64], directions: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Solve ``min a`` and ``max a`` subject to ``a t = M tau + center``, ``|tau|_inf <= 1``.

    Parameters
    ----------
    M : ndarray, shape (m, n)
        Generators (eq. 14).
    center : ndarray, shape (m,)
        Centre ``xdd_g`` (eq. 8).
    directions : ndarray, shape (k, m)
        Unit directions.

    Returns
    -------
    lo, hi : ndarray, shape (k,)
        Interval ends; NaN where the line misses the polytope.

    Raises
    ------
    SolverError
        If Clarabel returns anything but a certified optimum or infeasibility (an
        "inaccurate" status is not accepted as an answer).
    """
    try:
        import cvxpy as cp  # here: cvxpy takes most of a second to import
    except ImportError as exn:
        raise MissingDependencyError(
            'method="lp" needs cvxpy and Clarabel. Fix: ' + install_hint("lp") + "."
        ) from exn

    m, n = M.shape
    t = cp.Parameter(m)
    a = cp.Variable()
    tau = cp.Variable(n)
    constraints = [a * t == M @ tau + center, cp.norm(tau, "inf") <= 1]
    problems = {sense: cp.Problem(sense(a), constraints) for sense in (cp.Minimize, cp.Maximize)}
    bounds = np.full((2, directions.shape[0]), np.nan)
    for k, direction in enumerate(directions):
        t.value = direction
        for row, problem in enumerate(problems.values()):
            try:
                problem.solve(solver=cp.CLARABEL, **CLARABEL_SETTINGS)
            except cp.error.SolverError as exn:
                raise SolverError(f"Clarabel failed on direction {direction}: {exn}") from exn
            if problem.status == cp.OPTIMAL:
                bounds[row, k] = a.value
            elif problem.status != cp.INFEASIBLE:
                raise SolverError(
                    f"Clarabel returned status {problem.status!r} on direction {direction}; "
                    "the LP limit is not certified to 1e-12. Use the closed form "
                    "(method='closed_form'), which needs no solver."
                )
    return bounds[0], bounds[1]
