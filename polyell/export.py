"""Meshes of the polytope and the ellipsoids (OBJ, PLY) for Blender, RViz or meshcat.

Coordinates are in the task frame and the capacity's units (m/s^2, m/s, N, N m, rad/s^2
... or weighted units; the capacity and its unit are written in each file's header).  A 3-D
set of full rank is a closed triangle mesh with outward normals (counter-clockwise faces); a
flat one (a polygon or an ellipse in a plane, or any set of a 2-D task, drawn in the plane
z = 0) is a fan of triangles; a segment (a singular configuration) is a line element; a
point, a single vertex.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import check_capacity
from polyell.comparison.comparison import Comparison
from polyell.comparison.tables import check_text
from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope, require_drawable
from polyell.geometry.polytope import Polytope
from polyell.storage import as_path, write_text_atomically
from polyell.validation import as_floats, check_integer

__all__ = [
    "MAX_RESOLUTION",
    "Mesh",
    "check_resolution",
    "comparison_meshes",
    "export_comparison",
    "mesh",
    "polytope_edges",
    "write_obj",
    "write_ply",
]

#: Rings of latitude of an ellipsoid's mesh (twice as many meridians).
RESOLUTION = 24
#: Largest resolution: 2 k^2 vertices and 4 k^2 triangles for k rings, so 512 gives about
#: 0.5 M vertices and 1 M triangles (some 100 MB of memory while it is written and a
#: 60 MB OBJ file), far finer than any viewer needs.  The smallest, 2, is an octahedron.
MAX_RESOLUTION = 512


def check_resolution(resolution: object) -> int:
    """Check a mesh resolution: an integer from 2 to :data:`MAX_RESOLUTION`."""
    try:
        return check_integer("resolution", resolution, 2, MAX_RESOLUTION)
    except InputError as exn:
        raise InputError(
            exn.argument,
            exn.expected + " (rings of latitude of an ellipsoid's mesh)",
            exn.got,
            f"use the default {RESOLUTION}, or an integer in [2, {MAX_RESOLUTION}].",
        ) from None


class Mesh(NamedTuple):
    """A set as a mesh in 3-D task coordinates.

    Attributes
    ----------
    vertices : ndarray, shape (V, 3)
    faces : ndarray of int, shape (F, 3)
        Triangles (counter-clockwise seen from outside for a closed mesh).
    lines : ndarray of int, shape (L, 2)
        Line elements (a segment).
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int_]
    lines: NDArray[np.int_]


def _lift(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Points of a 2-D task drawn in the plane z = 0."""
    return points if points.shape[1] == 3 else np.column_stack([points, np.zeros(len(points))])


def _fan(count: int, first: int = 0) -> NDArray[np.int_]:
    """Triangles of a convex polygon whose vertices are ``first .. first + count - 1`` in order."""
    return np.array([(first, first + i, first + i + 1) for i in range(1, count - 1)], dtype=int)


def _orient(vertices: NDArray[np.float64], faces: NDArray[np.int_]) -> NDArray[np.int_]:
    """Turn each triangle of a closed convex mesh to face away from its centroid."""
    scale = float(np.max(np.abs(vertices))) or 1.0  # no overflow at 1e300 (signs only)
    unit = vertices / scale
    centre = unit.mean(axis=0)
    a, b, c = (unit[faces[:, i]] for i in range(3))
    outward = np.einsum("ij,ij->i", np.cross(b - a, c - a), a - centre) > 0
    return np.where(outward[:, None], faces, faces[:, ::-1])


def _ellipsoid_surface(E: Ellipsoid, k: int) -> tuple[NDArray[np.float64], NDArray[np.int_]]:
    """A triangulated surface of a full-rank 3-D ellipsoid: vertices (V, 3), faces (F, 3)."""
    theta = np.linspace(0.0, np.pi, k + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, 2 * k, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    unit = np.column_stack(
        [(np.sin(t) * np.cos(p)).ravel(), (np.sin(t) * np.sin(p)).ravel(), np.cos(t).ravel()]
    )
    unit = np.vstack([[0.0, 0.0, 1.0], unit, [0.0, 0.0, -1.0]])
    rings, around = len(theta), len(phi)
    faces = []
    index = lambda i, j: 1 + i * around + (j % around)  # noqa: E731 - a two-index helper
    for j in range(around):
        faces.append((0, index(0, j), index(0, j + 1)))
        faces.append((len(unit) - 1, index(rings - 1, j + 1), index(rings - 1, j)))
        for i in range(rings - 1):
            faces.append((index(i, j), index(i + 1, j), index(i + 1, j + 1)))
            faces.append((index(i, j), index(i + 1, j + 1), index(i, j + 1)))
    vertices = E.center + (unit * E.semi_axes) @ E.axes.T
    return vertices, np.array(faces)


def mesh(S: Polytope | HPolytope | Ellipsoid, resolution: int = RESOLUTION) -> Mesh:
    """The mesh of a polytope or an ellipsoid of a 2-D or 3-D task space.

    Parameters
    ----------
    S : Polytope, HPolytope or Ellipsoid
    resolution : int, optional
        Rings of latitude of an ellipsoid (its boundary curve has ``8 * resolution``
        points when it is flat); a polytope is exact.

    Raises
    ------
    InputError
        For a set that is neither, a task space of another dimension, or a resolution
        outside ``[2, MAX_RESOLUTION]``.
    """
    if not isinstance(S, Polytope | HPolytope | Ellipsoid):
        raise InputError(
            "set",
            "a pe.Polytope or a pe.Ellipsoid",
            type(S).__name__,
            "pass a set of an analysis, e.g. analysis.polytope or "
            "comparison.ellipsoid('chiacchio')",
        )
    require_drawable(S, "set")
    resolution = check_resolution(resolution)
    m = S.ambient_dim
    if m not in (2, 3):
        raise InputError(
            "set",
            "a set of a 2-D or 3-D task space",
            f"m = {m}",
            "analyze a task of 2 or 3 rows (task='planar' or 'linear'), or read the scores "
            "(comparison.to_markdown())",
        )
    no_lines = np.zeros((0, 2), dtype=int)
    if isinstance(S, Ellipsoid):
        rank = S.rank
        if rank == 3:
            vertices, faces = _ellipsoid_surface(S, resolution)
        elif rank == 2:
            vertices = S.boundary_curve(8 * resolution)
        elif rank == 1:
            vertices = S.boundary_curve(2)
        else:
            vertices = S.center[None, :]
    else:
        rank, vertices = S.dim, S.vertices
        if rank == 3:
            from scipy.spatial import ConvexHull

            faces = ConvexHull(vertices).simplices
        elif rank == 2:  # a polygon: its vertices in order around it
            vertices = vertices[_around(S)]
    if rank == 3:
        return Mesh(vertices, _orient(vertices, faces), no_lines)
    if rank == 2:
        return Mesh(_lift(vertices), _fan(len(vertices)), no_lines)
    lines = np.array([[0, 1]]) if len(vertices) == 2 else no_lines
    return Mesh(_lift(np.asarray(vertices)), np.zeros((0, 3), dtype=int), lines)


def _around(P: Polytope | HPolytope) -> NDArray[np.int_]:
    """The order of a flat (2-D) polytope's vertices around it."""
    basis = P.affine_set.basis if P.ambient_dim == 3 else np.eye(2)
    local = (P.vertices - P.vertices.mean(axis=0)) @ basis
    return np.argsort(np.arctan2(local[:, 1], local[:, 0]))


def polytope_edges(P: Polytope | HPolytope) -> NDArray[np.int_]:
    """The edges of a polytope of a 2-D or 3-D task space, as pairs of vertex indices.

    The triangles of a mesh cut each face of a 3-D polytope into pieces; an edge here is
    an edge of the polytope itself (between two faces of different planes), what a
    drawing of its outline needs.

    Parameters
    ----------
    P : Polytope or HPolytope (bounded)

    Returns
    -------
    ndarray of int, shape (E, 2)
        Indices into ``P.vertices``, each edge once (``i < j``): the hull's edges (3-D),
        the polygon's sides (a flat polytope), one segment, or none (a point).
    """
    if not isinstance(P, Polytope | HPolytope):
        raise InputError(
            "P", "a pe.Polytope", type(P).__name__, "pass a polytope, e.g. analysis.polytope"
        )
    require_drawable(P, "P")
    if P.ambient_dim not in (2, 3):
        raise InputError(
            "P",
            "a polytope of a 2-D or 3-D task space",
            f"m = {P.ambient_dim}",
            "analyze a task of 2 or 3 rows (task='planar' or 'linear')",
        )
    count = len(P.vertices)
    if P.dim == 3:
        from scipy.spatial import ConvexHull

        hull = ConvexHull(P.vertices)
        normals = hull.equations[:, :3]
        pairs = set()
        for face, simplex in enumerate(hull.simplices):
            for k, other in enumerate(hull.neighbors[face]):
                # a side shared with a triangle of another plane is an edge of P
                if normals[face] @ normals[other] < 1.0 - 1e-9:
                    i, j = sorted(int(v) for v in np.delete(simplex, k))
                    pairs.add((i, j))
        return np.array(sorted(pairs), dtype=int).reshape(-1, 2)
    if P.dim == 2:
        order = _around(P)
        sides = np.column_stack([order, np.roll(order, -1)])
        return np.sort(sides, axis=1)
    if P.dim == 1 and count == 2:
        return np.array([[0, 1]])
    return np.zeros((0, 2), dtype=int)


def comparison_meshes(comparison: Comparison, resolution: int = RESOLUTION) -> dict[str, Mesh]:
    """The polytope and every defined ellipsoid of a comparison, by name."""
    if not isinstance(comparison, Comparison):
        raise InputError(
            "comparison", "a pe.Comparison", type(comparison).__name__, "call pe.compare first."
        )
    resolution = check_resolution(resolution)
    meshes = {"polytope": mesh(comparison.analysis.polytope, resolution)}
    for kind in comparison.kinds:
        if comparison[kind].defined:
            meshes[kind] = mesh(comparison.ellipsoid(kind), resolution)
    return meshes


def _header(unit: str, task: tuple[str, ...] | None, capacity: str) -> list[str]:
    """Header lines (comments) of a mesh file; each text is checked to stay on its line."""
    from polyell import __version__

    capacity = check_capacity(capacity)
    unit = check_text("unit", unit)
    if task is not None and (isinstance(task, str) or not isinstance(task, tuple | list)):
        raise InputError(
            "task",
            "a tuple of task rows such as ('x', 'y')",
            repr(task),
            "pass the rows as a tuple, e.g. task=analysis.task or task=('x', 'y', 'z')",
        )
    frame = ", ".join(check_text("task", row) for row in task) if task else "x, y, z"
    return [
        f"polyell {__version__}: {capacity} sets in the task frame ({frame})",
        f"units: {unit} on every axis",
    ]


def _check_meshes(meshes: object) -> dict[str, Mesh]:
    """Check meshes by name: a name is one line of text without spaces at its ends."""
    if not isinstance(meshes, Mapping):
        raise InputError(
            "meshes",
            "a mapping of names to pe.export.Mesh",
            type(meshes).__name__,
            "pass a dict of meshes by name, e.g. pe.export.comparison_meshes(comparison)",
        )
    for name, item in meshes.items():
        if not isinstance(name, str) or not name.strip() or check_text("name", name) != name:
            raise InputError(
                "name", "a one-line name such as 'polytope'", repr(name), "remove line breaks."
            )
        if not isinstance(item, Mesh):
            raise InputError(
                f"meshes[{name!r}]",
                "a pe.export.Mesh",
                type(item).__name__,
                f"map each name to a mesh, e.g. {{{name!r}: pe.export.mesh(analysis.polytope)}}",
            )
        _check_mesh(f"meshes[{name!r}]", item)
    return dict(meshes)


def _check_mesh(name: str, item: Mesh) -> None:
    """Refuse a mesh whose arrays are not finite vertices (V, 3) and indices into them."""
    vertices = as_floats(f"{name}.vertices", item.vertices)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or not np.isfinite(vertices).all():
        raise InputError(
            f"{name}.vertices",
            "finite points of shape (V, 3)",
            f"shape {vertices.shape}" + ("" if np.isfinite(vertices).all() else " with NaN or inf"),
            "give finite x, y, z columns, e.g. np.column_stack([x, y, np.zeros_like(x)]) for a "
            "2-D set",
        )
    for field, width in (("faces", 3), ("lines", 2)):
        try:
            indices = np.asarray(getattr(item, field))
        except ValueError:  # a ragged list
            raise InputError(
                f"{name}.{field}",
                f"integer indices of shape (k, {width})",
                "a ragged list",
                f"give every row {width} vertex indices, "
                f"e.g. np.array([{list(range(width))}], dtype=int)",
            ) from None
        if indices.size == 0:
            continue
        integral = indices.dtype.kind in "iu"
        if not integral or indices.ndim != 2 or indices.shape[1] != width:
            raise InputError(
                f"{name}.{field}",
                f"integer indices of shape (k, {width})",
                f"{indices.dtype} of shape {indices.shape}",
                f"convert with np.asarray({name}.{field}, dtype=int).reshape(-1, {width})",
            )
        if indices.min() < 0 or indices.max() >= len(vertices):
            raise InputError(
                f"{name}.{field}",
                f"indices of its {len(vertices)} vertices (0 to {len(vertices) - 1})",
                f"indices from {indices.min()} to {indices.max()}",
                f"keep every index in [0, {len(vertices)}) (0-based, as in {name}.vertices), "
                "or add the vertices the others name",
            )


def write_obj(
    path: str | Path,
    meshes: Mapping[str, Mesh],
    *,
    unit: str = "m/s^2",
    task: tuple[str, ...] | None = None,
    capacity: str = "acceleration",
) -> Path:
    """Write meshes as one Wavefront OBJ file, one object (``o name``) per set.

    Parameters
    ----------
    path : str or Path
    meshes : mapping of str to Mesh
        E.g. :func:`comparison_meshes`.
    unit : str, optional
        The unit of the sets (``analysis.unit()``), written in the header.
    task : tuple of str, optional
        The task rows (the frame's axes), written in the header.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose sets they are, written in the header ("force sets in the task frame").

    Returns
    -------
    Path
        The file, written atomically.
    """
    path = as_path("path", path)
    lines = [f"# {text}" for text in _header(unit, task, capacity)]
    offset = 1  # OBJ indices start at 1 and run over the whole file
    for name, item in _check_meshes(meshes).items():
        lines.append(f"o {name}")
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in item.vertices]
        lines += [f"f {a + offset} {b + offset} {c + offset}" for a, b, c in item.faces]
        lines += [f"l {a + offset} {b + offset}" for a, b in item.lines]
        if not len(item.faces) and not len(item.lines):
            lines += [f"p {offset + i}" for i in range(len(item.vertices))]
        offset += len(item.vertices)
    return write_text_atomically(Path(path), "\n".join(lines) + "\n")


def write_ply(
    path: str | Path,
    item: Mesh,
    *,
    name: str = "set",
    unit: str = "m/s^2",
    task: tuple[str, ...] | None = None,
    capacity: str = "acceleration",
) -> Path:
    """Write one mesh as an ASCII PLY file (vertices, faces and edges).

    ``name``, ``unit``, ``task`` and ``capacity`` are written in its header, as in
    :func:`write_obj`.
    """
    path = as_path("path", path)
    if not isinstance(name, str):
        raise InputError(
            "name",
            "a one-line name such as 'polytope'",
            repr(name)[:80],
            "pass the set's name as a str, e.g. name='polytope'",
        )
    if not isinstance(item, Mesh):
        raise InputError(
            "item",
            "a pe.export.Mesh",
            type(item).__name__,
            "pass a mesh, e.g. pe.export.mesh(analysis.polytope)",
        )
    (item,) = _check_meshes({name: item}).values()
    header = ["ply", "format ascii 1.0"]
    header += [f"comment {text}" for text in [f"set: {name}", *_header(unit, task, capacity)]]
    header += [f"element vertex {len(item.vertices)}", *(f"property double {a}" for a in "xyz")]
    header += [f"element face {len(item.faces)}", "property list uchar int vertex_indices"]
    if len(item.lines):
        header += [
            f"element edge {len(item.lines)}",
            "property int vertex1",
            "property int vertex2",
        ]
    body = [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in item.vertices]
    body += [f"3 {a} {b} {c}" for a, b, c in item.faces]
    body += [f"{a} {b}" for a, b in item.lines]
    return write_text_atomically(Path(path), "\n".join([*header, "end_header", *body]) + "\n")


def export_comparison(
    comparison: Comparison, path: str | Path, resolution: int = RESOLUTION
) -> list[Path]:
    """Every set of a comparison: one OBJ file (``.obj``) or one PLY file per set (``.ply``).

    A PLY path ``sets.ply`` gives ``sets_polytope.ply``, ``sets_chiacchio.ply``, ...  The
    header states the comparison's capacity and its unit (``analysis.unit()``: m/s^2, m/s,
    N, N m, ...).
    """
    if not isinstance(path, str | Path) or Path(path).suffix not in (".obj", ".ply"):
        raise InputError(
            "path",
            "a file name ending in .obj or .ply",
            repr(path),
            "pass a str or Path ending in .obj (one file) or .ply (a file per set), "
            "e.g. 'sets.obj'",
        )
    target = Path(path)
    meshes = comparison_meshes(comparison, resolution)
    analysis = comparison.analysis
    task, unit, capacity = analysis.task, analysis.unit(), analysis.capacity
    if target.suffix == ".obj":
        return [write_obj(target, meshes, unit=unit, task=task, capacity=capacity)]
    return [
        write_ply(
            target.with_name(f"{target.stem}_{name}.ply"),
            item,
            name=name,
            unit=unit,
            task=task,
            capacity=capacity,
        )
        for name, item in meshes.items()
    ]
