"""What the polytope and the ellipsoids share: a convex set inside its affine hull."""

from __future__ import annotations

import warnings
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.cached import cached_property
from polyell.errors import InputError, ProjectedInputWarning
from polyell.geometry.limits import ATOL_RELATIVE, DirectionalLimits
from polyell.geometry.subspace import AFFINE_RTOL, AffineSubspace
from polyell.validation import check_directions, check_points

__all__ = ["ATOL_RELATIVE", "BARE_ROWS", "ConvexSet"]

#: The rows a named direction of a set built from arrays is read against (m <= 3).
BARE_ROWS = ("x", "y", "z")
#: A projected direction that moved by more than this is reported (rounding is not).
PROJECTION_NOTICE = 1e-12


class ConvexSet(ABC):
    """A compact convex set of the task space, full-dimensional in its affine hull.

    Subclasses set ``center`` (m,) and ``affine_set``, and implement :meth:`_size`,
    :meth:`_inside_hull` and :meth:`_interval_on_lines`.
    """

    center: NDArray[np.float64]
    affine_set: AffineSubspace
    #: :data:`~polyell.AFFINE_RTOL` unless set: the tolerance of "on the affine set".
    affine_rtol: float = AFFINE_RTOL
    _task: tuple[str, ...] | None = None

    @property
    def task(self) -> tuple[str, ...] | None:
        """The names of the task rows (``("x", "z")``), or None (unset: a set built from arrays).

        :meth:`limits` reads a named direction (``"z"``, ``"-x"``, ``"xy"``) against them;
        a set without them reads names against ``x, y, z`` when ``m <= 3`` and refuses
        them otherwise.  Set it to the analysis's rows (``S.task = analysis.task``): m
        distinct names (:func:`~polyell.models.task.check_task`), or None.
        """
        return self._task

    @task.setter
    def task(self, rows: Sequence[str] | None) -> None:
        from polyell.models.task import check_task  # (models import geometry)

        self._task = None if rows is None else check_task(rows, self.ambient_dim)

    def _direction_rows(self, directions: object) -> tuple[str, ...]:
        """The row names a named direction is read against (:attr:`task`, or x, y, z)."""
        if self._task is not None:
            return self._task
        m = self.ambient_dim
        if m <= len(BARE_ROWS):
            return BARE_ROWS[:m]
        shown = repr(directions)
        raise InputError(
            "directions",
            f"unit vectors of {m} entries: this {m}-dimensional set has no task row names "
            "to read a named direction against (a set built from arrays knows x, y, z "
            "only up to m = 3)",
            shown if len(shown) <= 60 else f"{shown[:57]}...",
            "give the unit vector, or set the set's row names first, e.g. "
            "S.task = analysis.task (('x', 'y', 'z', 'wx', 'wy', 'wz') for a frame).",
        )

    @abstractmethod
    def _size(self) -> float:
        """A length of the order of the set's extent, for :attr:`atol`."""

    @cached_property
    def atol(self) -> float:
        """An absolute length: ``ATOL_RELATIVE`` times the larger of the size and ``||c||``.

        A distance below which two points of the set's scale are the same (a centre off
        the affine set, a projection worth a warning).  Membership is decided relative to
        the set itself instead (:data:`ATOL_RELATIVE`): an absolute slack at every facet
        would widen a thin set far beyond itself at its sharp tips.
        """
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

    @property
    def A_eq(self) -> NDArray[np.float64]:
        """Equality normals of the affine hull, shape (m - r, m); empty when full-dimensional."""
        return self.affine_set.equalities[0]

    @property
    def b_eq(self) -> NDArray[np.float64]:
        """Equality right-hand sides, shape (m - r,): the hull is ``A_eq x = b_eq``."""
        return self.affine_set.equalities[1]

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether points belong to the set.

        A point counts as lying in the affine set within :data:`~polyell.AFFINE_RTOL`
        (rounded input, see :attr:`affine_rtol`) and inside the set when it is inside the
        set grown by ``1 + ATOL_RELATIVE`` about its centre (a tolerance relative to the
        set's width in every direction), plus the rounding floor of evaluating the facets in
        double precision, ``(m + n + 2) eps (|x| + |c| + sum_i |g_i|)``
        (:func:`~polyell.geometry.limits.facet_slack`).  For a thin set the floor dominates:
        relative to its width along a thin facet normal it is about ``(m + n + 2) eps``
        times the condition number of the generators (some 2.5e-6 of the thin width at
        condition number 1e9, 1e-8 at 1e7).

        Parameters
        ----------
        points : array-like, shape (m,) or (k, m)

        Returns
        -------
        inside : ndarray of bool, shape () or (k,)
        """
        x = check_points("points", points, self.ambient_dim)
        return self.affine_set.near(x, self.affine_rtol, self._size()) & self._inside_hull(x)

    @abstractmethod
    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Membership of points (..., m), tested on their projection onto the affine hull."""

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
        line is of the first kind.  A direction within :attr:`affine_rtol` of the affine
        hull (a rounded one) is projected onto it, with a :class:`ProjectedInputWarning`.

        Parameters
        ----------
        directions : str, array-like of shape (m,) or (k, m), or list of both
            Unit directions ``t``, or names of the task rows
            (:func:`~polyell.comparison.directions.named_direction`): ``"z"``, ``"-x"``,
            ``"xy"`` (the unit diagonal), ``["x", "wz"]``; read against :attr:`task`
            (``x, y, z`` for a set built from arrays with ``m <= 3``).

        Returns
        -------
        DirectionalLimits
            ``(lo, hi)`` with the leading shape of ``directions`` (a name is one
            direction, a list of k names or vectors has shape (k,)); NaN where the line
            misses the set.

        Raises
        ------
        InputError
            Naming ``directions``: a vector of the wrong size or not of unit length, a
            name with a row the task does not have (the message lists the rows), or any
            name for a set of more than 3 rows without :attr:`task`.
        """
        return self._limits(directions, self._interval_on_lines)

    def _limits(
        self,
        directions: ArrayLike,
        interval_on_lines: Callable[
            [NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]
        ],
    ) -> DirectionalLimits:
        """:meth:`limits`, with the interval on in-set lines computed by ``interval_on_lines``."""
        # (directions come after geometry in the import order: read here, when called)
        from polyell.comparison.directions import direction_vectors, has_names

        if has_names(directions):
            rows = self._direction_rows(directions)
            directions = direction_vectors(directions, rows, "directions")
        else:
            directions = check_directions("directions", directions, self.ambient_dim)
        T = np.atleast_2d(directions)
        lo = np.full(T.shape[0], np.nan)
        hi = np.full(T.shape[0], np.nan)
        meeting = self.affine_set._meet_lines(T, self.affine_rtol, self._size())
        if meeting.inside.any():
            lines = meeting.projected[meeting.inside]
            moved = np.linalg.norm(lines - T[meeting.inside], axis=1)
            if moved.max() > PROJECTION_NOTICE:
                warnings.warn(
                    f"directions: {np.count_nonzero(moved > PROJECTION_NOTICE)} direction(s) "
                    f"up to {moved.max():.2g} off the {self.dim}-dimensional affine set of "
                    "this singular configuration were taken as rounded and projected onto "
                    f"it (affine_rtol = {self.affine_rtol:g}).",
                    ProjectedInputWarning,
                    stacklevel=3,
                )
            lo[meeting.inside], hi[meeting.inside] = interval_on_lines(lines)
        if meeting.single.any():
            a0 = meeting.a0[meeting.single]
            member = self._inside_hull(a0[:, None] * T[meeting.single])
            lo[meeting.single] = np.where(member, a0, np.nan)
            hi[meeting.single] = np.where(member, a0, np.nan)
        shape = directions.shape[:-1]
        return DirectionalLimits(lo.reshape(shape), hi.reshape(shape))
