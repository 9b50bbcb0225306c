"""The force sweep path (polyell.studies.force_batch) against the scalar path, row by row.

Every row it covers equals ``compare(analyze(..., capacity="force")).to_row()``: 1e-12
relative to the value or 1, the columns of the set's volume to ten times ``VOLUME_RTOL``
(Lawrence's formula, whose two evaluations must agree to it, against Qhull), the
quasi-Monte-Carlo columns included (the same points, mapped by the same axes).  The rows it
leaves to the scalar path -- singular, an empty gravity-consistent ellipsoid, vertices not
in general position -- are those the tests build, and a sweep mixes both.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.geometry.directions import sphere_directions
from polyell.studies.batch import BatchOptions
from polyell.studies.force_batch import VOLUME_RTOL, _closed, _layout, force_rows

VOLUME_COLUMNS = ("polytope_volume", "_coverage", "_coverage_stderr", "_overreach")
#: An optimal ellipsoid's log det is certified to MVIE_GAP; its volume and shape differ
#: from compare's (solved in another frame) by about its square root.
LOG_DET_TOL = 2.0 * np.sqrt(2.0 * 1e-8)


def arms(seed: int, K: int, m: int, n: int, gravity: float):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(K, m, n)) * rng.uniform(0.1, 10.0, size=(K, 1, n))
    g = gravity * rng.normal(size=(K, n))
    upper = rng.uniform(1.0, 3.0, n)
    lower = -upper * rng.uniform(0.5, 1.0, n)
    return J, g, upper, lower


def dynamics(J, g) -> pe.Dynamics:
    K, _, n = J.shape
    return pe.Dynamics(J, np.broadcast_to(np.eye(n), (K, n, n)).copy(), g)


def assert_row(columns, k, expected) -> None:
    for name, want in expected.items():
        got = columns[name][k]
        if not np.isfinite(want):
            assert got == want or (np.isnan(got) and np.isnan(want)), (k, name, got, want)
            continue
        scale = abs(want) if "radius" in name else max(1.0, abs(want))
        rtol = 10 * VOLUME_RTOL if name.endswith(VOLUME_COLUMNS) else 1e-12
        assert abs(got - want) <= rtol * max(scale, 1e-300), (k, name, got, want)


@pytest.mark.parametrize(
    ("m", "n", "gravity"),
    [(2, 3, 0.3), (2, 7, 0.5), (3, 4, 0.05), (3, 7, 0.05), (3, 7, 0.6), (6, 7, 0.05)],
)
def test_rows_equal_compare(m, n, gravity):
    J, g, upper, lower = arms(m * 10 + n, 24, m, n, gravity)
    T = sphere_directions(40, m)
    options = BatchOptions(capacity="force", samples=512, seed=3)
    columns, scalar = force_rows(dynamics(J, g), upper, lower, T, options)
    for k in np.flatnonzero(scalar):  # random arms are in general position: the rows left
        # have gravity that no force balances beyond the limits (chiacchio empty)
        analysis = pe.analyze(pe.Dynamics(J[k], np.eye(n), g[k]), upper, lower, capacity="force")
        assert analysis.c_perp @ analysis.c_perp >= 1.0
    for k in np.flatnonzero(~scalar):
        analysis = pe.analyze(pe.Dynamics(J[k], np.eye(n), g[k]), upper, lower, capacity="force")
        row = pe.compare(analysis, T, samples=512, seed=3, mvie=False, outer=False).to_row()
        assert_row(columns, k, row)


def test_left_to_the_scalar_path():
    J, g, upper, lower = arms(5, 7, 3, 7, 0.05)
    J[0] = np.outer([1.0, 2.0, 3.0], J[0, 0])  # rank 1: an unbounded set
    g[1] = 10.0 * upper  # gravity no force balances beyond the limits: chiacchio empty
    J[2][:, 1] = J[2][:, 0]  # two equal joints under equal loads: crowded vertices
    g[2, 1], upper[1], lower[1] = g[2, 0], upper[0], lower[0]
    J[3][:, 4] = 0.0  # a joint no force loads: no constraint, still in the batch
    J[4][:, 1] = J[4][:, 0]  # parallel rows under other loads: still in the batch
    J[5][:, 2] = 0.3 * J[5][:, 0] - 2.0 * J[5][:, 1]  # coplanar rows (a spherical shoulder)
    columns, scalar = force_rows(
        dynamics(J, g), upper, lower, sphere_directions(8, 3), BatchOptions()
    )
    assert scalar.tolist() == [True, True, True, False, False, False, False]
    assert np.isnan(columns["polytope_volume"][:3]).all()
    for k in (3, 4, 5):
        an = pe.analyze(pe.Dynamics(J[k], np.eye(7), g[k]), upper, lower, capacity="force")
        row = pe.compare(an, sphere_directions(8, 3), mvie=False, outer=False).to_row()
        assert_row(columns, k, row)


def test_a_vertex_of_nearly_dependent_rows_is_left_to_cddlib():
    # Rows 1-3 have normals 7e-9 from coplanar, below DEPENDENT: the batch skips their
    # candidate, yet it is a vertex (1, 1, 0.5) of the set; its edges end nowhere among
    # the vertices found, so the row is not certified and goes to the scalar path.
    d = 1e-8
    J = np.array([[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, 1.0, 0.0], [0.0, 0.0, d, 1.0]])
    g = np.array([0.0, 0.0, -1.0 - 0.5 * d, 0.0])
    limit = np.ones(4)
    _, scalar = force_rows(dynamics(J[None], g[None]), limit, -limit, sphere_directions(8, 3),
                           BatchOptions())  # fmt: skip
    assert scalar.tolist() == [True]


def test_the_edge_certificate():
    # The cube |z|_inf <= 1: its 8 vertices close every edge; without one, three edges
    # end nowhere.
    _, _, incidence, edges = _layout(3, 3)
    candidates = (incidence[:, :3] + incidence[:, 3:] == 1).all(axis=1)  # rows 0, 1, 2
    assert candidates.sum() == 8
    missing = candidates.copy()
    missing[np.flatnonzero(candidates)[3]] = False
    assert _closed(np.stack([candidates, missing, np.zeros_like(candidates)]), edges).tolist() == [
        True,
        False,
        True,  # no vertex: nothing to close (such rows fail the volume check)
    ]


@pytest.mark.parametrize(("m", "n"), [(2, 3), (3, 7), (6, 7)])
def test_the_optimal_ellipsoids_are_batched_and_equal_compare(m, n):
    # The MVIE and the outer ellipsoid of each set, solved together (free_center_mvie_batch,
    # free_center_mvee_batch) in the whitened coordinates: compare solves them in the
    # vertices' frame, so they agree to the certified gap (LOG_DET_TOL), the rest to 1e-12.
    J, g, upper, lower = arms(60 + m + n, 8, m, n, 0.05)
    T = sphere_directions(16, m)
    options = BatchOptions(capacity="force", mvie=True, outer=True, samples=256)
    columns, scalar = force_rows(dynamics(J, g), upper, lower, T, options)
    assert not scalar.any()
    for k in range(len(J)):
        analysis = pe.analyze(pe.Dynamics(J[k], np.eye(n), g[k]), upper, lower, capacity="force")
        row = pe.compare(analysis, T, samples=256)
        for kind in ("mvie", "outer"):
            assert row[kind].volume == pytest.approx(columns[f"{kind}_volume"][k], rel=LOG_DET_TOL)
            ratio = columns[f"chiacchio_{kind}_ratio"][k]
            assert ratio == pytest.approx(
                row["chiacchio"].__getattribute__(f"{kind}_ratio"), rel=LOG_DET_TOL
            )
        assert columns["mvie_inscribed_scale"][k] >= 1.0 - 1e-12  # inside by construction
        assert columns["outer_enclosing_scale"][k] <= 1.0 + 1e-12  # around by construction
        exact = {c: v for c, v in row.to_row().items() if "mvie" not in c and "outer" not in c}
        assert_row(columns, k, exact)


def test_volume_against_the_hull_of_brute_force_vertices():
    # An independent computation: every m rows and signs solved by lstsq, kept where all
    # rows hold, and the volume of their convex hull (Qhull) -- not the scalar path's cdd.
    from itertools import combinations, product

    from scipy.spatial import ConvexHull

    J, g, upper, lower = arms(8, 10, 3, 6, 0.3)
    columns, scalar = force_rows(
        dynamics(J, g), upper, lower, sphere_directions(8, 3), BatchOptions()
    )
    center, half = (upper + lower) / 2, (upper - lower) / 2
    for k in np.flatnonzero(~scalar):
        A, c = (J[k] / half).T, (g[k] - center) / half
        points = []
        for rows in combinations(range(6), 3):
            for signs in product((1.0, -1.0), repeat=3):
                h = np.linalg.lstsq(A[list(rows)], np.array(signs) - c[list(rows)], rcond=None)[0]
                if np.all(np.abs(A @ h + c) <= 1 + 1e-9):
                    points.append(h)
        volume = ConvexHull(np.array(points)).volume
        assert columns["polytope_volume"][k] == pytest.approx(volume, rel=1e-9)


def test_sweep_mixes_both_paths_and_refuses_what_analyze_refuses():
    J, g, upper, lower = arms(9, 8, 3, 7, 0.05)
    J[2][:, 1] = J[2][:, 0]
    dyn = dynamics(J, g)
    frame = pe.sweep(dyn, tau_max=upper, tau_min=lower, capacity="force", directions=16, samples=64)
    for k in (1, 2):
        an = pe.analyze(dyn[k], upper, lower, capacity="force")
        row = pe.compare(an, 16, samples=64, mvie=False, outer=False).to_row()
        kept = {name: value for name, value in row.items() if name in frame.columns}
        assert_row({name: frame[name].to_numpy() for name in kept}, k, kept)
    g[4] = 1e200
    with pytest.raises(pe.InputError, match=r"dyn\.g"):
        pe.sweep(dynamics(J, g), tau_max=upper, tau_min=lower, capacity="force")


def test_rows_at_the_rank_threshold_of_J_follow_the_analysis():
    """J's singular-value ratio 9.99999e-11, just below RANK_RTOL, J L^-1's 1.48e-10 above
    it (the case of the sixth independent check): the analysis calls the set unbounded
    (the rank is J's); the sweep scored it as bounded (volume 6e16)."""
    J = np.array(
        [
            [
                0.027161686242652153,
                0.07081497801927512,
                0.05924707279742232,
                -0.028371571292263878,
                0.10953720027333921,
                0.2989970859189765,
                0.11678145547825369,
            ],
            [
                -0.058087156129311035,
                -0.15144820066493722,
                -0.12670768568219792,
                0.06067383575848785,
                -0.2342555501354112,
                -0.6394374011617742,
                -0.2497497502776941,
            ],
            [
                0.04224788170799822,
                0.11016626729520053,
                0.09216717182281162,
                -0.044127153139007266,
                0.1703857721811008,
                0.4651063644891467,
                0.18166015969382468,
            ],
        ]
    )
    g = np.array(
        [
            0.07269082545741505,
            -0.13286380798473657,
            -0.3551964506605231,
            -0.19455950654918697,
            -0.13164456889381682,
            0.09411569290733306,
            0.15968588252496743,
        ]
    )
    upper = np.linspace(1.0, 3.0, 7)
    an = pe.analyze(pe.Dynamics(J, np.eye(7), g), upper, -0.8 * upper, capacity="force")
    row = pe.compare(an, 16, mvie=False, outer=False).to_row()
    swept = pe.sweep(
        pe.Dynamics(J[None], np.eye(7)[None], g[None]),
        tau_max=upper,
        tau_min=-0.8 * upper,
        capacity="force",
        directions=16,
    )
    assert an.rank == 2 and row["polytope_volume"] == np.inf
    assert swept["polytope_volume"][0] == np.inf
    assert swept["polytope_ball_radius"][0] == row["polytope_ball_radius"]


def test_candidates_are_scored_in_the_batch_as_compare_scores_them():
    # A core and centre (inside, crossing or around the set), the set's own centre, and a
    # torque weighting (no force ellipsoid: undefined, NaN, as compare reports it); the
    # force sweep raised a KeyError with any candidate before.
    J, g, upper, lower = arms(71, 8, 3, 7, 0.05)
    # a rotated core: its axes as Ellipsoid keeps them (the same sampled points as compare)
    rotated = np.linalg.qr(np.random.default_rng(5).normal(size=(3, 3)))[0]
    candidates = (
        pe.Candidate("round", core=np.eye(3) / 0.3**2),  # the sets are about 0.3 across
        pe.Candidate(
            "off",
            core=rotated @ np.diag([25.0, 100.0, 4.0]) @ rotated.T,
            center=[0.05, -0.02, 0.01],
        ),
        pe.Candidate("weighted", weighting=np.eye(7)),
    )
    T = sphere_directions(16, 3)
    options = BatchOptions(capacity="force", candidates=candidates, samples=256)
    columns, scalar = force_rows(dynamics(J, g), upper, lower, T, options)
    assert not scalar.any()
    assert np.isnan(columns["weighted_coverage"]).all()
    crossing = 0
    for k in range(len(J)):
        analysis = pe.analyze(pe.Dynamics(J[k], np.eye(7), g[k]), upper, lower, capacity="force")
        row = pe.compare(analysis, T, samples=256, mvie=False, outer=False, candidates=candidates)
        crossing += row["round"].coverage_stderr > 0
        assert_row(columns, k, row.to_row())
    assert crossing > 0  # some are estimated (caps that meet), not only exact
    assert (columns["off_coverage_stderr"] > 0).any()


@pytest.mark.parametrize(
    ("J", "g"),
    [
        ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [0.0, 0.0, 5.0]),  # cannot hold itself: empty
        ([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [0.0, 0.0, 0.5]),  # a joint no force loads
        ([[0.0, 1.0, 0.0], [0.0, 2.0, 0.0]], [0.0, 0.0, 0.0]),  # rank 1: unbounded
        ([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]], [0.0, 0.0, 0.0]),  # J = 0
    ],
)
def test_a_block_without_any_vertex_is_left_to_compare(J, g):
    # Found by the independent check: a block whose rows have no vertex candidate at all
    # raised a raw IndexError in the edge certificate; each row equals compare.
    dyn = dynamics(np.array([J]), np.array([g]))
    frame = pe.sweep(dyn, tau_max=np.ones(3), capacity="force", directions=8)
    row = pe.compare(pe.analyze(dyn[0], np.ones(3), capacity="force"), 8).to_row()
    for column in ("polytope_dim", "polytope_volume", "static_coverage"):
        assert frame[column][0] == pytest.approx(row[column], nan_ok=True), column
