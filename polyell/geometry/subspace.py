r"""Rank decisions and the affine set that holds a degenerate polytope or ellipsoid.

At a singular configuration (eq. 35) ``M = U_1 \Sigma V_1^T`` has rank ``r < m`` and both
the polytope (15) and the ellipsoid (38) lie in the ``r``-dimensional affine set
``xdd_g + Im(M) = xdd_g + Im(U_1)``.  One rank decision, made here, is shared by every
object built from the same ``M`` so that they always agree on the dimension.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from polyell.errors import SolverError
from polyell.validation import ROUNDED_INPUT_RTOL, check_array, check_fraction, check_points

__all__ = [
    "AFFINE_RTOL",
    "RANK_RTOL",
    "AffineSubspace",
    "LineMeeting",
    "RankRevealingSVD",
    "rank_revealing_svd",
    "scaled_norm",
]

#: Singular values at or below ``RANK_RTOL * sigma_max`` count as zero (eq. 35).
RANK_RTOL = 1e-10
#: "On the affine set" at a singular configuration, for input rounded to 5-7 significant
#: digits (a direction or a point typed from a paper or a log): a unit direction whose
#: component off the set (the sine of its angle to it) is at most ``AFFINE_RTOL`` lies in it,
#: and so does a point at a distance of at most ``AFFINE_RTOL * max(|x|, |xg|)``.  Relative
#: to the point and the centre, not to a set's extent, so that the polytope and every
#: ellipsoid of one analysis decide alike.  ``pe.analyze(..., affine_rtol=...)`` sets it.
#: It is the rounded-input rule of :data:`polyell.validation.ROUNDED_INPUT_RTOL`, which also
#: bounds a direction's unit norm: one tolerance for typed input.
AFFINE_RTOL = ROUNDED_INPUT_RTOL


class RankRevealingSVD(NamedTuple):
    """The singular value decomposition of eq. (35), split at the numerical rank.

    Attributes
    ----------
    U1 : ndarray, shape (m, r)
        Orthonormal basis of ``Im(M)``.
    U2 : ndarray, shape (m, m - r)
        Orthonormal basis of ``Im(M)^perp``.
    sigma : ndarray, shape (r,)
        The non-zero singular values, descending.
    V1 : ndarray, shape (n, r)
        Orthonormal basis of ``Ker(M)^perp``.
    singular_values : ndarray, shape (min(m, n),)
        All singular values, including those counted as zero.
    rtol : float
        The relative tolerance used for the rank decision.
    """

    U1: NDArray[np.float64]
    U2: NDArray[np.float64]
    sigma: NDArray[np.float64]
    V1: NDArray[np.float64]
    singular_values: NDArray[np.float64]
    rtol: float

    @property
    def rank(self) -> int:
        """Numerical rank ``r``."""
        return int(self.sigma.size)

    def pinv(self) -> NDArray[np.float64]:
        """The generalized inverse ``V_1 Sigma^-1 U_1^T`` of eq. (37), shape (n, m)."""
        return (self.V1 / self.sigma) @ self.U1.T


def scaled_norm(x: NDArray[np.float64], axis: int = -1) -> NDArray[np.float64]:
    """Euclidean norms along ``axis`` without underflow or overflow of the squares.

    ``numpy.linalg.norm`` squares the entries: vectors of entries below about 1e-154 get
    norm 0 (and above 1e154, inf). Here each vector is divided by its largest entry first.
    """
    if not isinstance(x, np.ndarray) or x.dtype != np.float64:
        x = check_array("x", x, (None,) * max(1, np.ndim(x)))
    size = np.max(np.abs(x), axis=axis, keepdims=True, initial=0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(size > 0, x / np.where(size > 0, size, 1.0), 0.0)
    norms: NDArray[np.float64] = np.squeeze(size, axis=axis) * np.linalg.norm(unit, axis=axis)
    return norms


def rank_revealing_svd(
    M: NDArray[np.float64], rtol: float = RANK_RTOL, rank: int | None = None
) -> RankRevealingSVD:
    """Decompose ``M`` (eq. 35) and decide its numerical rank.

    Parameters
    ----------
    M : ndarray, shape (m, n)
        The matrix.
    rtol : float, optional
        Singular values ``<= rtol * sigma_max`` are treated as zero.  A zero matrix has
        rank 0.
    rank : int, optional
        A rank decided elsewhere (the same set seen through another matrix: a force
        polytope's rows normalized, the rank of ``J``), used instead of ``rtol`` (at most
        the number of non-zero singular values).

    Returns
    -------
    RankRevealingSVD

    Raises
    ------
    InputError
        If ``rtol`` is not in ``[0, 1)``.
    """
    rtol = check_fraction("rank_rtol", rtol)
    if not isinstance(M, np.ndarray) or M.ndim != 2 or M.dtype != np.float64:
        M = check_array("M", M, ("m", "n"))
    m, n = M.shape
    # (an int flag: f2py converts a bool far more slowly)
    U, s, Vt, info = lapack.dgesdd(M, full_matrices=int(m > n))  # U is square either way
    if info != 0:
        raise SolverError(f"The SVD of M (eq. 35) did not converge: LAPACK dgesdd info={info}.")
    values = s.tolist()  # a few numbers: counted in Python, without numpy's per-call cost
    positive = sum(value > 0 for value in values)
    if rank is None:
        rank = sum(value > rtol * values[0] for value in values) if values and values[0] > 0 else 0
    rank = min(rank, positive)
    return RankRevealingSVD(
        U1=U[:, :rank],
        U2=U[:, rank:],
        sigma=s[:rank],
        V1=Vt[:rank].T,
        singular_values=s,
        rtol=rtol,
    )


@lru_cache(maxsize=16)
def _whole_space(m: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The identity basis and the empty normal basis of R^m (cached, read-only)."""
    basis, normals = np.eye(m), np.zeros((m, 0))
    basis.flags.writeable = normals.flags.writeable = False
    return basis, normals


class LineMeeting(NamedTuple):
    """How the lines ``{a t}`` through the origin meet an affine set.

    Attributes
    ----------
    inside : ndarray of bool, shape (k,)
        The whole line lies in the set, within the tolerance (it is parallel to it and the
        set contains 0).
    single : ndarray of bool, shape (k,)
        The line crosses the set in exactly one point ``a = a0``.
    a0 : ndarray, shape (k,)
        The crossing parameter where ``single`` is true, NaN elsewhere.
    projected : ndarray, shape (k, m)
        The directions projected onto the set and renormalised where ``inside`` (the line
        then lies in it exactly), the directions themselves elsewhere.
    """

    inside: NDArray[np.bool_]
    single: NDArray[np.bool_]
    a0: NDArray[np.float64]
    projected: NDArray[np.float64]


#: An affine set offset from the origin by at most this share of its set's extent passes
#: through the origin (the rounding of a computed centre, e.g. an MVIE's of a segment on an
#: axis), whatever ``rtol``: :meth:`AffineSubspace.near` and the lines of ``limits``.
OFFSET_RTOL = 1e-12


@dataclass(frozen=True)
class AffineSubspace:
    """The affine set ``point + Im(basis)`` in the m-dimensional task space.

    Attributes
    ----------
    point : ndarray, shape (m,)
        A point of the set (the centre ``xdd_g``).
    basis : ndarray, shape (m, r)
        Orthonormal basis of the directions in the set.
    normals : ndarray, shape (m, m - r)
        Orthonormal basis of the directions orthogonal to the set.
    """

    point: NDArray[np.float64]
    basis: NDArray[np.float64]
    normals: NDArray[np.float64]

    @classmethod
    def _from_svd(cls, point: NDArray[np.float64], svd: RankRevealingSVD) -> AffineSubspace:
        """The set ``point + Im(M)``; the whole space (identity basis) when M has full rank."""
        m = point.size
        if svd.rank == m:
            return cls(point, *_whole_space(m))
        return cls(point, svd.U1, svd.U2)

    @property
    def dim(self) -> int:
        """Dimension ``r`` of the set."""
        return int(self.basis.shape[1])

    @property
    def ambient_dim(self) -> int:
        """Dimension ``m`` of the task space."""
        return int(self.point.size)

    @property
    def equalities(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(A_eq, b_eq)``, shapes (m - r, m) and (m - r,): the set is ``{x : A_eq x = b_eq}``."""
        return self.normals.T.copy(), self.normals.T @ self.point

    def coordinates(self, x: ArrayLike) -> NDArray[np.float64]:
        """Coordinates ``basis^T (x - point)`` of points, shape ``(..., r)``."""
        return (check_points("x", x, self.ambient_dim) - self.point) @ self.basis

    def distance(self, x: ArrayLike) -> NDArray[np.float64]:
        """Euclidean distance of points ``x`` (shape ``(..., m)``) from the set."""
        x = check_points("x", x, self.ambient_dim)
        return np.linalg.norm((x - self.point) @ self.normals, axis=-1)

    def near(self, x: ArrayLike, rtol: float = AFFINE_RTOL, size: float = 0.0) -> NDArray[np.bool_]:
        """Whether points ``x`` (shape ``(..., m)``) lie on the set to ``rtol`` (AFFINE_RTOL).

        Within ``rtol * max(|x|, |point|)``, plus :data:`OFFSET_RTOL` times ``size`` (the
        extent of a set in this affine set): a set whose offset from the origin is the
        rounding of its computation holds the origin.
        """
        x = check_points("x", x, self.ambient_dim)
        scale = np.maximum(np.linalg.norm(x, axis=-1), np.linalg.norm(self.point))
        floor = OFFSET_RTOL * size if np.isfinite(size) else 0.0
        return self.distance(x) <= check_fraction("rtol", rtol) * scale + floor

    def project(self, x: ArrayLike) -> NDArray[np.float64]:
        """Orthogonal projection of points ``x`` (shape ``(..., m)``) onto the set."""
        return self.point + self.coordinates(x) @ self.basis.T

    def _meet_lines(
        self, directions: NDArray[np.float64], rtol: float = AFFINE_RTOL, size: float = 0.0
    ) -> LineMeeting:
        """Intersect the lines ``{a t : a real}`` with the set.

        Parameters
        ----------
        directions : ndarray, shape (k, m)
            Unit directions ``t``.
        rtol : float
            :data:`AFFINE_RTOL`: a direction whose component off the set is at most this
            is parallel to it (and is projected onto it), and a point within
            ``rtol * max(|x|, |point|)`` of the set lies on it.
        size : float
            The extent of the set in this affine set: offsets below :data:`OFFSET_RTOL`
            times it are the rounding of the set's computation (see :meth:`near`).

        Returns
        -------
        LineMeeting
        """
        k = directions.shape[0]
        if self.dim == self.ambient_dim:
            return LineMeeting(np.ones(k, bool), np.zeros(k, bool), np.full(k, np.nan), directions)
        off = directions @ self.normals  # (k, m - r)
        target = self.point @ self.normals  # (m - r,): solve a * off = target
        off_norm2 = np.einsum("ij,ij->i", off, off)
        parallel = off_norm2 <= rtol**2
        through_origin = bool(self.near(np.zeros(self.ambient_dim), rtol, size))
        with np.errstate(invalid="ignore", divide="ignore"):
            a0 = np.where(parallel, np.nan, (off @ target) / off_norm2)
        if through_origin:  # a line not parallel to a set through 0 crosses it at a = 0
            a0 = np.where(parallel, np.nan, 0.0)
        crossing = np.where(parallel, 0.0, a0)[:, None] * directions
        single = ~parallel & self.near(crossing, rtol, size)
        inside = parallel & through_origin
        projected = directions.copy()
        if inside.any():
            in_set = directions[inside] @ self.basis @ self.basis.T
            projected[inside] = in_set / np.linalg.norm(in_set, axis=1, keepdims=True)
        return LineMeeting(inside, single, np.where(single, a0, np.nan), projected)
