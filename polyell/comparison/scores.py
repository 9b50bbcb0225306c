r"""Every score of every ellipsoid against the exact set, for K configurations at once.

One implementation for every capacity's sweep: a capacity's batched set builder describes
its sets as :class:`SetBatch` (slabs ``|n . x - mu| <= w``, the one-sided rows that are
facets, the vertices, the volume) and its ellipsoids as ``(centre, axes, semi-axes,
witness)``; this module turns them into the columns of ``Comparison.to_row`` -- inscribed
and enclosing scales, coverage and overreach (exact inside or around the set, else the
union of the caps beyond the facets, :func:`~polyell.comparison.metrics.cap_union_share`,
as :func:`~polyell.comparison.metrics.overlap` computes them), volume ratios to the MVIE
and the outer ellipsoid, directional statistics
(:func:`~polyell.comparison.directional.direction_scores`) and witnesses.  ``compare``
still scores one set at a time with the functions of :mod:`~polyell.comparison.metrics`
(the same closed forms and estimate; the tests hold the two equal to 1e-12): making it
this module's batch of one is the open part of issue 31.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.directional import direction_scores
from polyell.comparison.metrics import INSIDE_RTOL, cap_union_share, scale_rtol
from polyell.geometry.ellipsoid import unit_ball_volume
from polyell.geometry.limits import facet_slack, rounding_floor

__all__ = ["EllipsoidBatch", "SetBatch", "polytope_columns", "score_ellipsoids"]

Array = NDArray[np.float64]

#: The scores of an undefined ellipsoid that are 0, not NaN (as ``Comparison.to_row``).
_COUNTS = ("feasibility_mismatch", "directions_used")


class SetBatch(NamedTuple):
    """The exact sets of K configurations, full-dimensional, bounded and not empty.

    Attributes
    ----------
    center : ndarray, shape (K, m)
        A point inside each set (``x_g`` of a zonotope, ``h0`` of a force set): the facets'
        offsets are taken about it.
    normals : ndarray, shape (K, S, m)
        Unit normals of the slabs ``|n . x - mu| <= w`` (zero rows: no constraint).
    widths : ndarray, shape (K, S)
        Their half-widths ``w`` (inf: no constraint).
    midpoints : ndarray, shape (K, S)
        Their middles ``mu`` along the normal.
    offsets : ndarray, shape (K, 2S)
        The one-sided rows' offsets about ``center``: ``n . (x - center) <= offset`` for
        ``+n`` then ``-n`` (inf: no constraint).
    facet : ndarray of bool, shape (K, 2S)
        The one-sided rows (``+n`` then ``-n``) that are facets.
    vertices : ndarray, shape (K, V, m), or None
        The vertices (padded; see ``is_vertex``), or None where not enumerated.
    is_vertex : ndarray of bool, shape (K, V), or None
    volume : ndarray, shape (K,)
    size : ndarray, shape (K,)
        A bound on the distance of any point of the set from ``center`` (tolerances).
    terms : int
        Rounding terms of a facet's evaluation (:func:`~polyell.geometry.limits.facet_slack`).
    rtol_terms : int
        The ``n`` of :func:`~polyell.comparison.metrics.scale_rtol`.
    """

    center: Array
    normals: Array
    widths: Array
    midpoints: Array
    offsets: Array
    facet: NDArray[np.bool_]
    vertices: Array | None
    is_vertex: NDArray[np.bool_] | None
    volume: Array
    size: Array
    terms: int
    rtol_terms: int

    def one_sided(self) -> tuple[Array, Array]:
        """The one-sided rows' unit normals (K, 2S, m) and offsets from the origin (K, 2S)."""
        from_origin = np.concatenate(
            [self.widths + self.midpoints, self.widths - self.midpoints], axis=1
        )
        return np.concatenate([self.normals, -self.normals], axis=1), from_origin


class EllipsoidBatch(NamedTuple):
    """K ellipsoids ``{c + U diag(s) u : |u| <= 1}`` and their witnesses.

    Attributes
    ----------
    center : ndarray, shape (K, m)
    axes : ndarray, shape (K, m, m)
    semi : ndarray, shape (K, m)
        Semi-axes, positive; NaN in a row where the ellipsoid is undefined (an MVIE the
        solver did not certify): its scores are then NaN, as in ``compare``.
    witness : ndarray, shape (K,)
        The largest normalised joint quantity over the ellipsoid (> 1: it promises what the
        arm cannot do).
    """

    center: Array
    axes: Array
    semi: Array
    witness: Array


def polytope_columns(sets: SetBatch) -> dict[str, Array]:
    """``polytope_dim``, ``polytope_volume`` and the isotropic radii of each set.

    The ball radius is the smallest facet offset about the centre; the origin radius the
    smallest from the origin, NaN where the origin lies outside (by more than
    :func:`~polyell.geometry.limits.facet_slack`), as ``ConvexSet.origin_radius``.
    """
    K, _, m = sets.normals.shape
    _, from_origin = sets.one_sided()
    from_center = sets.offsets
    reach = np.linalg.norm(sets.center, axis=-1) + sets.size
    slack = facet_slack(from_center, reach[:, None], sets.terms)
    inside = np.all(~sets.facet | (from_origin >= -slack), axis=-1)
    origin = np.maximum(0.0, np.min(np.where(sets.facet, from_origin, np.inf), axis=-1))
    ball = np.maximum(0.0, np.min(np.where(sets.facet, from_center, np.inf), axis=-1))
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
    """The ``<kind>_<score>`` columns of every ellipsoid (``Comparison.to_row``).

    Parameters
    ----------
    sets : SetBatch
    ellipsoids : dict of str to EllipsoidBatch
        The kinds, in column order; ``"mvie"`` and ``"outer"``, where present, are the
        denominators of every ``mvie_ratio`` and ``outer_ratio`` (NaN otherwise).
    directions : ndarray, shape (k, m)
        Unit directions of the directional statistics.
    samples, seed : int
        The sampling budget and seed of :func:`~polyell.comparison.metrics.cap_union_share`,
        as in :func:`polyell.compare`, where an ellipsoid is neither inside nor around the
        set and its caps meet.

    Returns
    -------
    columns : dict of str to ndarray (K,)
    undecided : ndarray of bool, shape (K,)
        Rows with an ellipsoid that is not inside the set where the vertices are not
        enumerated: whether it lies around the set (exact shares) is not known here.
    """
    K, _, m = sets.normals.shape
    undecided = np.zeros(K, dtype=bool)
    normals, _ = sets.one_sided()
    from_center = sets.offsets
    unit_ball = unit_ball_volume(m)
    optimum = {
        name: unit_ball * np.prod(ellipsoids[name].semi, axis=-1) if name in ellipsoids else None
        for name in ("mvie", "outer")
    }
    center_norm = np.linalg.norm(sets.center, axis=-1)
    records: list[dict[str, Array]] = []
    scored, undefined = [], []
    for E in ellipsoids.values():
        defined = np.asarray(~np.isnan(E.semi).any(axis=-1), dtype=bool)
        semi = np.where(defined[:, None], E.semi, 1.0)  # undefined rows: NaN below
        shift = E.center - sets.center
        reach = np.linalg.norm((normals @ E.axes) * semi[:, None, :], axis=-1)
        slacks = from_center - np.einsum("kfm,km->kf", normals, shift)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.min(np.where(sets.facet, slacks / reach, np.inf), axis=-1)
        enclosing = np.full(K, np.nan)
        if sets.vertices is not None and sets.is_vertex is not None:
            local = ((sets.vertices - E.center[:, None, :]) @ E.axes) / semi[:, None, :]
            norms = np.linalg.norm(local, axis=-1)
            enclosing = np.max(np.where(sets.is_vertex, norms, 0.0), axis=-1)
        volume = unit_ball * np.prod(semi, axis=-1)
        extent = np.maximum(np.maximum(center_norm, np.linalg.norm(E.center, axis=-1)), sets.size)
        rtol = np.maximum(
            INSIDE_RTOL, scale_rtol(extent, np.min(semi, axis=-1), m, sets.rtol_terms)
        )
        inside = (scale >= 1.0 - rtol) | ~defined  # (undefined: no estimate)
        if sets.vertices is None:
            undecided |= ~inside
            inside |= undecided
        shares = _shares(
            inside,
            enclosing <= 1.0 + rtol,
            volume / sets.volume,
            (E.axes, semi, normals, slacks, sets.facet),
            samples,
            seed,
        )
        record = {
            "dimension": np.full(K, float(m)),
            "volume": volume,
            "inscribed_scale": scale,
            "enclosing_scale": enclosing,
            **dict(
                zip(
                    ("coverage", "overreach", "coverage_stderr", "overreach_stderr"),
                    shares,
                    strict=True,
                )
            ),
            "witness_torque_max": np.array(E.witness, dtype=float),
        }
        for name, volumes in optimum.items():
            record[f"{name}_ratio"] = np.full(K, np.nan) if volumes is None else volume / volumes
        records.append(record)
        scored.append((E.center, E.axes, semi))
        undefined.append(~defined)
    # The directional limits: slabs about their own middles (Polytope.limits' tolerances).
    reach = 2.0 * (center_norm + sets.size)
    statistics = direction_scores(
        sets.normals,
        sets.widths,
        sets.midpoints,
        facet_slack(sets.widths, reach[:, None], sets.terms),
        rounding_floor(reach[:, None], sets.terms),
        scored,
        directions,
    )
    rows: dict[str, Array] = {}
    for kind, record, stats, missing in zip(
        ellipsoids, records, statistics, undefined, strict=True
    ):
        record |= stats
        if missing.any():  # an ellipsoid undefined here: NaN, as in compare
            for name, values in record.items():
                values[missing] = 0.0 if name in _COUNTS else np.nan
        rows |= {f"{kind}_{name}": values for name, values in record.items()}
    return rows, undecided


def _shares(
    inside: NDArray[np.bool_],
    around: NDArray[np.bool_],
    ratio: Array,
    sets: tuple[Array, Array, Array, Array, NDArray[np.bool_]],
    samples: int,
    seed: int,
) -> tuple[Array, Array, Array, Array]:
    """Coverage, overreach and their standard errors, as in ``metrics.overlap``.

    Exact inside or around P; else the share of E outside, the union of its caps beyond
    the facets (:func:`~polyell.comparison.metrics.cap_union_share`: exact where no two
    meet, else estimated with its standard error), all crossing rows at once.
    """
    coverage = np.where(inside, np.minimum(1.0, ratio), 1.0)
    overreach = np.where(inside, 0.0, np.maximum(0.0, 1.0 - 1.0 / ratio))
    coverage_err, overreach_err = np.zeros_like(ratio), np.zeros_like(ratio)
    axes, semi, normals, slacks, facet = sets
    crossing = ~inside & ~around
    if crossing.any():
        reach_vectors = (normals[crossing] @ axes[crossing]) * semi[crossing][:, None, :]
        outside, stderr = cap_union_share(
            reach_vectors, np.where(facet, slacks, np.inf)[crossing], samples=samples, seed=seed
        )
        coverage[crossing] = np.minimum(1.0, (1.0 - outside) * ratio[crossing])
        overreach[crossing] = outside
        coverage_err[crossing], overreach_err[crossing] = stderr * ratio[crossing], stderr
    return coverage, overreach, coverage_err, overreach_err
