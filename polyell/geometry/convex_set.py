"""What the polytope and the ellipsoids share: a convex set inside its affine hull."""

from __future__ import annotations

from abc import ABC, abstractmethod
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.geometry.limits import DirectionalLimits
from polyell.geometry.subspace import AffineSubspace
from polyell.validation import check_directions, check_points

__all__ = ["ATOL_RELATIVE", "ConvexSet"]

#: Distance tolerance of membership tests, relative to the set's size.
ATOL_RELATIVE = 1e-9


class ConvexSet(ABC):
    """A compact convex set of the task space, full-dimensional in its affine hull.

    Subclasses set ``center`` (m,) and ``affine_set``, and implement :meth:`_size`,
    :meth:`_inside_hull` and :meth:`_interval_on_lines`.
    """

    center: NDArray[np.float64]
    affine_set: AffineSubspace

    @abstractmethod
    def _size(self) -> float:
        """A length of the order of the set's extent, for :attr:`atol`."""

    @cached_property
    def atol(self) -> float:
        """Membership tolerance: ``ATOL_RELATIVE`` times the larger of the size and ``||c||``."""
        return ATOL_RELATIVE * max(
            self._size(), float(np.linalg.norm(self.center)), np.finfo(float).tiny
        )

    @property
    def ambient_dim(self) -> int:
        """Task-space dimension m."""
        return int(self.center.size)

    @property
    def dim(self) -> int:
        """Dimension r of the set (of its affine hull)."""
        return self.affine_set.dim

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether points belong to the set (within the distance :attr:`atol`).

        Parameters
        ----------
        points : array-like, shape (m,) or (k, m)

        Returns
        -------
        inside : ndarray of bool, shape () or (k,)
        """
        x = check_points("points", points, self.ambient_dim)
        return (self.affine_set.distance(x) <= self.atol) & self._inside_hull(x)

    @abstractmethod
    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Membership of points (..., m) assumed to lie on the affine hull."""

    @abstractmethod
    def _interval_on_lines(
        self, lines: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(lo, hi)`` for unit directions (k, m) whose lines lie in the affine hull."""

    def limits(self, directions: ArrayLike) -> DirectionalLimits:
        """Achievable accelerations ``a`` along unit directions: ``{a : a t in S}``.

        A line ``{a t}`` lying in the affine hull gets the set's own interval; a line
        crossing the hull in one point ``a0 t`` gets ``[a0, a0]`` if that point belongs to
        the set; any other line gets an empty interval.  For a full-dimensional set every
        line is of the first kind.

        Parameters
        ----------
        directions : array-like, shape (m,) or (k, m)
            Unit directions ``t``.

        Returns
        -------
        DirectionalLimits
            ``(lo, hi)`` with the leading shape of ``directions``; NaN where the line
            misses the set.
        """
        directions = check_directions("directions", directions, self.ambient_dim)
        T = np.atleast_2d(directions)
        lo = np.full(T.shape[0], np.nan)
        hi = np.full(T.shape[0], np.nan)
        meeting = self.affine_set.meet_lines(T, self.atol)
        if meeting.inside.any():
            lo[meeting.inside], hi[meeting.inside] = self._interval_on_lines(T[meeting.inside])
        if meeting.single.any():
            a0 = meeting.a0[meeting.single]
            member = self.contains(a0[:, None] * T[meeting.single])
            lo[meeting.single] = np.where(member, a0, np.nan)
            hi[meeting.single] = np.where(member, a0, np.nan)
        shape = directions.shape[:-1]
        return DirectionalLimits(lo.reshape(shape), hi.reshape(shape))
