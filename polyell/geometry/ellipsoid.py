r"""Ellipsoids in the task space, possibly degenerate (eq. 16-24, 38)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import null_space
from scipy.special import gammaln

from polyell.cached import cached_property
from polyell.errors import InputError
from polyell.geometry.convex_set import ConvexSet
from polyell.geometry.limits import (
    ATOL_RELATIVE,
    DirectionalLimits,
    line_interval_in_ellipsoids,
)
from polyell.geometry.subspace import AffineSubspace
from polyell.validation import (
    MAX_DIRECTIONS,
    check_array,
    check_integer,
    check_points,
    magnitude_limit,
)

__all__ = ["Ellipsoid", "canonical_axes", "unit_ball_volume"]


def canonical_axes(
    axes: NDArray[np.float64], semi_axes: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Axes (..., m, r) and semi-axes (..., r) as an :class:`Ellipsoid` keeps them.

    Semi-axes in descending order (a stable sort) and each axis flipped so that its
    largest-magnitude entry is positive: one ellipsoid, one representation, so that points
    mapped into it (the quasi-Monte-Carlo points of a coverage) do not depend on how its
    axes were computed.  Works on one ellipsoid or a batch.
    """
    axes = _as_float_array(
        "axes", axes, "an array of axes, shape (..., m, r)", 2, "np.eye(2) (columns: the axes)"
    )
    semi_axes = _as_float_array(
        "semi_axes", semi_axes, "an array of semi-axes, shape (..., r)", 1, "[2.0, 1.0]"
    )
    if axes.shape[:-2] + axes.shape[-1:] != semi_axes.shape:
        raise InputError(
            "semi_axes",
            f"shape {axes.shape[:-2] + axes.shape[-1:]} (one per column of axes {axes.shape})",
            f"shape {semi_axes.shape}",
            "give one semi-axis per axis.",
        )
    if axes.size == 0:
        return axes, semi_axes
    order = np.argsort(-semi_axes, axis=-1, kind="stable")
    semi_axes = np.take_along_axis(semi_axes, order, axis=-1)
    axes = np.take_along_axis(axes, order[..., None, :], axis=-1)
    pivot_rows = np.argmax(np.abs(axes), axis=-2)[..., None, :]
    pivots = np.take_along_axis(axes, pivot_rows, axis=-2)
    return axes * np.where(pivots < 0, -1.0, 1.0), semi_axes


def _as_float_array(
    name: str, value: object, expected: str, ndim: int, example: str
) -> NDArray[np.float64]:
    """``value`` as a float array of at least ``ndim`` dimensions (NaN kept), or an InputError.

    ``example`` shows a valid value in the error's fix.
    """
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(
            name,
            expected,
            f"{type(value).__name__} {value!r:.80}",
            f"pass {name} as an array of real numbers, e.g. {example}",
        ) from None
    if array.ndim < ndim:
        raise InputError(
            name,
            expected,
            f"shape {array.shape}",
            f"pass {name} with at least {ndim} dimension(s), e.g. {example}",
        )
    return array


def unit_ball_volume(r: int) -> float:
    """Volume of the unit ball in R^r: ``pi^(r/2) / Gamma(r/2 + 1)``.

    Parameters
    ----------
    r : int
        Dimension, from 0 (a point: 1) to 1,000,000.
    """
    r = check_integer("r", r, 0, MAX_DIRECTIONS)
    return float(np.exp(0.5 * r * np.log(np.pi) - gammaln(0.5 * r + 1)))


class Ellipsoid(ConvexSet):
    r"""The ellipsoid :math:`\{ c + U \operatorname{diag}(s)\, u : \|u\| \le 1 \}`.

    Equivalently :math:`(\ddot x - c)^T N (\ddot x - c) \le 1` with the core
    :math:`N = U \operatorname{diag}(s)^{-2} U^T`, restricted to the affine set
    :math:`c + \operatorname{Im}(U)` when the rank ``r`` is below ``m`` (eq. 38): then it
    is degenerate (a segment, a disc, ...) and :attr:`volume` is its r-dimensional volume.

    Parameters
    ----------
    center : array-like, shape (m,)
        Centre ``c`` [m/s^2].
    axes : array-like, shape (m, r)
        Orthonormal principal axes ``U`` (columns).
    semi_axes : array-like, shape (r,)
        Strictly positive semi-axis lengths ``s`` [m/s^2], any order (sorted descending).
    kind : str, optional
        The definition it comes from (``"chiacchio"``, ``"yoshikawa"``, ...), for display.

    Examples
    --------
    >>> import polyell as pe
    >>> E = pe.Ellipsoid(center=[0.0, 0.0], axes=[[1.0, 0.0], [0.0, 1.0]], semi_axes=[2.0, 1.0])
    >>> E.limits([1.0, 0.0])
    DirectionalLimits(lo=array(-2.), hi=array(2.))
    """

    def __init__(
        self, center: ArrayLike, axes: ArrayLike, semi_axes: ArrayLike, *, kind: str = "custom"
    ) -> None:
        self.center = check_array("center", center, (None,))
        m = self.center.size
        U = check_array("axes", axes, (m, None))
        s = check_array("semi_axes", semi_axes, (U.shape[1],))
        if np.any(s <= 0):
            raise InputError(
                "semi_axes", "strictly positive lengths", f"{s}", "drop axes of zero length."
            )
        # The bound of check_magnitudes: volumes (products of r semi-axes) and the squares
        # of eq. (23) stay representable.
        limit = magnitude_limit(m) if m else 1
        for name, sizes in (("semi_axes", s), ("center", np.abs(self.center))):
            outside = (sizes > 10.0**limit) | ((sizes > 0) & (sizes < 10.0**-limit))
            if outside.any():
                raise InputError(
                    name,
                    f"lengths within 1e-{limit}..1e{limit} in a {m}-dimensional space, so "
                    "that volumes stay representable",
                    f"{sizes[np.argmax(outside)]:.3g}",
                    "express the task in other units.",
                )
        # (orthonormal columns have entries of at most 1: larger ones are refused before
        # U^T U, which could overflow)
        big = max(1.0, float(np.max(np.abs(U)))) if U.size else 1.0
        if big > 1.0 + 1e-9 or not np.allclose(U.T @ U, np.eye(U.shape[1]), atol=1e-9):
            if big > 1.0 + 1e-9:
                got = f"an entry of size {big:.3g}"
            else:
                off = np.max(np.abs(U.T @ U - np.eye(U.shape[1])))
                got = f"U^T U - I with max |entry| {off:.3g}"
            raise InputError(
                "axes",
                "orthonormal columns",
                got,
                "orthonormalise the axes, e.g. with an SVD.",
            )
        self.axes, self.semi_axes = canonical_axes(U, s)
        self.kind = kind
        if self.rank == m:
            basis, normals = np.eye(m), np.zeros((m, 0))
        else:
            basis = self.axes
            normals = null_space(self.axes.T) if self.rank else np.eye(m)
        self.affine_set = AffineSubspace(point=self.center, basis=basis, normals=normals)

    @classmethod
    def from_core(cls, center: ArrayLike, core: ArrayLike, *, kind: str = "custom") -> Ellipsoid:
        """The full-dimensional ellipsoid ``(x - c)^T N (x - c) <= 1`` of a positive-definite N.

        Parameters
        ----------
        center : array-like, shape (m,)
        core : array-like, shape (m, m)
            Symmetric positive-definite core ``N`` [(m/s^2)^-2].
        kind : str, optional
        """
        c = check_array("center", center, (None,))
        N = check_array("core", core, (c.size, c.size))
        eigenvalues, eigenvectors = np.linalg.eigh(0.5 * (N + N.T))
        if eigenvalues[0] <= 0:
            raise InputError(
                "core",
                "a positive-definite core",
                f"smallest eigenvalue {eigenvalues[0]:.3g}",
                "pass a symmetric positive-definite N, e.g. np.diag([4.0, 1.0]); a flat "
                "ellipsoid takes its axes: Ellipsoid(center, axes, semi_axes)",
            )
        return cls(c, eigenvectors, 1.0 / np.sqrt(eigenvalues), kind=kind)

    def __repr__(self) -> str:
        return (
            f"Ellipsoid(kind={self.kind!r}, center={np.round(self.center, 6).tolist()}, "
            f"semi_axes={np.round(self.semi_axes, 6).tolist()}, rank={self.rank})"
        )

    @property
    def rank(self) -> int:
        """Number r of principal axes of non-zero length (its dimension)."""
        return int(self.semi_axes.size)

    @cached_property
    def core(self) -> NDArray[np.float64]:
        """Core ``N = U diag(s)^-2 U^T``, shape (m, m), semidefinite when ``rank < m``."""
        return (self.axes / self.semi_axes**2) @ self.axes.T

    @cached_property
    def volume(self) -> float:
        """Volume in its affine set: ``V_r prod(s)`` (1 for a single point)."""
        return unit_ball_volume(self.rank) * float(np.prod(self.semi_axes))

    def support(self, normals: ArrayLike) -> NDArray[np.float64]:
        """Support function ``max_{x in E} a . x = a . c + ||diag(s) U^T a||``.

        Parameters
        ----------
        normals : array-like, shape (m,) or (k, m)

        Returns
        -------
        ndarray, shape () or (k,)
        """
        a = check_points("normals", normals, self.ambient_dim)
        return a @ self.center + np.linalg.norm((a @ self.axes) * self.semi_axes, axis=-1)

    def boundary_curve(self, count: int, *, closed: bool = False) -> NDArray[np.float64]:
        """Points on the boundary of a rank-1 or rank-2 ellipsoid, for drawing and meshes.

        Parameters
        ----------
        count : int
            Points of a rank-2 boundary, at evenly spaced angles from the first axis.
        closed : bool, optional
            Repeat the first point at the end (a curve to draw).

        Returns
        -------
        ndarray, shape (count, m) (count + 1 closed), or (2, m) for a segment's end points

        Raises
        ------
        InputError
            For another rank, or a count that is not an integer from 2 to 1,000,000.
        """
        count = check_integer("count", count, 2, MAX_DIRECTIONS)
        if not isinstance(closed, bool | np.bool_):
            raise InputError(
                "closed",
                "True or False",
                repr(closed),
                "pass closed=True to repeat the first point at the end, or closed=False",
            )
        if self.rank == 1:
            return self.center + np.outer([-1.0, 1.0], self.semi_axes[0] * self.axes[:, 0])
        if self.rank != 2:
            raise InputError(
                "ellipsoid",
                "a rank-1 or rank-2 ellipsoid",
                f"rank {self.rank}",
                "use E.center for a single point"
                if self.rank == 0
                else "draw it as a surface with polyell.export.mesh(E) instead"
                if self.rank == 3 and self.ambient_dim == 3
                else "evaluate its extent along chosen directions with E.limits(directions)",
            )
        angles = 2.0 * np.pi * np.arange(count) / count
        circle = np.column_stack([np.cos(angles), np.sin(angles)])
        curve: NDArray[np.float64] = self.center + (circle * self.semi_axes) @ self.axes.T
        return np.vstack([curve, curve[:1]]) if closed else curve

    def _size(self) -> float:
        return float(self.semi_axes.sum())

    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whitened radius ``|diag(s)^-1 U^T (x - c)| <= 1 + ATOL_RELATIVE + floor``.

        The set grown by ``1 + ATOL_RELATIVE`` about its centre (relative along every axis,
        as :func:`~polyell.geometry.limits.facet_slack` grows a polytope), plus a floor that
        bounds the rounding error of the radius.  The point and the centre carry errors of
        ``eps |x|`` and ``eps |c|``; ``x - c`` adds ``eps |x - c|``, the product with ``U``
        (m terms) ``m eps |x - c|`` (first-order ``gamma_m``, Higham, section 3.1), so each
        whitened coordinate errs by at most ``(m + 1) eps (|x| + |c|) / s_min`` plus
        ``eps |u_i|`` for the division, and the norm of r terms adds ``(r + 1) eps``
        relative.  Near the boundary (radius 1, and ``|x - c| / s_min >= 1``) all of it is
        below ``(m + r + 3) eps (|x| + |c|) / s_min``.  It is scale-free (units cancel) and,
        for a set near the origin, about ``eps`` whatever its condition number: a point
        ``1 + 1e-6`` times the thinnest semi-axis from the centre is outside even at
        ``s_max / s_min = 1e9`` (an absolute slack ``atol / s_min`` would grow that axis by
        ``1e-9 * s_max / s_min``).
        """
        u = ((x - self.center) @ self.axes) / self.semi_axes
        radius = np.linalg.norm(u, axis=-1)
        if not self.rank:
            return radius <= 1.0
        m, r = self.ambient_dim, self.rank
        size = np.linalg.norm(x, axis=-1) + np.linalg.norm(self.center)
        floor = (m + r + 3) * np.finfo(float).eps * size / self.semi_axes[-1]
        inside: NDArray[np.bool_] = radius <= 1.0 + ATOL_RELATIVE + floor
        return inside

    def limits(self, directions: ArrayLike) -> DirectionalLimits:
        """Achievable accelerations along unit directions, eq. (23)-(24).

        On lines in the ellipsoid's affine set, the roots of eq. (23) give the interval
        (24); a degenerate ellipsoid meets any other line in at most one point, tested
        directly (see :meth:`ConvexSet.limits`).

        Parameters
        ----------
        directions : str, array-like of shape (m,) or (k, m), or list of both
            Unit directions ``t``, or names of the task rows (``"z"``, ``"-x"``, ``"xy"``)
            read against :attr:`task`, as :meth:`ConvexSet.limits`.

        Returns
        -------
        DirectionalLimits
            NaN where the line misses the ellipsoid.
        """
        return super().limits(directions)

    def _interval_on_lines(
        self, lines: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Eq. (23)-(24) on lines in the affine set, from the factors ``(U, s)``.

        For a degenerate ellipsoid, lines that leave the affine set are handled by
        :meth:`limits` directly: eq. (23) alone would be wrong there because N is only
        semidefinite.
        """
        lo, hi = line_interval_in_ellipsoids(
            self.center[None], self.axes[None], self.semi_axes[None], lines
        )
        return lo[0], hi[0]
