"""The comparison metrics of an ellipsoid against the exact polytope (DESIGN.md section 2).

Each function takes an ellipsoid ``E`` lying in the affine set of the polytope ``P`` (as
both ellipsoid definitions and the MVIE do) and returns plain numbers.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.limits import DirectionalLimits, line_interval_in_halfspaces
from polyell.geometry.polytope import Polytope
from polyell.inverse import AffineMap

__all__ = [
    "CAP_GAP",
    "INSIDE_RTOL",
    "ROUNDING_FACTOR",
    "DirectionErrors",
    "Overlap",
    "cap_share",
    "check_same_affine_set",
    "direction_errors",
    "enclosing_scale",
    "estimate",
    "inscribed_scale",
    "inside_rtol",
    "overlap",
    "relative_error",
    "scale_rtol",
    "witness_torque_max",
]


#: Floor of :func:`inside_rtol`: an ellipsoid within this relative scale of touching counts
#: as touching.  Treating ``c + (1 - d)(E - c) inside P`` as ``E inside P`` makes the exact
#: coverage err by at most ``1 - (1 - d)^r <= r d`` relative (6e-9 in 6-D), far below the
#: standard error of any Monte Carlo estimate it replaces.
INSIDE_RTOL = 1e-9
#: Rounding errors of a scale, in units of ``eps * extent / s_min`` (see :func:`scale_rtol`).
ROUNDING_FACTOR = 16.0


def scale_rtol(
    extent: float | NDArray[np.float64],
    smallest_axis: float | NDArray[np.float64],
    m: int,
    n: int,
) -> float | NDArray[np.float64]:
    """Relative rounding bound of an inscribed or enclosing scale computed in task coordinates.

    A scale divides a distance in the task space (a facet's slack, a vertex's offset, each
    computed from the SVD of M, the facets and the ellipsoid's factors by backward-stable
    steps with sums of at most ``m + n`` terms) by a length of the ellipsoid of at least
    its smallest semi-axis.  Each distance carries an absolute error of at most about
    ``(m + n) eps extent`` (``extent``: the largest of ``|xg|``, ``|c|`` and the polytope's
    size), so the scale carries a relative one of ``ROUNDING_FACTOR (m + n) eps extent /
    s_min``: the condition number of the sets (``s_max / s_min``) and their distance from
    the origin (``|xg| / s_min``) enter, the units do not.

    Parameters
    ----------
    extent : float or ndarray
        ``max(|xg|, |c|, sum of the generator lengths)`` [m/s^2].
    smallest_axis : float or ndarray
        The ellipsoid's smallest semi-axis [m/s^2].
    m, n : int
        Task rows and joints.
    """
    eps = float(np.finfo(float).eps)
    return ROUNDING_FACTOR * (m + n) * eps * np.asarray(extent) / np.asarray(smallest_axis)


def inside_rtol(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Tolerance of "E inside P" and "E around P": ``max(INSIDE_RTOL, scale_rtol(...))``.

    An ellipsoid with ``inscribed_scale >= 1 - inside_rtol`` is inside P, one with
    ``enclosing_scale <= 1 + inside_rtol`` around it: one that touches (scale exactly 1, as
    the new ellipsoid of a parallelotope, the MVIE and the outer ellipsoid do) is never sent
    to a Monte Carlo estimate by rounding errors.
    """
    if E.rank == 0:
        return INSIDE_RTOL
    if isinstance(P, HPolytope):  # facets are its data: (m + 2) terms, its vertices' reach
        m, n, size = P.ambient_dim, 2, P._size()  # an unbounded set: its facets' offsets
    else:
        (m, n), size = P.generators.shape, float(np.linalg.norm(P.generators, axis=0).sum())
    extent = max(float(np.linalg.norm(P.center)), float(np.linalg.norm(E.center)), size)
    return max(INSIDE_RTOL, float(scale_rtol(extent, E.semi_axes[-1], m, n)))


def check_same_affine_set(E: Ellipsoid, P: Polytope | HPolytope) -> None:
    """Raise unless ``E`` spans exactly the affine set of ``P``."""
    off = P.affine_set.distance(E.center + (E.axes * E.semi_axes).T)
    if E.rank != P.dim or P.affine_set.distance(E.center) > P.atol or np.any(off > P.atol):
        raise InputError(
            "ellipsoid",
            f"an ellipsoid spanning the polytope's {P.dim}-dimensional affine set",
            f"one of rank {E.rank} at distance {P.affine_set.distance(E.center):.3g}",
            "compare ellipsoids built from the same analysis as the polytope.",
        )


def _half_widths(P: Polytope | HPolytope) -> NDArray[np.float64]:
    """Offsets of P's facets about its centre (F,).

    For a zonotope its support function ``h_i = sum_j |a_i . M_j|``, computed from the
    generators: ``b - A xg`` would lose the digits of h when P is small against its
    distance from the origin.  For an H-polytope ``b - A c`` (its facets are its data).
    """
    if isinstance(P, HPolytope):
        return P.half_widths
    half: NDArray[np.float64] = np.abs(P.A @ P.generators).sum(axis=1)
    return half


def _slacks(E: Ellipsoid, P: Polytope | HPolytope) -> NDArray[np.float64]:
    """``b_i - a_i . c`` for E's centre c, about P's centre (no cancellation at c = xg)."""
    return _half_widths(P) - P.A @ (E.center - P.center)


def inscribed_scale(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Largest ``k`` with ``c + k (E - c)`` inside ``P``.

    ``min_i (b_i - a_i . c) / |diag(s) U^T a_i|`` over the facets; at least 1 iff ``E`` is
    inside ``P``, negative if even its centre is outside.  A point ellipsoid gives
    ``inf`` (if its centre is in P) or ``-inf``.  The slacks are taken about P's centre
    (``h_i - a_i . (c - xg)``), so the scale keeps its digits however far P is from 0.
    """
    reach = np.linalg.norm((P.A @ E.axes) * E.semi_axes, axis=1)
    slack = _slacks(E, P)
    if E.rank == 0:
        return float("inf") if np.all(slack >= -P.atol) else float("-inf")
    return float(np.min(slack / reach))


def enclosing_scale(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Smallest ``k`` with ``P`` inside ``c + k (E - c)``.

    The largest ``|diag(s)^-1 U^T (v - c)|`` over the vertices v of ``P``: at most 1 iff
    ``E`` contains ``P`` (the outer ellipsoid touches: exactly 1), the counterpart of
    :func:`inscribed_scale`.  A point ellipsoid gives 0 (if P is that point) or ``inf``.
    """
    if isinstance(P, HPolytope) and not P.is_bounded:
        return float("inf")
    offsets = (P.vertices - P.center) + (P.center - E.center)
    if not len(offsets):  # an empty set is inside every ellipsoid
        return 0.0
    if E.rank == 0:
        return 0.0 if np.all(np.linalg.norm(offsets, axis=1) <= P.atol) else float("inf")
    return float(np.max(np.linalg.norm((offsets @ E.axes) / E.semi_axes, axis=1)))


class Overlap(NamedTuple):
    r"""Volume shares of ``E`` and ``P``, exact or estimated.

    Attributes
    ----------
    coverage : float
        ``vol(E & P) / vol(P)``.
    overreach : float
        ``vol(E \ P) / vol(E)``.
    coverage_stderr, overreach_stderr : float
        Standard errors of the quasi-Monte-Carlo estimates; 0 when exact.
    """

    coverage: float
    overreach: float
    coverage_stderr: float
    overreach_stderr: float


def _uniform_in_ball(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Map points of (0, 1)^(r+1) to uniform points of the unit r-ball."""
    from scipy.stats import norm  # here: scipy.stats takes half a second to import

    r = points.shape[1] - 1
    gaussian = norm.ppf(np.clip(points[:, :r], 1e-12, 1 - 1e-12))
    directions = gaussian / np.linalg.norm(gaussian, axis=1, keepdims=True)
    return directions * points[:, r:] ** (1.0 / r)


def _ball_points(
    r: int, samples: int, replicates: int, seed: int
) -> tuple[NDArray[np.float64], ...]:
    """The quasi-Monte-Carlo points of :func:`overlap`: uniform in the unit r-ball.

    ``replicates`` independently scrambled Sobol' sets of ``samples`` points, the first
    ``samples`` of a power-of-two draw (the size at which scipy's generator keeps its
    balance and issues no warning), from ``seed``.  They depend on nothing else: a sweep
    of many configurations draws them once (:func:`_sorted_ball_points` keeps them).
    """
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    exponent = max(0, int(samples - 1).bit_length())
    sets = []
    for _ in range(replicates):
        sobol = qmc.Sobol(d=r + 1, scramble=True, seed=rng)
        ball = _uniform_in_ball(sobol.random_base2(exponent)[:samples])
        ball.flags.writeable = False
        sets.append(ball)
    return tuple(sets)


@lru_cache(maxsize=8)
def _sorted_ball_points(
    r: int, samples: int, replicates: int, seed: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Every replicate's points of :func:`_ball_points` together, sorted by radius.

    Only how many points of each replicate fall inside P enters an estimate, not their
    order: sorted, the points of the ball of radius t (all inside P when ``t E`` is) are a
    prefix, and one product tests the rest of every replicate at once.

    Returns
    -------
    points : ndarray, shape (replicates * samples, r)
    radii : ndarray, shape (replicates * samples,)
        Their norms, ascending.
    replicate : ndarray of int, shape (replicates * samples,)
        The replicate each point belongs to.
    """
    sets = _ball_points(r, samples, replicates, seed)
    points = np.concatenate(sets)
    radii = np.linalg.norm(points, axis=1)
    order = np.argsort(radii, kind="stable")
    replicate = np.repeat(np.arange(replicates), samples)[order]
    points, radii = points[order], radii[order]
    for array in (points, radii, replicate):
        array.flags.writeable = False
    return points, radii, replicate


_sorted_ball_points = lru_cache(maxsize=8)(_sorted_ball_points)


#: Two caps of E (its parts beyond two facets) count as disjoint when the nearest point
#: beyond both facets lies this far beyond E's boundary, relatively: well above the
#: rounding of the normalized offsets, so an exact share never rests on a near-touching pair.
CAP_GAP = 1e-9


def cap_share(
    reach_vectors: NDArray[np.float64], slack: NDArray[np.float64]
) -> NDArray[np.float64]:
    r"""The exact share of E outside P where E's caps beyond P's facets are disjoint, else NaN.

    In the coordinates ``u`` of E (``x = c + U diag(s) u``, ``|u| <= 1``) facet i reads
    ``w_i . u <= slack_i`` with ``w_i = diag(s) U^T a_i``: its cap (the part of the unit
    ball beyond it) lies at distance ``t_i = slack_i / |w_i|`` from the centre and holds the
    share

    .. math:: F_r(t) = \tfrac12 I_{1 - t^2}\left(\tfrac{r + 1}{2}, \tfrac12\right)
              \quad (t \ge 0), \qquad F_r(t) = 1 - F_r(-t) \quad (t < 0)

    of the ball (``I`` the regularized incomplete beta function; for small ``|t|`` as
    ``1/2 - 1/2 I_{t^2}(1/2, (r+1)/2)``, which keeps its digits).  ``E \ P`` is the union
    of the caps; where no two of them meet (the nearest point beyond both facets, a
    two-constraint projection, lies outside the ball by :data:`CAP_GAP`) the share outside
    is ``sum F_r(t_i)`` exactly (summed as such: a small overreach keeps its relative
    accuracy), and 1 where one facet leaves all of E outside.  Each row is normalised by
    its largest entry first: the result does not depend on the units.

    Parameters
    ----------
    reach_vectors : ndarray, shape (..., F, r)
        ``w_i`` of every facet.
    slack : ndarray, shape (..., F)
        The facets' offsets about E's centre (``+inf``: a facet to ignore).

    Returns
    -------
    ndarray, shape (...)
        The share outside P in [0, 1], NaN where two caps meet (or an input is NaN):
        estimate those.
    """
    from scipy.special import betainc

    W = np.asarray(reach_vectors, dtype=float)
    slack = np.asarray(slack, dtype=float)
    if W.ndim < 2 or slack.shape != W.shape[:-1]:
        raise InputError(
            "reach_vectors",
            "an (..., F, r) array and slack of shape (..., F)",
            f"shapes {W.shape} and {slack.shape}",
        )
    r = W.shape[-1]
    size = np.max(np.abs(W), axis=-1)  # rows scaled to entries of at most 1: no underflow
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        unit = np.where(size[..., None] > 0, W / size[..., None], 0.0)
        norm = np.maximum(np.linalg.norm(unit, axis=-1), 1.0)  # >= 1 with an entry of 1
        unit = unit / norm[..., None]
        t = np.where(size > 0, slack / size / norm, np.where(slack >= 0, np.inf, -np.inf))
    bad = np.isnan(slack) | np.isnan(size)  # NaN in: NaN out
    nan = np.any(bad, axis=-1)
    t = np.where(bad, np.inf, t)
    lost = np.any(t <= -1.0, axis=-1)  # one facet leaves all of E outside
    # only the facets that cut E from here: the first of each row, cut first
    order = np.argsort(~(t < 1.0), axis=-1, kind="stable")
    order = order[..., : int(np.sum(t < 1.0, axis=-1).max(initial=0))]
    unit = np.take_along_axis(unit, order[..., None], axis=-2)
    t = np.take_along_axis(t, order, axis=-1)
    cut = t < 1.0
    ti, tj = t[..., :, None], t[..., None, :]
    cosine = unit @ np.swapaxes(unit, -1, -2)
    # The nearest point of {a_i . u >= t_i, a_j . u >= t_j}: on one plane if that point
    # satisfies the other, else on both.
    di, dj = np.maximum(ti, 0.0), np.maximum(tj, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        both = np.sqrt(
            np.maximum(0.0, ti * ti - 2.0 * cosine * ti * tj + tj * tj)
            / np.maximum(0.0, 1.0 - cosine * cosine)
        )
        nearest = np.where(cosine * di >= tj, di, np.where(cosine * dj >= ti, dj, both))
    pairs = cut[..., :, None] & cut[..., None, :] & ~np.eye(t.shape[-1], dtype=bool)
    meet = np.any(pairs & ~(nearest >= 1.0 + CAP_GAP), axis=(-2, -1))
    tc = np.clip(np.where(cut, t, 1.0), -1.0, 1.0)
    x = np.abs(tc)  # I_x(a, b) = 1 - I_(1-x)(b, a): the argument that keeps its digits
    half = np.where(
        x * x < 0.5,
        0.5 - 0.5 * betainc(0.5, (r + 1) / 2.0, x * x),
        0.5 * betainc((r + 1) / 2.0, 0.5, (1.0 - x) * (1.0 + x)),
    )
    caps = np.where(tc >= 0.0, half, 1.0 - half)
    outside = np.clip(np.sum(np.where(cut, caps, 0.0), axis=-1), 0.0, 1.0)
    outside = np.where(meet, np.nan, outside)
    result: NDArray[np.float64] = np.where(nan, np.nan, np.where(lost, 1.0, outside))
    return result


def estimate(counts: NDArray[np.int64], samples: int) -> tuple[float, float]:
    """The share of points inside and its standard error, from each replicate's count.

    The standard error of the replicate means; where every replicate counted the same
    (no point, or every point, fell outside), the binomial error of the pooled count with
    half a point added, ``sqrt(p (1 - p) / N)``, ``p = (k + 1/2) / (N + 1)``: an estimate
    never reads as exact (standard error 0).
    """
    shares = counts / samples
    replicates = len(counts)
    stderr = float(shares.std(ddof=1) / np.sqrt(replicates))
    if stderr == 0.0:
        total = samples * replicates
        p = (float(counts.sum()) + 0.5) / (total + 1.0)
        stderr = float(np.sqrt(p * (1.0 - p) / total))
    return float(shares.mean()), stderr


def _count_inside(
    axes: NDArray[np.float64],
    semi_axes: NDArray[np.float64],
    A: NDArray[np.float64],
    slack: NDArray[np.float64],
    samples: int,
    replicates: int,
    seed: int,
) -> NDArray[np.int64]:
    """How many quasi-Monte-Carlo points of each replicate, mapped into E, satisfy A x <= slack.

    ``E`` is ``{c + U diag(s) u : |u| <= 1}`` with ``axes`` U (m, r) and ``semi_axes`` s
    (r,); ``slack`` (F,) holds the facets' offsets about its centre c.

    The same counts as testing every point against every facet (``x = U diag(s) u``,
    ``all(x @ A.T <= slack)``), with the work only where the answer can be no: a facet
    whose reach over E (``|diag(s) U^T a_i|``) stays below its slack by more than the
    rounding of ``a_i . x`` (``ROUNDING_FACTOR (m + r + 2) eps s_max`` for unit normals)
    holds for every point of E, and a point of radius at most ``t`` with ``t reach_i <=
    slack_i`` minus that rounding for every facet (the scaled copy ``t E`` inside P) holds
    for all.  The rest are tested as before.
    """
    rank = len(semi_axes)
    reach = np.linalg.norm((A @ axes) * semi_axes, axis=1)
    terms = A.shape[1] + rank + 2
    rounding = ROUNDING_FACTOR * terms * float(np.finfo(float).eps) * float(np.max(semi_axes))
    rounding *= max(1.0, float(np.linalg.norm(A, axis=1).max(initial=0.0)))
    margin = slack - rounding
    crossing = ~(reach < margin)  # NaN-safe: test a facet unless it surely holds
    with np.errstate(divide="ignore", invalid="ignore"):
        scales = np.where(reach > 0, margin / reach, np.where(margin >= 0, np.inf, -np.inf))
    radius = float(np.min(scales, initial=np.inf)) * (1.0 - 1e-12)
    points, radii, replicate = _sorted_ball_points(rank, samples, replicates, seed)
    start = int(np.searchsorted(radii, radius, side="right")) if radius > 0 else 0
    offsets = (points[start:] * semi_axes) @ axes.T  # about E's centre
    # each facet only on the points beyond its own radius (the copy of E it holds)
    holds = np.where(scales > 0.0, scales, 0.0) * (1.0 - 1e-12)  # NaN: test every point
    firsts = np.searchsorted(radii, holds, side="right")
    outside = np.zeros(len(offsets), dtype=bool)
    for i in np.flatnonzero(crossing):
        tail = outside[firsts[i] - start :]
        tail |= offsets[firsts[i] - start :] @ A[i] > slack[i]
    missed = np.bincount(replicate[start:][outside], minlength=replicates)
    return samples - missed


def overlap(
    E: Ellipsoid,
    P: Polytope | HPolytope,
    *,
    samples: int = 2**13,
    replicates: int = 8,
    seed: int = 0,
) -> Overlap:
    """Coverage and overreach of ``E`` with respect to ``P``.

    Exact when ``E`` is inside ``P`` (``inscribed_scale >= 1 - inside_rtol``: coverage is
    ``vol(E) / vol(P)``, overreach 0), when ``E`` contains ``P`` (``enclosing_scale <= 1 +
    inside_rtol``: coverage 1, overreach ``1 - vol(P) / vol(E)``) and in one dimension
    (intervals); :func:`inside_rtol` is the larger of :data:`INSIDE_RTOL` and the rounding
    bound of the scales.  Exact as well when the parts of ``E`` beyond the facets (its
    caps) are pairwise disjoint: the share of ``E`` outside is the sum of the caps' closed
    forms (:func:`cap_share`).  Otherwise the share
    of ``E`` inside ``P`` is estimated by randomized quasi-Monte Carlo: ``replicates``
    independently scrambled Sobol' sets of ``samples`` points each, mapped uniformly into
    ``E``; the standard error is that of the replicate means (never 0: :func:`estimate`).

    Parameters
    ----------
    E : Ellipsoid
    P : Polytope
    samples : int, optional
        Points per replicate (a power of two keeps the Sobol' balance).
    replicates : int, optional
        Independent scramblings (at least 2, for the standard error).
    seed : int, optional
        Seed of the scramblings: the estimate is reproducible.
    """
    if E.rank == 0:
        inside = float(P.contains(E.center))
        return Overlap(inside, 1.0 - inside, 0.0, 0.0)
    tolerance = inside_rtol(E, P)
    if inscribed_scale(E, P) >= 1.0 - tolerance:
        return Overlap(min(1.0, E.volume / P.volume), 0.0, 0.0, 0.0)
    if enclosing_scale(E, P) <= 1.0 + tolerance:
        return Overlap(1.0, max(0.0, 1.0 - P.volume / E.volume), 0.0, 0.0)
    slack = _slacks(E, P)  # the facets about E's centre
    if E.rank == 1:
        axis = E.axes[:, 0]
        lo, hi = line_interval_in_halfspaces(P.A, slack, axis[None], P.atol)
        s = E.semi_axes[0]
        length = 0.0 if np.isnan(lo[0]) else max(0.0, min(hi[0], s) - max(lo[0], -s))
        return Overlap(length / P.volume, 1.0 - length / (2.0 * s), 0.0, 0.0)
    ratio = E.volume / P.volume
    outside = float(cap_share((P.A @ E.axes) * E.semi_axes, slack))
    if not np.isnan(outside):
        return Overlap(min(1.0, (1.0 - outside) * ratio), outside, 0.0, 0.0)
    counts = _count_inside(E.axes, E.semi_axes, P.A, slack, samples, replicates, seed)
    share, stderr = estimate(counts, samples)
    # vol(E & P) <= vol(P): an estimate above 1 is noise of the sampling (within stderr)
    return Overlap(min(1.0, share * ratio), 1.0 - share, stderr * ratio, stderr)


class DirectionErrors(NamedTuple):
    """Relative errors ``(hi_E - hi_P) / |hi_P|`` of an ellipsoid's directional limits.

    Over directions where both intervals are non-empty and ``hi_P != 0``.

    Attributes
    ----------
    mean, max, rms : float
        Mean, maximum and root-mean-square of the absolute relative error.
    bias : float
        Mean signed relative error (> 0: the ellipsoid promises too much).
    mismatch : int
        Directions where exactly one of the two intervals is empty.
    used : int
        Directions that entered the statistics.
    """

    mean: float
    max: float
    rms: float
    bias: float
    mismatch: int
    used: int


def relative_error(
    ellipsoid: NDArray[np.float64], polytope: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``(e - p) / |p|`` of directional limits, elementwise; NaN where either is NaN or p = 0.

    Parameters
    ----------
    ellipsoid, polytope : ndarray, shape (k,)
        The same end (``hi`` or ``lo``) of the intervals of an ellipsoid and of the polytope
        [m/s^2 or rad/s^2]; NaN where the interval is empty.

    Returns
    -------
    ndarray, shape (k,)
        Dimensionless.  For upper limits > 0 means the ellipsoid promises too much; for
        lower limits < 0 does (it reaches further down).
    """
    e, p = np.asarray(ellipsoid, dtype=float), np.asarray(polytope, dtype=float)
    used = ~np.isnan(e) & ~np.isnan(p) & (p != 0)
    error = np.full(np.broadcast_shapes(e.shape, p.shape), np.nan)
    error[used] = (e[used] - p[used]) / np.abs(p[used])
    return error


def direction_errors(ellipsoid: DirectionalLimits, polytope: DirectionalLimits) -> DirectionErrors:
    """Statistics of the upper directional limits of an ellipsoid against the polytope's."""
    feasible_e, feasible_p = ellipsoid.feasible, polytope.feasible
    mismatch = int(np.count_nonzero(feasible_e != feasible_p))
    errors = relative_error(ellipsoid.hi, polytope.hi)
    used = ~np.isnan(errors)
    if not used.any():
        return DirectionErrors(np.nan, np.nan, np.nan, np.nan, mismatch, 0)
    error = errors[used]
    return DirectionErrors(
        float(np.mean(np.abs(error))),
        float(np.max(np.abs(error))),
        float(np.sqrt(np.mean(error**2))),
        float(np.mean(error)),
        mismatch,
        int(used.sum()),
    )


def witness_torque_max(E: Ellipsoid, torques: AffineMap) -> float:
    """Largest ``|tau_n|_inf`` over the boundary of ``E`` under an affine inverse map.

    With ``tau_n = W x + w`` and boundary points ``x = c + U diag(s) u``, ``|u| = 1``, the
    maximum of ``|tau_n,i|`` is ``|W c + w|_i + |(W U diag(s))_i|`` (Cauchy-Schwarz, attained),
    so the value is exact, not sampled.
    """
    centre = torques(E.center)
    spread = np.linalg.norm(torques.matrix @ (E.axes * E.semi_axes), axis=1)
    return float(np.max(np.abs(centre) + spread))
