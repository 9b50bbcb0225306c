"""Batched vertices of degenerate zonotopes: the velocity sets of the library's arms.

A real arm's velocity zonotope ``{J qd_c + J L_v u}`` has a zero generator (the tip on the
last joint's axis), and generators three or four to a plane (parallel axes, a spherical
shoulder or wrist); so has its acceleration zonotope when its inertia is its (diagonal)
rotor inertia, as in a highly geared arm.  The batch enumerates their vertices
(:func:`polyell.studies.block_sets.vertex_signs`) as the scalar path does: the vertices
are the same sets, every sweep row with the MVIE and the outer ellipsoid is
``compare(analyze(...)).to_row()``, and at most 1 % of the rows leave the batch.
"""

from __future__ import annotations

import sys
from functools import cache
from itertools import product

import numpy as np
import pandas as pd
import pytest
from scipy.spatial import ConvexHull
from test_sweep import LOG_DET_TOL

import polyell as pe
from polyell.studies.batch import BatchOptions, block_sets
from polyell.studies.block_sets import facets, vertex_signs

ROBOTS = ("panda", "ur5", "kinova", "xarm7", "z1")
#: Random configurations per robot, and the first ones compared with compare() row by row.
COUNT, COMPARED = 200, 40
DIRECTIONS = 32


@cache
def arm(name: str, capacity: str) -> tuple[pe.Dynamics, dict[str, np.ndarray]]:
    """A seeded batch of the robot within its joint limits, and the sweep's joint limits.

    Accelerations: the arm's inertia replaced by its diagonal (decoupled rotors), which
    keeps the Jacobian's zero, parallel and coplanar columns in ``M = J B^-1 L``.
    """
    robot = pe.robots.load(name)
    low, high = robot.position_limits
    q = np.random.default_rng(sum(map(ord, name))).uniform(low, high, (COUNT, robot.nq))
    dyn = robot.dynamics(q)
    if capacity == "velocity":
        qd_max, qd_min = robot.velocity_limits()
        return dyn, {"qd_max": qd_max, "qd_min": qd_min}
    rotors = np.diagonal(dyn.B, axis1=1, axis2=2)[:, :, None] * np.eye(robot.nq)
    rotor_arm = pe.Dynamics(dyn.J, rotors, dyn.g, dyn.xdd_bias)
    return rotor_arm, {"tau_max": robot.tau_max, "tau_min": robot.tau_min}


def analysis(dyn: pe.Dynamics, limits: dict[str, np.ndarray], capacity: str) -> pe.Analysis:
    if capacity == "velocity":
        return pe.analyze(dyn, capacity="velocity", **limits)
    return pe.analyze(dyn, limits["tau_max"], limits["tau_min"])


@cache
def swept(name: str, capacity: str) -> tuple[pd.DataFrame, int]:
    """The sweep with the MVIE and the outer ellipsoid, and how many rows left the batch."""
    dyn, limits = arm(name, capacity)
    module = sys.modules["polyell.studies.sweep"]  # (shadowed by the function pe.sweep)
    scalar_rows, count = module._scalar_rows, [0]

    def counted(dyn, rows, job, state=None, first=0):
        count[0] += int(np.count_nonzero(rows))
        return scalar_rows(dyn, rows, job, state, first)

    module._scalar_rows = counted
    try:
        frame = pe.sweep(
            dyn,
            capacity=capacity,
            mvie=True,
            outer=True,
            scores=pe.SCORE_NAMES,
            directions=DIRECTIONS,
            **limits,
        )
    finally:
        module._scalar_rows = scalar_rows
    return frame, count[0]


def assert_same_points(points: np.ndarray, expected: np.ndarray, atol: float) -> None:
    """The same finite sets of points (rows), each within ``atol`` of one of the other."""
    assert len(points) == len(expected)
    distance = np.linalg.norm(points[:, None, :] - expected[None, :, :], axis=-1)
    assert distance.min(axis=1).max() <= atol
    assert distance.min(axis=0).max() <= atol


@pytest.mark.parametrize("capacity", ["velocity", "acceleration"])
@pytest.mark.parametrize("name", ROBOTS)
def test_batch_vertices_are_the_scalar_paths(name, capacity):
    dyn, limits = arm(name, capacity)
    if capacity == "velocity":  # the zonotope of B = I, no gravity (the sweep's)
        n = dyn.n
        B, g = np.broadcast_to(np.eye(n), (COUNT, n, n)), np.zeros((COUNT, n))
        bias = np.zeros((COUNT, dyn.m))
        upper, lower = limits["qd_max"], limits["qd_min"]
    else:
        B, g, bias = dyn.B, dyn.g, dyn.xdd_bias
        upper, lower = limits["tau_max"], limits["tau_min"]
    options = BatchOptions(vertices=True, outer=True, capacity=capacity)
    sets, _ = block_sets(dyn.J, B, g, bias, upper, lower, options)
    assert sets is not None and sets.signs is not None
    assert len(sets.rows) >= 0.99 * COUNT
    for row, k in enumerate(sets.rows):
        P = analysis(dyn[int(k)], limits, capacity).polytope
        half = sets.signs[row] @ sets.M[row].T
        batch = np.unique(np.concatenate([half, -half]), axis=0) + sets.xg[row]
        scale = np.linalg.norm(P.generators, axis=0).sum() + np.linalg.norm(P.center)
        assert_same_points(batch, P.vertices, 1e-12 * scale)


@pytest.mark.parametrize("capacity", ["velocity", "acceleration"])
@pytest.mark.parametrize("name", ROBOTS)
def test_at_most_one_row_in_a_hundred_leaves_the_batch(name, capacity):
    frame, scalar = swept(name, capacity)
    assert len(frame) == COUNT
    assert scalar <= 0.01 * COUNT


@pytest.mark.parametrize("capacity", ["velocity", "acceleration"])
@pytest.mark.parametrize("name", ROBOTS)
def test_sweep_rows_with_mvie_and_outer_equal_compare(name, capacity):
    """Columns at 1e-12 (relative to the value or 1); the MVIE's and the outer ellipsoid's,
    certified to a gap in log det, at LOG_DET_TOL (tests/studies/test_sweep.py)."""
    dyn, limits = arm(name, capacity)
    frame, scalar = swept(name, capacity)
    assert scalar <= 0.01 * COUNT  # (rows from the scalar path would be compare's own)
    for k in range(COMPARED):
        an = analysis(dyn[k], limits, capacity)
        expected = pe.compare(an, DIRECTIONS, mvie=True, outer=True).to_row()
        for name_ in frame.columns.intersection(list(expected)):
            value, wanted = frame.loc[k, name_], expected[name_]
            if not np.isfinite(wanted):
                assert value == wanted or (np.isnan(value) and np.isnan(wanted)), (k, name_)
                continue
            if "mvie" in name_ or "outer" in name_:
                tol = LOG_DET_TOL * max(1.0, abs(wanted))
            else:
                scale = abs(wanted) if "radius" in name_ else max(1.0, abs(wanted))
                tol = 1e-12 * scale
            assert abs(value - wanted) <= tol, (k, name_, value, wanted)


def corner_vertices(G: np.ndarray) -> np.ndarray:
    """The vertices by brute force: all 2^n sign vectors, their hull by Qhull."""
    corners = np.unique(np.array(list(product((-1.0, 1.0), repeat=G.shape[1]))) @ G.T, axis=0)
    return corners[ConvexHull(corners).vertices]


def degenerate(m: int, seed: int) -> np.ndarray:
    """Zonotopes (K, m, 6) in R^m with a zero column, parallel and coplanar columns."""
    rng = np.random.default_rng(seed)
    G = rng.normal(size=(4, m, 6))
    G[0, :, 3] = 0.0  # a zero column
    G[1, :, 4] = -0.5 * G[1, :, 1]  # two parallel columns
    if m == 3:
        G[2, :, 2] = 0.8 * G[2, :, 0] - 1.3 * G[2, :, 5]  # three coplanar columns
        G[3, :, 1] = G[3, :, 0] + 0.4 * G[3, :, 2]  # four coplanar columns
        G[3, :, 4] = -0.7 * G[3, :, 0] + 2.0 * G[3, :, 2]
    else:  # a parallel triple and a zero column
        G[2, :, 2], G[2, :, 5] = 2.0 * G[2, :, 0], -0.3 * G[2, :, 0]
        G[3, :, 1], G[3, :, 2] = 0.0, 1.5 * G[3, :, 4]
    return G


@pytest.mark.parametrize("m", [2, 3])
@pytest.mark.parametrize("seed", range(5))
def test_degenerate_zonotopes_against_brute_force(m, seed):
    """One batch of zonotopes with different vertex counts (the short rows are padded)."""
    G = degenerate(m, seed)
    U, s, Vt = np.linalg.svd(G, full_matrices=False)
    signs, generic = vertex_signs(Vt, facets(U, s, Vt).whitened)
    assert generic.all()
    counts = set()
    for k in range(len(G)):
        half = signs[k] @ G[k].T
        vertices = np.unique(np.concatenate([half, -half]), axis=0)
        expected = corner_vertices(G[k])
        assert_same_points(vertices, expected, 1e-12 * np.abs(G[k]).sum())
        counts.add(len(expected))
    assert len(counts) > 1
