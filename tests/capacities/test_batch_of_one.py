"""One analysis is a batch of one of the batched set builders (issue 31).

A :class:`~polyell.Polytope` in R^2 or R^3 takes its facets and vertex codes from the
batched zonotope decisions of :mod:`polyell.geometry.zonotope` (those of the sweeps), and
a force polytope its vertices and facets from :func:`polyell.capacities.force.
force_vertices`; each falls back to the enumeration it used before where the batch cannot
certify its answer.  Checked here against those enumerations (vertices bit for bit, facets
to rounding), against brute force (every cube corner through Qhull; every m rows of the
force set solved) and, for forces, against cddlib.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.capacities.force import ForceAnalysis
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.zonotope import (
    _enumerated_facets,
    corner_vertices,
    zonotope_facets,
    zonotope_vertices,
)


def generators(kind: str, m: int, n: int, seed: int) -> np.ndarray:
    """Seeded (m, n) generators: general, or with coplanar, parallel or zero columns."""
    rng = np.random.default_rng(seed)
    G = rng.normal(size=(m, n))
    if kind == "coplanar" and m == 3:  # three in a plane (a spherical shoulder)
        G[:, 2] = 0.7 * G[:, 0] - 1.3 * G[:, 1]
    elif kind == "parallel":
        G[:, -1] = -2.0 * G[:, 1]
    elif kind == "zero":
        G[:, -1] = 0.0
    elif kind == "prism" and m == 3:  # the Panda's velocities at the README posture
        G[2, : n // 2] = 0.0
        G[:2, n // 2 :] = 0.0
        G[:, n // 2 :] *= rng.choice([-1.0, 1.0], n - n // 2)
    return G


def same_sets(X: np.ndarray, Y: np.ndarray, rtol: float) -> bool:
    """Equal point sets (each point within ``rtol`` of the sets' size of one of the other)."""
    if X.shape != Y.shape:
        return False
    if not len(X):
        return True
    size = max(1.0, float(np.abs(Y).max()))
    distance = np.linalg.norm(X[:, None] - Y[None], axis=-1)
    return bool(max(distance.min(axis=0).max(), distance.min(axis=1).max()) <= rtol * size)


KINDS = ("general", "coplanar", "parallel", "zero", "prism")


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(("m", "n"), [(2, 3), (2, 6), (3, 3), (3, 6), (3, 7), (3, 9)])
@pytest.mark.parametrize("seed", range(4))
def test_zonotope_batch_of_one_equals_the_enumeration(kind, m, n, seed):
    M = generators(kind, m, n, seed)
    P = pe.Polytope(M, np.zeros(m))
    W = P.svd.V1.T  # the whitened generators, as Polytope enumerates them
    fast, enumerated = zonotope_facets(W), _enumerated_facets(W)
    assert fast.keys is not None  # these clear arrangements are the batch's
    assert enumerated.keys is None
    # the same vertices bit for bit (the same sign vectors, in the same order)
    assert np.array_equal(zonotope_vertices(fast, P.generators), zonotope_vertices(enumerated, M))
    # the same facets, in the same order, to rounding
    assert fast.normals.shape == enumerated.normals.shape
    np.testing.assert_allclose(fast.normals, enumerated.normals, rtol=0, atol=1e-14)
    np.testing.assert_allclose(fast.offsets, enumerated.offsets, rtol=1e-14, atol=1e-14)
    assert np.array_equal(fast.columns, enumerated.columns)
    # and both are the hull of the 2^n cube corners' images (brute force, Qhull)
    if P.dim == m:
        assert same_sets(P.vertices, corner_vertices(M), 1e-12)


def test_the_readme_panda_velocity_set_is_a_prism_of_the_batch():
    robot = pe.robots.load("panda")
    dyn = robot.dynamics([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8])
    P = pe.analyze(dyn, capacity="velocity", qd_max=robot.qd_max, qd_min=robot.qd_min).polytope
    fast = zonotope_facets(P.svd.V1.T)
    assert fast.keys is not None and not fast.general_position
    # a hexagon (three coplanar generators) times a segment (three parallel ones)
    assert (len(P.vertices), len(P.A)) == (12, 8)
    M = P.generators
    assert same_sets(P.vertices, corner_vertices(M), 1e-12)
    enumerated = _enumerated_facets(P.svd.V1.T)
    assert np.array_equal(zonotope_vertices(fast, M), zonotope_vertices(enumerated, M))


@pytest.mark.parametrize("scale", [1e-13, 1e-11, 1e-10, 1e-9, 1e-7])
def test_nearly_coplanar_generators_are_decided_as_before(scale):
    # In the bands about the thresholds the batch leaves the set to the enumeration; on
    # either side both decide alike: the same vertices and facets as before either way.
    rng = np.random.default_rng(7)
    M = rng.normal(size=(3, 6))
    M[:, 2] = 0.4 * M[:, 0] + 0.9 * M[:, 1] + scale * rng.normal(size=3)
    W = pe.Polytope(M, np.zeros(3)).svd.V1.T
    fast, enumerated = zonotope_facets(W), _enumerated_facets(W)
    assert np.array_equal(zonotope_vertices(fast, M), zonotope_vertices(enumerated, M))
    assert fast.normals.shape == enumerated.normals.shape
    np.testing.assert_allclose(fast.normals, enumerated.normals, rtol=0, atol=1e-14)


def brute_force_vertices(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The vertices of ``{A x <= b}``: every m rows solved, the feasible points kept."""
    m = A.shape[1]
    found = []
    for rows in itertools.combinations(range(len(A)), m):
        block = A[list(rows)]
        if abs(np.linalg.det(block)) < 1e-12:
            continue
        x = np.linalg.solve(block, b[list(rows)])
        if np.all(A @ x <= b + 1e-9 * np.abs(b).max()):
            found.append(x)
    points = np.array(found)
    keep = [
        i for i in range(len(points)) if not np.any(np.all(np.isclose(points[:i], points[i]), 1))
    ]
    return points[keep]


def force_analysis(m: int, n: int, seed: int, gravity: float = 0.05) -> ForceAnalysis:
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(m, n))
    high = rng.uniform(1.0, 3.0, n)
    dyn = pe.Dynamics(J, np.eye(n), gravity * rng.normal(size=n))
    return pe.analyze(dyn, high, -high * rng.uniform(0.7, 1.0, n), capacity="force")


def by_cddlib(an: ForceAnalysis) -> HPolytope:
    """The force set as the analysis built it before: cddlib on the 2n rows."""
    J, g = an.dynamics.J, an.dynamics.g
    A = np.vstack([J.T, -J.T])
    b = np.concatenate([an.tau_max - g, g - an.tau_min])
    return HPolytope(A, b, center=an.center, rank=an.rank)


def sorted_facets(P: HPolytope) -> np.ndarray:
    """The facets as rows ``[a | b / size]`` (offsets relative to the set's size), sorted."""
    size = float(np.abs(P.vertices).max(initial=1.0))
    rows = np.hstack([P.A, P.b[:, None] / size])
    return rows[np.lexsort(np.round(rows, 6).T[::-1])]


def are_data_rows(P: HPolytope, A: np.ndarray, b: np.ndarray) -> bool:
    """Whether every facet of P is one of the rows ``A x <= b``, normalized (to 2 eps)."""
    norms = np.linalg.norm(A, axis=1)
    rows = np.hstack([A / norms[:, None], (b / norms)[:, None]])
    facets = np.hstack([P.A, P.b[:, None]])
    scale = np.maximum(1.0, np.abs(rows))
    close = np.abs(facets[:, None] - rows[None]) <= 4 * np.finfo(float).eps * scale[None]
    return bool(close.all(axis=-1).any(axis=1).all())


@pytest.mark.parametrize(("m", "n"), [(2, 3), (2, 5), (3, 4), (3, 7), (4, 6)])
@pytest.mark.parametrize("seed", range(5))
def test_force_batch_of_one_equals_cddlib_and_brute_force(m, n, seed):
    an = force_analysis(m, n, seed)
    J, g = an.dynamics.J, an.dynamics.g
    A = np.vstack([J.T, -J.T])
    b = np.concatenate([an.tau_max - g, g - an.tau_min])
    assert an._enumerated(A, b) is not None  # taken by the batch
    P, reference = an.polytope, by_cddlib(an)
    assert are_data_rows(P, A, b)  # the facets: the data's own rows
    assert same_sets(P.vertices, reference.vertices, 1e-13)
    assert same_sets(P.vertices, brute_force_vertices(A, b), 1e-12)
    np.testing.assert_allclose(sorted_facets(P), sorted_facets(reference), rtol=0, atol=1e-13)
    assert P.volume == pytest.approx(reference.volume, rel=1e-12)
    assert P.volume == pytest.approx(ConvexHull(brute_force_vertices(A, b)).volume, rel=1e-12)
    assert (P.is_bounded, P.is_empty, P.dim) == (True, False, m)
    directions = pe.geometry.directions.sphere_directions(40, m) if m in (2, 3) else np.eye(m)
    for ours, theirs in zip(P.limits(directions), reference.limits(directions), strict=True):
        np.testing.assert_allclose(ours, theirs, rtol=1e-12, atol=1e-12)
    if m == 2:  # counter-clockwise, as cddlib's sets are ordered
        angles = np.unwrap(np.arctan2(*(P.vertices - P.vertices.mean(0)).T[::-1]))
        assert np.all(np.diff(angles) > 0)


@pytest.mark.parametrize("seed", range(6))
def test_panda_force_sets_are_the_batch_s_and_cddlib_s(seed):
    robot = pe.robots.load("panda")
    low, high = robot.position_limits
    q = np.random.default_rng(seed).uniform(low, high)
    an = pe.analyze(robot.dynamics(q), robot.tau_max, robot.tau_min, capacity="force")
    reference = by_cddlib(an)
    P = an.polytope
    assert same_sets(P.vertices, reference.vertices, 1e-13)
    np.testing.assert_allclose(sorted_facets(P), sorted_facets(reference), rtol=0, atol=1e-13)
    assert P.volume == pytest.approx(reference.volume, rel=1e-12)


def degenerate_force_sets():
    rng = np.random.default_rng(11)
    J = rng.normal(size=(3, 6))
    high = np.full(6, 2.0)
    g = 0.05 * rng.normal(size=6)
    singular = J.copy()
    singular[2] = singular[0] + singular[1]  # rank 2: unbounded along Ker J^T
    twins = J.copy()
    twins[:, 1] = twins[:, 0]  # two equal joints under equal loads: crowded vertices
    return {
        "singular": (singular, g, high),
        "empty": (J, g + 10.0 * high, high),  # gravity no force balances, beyond the limits
        "crowded": (twins, np.where(np.arange(6) == 1, g[0], g), high),
        "thin": (J, g, np.where(np.arange(6) == 2, 1e-7, high)),
    }


@pytest.mark.parametrize("name", ["singular", "empty", "crowded", "thin"])
def test_force_sets_the_batch_cannot_certify_are_cddlib_s(name):
    J, g, high = degenerate_force_sets()[name]
    an = pe.analyze(pe.Dynamics(J, np.eye(6), g), high, capacity="force")
    P, reference = an.polytope, by_cddlib(an)
    assert (P.is_empty, P.is_bounded, P.dim) == (
        reference.is_empty,
        reference.is_bounded,
        reference.dim,
    )
    assert reference.is_empty == (name == "empty")
    assert reference.is_bounded == (name != "singular")
    if name in ("singular", "empty", "crowded"):  # not certified: cddlib's own answer
        A = np.vstack([J.T, -J.T])
        b = np.concatenate([an.tau_max - g, g - an.tau_min])
        assert an._enumerated(A, b) is None
        assert np.array_equal(P.vertices, reference.vertices)
        assert np.array_equal(P.rays, reference.rays)
    # A slab 1e-7 wide amplifies rounding by its aspect ratio: both computations' vertices
    # are within 3e-8 of a 50-digit brute force there, and cddlib's facet normals within
    # 1e-8 of the data's rows (the batch's are the rows themselves).
    tolerance = 1e-7 if name == "thin" else 1e-13
    assert same_sets(P.vertices, reference.vertices, tolerance)
    np.testing.assert_allclose(sorted_facets(P), sorted_facets(reference), rtol=0, atol=tolerance)
