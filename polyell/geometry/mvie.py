r"""The maximum-volume ellipsoid inscribed in the acceleration polytope.

The polytope :math:`P = \{\ddot x_g + M \tilde\tau : \|\tilde\tau\|_\infty \le 1\}` is
symmetric about :math:`\ddot x_g`, so its maximum-volume inscribed ellipsoid (MVIE) is
centred there and only its shape is unknown.  It is computed in whitened coordinates
:math:`\ddot x = \ddot x_g + U_1 \Sigma y` (eq. 35), where P becomes the zonotope
:math:`\{V_1^T \tilde\tau\}` of orthonormal rows: between the unit ball (the new ellipsoid,
eq. 32/38) and the ball of radius :math:`\sqrt n`, however close the configuration is to a
singular one.  There the shape :math:`X` of :math:`\{X^{1/2} u : \|u\| \le 1\}` solves

.. math::

    \max_X \ \log\det X \quad \text{s.t.} \quad a_i^T X a_i \le h_i^2

over the facet pairs :math:`\pm a_i^T y \le h_i`, and the MVIE is
:math:`\{\ddot x_g + U_1 \Sigma X^{1/2} u\}`.  With n = r generators P is a parallelotope, X =
I, and the MVIE is exactly the new ellipsoid.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.logdet import centred_mvee, centred_mvee_by_cvxpy
from polyell.geometry.polytope import Polytope
from polyell.geometry.zonotope import zonotope_facets
from polyell.validation import check_instance, check_spd

__all__ = [
    "MVIE_GAP",
    "MVIE_METHODS",
    "ellipsoid_from_shape",
    "log_det_shape",
    "max_volume_inscribed_ellipsoid",
]

#: Certified gap in log det of the MVIE (its volume is within a relative MVIE_GAP / 2).
MVIE_GAP = 1e-8

#: ``"logdet"``: the dedicated primal-dual interior-point method of
#: :func:`~polyell.geometry.logdet.centred_mvee` (the default); ``"cvxpy"``: the same
#: program through cvxpy and Clarabel (a cross-check).
MVIE_METHODS = ("logdet", "cvxpy")


def check_method(method: object) -> str:
    """A method of :data:`MVIE_METHODS`, or an InputError naming ``method``."""
    if not isinstance(method, str) or method not in MVIE_METHODS:
        raise InputError(
            "method",
            f"one of {MVIE_METHODS}",
            repr(method)[:80],
            "pass method='logdet' (the default) or method='cvxpy' (a cross-check)",
        )
    return method


def max_volume_inscribed_ellipsoid(
    P: Polytope | HPolytope, method: Literal["logdet", "cvxpy"] = "logdet"
) -> Ellipsoid:
    """The maximum-volume ellipsoid inscribed in ``P``, in ``P``'s affine set.

    Parameters
    ----------
    P : Polytope
    method : {"logdet", "cvxpy"}
        The solver of the log-det program (see :data:`MVIE_METHODS`); both work in the
        whitened coordinates.

    Returns
    -------
    Ellipsoid
        Of kind ``"mvie"``, centred at ``P.center``, touching the boundary of ``P``.  Its
        volume is within a relative 1e-8 of the optimum (the dual certificate of
        ``"logdet"``).

    Raises
    ------
    SolverError
        If the solver does not certify an optimum.
    """
    return fit_ellipsoid(P, method, "mvie", _mvie)


def fit_ellipsoid(
    P: Polytope | HPolytope,
    method: str,
    kind: Literal["mvie", "outer"],
    centred: Callable[[Polytope, str], Ellipsoid],
) -> Ellipsoid:
    """The MVIE or the outer ellipsoid (``kind``) of ``P``, in ``P``'s affine set.

    A zonotope's is ``centred(P, method)``, centred at its centre of symmetry; an
    :class:`HPolytope` has none: its ellipsoid is the free-centre program's.
    """
    check_method(method)
    check_instance("P", P, (Polytope, HPolytope), "pass a set, such as analysis.polytope.")
    if isinstance(P, HPolytope):  # no centre of symmetry: the free-centre programs
        from polyell.geometry.free_center import free_center_mvee, free_center_mvie

        E = free_center_mvie(P) if kind == "mvie" else free_center_mvee(P)
    else:
        E = centred(P, method)
    E.affine_rtol, E.task = P.affine_rtol, P.task
    return E


def _mvie(P: Polytope, method: str) -> Ellipsoid:
    svd, r = P.svd, P.dim
    if r == 0:
        return Ellipsoid(P.center, np.zeros((P.ambient_dim, 0)), np.zeros(0), kind="mvie")
    if P.generators.shape[1] == r:  # a parallelotope: X = I, the new ellipsoid itself
        return Ellipsoid(P.center, svd.U1, svd.sigma, kind="mvie")
    whitened = svd.V1.T  # (r, n), orthonormal rows
    if r == 1:  # a segment: the whole of it
        return Ellipsoid(P.center, svd.U1, svd.sigma * np.abs(whitened).sum(), kind="mvie")
    facets = zonotope_facets(whitened)
    half = len(facets.normals) // 2  # one of each pair +-a: the same constraint
    points = facets.normals[:half] / facets.offsets[:half, None]
    X = log_det_shape(points, method, "the maximum-volume inscribed ellipsoid")
    return ellipsoid_from_shape(P, X, 0.5, "mvie")


def log_det_shape(points: NDArray[np.float64], method: str, what: str) -> NDArray[np.float64]:
    """The shape X of the centred log-det program on ``points`` (N, r) by ``method``."""
    check_method(method)
    if not isinstance(what, str):
        raise InputError(
            "what",
            "a description of the problem (str)",
            repr(what)[:80],
            "pass a str naming the set, e.g. 'the maximum-volume inscribed ellipsoid'",
        )
    if method == "logdet":
        return centred_mvee(points, gap=MVIE_GAP).shape
    return centred_mvee_by_cvxpy(points, what)


def ellipsoid_from_shape(P: Polytope, X: NDArray[np.float64], power: float, kind: str) -> Ellipsoid:
    """``{xg + U1 Sigma X^power u}`` from a whitened shape X (power 1/2: the MVIE, -1/2: outer).

    Axes and semi-axes from the SVD of ``Sigma X^power``.
    """
    check_instance("P", P, Polytope, "pass a zonotope, such as analysis.polytope.")
    X = check_spd("X", X, P.dim, fix="X is the whitened shape of an ellipsoid (positive definite).")
    if isinstance(power, bool) or not isinstance(power, int | float) or not np.isfinite(power):
        raise InputError(
            "power",
            "a finite real exponent (1/2: MVIE, -1/2: outer)",
            repr(power),
            "pass power=0.5 for the MVIE or power=-0.5 for the outer ellipsoid",
        )
    if not isinstance(kind, str):
        raise InputError(
            "kind",
            "the name of the ellipsoid (str)",
            repr(kind)[:80],
            "pass the name as a str, e.g. kind='mvie' or kind='outer'",
        )
    eigenvalues, eigenvectors = np.linalg.eigh(X)
    root = (eigenvectors * eigenvalues**power) @ eigenvectors.T
    W, semi_axes, _ = np.linalg.svd(P.svd.sigma[:, None] * root)
    return Ellipsoid(P.center, P.svd.U1 @ W, semi_axes, kind=kind)
