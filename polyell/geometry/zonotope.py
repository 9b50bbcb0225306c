r"""Closed forms for a zonotope ``Z = { G t : ||t||_inf <= 1 }`` in its own coordinates.

The acceleration polytope (15) is ``xdd_g + Z`` with ``G = M`` (written in the
coordinates of its affine set).  Here ``G`` has shape (r, n) and full row rank ``r``.

* Facets: every facet normal ``a`` is orthogonal to ``r - 1`` linearly independent
  generators and, conversely, every such ``a`` is a facet normal.  The offset is the
  support function ``h(a) = sum_i |a . g_i|``.
* Vertices: every vertex lies on a facet ``a``, where the generators not orthogonal to
  ``a`` take the sign ``sign(a . g_i)``; only the orthogonal ones vary.
* Volume: ``vol(Z) = 2^r sum_{|S| = r} |det G_S|``.

Thin zonotopes (DESIGN.md section 7): with ``G = U S V^T`` (SVD), ``Z = U S {V^T u}`` and
the whitened zonotope ``{V^T u}`` (orthonormal rows) is well conditioned however thin ``Z``
is: it contains the unit ball and lies in the ball of radius ``sqrt(n)``.  Its facets are
enumerated there, where cofactors, the dependence test and the in-facet test compare
well-scaled numbers, and mapped back by :func:`unwhiten`.
"""

from __future__ import annotations

from functools import lru_cache
from itertools import combinations, product
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull

from polyell.errors import InputError

__all__ = [
    "DEPENDENT_RTOL",
    "MAX_CORNER_JOINTS",
    "ZonotopeFacets",
    "corner_vertices",
    "order_polygon",
    "subset_cofactors",
    "unwhiten",
    "zonotope_facets",
    "zonotope_vertices",
    "zonotope_volume",
]

#: Largest number of generators for which the 2^n cube corners are enumerated.
MAX_CORNER_JOINTS = 16
#: Generators shorter than this fraction of the longest one are zero.
_ZERO_GENERATOR_RTOL = 1e-12
#: Subsets whose normal is this small relative to their generator lengths are dependent.
DEPENDENT_RTOL = 1e-12
#: Unit normals closer than this (up to sign) are the same facet direction.
_SAME_NORMAL_TOL = 1e-10
#: A generator with |a . g| <= this * |g| lies in the facet plane of normal a.
_IN_FACET_RTOL = 1e-10
#: Up to this many generators, vertices are picked from a cached table of sign vectors.
_SIGN_TABLE_JOINTS = 12


@lru_cache(maxsize=64)
def subsets(n: int, k: int) -> NDArray[np.int_]:
    """All k-subsets of range(n) as rows, shape (C(n, k), k) (cached, read-only)."""
    rows = np.array(list(combinations(range(n), k)), dtype=int).reshape(-1, k)
    rows.flags.writeable = False
    return rows


def cross(blocks: NDArray[np.float64]) -> NDArray[np.float64]:
    """Generalised cross product of the m-1 columns of (..., m, m-1): the cofactor vector.

    Component k is ``(-1)^k det(blocks without row k)``; orthogonal to every column, of
    length the (m-1)-volume they span.
    """
    m = blocks.shape[-2]
    if m == 2:
        return np.stack([-blocks[..., 1, 0], blocks[..., 0, 0]], axis=-1)
    if m == 3:
        a, b = blocks[..., 0], blocks[..., 1]
        return np.stack(
            [
                a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
            ],
            axis=-1,
        )
    return np.stack(
        [(-1) ** k * np.linalg.det(np.delete(blocks, k, axis=-2)) for k in range(m)], axis=-1
    )


@lru_cache(maxsize=16)
def _corner_bits(k: int) -> NDArray[np.int64]:
    """The 2^k corners of {0, 1}^k as rows (cached, read-only)."""
    rows = np.array(list(product((0, 1), repeat=k)), dtype=np.int64).reshape(2**k, k)
    rows.flags.writeable = False
    return rows


@lru_cache(maxsize=64)
def _bits(n: int) -> NDArray[np.int64]:
    """``2^i`` for i in range(n) (cached, read-only)."""
    bits = 1 << np.arange(n, dtype=np.int64)
    bits.flags.writeable = False
    return bits


@lru_cache(maxsize=16)
def _sign_table(n: int) -> NDArray[np.float64]:
    """Row k: the signs (+-1) of the bits of k, bit i in column i, shape (2^n, n) (cached)."""
    table = (_corner_bits(n)[:, ::-1] * 2 - 1).astype(np.float64)
    table.flags.writeable = False
    return table


def _nonzero_generators(
    G: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int_]]:
    """The generators longer than ``_ZERO_GENERATOR_RTOL`` of the longest, lengths, indices.

    In whitened coordinates (the columns of ``V^T``) "short" is relative to the set's
    width along the generator, not to the longest generator of a thin set.
    """
    lengths = np.sqrt((G * G).sum(axis=0))
    longest = lengths.max(initial=0.0)
    if longest == 0:
        return G[:, :0], lengths[:0], np.zeros(0, dtype=int)
    if lengths.min() > _ZERO_GENERATOR_RTOL * longest:
        return G, lengths, np.arange(G.shape[1])
    keep = np.flatnonzero(lengths > _ZERO_GENERATOR_RTOL * longest)
    return G[:, keep], lengths[keep], keep


def _unique_directions(normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drop unit vectors equal, up to sign, to an earlier one."""
    # A screen on the cosines (rounded by ~1e-15), then the decision on the distances:
    # two unit vectors within _SAME_NORMAL_TOL have a cosine above 1 - 1e-20.
    close = np.abs(normals @ normals.T) > 1.0 - 1e-12
    if np.count_nonzero(close) == len(normals):  # only the diagonal: the usual case
        return normals
    near = np.argwhere(np.triu(close, 1))
    first, second = normals[near[:, 0]], normals[near[:, 1]]
    distance = np.minimum(
        np.linalg.norm(first - second, axis=1), np.linalg.norm(first + second, axis=1)
    )
    duplicate = np.zeros(len(normals), dtype=bool)
    duplicate[near[distance < _SAME_NORMAL_TOL, 1]] = True
    return normals[~duplicate]


def subset_cofactors(G: NDArray[np.float64]) -> NDArray[np.float64]:
    """Generalised cross products of every (r - 1)-subset of the columns of ``G``.

    Parameters
    ----------
    G : ndarray, shape (..., r, n)
        Generators (columns), r >= 2; leading axes are a batch.

    Returns
    -------
    ndarray, shape (..., C, r)
        One cofactor vector per subset, in the order of ``subsets(n, r - 1)``.
    """
    *batch, r, n = G.shape
    if r == 3:  # the common task: four gathers from the flattened generators
        flat = G.reshape(*batch, 3 * n)
        a, b, c, d = _cross_indices(n)
        products = flat.take(a, -1) * flat.take(b, -1) - flat.take(c, -1) * flat.take(d, -1)
        return products.reshape(*batch, -1, 3)
    return cross(np.moveaxis(G[..., subsets(n, r - 1)], -3, -2))  # (..., C, r, r-1)


@lru_cache(maxsize=64)
def _cross_indices(n: int) -> tuple[NDArray[np.int_], ...]:
    """Flat indices into a (3, n) array for ``g_i x g_j`` over the pairs ``subsets(n, 2)``.

    Component k of the cross product is ``g_i[k+1] g_j[k+2] - g_i[k+2] g_j[k+1]`` (mod 3);
    pair by pair, the three components of each together (a (C, 3) result).
    """
    pairs = subsets(n, 2)
    i, j = pairs[:, :1], pairs[:, 1:]
    k1, k2 = np.array([[1, 2, 0]]), np.array([[2, 0, 1]])
    indices = tuple(
        (row * n + column).ravel() for row, column in ((k1, i), (k2, j), (k2, i), (k1, j))
    )
    for index in indices:
        index.flags.writeable = False
    return indices


class ZonotopeFacets(NamedTuple):
    """The facets of a zonotope, with what its vertex enumeration reuses.

    Attributes
    ----------
    generators : ndarray, shape (r, n)
        The non-zero generators (columns) of the zonotope given (whitened ones, for a
        :class:`~polyell.Polytope`).
    columns : ndarray of int, shape (n,)
        Their column indices in the matrix given.
    in_plane_tol : ndarray, shape (n,)
        ``_IN_FACET_RTOL |g_i|``: generator i lies in a facet's plane when
        ``|a . g_i|`` is at most this.
    normals : ndarray, shape (F, r)
        Unit outward facet normals: ``F/2`` directions ``a``, then their negatives.
    offsets : ndarray, shape (F,)
        ``h(a) = sum_i |a . g_i|``: the zonotope is ``{ y : normals @ y <= offsets }``.
    dots : ndarray, shape (F/2, n)
        ``a . g_i`` for the first ``F/2`` normals.
    in_facet : ndarray of bool, shape (F/2, n)
        ``|a . g_i| <= in_plane_tol``: generator i lies in the facet's plane.
    general_position : bool
        Every facet holds exactly r - 1 generators (a parallelotope facet).
    """

    generators: NDArray[np.float64]
    columns: NDArray[np.int_]
    in_plane_tol: NDArray[np.float64]
    normals: NDArray[np.float64]
    offsets: NDArray[np.float64]
    dots: NDArray[np.float64]
    in_facet: NDArray[np.bool_]
    general_position: bool


def zonotope_facets(G: NDArray[np.float64]) -> ZonotopeFacets:
    """Facet normals and offsets of the zonotope, ``Z = { y : normals @ y <= offsets }``.

    The tests on cofactors and on ``a . g_i`` are relative to unit generators: exact for a
    well-conditioned ``G``.  For a thin zonotope pass its whitened generators ``V^T`` and
    map the facets back with :func:`unwhiten` (as :class:`~polyell.Polytope` does).

    Parameters
    ----------
    G : ndarray, shape (r, n)
        Generators (columns) spanning R^r, r >= 1.

    Returns
    -------
    ZonotopeFacets
        Normals in pairs ``a, -a`` and offsets ``h(a) = sum_i |a . g_i|``.
    """
    r = G.shape[0]
    gens, lengths, columns = _nonzero_generators(G)
    if r == 1:
        half = np.ones((1, 1))
    else:
        # Cofactors of unit generators: their size is the volume spanned by the unit
        # vectors, so the dependence test needs no scale.
        cofactors = subset_cofactors(gens / lengths)
        size = np.sqrt((cofactors * cofactors).sum(axis=1))
        independent = size > DEPENDENT_RTOL
        if not independent.all():
            cofactors, size = cofactors[independent], size[independent]
        half = cofactors / size[:, None]
    tol = _IN_FACET_RTOL * lengths
    dots, size, in_facet, general = _incidence(half, gens, tol)
    if not general:  # two subsets may span one facet plane: keep its normal once
        half = _unique_directions(half)
        dots, size, in_facet, general = _incidence(half, gens, tol)
    offsets = size.sum(axis=1)
    return ZonotopeFacets(
        gens,
        columns,
        tol,
        np.concatenate([half, -half]),
        np.concatenate([offsets, offsets]),
        dots,
        in_facet,
        general,
    )


def unwhiten(
    normals: NDArray[np.float64],
    offsets: NDArray[np.float64],
    frame: NDArray[np.float64],
    sigma: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Facets of the whitened zonotope ``{V^T u}`` as facets of ``U S {V^T u}``.

    ``a_y . y <= h_y`` with ``y = S^-1 U^T x`` reads ``(U S^-1 a_y) . x <= h_y``; divided by
    ``|S^-1 a_y|`` (``U`` has orthonormal columns) the normal is a unit one.  Both sides
    keep the relative accuracy of ``a_y`` and ``h_y``: a division by ``sigma``, a norm
    and a product by the orthonormal ``U``, however thin the set.  Leading axes broadcast
    (a batch of configurations).

    Parameters
    ----------
    normals : ndarray, shape (..., F, r)
        Unit facet normals ``a_y`` of the whitened zonotope; zero rows (dependent subsets)
        stay zero.
    offsets : ndarray, shape (..., F)
        Their offsets ``h_y = sum_i |a_y . v_i|``.
    frame : ndarray, shape (..., m, r)
        ``U``: orthonormal columns, the left singular vectors of the generators.
    sigma : ndarray, shape (..., r)
        The (non-zero) singular values.

    Returns
    -------
    normals : ndarray, shape (..., F, m)
        Unit outward normals ``a_x`` in the m coordinates of ``frame``.
    offsets : ndarray, shape (..., F)
        ``h_x = h_y / |S^-1 a_y|``, the support of the set about its centre along ``a_x``.
    """
    scaled = normals / sigma[..., None, :]
    length = np.sqrt((scaled * scaled).sum(axis=-1))
    length = np.where(length > 0, length, 1.0)  # a zero row (no constraint) stays zero
    scaled /= length[..., None]
    return scaled @ np.swapaxes(frame, -1, -2), offsets / length


def _incidence(
    normals: NDArray[np.float64], gens: NDArray[np.float64], tol: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], bool]:
    """``a . g_i``, ``|a . g_i|``, the generators in each plane, and if each holds r - 1.

    In general position no two subsets share a plane (it would hold r generators), so
    the normals need no deduplication.
    """
    dots = normals @ gens
    size = np.abs(dots)
    in_facet = size <= tol
    general = np.count_nonzero(in_facet, axis=1) == gens.shape[0] - 1
    return dots, size, in_facet, bool(general.all())


def order_polygon(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """2-D points in counter-clockwise order about their mean."""
    centre = points.mean(axis=0)
    angles = np.arctan2(points[:, 1] - centre[1], points[:, 0] - centre[0])
    return points[np.argsort(angles)]


def _unique_points(points: NDArray[np.float64], atol: float) -> list[int]:
    """Indices of the points farther than ``atol`` from every earlier kept one."""
    keep: list[int] = []
    for i, p in enumerate(points):
        if not keep or np.min(np.linalg.norm(points[keep] - p, axis=1)) > atol:
            keep.append(i)
    return keep


def zonotope_vertices(
    facets: ZonotopeFacets, image: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """Extreme points of the zonotope from its facets (no 2^n enumeration).

    Parameters
    ----------
    facets : ZonotopeFacets
        From :func:`zonotope_facets`.
    image : ndarray, shape (p, n), optional
        The same zonotope's generators in other coordinates (``T @ G`` for the ``G`` given
        to :func:`zonotope_facets`, e.g. ``M`` for its whitened ``V^T``): the vertices are
        decided on ``facets`` and returned as sign vectors times these columns.

    Returns
    -------
    vertices : ndarray, shape (V, r) or (V, p)
        The extreme points; in counter-clockwise order when they are 2-D.
    """
    gens = facets.generators
    if image is None:
        out = gens
    else:  # the columns kept (all of them unless some generator is zero)
        out = image if len(facets.columns) == image.shape[1] else image[:, facets.columns]
    signs = _vertex_signs(facets)
    vertices = signs @ out.T
    return order_polygon(vertices) if out.shape[0] == 2 else vertices


def _vertex_signs(facets: ZonotopeFacets) -> NDArray[np.float64]:
    """The sign vectors (V, n) of the extreme points of a zonotope, from its facets."""
    positive = facets.dots > facets.in_plane_tol  # and not in the plane
    if facets.general_position:
        return _signs_in_general_position(positive, facets.in_facet)
    signs = _signs_by_faces(facets, positive)
    if signs is None:
        gens = facets.generators
        signs = _signs_by_active_facets(gens, facets.normals, facets.offsets)
        if not _hull_is_the_zonotope(signs @ gens.T, gens):
            signs = _corner_signs(gens)
    return signs


def _hull_is_the_zonotope(points: NDArray[np.float64], gens: NDArray[np.float64]) -> bool:
    """Whether the hull of candidate vertices has the zonotope's volume (none missed).

    The candidates are points of the zonotope, so their hull is inside it; equal volumes
    (to 1e-9, the closed form against Qhull) leave no room for a missed vertex beyond
    that.  The check of the last-resort path, which decides each candidate on facets
    found to a tolerance.
    """
    from scipy.spatial import QhullError

    r = gens.shape[0]
    if r < 2:
        return True
    try:
        hull = ConvexHull(points)
    except (QhullError, ValueError):
        return False
    return bool(abs(hull.volume - zonotope_volume(gens)) <= 1e-9 * zonotope_volume(gens))


def _corner_signs(gens: NDArray[np.float64]) -> NDArray[np.float64]:
    """The sign vectors of the vertices among all 2^n corners (Qhull), for n at most 16."""
    from polyell.errors import SolverError

    r, n = gens.shape
    if n > MAX_CORNER_JOINTS:
        raise SolverError(
            f"zonotope vertices: the facets of this {r}-D zonotope of {n} generators were "
            "decided inconsistently and its 2^n corners are too many to try; report it."
        )
    from scipy.spatial import QhullError

    signs = np.array(list(product((-1.0, 1.0), repeat=n)))
    try:
        return signs[ConvexHull(signs @ gens.T).vertices]
    except QhullError as exn:
        raise SolverError(f"zonotope vertices: Qhull failed on the 2^n corners ({exn}).") from exn


def _signs_by_faces(
    facets: ZonotopeFacets, positive: NDArray[np.bool_]
) -> NDArray[np.float64] | None:
    """Sign vectors of the vertices when some facets hold more than r - 1 generators.

    A facet of normal ``a`` is ``sum_{a . g_i > 0} g_i - sum_{a . g_i < 0} g_i`` plus the
    (r-1)-dimensional zonotope of the generators in its plane: its vertices are those of
    that zonotope, found the same way one dimension down (a structured Jacobian, as the
    Panda's, puts three generators in one plane), the generators off the plane keeping the
    signs fixed by ``a``.  Every vertex lies on a facet, so these are all the vertices;
    the decisions are the same in-plane tests as in general position.  None where a facet
    holds fewer than r - 1 generators (a plane decided inconsistently) or a face drops a
    generator as negligible: the caller then tests candidates against the active facets.
    """
    gens, in_facet = facets.generators, facets.in_facet
    r, n = gens.shape
    counts = in_facet.sum(axis=1)
    if n >= 63 or bool((counts < r - 1).any()):
        return None
    bits = _bits(n)
    general = counts == r - 1
    free = np.nonzero(in_facet[general])[1].reshape(-1, r - 1)
    keys = [(positive[general] @ bits + _corner_bits(r - 1) @ bits[free].T).ravel()]
    normals = facets.normals[: len(in_facet)]
    for f in np.flatnonzero(~general):
        columns = np.flatnonzero(in_facet[f])
        plane = np.linalg.svd(normals[f][:, None])[0][:, 1:]  # (r, r-1): orthogonal to a
        face = zonotope_facets(plane.T @ gens[:, columns])
        if len(face.columns) < len(columns):
            return None
        face_signs = (
            _signs_in_general_position(face.dots > face.in_plane_tol, face.in_facet)
            if face.general_position
            else _signs_by_faces(face, face.dots > face.in_plane_tol)
        )
        if face_signs is None:
            return None
        keys.append(positive[f] @ bits + (face_signs > 0) @ bits[columns])
    return _signs_of_keys(np.concatenate(keys), n)


def _signs_of_keys(keys: NDArray[np.int64], n: int) -> NDArray[np.float64]:
    """Sign vectors (V, n) of the integer keys and of their complements, without repeats."""
    if n <= _SIGN_TABLE_JOINTS:  # mark the keys present in a table of all 2^n
        present = np.zeros(1 << n, dtype=bool)
        present[keys] = True
        present |= present[::-1]
        return _sign_table(n)[present]
    keys = np.unique(np.concatenate([keys.ravel(), keys.ravel() ^ ((1 << n) - 1)]))
    return (((keys[:, None] >> np.arange(n)) & 1) * 2.0 - 1.0).astype(np.float64)


def _signs_in_general_position(
    positive: NDArray[np.bool_], in_facet: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """Every facet is a parallelotope of r - 1 generators: all its corners are vertices.

    ``positive`` (``a . g_i`` above the in-plane tolerance) and ``in_facet``, both (F, n),
    describe one normal of each pair ``a, -a``; the vertices on ``-a`` are the negatives
    of those on ``a``.  A vertex has a unique sign vector (no generator is zero), so the
    candidates are deduplicated exactly on their signs.  Returns the sign vectors (V, n).
    """
    F, n = positive.shape
    free = np.nonzero(in_facet)[1].reshape(F, -1)  # (F, r-1)
    if n >= 63:  # sign vectors do not fit in an integer key: rows of signs instead
        corners = np.array(list(product((-1, 1), repeat=free.shape[1])), dtype=np.int8)
        rows = np.repeat(np.where(positive, 1, -1).astype(np.int8)[:, None], len(corners), 1)
        facet = np.arange(F)[:, None, None]
        rows[facet, np.arange(len(corners))[None, :, None], free[:, None, :]] = corners[None]
        rows = rows.reshape(-1, n)
        return np.unique(np.concatenate([rows, -rows]), axis=0).astype(float)
    # A sign vector as the bits of an integer (bit i set: +g_i): the generators off the
    # facet plane are fixed by the normal, those in it take every combination.  The
    # opposite facet's vertices have every bit flipped: key ^ (2^n - 1) = 2^n - 1 - key.
    bits = _bits(n)
    keys = positive @ bits + _corner_bits(free.shape[1]) @ bits[free].T  # (2^(r-1), F)
    return _signs_of_keys(keys, n)


def _signs_by_active_facets(
    gens: NDArray[np.float64], normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Any arrangement: candidates from each facet, kept if the active facets span R^r.

    Returns the sign vectors (V, n) of the extreme points.
    """
    r = gens.shape[0]
    lengths = np.linalg.norm(gens, axis=0)
    atol = 1e-9 * max(lengths.sum(), 1e-300)
    candidates = []
    for a in normals:
        dots = a @ gens
        in_facet = np.abs(dots) <= _IN_FACET_RTOL * lengths
        free = np.flatnonzero(in_facet)
        corners = np.array(list(product((-1.0, 1.0), repeat=free.size)), dtype=float)
        corners = corners.reshape(2**free.size, free.size)  # one empty row if none is free
        signs = np.repeat(np.sign(dots)[None, :], len(corners), axis=0)
        signs[:, free] = corners
        candidates.append(signs)
    signs = np.concatenate(candidates)
    points = signs @ gens.T
    active = np.abs(points @ normals.T - offsets) <= atol  # (P, F)
    # The active unit normals span R^r iff their Gram matrix sum_f a_f a_f^T is regular:
    # one batched symmetric eigensolve instead of a rank per point.  The whitened normals
    # are well scaled, so a relative 1e-10 on its smallest eigenvalue (1e-5 on the normals'
    # smallest singular value) separates regular from rank-deficient sets.
    gram = np.einsum("pf,fi,fj->pij", active.astype(float), normals, normals)
    eigenvalues = np.linalg.eigvalsh(gram)
    extreme = (active.sum(axis=1) >= r) & (eigenvalues[:, 0] > 1e-10 * eigenvalues[:, -1])
    return signs[extreme][_unique_points(points[extreme], atol)]


def zonotope_volume(G: NDArray[np.float64]) -> float:
    """Volume of the zonotope in R^r: ``2^r sum_{|S| = r} |det G_S|``.

    Parameters
    ----------
    G : ndarray, shape (r, n)
        Generators; r = 0 gives 1 (the counting measure of a point).
    """
    r = G.shape[0]
    if r == 0:
        return 1.0
    gens = _nonzero_generators(G)[0]
    chosen = subsets(gens.shape[1], r)
    if chosen.size == 0:
        return 0.0
    dets = np.linalg.det(np.transpose(gens[:, chosen], (1, 0, 2)))
    return float(2.0**r * np.abs(dets).sum())


def corner_vertices(G: NDArray[np.float64]) -> NDArray[np.float64]:
    """Extreme points by brute force: the images of all 2^n cube corners, reduced by Qhull.

    An independent check of :func:`zonotope_vertices`; exponential in ``n``.

    Parameters
    ----------
    G : ndarray, shape (r, n)
        Generators spanning R^r, r >= 1, with ``n <= MAX_CORNER_JOINTS``.

    Raises
    ------
    InputError
        If ``n > MAX_CORNER_JOINTS``.
    """
    r, n = G.shape
    if n > MAX_CORNER_JOINTS:
        raise InputError(
            "generators",
            f"at most {MAX_CORNER_JOINTS} columns for the 2^n corner enumeration",
            f"{n} columns",
            "use the facet-based vertices (Polytope.vertices), which scale polynomially.",
        )
    corners = np.array(list(product((-1.0, 1.0), repeat=n))) @ G.T
    if r == 1:
        return np.array([[corners.min()], [corners.max()]])
    hull = ConvexHull(corners)
    points = corners[hull.vertices]
    return order_polygon(points) if r == 2 else points
