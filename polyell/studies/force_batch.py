r"""The force capacity's sweep path: the scores of many configurations at once.

For K configurations sharing (m, n), every step of
``compare(analyze(dyn[k], ..., capacity="force")).to_row()`` is done with batched linear
algebra, in the whitened coordinates of :class:`~polyell.capacities.force.ForceAnalysis`
(``z = S U^T (h - h0)``, where the rows of the set are those of ``V``):

* the set ``{h : |A h + c|_inf <= 1}``: its vertices from every choice of m rows and m
  signs (``C(n, m) 2^m`` candidates, each an m x m solve, kept where every row holds), its
  facets (the rows tight at a vertex) and its volume by Lawrence's formula for simple
  polytopes (J. Lawrence, "Polytope volume computation", Math. Comp. 57, 1991), evaluated
  for three directions, of which the two that cancel least must agree;
* the three ellipsoids (``chiacchio``, ``yoshikawa``, ``static``) with their torque
  witnesses, and with ``mvie``, ``outer`` the optimal ones (solved together in the whitened
  coordinates), scored by the one scorer of every capacity
  (:func:`~polyell.comparison.scores.score_ellipsoids`).

Rows this path does not cover are returned as a mask for the scalar path, so that every
row equals ``compare(analyze(...)).to_row()`` to rounding: a rank of ``J`` below m (or
within :data:`~polyell.studies.batch.RANK_BAND` of the threshold: an unbounded set), a part
of gravity no force balances of normalized norm 1 or more (an empty ``chiacchio``
ellipsoid; the set may be empty), vertices not in general position (another row within
:data:`GENERAL_POSITION` of tight at a vertex), vertices the enumeration cannot certify
complete (m nearly dependent rows, whose candidates it skips, may hide one: real robots
have exactly dependent ones, and their sets stay here), two volume evaluations that
differ by more than :data:`VOLUME_RTOL`; and every row of a task of fewer than two rows, or
with more than :data:`MAX_CANDIDATES` vertex candidates.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.capacities.base import centre_and_half_range
from polyell.capacities.force import (  # the force sets (an analysis': a batch of one)
    GENERAL_POSITION,
    MAX_CANDIDATES,
    _layout,
    force_terms,
    force_vertices,
)
from polyell.capacities.force import _closed as _closed  # (tests certify it here)
from polyell.comparison.candidates import Candidate
from polyell.comparison.comparison import compared_kinds
from polyell.comparison.scores import (
    EllipsoidBatch,
    SetBatch,
    Slabs,
    polytope_columns,
    score_ellipsoids,
    witness,
)
from polyell.geometry.ellipsoid import canonical_axes
from polyell.geometry.free_center import (
    FreeCenterBatch,
    free_center_mvee_batch,
    free_center_mvie_batch,
)
from polyell.geometry.subspace import RANK_RTOL, scaled_norm
from polyell.models.dynamics import Dynamics
from polyell.studies.batch import BLOCK_MEMORY, RANK_BAND, BatchOptions, score_columns

__all__ = ["GENERAL_POSITION", "MAX_CANDIDATES", "VOLUME_RTOL", "force_rows"]

Array = NDArray[np.float64]

#: Lawrence's sum can cancel: its two least cancelling evaluations must agree to this.
VOLUME_RTOL = 1e-10
#: The three generic directions of Lawrence's formula (fixed: rows are reproducible).
_DIRECTIONS = np.random.default_rng(20001).normal(size=(3, 64))


def force_rows(
    dyn: Dynamics,
    tau_max: Array,
    tau_min: Array,
    directions: Array,
    options: BatchOptions,
) -> tuple[dict[str, Array], NDArray[np.bool_]]:
    """Score columns of a batch of force capacities, and which rows need the scalar path.

    Parameters
    ----------
    dyn : Dynamics
        A batch: J (K, m, n) and the gravity torques g (K, n) [N m].
    tau_max, tau_min : ndarray, shape (n,)
        Torque limits [N m].
    directions : ndarray, shape (k, m)
        Unit directions of the directional statistics.
    options : BatchOptions
        ``samples``, ``seed``, ``rank_rtol``, ``mvie``, ``outer`` and ``candidates`` as in
        :func:`polyell.compare` (a candidate given by a torque weighting defines no force
        ellipsoid: NaN).

    Returns
    -------
    columns : dict of str to ndarray (K,)
        :func:`~polyell.studies.batch.score_columns` of the force capacity; rows flagged
        in ``scalar`` hold NaN.
    scalar : ndarray of bool, shape (K,)
        Rows to compute with ``compare(analyze(dyn[k], ..., capacity="force"))``.
    """
    K, m, n = dyn.J.shape
    columns = {name: np.full(K, np.nan) for name in score_columns(options.candidates, "force")}
    for kind in (*compared_kinds("force"), *(c.name for c in options.candidates)):
        columns[f"{kind}_feasibility_mismatch"][:] = 0.0
        columns[f"{kind}_directions_used"][:] = 0.0
    scalar = np.ones(K, dtype=bool)
    several = math.comb(n, m) * 2**m if m <= n else 0
    if not 2 <= m <= n:
        return columns, scalar
    if several > MAX_CANDIDATES:
        return columns, scalar
    tau_center, half = centre_and_half_range(tau_max, tau_min)
    # Rows per block: the (rows, n, candidates) temporaries, about 3n + m arrays' worth of
    # doubles per candidate, within a quarter of BLOCK_MEMORY (about 40 MiB measured for
    # 936 rows of 3x7 arms); larger blocks spread the per-call cost of numpy.
    size = max(1, (BLOCK_MEMORY // 4) // (8 * several * (3 * n + m)))
    for start in range(0, K, size):
        block = slice(start, start + size)
        rows, values = _block_rows(
            dyn.J[block], dyn.g[block], tau_center, half, directions, options
        )
        scalar[block][rows] = False
        for name, column in values.items():
            columns[name][start + rows] = column
    return columns, scalar


def _block_rows(
    J: Array,
    g: Array,
    tau_center: Array,
    half: Array,
    directions: Array,
    options: BatchOptions,
) -> tuple[NDArray[np.int_], dict[str, Array]]:
    """The rows of one block this path covers (indices into the block), and their scores."""
    m = J.shape[1]
    M, c = force_terms(J, g, tau_center, half)  # the checks (and errors) of analyze
    U, s, Vt = np.linalg.svd(M, full_matrices=False)  # A = V S U^T, M = A^T = U S V^T
    ok = s[:, -1] > options.rank_rtol * (1.0 + RANK_BAND) * s[:, 0]
    # the analysis decides the rank on J (ForceAnalysis): rows near J's threshold too
    kinematic = np.linalg.svd(J, compute_uv=False)
    ok &= kinematic[:, -1] > options.rank_rtol * (1.0 + RANK_BAND) * kinematic[:, 0]
    along = np.einsum("kmn,kn->km", Vt, c)
    c_perp = c - np.einsum("kmn,km->kn", Vt, along)
    margin = 1.0 - np.einsum("kn,kn->k", c_perp, c_perp)
    ok &= margin > 0.0
    norms = np.linalg.norm(M, axis=1)  # |a_i| (K, n)
    # HPolytope drops the rows negligible against the others (RANK_RTOL), in torques: a
    # joint whose column of J is negligible against the others' constrains no force
    loads = scaled_norm(J, axis=1)
    used = loads > RANK_RTOL * loads.max(axis=-1, keepdims=True)
    vertices = _vertices(Vt, c_perp, used)
    ok &= vertices.general
    volume_z = vertices.volume
    keep = np.flatnonzero(ok)
    if not keep.size:
        return keep, {}
    M, c, U, s, Vt, c_perp = M[keep], c[keep], U[keep], s[keep], Vt[keep], c_perp[keep]
    J, g, along, margin = J[keep], g[keep], along[keep], margin[keep]
    z, is_vertex, facet = vertices.z[keep], vertices.is_vertex[keep], vertices.facet[keep]
    h0 = -np.einsum("kij,kj->ki", U, along / s)

    # The rows as unit normals: n_i . h in [(-1 - c_i) / |a_i|, (1 - c_i) / |a_i|]; about
    # h0, n_i . (h - h0) in [-1 - cp_i, 1 - cp_i] / |a_i|.
    A = np.swapaxes(M, 1, 2)  # (k, n, m)
    norms, used = norms[keep], used[keep]
    with np.errstate(divide="ignore"):
        width = np.where(used, 1.0 / norms, np.inf)
    points = h0[:, None, :] + (z / s[:, None, :]) @ np.swapaxes(U, 1, 2)  # (k, V, m)
    normals = np.where(used[..., None], A * np.where(used, width, 0.0)[..., None], 0.0)
    sets = SetBatch(
        center=h0,
        normals=np.concatenate([normals, -normals], axis=1),
        offsets=np.concatenate([(1.0 - c_perp) * width, (1.0 + c_perp) * width], axis=1),
        facet=facet,
        vertices=points,
        is_vertex=is_vertex,
        volume=volume_z[keep] / np.prod(s, axis=-1),
        size=np.max(
            np.where(is_vertex, np.linalg.norm(points - h0[:, None, :], axis=-1), 0.0), axis=-1
        ),
        terms=m + 2,  # HPolytope's facet terms
        rtol_terms=2,
        slabs=Slabs(normals, width, np.where(used, -c * np.where(used, width, 0.0), 0.0)),
    )
    ellipsoids = _ellipsoids(J, g, tau_center, half, U, s, h0, margin, A, c_perp)
    # The optimal ellipsoids, solved in the whitened coordinates z = S U^T (h - h0)
    to_force = (h0, U / s[:, None, :], A, c_perp)
    if options.mvie:
        V = np.swapaxes(Vt, 1, 2) * used[..., None]
        rows_z = np.concatenate([V, -V], axis=1)
        bounds = np.concatenate([1.0 - c_perp, 1.0 + c_perp], axis=1)
        mvie = free_center_mvie_batch(rows_z, bounds, facet)
        ellipsoids["mvie"] = _mapped(mvie, *to_force)
    if options.outer:
        ellipsoids["outer"] = _mapped(free_center_mvee_batch(z, is_vertex), *to_force)
    for candidate in options.candidates:
        ellipsoids[candidate.name] = _candidate(candidate, h0, A, c_perp)
    rows = polytope_columns(sets)
    scores, _ = score_ellipsoids(sets, ellipsoids, directions, options.samples, options.seed)
    return keep, rows | scores  # (the vertices are known: every share is decided)


class _Vertices(NamedTuple):
    """The vertices of a block's force sets in whitened coordinates, and their volume.

    Attributes
    ----------
    z : ndarray, shape (K, V, m)
        The vertices, as many as the row with the most; those of each row are marked in
        ``is_vertex``.
    is_vertex : ndarray of bool, shape (K, V)
    facet : ndarray of bool, shape (K, 2n)
        The one-sided rows (``+row`` then ``-row``) tight at some vertex: the facets.
    general : ndarray of bool, shape (K,)
        Vertices in general position and a volume the evaluations agree on.
    volume : ndarray, shape (K,)
        The volume in whitened coordinates (NaN where not ``general``).
    """

    z: Array
    is_vertex: NDArray[np.bool_]
    facet: NDArray[np.bool_]
    general: NDArray[np.bool_]
    volume: Array


def _vertices(Vt: Array, c_perp: Array, used: NDArray[np.bool_]) -> _Vertices:
    r"""The vertices of :func:`~polyell.capacities.force.force_vertices`, with their volume.

    With the outward normals ``N = diag(sigma) V_S`` of a vertex and a generic direction
    ``w = N^T gamma``, Lawrence's formula gives the volume of a simple polytope,
    ``sum (w . z)^m / (m! |det N| prod gamma)`` over the vertices (about an interior
    point: h0 is ``z = 0``).  A direction nearly orthogonal to an edge makes the sum cancel:
    of three directions the two with the least cancellation (``sum |term| / |sum|``) must
    agree, and the least cancelling one gives the volume.
    """
    K, m, n = Vt.shape
    found = force_vertices(Vt, c_perp, used)
    general = found.general.copy()
    # Only the vertices from here: the first V_max candidates in vertex-first order.
    count = int(found.vertex.sum(axis=1).max(initial=0))
    order = np.argsort(~found.vertex, axis=1, kind="stable")[:, :count]
    is_vertex = np.take_along_axis(found.vertex, order, axis=1)
    points = np.take_along_axis(found.z, order[..., None], axis=1)  # (K, V_max, m)
    points = np.where(is_vertex[..., None], points, 0.0)  # (candidates skipped: NaN)
    signs = _layout(n, m)[1]
    subset, sign = np.divmod(order, len(signs))
    factor = np.where(is_vertex, np.prod(signs, axis=-1)[sign], 0.0) / math.factorial(m)
    w = _DIRECTIONS[:, :m] / np.linalg.norm(_DIRECTIONS[:, :m], axis=1, keepdims=True)
    det = np.take_along_axis(found.det, subset, axis=1)  # (K, V_max)
    adjugate = np.take_along_axis(found.adjugate.reshape(K, -1, m * m), subset[..., None], axis=1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inverse = np.swapaxes(adjugate.reshape(K, -1, m, m), -1, -2) / det[..., None, None]
        gamma = np.tensordot(inverse, w, axes=(2, 1))  # V_S^T gamma = w
        scale = np.abs(det)[..., None] * np.prod(gamma, axis=2)
        heights = points @ w.T  # (K, V_max, 3)
        terms = factor[..., None] * heights**m / np.where(is_vertex[..., None], scale, 1.0)
        sums = np.sum(terms, axis=1)  # (K, 3)
        cancellation = np.sum(np.abs(terms), axis=1) / np.abs(sums)
    ranked = np.argsort(np.nan_to_num(cancellation, nan=np.inf), axis=1, kind="stable")
    best, second = np.take_along_axis(sums, ranked[:, :2], axis=1).T
    general &= np.abs(best - second) <= VOLUME_RTOL * np.abs(best)
    general &= best > 0
    return _Vertices(
        points,
        is_vertex,
        found.facet,
        general,
        np.where(general, best, np.nan),
    )


def _ellipsoids(
    J: Array,
    g: Array,
    tau_center: Array,
    half: Array,
    U: Array,
    s: Array,
    h0: Array,
    margin: Array,
    A: Array,
    c_perp: Array,
) -> dict[str, EllipsoidBatch]:
    """Each force ellipsoid, as ``ForceAnalysis`` builds it, and its torque witness.

    The witness: ``tau_n = A (h - h0) + c_perp`` at the centre, plus its spread over the
    boundary, at its largest.
    """
    pseudo_inverse = np.linalg.pinv(np.swapaxes(J, 1, 2))  # (J^T)^+ (k, m, n)
    classic_center = -np.einsum("kmn,kn->km", pseudo_inverse, g - tau_center)
    classic_axes, classic_semi, _ = np.linalg.svd(pseudo_inverse * half, full_matrices=False)
    sets = {
        "chiacchio": (h0, U, np.sqrt(margin)[:, None] / s),
        "yoshikawa": (classic_center, classic_axes, classic_semi),
        "static": (np.zeros_like(h0), U, 1.0 / s),
    }
    return {
        kind: _with_witness(center, *canonical_axes(axes, semi), h0, A, c_perp)
        for kind, (center, axes, semi) in sets.items()
    }


def _with_witness(
    center: Array, axes: Array, semi: Array, h0: Array, A: Array, c_perp: Array
) -> EllipsoidBatch:
    """An ellipsoid and its witness: ``tau_n = A (h - h0) + c_perp`` at its largest.

    At the centre, plus its spread over the boundary.
    """
    at_center = np.einsum("knm,km->kn", A, center - h0) + c_perp
    return EllipsoidBatch(center, axes, semi, witness(A, at_center, axes, semi))


def _mapped(
    solution: FreeCenterBatch, h0: Array, to_force: Array, A: Array, c_perp: Array
) -> EllipsoidBatch:
    """An optimal ellipsoid ``{d + C u}`` of the whitened set, in forces ``h0 + T z``.

    Not certified (``converged`` False): undefined, NaN semi-axes (as in ``compare``).
    """
    ok = solution.converged
    center = h0 + np.einsum("kmr,kr->km", to_force, np.nan_to_num(solution.centers))
    shapes = np.where(ok[:, None, None], solution.shapes, np.eye(h0.shape[1]))
    axes, semi, _ = np.linalg.svd(to_force @ shapes)
    E = _with_witness(center, *canonical_axes(axes, semi), h0, A, c_perp)
    return E._replace(semi=np.where(ok[:, None], E.semi, np.nan))


def _candidate(candidate: Candidate, h0: Array, A: Array, c_perp: Array) -> EllipsoidBatch:
    """A candidate ``{(h - c)^T N (h - c) <= 1}`` at every configuration (centre c or h0).

    A weighting of normalized joint quantities defines no force ellipsoid: undefined (NaN
    semi-axes), as ``compare`` reports it.
    """
    K, m = h0.shape
    if candidate.core is None:
        nan = np.full((K, m), np.nan)
        return EllipsoidBatch(h0, np.broadcast_to(np.eye(m), (K, m, m)), nan, nan[:, 0])
    eigenvalues, eigenvectors = np.linalg.eigh(candidate.core)
    center = h0 if candidate.center is None else np.broadcast_to(candidate.center, (K, m))
    axes, semi = canonical_axes(eigenvectors, 1.0 / np.sqrt(eigenvalues))  # as Ellipsoid
    axes, semi = np.broadcast_to(axes, (K, m, m)), np.broadcast_to(semi, (K, m))
    return _with_witness(np.array(center), np.array(axes), np.array(semi), h0, A, c_perp)
