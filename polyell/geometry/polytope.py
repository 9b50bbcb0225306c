r"""The exact task-space acceleration polytope (eq. 15), a zonotope."""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.cached import cached_property
from polyell.errors import InputError
from polyell.geometry.cddlib import halfspaces_from_vertices
from polyell.geometry.convex_set import ConvexSet
from polyell.geometry.limits import (
    DirectionalLimits,
    facet_slack,
    line_interval_in_halfspaces,
    rounding_floor,
)
from polyell.geometry.linprog import polytope_limits_lp
from polyell.geometry.subspace import (
    RANK_RTOL,
    AffineSubspace,
    RankRevealingSVD,
    rank_revealing_svd,
)
from polyell.geometry.zonotope import (
    ZonotopeFacets,
    order_polygon,
    unwhiten,
    zonotope_facets,
    zonotope_vertices,
    zonotope_volume,
)
from polyell.validation import check_array, check_magnitudes

__all__ = ["Polytope"]


class Polytope(ConvexSet):
    r"""The zonotope :math:`P = \{ M \tilde\tau + \ddot x_g : \|\tilde\tau\|_\infty \le 1 \}`.

    Eq. (15) of the paper: every end-effector acceleration the arm can produce at rest,
    exactly.  Its generators are the n columns of ``M`` (eq. 14).  When ``rank M = r <
    m`` (a singular configuration, eq. 35) it lies in the r-dimensional affine set
    ``xdd_g + Im(M)``: it is then described by ``A_eq x = b_eq`` together with
    ``A x <= b``, and :attr:`volume` is its r-dimensional volume.

    The facets are enumerated in the whitened coordinates ``y = S^-1 U_1^T (x - xdd_g)`` of
    the SVD ``M = U_1 S V_1^T``, where P is the well-conditioned zonotope ``{V_1^T u}``,
    and mapped back (:func:`~polyell.geometry.zonotope.unwhiten`): exact in number and
    accurate to the data for any ``sigma_min / sigma_max`` above ``rank_rtol`` (DESIGN.md
    section 7, "Thin zonotopes").

    Parameters
    ----------
    generators : array-like, shape (m, n)
        The matrix ``M`` [m/s^2 per unit normalized torque], n >= 1.
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
            if 0 in generators.shape:
                raise InputError(
                    "generators",
                    "an (m, n) matrix with at least one row and one column (generator)",
                    f"shape {generators.shape}",
                    "a polytope with no generators is its centre alone: pass a zero "
                    "column, e.g. np.zeros((m, 1)).",
                )
            center = check_array("center", center, (np.shape(generators)[0],))
            check_magnitudes(generators, center, argument="generators")
        self.generators = np.asarray(generators, dtype=float)
        self.center = np.asarray(center, dtype=float)
        self._svd = svd if svd is not None else rank_revealing_svd(self.generators, rank_rtol)
        self.affine_set = AffineSubspace._from_svd(self.center, self._svd)

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
        """The whitened zonotope's facets (None for a point); A; the half-widths h.

        ``P = {x : A (x - xg) <= h}`` (within the affine set).
        """
        if self.dim == 0:
            return None, np.zeros((0, self.ambient_dim)), np.zeros(0)
        svd = self._svd
        facets = zonotope_facets(svd.V1.T)  # the whitened generators, orthonormal rows
        A, h = unwhiten(facets.normals, facets.offsets, svd.U1, svd.sigma)
        return facets, A, h

    @cached_property
    def _reach(self) -> float:
        """``|xg| + sum |g_i|``: the scale of the rounding floor of :func:`facet_slack`."""
        return float(np.linalg.norm(self.center)) + self._size()

    @property
    def _terms(self) -> int:
        """``m + n + 2``: the terms of the rounding bound of :func:`facet_slack`."""
        return self.ambient_dim + int(self.generators.shape[1]) + 2

    @property
    def A(self) -> NDArray[np.float64]:
        """Unit outward facet normals in task coordinates, shape (F, m)."""
        return self._facets[1]

    @property
    def b(self) -> NDArray[np.float64]:
        """Facet offsets, shape (F,): ``P = {x : A x <= b, A_eq x = b_eq}``."""
        return self._offsets

    @cached_property
    def _offsets(self) -> NDArray[np.float64]:
        return self._facets[2] + self.A @ self.center

    @cached_property
    def vertices(self) -> NDArray[np.float64]:
        """Extreme points, shape (V, m); counter-clockwise when ``dim == 2``."""
        facets = self._facets[0]
        if facets is None:
            return self.center[None, :].copy()
        # Signs decided on the whitened facets, vertices summed from M's own columns.
        signs_times_m = zonotope_vertices(facets, self.generators)
        if self.dim == self.ambient_dim:
            return self.center + signs_times_m
        # In the affine set (M's singular values below the rank threshold dropped); a
        # polygon counter-clockwise in the set's basis.
        reduced = signs_times_m @ self._svd.U1
        if self.dim == 2:
            reduced = order_polygon(reduced)
        return self.center + reduced @ self._svd.U1.T

    @cached_property
    def volume(self) -> float:
        """Volume in the affine set (r-dimensional; 1 for a single point) [(m/s^2)^r].

        ``prod(sigma) vol({V_1^T u})``: the whitened zonotope's determinants are well
        scaled, so no cancellation comes from P's thinness itself; the rounding of the data
        and of the SVD still give relative errors of about eps times the condition number
        of the generators (3e-7 at 8e9, found by the second independent check).
        """
        return float(np.prod(self._svd.sigma)) * zonotope_volume(self._svd.V1.T)

    @cached_property
    def ball_radius(self) -> float:
        """Radius of the largest ball about the centre ``xg`` inside P, in its affine set.

        ``min_i (b_i - a_i . xg)`` over the unit facet normals: the acceleration P allows in
        every direction of its affine set around ``xg`` [m/s^2]; 0 for a single point.
        """
        if self.dim == 0:
            return 0.0
        return float(np.min(self._facets[2]))

    @cached_property
    def origin_radius(self) -> float:
        """Radius of the largest ball about the origin inside P, in its affine set.

        ``min_i b_i``: the acceleration available in every direction from rest against
        gravity [m/s^2].  NaN where the origin is not in P (the arm cannot even keep still)
        or, at a singular configuration, not on its affine set; 0 for the point ``{0}``.
        """
        if not self.contains(np.zeros(self.ambient_dim)):
            return float("nan")
        if self.dim == 0:
            return 0.0
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
        if not isinstance(method, str) or method not in ("zonotope", "cdd"):
            raise InputError(
                "method",
                "'zonotope' or 'cdd'",
                repr(method)[:80],
                "pass method='zonotope' (the default, closed-form facets) or method='cdd'",
            )
        if method == "zonotope":
            return self.A, self.b
        if self.dim == 0:
            return np.zeros((0, self.ambient_dim)), np.zeros(0)
        A_red, b_red = halfspaces_from_vertices(self.affine_set.coordinates(self.vertices))
        A = A_red @ self.affine_set.basis.T
        return A, b_red + A @ self.center

    def _size(self) -> float:
        return float(np.sqrt((self.generators**2).sum(axis=0)).sum())

    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """``A (x - xg) <= h`` grown by :func:`facet_slack` (relative to P's widths)."""
        h = self._facets[2]
        reach = np.linalg.norm(x, axis=-1)[..., None] + self._reach
        return np.all((x - self.center) @ self.A.T <= h + facet_slack(h, reach, self._terms), -1)

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
        if not isinstance(method, str) or method not in ("closed_form", "lp"):
            raise InputError(
                "method",
                "'closed_form' or 'lp'",
                repr(method)[:80],
                "pass method='closed_form' (the default) or method='lp' (the cvxpy reference)",
            )
        if method == "closed_form":
            return super().limits(directions)
        # The same decisions about the affine set as the closed form; LPs on in-set lines.
        return self._limits(
            directions, lambda lines: polytope_limits_lp(self.generators, self.center, lines)
        )

    def _interval_on_lines(
        self, lines: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        # Points of a line near P are within |xg| + size of the origin: reach twice that.
        h = self._facets[2]
        floor = rounding_floor(2.0 * self._reach, self._terms)
        slack = facet_slack(h, 2.0 * self._reach, self._terms)
        return line_interval_in_halfspaces(
            self.A, self.b, lines, slack, floor, reach=2.0 * self._reach
        )
