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
from polyell.geometry.logdet import centred_mvee_batch
from polyell.geometry.mvie import MVIE_GAP
from polyell.geometry.zonotope import DEPENDENT_RTOL, subset_cofactors, subsets, unwhiten

__all__ = ["BlockFacets", "candidate_ellipsoid", "facets", "log_det_ellipsoid", "vertex_signs"]

Array = NDArray[np.float64]
Ellipsoids = tuple[Array, Array, Array]

#: A generator whose (unit) normal product with a facet's (unit) normal is at most this
#: lies in that facet: a configuration not in general position, whose vertices the
#: scalar path enumerates (exact, with cddlib's check).
SIGN_RTOL = 1e-9
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

    In general position every vertex is a vertex of a facet: for the facet of the subset
    S (normal a), :math:`\sigma_i = \operatorname{sign}(a \cdot g_i)` off S and every
    choice of signs on S.  The sign vectors are coded as bits, made canonical
    (:math:`\sigma_1 = +1`) and made unique per row.  Decided in whitened coordinates,
    where the in-plane test ``|a . g_i| <= SIGN_RTOL`` compares well-scaled numbers.

    Parameters
    ----------
    V1t : ndarray, shape (K, m, n)
        The whitened generators (rows of ``V^T``; ``M = U S V^T``).
    normals : ndarray, shape (K, C, m)
        The whitened normals, :attr:`BlockFacets.whitened`.

    Returns
    -------
    signs : ndarray, shape (K, V, n)
        +-1 entries; the vertices about the centre are ``M sigma`` and ``-M sigma``.
        V = :func:`vertex_count`.
    generic : ndarray of bool, shape (K,)
        Rows in general position; the others hold zeros (the caller sends them to the
        scalar path).
    """
    K, m, n = V1t.shape
    V = vertex_count(m, n)
    if n > MAX_VERTEX_GENERATORS:
        return np.zeros((K, V, n)), np.zeros(K, dtype=bool)
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
    # M^+ = V1 Sigma^-1 U^T: at the centre, and the reach along the axes.
    pinv_t = np.swapaxes(V1t, 1, 2) / s[:, None, :] @ np.swapaxes(U, 1, 2)  # (K, n, m)
    at_center = np.einsum("knm,km->kn", pinv_t, center - xg)
    spread = np.linalg.norm(pinv_t @ (axes * semi[:, None, :]), axis=-1)
    witness = np.max(np.abs(at_center) + spread, axis=-1)
    return np.array(axes), np.array(semi), witness, np.array(center)
