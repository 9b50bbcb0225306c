r"""The maximum-volume ellipsoid inscribed in the acceleration polytope.

For a polytope :math:`\{y : a_i^T y \le h_i\}` symmetric about its centre (a zonotope),
the maximum-volume inscribed ellipsoid is centred there, and its shape
:math:`S \succeq 0` (:math:`E = \{c + S u : \|u\| \le 1\}`) solves the log-det program

.. math::

    \max_S \ \log\det S \quad \text{s.t.} \quad \|S a_i\| \le h_i ,

solved in the coordinates of the polytope's affine set (so degenerate polytopes get their
lower-dimensional MVIE) with cvxpy and Clarabel.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from polyell.errors import SolverError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.polytope import Polytope

__all__ = ["max_volume_inscribed_ellipsoid"]


def max_volume_inscribed_ellipsoid(P: Polytope) -> Ellipsoid:
    """The maximum-volume ellipsoid inscribed in ``P``, in ``P``'s affine set.

    Parameters
    ----------
    P : Polytope

    Returns
    -------
    Ellipsoid
        Of kind ``"mvie"``, centred at ``P.center``.  The solver's answer is rescaled
        uniformly (by its tolerance) so that it touches the boundary of ``P`` exactly.

    Raises
    ------
    SolverError
        If Clarabel does not certify an optimum.
    """
    basis = P.affine_set.basis
    r = P.dim
    if r == 0:
        return Ellipsoid(P.center, np.zeros((P.ambient_dim, 0)), np.zeros(0), kind="mvie")
    normals = P.A @ basis  # unit normals in the affine set's coordinates
    offsets = P.b - P.A @ P.center  # h_i > 0
    # P is a zonotope: its facets come in pairs (a, -a) with one offset from the centre,
    # and ||S a|| = ||S (-a)||, so one of each pair gives every constraint.  (The
    # duplicates are not harmless: they made Clarabel stop "inaccurate" on some
    # well-conditioned Panda polytopes.)
    half = len(normals) // 2
    if np.array_equal(normals[:half], -normals[half:]):
        normals, offsets = normals[:half], offsets[:half]
    if r == 1:
        half_length = float(np.min(offsets / np.abs(normals[:, 0])))
        return Ellipsoid(P.center, basis, [half_length], kind="mvie")
    scale = float(offsets.max())
    S = cp.Variable((r, r), PSD=True)
    problem = cp.Problem(
        cp.Maximize(cp.log_det(S)), [cp.norm(S @ normals.T, axis=0) <= offsets / scale]
    )
    try:
        problem.solve(solver=cp.CLARABEL)
    except cp.error.SolverError as exn:
        raise SolverError(f"Clarabel failed on the log-det program of the MVIE: {exn}") from exn
    if problem.status != cp.OPTIMAL:
        raise SolverError(
            f"Clarabel returned status {problem.status!r} for the maximum-volume inscribed "
            "ellipsoid; its scores are unknown."
        )
    shape = np.asarray(S.value)
    eigenvalues, eigenvectors = np.linalg.eigh(scale * 0.5 * (shape + shape.T))
    reach = np.linalg.norm((normals @ eigenvectors) * eigenvalues, axis=1)
    # Rescale to touch P exactly: the solver's answer is feasible and optimal to its
    # tolerance (1e-8); the uniform rescaling fixes the feasibility digits and only grows
    # the volume when the solver stopped strictly inside.
    eigenvalues *= float(np.min(offsets / reach))
    return Ellipsoid(P.center, basis @ eigenvectors, eigenvalues, kind="mvie")
