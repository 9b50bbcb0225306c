"""Mesh export (issue 14): OBJ and PLY files of the polytope and the ellipsoids, read back
and checked against the sets (boundaries, closed and outward meshes, exact volumes)."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

import polyell as pe
from polyell.export import comparison_meshes, export_comparison, mesh
from reference import PAPER_ARM, PAPER_Q_SINGULAR, PAPER_TAU_MAX, paper_analysis, random_problem


def read_obj(path):
    """Objects of an OBJ file: name -> (vertices, faces, lines), indices 0-based per object."""
    objects, vertices, current = {}, [], None
    for line in path.read_text().splitlines():
        kind, *rest = line.split() or [""]
        if kind == "o":
            current = rest[0]
            objects[current] = ([], [], [])
        elif kind == "v":
            vertices.append([float(v) for v in rest])
            objects[current][0].append(len(vertices) - 1)
        elif kind in ("f", "l"):
            objects[current][1 if kind == "f" else 2].append([int(v) - 1 for v in rest])
    result = {}
    for name, (indices, faces, lines) in objects.items():
        first = indices[0]
        result[name] = (
            np.array([vertices[i] for i in indices]),
            np.array(faces, dtype=int).reshape(-1, 3) - first,
            np.array(lines, dtype=int).reshape(-1, 2) - first,
        )
    return result


def signed_volume(vertices, faces):
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0


def assert_closed(faces):
    edges = Counter(
        tuple(sorted(e)) for f in faces for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))
    )
    assert set(edges.values()) == {2}  # every edge shared by exactly two triangles


@pytest.mark.parametrize("seed", range(3))
def test_3d_meshes_are_closed_outward_and_on_the_boundaries(seed, tmp_path):
    analysis = random_problem(seed, 3, 6)
    cmp = pe.compare(analysis, 16)
    path = export_comparison(cmp, tmp_path / "sets.obj")[0]
    objects = read_obj(path)
    assert list(objects) == ["polytope", *cmp.kinds[:4]]
    assert "units: m/s^2" in path.read_text() and "task frame (x, y, z)" in path.read_text()
    P = analysis.polytope
    vertices, faces, _ = objects["polytope"]
    assert_closed(faces)
    assert signed_volume(vertices, faces) == pytest.approx(P.volume, rel=1e-9)  # exact, outward
    for kind in cmp.kinds[:4]:
        E = cmp.ellipsoid(kind)
        vertices, faces, _ = objects[kind]
        assert_closed(faces)
        norms = np.linalg.norm(((vertices - E.center) @ E.axes) / E.semi_axes, axis=1)
        np.testing.assert_allclose(norms, 1.0, rtol=1e-9)
        assert 0.97 * E.volume < signed_volume(vertices, faces) < E.volume  # inscribed mesh


def test_2d_sets_lie_in_the_plane_z_0_and_ply_files_read_back(tmp_path):
    cmp = pe.compare(paper_analysis(np.array([np.pi / 2, -np.pi / 2, -np.pi / 2])), 16)
    paths = export_comparison(cmp, tmp_path / "sets.ply")
    assert [p.name for p in paths] == [f"sets_{k}.ply" for k in ("polytope", *cmp.kinds)]
    text = paths[0].read_text().splitlines()
    count = int(next(line for line in text if line.startswith("element vertex")).split()[-1])
    start = text.index("end_header") + 1
    vertices = np.array([[float(v) for v in line.split()] for line in text[start : start + count]])
    assert np.all(vertices[:, 2] == 0.0)
    np.testing.assert_allclose(
        np.sort(vertices[:, :2], axis=0), np.sort(cmp.analysis.polytope.vertices, axis=0)
    )
    faces = np.array([[int(v) for v in line.split()[1:]] for line in text[start + count :]])
    u = vertices[faces[:, 1]] - vertices[faces[:, 0]]
    v = vertices[faces[:, 2]] - vertices[faces[:, 0]]
    area = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum() / 2
    assert area == pytest.approx(cmp.analysis.polytope.volume, rel=1e-12)


def test_singular_sets_are_segments(tmp_path):
    analysis = pe.analyze(PAPER_ARM.dynamics([np.pi / 6, 0.0, 0.0]), tau_max=PAPER_TAU_MAX)
    meshes = comparison_meshes(pe.compare(analysis, 16))
    assert "yoshikawa" not in meshes  # undefined there
    for item in meshes.values():
        assert len(item.vertices) == 2 and len(item.faces) == 0 and item.lines.tolist() == [[0, 1]]
    objects = read_obj(export_comparison(pe.compare(analysis, 16), tmp_path / "s.obj")[0])
    assert objects["polytope"][2].tolist() == [[0, 1]]


def test_bad_paths_and_dimensions_are_refused(tmp_path):
    cmp = pe.compare(paper_analysis(np.array([0.3, 0.9, -0.7])), 16)
    with pytest.raises(pe.InputError, match=r"\.obj or \.ply"):
        export_comparison(cmp, tmp_path / "sets.stl")
    with pytest.raises(pe.InputError, match="2-D or 3-D"):
        mesh(random_problem(0, 6, 8).polytope)


def test_command_line_writes_the_meshes(tmp_path, capsys):
    from polyell.cli import main

    assert main(["analyze", "--mesh", str(tmp_path / "sets.obj")]) == 0
    assert "wrote" in capsys.readouterr().err
    objects = read_obj(tmp_path / "sets.obj")
    assert list(objects) == ["polytope", "chiacchio", "yoshikawa", "mvie", "outer"]


@pytest.mark.parametrize(("seed", "n"), [(0, 3), (1, 4), (2, 5), (3, 7)])
def test_polytope_edges_are_the_zonotopes_edges(seed, n):
    """Independent checks: Euler's formula with the facets of P.A, and every edge of a
    zonotope is a parallel copy of one generator, each generator giving 2 (n - 1) edges."""
    from polyell.export import polytope_edges

    analysis = random_problem(seed, 3, n)
    P, M = analysis.polytope, analysis.M
    edges = polytope_edges(P)
    assert len(P.vertices) - len(edges) + len(P.A) == 2
    vectors = P.vertices[edges[:, 1]] - P.vertices[edges[:, 0]]
    generator = []
    for v in vectors:  # 2 M_i up to sign: the edge joins vertices differing in one sign
        matches = [
            i for i in range(n) if np.allclose(np.abs(v), np.abs(2 * M[:, i]), rtol=1e-9, atol=0)
        ]
        assert len(matches) == 1
        generator.append(matches[0])
    assert np.bincount(generator, minlength=n).tolist() == [2 * (n - 1)] * n


def test_polytope_edges_of_flat_sets():
    from polyell.export import polytope_edges

    flat = random_problem(1, 3, 5, rank=2).polytope  # a polygon in a plane
    sides = polytope_edges(flat)
    assert len(sides) == len(flat.vertices)
    assert np.all(np.bincount(sides.ravel()) == 2)  # a closed loop through every vertex
    segment = paper_analysis(PAPER_Q_SINGULAR).polytope
    assert polytope_edges(segment).tolist() == [[0, 1]]
