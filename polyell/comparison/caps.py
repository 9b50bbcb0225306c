r"""The share of an ellipsoid beyond a polytope's facets: the union of its caps.

In the unit-ball coordinates of an ellipsoid E the part of E outside a polytope P is the
union of E's caps beyond P's facets.  :func:`cap_share` gives it exactly where no two caps
meet, :func:`cap_union_share` estimates it (Karp-Luby-Madras) where they do.  Every
coverage and overreach of :mod:`polyell.comparison.scores` comes from here.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.geometry.directions import sphere_directions
from polyell.validation import as_floats, check_integer

__all__ = [
    "ANTIPARALLEL",
    "CAP_GAP",
    "CAP_SAMPLES_RATIO",
    "PAIR_TIE",
    "ROUNDING_STDERR",
    "cap_points",
    "cap_share",
    "cap_union_share",
]


#: Two unit normals with ``1 + cos`` at most this are opposite (the two sides of one row,
#: rounded): a few eps, an angle below 1e-7.
ANTIPARALLEL = 8.0 * float(np.finfo(float).eps)
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
    outside, _ = _cap_geometry(reach_vectors, slack)
    return outside


class _Caps(NamedTuple):
    """The caps of a batch of rows that cut E, as :func:`_cap_geometry` finds them.

    Attributes
    ----------
    unit : ndarray, shape (K, F', r)
        Unit normals ``w_i / |w_i|`` of the cutting facets, first in each row in facet order
        (``F'`` the most of any row; padding has ``t = 1``).
    t : ndarray, shape (K, F')
        Their distances from E's centre in the unit-ball coordinates.
    cut : ndarray of bool, shape (K, F')
        The slots that hold a cutting facet (``t < 1``).
    share : ndarray, shape (K, F')
        ``F_r(t_i)``, the share of the ball beyond each (0 in padding).
    pairs : ndarray of bool, shape (K, F', F')
        The pairs of caps that meet (not disjoint by :data:`CAP_GAP`).
    lost, nan : ndarray of bool, shape (K,)
        Rows with one facet leaving all of E outside, rows with NaN input.
    """

    unit: NDArray[np.float64]
    t: NDArray[np.float64]
    cut: NDArray[np.bool_]
    share: NDArray[np.float64]
    pairs: NDArray[np.bool_]
    lost: NDArray[np.bool_]
    nan: NDArray[np.bool_]


def _beyond(t: NDArray[np.float64], r: int) -> NDArray[np.float64]:
    """``F_r(t)``, the share of the unit r-ball beyond the plane at distance t in [-1, 1]."""
    from scipy.special import betainc

    x = np.abs(t)  # I_x(a, b) = 1 - I_(1-x)(b, a): the argument that keeps its digits
    low = x * x < 0.5
    a, b = (r + 1) / 2.0, 0.5
    argument = np.where(low, x * x, (1.0 - x) * (1.0 + x))
    share = betainc(np.where(low, b, a), np.where(low, a, b), argument)
    half = np.where(low, 0.5 - 0.5 * share, 0.5 * share)
    result: NDArray[np.float64] = np.where(t >= 0.0, half, 1.0 - half)
    return result


def _slice_share(tau: NDArray[np.float64], d: int) -> NDArray[np.float64]:
    """``F_d(tau)`` for tau in [-1, 1]: closed forms for a segment and a disc, else ``_beyond``."""
    if d == 1:
        return 0.5 * (1.0 - tau)
    if d == 2:
        result: NDArray[np.float64] = (
            np.arccos(tau) - tau * np.sqrt((1.0 - tau) * (1.0 + tau))
        ) / np.pi
        return result
    return _beyond(tau, d)


def _cap_geometry(
    reach_vectors: NDArray[np.float64], slack: NDArray[np.float64]
) -> tuple[NDArray[np.float64], _Caps]:
    """:func:`cap_share` and the caps it found (for :func:`cap_union_share`)."""
    W, slack = as_floats("reach_vectors", reach_vectors), as_floats("slack", slack)
    if W.ndim < 2 or slack.shape != W.shape[:-1]:
        raise InputError(
            "reach_vectors",
            "an (..., F, r) array and slack of shape (..., F)",
            f"shapes {W.shape} and {slack.shape}",
            "pass one slack per facet row, e.g. reach_vectors of shape (F, r) and slack (F,)",
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
    # A cap beyond a facet parallel to another, farther out, lies inside the other's cap
    # (repeated rows; the facets on one side of a segment): only the nearer one counts.
    first = np.arange(t.shape[-1])
    nearer = (ti < tj) | ((ti == tj) & (first[:, None] < first[None, :]))
    cut &= ~np.any((cosine >= 1.0 - ANTIPARALLEL) & nearer & cut[..., :, None], axis=-2)
    # The nearest point of {a_i . u >= t_i, a_j . u >= t_j}: on one plane if that point
    # satisfies the other, else on both.
    di, dj = np.maximum(ti, 0.0), np.maximum(tj, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        both = np.sqrt(
            np.maximum(0.0, ti * ti - 2.0 * cosine * ti * tj + tj * tj)
            / np.maximum(0.0, 1.0 - cosine * cosine)
        )
        nearest = np.where(cosine * di >= tj, di, np.where(cosine * dj >= ti, dj, both))
    # Opposite normals to rounding (the two sides of one row of a thin set): the caps meet
    # only if the planes cross (t_i + t_j <= 0); 1 - cos^2 of a few eps is no angle.
    opposite = 1.0 + cosine <= ANTIPARALLEL
    nearest = np.where(opposite & (ti + tj > 0.0), np.inf, nearest)
    pairs = cut[..., :, None] & cut[..., None, :] & ~np.eye(t.shape[-1], dtype=bool)
    pairs &= ~(nearest >= 1.0 + CAP_GAP)
    meet = np.any(pairs, axis=(-2, -1))
    tc = np.clip(np.where(cut, t, 1.0), -1.0, 1.0)
    caps = np.where(cut, _beyond(tc, r), 0.0)
    outside = np.clip(np.sum(caps, axis=-1), 0.0, 1.0)
    outside = np.where(meet, np.nan, outside)
    result: NDArray[np.float64] = np.where(nan, np.nan, np.where(lost, 1.0, outside))
    return result, _Caps(unit, np.where(cut, tc, 1.0), cut, caps, pairs, lost, nan)


#: Heights per pair of meeting caps and replicate of :func:`cap_union_share`: ``samples //
#: CAP_SAMPLES_RATIO`` (a power of two; 16 at the default 2^13).  Chosen so that the
#: standard error stays well below the uniform 8 x 2^13-point estimate's on a Panda arm's
#: force ellipsoids: at most 0.20 of it (median 0.03) on 86 random configurations with 16,
#: 1.2 with 8.
CAP_SAMPLES_RATIO = 512
#: Two caps whose distances t from E's centre differ by at most this are a tie in
#: :func:`cap_union_share`: their overlap is integrated along both normals, not one.
PAIR_TIE = 1e-9
#: The least standard error of an estimated share: the rounding of its sums of cap shares
#: and replicate means (a few hundred eps), found by an independent check where the
#: replicates agreed to 5e-18 and the exact share differed by 4e-14.
ROUNDING_STDERR = 256 * float(np.finfo(float).eps)
#: Memory of one block of pairs sampled together in :func:`cap_union_share` [bytes].
_CAP_BLOCK_MEMORY = 1 << 22


def cap_points(samples: int) -> int:
    """Heights per pair of caps and replicate of :func:`cap_union_share` for ``samples``."""
    samples = check_integer("samples", samples, 1, 2**62)
    wanted = max(2, int(samples) // CAP_SAMPLES_RATIO)
    return 1 << (wanted - 1).bit_length()  # the power of two at or above


@lru_cache(maxsize=8)
def _cap_heights(points: int, replicates: int, seed: int) -> NDArray[np.float64]:
    """The stratified heights of :func:`cap_union_share`, shared by every pair of caps.

    ``replicates`` independent sets of ``points / 2`` points in [0, 1), one uniform in each
    interval of length ``2 / points`` (the distribution of a scrambled one-dimensional
    Sobol' set, without importing scipy.stats: half a second), each with its mirror image
    in its interval (every point uniform, the pair exact for a linear integrand), from the
    stream ``(seed, 1)`` of ``numpy.random.default_rng``.

    Returns
    -------
    ndarray, shape (replicates, points)
    """
    rng = np.random.default_rng([seed, 1])
    half = max(1, points // 2)
    # each point and its mirror image in its interval of length 1 / half: the pair is
    # exact for a linear integrand there (an error of O(half^-2.5), not O(half^-1.5))
    strata = np.arange(half)
    v = (strata + rng.random((replicates, half))) / half
    heights = np.concatenate([v, 2.0 * (strata + 0.5) / half - v], axis=1)
    heights.flags.writeable = False
    return heights


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``sum(a * b, axis=-1)`` in a fixed order (the same digits in any batch and BLAS)."""
    total = a[..., 0] * b[..., 0]
    for i in range(1, a.shape[-1]):
        total = total + a[..., i] * b[..., i]
    return total


def _solve(G: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Solutions of a stack of symmetric 2x2 or 3x3 systems by Cramer's rule (NaN: singular)."""
    if G.shape[-1] == 2:
        det = G[..., 0, 0] * G[..., 1, 1] - G[..., 0, 1] * G[..., 1, 0]
        x = np.stack(
            [
                b[..., 0] * G[..., 1, 1] - b[..., 1] * G[..., 0, 1],
                b[..., 1] * G[..., 0, 0] - b[..., 0] * G[..., 1, 0],
            ],
            axis=-1,
        )
    else:
        c = np.stack(
            [
                np.cross(G[..., 1, :], G[..., 2, :]),
                np.cross(G[..., 2, :], G[..., 0, :]),
                np.cross(G[..., 0, :], G[..., 1, :]),
            ],
            axis=-2,
        )  # rows: the cofactors, G symmetric
        det = _dot(G[..., 0, :], c[..., 0, :])
        x = _dot(c, b[..., None, :])
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(det)[..., None] > 1e-12, x / det[..., None], np.nan)


def _triples(
    unit: NDArray[np.float64], t: NDArray[np.float64], pairs: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Caps that meet two others at once: ``{w . u >= t}`` of the three has a point of the ball.

    Shape (K, F).  Only these caps change ``int g(N)``: a point of a cap in no such triple
    lies in at most one other cap, where ``g(N) = 0`` with or without it.

    Over the triples whose pairs meet, the point of least norm of the three half-spaces
    is the projection onto one of the seven sets of active planes: the least norm of the
    candidates that satisfy all three.  Two or three normals nearly dependent (a Gram
    determinant below 1e-12) count as meeting: the triple term is then sampled, not
    assumed 0.
    """
    row, i, j = np.nonzero(np.triu(pairs, 1))
    meets = pairs[row, i] & pairs[row, j]  # (T0, F): third caps meeting both
    later = np.arange(pairs.shape[-1])[None, :] > j[:, None]
    first, k = np.nonzero(meets & later)
    row, i, j = row[first], i[first], j[first]
    triple = np.zeros(pairs.shape[:2], dtype=bool)
    if not len(row):
        return triple
    W = np.stack([unit[row, i], unit[row, j], unit[row, k]], axis=1)  # (T, 3, r)
    b = np.stack([t[row, i], t[row, j], t[row, k]], axis=1)
    G = _dot(W[:, :, None, :], W[:, None, :, :])  # (T, 3, 3)
    least = np.where(np.all(b <= 0.0, axis=-1), 0.0, np.inf)  # the centre itself
    singular = np.zeros(len(row), dtype=bool)
    for active in ((0,), (1,), (2,), (0, 1), (0, 2), (1, 2), (0, 1, 2)):
        a = list(active)
        if len(a) == 1:
            multipliers = b[:, a] / G[:, a[0], a[0], None]
        else:
            multipliers = _solve(G[:, a][:, :, a], b[:, a])
            singular |= np.isnan(multipliers).any(axis=-1)
        point = _dot(np.swapaxes(W[:, a], 1, 2), multipliers[:, None, :])  # (T, r)
        feasible = np.all(_dot(W, point[:, None, :]) >= b - 1e-12, axis=-1)
        norm = np.sqrt(_dot(point, point))
        least = np.where(feasible & (norm < least), norm, least)
    meet = (least < 1.0 + CAP_GAP) | singular
    for caps in (i, j, k):
        triple[row[meet], caps[meet]] = True
    return triple


def cap_union_share(
    reach_vectors: NDArray[np.float64],
    slack: NDArray[np.float64],
    *,
    samples: int = 2**13,
    replicates: int = 8,
    seed: int = 0,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""The share of E outside P, the volume of the union of E's caps, and its standard error.

    In the unit-ball coordinates ``u`` of E (as in :func:`cap_share`) ``E \ P`` is the union
    of the caps ``C_i = {|u| <= 1, w_i . u > t_i}``, each of the exact share ``F_r(t_i)``.
    Where no two caps meet its share is :func:`cap_share`'s exact sum (standard error 0),
    and 1 where one facet leaves all of E outside.  Otherwise it is estimated from the
    identity of Karp, Luby and Madras,

    .. math:: \operatorname{vol}\Bigl(\bigcup_i C_i\Bigr) = \sum_i \int_{C_i}
              \frac{dx}{N(x)}, \qquad N(x) = \#\{j : x \in C_j\}

    (R. M. Karp, M. Luby, N. Madras, "Monte-Carlo approximation algorithms for enumeration
    problems", J. Algorithms 10 (1989) 429-448), with ``1/N = 1 - (N - 1)/2 + g(N)/N``,
    ``g(N) = (N - 1)(N - 2)/2``:

    .. math:: \operatorname{vol}\Bigl(\bigcup_i C_i\Bigr) = \sum_i F_r(t_i)
              - \sum_{i<j} V_{ij} + \int g(N)\,dx.

    Only what the caps share is estimated, so the variance comes only from the overlaps:

    * ``V_ij = vol(C_i & C_j)`` for each pair that meets (the others are disjoint by
      :data:`CAP_GAP`), as a 1-D integral along the normal ``w_i`` of the smaller cap (the
      larger t; both normals, each with weight 1/2, within :data:`PAIR_TIE` of a tie, so
      that neither the facets' order nor their rounding chooses): the cross-section of
      ``C_i`` at height ``h`` is an (r-1)-ball of radius ``rho = sqrt(1 - h^2)`` and
      density ``f_r(h) = (1 - h^2)^((r-1)/2) / B(1/2, (r+1)/2)``, of which cap j holds the
      share ``F_(r-1)(tau)``, ``tau = (t_j - c h) / (sqrt(1 - c^2) rho)``, ``c = w_i .
      w_j`` (the mean of ``(N - 1)/2`` over the cross-section in closed form: a
      conditional expectation of the KLM terms of points uniform in the caps, unbiased,
      with less variance).  Between the heights ``c t_j -+ sqrt(1 - c^2) sqrt(1 - t_j^2)``
      (``tau = +-1``) the cross-section is partly in ``C_j``; above them wholly if ``w_i``
      lies in ``C_j``, below them wholly if ``-w_i`` does, else not at all: those parts
      are exact (``F_r`` differences), and only the partial heights (from ``t_i`` on) are
      sampled, at uniform heights weighted by ``f_r`` (importance sampling with an exact
      weight, no inverse distribution function needed; stratified and mirrored points
      make the smooth integrand's error ``O(n^-2.5)``).
    * ``int g(N)``, 0 unless three caps meet: only in rows where the least-norm point of
      three caps' half-spaces lies in the ball (:func:`_triples`), along uniform directions
      ``d``, each ray's share in closed form from the sorted radii ``t_j / (w_j . d)`` at
      which it enters or leaves the caps (:func:`_triple_term`).

    The points are randomized quasi-Monte Carlo: ``replicates`` independently scrambled
    Sobol' sets from ``seed`` (:func:`_cap_heights`: :func:`cap_points` ``(samples)``
    heights per pair; :func:`_directions`: ``samples`` directions), the same for every
    pair and every row, so that a row's estimate depends on that row alone: not on the
    other rows of the batch, nor (beyond rounding) on the order of its facets; its sums
    run in a fixed order, without BLAS.  The estimate is the mean of the replicates'
    estimates, each unbiased, and its standard error the standard error of that mean;
    where every replicate gave the same value, half a point's worth of each pair's slab
    and of the ball's three-cap points (the binomial error of the pooled points with half
    a point added): an estimate never reads as exact.

    Parameters
    ----------
    reach_vectors : ndarray, shape (..., F, r)
        ``w_i`` of every facet (``diag(s) U^T a_i``).
    slack : ndarray, shape (..., F)
        The facets' offsets about E's centre (``+inf``: a facet to ignore).
    samples : int, optional
        The budget of the uniform estimate this replaced, per replicate: each pair of caps
        that meet gets ``samples // CAP_SAMPLES_RATIO`` heights per replicate (at least 2,
        rounded up to a power of two: 16 at the default 2^13), a row where three caps meet
        ``samples`` directions per replicate.
    replicates : int, optional
        Independent scramblings (at least 2, for the standard error).
    seed : int, optional
        Seed of the scramblings: the estimate is reproducible.

    Returns
    -------
    share : ndarray, shape (...)
        The share of E outside P in [0, 1]; NaN where an input is NaN.
    stderr : ndarray, shape (...)
        Its standard error: 0 where exact, NaN with NaN input; a positive one at least
        :data:`ROUNDING_STDERR` (the sums' rounding: an estimate never claims more digits
        than double precision keeps).
    """
    samples = check_integer("samples", samples, 1, 2**24)
    replicates = check_integer("replicates", replicates, 2, 1024)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    exact, caps = _cap_geometry(reach_vectors, slack)
    shape, r = exact.shape, np.shape(reach_vectors)[-1]
    share = exact.reshape(-1).copy()
    nan = caps.nan.reshape(-1)
    stderr = np.where(nan, np.nan, 0.0)
    rows = np.flatnonzero(np.isnan(share) & ~nan)
    if rows.size:
        cut = caps.t.shape[-1]
        share[rows], stderr[rows] = _union_share(
            caps.unit.reshape(-1, cut, r)[rows],
            caps.t.reshape(-1, cut)[rows],
            caps.share.reshape(-1, cut)[rows],
            caps.pairs.reshape(-1, cut, cut)[rows],
            caps.cut.reshape(-1, cut)[rows],
            samples,
            replicates,
            seed,
        )
        positive = stderr[rows] > 0  # (0: every sample gave the exact share)
        stderr[rows] = np.where(positive, np.maximum(stderr[rows], ROUNDING_STDERR), 0.0)
    return share.reshape(shape), stderr.reshape(shape)


def _union_share(
    unit: NDArray[np.float64],
    t: NDArray[np.float64],
    beyond: NDArray[np.float64],
    pairs: NDArray[np.bool_],
    cut: NDArray[np.bool_],
    samples: int,
    replicates: int,
    seed: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The estimate of :func:`cap_union_share` for rows whose caps meet (``_Caps`` fields)."""
    from scipy.special import beta

    K, F, r = unit.shape
    points = cap_points(samples)
    total = np.zeros(K)
    for slot in range(F):  # in slot order, whatever the padding: the same digits in any batch
        total = total + beyond[:, slot]
    # Each pair of caps that meet once, along the normal of the smaller cap (the larger t;
    # both, each with weight 1/2, within PAIR_TIE of a tie: the facets' order and their
    # rounding do not choose): V_ij = int f_r(h) F_(r-1)(tau_j(h)) dh over C_i & C_j.
    row, one, two = np.nonzero(np.triu(pairs, 1))
    t_one, t_two = t[row, one], t[row, two]
    tie = np.abs(t_one - t_two) <= PAIR_TIE
    along = np.where(t_one > t_two, one, two)
    i = np.concatenate([np.where(tie, one, along), two[tie]])
    j = np.concatenate([np.where(tie, two, one + two - along), one[tie]])
    share = np.concatenate([np.where(tie, 0.5, 1.0), np.full(int(tie.sum()), 0.5)])
    row = np.concatenate([row, row[tie]])
    order = np.argsort(row, kind="stable")  # each row's pairs together, in their order
    row, i, j, share = row[order], i[order], j[order], share[order]
    wi, wj, ti, tj = unit[row, i], unit[row, j], t[row, i], t[row, j]
    c = _dot(wi, wj)
    s = np.sqrt(np.maximum(0.0, (1.0 - c) * (1.0 + c)))
    # The cross-section of C_i at height h meets cap j in part only between the heights
    # c t_j -+ s sqrt(1 - t_j^2) (where tau = +-1); beyond them it lies wholly in cap j
    # (above if w_i lies in C_j, below if -w_i does) or wholly outside: those parts of
    # V_ij are exact, only the transition is sampled.
    middle, spread = c * tj, s * np.sqrt(np.maximum(0.0, (1.0 - tj) * (1.0 + tj)))
    low = np.clip(middle - spread, ti, 1.0)
    high = np.clip(middle + spread, low, 1.0)
    exact = np.where(c >= tj, _beyond(high, r), 0.0)
    exact = exact + np.where(-c >= tj, np.maximum(0.0, _beyond(ti, r) - _beyond(low, r)), 0.0)
    v = _cap_heights(points, replicates, seed)  # (R, n)
    density = 1.0 / float(beta(0.5, (r + 1) / 2.0))  # f_r(h) = density (1 - h^2)^((r-1)/2)
    overlaps = np.empty((len(row), replicates))
    block = max(1, _CAP_BLOCK_MEMORY // (8 * 4 * replicates * points))
    for start in range(0, len(row), block):
        b = slice(start, start + block)
        width = (high[b] - low[b])[:, None, None]
        h = low[b, None, None] + v * width
        across = (1.0 - h) * (1.0 + h)
        with np.errstate(divide="ignore", invalid="ignore"):
            tau = (tj[b, None, None] - c[b, None, None] * h) / (s[b, None, None] * np.sqrt(across))
        tau = np.where(np.isnan(tau), 1.0, np.clip(tau, -1.0, 1.0))
        weight = density * across ** ((r - 1) / 2.0)
        sampled = np.sum(weight * _slice_share(tau, r - 1), axis=-1) / points * width[..., 0]
        overlaps[b] = sampled * share[b, None]
    # each row's pairs in their order: in any batch, the same sums; the exact parts apart
    # (the replicates' spread is that of the sampled parts alone, without cancellation)
    known, doubled = np.zeros(K), np.zeros((K, replicates))
    np.add.at(known, row, exact * share)
    np.add.at(doubled, row, overlaps)
    # int g(N), g = (N - 1)(N - 2)/2: where three caps meet
    tripled = np.zeros((K, replicates))
    variance = np.zeros(K)
    triple = _triples(unit, t, pairs)
    for k in np.flatnonzero(triple.any(axis=-1)):
        caps = triple[k]
        tripled[k], hits = _triple_term(unit[k][caps], t[k][caps], samples, replicates, seed)
        p = (hits + 0.5) / (samples * replicates + 1.0)
        variance[k] = p * (1.0 - p) / (samples * replicates)
    replicate = doubled - tripled  # each replicate's estimate of sum F - the union - known
    value = np.clip((total - known) - replicate.mean(axis=-1), 0.0, 1.0)
    error = replicate.std(axis=-1, ddof=1) / np.sqrt(replicates)
    # every replicate the same (nothing sampled varied): half a point of each pair's
    # slab, and of the ball where three caps meet
    if np.any(error == 0.0):
        pooled = points * replicates
        slab = np.maximum(0.0, _beyond(low, r) - _beyond(high, r))
        np.add.at(variance, row, (share * slab) ** 2 * (0.5 / (pooled + 1.0)) / pooled)
    return value, np.where(error > 0.0, error, np.sqrt(variance))


@lru_cache(maxsize=8)
def _directions(r: int, count: int, replicates: int, seed: int) -> NDArray[np.float64]:
    """Uniform directions of R^r, ``replicates`` independent sets of ``count``.

    Each set is a low-discrepancy one moved at random so that every point is uniform on
    the sphere: in 2-D ``count`` equally spaced angles turned by a uniform angle; in 3-D
    the spherical Fibonacci lattice (:func:`~polyell.geometry.directions.sphere_directions`)
    turned by a uniform (Haar) rotation; above, scrambled Sobol' points of (0, 1)^r mapped
    to Gaussians and normalized (scipy.stats, whose import takes half a second, only
    there).  From the stream ``(seed, 2)`` of ``numpy.random.default_rng``.

    Returns
    -------
    ndarray, shape (r, replicates * count)
        The coordinates, replicate after replicate.
    """
    rng = np.random.default_rng([seed, 2])
    if r == 2:
        angles = 2.0 * np.pi * (np.arange(count) / count + rng.random((replicates, 1)))
        directions = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    elif r == 3:
        lattice = sphere_directions(count, 3)  # (count, 3)
        # Haar rotations: QR of Gaussian matrices, the signs fixed by R's diagonal
        Q, R = np.linalg.qr(rng.normal(size=(replicates, 3, 3)))
        Q = Q * np.sign(np.diagonal(R, axis1=1, axis2=2))[:, None, :]
        directions = lattice @ np.swapaxes(Q, 1, 2)  # (replicates, count, 3)
    else:
        from scipy.stats import norm, qmc

        exponent = max(0, int(count - 1).bit_length())
        sets = []
        for _ in range(replicates):
            sobol = qmc.Sobol(d=r, scramble=True, seed=rng).random_base2(exponent)[:count]
            sets.append(norm.ppf(np.clip(sobol, 1e-12, 1.0 - 1e-12)))
        gaussian = np.array(sets)
        directions = gaussian / np.sqrt(_dot(gaussian, gaussian))[..., None]
    coordinates = np.ascontiguousarray(directions.reshape(-1, r).T)  # one row each
    coordinates.flags.writeable = False
    return coordinates


def _triple_term(
    unit: NDArray[np.float64], t: NDArray[np.float64], samples: int, replicates: int, seed: int
) -> tuple[NDArray[np.float64], int]:
    """``int g(N)``, ``g = (N - 1)(N - 2)/2``, as a share of the unit ball per replicate.

    Also returned: how many of the sampled rays met three caps at once.

    Along a ray ``s d`` (``0 <= s <= 1``, ``a_j = w_j . d``) cap j holds the s with ``s a_j
    > t_j``: from ``t_j / a_j`` on (``t_j >= 0``, ``a_j > 0``), all of the ray but what
    lies beyond ``t_j / a_j`` (``t_j < 0``: the cap holds E's centre; ``a_j < 0``), all of
    it (``t_j < 0 <= a_j``) or none.  So N is a step function of s, from the number of caps
    that hold the centre, changing by +-1 at the sorted ``t_j / a_j`` below 1, and the
    ray's share ``int g(N(s)) d(s^r)`` is exact (a conditional expectation of a uniform
    point's ``g(N)`` given its direction): only the directions are sampled, ``samples``
    per replicate of :func:`_directions`.
    """
    r, F = unit.shape[-1], len(t)
    count = max(2, samples)
    d = _directions(r, count, replicates, seed)  # (r, R n)
    across = np.empty((F, d.shape[1]))
    for j, w in enumerate(unit):  # w . d, coordinate by coordinate in a fixed order
        np.multiply(d[0], w[0], out=across[j])
        for i in range(1, r):
            across[j] += w[i] * d[i]
    # only rays that three caps reach within the ball can count: the others give 0
    holding = int(np.sum(t < 0.0))  # caps holding the centre reach every ray
    reached = holding + np.count_nonzero((across > t[:, None]) & (t >= 0.0)[:, None], axis=0)
    rays = np.flatnonzero(reached >= 3)
    along = across[:, rays].T  # (rays, F)
    with np.errstate(divide="ignore", invalid="ignore"):
        at = np.where((along > 0.0) == (t >= 0.0), t / along, np.inf)  # an entry or an exit
    at = np.where((at >= 0.0) & (at < 1.0), at, np.inf)
    # the events in order; past a ray's last one (at = inf) every term is 0: the columns
    # beyond the most events of any ray are left out
    events = int(np.max(np.count_nonzero(at < np.inf, axis=-1), initial=0))
    if holding == 0:  # every cap entered, none left: N counts the events so far
        at = np.sort(at, axis=-1)[:, :events]
        counts = np.where(at < np.inf, np.arange(1.0, events + 1.0), 0.0)
    else:
        step = np.where(t >= 0.0, 1.0, -1.0) * np.isfinite(at)
        order = np.argsort(at, axis=-1, kind="stable")[:, :events]
        at = np.take_along_axis(at, order, axis=-1)
        counts = holding + np.cumsum(np.take_along_axis(step, order, axis=-1), axis=-1)
    ends = np.minimum(1.0, at) ** r
    g = np.where(counts >= 3.0, (counts - 1.0) * (counts - 2.0) / 2.0, 0.0)  # after each
    share = np.zeros(len(rays))
    for k in range(events):  # N = counts[k] from the k-th event to the next (or to s = 1)
        following = ends[:, k + 1] if k + 1 < events else np.ones(len(rays))
        share = share + g[:, k] * (following - ends[:, k])
    if holding >= 3:  # before the first event
        share = share + (holding - 1.0) * (holding - 2.0) / 2.0 * ends[:, 0]
    sums = np.bincount(rays // count, weights=share, minlength=replicates)
    return sums / count, int(np.count_nonzero(share > 0.0))
