"""HPolytope's vertex sets are complete: checked against an enumeration of every m rows.

Found by the independent check of the force sweep: cddlib in floating point missed
vertices where two joints' columns of J are nearly proportional (rows at angles near its
epsilon; 6 of 14 vertices, a volume of 3.15 for 9.83) and reported a clearly non-empty
6-D set empty.  The reference here is independent of the package: every m-subset of the
2n rows solved with numpy, the feasible points kept, their hull's volume by Qhull, and a
point strictly inside found by a linear program.  Tolerances: the volumes to 1e-9 (the
vertices are exact to rounding; the hull of a complete set is the set).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

import polyell as pe


def rows_of(J, g, tau_max, tau_min):
    centre, half = (tau_max + tau_min) / 2, (tau_max - tau_min) / 2
    A, c = (J / half).T, (g - centre) / half
    return np.vstack([A, -A]), np.concatenate([1 - c, 1 + c])


def brute_force_volume(A, b):
    m = A.shape[1]
    points = []
    for rows in itertools.combinations(range(len(A)), m):
        block = A[list(rows)]
        if abs(np.linalg.det(block)) < 1e-13 * np.prod(np.linalg.norm(block, axis=1)):
            continue
        x = np.linalg.solve(block, b[list(rows)])
        if np.all(A @ x <= b + 1e-10 * np.abs(b).max()):
            points.append(x)
    return ConvexHull(np.array(points)).volume


def thin_arm(seed, m, n):
    """J = U diag(1, ..., 1, 1e-9) V^T: full rank, sigma ratio 1e-9; gravity, limits."""
    rng = np.random.default_rng(seed)
    U, _ = np.linalg.qr(rng.normal(size=(m, m)))
    V, _ = np.linalg.qr(rng.normal(size=(n, m)))
    J = (U * np.r_[np.ones(m - 1), 1e-9]) @ V.T
    g = 0.3 * rng.normal(size=n)
    return J, g, 1 + rng.random(n), -1 - rng.random(n)


def nearly_proportional(seed, m, n, low):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(m, n))
    J[:, 1] = J[:, 0] + 1e-7 * rng.normal(size=m)
    g = 0.2 * rng.normal(size=n)
    return J, g, 2.0 * np.ones(n), low * np.ones(n)


@pytest.mark.parametrize(
    ("seed", "m", "n", "low"), [([10, 3, 7], 3, 7, -1.5), (6, 6, 7, -2.0), (8, 6, 7, -2.0)]
)
def test_nearly_proportional_columns_keep_every_vertex(seed, m, n, low):
    J, g, high, low = nearly_proportional(seed, m, n, low)
    P = pe.analyze(pe.Dynamics(J, np.eye(n), g), high, low, capacity="force").polytope
    A, b = rows_of(J, g, high, low)
    assert not P.is_empty
    assert P.volume == pytest.approx(brute_force_volume(A, b), rel=1e-9)
    assert np.all(A @ P.vertices.T <= b[:, None] + 1e-9)  # every vertex in the set
    # the limits along the axes (the line {a t} through the origin) equal a linear program's
    for axis in np.eye(m):
        best = linprog([-1.0], (A @ axis)[:, None], b, bounds=[(None, None)], method="highs")
        assert P.limits(axis).hi == pytest.approx(-best.fun, rel=1e-7)


def test_a_thin_but_full_set_is_not_reported_empty():
    # sigma_min / sigma_max = 1e-9 (full rank): long and thin, its centre well inside
    m, n = 6, 7
    J, g, high, low = thin_arm(11, m, n)
    an = pe.analyze(pe.Dynamics(J, np.eye(n), g), high, low, capacity="force")
    assert an.rank == m and not an.polytope.is_empty
    A, b = rows_of(J, g, high, low)
    assert np.all(A @ an.center < b)  # the centre h0 is strictly inside
    assert an.polytope.is_bounded and an.polytope.volume > 0


def test_ball_radius_is_undefined_when_the_centre_is_outside():
    J = np.array([[-0.1151, 0.7603, -0.1067], [-0.2969, -0.0222, -1.2360]])
    g = np.array([-0.3229, -0.1000, 0.3703])
    high, low = np.array([2.456, 2.586, 0.879]), np.array([0.0, -2.617, -0.669])
    an = pe.analyze(pe.Dynamics(J, np.eye(3), g), high, low, capacity="force")
    assert not an.polytope.is_empty and not an.polytope.contains(an.center)
    assert np.isnan(an.polytope.ball_radius)
    inside = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 2, 1])
    assert inside.ball_radius == pytest.approx(1.0)


def test_the_set_is_unbounded_exactly_when_the_analysis_finds_j_singular():
    # sigma_min / sigma_max of J L^-1 = 3.9e-11, below the rank threshold: rank 1 < 2,
    # so unbounded along Ker J^T (before, the normalized rows decided full rank: a
    # finite volume of 1e11 beside a singular analysis)
    J = np.array(
        [
            [-0.05399071408198852, 1.492590424813789, 0.9550756548240461],
            [-0.04568833493412482, 1.2630685217707298, 0.8082096571308486],
        ]
    )
    g = np.array([0.07981925488880452, -0.10174704537497091, 0.1642703828603681])
    high = np.array([2.957556923975349, 1.4830218157124804, 1.7901425192748097])
    low = np.array([-1.36234262538768, -2.6677995600413937, -2.684567873686438])
    an = pe.analyze(pe.Dynamics(J, np.eye(3), g), high, low, capacity="force")
    assert an.rank == 1 and an.is_singular
    assert not an.polytope.is_bounded and an.polytope.volume == np.inf
    assert len(an.polytope.rays) > 0


def test_a_nearly_parallel_row_keeps_its_vertex():
    # The square's top row and a copy tilted by 1e-6 about (0.9, 1): cddlib merged the two
    # and returned (1, 1 + 1e-7), outside the tilted row; the vertex (0.9, 1) was lost.
    tilt = 1e-6
    a = np.array([-np.sin(tilt), np.cos(tilt)])
    A = np.array([[1.0, 0], [-1, 0], [0, 1], [0, -1], a])
    b = np.array([1.0, 1, 1, 1, a @ [0.9, 1.0]])
    P = pe.HPolytope(A, b)
    assert np.all(A @ P.vertices.T <= b[:, None] + 1e-12)
    # the vertex where the rows meet, to their conditioning (eps / tilt)
    assert np.min(np.linalg.norm(P.vertices - [0.9, 1.0], axis=1)) <= 1e-9
    assert P.volume == pytest.approx(4 - 0.5 * 1.9**2 * np.tan(tilt), rel=1e-12)


def test_the_default_centre_is_the_chebyshev_centre():
    # an inradius (1.48) above the median offset: the radius cap bound, and the centre was
    # another point of the set (ball radius 0.82)
    A = np.array([[-0.067, -0.998], [0.853, -0.522], [0.095, -0.995], [0.593, -0.805]])
    A = np.vstack([A, [[0.002, 1.0], [0.97, 0.244]]])
    b = np.array([3.124, 0.664, 0.272, 0.432, 0.971, 1.074])
    P = pe.HPolytope(A, b)
    lengths = np.linalg.norm(A, axis=1)
    best = linprog([0, 0, -1], np.c_[A, lengths], b, bounds=[(None, None)] * 2 + [(0, None)])
    assert P.ball_radius == pytest.approx(best.x[2], rel=1e-9)


def test_a_thin_force_set_has_its_volume_where_qhull_fails():
    # sigma ratio 1e-9: Qhull finds a dupridge among the whitened vertices; the cones over
    # the faces were summed in task coordinates, where the set's length (1e9) swamped the
    # tolerance (4e-7 for 7e11).  Against Lawrence's formula of the force sweep, to the
    # rounding bound m n eps cond of the data's conditioning.
    from polyell.geometry.directions import sphere_directions
    from polyell.studies.batch import BatchOptions
    from polyell.studies.force_batch import force_rows

    m, n = 6, 7
    J, g, high, low = thin_arm(14, m, n)
    P = pe.analyze(pe.Dynamics(J, np.eye(n), g), high, low, capacity="force").polytope
    batch = pe.Dynamics(J[None], np.eye(n)[None], g[None])
    columns, scalar = force_rows(batch, high, low, sphere_directions(8, m), BatchOptions())
    assert not scalar[0]
    bound = m * n * np.finfo(float).eps * 1e9
    assert P.volume == pytest.approx(columns["polytope_volume"][0], rel=bound)


def test_a_ray_at_the_rank_threshold_has_infinite_limits():
    """sigma_3 / sigma_1 = 1e-11, below the rank tolerance: the force set has rays, and the
    limits along them are infinite as for an exact kernel (they were about 1e12)."""
    rng = np.random.default_rng(3)
    U, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    V, _ = np.linalg.qr(rng.standard_normal((4, 4)))
    S = np.zeros((3, 4))
    S[:, :3] = np.diag([2.0, 1.5, 2e-11])
    J = U @ S @ V.T
    an = pe.analyze(pe.Dynamics(J, np.eye(4), [0.3, -0.2, 0.1, 0.4]), [5.0] * 4, capacity="force")
    P = an.polytope
    assert not P.is_bounded and an.rank == 2
    for t in (U[:, 2], -U[:, 2], P.rays[0]):
        lo, hi = P.limits(t)
        assert lo == -np.inf and hi == np.inf
    lo, hi = P.limits(U[:, 0])  # across the rays: bounded
    assert np.isfinite(lo) and np.isfinite(hi)


@pytest.mark.parametrize("t0", [1e-8, 1e-10, 1e-12])
def test_a_thin_force_set_keeps_its_dimension_and_area(t0):
    """One torque range 2 t0 wide, the others 2: the set is a thin parallelogram of area
    4 t0 (the paper's planar arm shape), not a segment, nor unbounded (the rank is J's)."""
    J = np.array([[1.0, 0.5, 0.2], [0.0, 1.0, 0.3]])
    dyn = pe.Dynamics(J, np.diag([2.0, 1.0, 0.5]), [0.1, -0.2, 0.05])
    an = pe.analyze(dyn, [t0, 1.0, 1.0], capacity="force")
    P = an.polytope
    assert an.rank == 2 and P.dim == 2 and P.is_bounded
    # the area by brute force: every two rows, the hull of the feasible points
    A = np.vstack([J.T, -J.T])
    b = np.concatenate([np.array([t0, 1.0, 1.0]) - dyn.g, dyn.g + np.array([t0, 1.0, 1.0])])
    points = [
        np.linalg.solve(A[[i, j]], b[[i, j]])
        for i, j in itertools.combinations(range(6), 2)
        if abs(np.linalg.det(A[[i, j]])) > 1e-12
    ]
    inside = np.array([p for p in points if np.all(A @ p <= b + 1e-9 * t0)])
    # a convex polygon: its vertices by angle about their mean, the shoelace formula
    x, y = (inside - inside.mean(axis=0)).T
    order = np.argsort(np.arctan2(y, x))
    x, y = x[order], y[order]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    eps = np.finfo(float).eps
    assert P.volume == pytest.approx(area, rel=10 * eps / t0)  # eps times cond (1 / t0)
    row = pe.compare(an, 16, mvie=False, outer=False).to_row()
    swept = pe.sweep(
        pe.Dynamics(J[None], dyn.B[None], dyn.g[None]),
        tau_max=[t0, 1, 1],
        capacity="force",
        directions=16,
    )
    assert swept["polytope_volume"][0] == pytest.approx(row["polytope_volume"], rel=10 * eps / t0)


def test_a_force_set_at_the_edge_of_emptiness_is_scored_not_refused():
    """Gravity pulls the set to a vertex: its volume falls as (1 - f)^3, and at f = 1 it is a
    point whose ellipsoids are undefined with a reason (an unrelated InputError before)."""
    rng = np.random.default_rng(21)
    m, n = 3, 7
    J = rng.normal(size=(m, n))
    root = rng.normal(size=(n, n))
    B = root @ root.T + n * np.eye(n)
    upper, lower = rng.uniform(0.5, 2, n), -rng.uniform(0.5, 2, n)
    d = np.linalg.svd(J)[2][m:].T @ rng.normal(size=n - m)
    d /= np.abs(d).max()
    A_ub = np.vstack([np.hstack([J.T, d[:, None]]), -np.hstack([J.T, d[:, None]])])
    cost = np.r_[np.zeros(m), -1.0]
    edge = -linprog(
        cost, A_ub=A_ub, b_ub=np.concatenate([upper, -lower]), bounds=[(None, None)] * (m + 1)
    ).fun
    volumes = {}
    for f in (1 - 1e-3, 1 - 1e-6, 1.0):
        an = pe.analyze(pe.Dynamics(J, B, f * edge * d), upper, lower, capacity="force")
        row = pe.compare(an, 16, mvie=False, outer=False).to_row()
        volumes[f] = row["polytope_volume"]
    assert volumes[1 - 1e-6] == pytest.approx(volumes[1 - 1e-3] * 1e-9, rel=1e-3)
    assert volumes[1.0] in (0.0, 1.0) and row["polytope_dim"] < 3  # a point (or nothing)
    comparison = pe.compare(an, 16, mvie=False, outer=False)
    assert not comparison["static"].defined


def test_thin_sets_about_a_poorly_placed_interior_point():
    """The interior point far closer to one row than another (the Chebyshev centre of a
    slab sits at its end; a centre given 1e-9 from a facet; gravity 1e-9 short of a joint's
    limit): cddlib works from the analytic centre, and the sets keep their volume."""
    box = [[1, 0], [0, 1], [-1, 0], [0, -1]]
    P = pe.HPolytope(box, [1, 5e-9, 1, 5e-9])  # [-1, 1] x [-5e-9, 5e-9]
    assert P.is_bounded and P.volume == pytest.approx(2e-8, rel=1e-6)
    assert tuple(P.limits([1.0, 0.0])) == pytest.approx((-1.0, 1.0))
    assert not P.contains([-5.0, 0.0])
    for center in ([1 - 1e-9, 0.0], [1 - 1e-9, 1 - 1e-9]):
        assert pe.HPolytope(box, [1, 1, 1, 1], center=center).volume == pytest.approx(4.0)
    from scipy.stats import special_ortho_group

    R = special_ortho_group.rvs(6, random_state=np.random.default_rng(1))
    half = np.ones(6)
    half[0] = 5e-9
    P = pe.HPolytope(np.vstack([R.T, -R.T]), np.concatenate([half, half]))
    assert P.volume == pytest.approx(np.prod(2 * half), rel=1e-6)  # eps times 2e8
    J = np.array([[1.0, 0.0, -4.0], [0.0, 1.0, -2.0]])
    g = (1 - 1e-9) * np.array([1.0, 0.5, 0.25])
    an = pe.analyze(pe.Dynamics(J, np.eye(3), g), np.ones(3), -np.ones(3), capacity="force")
    # the exact area: the polygon of every two rows (shoelace), 0.19140625 to 1e-9
    A = np.vstack([J.T, -J.T])
    b = np.concatenate([1 - g, 1 + g])
    points = np.array(
        [
            np.linalg.solve(A[[i, j]], b[[i, j]])
            for i, j in itertools.combinations(range(6), 2)
            if abs(np.linalg.det(A[[i, j]])) > 1e-12
        ]
    )
    inside = points[np.all(points @ A.T <= b + 1e-12, axis=1)]
    x, y = (inside - inside.mean(axis=0)).T
    order = np.argsort(np.arctan2(y, x))
    x, y = x[order], y[order]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert an.polytope.is_bounded and an.polytope.volume == pytest.approx(area, rel=1e-7)


@pytest.mark.parametrize("m", [2, 3, 4, 5, 6])
@pytest.mark.parametrize("distance", [1e3, 1e6, 1e9, 1e12, 1e15])
def test_far_redundant_rows_leave_the_set_as_it_is(m, distance):
    # Redundant rows `distance` times the set's size away, more of them than the set's
    # rows, about a set off the origin.  Two defects: the walk's tolerance was relative to
    # the largest offset (a far row's: every row through every point, a triangle for a
    # hexagon), and the Chebyshev centre, solved in units of the median offset (a far
    # row's), left the set (a point of volume 1 and no facets).
    rng = np.random.default_rng(m)
    cuts = rng.normal(size=(m + 2, m))
    A = np.vstack([np.eye(m), -np.eye(m), cuts / np.linalg.norm(cuts, axis=1)[:, None]])
    centre = 10.0 * rng.normal(size=m)
    b = rng.uniform(0.5, 1.5, len(A)) + A @ centre
    reference = pe.HPolytope(A, b)
    far = rng.normal(size=(len(A) + 3, m))
    far /= np.linalg.norm(far, axis=1)[:, None]
    size = float(np.linalg.norm(reference.vertices - centre, axis=1).max())
    offsets = far @ centre + distance * size * rng.uniform(1, 3, len(far))
    P = pe.HPolytope(np.vstack([A, far]), np.concatenate([b, offsets]))
    assert np.all(A @ P.center < b)
    assert P.volume == pytest.approx(reference.volume, rel=1e-9)
    assert len(P.vertices) == len(reference.vertices) and len(P.b) == len(reference.b)
    gap = np.abs(P.vertices[:, None, :] - reference.vertices[None, :, :]).max(axis=2)
    assert gap.min(axis=1).max() <= 1e-9 * np.abs(centre).max()
    gap = np.abs(P.A[:, None, :] - reference.A[None, :, :]).max(axis=2)
    gap += np.abs(P.b[:, None] - reference.b[None, :]) / np.abs(b).max()
    assert gap.min(axis=1).max() <= 1e-9


@pytest.mark.parametrize("distance", [1e3, 1e9, 1e15])
def test_far_redundant_rows_leave_an_unbounded_set_as_it_is(distance):
    # A strip |x| <= 1, y >= 0 open upwards, and rows far below it: the analytic centre
    # (taken for rows at so different distances) has none, and its Newton steps stopped
    # 4e7 up the strip where lstsq cut the Hessian's small direction off; the whitening
    # from there moved the corners by 0.09.
    A = np.array([[0.0, -1.0], [1.0, 0.0], [-1.0, 0.0]])
    b = np.array([0.0, 1.0, 1.0])
    P = pe.HPolytope(np.vstack([A, [[0.3, -1.0], [-0.2, -1.0]]]), np.r_[b, distance, distance])
    assert not P.is_bounded and len(P.b) == 3
    corners = P.vertices[np.argsort(P.vertices[:, 0])]
    np.testing.assert_allclose(corners, [[-1.0, 0.0], [1.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(P.rays, [[0.0, 1.0]], atol=1e-12)
