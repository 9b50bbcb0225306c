r"""Two arms on one object: the sum and the intersection of two sets of the same task space.

Two arms holding one object in the same task frame exert the sum of their forces, so the
forces they can exert together form the Minkowski sum
:math:`P_1 \oplus P_2 = \{h_1 + h_2\}` (its vertices are among the sums of vertices);
the forces each of them can exert alone form the intersection :math:`P_1 \cap P_2` (the
two sets of half-spaces together).  Both are :class:`~polyell.HPolytope` objects that
:func:`~polyell.comparison.metrics.inscribed_scale` and the other metrics score like any
set.

The sum is computed at the speed of its vertex count, never from the hull of all pairwise
sums of vertices.  Two zonotopes add to the zonotope of both sets of generators, whose
facets and vertices are closed forms (:class:`~polyell.Polytope`).  Otherwise the sum's
vertex graph is walked: a vertex of the sum is ``v1 + v2`` with ``v1`` and ``v2`` the
vertices of each set maximising one direction, its tangent cone is the cone of both sets'
edges at ``v1`` and ``v2`` (Fukuda, "From the zonotope construction to the Minkowski
addition of convex polytopes", J. Symb. Comput. 38, 2004), the extreme rays among them are
its edges (to ``w1 + v2`` or ``v1 + w2``, both for parallel edges) and the extreme rays of
its normal cone ``{c : c . e <= 0}`` are its facet normals, each with the offset
``h1(a) + h2(a)`` (support functions add).

Two arms whose bases differ: each arm's set, computed in its own base frame, is first
expressed in a common frame by :func:`in_frame` (forces rotate, ``f = R f_base``; the
moments of a wrench pick up ``p x f`` from the point they are taken about), then added or
intersected.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.geometry.convex_set import ConvexSet
from polyell.geometry.hpolytope import (
    WALK_ON_PLANE,
    HPolytope,
    _Ambiguous,
    _cone_rays,
    _unique_directions,
    vertex_edges,
)
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import RANK_RTOL
from polyell.validation import check_array

__all__ = ["ROTATION_ATOL", "in_frame", "intersection", "minkowski_sum"]

#: Largest ``max |R^T R - I|`` (and ``|det R - 1|``) of a matrix taken as a rotation; the
#: nearest rotation (its polar factor) is then used.  Rotations computed in double
#: precision are within 1e-15; one typed to 6 digits is not a rotation here.
ROTATION_ATOL = 1e-9
#: The rows :func:`in_frame` knows, as axes of the 3-D frame: forces, then moments.
_FORCE_ROWS = ("x", "y", "z")
_MOMENT_ROWS = ("wx", "wy", "wz")

Set = Polytope | HPolytope


def _check_pair(P1: object, P2: object) -> tuple[Set, Set]:
    for name, P in (("P1", P1), ("P2", P2)):
        if not isinstance(P, Polytope | HPolytope):
            raise InputError(
                name,
                "a pe.Polytope or a pe.HPolytope",
                type(P).__name__,
                "pass a set the library builds, e.g. pe.analyze(...).polytope or "
                "pe.HPolytope(A, b).",
            )
    assert isinstance(P1, Polytope | HPolytope) and isinstance(P2, Polytope | HPolytope)
    if P1.ambient_dim != P2.ambient_dim:
        raise InputError(
            "P2",
            f"a set of the same {P1.ambient_dim}-dimensional task space as P1",
            f"a set of a {P2.ambient_dim}-dimensional one",
            "two polytopes of different task spaces cannot be added or intersected: "
            "express both in the same task frame and rows.",
        )
    return P1, P2


def _halfspaces(P: Set) -> tuple[np.ndarray, np.ndarray]:
    """All of P's constraints as half-spaces (an equality as two)."""
    if isinstance(P, HPolytope) and P.is_empty:
        m = P.ambient_dim
        return np.zeros((1, m)), np.array([-1.0])  # 0 <= -1: nothing satisfies it
    A_eq, b_eq = P.A_eq, P.b_eq
    return np.vstack([P.A, A_eq, -A_eq]), np.concatenate([P.b, b_eq, -b_eq])


def minkowski_sum(P1: Set, P2: Set) -> HPolytope:
    """The set ``{x1 + x2 : x1 in P1, x2 in P2}`` (forces of two arms add).

    Parameters
    ----------
    P1, P2 : Polytope or HPolytope
        Bounded sets of the same task space.

    Returns
    -------
    HPolytope
        Empty if either is empty.  Its vertices, facets, edges and volume come from the
        sets' own (the module's description): no hull of the pairwise sums of vertices.
        Where one set is far smaller than the other, its contribution is resolved down to
        about 1e-9 of the larger set's size (the vertex and facet tolerances, relative to
        the sum): a set 1e9 times smaller or less is then lost, and the sum's volume
        is the larger set's, off by a few times the ratio of their sizes (measured in 3-D,
        a unit-size set plus a cube of half-width e: relative error 4e-9 at e = 1e-9,
        4.5e-10 at e = 1e-10; the increment right to 1e-4 at e = 1e-8).

    Raises
    ------
    InputError
        For sets of different task spaces, or an unbounded or lower-dimensional sum (give
        nonsingular postures).
    """
    P1, P2 = _check_pair(P1, P2)
    for name, P in (("P1", P1), ("P2", P2)):
        if isinstance(P, HPolytope) and not P.is_empty and not P.is_bounded:
            raise InputError(
                name,
                "a bounded set",
                f"a set unbounded along {len(P.rays)} ray(s)",
                "the sum is then unbounded too: add the force polytopes of nonsingular postures.",
            )
    if any(isinstance(P, HPolytope) and P.is_empty for P in (P1, P2)):
        return HPolytope(*_halfspaces(P1 if isinstance(P1, HPolytope) and P1.is_empty else P2))
    m = P1.ambient_dim
    spans = np.hstack([P1.affine_set.basis, P2.affine_set.basis])  # (m, r1 + r2)
    sigma = np.linalg.svd(spans, compute_uv=False)
    rank = int(np.count_nonzero(sigma > RANK_RTOL * sigma[0])) if len(sigma) else 0
    if rank < m:
        raise InputError(
            "P1",
            f"sets whose sum spans the {m}-dimensional task space",
            f"a sum of dimension {rank}",
            "add full-dimensional sets (nonsingular postures).",
        )
    if isinstance(P1, Polytope) and isinstance(P2, Polytope):
        # a zonotope: both sets of generators, about the sum of the centres
        Z = Polytope(np.hstack([P1.generators, P2.generators]), P1.center + P2.center)
        return HPolytope._with_vertices(Z.A, Z.b, Z.vertices, None, Z.center, Z.volume)
    try:
        points, edges, normals = _sum_graph(P1, P2)
    except _Ambiguous:  # a tangent cone too close to call: the hull of all pairwise sums
        sums = (P1.vertices[:, None, :] + P2.vertices[None, :, :]).reshape(-1, m)
        total = HPolytope.from_vertices(sums)  # (its vertices and volume: not enumerated again)
        return HPolytope._with_vertices(
            total.A, total.b, total.vertices, None, P1.center + P2.center, total.volume
        )
    offsets = (normals @ P1.vertices.T).max(axis=1) + (normals @ P2.vertices.T).max(axis=1)
    volume = _sum_volume(P1.vertices, P2.vertices, normals, offsets, points)
    center = P1.center + P2.center
    return HPolytope._with_vertices(normals, offsets, points, edges, center, volume)


def _sum_volume(
    V1: NDArray[np.float64],
    V2: NDArray[np.float64],
    normals: NDArray[np.float64],
    offsets: NDArray[np.float64],
    points: NDArray[np.float64],
) -> float | None:
    """The volume of ``P1 + P2`` from its facets (F, m), each the sum of a face of each set.

    ``sum_F h_F vol(F) / m`` about the vertices' mean.  A facet ``F1 + F2`` whose faces'
    dimensions add up to m - 1 is affinely their product: ``vol(F1) vol(F2)`` times the
    sine of the angle between their spans (``sqrt(det(B^T B))`` of their orthonormal bases
    side by side), each face's volume by Qhull in its own span (few vertices, low
    dimension); other facets by Qhull on the sum's vertices in the facet's plane.  None
    where Qhull fails (the set's own volume then).
    """
    from scipy.spatial import ConvexHull, QhullError

    m = V1.shape[1]
    scale = float(np.abs(V1).max() + np.abs(V2).max())
    tol = 1e-9 * scale
    # each set's faces to its own size (about its vertices' mean): a set 1e10 times
    # smaller than the other is no single point to the sum's tolerance
    own = [1e-9 * float(np.abs(V - V.mean(axis=0)).max()) for V in (V1, V2)]
    faces: dict[tuple[int, bytes], tuple[float, NDArray[np.float64]]] = {}

    def face(which: int, a: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
        V = (V1, V2)[which]
        values = V @ a
        on = values >= values.max() - own[which]
        key = (which, np.packbits(on).tobytes())
        if key not in faces:
            faces[key] = _span_volume(V[on], own[which])
        return faces[key]

    centre = points.mean(axis=0)
    heights = offsets - normals @ centre
    total = 0.0
    try:
        for a, height in zip(normals, heights, strict=True):
            (volume1, basis1), (volume2, basis2) = face(0, a), face(1, a)
            if basis1.shape[1] + basis2.shape[1] == m - 1:
                both = np.hstack([basis1, basis2])
                sine = float(np.sqrt(max(0.0, np.linalg.det(both.T @ both))))
                area = volume1 * volume2 * sine
            else:  # not a product (parallel faces): the hull of its vertices in its plane
                on = np.abs(points @ a - (points @ a).max()) <= tol
                plane = np.linalg.svd(a[None, :], full_matrices=True)[2][1:].T
                area = float(ConvexHull((points[on] - points[on].mean(axis=0)) @ plane).volume)
            total += float(height) * area / m
    except (QhullError, ValueError):
        return None
    return total


def _span_volume(points: NDArray[np.float64], tol: float) -> tuple[float, NDArray[np.float64]]:
    """The volume of the hull of points (n, m) in their affine span, and its orthonormal basis."""
    from scipy.spatial import ConvexHull

    local = points - points.mean(axis=0)
    _, sigma, vt = np.linalg.svd(local, full_matrices=False)
    k = int(np.count_nonzero(sigma > tol))
    basis = vt[:k].T  # (m, k)
    if k == 0:
        return 1.0, basis
    coordinates = local @ basis
    if k == 1:
        return float(coordinates.max() - coordinates.min()), basis
    return float(ConvexHull(coordinates).volume), basis


def _edges(P: Set) -> NDArray[np.int_]:
    """The edges of a bounded set, pairs of indices into its vertices (E, 2)."""
    if isinstance(P, HPolytope):
        return P._vertex_edges()
    return vertex_edges(P.vertices, P.A, P.b, P.affine_set.basis)


def _neighbours(count: int, edges: NDArray[np.int_]) -> list[NDArray[np.int_]]:
    """Each vertex's neighbours in the edge list (E, 2)."""
    ends = np.concatenate([edges, edges[:, ::-1]])
    ends = ends[np.argsort(ends[:, 0], kind="stable")]
    return np.split(ends[:, 1], np.searchsorted(ends[:, 0], np.arange(1, count)))


def _directions(V: NDArray[np.float64], i: int, near: NDArray[np.int_]) -> NDArray[np.float64]:
    """Unit directions from vertex i to its neighbours, (len(near), m)."""
    D = V[near] - V[i]
    return D / np.sqrt((D * D).sum(axis=1))[:, None]


def _start(V1: NDArray[np.float64], V2: NDArray[np.float64]) -> tuple[int, int]:
    """The vertices of each set maximising one direction (a vertex of the sum)."""
    rng = np.random.default_rng(20040)  # fixed: the same sum every time
    scale = float(np.abs(V1).max() + np.abs(V2).max())
    for _ in range(16):
        c = rng.standard_normal(V1.shape[1])
        tops = []
        for V in (V1, V2):
            values = V @ c
            order = np.argsort(values)
            if len(V) > 1 and values[order[-1]] - values[order[-2]] <= 1e-9 * scale:
                break  # a tie: another direction
            tops.append(int(order[-1]))
        else:
            return tops[0], tops[1]
    raise _Ambiguous


def _tangent(
    V1: NDArray[np.float64],
    V2: NDArray[np.float64],
    near1: list[NDArray[np.int_]],
    near2: list[NDArray[np.int_]],
    i: int,
    j: int,
) -> tuple[NDArray[np.float64], list[tuple[int, int]]]:
    """The edge directions of both sets at ``(v1, v2)`` (unit, (t, m)) and where each leads.

    A direction of ``P1`` and a parallel one of ``P2`` are one direction along which both
    move (to ``(w1, w2)``).
    """
    D1, D2 = _directions(V1, i, near1[i]), _directions(V2, j, near2[j])
    moves = [(int(a), j) for a in near1[i]] + [(i, int(b)) for b in near2[j]]
    if not (len(D1) and len(D2)):
        return np.vstack([D1, D2]), moves
    same = np.argwhere(D2 @ D1.T >= 1 - 1e-12)  # (index in D2, index in D1)
    for b, a in same:
        moves[a] = (int(near1[i][a]), int(near2[j][b]))
    keep = np.ones(len(moves), dtype=bool)
    keep[len(D1) + same[:, 0]] = False
    return np.vstack([D1, D2])[keep], [move for move, k in zip(moves, keep, strict=True) if k]


def _edges_by_rank(facets: NDArray[np.float64], D: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which directions (t, m) are edges: the facets (p, m) through them have rank m - 1."""
    m = D.shape[1]
    through = np.abs(facets @ D.T) <= WALK_ON_PLANE  # (p, t)
    sigma = np.linalg.svd(facets[None, :, :] * through.T[:, :, None], compute_uv=False)
    return np.asarray(np.count_nonzero(sigma > WALK_ON_PLANE, axis=1) == m - 1)


def _sum_graph(
    P1: Set, P2: Set
) -> tuple[NDArray[np.float64], NDArray[np.int_], NDArray[np.float64]]:
    """The vertices (V, m), edges (E, 2) and unit facet normals (F, m) of ``P1 + P2``.

    Breadth first over the sum's vertices ``(v1, v2)``: the edge directions ``D`` of both
    sets there span the sum's tangent cone (:func:`_tangent`); its normal cone
    ``{c : D c <= 0}`` has the sum's facet normals at the vertex as its extreme rays
    (:func:`~polyell.geometry.hpolytope._cone_rays`, certified complete), and a direction
    is an edge of the sum when the facets through it have rank m - 1 (in a simple normal
    cone, each ray on m - 1 directions: when a facet passes through it).
    """
    V1, V2 = P1.vertices, P2.vertices
    m = V1.shape[1]
    near1, near2 = _neighbours(len(V1), _edges(P1)), _neighbours(len(V2), _edges(P2))
    start = _start(V1, V2)
    index = {start: 0}
    pairs, normals = [start], []
    edges: set[tuple[int, int]] = set()
    frontier = [start]
    while frontier:
        following = []
        for pair in frontier:
            D, moves = _tangent(V1, V2, near1, near2, *pair)
            facets = _cone_rays(D)  # (p, m): the sum's facet normals at the vertex
            normals.append(facets)
            through = np.abs(facets @ D.T) <= WALK_ON_PLANE  # (p, t)
            if bool((through.sum(axis=1) == m - 1).all()):  # simple: rows through a ray
                edge = through.any(axis=0)
            else:
                edge = _edges_by_rank(facets, D)
            here = index[pair]
            for move in (mv for mv, e in zip(moves, edge, strict=True) if e):
                there = index.get(move)
                if there is None:
                    there = index[move] = len(pairs)
                    pairs.append(move)
                    following.append(move)
                edges.add((min(here, there), max(here, there)))
        frontier = following
    chosen = np.array(pairs, dtype=int)
    points = V1[chosen[:, 0]] + V2[chosen[:, 1]]
    pairs_of_ends = np.array(sorted(edges), dtype=int).reshape(-1, 2)
    return points, pairs_of_ends, _unique_directions(np.vstack(normals))


def intersection(P1: Set, P2: Set) -> HPolytope:
    """The set of points in both (forces that each of two arms can exert).

    Parameters
    ----------
    P1, P2 : Polytope or HPolytope
        Sets of the same task space (unbounded ones too).

    Returns
    -------
    HPolytope
        Possibly empty (``is_empty``) or lower-dimensional.
    """
    P1, P2 = _check_pair(P1, P2)
    A1, b1 = _halfspaces(P1)
    A2, b2 = _halfspaces(P2)
    # A bounded set inside the other is the intersection: its own description, not one
    # with the other's rows, which may be far larger (units of two arms) and redundant.
    # Inside means inside to the rounding of the other's rows, not to its tolerances
    # (relative to its size): a set 1e9 times smaller at its boundary is not inside it.
    for inner, (A, b) in ((P1, (A2, b2)), (P2, (A1, b1))):
        if _bounded(inner) and _inside_rows(A, b, inner.vertices):
            return HPolytope(*_halfspaces(inner))
    return HPolytope(np.vstack([A1, A2]), np.concatenate([b1, b2]))


def _inside_rows(A: np.ndarray, b: np.ndarray, points: np.ndarray) -> bool:
    """Whether every point satisfies ``A x <= b`` to the rounding of evaluating the rows."""
    floor = (
        8
        * (A.shape[1] + 2)
        * np.finfo(float).eps
        * (np.abs(A) @ np.abs(points.T) + np.abs(b)[:, None])
    )
    return bool(np.all(A @ points.T - b[:, None] <= floor))


def _bounded(P: Set) -> bool:
    """Whether P is a non-empty bounded set (its vertices are all of it)."""
    if isinstance(P, HPolytope):
        return not P.is_empty and P.is_bounded
    return True


@overload
def in_frame(
    P: Polytope,
    rotation: ArrayLike,
    translation: ArrayLike | None = None,
    *,
    task: Sequence[str] | None = None,
) -> Polytope: ...


@overload
def in_frame(
    P: HPolytope,
    rotation: ArrayLike,
    translation: ArrayLike | None = None,
    *,
    task: Sequence[str] | None = None,
) -> HPolytope: ...


def in_frame(
    P: Set,
    rotation: ArrayLike,
    translation: ArrayLike | None = None,
    *,
    task: Sequence[str] | None = None,
) -> Set:
    r"""A force or wrench set given in an arm's base frame, expressed in a common frame.

    Two arms whose bases differ compute their sets in their own base frames; before they
    are added (:func:`minkowski_sum`) or intersected, each is expressed in one frame:
    ``in_frame(P1, R1)``, ``in_frame(P2, R2)``.  A force is a vector, ``f = R f_base``;
    a wrench ``(f, mu)`` taken about a point at ``p`` (in the common frame) is, about the
    common frame's origin, ``(R f_base, R mu_base + p x R f_base)`` (the wrench adjoint).

    Parameters
    ----------
    P : Polytope or HPolytope
        The set in the base frame [N; N m for moment rows].  Its rows are named by
        ``task`` (default ``P.task``, else ``x, y, z`` up to three rows and
        ``x, y, z, wx, wy, wz`` for six): forces ``x``, ``y``, ``z``, moments ``wx``,
        ``wy``, ``wz``, in any order and any subset that the pose maps onto itself (a
        planar wrench ``x, y, wz`` with a rotation about z; not ``x, y, z`` with a
        translation, whose moments have no rows).
    rotation : array-like, shape (k, k)
        The base frame's orientation in the common frame (its columns are the base axes
        in common coordinates), acting on the axes of the force rows (k of them; of the
        moment rows for a set of moments only).  Orthonormal with determinant +1 to
        :data:`ROTATION_ATOL`; the nearest rotation is used.
    translation : array-like, shape (k,), optional
        Where the point the set's moments are taken about lies in the common frame,
        relative to the point the common frame's moments are taken about [m], on the same
        axes as ``rotation``.  Only for a set with moment rows (forces are free vectors:
        moving the point they act at changes no force).  Default: the same point (the
        moments only rotate).  This is the wrench adjoint: a set of twists (velocities)
        transforms the other way round and is not handled here.
    task : sequence of str, optional
        The names of P's rows, if ``P.task`` is not set or differs.

    Returns
    -------
    Polytope or HPolytope
        The same kind of set (a zonotope stays a zonotope, with generators ``T G``; an
        H-polytope keeps its vertices, edges and volume, mapped: ``|det T| = 1``), with
        ``P``'s row names.  ``T`` is the (m, m) map of the pose on P's rows.

    Raises
    ------
    InputError
        Naming ``P`` (another type), ``task`` (rows other than forces and moments),
        ``rotation`` (a shape other than (k, k), not orthonormal, a reflection) or
        ``translation`` (a shape other than (k,), given for a set without moment rows, or
        moving a force into a moment row the set does not have).

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> from polyell.geometry.combine import in_frame
    >>> box = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [2, 2, 1, 1])
    >>> quarter = np.array([[0.0, -1.0], [1.0, 0.0]])  # base turned 90 degrees about z
    >>> turned = in_frame(box, quarter)
    >>> [float(x) for x in turned.limits(["x", "y"]).hi.round(12)]
    [1.0, 2.0]
    """
    if not isinstance(P, Polytope | HPolytope):
        raise InputError(
            "P",
            "a pe.Polytope or a pe.HPolytope",
            type(P).__name__,
            "pass a set the library builds, e.g. pe.analyze(...).polytope or pe.HPolytope(A, b).",
        )
    rows = _pose_rows(P, task)
    T, T_inverse = _pose_maps(rows, rotation, translation)
    center = T @ P.center
    if isinstance(P, Polytope):
        Z = Polytope(T @ P.generators, center)
        return _labelled(Z, P, task)
    A, b = _halfspaces(P)
    if P.is_empty or not P.is_bounded or P.dim < P.ambient_dim:
        return _labelled(HPolytope(A @ T_inverse, b, center=center), P, task)
    volume = P.__dict__.get("volume")  # computed already: the same in the common frame
    edges = getattr(P, "_edges", None)
    moved = HPolytope._with_vertices(P.A @ T_inverse, P.b, P.vertices @ T.T, edges, center, volume)
    return _labelled(moved, P, task)


def _labelled(S: ConvexSet, P: ConvexSet, task: Sequence[str] | None) -> Set:
    """``S`` with the row names and rounding tolerance of ``P`` (or ``task``)."""
    S.task = task if task is not None else P.task
    S.affine_rtol = P.affine_rtol
    assert isinstance(S, Polytope | HPolytope)
    return S


def _pose_rows(P: Set, task: Sequence[str] | None) -> tuple[int, ...]:
    """Each of P's rows as an axis of the frame: 0..2 forces x, y, z, 3..5 moments."""
    from polyell.models.task import check_task, default_task  # (models import geometry)

    m = P.ambient_dim
    if task is not None:
        rows = check_task(task, m)
    else:
        rows = P.task if P.task is not None else default_task(m)
    known = (*_FORCE_ROWS, *_MOMENT_ROWS)
    if not all(row in known for row in rows):
        raise InputError(
            "task" if task is not None else "P",
            "a set whose rows are forces x, y, z and moments wx, wy, wz (P.task, or task=)",
            f"rows {tuple(rows)}",
            "name the rows, e.g. task=('x', 'y', 'wz') for a planar wrench; a set of "
            "other quantities has no force frame to change.",
        )
    return tuple(known.index(row) for row in rows)


def _rotation(rotation: ArrayLike, k: int, axes: str) -> NDArray[np.float64]:
    """A (k, k) rotation (det +1, to :data:`ROTATION_ATOL`), as its polar factor."""
    R = check_array("rotation", rotation, (k, k))
    fix = (
        "give an exact rotation matrix, e.g. from angles: "
        "scipy.spatial.transform.Rotation.from_euler('z', 30, degrees=True).as_matrix(), "
        f"or [[cos a, -sin a], [sin a, cos a]] in a plane (acting on {axes})."
    )
    defect = float(np.abs(R.T @ R - np.eye(k)).max(initial=0.0))
    if not defect <= ROTATION_ATOL:
        raise InputError(
            "rotation",
            f"a rotation of the axes {axes}: orthonormal columns (R^T R = I to {ROTATION_ATOL:g})",
            f"max |R^T R - I| = {defect:.3g}",
            fix,
        )
    U, _, Vt = np.linalg.svd(R)
    polar = U @ Vt  # the nearest orthogonal matrix
    if np.linalg.det(polar) < 0:
        raise InputError(
            "rotation",
            f"a rotation of the axes {axes} (determinant +1)",
            "a reflection (det -1)",
            fix,
        )
    result: NDArray[np.float64] = polar
    return result


def _pose_maps(
    rows: tuple[int, ...], rotation: ArrayLike, translation: ArrayLike | None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (m, m) map of the pose on the rows, and its inverse (the pose undone)."""
    forces = [axis for axis in range(3) if axis in rows]
    moments = [axis - 3 for axis in rows if axis >= 3]
    axes = forces if forces else sorted(moments)  # the axes the rotation acts on
    names = _FORCE_ROWS if forces else _MOMENT_ROWS
    axes_text = ", ".join(names[a] for a in axes)
    R = _rotation(rotation, len(axes), axes_text)
    R3 = np.eye(3)
    R3[np.ix_(axes, axes)] = R
    p3 = np.zeros(3)
    if translation is not None:
        if not moments:
            raise InputError(
                "translation",
                "None for a set without moment rows (forces are free vectors: the point "
                "they act at changes no force)",
                "a translation",
                "drop translation, or give a wrench set (rows x, y, z, wx, wy, wz; "
                "x, y, wz in a plane).",
            )
        p3[axes] = check_array("translation", translation, (len(axes),))

    def adjoint(R3: NDArray[np.float64], p3: NDArray[np.float64]) -> NDArray[np.float64]:
        cross = np.array([[0.0, -p3[2], p3[1]], [p3[2], 0.0, -p3[0]], [-p3[1], p3[0], 0.0]])
        return np.block([[R3, np.zeros((3, 3))], [cross @ R3, R3]])

    forward, backward = adjoint(R3, p3), adjoint(R3.T, -R3.T @ p3)
    index = list(rows)
    absent = [axis for axis in range(6) if axis not in rows]
    named = tuple((*_FORCE_ROWS, *_MOMENT_ROWS)[a] for a in rows)
    for argument, matrix in (("rotation", adjoint(R3, np.zeros(3))), ("translation", forward)):
        if np.abs(matrix[np.ix_(absent, index)]).max(initial=0.0) > 0:
            raise InputError(
                argument,
                f"a pose that maps the set's rows {named} onto themselves",
                f"a {argument} that moves part of a row into an axis the set has no row for",
                "a set in a plane (x, y; x, y, wz) turns about its normal, with a translation "
                "in the plane; give all six rows (x, y, z, wx, wy, wz) for other poses.",
            )
    return forward[np.ix_(index, index)], backward[np.ix_(index, index)]
