"""A line that runs in the plane of a facet through the origin (issue 33's attack).

Such lines are common, not contrived: a force set whose torque limit equals the gravity
torque, a velocity set with ``qd_min = 0``, an acceleration set with ``tau_min = g`` all have
the origin on a facet, and a direction along that facet is one a user asks for.  In rounded
arithmetic the line's slope against the facet is 1e-17, not 0: it was cut at
``0 / 1e-17 = 0`` and lost half its interval.  Every interval here is checked against an LP
over the same half-spaces (HiGHS), or against a closed form by construction.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import linprog

import polyell as pe


def lp_interval(A, b, t):
    """``{s : A (s t) <= b}`` by HiGHS: the line's ends (NaN if it misses)."""
    ends = []
    for sign in (1.0, -1.0):
        result = linprog(
            -sign, A_ub=(A @ t)[:, None], b_ub=b, bounds=[(None, None)], method="highs"
        )
        ends.append(result.x[0] if result.status == 0 else np.nan)  # max s, then min s
    return ends[1], ends[0]


def rotation(theta):
    return np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])


@pytest.mark.parametrize("theta", np.linspace(0.0, 2.0 * np.pi, 37)[:-1])
def test_a_rotated_triangle_along_its_edge_through_the_origin_line(theta):
    """conv{(1,0), (3,0), (2,2)} turned by theta: the line along its bottom edge is [1, 3]."""
    R = rotation(theta)
    A = np.array([[0.0, -1.0], [2.0, 1.0], [-2.0, 1.0]]) @ R.T
    b = np.array([0.0, 6.0, -2.0])
    t = R @ np.array([1.0, 0.0])
    for P in (
        pe.HPolytope(A, b),
        pe.HPolytope.from_vertices(np.array([[1, 0], [3, 0], [2, 2]]) @ R.T),
    ):
        got = P.limits(t)
        np.testing.assert_allclose([got.lo, got.hi], [1.0, 3.0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_a_rotated_square_with_the_origin_on_an_edge(seed):
    theta = np.random.default_rng(seed).uniform(0, 2 * np.pi)
    R = rotation(theta)
    corners = np.array([[-0.5, 0.0], [0.5, 0.0], [0.5, 1.0], [-0.5, 1.0]]) @ R.T
    P = pe.HPolytope.from_vertices(corners)
    t = R @ np.array([1.0, 0.0])
    got = P.limits(t)
    np.testing.assert_allclose([got.lo, got.hi], [-0.5, 0.5], rtol=0, atol=1e-12)
    inside = P.contains(np.outer([-0.49, 0.0, 0.49], t))
    assert inside.all()  # (HiGHS on these rows, a 1e-17 slope, gives [0.5, 0.5]: no LP here)


def two_link(seed):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(2, 2))
    B = np.eye(2) + 0.3 * np.ones((2, 2))
    g = rng.normal(scale=5.0, size=2)
    return J, B, g


@pytest.mark.parametrize("seed", range(8))
def test_the_capacities_with_the_origin_on_a_facet(seed):
    """Force with tau_max = |g| on a joint, velocity with qd_min = 0, acceleration with
    tau_min = g: along the facet through the origin, polytope.limits, limits_along and the
    sweep's directional statistics all give the LP's interval."""
    J, B, g = two_link(seed)
    dyn = pe.Dynamics(J, B, g)
    cases = {}
    # force: rows J^T f in [tau_min - g, tau_max - g]; joint 0's upper row through 0
    tau_max = np.array([abs(g[0]) + 0.0, 30.0]) if g[0] < 0 else np.array([30.0, 30.0])
    tau_min = -np.array([30.0, 30.0])
    if g[0] >= 0:
        tau_min = np.array([g[0], -30.0])
    force = pe.analyze(dyn, tau_max, tau_min, capacity="force")
    edge = np.array([-J[1, 0], J[0, 0]])  # J[:, 0] . f = 0
    A = np.vstack([J.T, -J.T])
    cases["force"] = (
        force,
        edge / np.linalg.norm(edge),
        A,
        np.concatenate([tau_max - g, g - tau_min]),
    )
    # velocity: qd in [0, 2] x [-3, 3]: the image of qd_1 = 0 is along J[:, 1]
    velocity = pe.analyze(
        pe.Kinematics(J), capacity="velocity", qd_max=[2.0, 3.0], qd_min=[0.0, -3.0]
    )
    Jinv = np.linalg.inv(J)
    along = J[:, 1] / np.linalg.norm(J[:, 1])
    cases["velocity"] = (velocity, along, np.vstack([Jinv, -Jinv]), np.array([2.0, 3.0, 0.0, 3.0]))
    # acceleration: tau_min[0] = g[0]: qdd with (B qdd)_0 = 0 maps to J B^-1 e_1 ...
    acc = pe.analyze(dyn, [40.0, 40.0], [g[0], -40.0])
    M = J @ np.linalg.inv(B)
    rows = np.linalg.inv(M)  # x = M (tau - g): tau - g = M^-1 x
    line = M[:, 1] / np.linalg.norm(M[:, 1])  # tau_0 - g_0 = 0 along it
    lows, highs = np.array([0.0, -40.0 - g[1]]), np.array([40.0 - g[0], 40.0 - g[1]])
    cases["acceleration"] = (acc, line, np.vstack([rows, -rows]), np.concatenate([highs, -lows]))
    for name, (analysis, t, A, b) in cases.items():
        expected = lp_interval(A, b, t)
        got = analysis.polytope.limits(t)
        size = float(np.abs(analysis.polytope.vertices).max())
        np.testing.assert_allclose(
            [got.lo, got.hi], expected, rtol=0, atol=1e-9 * size, err_msg=name
        )
        assert expected[0] < -1e-6 * size and expected[1] > 1e-6 * size  # both sides of 0
        if name != "force":  # limits_along: accelerations and velocities
            limits = {"qd_max": [2.0, 3.0], "qd_min": [0.0, -3.0]} if name == "velocity" else {}
            batch = pe.Dynamics(J[None], B[None], g[None])
            upper = [40.0, 40.0] if name == "acceleration" else None
            lower = [g[0], -40.0] if name == "acceleration" else None
            with warnings.catch_warnings():
                warnings.simplefilter("error")  # no RuntimeWarning of a 0/0
                along_rows = pe.limits_along(
                    batch, None, t[None], upper, lower, capacity=name, **limits
                )
            np.testing.assert_allclose(
                [along_rows["polytope"].lo[0], along_rows["polytope"].hi[0]],
                expected, rtol=0, atol=1e-9 * size, err_msg=name,
            )  # fmt: skip
        # the sweep's far ends (its slabs, polytope_far_ends): the LP's upper end
        if name != "force":
            from polyell.comparison.directional import polytope_far_ends
            from polyell.geometry.limits import facet_slack, rounding_floor
            from polyell.studies.batch import BatchOptions, block_sets

            Bb, gb = (np.eye(2), np.zeros(2)) if name == "velocity" else (B, g)
            upper, lower = ([2.0, 3.0], [0.0, -3.0]) if name == "velocity" else (
                [40.0, 40.0], [g[0], -40.0])  # fmt: skip
            sets, _ = block_sets(J[None], Bb[None], gb[None], np.zeros((1, 2)),
                                 np.array(upper), np.array(lower), BatchOptions())  # fmt: skip
            slabs = sets.as_set_batch().slabs
            reach = 2.0 * (np.linalg.norm(sets.xg, axis=-1) + sets.size)
            far, meets = polytope_far_ends(
                slabs.normals, slabs.widths, slabs.midpoints, t[:, None],
                facet_slack(slabs.widths, reach[:, None], 6), rounding_floor(reach[:, None], 6),
            )  # fmt: skip
            assert meets[0, 0]
            np.testing.assert_allclose(far[0, 0], expected[1], rtol=0, atol=1e-9 * size)


def generator_line_case(seed, arm, m):
    """An acceleration zonotope whose origin lies inside a facet (or, in 3-D, on an edge):
    torque limits centred so that ``xg = -M u`` with ``u`` on that face; the line along the
    face's generator(s) through the origin (the recheck's construction, issue 33)."""
    rng = np.random.default_rng(seed)
    q = (
        rng.uniform(-3, 3, arm.n)
        if m == 2
        else pe.random_configurations(arm, 1, seed=seed).rows(0, 1)[0]
    )
    d = arm.dynamics(q)
    J, B, g = d.J, d.B, d.g
    L = rng.uniform(5, 50, arm.n)
    M = J @ np.linalg.solve(B, np.diag(L))
    free = list(rng.choice(arm.n, m - 1, replace=False))
    normal = np.linalg.svd(M[:, free].T)[2][-1]
    u = np.sign(normal @ M)
    u[free] = rng.uniform(-0.8, 0.8, m - 1)
    center = g - L * u
    t = M[:, free[0]] / np.linalg.norm(M[:, free[0]])
    return d, center + L, center - L, M, t


def lp_along(M, xg, t):
    """``{s : s t = xg + M u, |u| <= 1}`` by HiGHS with t and M as equalities (no tiny rows)."""
    n = M.shape[1]
    ends = []
    for sign in (1.0, -1.0):
        result = linprog(
            np.r_[-sign, np.zeros(n)], A_eq=np.c_[-t[:, None], M], b_eq=-xg,
            bounds=[(None, None)] + [(-1.0, 1.0)] * n, method="highs",
        )  # fmt: skip
        ends.append(result.x[0])
    return ends[1], ends[0]


@pytest.mark.parametrize("seed", [21, 3, 8, 13])
def test_a_zonotope_with_the_origin_in_a_facet_along_the_facet(seed):
    """The recheck's planar case (seed 21 gave [-0, 2.018], the LP [-0.473, 2.018]): the
    facet's normal is known to the rounding of M's conditioning, more than PARALLEL_SLOPE;
    within the slack over the set's reach the line runs in the facet."""
    arm = pe.PlanarArm([1.0, 0.8, 0.5], [4.0, 2.0, 0.6])
    d, tau_max, tau_min, M, t = generator_line_case(seed, arm, 2)
    analysis = pe.analyze(d, tau_max, tau_min)
    expected = lp_along(analysis.M, analysis.xg, t)
    size = float(np.abs(M).sum())
    got = analysis.polytope.limits(t)
    np.testing.assert_allclose([got.lo, got.hi], expected, rtol=0, atol=1e-8 * size)
    batch = pe.Dynamics(d.J[None], d.B[None], d.g[None])
    along = pe.limits_along(batch, None, t[None], tau_max, tau_min)["polytope"]
    np.testing.assert_allclose([along.lo[0], along.hi[0]], expected, rtol=0, atol=1e-8 * size)


@pytest.mark.parametrize("seed", range(6))
def test_the_panda_with_the_origin_on_an_edge_along_the_edge(seed):
    """3-D: the origin on an edge of the Panda's acceleration zonotope, the line along it;
    the sweep's far ends (its slabs, with the same parallel rule) agree."""
    from polyell.comparison.directional import polytope_far_ends
    from polyell.geometry.limits import facet_slack, parallel_slopes, rounding_floor
    from polyell.studies.batch import BatchOptions, block_sets

    panda = pe.robots.load("panda")
    d, tau_max, tau_min, M, t = generator_line_case(seed, panda, 2)
    analysis = pe.analyze(d, tau_max, tau_min)
    expected = lp_along(analysis.M, analysis.xg, t)
    size = float(np.abs(M).sum())
    got = analysis.polytope.limits(t)
    np.testing.assert_allclose([got.lo, got.hi], expected, rtol=0, atol=1e-8 * size)
    sets, _ = block_sets(d.J[None], d.B[None], d.g[None], d.xdd_bias[None], tau_max, tau_min,
                         BatchOptions())  # fmt: skip
    slabs = sets.as_set_batch().slabs
    reach = 2.0 * (np.linalg.norm(sets.xg, axis=-1) + sets.size)
    slack = facet_slack(slabs.widths, reach[:, None], 12)
    far, meets = polytope_far_ends(
        slabs.normals, slabs.widths, slabs.midpoints, t[:, None], slack,
        rounding_floor(reach[:, None], 12), parallel_slopes(slack, reach[:, None]),
    )  # fmt: skip
    assert meets[0, 0]
    np.testing.assert_allclose(far[0, 0], expected[1], rtol=0, atol=1e-8 * size)
