"""HPolytope in 4 to 6 dimensions, unbounded and rescaled: issue 33, against independent references.

Found by the attacker of issue 33: the half-space description of a well-conditioned 5-D
zonotope (its 140 facets), the intersection of two 5-D zonotopes and 72 random tangent
planes of the 6-D unit ball raised SolverError (the Qhull completeness check rejected
cddlib's complete answer; the last after two minutes), and a 6-D set with a line and rays
came out with four far "vertices" at 1e16 where cddlib had rounded rays to t = 1e-15.

References, none of them the package's: a zonotope's vertices are its corners ``c + G s``
that maximise a direction, its support ``c . d + sum |G^T d|`` and its volume
``2^r sum |det G_S|`` over r-subsets of generators; the vertices of small sets are every
r rows solved with numpy; the support function and the vertex solutions of HiGHS's dual
simplex (a basic solution: a vertex) in random directions for the large ones.
Tolerances: relative 1e-9 on volumes and coordinates (rounding of well-conditioned data),
1e-9 on LP optima (HiGHS's defaults at this scale).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.optimize import linprog

import polyell as pe
from polyell.geometry.combine import intersection


def corners(G, c):
    """Every corner c + G s of the cube's image (2^n, m)."""
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=G.shape[1])))
    return c + signs @ G.T


def zonotope_volume(G):
    m, n = G.shape
    return 2.0**m * sum(
        abs(np.linalg.det(G[:, list(s)])) for s in itertools.combinations(range(n), m)
    )


def brute_vertices(A, b):
    """Every r rows solved; the points satisfying all rows (to 1e-9), each once."""
    k, r = A.shape
    points = []
    for rows in itertools.combinations(range(k), r):
        block = A[list(rows)]
        if abs(np.linalg.det(block)) <= 1e-12 * np.prod(np.linalg.norm(block, axis=1)):
            continue
        y = np.linalg.solve(block, b[list(rows)])
        if np.all(A @ y <= b + 1e-9 * np.abs(b).max()):
            points.append(y)
    points = np.array(points)
    keep: list[int] = []
    for i, point in enumerate(points):
        if not keep or np.abs(points[keep] - point).max(axis=1).min() > 1e-9:
            keep.append(i)
    return points[keep]


def matched(found, expected, atol):
    """Whether each row of ``expected`` is within ``atol`` of a row of ``found``."""
    distance = np.abs(found[:, None, :] - expected[None, :, :]).max(axis=2)
    return bool((distance.min(axis=0) <= atol).all())


def check_against_highs(P, A, b, seed, count=300):
    """Support values and HiGHS's vertex solutions in random directions are P's own."""
    rng = np.random.default_rng(seed)
    m = A.shape[1]
    scale = float(np.abs(P.vertices).max())
    for d in rng.standard_normal((count, m)):
        found = linprog(-d, A, b, bounds=[(None, None)] * m, method="highs-ds")
        assert found.status == 0
        assert float(np.max(P.vertices @ d)) == pytest.approx(-found.fun, rel=1e-9, abs=1e-9)
        assert np.abs(P.vertices - found.x).max(axis=1).min() <= 1e-7 * scale


def check_vertices_are_vertices(P, A, b):
    """Every vertex satisfies every row and lies on rows of rank m (numpy, to 1e-9)."""
    unit, reach = A / np.linalg.norm(A, axis=1)[:, None], b / np.linalg.norm(A, axis=1)
    slack = reach - P.vertices @ unit.T
    tol = 1e-9 * (np.abs(reach).max() + np.abs(P.vertices).max())
    assert slack.min() >= -tol
    for on in slack <= tol:
        assert np.linalg.matrix_rank(unit[on], tol=1e-9) == A.shape[1]


def test_the_facets_of_a_5d_zonotope_give_its_vertices():
    """140 facets of a well-conditioned zonotope with 8 generators (SolverError before)."""
    rng = np.random.default_rng(0)
    G, c = rng.standard_normal((5, 8)), rng.standard_normal(5)
    Z = pe.Polytope(G, c)
    P = pe.HPolytope(Z.A, Z.b)
    # 2 sum_{i < 5} C(7, i) = 198 vertices in general position, each a corner
    assert len(P.vertices) == 198 and len(P.b) == 140
    assert matched(corners(G, c), P.vertices, 1e-9 * np.abs(G).sum())
    assert P.volume == pytest.approx(zonotope_volume(G), rel=1e-9)
    for d in rng.standard_normal((50, 5)):
        assert np.max(P.vertices @ d) == pytest.approx(c @ d + np.abs(G.T @ d).sum(), rel=1e-12)


@pytest.mark.parametrize(("scale_A", "scale_b"), [(1e-6, 1.0), (1e6, 1.0), (1.0, 1e-6), (1.0, 1e6)])
def test_rescaled_rows_change_nothing_but_the_scale(scale_A, scale_b):
    """A or b times 1e-6 or 1e6: the same vertices times scale_b / scale_A, the same facets."""
    rng = np.random.default_rng(0)
    G, c = rng.standard_normal((5, 8)), rng.standard_normal(5)
    Z = pe.Polytope(G, c)
    P = pe.HPolytope(Z.A * scale_A, Z.b * scale_b)
    factor = scale_b / scale_A
    assert len(P.vertices) == 198 and len(P.b) == 140
    assert matched(corners(G, c), P.vertices / factor, 1e-9 * np.abs(G).sum())
    assert P.volume == pytest.approx(zonotope_volume(G) * factor**5, rel=1e-9)


def test_the_intersection_of_two_5d_zonotopes_has_every_vertex():
    """60 rows (SolverError before): against HiGHS in 300 directions."""
    rng = np.random.default_rng(7)
    Z1 = pe.Polytope(rng.standard_normal((5, 6)), np.zeros(5))
    Z2 = pe.Polytope(rng.standard_normal((5, 6)), 0.3 * rng.standard_normal(5))
    P = intersection(Z1, Z2)
    A, b = np.vstack([Z1.A, Z2.A]), np.concatenate([Z1.b, Z2.b])
    assert P.is_bounded and P.dim == 5
    check_vertices_are_vertices(P, A, b)
    check_against_highs(P, A, b, seed=1)


def test_a_4d_intersection_equals_every_four_rows_solved():
    rng = np.random.default_rng(3)
    Z1 = pe.Polytope(rng.standard_normal((4, 5)), np.zeros(4))
    Z2 = pe.Polytope(rng.standard_normal((4, 5)), 0.3 * rng.standard_normal(4))
    P = intersection(Z1, Z2)
    A, b = np.vstack([Z1.A, Z2.A]), np.concatenate([Z1.b, Z2.b])
    expected = brute_vertices(A, b)
    assert len(P.vertices) == len(expected)
    assert matched(P.vertices, expected, 1e-9) and matched(expected, P.vertices, 1e-9)


@pytest.mark.parametrize("seed", [2, 8])
def test_72_tangent_planes_of_the_6d_ball(seed):
    """A generic 6-D set of 72 rows (SolverError after two minutes before; 0.4 s now)."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((72, 6))
    A /= np.linalg.norm(A, axis=1)[:, None]
    b = np.ones(72)
    P = pe.HPolytope(A, b)
    assert len(P.b) == 72  # each plane touches the ball inside: every row a facet
    check_vertices_are_vertices(P, A, b)
    check_against_highs(P, A, b, seed=seed)


def test_a_6d_intersection_of_a_zonotope_and_a_force_set():
    """126 rows in 6-D (SolverError before)."""
    rng = np.random.default_rng(6)
    Z = pe.Polytope(rng.standard_normal((6, 8)), np.zeros(6))
    J = rng.standard_normal((6, 7))
    g = 0.2 * rng.standard_normal(7)
    force = pe.analyze(pe.Dynamics(J, np.eye(7), g), np.full(7, 2.0), capacity="force")
    P = intersection(Z, force.polytope)
    A = np.vstack([Z.A, J.T, -J.T])
    b = np.concatenate([Z.b, 2.0 - g, 2.0 + g])
    check_vertices_are_vertices(P, A, b)
    check_against_highs(P, A, b, seed=2, count=200)


def line_and_rays_set():
    """Six rows in R^6 of rank 5: a line, and in the row space 4 vertices and 8 rays."""
    rng = np.random.default_rng(9)
    basis = rng.standard_normal((5, 6))
    A = rng.standard_normal((6, 5))
    A[:, 0] = -np.abs(A[:, 0]) - 0.3
    return A @ basis, rng.uniform(0.5, 2.0, 6)


def brute_rays(A):
    """Extreme rays of {d : A d <= 0} within the row space: null directions of r - 1 rows."""
    unit = A / np.linalg.norm(A, axis=1)[:, None]
    space = np.linalg.svd(unit)[2][: np.linalg.matrix_rank(unit)].T  # (m, r)
    rows = unit @ space
    r = rows.shape[1]
    found = []
    for subset in itertools.combinations(range(len(rows)), r - 1):
        _, sigma, vt = np.linalg.svd(rows[list(subset)])
        if sigma[-1] <= 1e-9:
            continue
        for d in (vt[-1], -vt[-1]):
            new = not any(np.abs(d - e).max() <= 1e-9 for e in found)
            if np.all(rows @ d <= 1e-12) and new:
                found.append(d)
    return np.array(found) @ space.T, space


@pytest.mark.parametrize(
    ("scale_A", "scale_b"), [(1.0, 1.0), (1e-6, 1.0), (1e6, 1.0), (1.0, 1e6), (1.0, 1e-6)]
)
def test_rays_and_lines_by_a_relative_rule(scale_A, scale_b):
    """Rays cddlib rounded to t ~ 1e-15 are rays, not vertices at 1e16 (6 to 9 "vertices"
    and 8 to 5 rays before, depending on the scale)."""
    A, b = line_and_rays_set()
    P = pe.HPolytope(A * scale_A, b * scale_b)
    rays, space = brute_rays(A)
    line = np.linalg.svd(space.T)[2][-1]  # the direction no row sees
    assert len(rays) == 8
    assert len(P.rays) == 8 + 2 and len(P.vertices) == 4
    expected = np.vstack([rays, line, -line])
    assert matched(P.rays, expected, 1e-9) and matched(expected, P.rays, 1e-9)
    # the vertices, in the row space: every 5 rows solved there
    unit = A / np.linalg.norm(A, axis=1)[:, None]
    vertices = brute_vertices(unit @ space, b / np.linalg.norm(A, axis=1))
    factor = scale_b / scale_A
    assert matched((P.vertices / factor) @ space, vertices, 1e-9 * np.abs(vertices).max())
    assert P.limits(line).hi == np.inf and P.limits(-line).hi == np.inf


@pytest.mark.parametrize("m", [3, 4, 5, 6])
def test_unbounded_sets_scale(m):
    """Cones with an apex and a few more rows: vertices and rays as every m rows (and
    m - 1) give them, at any scale of A and b."""
    rng = np.random.default_rng(m)
    A = rng.standard_normal((m + 3, m))
    A[:, 0] = -np.abs(A[:, 0]) - 0.5  # unbounded along +x0
    b = rng.uniform(0.5, 2.0, m + 3)
    vertices = brute_vertices(A / np.linalg.norm(A, axis=1)[:, None], b / np.linalg.norm(A, axis=1))
    rays, _ = brute_rays(A)
    for scale_A, scale_b in [(1.0, 1.0), (1e-6, 1e-6), (1e6, 1.0), (1.0, 1e-6)]:
        P = pe.HPolytope(A * scale_A, b * scale_b)
        assert len(P.vertices) == len(vertices) and len(P.rays) == len(rays)
        factor = scale_b / scale_A
        assert matched(P.vertices / factor, vertices, 1e-9 * np.abs(vertices).max())
        assert matched(P.rays, rays, 1e-9)


@pytest.mark.parametrize("m", [2, 3, 4, 5, 6])
def test_random_polytopes_equal_every_m_rows_solved(m):
    """Random rows about a far point, a box's rows through its vertices (degenerate)."""
    rng = np.random.default_rng(10 + m)
    k = {2: 9, 3: 12, 4: 14, 5: 15, 6: 16}[m]
    A = rng.standard_normal((k, m))
    shift = 50.0 * rng.standard_normal(m)
    b = rng.uniform(0.5, 2.0, k) * np.linalg.norm(A, axis=1) + A @ shift
    P = pe.HPolytope(A, b)
    expected = brute_vertices(A, b)
    assert len(P.vertices) == len(expected)
    assert matched(P.vertices, expected, 1e-9 * np.abs(expected).max())
    # a cube with a row through each vertex besides its m facets (degenerate vertices)
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=m)))
    cube = pe.HPolytope(
        np.vstack([np.eye(m), -np.eye(m), signs]), np.r_[np.ones(2 * m), np.full(len(signs), m)]
    )
    assert len(cube.vertices) == 2**m and len(cube.b) == 2 * m
    assert cube.volume == pytest.approx(2.0**m, rel=1e-12)
