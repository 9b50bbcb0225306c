r"""Every score of every ellipsoid against the exact set, for K configurations at once.

The one implementation of the scores (DESIGN.md section 2), for every capacity and every
path: a capacity's set builder describes its sets as a :class:`SetBatch` (one-sided facet
rows about a centre, the vertices, the volume; for the sweeps' directional limits also the
rows as slabs ``|n . x - mu| <= w``) and its ellipsoids as an :class:`EllipsoidBatch`; this
module turns them into the columns of ``Comparison.to_row``: inscribed and enclosing scales
(:func:`fit`), coverage and overreach (:func:`shares`: exact inside or around the set, else
the union of the caps beyond the facets, :func:`~polyell.comparison.caps.cap_union_share`),
volume ratios to the MVIE and the outer ellipsoid, directional statistics
(:func:`~polyell.comparison.directional.statistics`) and witnesses (:func:`witness`).
``compare`` is the batch of one (:func:`set_of`, :func:`ellipsoid_of`); the sweeps, the
posture choice and the scalar functions of :mod:`~polyell.comparison.metrics` call the
same functions.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.caps import cap_union_share
from polyell.comparison.directional import direction_scores
from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid, unit_ball_volume
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.limits import facet_slack, parallel_slopes, rounding_floor
from polyell.geometry.polytope import Polytope
from polyell.validation import as_floats, check_integer

__all__ = [
    "INSIDE_RTOL",
    "ROUNDING_FACTOR",
    "EllipsoidBatch",
    "Fit",
    "SetBatch",
    "Slabs",
    "ellipsoid_of",
    "fit",
    "polytope_columns",
    "scale_rtol",
    "score_ellipsoids",
    "set_of",
    "shape_scores",
    "shares",
    "witness",
]

Array = NDArray[np.float64]

#: The scores of an undefined ellipsoid that are 0, not NaN (as ``Comparison.to_row``).
_COUNTS = ("feasibility_mismatch", "directions_used")

#: Floor of the tolerance of "inside" and "around" (:attr:`Fit.rtol`): an ellipsoid within
#: this relative scale of touching counts as touching.  Treating ``c + (1 - d)(E - c)
#: inside P`` as ``E inside P`` makes the exact coverage err by at most ``1 - (1 - d)^r <=
#: r d`` relative (6e-9 in 6-D), far below the standard error of any estimate it replaces.
INSIDE_RTOL = 1e-9
#: Rounding errors of a scale, in units of ``eps * extent / s_min`` (see :func:`scale_rtol`).
ROUNDING_FACTOR = 16.0


def scale_rtol(
    extent: float | Array,
    smallest_axis: float | Array,
    m: int,
    n: int,
) -> float | Array:
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
    m, n = check_integer("m", m, 0, 2**31), check_integer("n", n, 0, 2**31)
    extent, smallest = as_floats("extent", extent), as_floats("smallest_axis", smallest_axis)
    with np.errstate(divide="ignore"):
        result: float | Array = ROUNDING_FACTOR * (m + n) * eps * extent / smallest
    return result


class Slabs(NamedTuple):
    """A batch's facet rows as slabs ``|n . x - mu| <= w`` (for the sweeps' limits).

    Attributes
    ----------
    normals : ndarray, shape (K, S, m)
        Unit normals, one of each +-pair (zero rows: no constraint).
    widths : ndarray, shape (K, S)
        Half-widths ``w`` (inf: no constraint).
    midpoints : ndarray, shape (K, S)
        Middles ``mu`` along the normal.
    """

    normals: Array
    widths: Array
    midpoints: Array


class SetBatch(NamedTuple):
    """The exact sets of K configurations, not empty, in their affine sets.

    Attributes
    ----------
    center : ndarray, shape (K, m)
        A point inside each set (``x_g`` of a zonotope, ``h0`` of a force set): the facets'
        offsets are taken about it.
    normals : ndarray, shape (K, F, m)
        Unit outward normals of the one-sided rows ``n . (x - center) <= offset``.
    offsets : ndarray, shape (K, F)
        Their offsets about ``center`` (inf: no constraint).
    facet : ndarray of bool, shape (K, F)
        The rows that are facets (the others are implied by them).
    vertices : ndarray, shape (K, V, m), or None
        The vertices (padded; see ``is_vertex``), or None where not enumerated.
    is_vertex : ndarray of bool, shape (K, V), or None
    volume : ndarray, shape (K,)
        In the affine set; inf for an unbounded set (inside no ellipsoid).
    size : ndarray, shape (K,)
        A bound on the distance of any point of the set from ``center`` (tolerances).
    terms : int
        Rounding terms of a facet's evaluation (:func:`~polyell.geometry.limits.facet_slack`).
    rtol_terms : int
        The ``n`` of :func:`scale_rtol`.
    slabs : Slabs or None
        The same rows as slabs, ``normals`` being ``+n`` then ``-n`` of theirs: what the
        sweeps' directional limits take (:func:`score_ellipsoids`).
    """

    center: Array
    normals: Array
    offsets: Array
    facet: NDArray[np.bool_]
    vertices: Array | None
    is_vertex: NDArray[np.bool_] | None
    volume: Array
    size: Array
    terms: int
    rtol_terms: int
    slabs: Slabs | None = None


class EllipsoidBatch(NamedTuple):
    """K ellipsoids ``{c + U diag(s) u : |u| <= 1}`` and their witnesses.

    Attributes
    ----------
    center : ndarray, shape (K, m)
    axes : ndarray, shape (K, m, r)
        Orthonormal axes spanning the set's affine set (r = m for a full-dimensional set).
    semi : ndarray, shape (K, r)
        Semi-axes, positive; NaN in a row where the ellipsoid is undefined (an MVIE the
        solver did not certify): its scores are then NaN, as in ``compare``.
    witness : ndarray, shape (K,)
        The largest normalised joint quantity over the ellipsoid (> 1: it promises what the
        arm cannot do; :func:`witness`).
    """

    center: Array
    axes: Array
    semi: Array
    witness: Array


def witness(matrix: Array, at_center: Array, axes: Array, semi: Array) -> Array:
    """Largest ``|W x + w|_inf`` over the ellipsoids, exactly.

    At the boundary points ``x = c + U diag(s) u``, ``|u| = 1``, row i of ``W x + w`` is at
    most ``|(W c + w)_i| + |(W U diag(s))_i|`` (Cauchy-Schwarz, attained).

    Parameters
    ----------
    matrix : ndarray, shape (K, n, m)
        ``W``, the normalised joint quantity's linear part (torques or joint velocities).
    at_center : ndarray, shape (K, n)
        ``W c + w`` at each ellipsoid's centre.
    axes : ndarray, shape (K, m, r)
    semi : ndarray, shape (K, r)

    Returns
    -------
    ndarray, shape (K,)
    """
    spread = np.linalg.norm((matrix @ axes) * semi[:, None, :], axis=-1)
    result: Array = np.max(np.abs(at_center) + spread, axis=-1)
    return result


def set_of(P: Polytope | HPolytope) -> SetBatch:
    """One polytope as a batch of one (not empty; unbounded: volume inf).

    A zonotope's offsets are its support function ``h_i = sum_j |a_i . M_j|`` from the
    generators (``b - A xg`` would lose the digits of h when P is small against its distance
    from the origin); an H-polytope's are ``b - A c`` (its facets are its data).
    """
    if isinstance(P, HPolytope):
        offsets, size, terms, rtol_terms = P.half_widths, P._size(), P.ambient_dim + 2, 2
    else:
        offsets = np.abs(P.A @ P.generators).sum(axis=1)
        size = float(np.linalg.norm(P.generators, axis=0).sum())
        terms, rtol_terms = P._terms, int(P.generators.shape[1])
    return SetBatch(
        center=P.center[None],
        normals=P.A[None],
        offsets=offsets[None],
        facet=np.ones((1, len(offsets)), dtype=bool),
        vertices=P.vertices[None],
        is_vertex=np.ones((1, len(P.vertices)), dtype=bool),
        volume=np.array([P.volume]),
        size=np.array([size]),
        terms=terms,
        rtol_terms=rtol_terms,
    )


def ellipsoid_of(
    E: Ellipsoid, matrix: Array | None = None, at_center: Array | None = None
) -> EllipsoidBatch:
    """One ellipsoid as a batch of one, its witness from ``W`` (n, m) and ``W c + w`` (n,)."""
    w = np.array([np.nan])
    if matrix is not None and at_center is not None:
        w = witness(matrix[None], at_center[None], E.axes[None], E.semi_axes[None])
    return EllipsoidBatch(E.center[None], E.axes[None], E.semi_axes[None], w)


class Fit(NamedTuple):
    """How an ellipsoid fits each set of a batch (:func:`fit`).

    Attributes
    ----------
    inscribed : ndarray, shape (K,)
        Largest ``k`` with ``c + k (E - c)`` inside the set: ``min_i (b_i - a_i . c) /
        |diag(s) U^T a_i|`` over the facets; at least 1 iff E is inside, negative if even
        its centre is outside; for a point ellipsoid ``inf`` (its centre in the set) or
        ``-inf``.
    enclosing : ndarray, shape (K,)
        Smallest ``k`` with the set inside ``c + k (E - c)``: the largest
        ``|diag(s)^-1 U^T (v - c)|`` over the vertices (inf for an unbounded set, NaN
        where the vertices are not enumerated).
    rtol : ndarray, shape (K,)
        The tolerance of "inside" and "around": the larger of :data:`INSIDE_RTOL` and the
        rounding bound of the scales (:func:`scale_rtol`), so that an ellipsoid that touches
        (the new ellipsoid of a parallelotope, the MVIE, the outer ellipsoid) is never sent
        to an estimate by rounding errors.
    slacks : ndarray, shape (K, F)
        ``b_i - a_i . c``: the rows' offsets about the ellipsoid's centre.
    reach : ndarray, shape (K, F, r)
        ``diag(s) U^T a_i``: the rows in the ellipsoid's unit-ball coordinates.
    """

    inscribed: Array
    enclosing: Array
    rtol: Array
    slacks: Array
    reach: Array


def fit(sets: SetBatch, E: EllipsoidBatch) -> Fit:
    """The inscribed and enclosing scales of ``E`` in each set, and their tolerance.

    The slacks are taken about the sets' centres (``h_i - a_i . (c - center)``), so a scale
    keeps its digits however far the set is from the origin.  Rows where ``E`` is undefined
    (NaN semi-axes) give NaN.
    """
    shift = E.center - sets.center
    reach = (sets.normals @ E.axes) * E.semi[:, None, :]
    slacks = sets.offsets - np.einsum("kfm,km->kf", sets.normals, shift)
    lengths = np.linalg.norm(reach, axis=-1)
    center_norm = np.linalg.norm(sets.center, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = slacks / lengths
    # A point ellipsoid (r = 0): its centre is inside the facets, to rounding, or not.
    tolerance = facet_slack(sets.offsets, (center_norm + sets.size)[:, None], sets.terms)
    ratios = np.where(lengths > 0, ratios, np.where(slacks >= -tolerance, np.inf, -np.inf))
    inscribed = np.min(np.where(sets.facet, ratios, np.inf), axis=-1, initial=np.inf)
    inscribed = np.where(np.isnan(E.semi).any(axis=-1), np.nan, inscribed)
    enclosing = np.full(len(shift), np.nan)
    if sets.vertices is not None and sets.is_vertex is not None:
        local = ((sets.vertices - E.center[:, None, :]) @ E.axes) / E.semi[:, None, :]
        norms = np.linalg.norm(local, axis=-1)
        enclosing = np.max(np.where(sets.is_vertex, norms, 0.0), axis=-1, initial=0.0)
        enclosing = np.where(np.isnan(E.semi).any(axis=-1), np.nan, enclosing)
    enclosing = np.where(np.isinf(sets.volume), np.inf, enclosing)
    extent = np.maximum(np.maximum(center_norm, np.linalg.norm(E.center, axis=-1)), sets.size)
    smallest = np.min(E.semi, axis=-1, initial=np.inf)
    rtol = np.maximum(
        INSIDE_RTOL,
        np.nan_to_num(scale_rtol(extent, smallest, sets.normals.shape[-1], sets.rtol_terms)),
    )
    return Fit(inscribed, enclosing, rtol, slacks, reach)


def shares(
    sets: SetBatch,
    E: EllipsoidBatch,
    scales: Fit,
    *,
    samples: int,
    seed: int,
    replicates: int = 8,
) -> tuple[Array, Array, Array, Array]:
    r"""Coverage ``vol(E & P) / vol(P)``, overreach ``vol(E \ P) / vol(E)`` and their errors.

    Exact when E is inside P (``inscribed >= 1 - rtol``: coverage ``vol(E) / vol(P)``,
    overreach 0) and when E contains P (``enclosing <= 1 + rtol``: coverage 1, overreach
    ``1 - vol(P) / vol(E)``).  Otherwise ``E \ P`` is the union of E's caps beyond P's
    facets, whose share of E comes from :func:`~polyell.comparison.caps.cap_union_share`
    (exact where no two caps meet, else estimated with its standard error from
    ``replicates`` scramblings of ``seed``, at the budget ``samples``); coverage is ``(1 -
    share outside) vol(E) / vol(P)``, at most 1.  Rows where E is undefined: NaN.

    Returns
    -------
    coverage, overreach, coverage_stderr, overreach_stderr : ndarray, shape (K,)
    """
    r = E.semi.shape[-1]
    volume = unit_ball_volume(r) * np.prod(E.semi, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = volume / sets.volume
    inside = scales.inscribed >= 1.0 - scales.rtol
    around = scales.enclosing <= 1.0 + scales.rtol
    coverage = np.where(inside, np.minimum(1.0, ratio), 1.0)
    with np.errstate(divide="ignore"):
        overreach = np.where(inside, 0.0, np.maximum(0.0, 1.0 - 1.0 / ratio))
    coverage_err, overreach_err = np.zeros_like(ratio), np.zeros_like(ratio)
    crossing = ~inside & ~around & ~np.isnan(scales.inscribed)
    if crossing.any():
        slacks = np.where(sets.facet, scales.slacks, np.inf)[crossing]
        outside, stderr = cap_union_share(
            scales.reach[crossing], slacks, samples=samples, replicates=replicates, seed=seed
        )
        coverage[crossing] = np.minimum(1.0, (1.0 - outside) * ratio[crossing])
        overreach[crossing] = outside
        coverage_err[crossing], overreach_err[crossing] = stderr * ratio[crossing], stderr
    undefined = np.isnan(scales.inscribed)
    return tuple(  # type: ignore[return-value]
        np.where(undefined, np.nan, values)
        for values in (coverage, overreach, coverage_err, overreach_err)
    )


def shape_scores(
    sets: SetBatch,
    ellipsoids: dict[str, EllipsoidBatch],
    samples: int,
    seed: int,
) -> tuple[dict[str, dict[str, Array]], NDArray[np.bool_]]:
    """Every score but the directional ones, of every ellipsoid (``Comparison.to_row``).

    Parameters
    ----------
    sets : SetBatch
    ellipsoids : dict of str to EllipsoidBatch
        The kinds, in column order; ``"mvie"`` and ``"outer"``, where present, are the
        denominators of every ``mvie_ratio`` and ``outer_ratio`` (NaN otherwise).
    samples, seed : int
        The budget and seed of the estimate where an ellipsoid is neither inside nor around
        a set and its caps meet (:func:`shares`).

    Returns
    -------
    records : dict of str to dict of str to ndarray (K,)
        Per kind: ``dimension``, ``volume``, ``inscribed_scale``, ``enclosing_scale``,
        ``coverage``, ``overreach`` and their standard errors, ``witness_torque_max``,
        ``mvie_ratio``, ``outer_ratio``.
    undecided : ndarray of bool, shape (K,)
        Rows with an ellipsoid that is not inside the set where the vertices are not
        enumerated: whether it lies around the set (exact shares) is not known here.
    """
    K = len(sets.center)
    undecided = np.zeros(K, dtype=bool)
    optimum = {
        name: unit_ball_volume(ellipsoids[name].semi.shape[-1])
        * np.prod(ellipsoids[name].semi, axis=-1)
        if name in ellipsoids
        else np.full(K, np.nan)
        for name in ("mvie", "outer")
    }
    records: dict[str, dict[str, Array]] = {}
    for kind, E in ellipsoids.items():
        r = E.semi.shape[-1]
        scales = fit(sets, E)
        assumed = scales
        if sets.vertices is None:  # around the set or not: unknown here
            unknown = ~(scales.inscribed >= 1.0 - scales.rtol) & ~np.isnan(scales.inscribed)
            undecided |= unknown
            assumed = scales._replace(inscribed=np.where(unknown, np.inf, scales.inscribed))
        coverage = shares(sets, E, assumed, samples=samples, seed=seed)
        volume = unit_ball_volume(r) * np.prod(E.semi, axis=-1)
        records[kind] = {
            "dimension": np.full(K, float(r)),
            "volume": volume,
            "inscribed_scale": scales.inscribed,
            "enclosing_scale": scales.enclosing,
            **dict(
                zip(
                    ("coverage", "overreach", "coverage_stderr", "overreach_stderr"),
                    coverage,
                    strict=True,
                )
            ),
            "witness_torque_max": np.array(E.witness, dtype=float),
            "mvie_ratio": volume / optimum["mvie"],
            "outer_ratio": volume / optimum["outer"],
        }
    return records, undecided


def polytope_columns(sets: SetBatch) -> dict[str, Array]:
    """``polytope_dim``, ``polytope_volume`` and the isotropic radii of each set.

    The ball radius is the smallest facet offset about the centre; the origin radius the
    smallest from the origin, NaN where the origin lies outside (by more than
    :func:`~polyell.geometry.limits.facet_slack`), as ``ConvexSet.origin_radius``.
    """
    K, _, m = sets.normals.shape
    from_center = sets.offsets
    from_origin = from_center + np.einsum("kfm,km->kf", sets.normals, sets.center)
    reach = np.linalg.norm(sets.center, axis=-1) + sets.size
    slack = facet_slack(from_center, reach[:, None], sets.terms)
    inside = np.all(~sets.facet | (from_origin >= -slack), axis=-1)
    origin = np.maximum(
        0.0, np.min(np.where(sets.facet, from_origin, np.inf), axis=-1, initial=np.inf)
    )
    ball = np.maximum(
        0.0, np.min(np.where(sets.facet, from_center, np.inf), axis=-1, initial=np.inf)
    )
    return {
        "polytope_dim": np.full(K, float(m)),
        "polytope_volume": sets.volume,
        "polytope_ball_radius": ball,
        "polytope_origin_radius": np.where(inside, origin, np.nan),
    }


def score_ellipsoids(
    sets: SetBatch,
    ellipsoids: dict[str, EllipsoidBatch],
    directions: Array,
    samples: int,
    seed: int,
) -> tuple[dict[str, Array], NDArray[np.bool_]]:
    """The ``<kind>_<score>`` columns of every ellipsoid, for a sweep.

    :func:`shape_scores`, then the directional statistics of every ellipsoid on
    ``directions`` (k, m), the polytopes' far ends taken from ``sets.slabs`` by the
    sweeps' cache-sized passes (:func:`~polyell.comparison.directional.direction_scores`).
    Rows where an ellipsoid is undefined get NaN (counts 0), as in ``compare``.

    Returns
    -------
    columns : dict of str to ndarray (K,)
    undecided : ndarray of bool, shape (K,)
        As :func:`shape_scores`.
    """
    if sets.slabs is None:
        raise InputError(
            "sets",
            "a SetBatch with its slabs",
            "slabs=None",
            "pass a batch built with slabs, e.g. batch.as_set_batch(), or use shape_scores",
        )
    records, undecided = shape_scores(sets, ellipsoids, samples, seed)
    # The directional limits: slabs about their own middles (Polytope.limits' tolerances).
    slabs = sets.slabs
    reach = 2.0 * (np.linalg.norm(sets.center, axis=-1) + sets.size)
    slack = facet_slack(slabs.widths, reach[:, None], sets.terms)
    statistics = direction_scores(
        slabs.normals,
        slabs.widths,
        slabs.midpoints,
        slack,
        rounding_floor(reach[:, None], sets.terms),
        [(E.center, E.axes, np.where(np.isnan(E.semi), 1.0, E.semi)) for E in ellipsoids.values()],
        directions,
        parallel_slopes(slack, reach[:, None]),  # as Polytope.limits decides it
    )
    rows: dict[str, Array] = {}
    for (kind, record), stats, E in zip(
        records.items(), statistics, ellipsoids.values(), strict=True
    ):
        record |= stats
        missing = np.isnan(E.semi).any(axis=-1)
        if missing.any():  # an ellipsoid undefined here: NaN, as in compare
            for name, values in record.items():
                values[missing] = 0.0 if name in _COUNTS else np.nan
        rows |= {f"{kind}_{name}": values for name, values in record.items()}
    return rows, undecided
