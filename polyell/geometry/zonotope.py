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

Batches (a leading axis K of configurations): :func:`facets` and :func:`vertex_signs` are
the sweeps' set builders (:mod:`polyell.studies.block_sets`), and one zonotope in R^2 or
R^3 is their batch of one (:func:`zonotope_facets` takes the facets and the vertex codes
from the same decisions); the enumeration one subset at a time stays where a decision is
too close to its threshold to be the batch's.
"""

from __future__ import annotations

import math
from functools import lru_cache
from itertools import combinations, product
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull

from polyell.errors import InputError

__all__ = [
    "DEPENDENT_RTOL",
    "IN_PLANE_RTOL",
    "LOOSE_RTOL",
    "MAX_CORNER_JOINTS",
    "MAX_VERTEX_GENERATORS",
    "SIGN_RTOL",
    "ZERO_RTOL",
    "BlockFacets",
    "ZonotopeFacets",
    "corner_vertices",
    "facets",
    "order_polygon",
    "subset_cofactors",
    "unwhiten",
    "vertex_count",
    "vertex_signs",
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
#: Reductions without the array methods' Python wrappers (several microseconds apiece on
#: the small arrays of one set).
_ADD, _MAX, _MIN = np.add.reduce, np.maximum.reduce, np.minimum.reduce
_ANY, _ALL = np.logical_or.reduce, np.logical_and.reduce
#: The smallest positive normal double.
_TINY = float(np.finfo(np.float64).tiny)


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
    earlier, later = np.nonzero(close)  # row by row; the pairs above the diagonal kept
    above = earlier < later
    earlier, later = earlier.compress(above), later.compress(above)
    first, second = normals.take(earlier, 0), normals.take(later, 0)
    difference, total = first - second, first + second
    distance = np.sqrt(  # the Euclidean norms of numpy.linalg.norm, without its wrapper
        np.minimum(_ADD(difference * difference, 1), _ADD(total * total, 1))
    )
    duplicate = np.zeros(len(normals), dtype=bool)
    duplicate[later.compress(distance < _SAME_NORMAL_TOL)] = True
    return normals.compress(~duplicate, 0)


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
    if r == 3:  # the common task: one gather of four factors from the flattened generators
        t = G.reshape(*batch, 3 * n).take(_cross_indices(n), -1)  # (..., 4, 3 C)
        products = t[..., 0, :] * t[..., 1, :] - t[..., 2, :] * t[..., 3, :]
        return products.reshape(*batch, -1, 3)
    return cross(np.moveaxis(G[..., subsets(n, r - 1)], -3, -2))  # (..., C, r, r-1)


@lru_cache(maxsize=64)
def _cross_indices(n: int) -> NDArray[np.int_]:
    """Flat indices into a (3, n) array for ``g_i x g_j`` over the pairs ``subsets(n, 2)``.

    Component k of the cross product is ``g_i[k+1] g_j[k+2] - g_i[k+2] g_j[k+1]`` (mod 3):
    the four factors' indices as rows (4, 3 C), pair by pair, the three components of each
    together (a (C, 3) result).
    """
    pairs = subsets(n, 2)
    i, j = pairs[:, :1], pairs[:, 1:]
    k1, k2 = np.array([[1, 2, 0]]), np.array([[2, 0, 1]])
    indices = np.stack(
        [(row * n + column).ravel() for row, column in ((k1, i), (k2, j), (k2, i), (k1, j))]
    )
    indices.flags.writeable = False
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
    keys : ndarray of int64, shape (k,), or None
        Codes of the vertices' sign vectors over ``columns`` (bit i: ``+g_i``; with
        repeats, one of each +-pair at least) where the batch of one decided them
        (:func:`_facets_of_one`); None: :func:`zonotope_vertices` enumerates.
    """

    generators: NDArray[np.float64]
    columns: NDArray[np.int_]
    in_plane_tol: NDArray[np.float64]
    normals: NDArray[np.float64]
    offsets: NDArray[np.float64]
    dots: NDArray[np.float64]
    in_facet: NDArray[np.bool_]
    general_position: bool
    keys: NDArray[np.int64] | None = None


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
    if G.shape[0] in (2, 3) and G.shape[1] <= MAX_VERTEX_GENERATORS:
        # the batched decisions as a batch of one (and the vertices with them), where clear
        one = _facets_of_one(G)
        if one is not None:
            return one
    return _enumerated_facets(G)


def _enumerated_facets(G: NDArray[np.float64]) -> ZonotopeFacets:
    """The facets of :func:`zonotope_facets` by its subsets, one decision at a time.

    Any r; the vertices are left to :func:`zonotope_vertices` (no ``keys``).
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
    # A zero row (no constraint) stays zero: divided by the smallest normal number, which
    # no other row's length is below (sigma is at most about 1e146, check_magnitudes).
    length = np.maximum(np.sqrt(_ADD(scaled * scaled, -1)), _TINY)
    scaled /= length[..., None]
    return scaled @ frame.swapaxes(-1, -2), offsets / length


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
    if facets.keys is not None:  # decided with the facets (a batch of one)
        return _signs_of_keys(facets.keys, facets.generators.shape[1])
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
        face = _enumerated_facets(plane.T @ gens[:, columns])
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
        present.put(keys, True)
        present.put(keys ^ ((1 << n) - 1), True)  # their complements (-sigma)
        return _sign_table(n).compress(present, axis=0)
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


# --- Batches of zonotopes --------------------------------------------------------------
# Leading axis K: the configurations of a sweep's block (polyell.studies.block_sets), or a
# batch of one (zonotope_facets, for a Polytope).

#: A generator whose (unit) normal product with a facet's (unit) normal is at most this
#: lies in that facet: a configuration not in general position, whose vertices the
#: scalar path enumerates (exact, with cddlib's check) for m > 3.
SIGN_RTOL = 1e-9
#: For m <= 3 (:func:`vertex_signs`) decisions are made below the scalar path's thresholds
#: (zero generators and parallel pairs at 1e-12, in-plane generators at 1e-10) and left to
#: it in a band above.  A whitened generator at most this long (relative to the longest) is
#: zero, two unit generators whose cross product is at most this long are parallel:
#: structural zeros (a tip on a joint axis) come out near 1e-16, or 1e-13 divided by a
#: light link's inertia; the whitened coordinates of the two paths agree to about 1e-16
#: times the condition number of M.
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
        Unit normals ``a_x`` in task coordinates (:func:`unwhiten`).
    offsets : ndarray, shape (K, C)
        Half-widths ``h_x`` about ``xg``: ``P = {x : |a_x . (x - xg)| <= h_x}``.
    """

    whitened: NDArray[np.float64]
    whitened_offsets: NDArray[np.float64]
    normals: NDArray[np.float64]
    offsets: NDArray[np.float64]


def facets(U: NDArray[np.float64], s: NDArray[np.float64], V1t: NDArray[np.float64]) -> BlockFacets:
    """Facets of every configuration's zonotope, enumerated in its whitened coordinates.

    As :func:`zonotope_facets` does for one (DESIGN.md section 7): cross products of the
    unit whitened generators (the columns of ``V^T``), a subset dependent when theirs is
    at most ``DEPENDENT_RTOL`` long, mapped back by :func:`unwhiten`.  Exact in number
    and accurate to the data for any ``sigma_min / sigma_max`` above the rank threshold.

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
        lengths = np.sqrt((V1t * V1t).sum(axis=1))
        # A generator negligible against the longest (a Jacobian column of 1e-16 where the
        # tip lies on a joint's axis) has no direction: zero, as _nonzero_generators does.
        lengths[lengths <= _ZERO_GENERATOR_RTOL * lengths.max(axis=-1, keepdims=True)] = np.inf
        unit = V1t / lengths[:, None, :]
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


def vertex_signs(
    V1t: NDArray[np.float64], normals: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
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


def _unit_generators(
    V1t: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """Unit generators (K, m, n) (zero ones: 0), which are zero (K, n), and the clear rows (K,).

    A row is not clear where a generator is between :data:`ZERO_RTOL` and
    :data:`LOOSE_RTOL` of the longest (its direction too inaccurate) or the longest is not
    finite.
    """
    lengths = np.sqrt((V1t * V1t).sum(axis=1))  # (K, n)
    longest = lengths.max(axis=1, keepdims=True)
    zero = ~(lengths > ZERO_RTOL * longest)
    clear = ~(~zero & (lengths <= LOOSE_RTOL * longest)).any(axis=1)
    clear &= np.isfinite(longest[:, 0])
    unit = np.where(zero[:, None, :], 0.0, V1t / np.where(zero, 1.0, lengths)[:, None, :])
    return unit, zero, clear


def _pair_planes(
    size: NDArray[np.float64], magnitude: NDArray[np.float64], near: NDArray[np.bool_]
) -> tuple[NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]:
    """Which subsets span a facet plane and which generators lie in it, and if that is clear.

    Parameters
    ----------
    size : ndarray, shape (K, C)
        The lengths of the cofactors of the unit generators (:func:`subset_cofactors`).
    magnitude : ndarray, shape (K, C, n)
        ``|cofactor . u_k| = |cofactor| |a . u_k|``.
    near : ndarray of bool, shape (K, C, n)
        ``magnitude <= SIGN_RTOL |cofactor|``.

    Returns
    -------
    valid : ndarray of bool, shape (K, C)
        The cofactor is longer than :data:`ZERO_RTOL`: a plane (its generators neither
        zero nor parallel).
    flat : ndarray of bool, shape (K, C, n)
        ``|a . u_k| <= IN_PLANE_RTOL``: generator k lies in the plane.
    clear : ndarray of bool, shape (K,)
        No cofactor between :data:`ZERO_RTOL` and :data:`LOOSE_RTOL` long and no product
        of a plane between :data:`IN_PLANE_RTOL` and :data:`SIGN_RTOL` (relative):
        decisions that the scalar path makes alike.
    """
    valid = size > ZERO_RTOL
    flat = magnitude <= IN_PLANE_RTOL * size[..., None]
    unclear = _ANY(near ^ flat, 2) | (size <= LOOSE_RTOL)
    return valid, flat, ~_ANY(unclear & valid, 1)


def _flag_codes(
    unit: NDArray[np.float64],
    zero: NDArray[np.bool_],
    cofactors: NDArray[np.float64],
    size: NDArray[np.float64],
    products: NDArray[np.float64],
    valid: NDArray[np.bool_],
    flat: NDArray[np.bool_],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    r"""The vertex codes of zonotopes in R^2 or R^3 from flags of faces, any arrangement.

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
    every vertex comes out.  The sign vectors are coded as bits (bit k: ``+g_k``; zero
    generators: bit 0).

    Parameters
    ----------
    unit : ndarray, shape (K, m, n)
        Unit whitened generators (zero ones: 0), m = 2 or 3, n <= 62.
    zero : ndarray of bool, shape (K, n)
        The zero generators.
    cofactors, size, products, valid, flat : ndarray
        The cofactors (K, C, m) of the unit generators, their lengths (K, C) and products
        (K, C, n), and :func:`_pair_planes`' ``valid`` and ``flat``, for the subsets
        ``subsets(n, m - 1)``.

    Returns
    -------
    codes : ndarray of int64, shape (K, C, 2^(m-1))
        The codes of the vertices on the facet ``+a`` of each frame (those on ``-a`` are
        their complements over the non-zero generators); meaningless where not ``valid``.
    clear : ndarray of bool, shape (K,)
        No product deciding an in-plane generator's sign within :data:`SIGN_RTOL` of zero
        (relative; those of the planes are :func:`_pair_planes`' ``clear``).
    """
    K, m, n = unit.shape
    bits = _bits(n)
    edge, first, pair, edge_bits, edge_flips = _frames(n, m)
    # The bits of the generators decided by a later vector of the frame flip with its
    # sense: (K, C, 2^(m-1)) flips, the choices of senses.
    if m == 3 and _ALL(valid, None):
        # No zero or parallel generators: in a plane, only u_j itself is parallel to u_j,
        # and every other generator k is at least LOOSE_RTOL from it (|b . u_k| is the
        # sine between them): u_j's sign flips with the edge's sense, the others' with b's.
        # For k in the plane, u_k = alpha u_i + beta u_j and b . u_i < 0: the sign of
        # b . u_k is that of -alpha, of -(u_k x u_j) . (u_i x u_j).
        edge_pairs, sense = _edge_pairs(n)
        middle = _ADD(cofactors.take(edge_pairs, axis=1) * cofactors[:, :, None, :], -1)
        deciding = np.where(flat, middle * sense, products)
        flips = ((flat @ bits ^ edge_bits)[..., None] & _FLIPS[1]) | edge_flips
        return ((deciding > 0) @ bits)[..., None] ^ flips, np.ones(K, dtype=bool)
    gram = unit.swapaxes(1, 2) @ unit  # (K, n, n)
    along = gram.take(edge, axis=1)  # u_j . u_k (K, C, n)
    if m == 2:  # frame j: a = (-u_j2, u_j1), u_j; in a's line: parallel to u_j
        deciding = np.where(flat, along, products)
        flips = (flat @ bits & (~zero @ bits)[:, None])[..., None] & _FLIPS[1]
        return ((deciding > 0) @ bits)[..., None] ^ flips, np.ones(K, dtype=bool)
    # |cofactor| (b . u_k) = (u_i . u_j)(u_j . u_k) - u_i . u_k
    middle = gram.reshape(K, n * n).take(pair, axis=1)[..., None] * along
    middle -= gram.take(first, axis=1)
    middle_magnitude = np.abs(middle)
    scale = size[..., None]
    flat_middle = middle_magnitude <= IN_PLANE_RTOL * scale
    deciding = np.where(flat, np.where(flat_middle, along, middle), products)
    by_edge_normal = flat & ~flat_middle
    ambiguous = by_edge_normal & (middle_magnitude <= SIGN_RTOL * scale)
    clear = ~_ANY(_ANY(ambiguous, 2) & valid, 1)
    by_edge = (flat & flat_middle) @ bits & (~zero @ bits)[:, None]
    flips = ((by_edge_normal @ bits)[..., None] & _FLIPS[1]) | (by_edge[..., None] & _FLIPS[2])
    return ((deciding > 0) @ bits)[..., None] ^ flips, clear


#: The sense choices of a frame's later vectors: all bits (-1) where a choice flips them.
_FLIPS = (
    np.zeros(4, dtype=np.int64),
    np.array([0, -1, 0, -1], dtype=np.int64),  # the second vector (b; u_j in R^2)
    np.array([0, 0, -1, -1], dtype=np.int64),  # the third (u_j in R^3)
)


@lru_cache(maxsize=64)
def _edge_pairs(n: int) -> tuple[NDArray[np.int_], NDArray[np.float64]]:
    """For the pairs (i, j) of ``subsets(n, 2)`` and every generator k: the pair {k, j}.

    Its index in ``subsets(n, 2)`` (C, n) (any for k = j), and ``sense`` (C, n): -1 where
    k < j (its cofactor is ``u_k x u_j``), +1 where k > j (``-(u_k x u_j)``), 0 at k = j.
    """
    index = {pair: p for p, pair in enumerate(map(tuple, subsets(n, 2).tolist()))}
    j = subsets(n, 2)[:, 1]
    pairs = np.array([[index.get((min(k, e), max(k, e)), 0) for k in range(n)] for e in j])
    k = np.arange(n)
    sense = np.where(k[None, :] < j[:, None], -1.0, np.where(k[None, :] > j[:, None], 1.0, 0.0))
    pairs = pairs.reshape(len(j), n)
    pairs.flags.writeable = sense.flags.writeable = False
    return pairs, sense


@lru_cache(maxsize=64)
def _frames(n: int, m: int) -> tuple[NDArray[np.int_], ...]:
    """The frames of :func:`_flag_codes` over ``subsets(n, m - 1)``.

    Their edges j and first generators i (for m = 2 the same), the flat index ``i n + j``
    of ``u_i . u_j``, the bit of j and its flips with the third vector's sense (C, 4).
    """
    S = subsets(n, m - 1)
    edge, first = S[:, -1].copy(), S[:, 0].copy()
    pair = first * n + edge
    edge_bits = _bits(n)[edge]
    edge_flips = edge_bits[:, None] & _FLIPS[2]
    for array in (edge, first, pair, edge_bits, edge_flips):
        array.flags.writeable = False
    return edge, first, pair, edge_bits, edge_flips


def _flag_signs(V1t: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    r"""Vertex sign vectors of zonotopes in R^2 or R^3, whatever their degeneracies.

    The codes of :func:`_flag_codes`, made canonical (the smaller of a code and its
    complement over the non-zero generators) and unique.  Rows with a generator or a
    cross product between :data:`ZERO_RTOL` and :data:`LOOSE_RTOL` long, or a deciding
    product between :data:`IN_PLANE_RTOL` and :data:`SIGN_RTOL` (decisions that could
    differ from the scalar path's), are not enumerated.

    Parameters
    ----------
    V1t : ndarray, shape (K, m, n)
        Whitened generators, m = 2 or 3, n <= :data:`MAX_VERTEX_GENERATORS`.

    Returns
    -------
    signs, generic
        As :func:`vertex_signs`.
    """
    K, n = V1t.shape[0], V1t.shape[2]
    unit, zero, generic = _unit_generators(V1t)
    cofactors = subset_cofactors(unit)
    size = np.sqrt((cofactors * cofactors).sum(axis=-1))
    products = cofactors @ unit  # |cofactor| (a . u_k)
    magnitude = np.abs(products)
    near = magnitude <= SIGN_RTOL * size[..., None]
    valid, flat, clear = _pair_planes(size, magnitude, near)
    codes, clear_edges = _flag_codes(unit, zero, cofactors, size, products, valid, flat)
    generic &= clear & clear_edges
    nonzero = ~zero @ _bits(n)  # (K,)
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


def _general_position_signs(
    V1t: NDArray[np.float64], normals: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
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
    in_subset = _facet_corner_codes(n, m)[1]
    with np.errstate(divide="ignore", invalid="ignore"):  # a zero generator: dependent rows
        unit = V1t / np.linalg.norm(V1t, axis=1)[:, None, :]
    products = normals @ unit  # (K, C, n)
    off = ~in_subset[None]
    generic = ~np.any(off & ~(np.abs(products) > SIGN_RTOL), axis=(1, 2))  # NaN: not generic
    generic &= ~np.any((normals == 0).all(axis=-1), axis=1)  # a dependent subset
    codes = _general_position_codes(off & (products > 0), n, m).reshape(K, -1)
    codes = np.where(codes & 1, codes, codes ^ ((np.int64(1) << n) - 1))  # sigma_1 = +1
    codes.sort(axis=1)
    first = np.ones(codes.shape, dtype=bool)
    first[:, 1:] = codes[:, 1:] != codes[:, :-1]
    generic &= first.sum(axis=1) == V
    unique = np.zeros((K, V), dtype=np.int64)
    unique[generic] = codes[generic][first[generic]].reshape(-1, V)
    signs = ((unique[..., None] >> np.arange(n)) & 1) * 2.0 - 1.0
    return np.where(generic[:, None, None], signs, 0.0), generic


def _general_position_codes(positive: NDArray[np.bool_], n: int, m: int) -> NDArray[np.int64]:
    """The vertex codes on the facets ``+a`` of zonotopes in general position.

    ``positive`` (K, C, n): ``a . g_i > 0`` off the facet's subset S (False on S), for the
    subsets of :func:`subsets` ``(n, m - 1)``.  Returns (K, C, 2^(m-1)): the generators
    off S take the sign of ``a . g_i``, those on S every choice.
    """
    corner_codes = _facet_corner_codes(n, m)[0]
    base: NDArray[np.int64] = positive @ _bits(n)  # (K, C)
    return base[..., None] + corner_codes


def _facets_of_one(G: NDArray[np.float64]) -> ZonotopeFacets | None:
    """:func:`zonotope_facets` of a zonotope in R^2 or R^3 as a batch of one, with its vertices.

    The batch's decisions on the one zonotope: its generators (:func:`_unit_generators`),
    general position as :func:`_general_position_signs` decides it, else the planes and
    flags of :func:`_pair_planes` and :func:`_flag_codes`.  The facets are those of
    :func:`_enumerated_facets` (the same normals; a plane held by several subsets kept once,
    at the first of them), the vertices are coded with them (``keys``).  None where a
    decision is not clear (a length or a product in a band about its threshold, or facet
    planes the two decisions of "in the plane" group differently): the caller enumerates.
    """
    r = G.shape[0]
    lengths = np.sqrt(_ADD(G * G, 0))
    columns = None
    if not _MIN(lengths) > LOOSE_RTOL * _MAX(lengths):  # zero, short or not finite
        _, zero, clear = _unit_generators(G[None])
        if not clear[0]:
            return None
        columns = np.flatnonzero(~zero[0])  # far below the scalar path's threshold too
        G, lengths = G[:, columns], lengths[columns]
    n = G.shape[1]
    if n < r:
        return None
    unit = G / lengths
    cofactors = subset_cofactors(unit)  # (C, r)
    size = np.sqrt(_ADD(cofactors * cofactors, 1))
    products = cofactors @ unit  # |cofactor| (a . u_k)
    magnitude = np.abs(products)
    threshold = SIGN_RTOL * size[:, None]
    near = magnitude <= threshold
    if np.count_nonzero(near) == len(size) * (r - 1) and _MIN(size) > LOOSE_RTOL:
        # general position: each facet holds its subset alone, every other product clear
        half = cofactors / size[:, None]
        keys = _general_position_codes(products > threshold, n, r)
        in_facet, general = near, True
    else:
        valid, flat, clear = _pair_planes(size[None], magnitude[None], near[None])
        if not clear[0]:
            return None
        batch = unit[None], np.zeros((1, n), dtype=bool), cofactors[None], size[None]
        codes, clear = _flag_codes(*batch, products[None], valid, flat)
        if not clear[0]:
            return None
        valid, flat, general = valid[0], flat[0], False
        keys = codes[0].compress(valid, axis=0)
        first = _first_of_planes(flat @ _bits(n), valid, n, r)
        half = cofactors.compress(first, axis=0) / size.compress(first)[:, None]
        in_facet = flat.compress(first, axis=0)
        # The scalar path keeps a normal once where later ones are within 1e-10 of it,
        # which the in-plane decisions guarantee where the cofactors are long; elsewhere
        # its grouping must have as many planes.
        if not _MIN(size.compress(valid & ~first), initial=np.inf) > _CONSISTENT_SIZE:
            unique = _unique_directions(cofactors.compress(valid, axis=0) / size[valid, None])
            if len(unique) != len(half):
                return None  # the two decisions of "in the plane" group differently
    dots = half @ G
    offsets = _ADD(np.abs(dots), 1)
    return ZonotopeFacets(
        G,
        _columns(n) if columns is None else columns,
        _IN_FACET_RTOL * lengths,
        np.concatenate((half, -half)),
        np.concatenate((offsets, offsets)),
        dots,
        in_facet,
        general,
        keys.ravel(),
    )


#: Subsets of the same plane whose cofactors (of unit generators) are longer than this have
#: unit normals within 1e-10 of one another (the in-plane decisions are at 1e-11; the
#: normals differ by at most 2 sqrt(2) 1e-11 / |cofactor|): the scalar path's grouping.
_CONSISTENT_SIZE = 0.3


@lru_cache(maxsize=64)
def _columns(n: int) -> NDArray[np.int_]:
    """``arange(n)`` (cached, read-only)."""
    columns = np.arange(n)
    columns.flags.writeable = False
    return columns


def _first_of_planes(
    plane: NDArray[np.int64], valid: NDArray[np.bool_], n: int, m: int
) -> NDArray[np.bool_]:
    """The subsets that are the first of their facet plane (in the order of :func:`subsets`).

    Parameters
    ----------
    plane : ndarray of int64, shape (C,)
        The generators in each subset's plane, as bits (subset i, j for m = 3, j for
        m = 2; the plane holds them).
    valid : ndarray of bool, shape (C,)
        The subsets that span a plane (m = 3: i and j not parallel).
    n, m : int
        The number of generators, and the dimension (2 or 3).

    Returns
    -------
    ndarray of bool, shape (C,)
        In R^2 a generator is the first of its line when no generator before it lies on
        it.  In R^3 the first valid subset of a plane is ``(i, j)`` with ``i`` its first
        generator and ``j`` the first after it not parallel to ``i``: no generator of the
        plane before ``i``, and none between ``i`` and ``j`` but those parallel to ``i``.
    """
    low_i, low_j, others, pair_rows = _subset_masks(n, m)
    if m == 2:
        return (plane & low_j) == 0
    if _ALL(valid, None):  # no parallel generators: none before j but i
        return (plane & low_j) == others
    # each generator's parallel ones, as bits (itself too): i's gets j's bit, j's i's
    at_first, at_last, bits_i, bits_j = _pair_incidence(n)
    parallel_pairs = ~valid
    parallel = _bits(n) | at_first @ (bits_j * parallel_pairs) | at_last @ (bits_i * parallel_pairs)
    return valid & ((plane & low_i) == 0) & ((plane & low_j & ~parallel.take(pair_rows[0])) == 0)


@lru_cache(maxsize=64)
def _pair_incidence(n: int) -> tuple[NDArray[np.int64], ...]:
    """The pairs p = (i, j) of ``subsets(n, 2)``: which generators are their ends, and theirs.

    (n, C) 0/1 matrices (generator g is the first, the last, of the pair p), then the bits
    of each pair's first and last generators (C,) each.
    """
    pairs = subsets(n, 2)
    at_first = (np.arange(n)[:, None] == pairs[:, 0]).astype(np.int64)
    at_last = (np.arange(n)[:, None] == pairs[:, 1]).astype(np.int64)
    bits_i, bits_j = _bits(n)[pairs[:, 0]], _bits(n)[pairs[:, 1]]
    for array in (at_first, at_last, bits_i, bits_j):
        array.flags.writeable = False
    return at_first, at_last, bits_i, bits_j


@lru_cache(maxsize=64)
def _subset_masks(n: int, m: int) -> tuple[NDArray[np.int_], ...]:
    """Masks of the subsets ``subsets(n, m - 1)``, as bits, and their generators.

    The bits below each subset's first generator, below its last and of its others than
    the last, (C,) each; and the subsets as rows (m - 1, C).
    """
    S = subsets(n, m - 1)
    bits = _bits(n)
    low_i, low_j = bits[S[:, 0]] - 1, bits[S[:, -1]] - 1
    others = bits[S[:, :-1]].sum(axis=1)
    rows = np.ascontiguousarray(S.T)
    for array in (low_i, low_j, others, rows):
        array.flags.writeable = False
    return low_i, low_j, others, rows
