r"""Scores of many configurations at once: the vectorised path behind :func:`polyell.sweep`.

For K configurations sharing (m, n) every step of :func:`polyell.compare` is done with
batched linear algebra: M and x_g (eq. 8, 14), the SVD of M (eq. 35), the closed-form
zonotope facets and volume, both ellipsoids (from the SVDs of M and of
F = L^-1 B J^+), the MVIE, the outer ellipsoid and user-defined candidates
(:mod:`polyell.studies.block_sets`), inscribed and enclosing scales, directional limits
(rays against facets, eq. 24), the directional statistics and the exact torque witnesses.
Both definitions always lie inside the polytope (E_yoshikawa within E_chiacchio within P)
and the outer ellipsoid around it, so coverage and overreach are exact.  Configurations
this path does not cover -- a rank below m (singular), vertices (when they are needed)
not in general position for m > 3 or decided too near a tolerance
(:func:`~polyell.studies.block_sets.vertex_signs`), an ellipsoid neither inside nor around
P to rounding -- are returned as a mask for the scalar path, so every row equals
``compare(analyze(...)).to_row()``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple, cast

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import capacity_class, check_capacity
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.comparison.candidates import Candidate
from polyell.comparison.comparison import COMPARED_KINDS, SCORE_NAMES, compared_kinds
from polyell.comparison.scores import (
    EllipsoidBatch,
    SetBatch,
    Slabs,
    polytope_columns,
    score_ellipsoids,
    witness,
)
from polyell.geometry.subspace import RANK_RTOL
from polyell.geometry.zonotope import cross, subsets
from polyell.inverse import classic_terms
from polyell.models.dynamics import Dynamics
from polyell.studies.block_sets import (
    candidate_ellipsoid,
    facets,
    log_det_ellipsoid,
    vertex_count,
    vertex_signs,
)

__all__ = ["BatchOptions", "BlockSets", "batch_rows", "block_sets", "score_columns"]

Array = NDArray[np.float64]


def score_columns(
    candidates: Sequence[Candidate] = (), capacity: str = "acceleration"
) -> list[str]:
    """The score columns of a results row, in order (``Comparison.to_row``).

    ``<kind>_<score>`` over :func:`~polyell.comparison.comparison.compared_kinds` of the
    capacity (``static_*`` for forces, no ``chiacchio_*`` for velocities), then the
    candidates'.
    """
    columns = ["polytope_dim", "polytope_volume", "polytope_ball_radius", "polytope_origin_radius"]
    kinds = (*compared_kinds(check_capacity(capacity)), *(c.name for c in candidates))
    return columns + [f"{kind}_{name}" for kind in kinds for name in SCORE_NAMES]


@dataclass(frozen=True)
class BatchOptions:
    """What a batch computes beyond both ellipsoid definitions.

    Attributes
    ----------
    mvie, outer : bool
        Score the maximum-volume inscribed / minimum-volume enclosing ellipsoid (batched
        log-det solver) and every ``mvie_ratio`` / ``outer_ratio``; NaN otherwise.
    vertices : bool
        Enumerate the vertices (needed by ``outer`` and by every ``enclosing_scale``, NaN
        otherwise; an ellipsoid neither inside nor around P then takes the scalar path).
    candidates : tuple of Candidate
        User-defined ellipsoids.
    rank_rtol : float
        Rank tolerance, as in :func:`polyell.analyze`.
    capacity : str
        The capacity of :func:`polyell.analyze` (``"acceleration"``, ``"velocity"``,
        ``"force"``); the batch path computes accelerations, velocities as accelerations of
        an arm with ``B = I`` and no gravity (the same zonotope); forces take
        :func:`polyell.studies.force_batch.force_rows`.
    samples, seed : int
        The sampling budget and seed of a share estimate, as in :func:`polyell.compare`
        (:func:`~polyell.comparison.caps.cap_union_share`).
    """

    mvie: bool = False
    outer: bool = False
    vertices: bool = False
    candidates: tuple[Candidate, ...] = ()
    rank_rtol: float = RANK_RTOL
    samples: int = 2**13
    seed: int = 0
    capacity: str = "acceleration"


def _zonotope_volume(s: Array, V1t: Array) -> Array:
    """``2^m prod(s) sum_{|S| = m} |det (V^T)_S|`` for every configuration (K,).

    As :attr:`Polytope.volume`: the whitened determinants keep their relative accuracy
    however thin the zonotope.
    """
    _, m, n = V1t.shape
    blocks = np.transpose(V1t[:, :, subsets(n, m)], (0, 2, 1, 3))  # (K, C, m, m)
    if m in (2, 3):  # det = last column . cofactors of the others
        dets = np.einsum("...i,...i->...", cross(blocks[..., :-1]), blocks[..., -1])
    else:
        dets = np.linalg.det(blocks)
    return 2.0**m * np.prod(s, axis=-1) * np.abs(dets).sum(axis=-1)


#: Rows with ``sigma_min / sigma_max`` within this relative band above ``rank_rtol`` take
#: the scalar path, which makes the rank decision (far wider than any rounding difference
#: between the two computations of M and its SVD, and met by almost no configuration).
RANK_BAND = 1e-2

#: Configurations processed together: large enough to amortise numpy's per-call cost,
#: small enough for the (block, facets, directions) arrays to stay in cache.
BLOCK = 512
#: Memory for the largest temporaries of a block, (block, facets, m + n) arrays: a 6-D
#: task of a 20-joint arm has 15,504 facet pairs, so its blocks shrink to a few rows.
BLOCK_MEMORY = 256 * 2**20


def block_size(m: int, n: int, vertices: bool = False) -> int:
    """Rows per block: BLOCK, or fewer so that a block's temporaries fit BLOCK_MEMORY."""
    count = max(1, math.comb(n, m - 1)) if m > 1 else 1  # no facets for m > n + 1
    per_row = 8 * count * (m + n) * 4  # float64; about four arrays of that shape at once
    if vertices:  # the vertex codes (sorted in place) and the sign vectors
        per_row += 8 * count * 2 ** (m - 1) * 3 + 8 * vertex_count(m, n) * (n + 2 * m)
    return max(1, min(BLOCK, BLOCK_MEMORY // per_row))


def batch_rows(
    dyn: Dynamics,
    tau_max: Array,
    tau_min: Array,
    directions: Array,
    options: BatchOptions = BatchOptions(),
) -> tuple[dict[str, Array], NDArray[np.bool_]]:
    """Score columns of a batch, and which rows need the scalar path.

    Parameters
    ----------
    dyn : Dynamics
        A batch: J (K, m, n), B (K, n, n), g (K, n), xdd_bias (K, m).
    tau_max, tau_min : ndarray, shape (n,)
        Torque limits [N m].
    directions : ndarray, shape (k, m)
        Unit directions of the directional statistics.
    options : BatchOptions
        The optional sets and scores, and the rank tolerance.

    Returns
    -------
    columns : dict of str to ndarray (K,)
        :func:`score_columns`; rows flagged in ``scalar`` hold NaN.
    scalar : ndarray of bool, shape (K,)
        Rows to compute with ``compare(analyze(dyn[k]))``.
    """
    K = len(dyn)
    columns = {name: np.empty(K) for name in score_columns(options.candidates)}
    scalar = np.empty(K, dtype=bool)
    size = block_size(dyn.m, dyn.n, options.vertices)
    for start in range(0, K, size):
        block = slice(start, start + size)
        values, scalar[block] = _block_rows(
            dyn.J[block],
            dyn.B[block],
            dyn.g[block],
            dyn.xdd_bias[block],
            tau_max,
            tau_min,
            directions,
            options,
        )
        for name, column in values.items():
            columns[name][block] = column
    return columns, scalar


class BlockSets(NamedTuple):
    """The sets of the full-rank rows of a block: the polytopes and every ellipsoid.

    What :func:`batch_rows` scores and :func:`polyell.posture_choice` measures, computed in
    one place (:func:`block_sets`).  Every array has a leading axis over the rows ``rows``.

    Attributes
    ----------
    rows : ndarray of int, shape (k,)
        The rows of the block these sets belong to (the others take the scalar path).
    J, B, M, xg, bias : ndarray
        ``J`` (k, m, n), ``B`` (k, n, n), ``M`` (k, m, n) (eq. 14), ``xg`` (k, m) (eq. 8)
        and ``bias`` ``g - tau_c`` (k, n).
    U, s, Vt : ndarray
        The SVD of M: (k, m, m), (k, m), (k, m, n).
    normals, offsets : ndarray, shape (k, C, m) and (k, C)
        The facet pairs of each polytope, ``|a . (x - xg)| <= h`` (:func:`facets`).
    whitened, whitened_offsets : ndarray, shape (k, C, m) and (k, C)
        The same facets in whitened coordinates.
    signs : ndarray, shape (k, V, n), or None
        The vertices' sign vectors (with ``options.vertices``).
    size : ndarray, shape (k,)
        The sum of the generator lengths (the polytope's extent about xg).
    volume : ndarray, shape (k,)
        The polytope's volume [(task unit)^m].
    ellipsoids : dict of str to (axes, semi_axes, witness, center or None)
        ``chiacchio``, ``yoshikawa`` and the optional ones: axes (k, m, m), semi-axes
        (k, m) (NaN: not certified), the torque witness (k,) and the centre (k, m), None
        for ``xg``.
    """

    rows: NDArray[np.int_]
    J: Array
    B: Array
    M: Array
    xg: Array
    bias: Array
    U: Array
    s: Array
    Vt: Array
    normals: Array
    offsets: Array
    whitened: Array
    whitened_offsets: Array
    signs: Array | None
    size: Array
    volume: Array
    ellipsoids: dict[str, tuple[Array, Array, Array, Array | None]]

    def as_set_batch(self) -> SetBatch:
        """The zonotopes as the scorer takes them: facet pairs about ``xg``, the vertices."""
        k, m, n = self.M.shape
        h = self.offsets
        vertices = None
        if self.signs is not None:  # about xg, one of each +-pair
            half = self.signs @ np.swapaxes(self.M, 1, 2)
            vertices = np.concatenate([self.xg[:, None] + half, self.xg[:, None] - half], 1)
        return SetBatch(
            center=self.xg,
            normals=np.concatenate([self.normals, -self.normals], axis=1),
            offsets=np.concatenate([h, h], axis=1),
            facet=np.ones((k, 2 * h.shape[1]), dtype=bool),
            vertices=vertices,
            is_vertex=None if vertices is None else np.ones(vertices.shape[:2], dtype=bool),
            volume=self.volume,
            size=self.size,
            terms=m + n + 2,  # Polytope's facet terms
            rtol_terms=n,
            slabs=Slabs(self.normals, h, np.einsum("kcm,km->kc", self.normals, self.xg)),
        )


def block_sets(
    J: Array,
    B: Array,
    g: Array,
    xdd_bias: Array,
    tau_max: Array,
    tau_min: Array,
    options: BatchOptions,
) -> tuple[BlockSets | None, NDArray[np.bool_]]:
    """The polytopes and ellipsoids of one block of configurations, on validated arrays.

    Parameters
    ----------
    J, B, g, xdd_bias : ndarray
        A block: (K, m, n), (K, n, n), (K, n), (K, m).
    tau_max, tau_min : ndarray, shape (n,)
        Torque limits [N m].
    options : BatchOptions
        Which optional sets, and the rank tolerance.

    Returns
    -------
    sets : BlockSets or None
        The sets of the rows this path covers (None if it covers none).
    scalar : ndarray of bool, shape (K,)
        Rows to compute by the scalar path: a rank below m or within :data:`RANK_BAND` of
        the threshold, more rows than joints, vertices :func:`vertex_signs` does not
        enumerate (when they are needed).
    """
    K, m, n = J.shape
    # Inputs near 1e308 may overflow here; check_magnitudes refuses the inf and NaN that
    # come out (naming the argument), so no RuntimeWarning is emitted before it does.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
        center_torque = 0.5 * (tau_max + tau_min)  # as in Analysis
        half = 0.5 * (tau_max - tau_min)
        bias = g - center_torque
        Binv_Jt = np.linalg.solve(B, np.swapaxes(J, -1, -2))  # (K, n, m); B is symmetric
        M = np.swapaxes(Binv_Jt, -1, -2) * half
        xg = xdd_bias - np.einsum("knm,kn->km", Binv_Jt, bias)
    zonotope = cast(type[ZonotopeAnalysis], capacity_class(options.capacity))
    zonotope._check_generators(M, xg)  # (velocities: B = I, g = 0)
    if m > n:
        return None, np.ones(K, dtype=bool)
    U, s, Vt = np.linalg.svd(M, full_matrices=False)
    # The rank decision is the scalar path's (Analysis computes M by a Cholesky solve and
    # its own SVD; both agree with these to rounding, not bit for bit): rows within
    # RANK_BAND of the threshold go there, so that one computation decides their rank.
    scalar = ~(s[:, -1] > options.rank_rtol * (1.0 + RANK_BAND) * s[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):  # rows sent to the scalar path
        block = facets(U, s, Vt)
    signs = None
    if options.vertices:  # rows vertex_signs leaves: the scalar path enumerates
        signs, generic = vertex_signs(Vt, block.whitened)
        scalar |= ~generic
    ok = ~scalar
    if not ok.any():
        return None, scalar
    J, B, M, xg, U, s, Vt = J[ok], B[ok], M[ok], xg[ok], U[ok], s[ok], Vt[ok]
    bias_ok = bias[ok]
    normals, h = block.normals[ok], block.offsets[ok]
    V1t = Vt[:, :m, :]
    size_p = np.linalg.norm(M, axis=1).sum(axis=-1)  # sum of the generator lengths

    # Every scored set as (axes, semi-axes, witness, centre or None for xg).
    ellipsoids: dict[str, tuple[Array, Array, Array, Array | None]] = {
        "chiacchio": (U, s, np.max(np.linalg.norm(Vt, axis=1), axis=-1), None),
        "yoshikawa": _classic(J, B, half, bias_ok),
    }
    parallelotope = n == m
    if options.mvie:
        whitened_normals, offsets = block.whitened[ok], block.whitened_offsets[ok]
        with np.errstate(invalid="ignore"):
            points = np.where(
                np.isinf(offsets)[..., None], 0.0, whitened_normals / offsets[..., None]
            )
        mvie = log_det_ellipsoid(U, s, V1t, None if parallelotope else points, enclosing=False)
        ellipsoids["mvie"] = (*mvie, None)
    if options.outer:
        assert signs is not None
        points = signs[ok] @ np.swapaxes(V1t, 1, 2)  # the vertices, whitened
        outer = log_det_ellipsoid(U, s, V1t, None if parallelotope else points, enclosing=True)
        ellipsoids["outer"] = (*outer, None)
    for candidate in options.candidates:
        ellipsoids[candidate.name] = candidate_ellipsoid(candidate, M, xg, U, s, V1t)
    sets = BlockSets(
        rows=np.flatnonzero(ok),
        J=J,
        B=B,
        M=M,
        xg=xg,
        bias=bias_ok,
        U=U,
        s=s,
        Vt=Vt,
        normals=normals,
        offsets=h,
        whitened=block.whitened[ok],
        whitened_offsets=block.whitened_offsets[ok],
        signs=None if signs is None else signs[ok],
        size=size_p,
        volume=_zonotope_volume(s, V1t),
        ellipsoids=ellipsoids,
    )
    return sets, scalar


def _block_rows(
    J: Array,
    B: Array,
    g: Array,
    xdd_bias: Array,
    tau_max: Array,
    tau_min: Array,
    directions: Array,
    options: BatchOptions,
) -> tuple[dict[str, Array], NDArray[np.bool_]]:
    """:func:`batch_rows` for one block of configurations, on validated arrays."""
    K = len(J)
    columns = {name: np.full(K, np.nan) for name in score_columns(options.candidates)}
    for kind in (*COMPARED_KINDS, *(c.name for c in options.candidates)):
        columns[f"{kind}_feasibility_mismatch"][:] = 0.0
        columns[f"{kind}_directions_used"][:] = 0.0
    sets, scalar = block_sets(J, B, g, xdd_bias, tau_max, tau_min, options)
    if sets is None:
        return columns, scalar
    zonotopes = sets.as_set_batch()
    ellipsoids = {
        kind: EllipsoidBatch(sets.xg if center is None else center, axes, semi, witness)
        for kind, (axes, semi, witness, center) in sets.ellipsoids.items()
    }
    scores, undecided = score_ellipsoids(
        zonotopes, ellipsoids, directions, options.samples, options.seed
    )
    rows = polytope_columns(zonotopes) | scores
    indices = sets.rows
    for name, values in rows.items():
        columns[name][indices] = values
    # an ellipsoid not inside P where its vertices are not enumerated: the exact path
    scalar[indices[undecided]] = True
    for name in columns:
        if name != "polytope_dim":
            columns[name][indices[undecided]] = np.nan
    return columns, scalar


def _classic(J: Array, B: Array, half: Array, bias: Array) -> tuple[Array, Array, Array, None]:
    """The classic ellipsoid from F = L^-1 B J^+ (its core is F^T F), as in Analysis.

    Its witness maps the boundary by eq. 26 written about the centre ``xg`` as
    :func:`polyell.inverse.classic_maps` does: ``tau_n = F (x - xg) + L^-1 B V_2 V_2^T f``
    with ``f = B^-1 (g - tau_c)`` and ``V_2`` a basis of ``Ker J``.  The value at the centre
    is computed directly, not as ``F xg + offset``, which cancels when the torques are weak
    against gravity (the motion bias ``Jdot qdot`` only enters through ``xg``).
    """
    J_pinv, _, at_center = classic_terms(J, B, half, bias)
    F = (B @ J_pinv) / half[..., None]
    _, s_f, Vt_f = np.linalg.svd(F, full_matrices=False)
    axes, semi = np.swapaxes(Vt_f, -1, -2)[:, :, ::-1], (1.0 / s_f)[:, ::-1]
    return axes, semi, witness(F, at_center, axes, semi), None
