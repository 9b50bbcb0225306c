r"""The sets of a block of full-rank configurations, batched.

Facets, vertices, the MVIE, the outer ellipsoid and user-defined candidates.

Every function takes arrays with a leading batch axis K (configurations of one block) and
computes what :class:`~polyell.geometry.polytope.Polytope`,
:func:`~polyell.geometry.mvie.max_volume_inscribed_ellipsoid`,
:func:`~polyell.geometry.outer.min_volume_enclosing_ellipsoid` and
:meth:`~polyell.comparison.candidates.Candidate.ellipsoid` compute for one.  An ellipsoid
is returned as ``(axes (K, m, m), semi_axes (K, m), witness (K,))``, centred at ``xg``
unless said otherwise; NaN semi-axes mark rows whose solver did not certify an optimum.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.candidates import Candidate
from polyell.comparison.scores import witness
from polyell.geometry.ellipsoid import canonical_axes
from polyell.geometry.logdet import centred_mvee_batch
from polyell.geometry.mvie import MVIE_GAP
from polyell.geometry.zonotope import DEPENDENT_RTOL, subset_cofactors, subsets, unwhiten

__all__ = ["BlockFacets", "candidate_ellipsoid", "facets", "log_det_ellipsoid", "vertex_signs"]

Array = NDArray[np.float64]
Ellipsoids = tuple[Array, Array, Array]

#: A generator whose (unit) normal product with a facet's (unit) normal is at most this
#: lies in that facet: a configuration not in general position, whose vertices the
#: scalar path enumerates (exact, with cddlib's check) for m > 3.
SIGN_RTOL = 1e-9
#: For m <= 3 (:func:`vertex_signs`) decisions are made below the scalar path's thresholds
#: (:mod:`polyell.geometry.zonotope`: zero generators and parallel pairs at 1e-12, in-plane
#: generators at 1e-10) and left to it in a band above.  A whitened generator at most this
#: long (relative to the longest) is zero, two unit generators whose cross product is at
#: most this long are parallel: structural zeros (a tip on a joint axis) come out near
#: 1e-16, or 1e-13 divided by a light link's inertia; the whitened coordinates of the two
#: paths agree to about 1e-16 times the condition number of M.
ZERO_RTOL = 5e-13
#: A product of unit vectors at most this large is zero (a generator in a facet's plane):
#: structural ones (parallel or intersecting axes) come out below 1e-11 from the rounding
#: of the forward kinematics.
IN_PLANE_RTOL = 1e-11
#: A generator or a cross product of unit generators between ZERO_RTOL and this long has a
#: direction too inaccurate (1e-16 / length) for the in-plane decisions of the batch and of
#: the scalar path to agree: its row takes the scalar path, as one with a product between
#: IN_PLANE_RTOL and SIGN_RTOL does.
LOOSE_RTOL = 1e-4
#: Most generators the batched vertex codes (bits of an int64) can hold.
MAX_VERTEX_GENERATORS = 62


class BlockFacets(NamedTuple):
    """The facets of a block of full-rank zonotopes ``{xg + U S V^T u}``, one of each +-pair.

    Attributes
    ----------
    whitened : ndarray, shape (K, C, m)
        Unit normals ``a_y`` of the whitened zonotopes ``{V^T u}``; zero for a dependent
        subset (no constraint).
    whitened_offsets : ndarray, shape (K, C)
        ``h_y = sum_i |a_y . v_i|``; infinite for a dependent subset.
    normals : ndarray, shape (K, C, m)
        Unit normals ``a_x`` in task coordinates (:func:`~polyell.geometry.zonotope.unwhiten`).
    offsets : ndarray, shape (K, C)
        Half-widths ``h_x`` about ``xg``: ``P = {x : |a_x . (x - xg)| <= h_x}``.
    """

    whitened: Array
    whitened_offsets: Array
    normals: Array
    offsets: Array


def facets(U: Array, s: Array, V1t: Array) -> BlockFacets:
    """Facets of every configuration's zonotope, enumerated in its whitened coordinates.

    As :class:`~polyell.Polytope` does for one (DESIGN.md section 7): cross products of
    the unit whitened generators (the columns of ``V^T``), a subset dependent when theirs
    is at most ``DEPENDENT_RTOL`` long, mapped back by
    :func:`~polyell.geometry.zonotope.unwhiten`.  Exact in number and accurate to the data
    for any ``sigma_min / sigma_max`` above the rank threshold.

    Parameters
    ----------
    U : ndarray, shape (K, m, m)
        Left singular vectors of M.
    s : ndarray, shape (K, m)
        Singular values (all non-zero).
    V1t : ndarray, shape (K, m, n)
        The first m right singular vectors, as rows.
    """
    K, m = s.shape
    if m == 1:
        whitened = np.ones((K, 1, 1))
        whitened_offsets = np.abs(V1t).sum(axis=-1)
    else:
        with np.errstate(divide="ignore", invalid="ignore"):  # a zero generator: dependent
            unit = V1t / np.sqrt((V1t * V1t).sum(axis=1))[:, None, :]
        cofactors = subset_cofactors(unit)  # (K, C, m)
        size = np.sqrt((cofactors * cofactors).sum(axis=-1))
        dependent = ~(size > DEPENDENT_RTOL)
        whitened = np.where(
            dependent[..., None], 0.0, cofactors / np.where(dependent, 1.0, size)[..., None]
        )
        whitened_offsets = np.where(dependent, np.inf, np.abs(whitened @ V1t).sum(axis=-1))
    normals, offsets = unwhiten(whitened, whitened_offsets, U, s)
    return BlockFacets(whitened, whitened_offsets, normals, offsets)


def vertex_count(m: int, n: int) -> int:
    """Vertices of a zonotope of n generators in general position in R^m, one per +-pair."""
    return sum(math.comb(n - 1, k) for k in range(m))


@lru_cache(maxsize=32)
def _facet_corner_codes(n: int, m: int) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """For each facet subset S: the codes of every sign choice on S (C, 2^(m-1)), and S."""
    S = subsets(n, m - 1)  # (C, m - 1)
    choices = (np.arange(2 ** (m - 1))[:, None] >> np.arange(m - 1)) & 1  # (2^(m-1), m-1)
    codes = (choices[None, :, :] << S[:, None, :]).sum(axis=-1).astype(np.int64)
    in_subset = np.zeros((len(S), n), dtype=bool)
    in_subset[np.arange(len(S))[:, None], S] = True
    codes.flags.writeable = in_subset.flags.writeable = False
    return codes, in_subset


def vertex_signs(V1t: Array, normals: Array) -> tuple[Array, NDArray[np.bool_]]:
    r"""Sign vectors of the vertices of each zonotope ``{M sigma}``, one of each +-pair.

    For m = 2 and 3, any arrangement of the generators (:func:`_flag_signs`): zero ones,
    parallel ones and facets holding more than m - 1 (the velocity zonotope of a real arm,
    whose tip lies on its last axis and whose axes are parallel or meet).  Otherwise in
    general position only (:func:`_general_position_signs`).  Decided in whitened
    coordinates, where the tests compare well-scaled numbers.

    Parameters
    ----------
    V1t : ndarray, shape (K, m, n)
        The whitened generators (rows of ``V^T``; ``M = U S V^T``).
    normals : ndarray, shape (K, C, m)
        The whitened normals, :attr:`BlockFacets.whitened` (used unless m is 2 or 3).

    Returns
    -------
    signs : ndarray, shape (K, V, n)
        Entries +-1, and 0 for a zero generator; the vertices about the centre are
        ``M sigma`` and ``-M sigma``.  V is the most vertex pairs of a row, at most
        :func:`vertex_count`; a row with fewer repeats its first one.
    generic : ndarray of bool, shape (K,)
        Rows enumerated; the others hold zeros (the caller sends them to the scalar path).
    """
    K, m, n = V1t.shape
    if n > MAX_VERTEX_GENERATORS:
        return np.zeros((K, vertex_count(m, n), n)), np.zeros(K, dtype=bool)
    if m in (2, 3):
        return _flag_signs(V1t)
    return _general_position_signs(V1t, normals)


def _flag_signs(V1t: Array) -> tuple[Array, NDArray[np.bool_]]:
    r"""Vertex sign vectors of zonotopes in R^2 or R^3, whatever their degeneracies.

    A vertex is the maximiser of a direction perturbed along a flag of faces: a facet
    (normal :math:`a`), an edge of it (parallel to a generator :math:`g_j`, outward normal
    :math:`b` within the facet) and an end of that edge.  In R^3 every pair i < j of
    non-parallel unit generators gives the orthonormal frame :math:`a \propto u_i \times
    u_j`, :math:`b = a \times u_j`, :math:`u_j`; in R^2 every generator gives :math:`a
    \perp u_j`, :math:`u_j`.  The sign of :math:`g_k` is that of its first non-zero
    product with the frame, whose later vectors take either sense: every choice is a
    vertex.  Generators parallel to :math:`g_j` follow it, and a facet holding several
    (a polygon) has as edges all of its generators but possibly the first: each of its
    vertices ends two edges of different directions, one of them not the first's, so
    every vertex comes out.  The sign vectors are coded as bits over the non-zero
    generators (zero ones: sign 0, as the scalar path drops them), made canonical (the
    smaller of a code and its complement) and unique.

    Rows with a generator or a cross product between :data:`ZERO_RTOL` and
    :data:`LOOSE_RTOL` long, or a deciding product between :data:`IN_PLANE_RTOL` and
    :data:`SIGN_RTOL` (decisions that could differ from the scalar path's), are not
    enumerated.

    Parameters
    ----------
    V1t : ndarray, shape (K, m, n)
        Whitened generators, m = 2 or 3, n <= :data:`MAX_VERTEX_GENERATORS`.

    Returns
    -------
    signs, generic
        As :func:`vertex_signs`.
    """
    K, m, n = V1t.shape
    lengths = np.sqrt((V1t * V1t).sum(axis=1))  # (K, n)
    longest = lengths.max(axis=1, keepdims=True)
    zero = ~(lengths > ZERO_RTOL * longest)
    generic = ~(~zero & (lengths <= LOOSE_RTOL * longest)).any(axis=1)
    generic &= np.isfinite(longest[:, 0])
    unit = np.where(zero[:, None, :], 0.0, V1t / np.where(zero, 1.0, lengths)[:, None, :])
    gram = np.swapaxes(unit, 1, 2) @ unit  # (K, n, n)
    # The products (K, T, n) of every unit generator with each vector of the T frames.
    if m == 2:  # frame j: a = (-u_j2, u_j1), u_j
        valid = ~zero
        u, v = unit[:, 0], unit[:, 1]
        levels = [u[:, :, None] * v[:, None, :] - v[:, :, None] * u[:, None, :]]
        levels.append(gram)
    else:  # frame (i, j): a . u_k = det(u_i, u_j, u_k) / size, b . u_k by the Gram matrix
        first, edge = subsets(n, 2).T
        cofactors = subset_cofactors(unit)  # (K, T, 3)
        size = np.sqrt((cofactors * cofactors).sum(axis=-1))
        valid = size > ZERO_RTOL  # neither is zero, nor are they parallel
        generic &= ~(valid & (size <= LOOSE_RTOL)).any(axis=1)
        scale = 1.0 / np.where(valid, size, 1.0)[..., None]
        along = gram[:, edge]
        levels = [(cofactors @ unit) * scale]
        levels.append((gram[:, first, edge][..., None] * along - gram[:, first]) * scale)
        levels.append(along)
    # A generator's sign is that of its first product above IN_PLANE_RTOL; the bits of those
    # decided by a later vector of the frame flip with it (its two senses).
    bits = np.int64(1) << np.arange(n, dtype=np.int64)
    nonzero = ~zero @ bits  # (K,)
    flat = [np.abs(level) <= IN_PLANE_RTOL for level in levels[:-1]]
    deciding = levels[-1]
    for level, flat_r in zip(levels[-2::-1], flat[::-1], strict=True):
        deciding = np.where(flat_r, deciding, level)
    ambiguous = ~zero[:, None, :] & ~(np.abs(deciding) > SIGN_RTOL)
    generic &= ~(ambiguous.any(axis=2) & valid).any(axis=1)
    before = np.ones((K, 1, n), dtype=bool)
    flips = [np.zeros((K, 1), dtype=np.int64)]  # the bits each sense choice flips
    for r in range(1, m):
        before = before & flat[r - 1]  # not decided by vectors 0 .. r - 1
        here = (before & ~flat[r] if r < m - 1 else before) @ bits & nonzero[:, None]
        flips += [flip ^ here for flip in flips]
    codes = ((deciding > 0) @ bits)[..., None] ^ np.stack(np.broadcast_arrays(*flips), axis=-1)
    codes = np.minimum(codes, codes ^ nonzero[:, None, None])
    invalid = np.iinfo(np.int64).max
    codes = np.where(valid[..., None], codes, invalid).reshape(K, -1)
    codes.sort(axis=1)
    new = np.ones(codes.shape, dtype=bool)
    new[:, 1:] = codes[:, 1:] != codes[:, :-1]
    new &= codes != invalid
    count = new.sum(axis=1)
    generic &= count > 0
    V = int(count[generic].max(initial=1))
    new &= generic[:, None]
    unique = np.zeros((K, V), dtype=np.int64)  # compacted, then padded with the first
    unique[np.nonzero(new)[0], (np.cumsum(new, axis=1) - 1)[new]] = codes[new]
    unique = np.where(np.arange(V) < count[:, None], unique, unique[:, :1])
    signs = (((unique[..., None] >> np.arange(n)) & 1) * 2.0 - 1.0) * ~zero[:, None, :]
    return np.where(generic[:, None, None], signs, 0.0), generic


def _general_position_signs(V1t: Array, normals: Array) -> tuple[Array, NDArray[np.bool_]]:
    r"""Vertex sign vectors of zonotopes in general position (any m).

    Every vertex is a vertex of a facet: for the facet of the subset S (normal a),
    :math:`\sigma_i = \operatorname{sign}(a \cdot g_i)` off S and every choice of signs on
    S.  The sign vectors are coded as bits, made canonical (:math:`\sigma_1 = +1`) and
    made unique per row; a row where some ``|a . g_i| <= SIGN_RTOL`` off S (not in general
    position) is not enumerated.  Parameters and returns as :func:`vertex_signs`, with
    V = :func:`vertex_count`.
    """
    K, m, n = V1t.shape
    V = vertex_count(m, n)
    corner_codes, in_subset = _facet_corner_codes(n, m)
    with np.errstate(divide="ignore", invalid="ignore"):  # a zero generator: dependent rows
        unit = V1t / np.linalg.norm(V1t, axis=1)[:, None, :]
    products = normals @ unit  # (K, C, n)
    off = ~in_subset[None]
    generic = ~np.any(off & ~(np.abs(products) > SIGN_RTOL), axis=(1, 2))  # NaN: not generic
    generic &= ~np.any((normals == 0).all(axis=-1), axis=1)  # a dependent subset
    bits = np.int64(1) << np.arange(n, dtype=np.int64)
    base = np.where(off & (products > 0), bits, 0).sum(axis=-1)  # (K, C)
    codes = (base[..., None] + corner_codes[None]).reshape(K, -1)
    codes = np.where(codes & 1, codes, codes ^ ((np.int64(1) << n) - 1))  # sigma_1 = +1
    codes.sort(axis=1)
    first = np.ones(codes.shape, dtype=bool)
    first[:, 1:] = codes[:, 1:] != codes[:, :-1]
    generic &= first.sum(axis=1) == V
    unique = np.zeros((K, V), dtype=np.int64)
    unique[generic] = codes[generic][first[generic]].reshape(-1, V)
    signs = ((unique[..., None] >> np.arange(n)) & 1) * 2.0 - 1.0
    return np.where(generic[:, None, None], signs, 0.0), generic


def log_det_ellipsoid(
    U: Array, s: Array, V1t: Array, points: Array | None, *, enclosing: bool
) -> Ellipsoids:
    """The MVIE (``enclosing=False``) or the outer ellipsoid of full-rank blocks, batched.

    In whitened coordinates (P the zonotope of the rows of V1^T) the shape X of
    :func:`~polyell.geometry.logdet.centred_mvee_batch` of ``points`` (K, N, m) -- the
    scaled facet normals for the MVIE, the vertices for the outer ellipsoid -- gives
    ``E = {xg + U Sigma X^(+-1/2) u}``.  n = m: X = I (the MVIE is the new ellipsoid, the
    outer one that scaled by sqrt(m)).

    Returns
    -------
    axes, semi_axes, witness
        The witness is the largest row norm of ``V1 X^(+-1/2)``: the torque witness under
        the minimum-torque map (eq. 33).
    """
    K, m = s.shape
    if points is None:  # a parallelotope
        root = np.broadcast_to(np.eye(m) * (np.sqrt(m) if enclosing else 1.0), (K, m, m))
        certified = np.ones(K, dtype=bool)
    else:
        shapes, gaps, _ = centred_mvee_batch(points, gap=MVIE_GAP)
        certified = gaps <= MVIE_GAP
        shapes = np.where(certified[:, None, None], shapes, np.eye(m))
        eigenvalues, eigenvectors = np.linalg.eigh(shapes)
        power = -0.5 if enclosing else 0.5
        root = (eigenvectors * eigenvalues[:, None, :] ** power) @ np.swapaxes(eigenvectors, 1, 2)
    W, semi, _ = np.linalg.svd(s[:, :, None] * root)
    witness = np.max(np.linalg.norm(np.swapaxes(V1t, -1, -2) @ root, axis=-1), axis=-1)
    semi = np.where(certified[:, None], semi, np.nan)
    return U[:, :, :m] @ W, semi, np.where(certified, witness, np.nan)


def candidate_ellipsoid(
    candidate: Candidate, M: Array, xg: Array, U: Array, s: Array, V1t: Array
) -> tuple[Array, Array, Array, Array]:
    """A candidate at every (full-rank) configuration of a block.

    Returns
    -------
    axes, semi_axes, witness, center
        ``center`` (K, m): ``xg``, or a core-defined candidate's own centre.  The witness
        uses the minimum-torque map ``tau_n = M^+ (x - xg)``.
    """
    K, m = s.shape
    if candidate.weighting is not None:
        axes, semi, _ = np.linalg.svd(M @ candidate.root_inverse, full_matrices=False)
        center = xg
    else:
        assert candidate.core is not None
        eigenvalues, eigenvectors = np.linalg.eigh(candidate.core)
        axes = np.broadcast_to(eigenvectors, (K, m, m))
        semi = np.broadcast_to(1.0 / np.sqrt(eigenvalues), (K, m))
        center = xg if candidate.center is None else np.broadcast_to(candidate.center, (K, m))
    axes, semi = canonical_axes(np.array(axes), np.array(semi))  # as Ellipsoid: the same points
    # M^+ = V1 Sigma^-1 U^T: at the centre, and the reach along the axes.
    pinv_t = np.swapaxes(V1t, 1, 2) / s[:, None, :] @ np.swapaxes(U, 1, 2)  # (K, n, m)
    at_center = np.einsum("knm,km->kn", pinv_t, center - xg)
    return np.array(axes), np.array(semi), witness(pinv_t, at_center, axes, semi), np.array(center)
