r"""Directional statistics of many configurations: the part of a sweep that grows with k.

For every configuration of a block and every direction ``t`` of the set, the far end of the
line ``{a t}`` in the polytope and in each scored ellipsoid (eq. 23-24), and the statistics
of ``(hi_E - hi_P) / |hi_P|`` (:func:`statistics`).  This
is where a default sweep spends its time, so it is written for the cache:

* rows are taken a few at a time (:data:`PASS_ELEMENTS`), so that every (rows, k) array of a
  pass stays in cache and is reused in place;
* when the origin is inside a polytope (``|a . x_g| < h`` on every facet pair: the usual
  case) its far ends come from its *gauge*, one matrix product and one maximum,
  ``1 / hi_P(t) = max_i (g_i . t)`` with the 2C polar points
  ``g = a / (h + a . x_g)`` and ``-a / (h - a . x_g)``;
* an ellipsoid's far end is ``r + sqrt(r^2 + q)`` with ``r = p . w / |p|^2`` and
  ``q = (1 - |w|^2) / |p|^2`` (``p = S^-1 U^T t``, ``w = S^-1 U^T c``), computed without
  cancellation on either sign of ``r``.

Each is the same closed form as the scalar path's (:meth:`Polytope.limits`,
:meth:`Ellipsoid.limits`), rearranged; they agree to rounding (the tests hold them to 1e-12).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from polyell.geometry.limits import PARALLEL_SLOPE, snap_to_zero

__all__ = ["PASS_ELEMENTS", "STATISTICS", "direction_scores", "polytope_far_ends", "statistics"]

Array = NDArray[np.float64]

#: The direction statistics of a row, in the order of ``Comparison.to_row``.
STATISTICS = (
    "direction_error_mean",
    "direction_error_max",
    "direction_error_rms",
    "direction_bias",
    "feasibility_mismatch",
    "directions_used",
)

#: Elements of the largest temporary of a pass, the (rows, 2C, k) products of the gauge:
#: 2^19 doubles (4 MiB) keeps every array of a pass in a core's share of cache while
#: amortising numpy's per-call cost (measured: docs/performance.md, section (h)).
PASS_ELEMENTS = 2**19
#: Elements of the (rows, k) arrays of a pass: 2^15 doubles (256 KiB).
ROW_ELEMENTS = 2**15


def direction_scores(
    normals: Array,
    half_widths: Array,
    offsets: Array,
    slack: Array,
    floor: Array,
    ellipsoids: Sequence[tuple[Array, Array, Array]],
    directions: Array,
    parallel: Array | None = None,
) -> list[dict[str, Array]]:
    """The direction statistics of each ellipsoid against the polytope, row by row.

    Parameters
    ----------
    normals : ndarray, shape (K, C, m)
        Unit facet normals of each polytope, one of each +-pair (zero: no constraint).
    half_widths : ndarray, shape (K, C)
        ``h``: the polytope is ``{x : |a . x - o| <= h}`` (inf: no constraint).
    offsets : ndarray, shape (K, C)
        ``o``: each facet pair's midpoint along its normal, ``a . x_g`` for a polytope
        symmetric about ``x_g`` (a zonotope); a force polytope's pairs have their own.
    slack : ndarray, shape (K, C)
        :func:`~polyell.geometry.limits.facet_slack` for the lines that graze a polytope.
    floor : ndarray, shape (K, 1)
        :func:`~polyell.geometry.limits.rounding_floor`: a facet within it of the origin
        passes through the origin.
    ellipsoids : sequence of (center (K, m), axes (K, m, m), semi_axes (K, m))
        The scored ellipsoids ``{c + U diag(s) u : |u| <= 1}``, semi-axes positive.
    directions : ndarray, shape (k, m)
        Unit directions.
    parallel : ndarray, shape (K, C), optional
        Slopes up to which a line runs along a facet pair
        (:func:`~polyell.geometry.limits.parallel_slopes`; default
        :data:`~polyell.geometry.limits.PARALLEL_SLOPE`).

    Returns
    -------
    list of dict of str to ndarray (K,)
        One dict per ellipsoid, keyed by :data:`STATISTICS`.
    """
    K = len(normals)
    k = len(directions)
    Tt = np.ascontiguousarray(directions.T)
    results = [{name: np.empty(K) for name in STATISTICS} for _ in ellipsoids]
    step = max(1, ROW_ELEMENTS // max(k, 1))
    for start in range(0, K, step):
        rows = slice(start, start + step)
        hi_p, feasible_p = polytope_far_ends(
            normals[rows], half_widths[rows], offsets[rows], Tt, slack[rows], floor[rows],
            None if parallel is None else parallel[rows],
        )  # fmt: skip
        with np.errstate(divide="ignore"):
            scale = 1.0 / np.abs(hi_p)  # shared by every ellipsoid (inf where hi_P = 0)
        for result, (c, axes, semi) in zip(results, ellipsoids, strict=True):
            hi_e, feasible_e = _ellipsoid_far_ends(c[rows], axes[rows], semi[rows], Tt)
            for name, values in statistics(hi_e, feasible_e, hi_p, feasible_p, scale).items():
                result[name][rows] = values
    return results


def polytope_far_ends(
    normals: Array,
    half_widths: Array,
    offsets: Array,
    Tt: Array,
    slack: Array,
    floor: Array,
    parallel: Array | None = None,
) -> tuple[Array, NDArray[np.bool_]]:
    """Far ends ``hi_P`` (K, k) of the lines ``{a t}`` in each polytope, and which meet it.

    ``Tt`` holds the directions as columns (m, k).  Rows whose origin is inside by more than
    ``floor`` (:func:`~polyell.geometry.limits.rounding_floor`, (K, 1)) on every facet take
    the gauge; the others cut the line with every facet pair (both ends), an offset within
    ``floor`` of 0 taken as 0 (the origin on that facet: a far end of exactly 0), and a
    line that misses P but meets it grown by ``slack`` touches it at ``(lo + hi) / 2``, as
    :meth:`Polytope.limits`.  NaN where the line misses P.
    """
    inside = (np.abs(offsets) < half_widths - floor).all(axis=1)
    hi = np.empty((len(normals), Tt.shape[1]))
    meets = np.ones(hi.shape, dtype=bool)
    if inside.any():
        rows = inside if not inside.all() else slice(None)
        a, o, h = normals[rows], offsets[rows], half_widths[rows, :, None]
        with np.errstate(invalid="ignore"):  # 0 / inf: a dependent subset, no constraint
            polar = np.concatenate([a / (h + o[..., None]), a / (o[..., None] - h)], axis=1)
        gauge = np.empty((len(polar), Tt.shape[1]))
        step = max(1, PASS_ELEMENTS // max(1, polar.shape[1] * Tt.shape[1]))
        for start in range(0, len(polar), step):  # (step, 2C, k) products: in cache
            block = slice(start, start + step)
            np.max(polar[block] @ Tt, axis=1, out=gauge[block])
        hi[rows] = 1.0 / gauge
    if not inside.all():
        out = ~inside
        threshold = np.full(slack.shape, PARALLEL_SLOPE) if parallel is None else parallel
        hi[out], meets[out] = _cut_far_ends(
            normals[out], offsets[out], half_widths[out], Tt, slack[out], floor[out],
            threshold[out],
        )  # fmt: skip
    return hi, meets


def _cut_far_ends(
    normals: Array,
    offsets: Array,
    half_widths: Array,
    Tt: Array,
    slack: Array,
    floor: Array,
    parallel: Array,
) -> tuple[Array, NDArray[np.bool_]]:
    """:func:`polytope_far_ends` for rows whose origin is not inside by more than ``floor``."""
    ends = snap_to_zero(offsets - half_widths, floor), snap_to_zero(offsets + half_widths, floor)
    lower, upper = _rays(normals, *ends, Tt, parallel)
    missed = lower > upper
    grazing = np.zeros_like(missed)
    rows = np.flatnonzero(missed.any(axis=1))
    if rows.size:  # a touch, to rounding: does the line meet P grown by the slack?
        loose = half_widths[rows] + slack[rows]
        o = offsets[rows]
        loose_ends = _rays(normals[rows], o - loose, o + loose, Tt, parallel[rows])
        grazing[rows] = missed[rows] & (loose_ends[0] <= loose_ends[1])
        with np.errstate(invalid="ignore"):
            middle = 0.5 * (lower[rows] + upper[rows])
        # a line along a facet's plane just beyond it (within the slack; its strict ends
        # infinite): the grown set's far end, else the touching point
        touch = np.where(np.isfinite(middle), middle, loose_ends[1])
        upper[rows] = np.where(grazing[rows], touch, upper[rows])
    meets = (lower <= upper) | grazing  # False for NaN: 0/0, a line on a facet's boundary
    return np.where(meets, upper, np.nan), meets


def _rays(
    normals: Array, below: Array, above: Array, Tt: Array, parallel: Array
) -> tuple[Array, Array]:
    """Both ends (K, k) of the lines in the facet pairs ``below <= a . x <= above`` (K, C).

    With ``s = a . t`` the pair bounds ``lambda`` between ``below / s`` and ``above / s``
    (their order by the sign of s, -0 included); one pair at a time.
    """
    K, k = len(normals), Tt.shape[1]
    lower, upper = np.full((K, k), -np.inf), np.full((K, k), np.inf)
    slopes, bound = np.empty((K, k)), np.empty((K, k))
    with np.errstate(divide="ignore", invalid="ignore"):
        # A line parallel to the pair to rounding (PARALLEL_SLOPE) keeps no bound from it
        # where below <= 0 <= above (the origin's value, constant along it), else is empty.
        for j in range(normals.shape[1]):
            np.matmul(normals[:, j], Tt, out=slopes)
            along = np.abs(slopes) <= parallel[:, j, None]
            if along.any():
                slopes[along] = 0.0
                keeps = (below[:, j, None] <= 0.0) & (above[:, j, None] >= 0.0)
                empty = along & ~keeps
                lower[empty], upper[empty] = np.inf, -np.inf
            negative = np.signbit(slopes)
            np.divide(np.where(negative, above[:, j, None], below[:, j, None]), slopes, out=bound)
            bound[along] = -np.inf
            np.maximum(lower, bound, out=lower)  # NaN (0/0) propagates: an empty line
            np.divide(np.where(negative, below[:, j, None], above[:, j, None]), slopes, out=bound)
            bound[along] = np.inf
            np.minimum(upper, bound, out=upper)
    return lower, upper


def _ellipsoid_far_ends(
    center: Array, axes: Array, semi_axes: Array, Tt: Array
) -> tuple[Array, NDArray[np.bool_]]:
    r"""Far ends (K, k) of the lines ``{a t}`` in ellipsoids, and which meet them.

    ``a t`` is in ``E`` when ``|a p - w| <= 1`` (``p = S^-1 U^T t``, ``w = S^-1 U^T c``):
    ``a = r +- sqrt(r^2 + q)`` with ``r = p . w / |p|^2``, ``q = (1 - |w|^2) / |p|^2``.  The
    far end is taken as ``q / (sqrt(r^2 + q) - r)`` where ``r < 0``: no cancellation when the
    origin is near E's boundary on the far side.  NaN where the line misses E.
    """
    inverse = np.swapaxes(axes, 1, 2) / semi_axes[:, :, None]  # S^-1 U^T (K, m, m)
    p = inverse @ Tt  # (K, m, k)
    w = np.einsum("kij,kj->ki", inverse, center)
    length2 = np.einsum("kmd,kmd->kd", p, p)
    r = np.einsum("kmd,km->kd", p, w)
    np.divide(r, length2, out=r)
    q = np.divide((1.0 - np.einsum("km,km->k", w, w))[:, None], length2, out=length2)
    root = np.add(np.square(r), q)
    meets = root >= 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        np.sqrt(root, out=root)  # NaN where the line misses E
        far = np.add(r, root)
        np.divide(q, np.subtract(root, r, out=root), out=far, where=r < 0.0)
    return far, meets


def statistics(
    hi_e: Array,
    feasible_e: NDArray[np.bool_],
    hi_p: Array,
    feasible_p: NDArray[np.bool_],
    scale: Array | None = None,
) -> dict[str, Array]:
    """The direction statistics of K rows of far ends (:data:`STATISTICS`).

    The relative errors ``(hi_E - hi_P) / |hi_P|`` (along a ray of an unbounded set, where
    ``hi_P = inf``, their limit -1: the ellipsoid states none of it) over the directions
    where both lines meet their sets and ``hi_P != 0``: mean, maximum and root mean square
    of their magnitudes and their mean (> 0: the ellipsoid promises too much); the
    directions where exactly one line meets its set; the directions used.

    Parameters
    ----------
    hi_e, hi_p : ndarray, shape (K, k)
        Far ends of the lines in the ellipsoid and in the polytope [task units].
    feasible_e, feasible_p : ndarray of bool, shape (K, k)
        Whether each line meets its set.
    scale : ndarray, shape (K, k), optional
        ``1 / |hi_P|`` if already at hand (shared by every ellipsoid of a sweep).

    Returns
    -------
    dict of str to ndarray (K,)
    """
    if scale is None:
        with np.errstate(divide="ignore"):
            scale = 1.0 / np.abs(hi_p)
    used = feasible_e & feasible_p & (hi_p != 0)
    error = np.subtract(hi_e, hi_p)
    with np.errstate(invalid="ignore"):  # 0 * inf where hi_P = 0: not used
        np.multiply(error, scale, out=error)
    ray = np.isinf(hi_p) & used
    if ray.any():
        error[ray] = -np.sign(hi_p[ray])
    everywhere = bool(used.all())
    if not everywhere:
        error[~used] = 0.0
    count = np.full(len(error), float(error.shape[1])) if everywhere else used.sum(axis=1) * 1.0
    absolute = np.abs(error)
    with np.errstate(divide="ignore", invalid="ignore"):
        stats = {
            "direction_error_mean": absolute.sum(axis=1) / count,
            "direction_error_max": absolute.max(axis=1, initial=0.0),
            "direction_error_rms": np.sqrt(np.einsum("kd,kd->k", error, error) / count),
            "direction_bias": error.sum(axis=1) / count,
        }
    stats = {key: np.where(count == 0, np.nan, value) for key, value in stats.items()}
    mismatch = feasible_e != feasible_p
    stats["feasibility_mismatch"] = mismatch.sum(axis=1) * 1.0
    stats["directions_used"] = count
    return stats
