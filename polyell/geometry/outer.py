r"""The minimum-volume ellipsoid containing the acceleration polytope (Löwner-John).

P is symmetric about :math:`\ddot x_g`, so its minimum-volume enclosing ellipsoid (the
outer Löwner-John ellipsoid) is centred there.  In the whitened coordinates of
:mod:`polyell.geometry.mvie` (:math:`\ddot x = \ddot x_g + U_1 \Sigma y`) it is
:math:`\{y : y^T X y \le 1\}` with

.. math::

    \max_X \ \log\det X \quad \text{s.t.} \quad v_j^T X v_j \le 1

over the vertices :math:`v_j` of the zonotope of :math:`V_1^T`: the same log-det program as
the MVIE's, on the vertices instead of the scaled facet normals.  With n = r generators P is
a parallelotope (a rotated cube in those coordinates) and the outer ellipsoid is exactly
the new ellipsoid scaled by :math:`\sqrt r`.  By John's theorem for symmetric bodies,
:math:`E_{\text{MVIE}} \subseteq P \subseteq E_{\text{outer}} \subseteq
\ddot x_g + \sqrt r \, (E_{\text{MVIE}} - \ddot x_g)`.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.mvie import ellipsoid_from_shape, fit_ellipsoid, log_det_shape
from polyell.geometry.polytope import Polytope
from polyell.validation import check_instance

__all__ = ["min_volume_enclosing_ellipsoid", "whitened_vertices"]


def min_volume_enclosing_ellipsoid(
    P: Polytope | HPolytope, method: Literal["logdet", "cvxpy"] = "logdet"
) -> Ellipsoid:
    """The minimum-volume ellipsoid containing ``P``, in ``P``'s affine set.

    Parameters
    ----------
    P : Polytope
    method : {"logdet", "cvxpy"}
        The solver of the log-det program, as for the MVIE (:data:`MVIE_METHODS`).

    Returns
    -------
    Ellipsoid
        Of kind ``"outer"``, centred at ``P.center``, through vertices of ``P``; its
        volume is within a relative 1e-8 of the least (certified gap, ``"logdet"``).

    Raises
    ------
    SolverError
        If the solver does not certify an optimum.
    """
    return fit_ellipsoid(P, method, "outer", _outer)


def _outer(P: Polytope, method: str) -> Ellipsoid:
    svd, r = P.svd, P.dim
    if r == 0:
        return Ellipsoid(P.center, np.zeros((P.ambient_dim, 0)), np.zeros(0), kind="outer")
    if r == 1:  # a segment: the whole of it, as the MVIE
        semi = svd.sigma * np.abs(svd.V1.T).sum()
        return Ellipsoid(P.center, svd.U1, semi, kind="outer")
    if P.generators.shape[1] == r:  # a rotated cube: the ball of radius sqrt(r)
        return Ellipsoid(P.center, svd.U1, np.sqrt(r) * svd.sigma, kind="outer")
    X = log_det_shape(whitened_vertices(P), method, "the minimum-volume enclosing ellipsoid")
    return ellipsoid_from_shape(P, X, -0.5, "outer")


def whitened_vertices(P: Polytope) -> NDArray[np.float64]:
    """One vertex of each pair ``xg +- v`` of ``P``, in whitened coordinates (V/2, r).

    ``y = Sigma^-1 U1^T (v - xg)``: the vertices of the zonotope of ``V1^T``.
    """
    check_instance("P", P, Polytope, "pass a zonotope, such as analysis.polytope.")
    svd = P.svd
    y = ((P.vertices - P.center) @ svd.U1) / svd.sigma
    # Vertices come in pairs +-y (none is 0): keep the half on one side of a generic plane.
    side = y @ np.linspace(1.0, 1.5, P.dim)
    half: NDArray[np.float64] = y[side >= 0]
    return half
