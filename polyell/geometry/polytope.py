r"""The exact task-space acceleration polytope (eq. 15), a zonotope."""

from __future__ import annotations

from functools import cached_property
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.geometry.cddlib import halfspaces_from_vertices
from polyell.geometry.convex_set import ConvexSet
from polyell.geometry.limits import DirectionalLimits, line_interval_in_halfspaces
from polyell.geometry.linprog import polytope_limits_lp
from polyell.geometry.subspace import (
    RANK_RTOL,
    AffineSubspace,
    RankRevealingSVD,
    rank_revealing_svd,
)
from polyell.geometry.zonotope import (
    ZonotopeFacets,
    zonotope_facets,
    zonotope_vertices,
    zonotope_volume,
)
from polyell.validation import check_array

__all__ = ["Polytope"]


class Polytope(ConvexSet):
    r"""The zonotope :math:`P = \{ M \tilde\tau + \ddot x_g : \|\tilde\tau\|_\infty \le 1 \}`.

    Eq. (15) of the paper: every end-effector acceleration the arm can produce at rest,
    exactly.  Its generators are the n columns of ``M`` (eq. 14).  When ``rank M = r <
    m`` (a singular configuration, eq. 35) it lies in the r-dimensional affine set
    ``xdd_g + Im(M)``: it is then described by ``A_eq x = b_eq`` together with
    ``A x <= b``, and :attr:`volume` is its r-dimensional volume.

    Parameters
    ----------
    generators : array-like, shape (m, n)
        The matrix ``M`` [m/s^2 per unit normalized torque].
    center : array-like, shape (m,)
        The centre ``xdd_g`` [m/s^2].
    rank_rtol : float, optional
        Singular values of ``M`` at or below ``rank_rtol * sigma_max`` count as zero.
    svd : RankRevealingSVD, optional
        A decomposition of ``M`` already computed with the same tolerance (used by
        :class:`~polyell.Analysis` so that polytope and ellipsoid share one rank decision).

    Examples
    --------
    >>> import polyell as pe
    >>> P = pe.Polytope([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], center=[0.0, -1.0])
    >>> P.dim, round(P.volume, 12)
    (2, 12.0)
    """

    def __init__(
        self,
        generators: ArrayLike,
        center: ArrayLike,
        *,
        rank_rtol: float = RANK_RTOL,
        svd: RankRevealingSVD | None = None,
    ) -> None:
        if svd is None:  # a user's input; an Analysis passes its own clean arrays
            generators = check_array("generators", generators, ("m", "n"))
            center = check_array("center", center, (np.shape(generators)[0],))
        self.generators = np.asarray(generators, dtype=float)
        self.center = np.asarray(center, dtype=float)
        self._svd = svd if svd is not None else rank_revealing_svd(self.generators, rank_rtol)
        self.affine_set = AffineSubspace.from_svd(self.center, self._svd)
        # The generators in the affine set's coordinates, (r, n): M itself at full rank.
        self._coordinate_generators = (
            self.generators
            if self.dim == self.ambient_dim
            else self.affine_set.basis.T @ self.generators
        )

    @property
    def svd(self) -> RankRevealingSVD:
        """The rank-revealing SVD of the generators (eq. 35) behind :attr:`dim`."""
        return self._svd

    def __repr__(self) -> str:
        return (
            f"Polytope(m={self.ambient_dim}, n={self.generators.shape[1]}, dim={self.dim}, "
            f"facets={self.A.shape[0]}, volume={self.volume:.6g})"
        )

    @cached_property
    def _facets(
        self,
    ) -> tuple[ZonotopeFacets | None, NDArray[np.float64], NDArray[np.float64]]:
        """The zonotope's facets in the affine set's coordinates (None for a point); A; b."""
        if self.dim == 0:
            return None, np.zeros((0, self.ambient_dim)), np.zeros(0)
        facets = zonotope_facets(self._coordinate_generators)
        if self.dim == self.ambient_dim:  # the basis is the identity
            A = facets.normals
        else:
            A = facets.normals @ self.affine_set.basis.T
        return facets, A, facets.offsets + A @ self.center

    @property
    def A(self) -> NDArray[np.float64]:
        """Unit outward facet normals in task coordinates, shape (F, m)."""
        return self._facets[1]

    @property
    def b(self) -> NDArray[np.float64]:
        """Facet offsets, shape (F,): ``P = {x : A x <= b, A_eq x = b_eq}``."""
        return self._facets[2]

    @property
    def A_eq(self) -> NDArray[np.float64]:
        """Equality normals, shape (m - r, m); empty when P is full-dimensional."""
        return self.affine_set.equalities[0]

    @property
    def b_eq(self) -> NDArray[np.float64]:
        """Equality right-hand sides, shape (m - r,)."""
        return self.affine_set.equalities[1]

    @cached_property
    def vertices(self) -> NDArray[np.float64]:
        """Extreme points, shape (V, m); counter-clockwise when ``dim == 2``."""
        facets = self._facets[0]
        if facets is None:
            return self.center[None, :].copy()
        reduced = zonotope_vertices(facets)
        if self.dim == self.ambient_dim:
            return self.center + reduced
        return self.center + reduced @ self.affine_set.basis.T

    @cached_property
    def volume(self) -> float:
        """Volume in the affine set (r-dimensional; 1 for a single point) [(m/s^2)^r]."""
        return zonotope_volume(self._coordinate_generators)

    @cached_property
    def ball_radius(self) -> float:
        """Radius of the largest ball about the centre ``xg`` inside P, in its affine set.

        ``min_i (b_i - a_i . xg)`` over the unit facet normals: the acceleration P allows in
        every direction of its affine set around ``xg`` [m/s^2]; 0 for a single point.
        """
        if self.dim == 0:
            return 0.0
        return float(np.min(self.b - self.A @ self.center))

    @cached_property
    def origin_radius(self) -> float:
        """Radius of the largest ball about the origin inside P, in its affine set.

        ``min_i b_i``: the acceleration available in every direction from rest against
        gravity [m/s^2].  NaN where the origin is not in P (the arm cannot even keep still)
        or, at a singular configuration, not on its affine set.
        """
        if self.dim == 0 or not self.contains(np.zeros(self.ambient_dim)):
            return float("nan")
        return float(max(0.0, np.min(self.b)))

    def halfspaces(
        self, method: Literal["zonotope", "cdd"] = "zonotope"
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Facets ``(A, b)`` in task coordinates by the chosen method.

        Parameters
        ----------
        method : {"zonotope", "cdd"}
            ``"zonotope"``: the closed-form facets (the default, :attr:`A`, :attr:`b`).
            ``"cdd"``: pycddlib's V-to-H conversion of :attr:`vertices`, within the
            affine set.  Both describe the same set; the rows may come in another order.

        Returns
        -------
        A : ndarray, shape (F, m)
        b : ndarray, shape (F,)
        """
        if method == "zonotope":
            return self.A, self.b
        if method != "cdd":
            raise InputError("method", "'zonotope' or 'cdd'", repr(method))
        if self.dim == 0:
            return np.zeros((0, self.ambient_dim)), np.zeros(0)
        A_red, b_red = halfspaces_from_vertices(self.affine_set.coordinates(self.vertices))
        A = A_red @ self.affine_set.basis.T
        return A, b_red + A @ self.center

    def _size(self) -> float:
        return float(np.sqrt((self.generators**2).sum(axis=0)).sum())

    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        return np.all(x @ self.A.T <= self.b + self.atol, axis=-1)

    def limits(
        self, directions: ArrayLike, method: Literal["closed_form", "lp"] = "closed_form"
    ) -> DirectionalLimits:
        """Achievable accelerations ``a`` along unit directions: ``{a : a t in P}``.

        Parameters
        ----------
        directions : array-like, shape (m,) or (k, m)
            Unit directions ``t``.
        method : {"closed_form", "lp"}
            ``"closed_form"``: each line against every facet (fast, the default).
            ``"lp"``: two linear programs per direction in the normalized-torque space,
            solved by cvxpy with Clarabel (the reference; slow).

        Returns
        -------
        DirectionalLimits
            ``(lo, hi)`` of the leading shape of ``directions``; NaN where the line
            misses P.
        """
        if method == "closed_form":
            return super().limits(directions)
        if method != "lp":
            raise InputError("method", "'closed_form' or 'lp'", repr(method))
        # The same decisions about the affine set as the closed form; LPs on in-set lines.
        return self._limits(
            directions, lambda lines: polytope_limits_lp(self.generators, self.center, lines)
        )

    def _interval_on_lines(
        self, lines: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return line_interval_in_halfspaces(self.A, self.b, lines, self.atol)
