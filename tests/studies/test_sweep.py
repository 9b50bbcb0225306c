"""pe.sweep: equal to pe.compare row by row, Parquet datasets, resuming, Dask."""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.studies.batch import batch_rows
from reference import random_spd

ARM = pe.robots.load("chiacchio2000")

# The MVIE and the outer ellipsoid are certified to a gap of MVIE_GAP in log det, and a batch
# and a single solve may stop at different points within it.  In the optimum's metric,
# Y = X*^(-1/2) X X*^(-1/2), log det is strongly concave near I, so a feasible X within the
# gap has ||Y - I||_F <= sqrt(2 gap) to first order (a factor 2 covers the second-order
# term): its volume moves by at most gap / 2 and its support function sqrt(t^T X t) -- every
# directional limit, scale and score read from the shape -- by at most sqrt(2 gap) / 2
# relative; between two solutions twice that.  A score that is a ratio to the polytope (at
# most sqrt(m) <= sqrt(3) here, for the outer ellipsoid) moves by that much absolutely.
LOG_DET_TOL = np.sqrt(3.0) * 2.0 * np.sqrt(2.0 * pe.geometry.mvie.MVIE_GAP)


def assert_rows_equal_compare(
    frame: pd.DataFrame, dynamics, tau_max, tau_min, directions, mvie=False, candidates=()
):
    for _, row in frame.iterrows():
        k = int(row["configuration"])
        expected = pe.compare(
            pe.analyze(dynamics(k), tau_max, tau_min),
            directions,
            mvie=mvie,
            outer=mvie,
            candidates=candidates,
        ).to_row()
        unscored = {"configuration", "per_row", "t"} | {f"q{i}" for i in range(1, 8)}
        assert set(frame.columns) - set(expected) <= unscored
        for name in frame.columns.intersection(list(expected)):
            tol = LOG_DET_TOL if "mvie" in name or "outer" in name else 1e-9
            np.testing.assert_allclose(
                row[name], expected[name], rtol=tol, atol=tol, err_msg=f"{name} at {k}"
            )


def test_grid_sweep_of_the_paper_arm_equals_compare_including_singularities():
    g = pe.grid(np.pi / 2, (-np.pi, np.pi, 9), (-np.pi, np.pi, 9))
    frame = pe.sweep(ARM, g, chunk=17)
    assert list(frame["configuration"]) == list(range(81))
    q = frame[["q1", "q2", "q3"]].to_numpy()
    np.testing.assert_allclose(q, g.rows(0, 81))
    assert (frame["polytope_dim"] == 1).sum() == 9  # the stretched and folded postures
    assert frame.loc[frame["polytope_dim"] == 1, "yoshikawa_coverage"].isna().all()
    assert frame["per_row"].tolist() == (frame["polytope_dim"] == 1).tolist()  # singular
    assert_rows_equal_compare(
        frame, lambda k: ARM.dynamics(q[k]), ARM.tau_max, None, None
    )  # the defaults agree


def test_random_panda_sweep_equals_compare():
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    configurations = pe.random_configurations(40, low, high, seed=5)
    frame = pe.sweep(panda, configurations, directions=32, chunk=15)
    q = configurations.rows(0, 40)
    assert_rows_equal_compare(frame, lambda k: panda.dynamics(q[k]), panda.tau_max, None, 32)


def test_batched_mvie_and_outer_scores_equal_compare():
    """The batched log-det solver and the one of compare (its K = 1 case) agree row by row,
    for the MVIE and the outer ellipsoid, at singular configurations (the scalar path) and at
    random Panda ones."""
    g = pe.grid(np.pi / 2, (-np.pi, np.pi, 7), (-np.pi, np.pi, 7))
    frame = pe.sweep(ARM, g, mvie=True, outer=True, scores=pe.SCORE_NAMES, chunk=20)
    assert frame["mvie_mvie_ratio"].eq(1.0).all() and frame["outer_outer_ratio"].eq(1.0).all()
    assert np.allclose(frame["outer_enclosing_scale"], 1.0, atol=1e-12)
    assert np.allclose(frame["outer_coverage"], 1.0, rtol=1e-12)
    q = g.rows(0, 49)
    assert_rows_equal_compare(frame, lambda k: ARM.dynamics(q[k]), ARM.tau_max, None, None, True)
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    configurations = pe.random_configurations(30, low, high, seed=8)
    frame = pe.sweep(
        panda, configurations, mvie=True, outer=True, scores=pe.SCORE_NAMES, directions=16
    )
    q = configurations.rows(0, 30)
    assert frame["chiacchio_mvie_ratio"].between(0.05, 1.0).all()
    assert (frame["mvie_outer_ratio"] > 3.0**-1.5).all()  # John: vol(outer) <= 3^(3/2) vol(MVIE)
    assert_rows_equal_compare(frame, lambda k: panda.dynamics(q[k]), panda.tau_max, None, 16, True)


def test_a_batched_mvie_that_is_not_certified_is_undefined_in_its_row(monkeypatch):
    batch_module = sys.modules["polyell.studies.block_sets"]
    solve = batch_module.centred_mvee_batch

    def second_row_fails(points, **options):
        shapes, gaps, iterations = solve(points, **options)
        gaps[1] = np.inf
        return shapes, gaps, iterations

    monkeypatch.setattr(batch_module, "centred_mvee_batch", second_row_fails)
    frame = pe.sweep(
        ARM,
        [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6], [0.7, 0.8, 0.9]],
        mvie=True,
        scores=("coverage", "mvie_ratio"),
        directions=16,
    )
    assert frame["mvie_coverage"].isna().tolist() == [False, True, False]
    assert frame["chiacchio_mvie_ratio"].isna().tolist() == [False, True, False]
    assert frame["chiacchio_coverage"].notna().all()


def test_batched_dynamics_with_asymmetric_limits_and_motion_bias():
    rng = np.random.default_rng(4)
    K, m, n = 30, 3, 5
    J = rng.normal(size=(K, m, n))
    J[3] = np.outer(rng.normal(size=m), rng.normal(size=n))  # rank 1: singular
    B = np.array([random_spd(rng, n) for _ in range(K)])
    g = rng.normal(size=(K, n)) * 3
    bias = rng.normal(size=(K, m))
    dyn = pe.Dynamics(J, B, g, xdd_bias=bias)
    tau_max, tau_min = np.full(n, 5.0), np.array([-2.0, -5.0, -1.0, -4.0, -3.0])
    T = rng.normal(size=(20, m))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    frame = pe.sweep(dyn, tau_max=tau_max, tau_min=tau_min, directions=T, chunk=7)
    assert frame.loc[3, "polytope_dim"] == 1  # a rank-1 Jacobian: the scalar path
    assert (frame["chiacchio_directions_used"] < len(T)).any()  # lines that miss P
    assert_rows_equal_compare(frame, lambda k: dyn[k], tau_max, tau_min, T)


def test_chunking_does_not_change_the_rows():
    configurations = pe.random_configurations(50, [-1, -1, -1], [1, 1, 1], seed=2)
    np.testing.assert_array_equal(
        configurations.rows(10, 50),
        np.vstack([configurations.rows(10, 20), configurations.rows(20, 50)]),
    )
    a = pe.sweep(ARM, configurations, chunk=7)
    b = pe.sweep(ARM, configurations, chunk=50)
    pd.testing.assert_frame_equal(a, b)


def test_parquet_dataset_resumes_and_refuses_other_arguments(tmp_path):
    g = pe.grid(0.3, (-2, 2, 6), (-2, 2, 5))
    out = tmp_path / "sweep"
    assert pe.sweep(ARM, g, out=out, chunk=4) == out
    parts = sorted(out.glob("part-*.parquet"))
    assert len(parts) == 8
    expected = pe.sweep(ARM, g, chunk=4)
    pd.testing.assert_frame_equal(
        pd.read_parquet(out).sort_values("configuration").reset_index(drop=True), expected
    )
    kept = {p: p.stat().st_mtime_ns for p in parts[:5]}
    for p in parts[5:]:
        p.unlink()
    pe.sweep(ARM, g, out=out, chunk=4)
    assert {p: p.stat().st_mtime_ns for p in parts[:5]} == kept  # not recomputed
    assert len(list(out.glob("part-*.parquet"))) == 8
    with pytest.raises(pe.InputError, match=r"chunk: expected 4 .*pass chunk=4"):
        pe.sweep(ARM, g, out=out, chunk=5)  # the dataset's chunk size, named
    with pytest.raises(pe.InputError, match="holds a different sweep"):
        pe.sweep(ARM, g, out=out, chunk=4, directions=9)


def test_dask_local_cluster_on_loopback_gives_the_same_rows(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    g = pe.grid(np.pi / 2, (-2, 2, 8), (-2, 2, 8))
    expected = pe.sweep(ARM, g, chunk=10)
    threads = os.environ.get("OPENBLAS_NUM_THREADS")  # whatever the caller runs with
    with pe.local_cluster(2) as cluster, distributed.Client(cluster) as client:
        assert os.environ.get("OPENBLAS_NUM_THREADS") == threads  # restored after the spawns
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        environments = client.run(lambda: dict(os.environ)).values()
        assert len(environments) == 2
        for environment in environments:  # one BLAS thread, glibc's adaptive allocator
            assert environment["OPENBLAS_NUM_THREADS"] == "1"
            assert "MALLOC_TRIM_THRESHOLD_" not in environment
        frame = pe.sweep(ARM, g, chunk=10, scheduler=cluster.scheduler_address)
        pd.testing.assert_frame_equal(frame, expected)
        panda = pe.robots.load("panda")  # pickled to the workers by its arguments
        q = np.random.default_rng(1).uniform(-1, 1, (12, 7))
        out = pe.sweep(panda, q, chunk=5, scheduler=cluster.scheduler_address, out=tmp_path / "p")
        pd.testing.assert_frame_equal(
            pd.read_parquet(out).sort_values("configuration").reset_index(drop=True),
            pe.sweep(panda, q, chunk=5),
        )


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"configurations": None}, "configurations: expected a (K, n) array"),
        ({"scheduler": "threads"}, "scheduler: expected None, 'processes'"),
        ({"chunk": 0}, "chunk: expected an integer from 1"),
        ({"scores": ("coverage", "beauty")}, "scores: expected names among"),
        ({"scores": ("mvie_ratio",)}, "no 'mvie_ratio' without mvie=True"),
        ({"configurations": np.zeros((3, 2))}, "configurations: expected an array"),
        ({"directions": [[1.0, 1.0]]}, "unit direction vectors"),
    ],
)
def test_bad_sweeps(kwargs, fragment):
    arguments = {"configurations": np.zeros((2, 3))} | kwargs
    with pytest.raises(pe.InputError) as info:
        pe.sweep(ARM, **arguments)
    assert fragment in str(info.value)


@pytest.mark.parametrize("n_workers", [0, -1, 1.5, True])
def test_local_cluster_refuses_bad_worker_counts(n_workers):
    with pytest.raises(pe.InputError, match="n_workers: expected a positive number"):
        pe.local_cluster(n_workers)


def test_a_single_dynamics_is_not_a_batch():
    with pytest.raises(pe.InputError, match="a batched Dynamics"):
        pe.sweep(ARM.dynamics([0.1, 0.2, 0.3]), tau_max=ARM.tau_max)
    with pytest.raises(pe.InputError, match=r"call pe\.sweep for the whole batch"):
        pe.analyze(ARM.dynamics(np.zeros((2, 3))), ARM.tau_max)


@pytest.mark.parametrize("rank_rtol", [pe.RANK_RTOL, 1e-6])
def test_sweep_and_analyze_decide_the_same_rank_at_the_threshold(rank_rtol):
    """sigma_min / sigma_max of M from 1e-3 below to 1e-3 above the threshold (issue 15).

    M is built with its singular values in place and J = M B (unit limits), so both paths
    compute M = J B^-1 with rounding errors of their own.
    """
    rng = np.random.default_rng(11)
    side = np.geomspace(1e-3, 1e-9, 25)
    offsets = np.concatenate([-side, [0.0], side[::-1]])
    K, n = len(offsets), 3
    J, B = np.empty((K, 2, n)), np.empty((K, n, n))
    for k, offset in enumerate(offsets):
        U = np.linalg.qr(rng.normal(size=(2, 2)))[0]
        V = np.linalg.qr(rng.normal(size=(n, n)))[0][:, :2]
        B[k] = random_spd(rng, n, 1e3)
        J[k] = ((U * [2.0, 2.0 * rank_rtol * (1.0 + offset)]) @ V.T) @ B[k]
    dyn = pe.Dynamics(J, B, rng.normal(size=(K, n)))
    frame = pe.sweep(dyn, tau_max=np.ones(n), rank_rtol=rank_rtol, directions=16)
    ranks = [pe.analyze(dyn[k], np.ones(n), rank_rtol=rank_rtol).rank for k in range(K)]
    assert frame["polytope_dim"].tolist() == ranks
    assert ranks[:3] == [1] * 3 and ranks[-3:] == [2] * 3  # well inside either side


def thin_arm_batch(m: int, n: int, conds: np.ndarray, seed: int) -> pe.Dynamics:
    """Arms whose M = J B^-1 (unit limits) has singular values 1 .. 1/cond, geometric."""
    rng = np.random.default_rng(seed)
    K = len(conds)
    J, B = np.empty((K, m, n)), np.empty((K, n, n))
    for k, cond in enumerate(conds):
        U = np.linalg.qr(rng.normal(size=(m, m)))[0]
        V = np.linalg.qr(rng.normal(size=(n, n)))[0][:, :m]
        B[k] = random_spd(rng, n, 10.0)
        J[k] = ((U * np.geomspace(1.0, 1.0 / cond, m)) @ V.T) @ B[k]
    return pe.Dynamics(J, B, 0.1 * rng.normal(size=(K, n)))


@pytest.mark.parametrize(("m", "n"), [(2, 2), (3, 3), (2, 4), (3, 6)])
def test_sweep_rows_equal_compare_on_thin_arms(m, n):
    """Condition numbers 1e6 .. 1e9 of M, far above RANK_RTOL: every row is compare's.

    Both paths compute the same quantities of a thin set by different (backward-stable)
    routes, so they differ by at most about ``C eps cond`` with ``C = 10 m n`` (the bound of
    tests/geometry/test_thin_zonotopes.py), relative to ``max(1, |value|)`` (direction
    errors and coverages are fractions).  Square arms touch: both ellipsoids have an
    inscribed scale of exactly 1, within the rounding bound scores.scale_rtol (up to
    2e-5 at cond 1e9, far above INSIDE_RTOL = 1e-9), so the batch keeps them (no
    fallback to the scalar path) with coverage exact, as compare does.
    """
    conds = np.geomspace(1e6, 1e9, 7)
    dyn = thin_arm_batch(m, n, conds, seed=5)
    rng = np.random.default_rng(6)
    T = rng.normal(size=(16, m))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    tau_max = np.ones(n)
    frame = pe.sweep(dyn, tau_max=tau_max, directions=T)
    for k, cond in enumerate(conds):
        expected = pe.compare(pe.analyze(dyn[k], tau_max), T).to_row()
        tol = 10 * m * n * np.finfo(float).eps * cond
        for name in frame.columns.intersection(list(expected)):
            np.testing.assert_allclose(
                frame.loc[k, name], expected[name], rtol=tol, atol=tol, err_msg=f"{name} at {k}"
            )
    if m == n:
        _, scalar = batch_rows(dyn, tau_max, -tau_max, T)
        assert not scalar.any()
        for kind in ("chiacchio", "yoshikawa"):
            assert (frame[f"{kind}_coverage_stderr"] == 0.0).all()
            assert (frame[f"{kind}_overreach"] == 0.0).all()


@pytest.mark.parametrize("n", [3, 7])
def test_classic_witness_keeps_its_digits_when_torques_are_weak_against_gravity(n):
    """Gravity torques 1e7 times the limits: xg is 1e7 times the polytope's size.

    The classic witness at the centre is the null-space part of the free fall, 0 for a
    non-redundant arm (n = 3); written as ``F xg + offset`` it would carry an error of about
    ``n eps |F xg|`` ~ 1e7 n eps ~ 1e-8 of the witness (size 1), 10 times the 1e-9 of
    assert_rows_equal_compare; about xg both paths agree to a few eps times the
    conditioning of J, B (condition numbers below 1e2 here).
    """
    rng = np.random.default_rng(8)
    K, m = 12, 3
    J = rng.normal(size=(K, m, n))
    B = np.array([random_spd(rng, n, 10.0) for _ in range(K)])
    g = 1e7 * rng.normal(size=(K, n))
    dyn = pe.Dynamics(J, B, g)
    tau_max = np.ones(n)
    frame = pe.sweep(dyn, tau_max=tau_max, directions=16)
    assert (frame["polytope_dim"] == m).all()
    assert_rows_equal_compare(frame, lambda k: dyn[k], tau_max, -tau_max, 16)
    if n == m:  # E = xg + F^-1 (unit ball): every row of F U diag(s) has norm 1, the witness 1
        np.testing.assert_allclose(frame["yoshikawa_witness_torque_max"], 1.0, rtol=1e-9)


@pytest.mark.parametrize("rank_rtol", ["1e-10", None, -1e-10, 1.0, 1.5, np.nan, np.inf, True])
def test_sweep_refuses_a_bad_rank_rtol(rank_rtol):
    """A relative tolerance in [0, 1), as analyze and limits_along take it (check_fraction)."""
    with pytest.raises(pe.InputError, match="rank_rtol"):
        pe.sweep(ARM, np.zeros((2, 3)), rank_rtol=rank_rtol)


def test_the_rows_left_to_compare_are_counted_in_the_log(caplog, tmp_path):
    g = pe.grid(np.pi / 2, (-np.pi, np.pi, 5), (-np.pi, np.pi, 5))
    with caplog.at_level("INFO", logger="polyell"):
        frame = pe.sweep(ARM, g, directions=8)
        pe.sweep(ARM, g, directions=8, out=tmp_path / "d", chunk=7)
    singular = int((frame["polytope_dim"] < 2).sum())
    assert singular > 0 and frame["per_row"].sum() == singular
    note = f"acceleration: {singular} of 25 rows per row ({100 * singular / 25:.2f} %)"
    messages = [r.getMessage().split(" into ")[0] for r in caplog.records]
    assert messages == [f"note: sweep of {note}"] * 2


def test_a_candidate_crossing_the_zonotope_is_estimated_in_the_batch_as_compare_does():
    # With the vertices enumerated (enclosing_scale), a candidate neither inside nor around
    # P is estimated in the batch: the same points as compare (its axes kept as Ellipsoid
    # keeps them), so the same shares and standard errors.
    rng = np.random.default_rng(12)
    J, g, limit = rng.normal(size=(6, 3, 6)), rng.normal(size=(6, 6)), np.full(6, 3.0)
    dyn = pe.Dynamics(J, np.broadcast_to(np.eye(6), (6, 6, 6)).copy(), g)
    rotated = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    candidates = [
        pe.Candidate("tilted", core=rotated @ np.diag([1 / 144, 1 / 36, 1 / 400]) @ rotated.T),
        pe.Candidate("weighted", weighting=np.diag(rng.uniform(0.3, 3.0, 6))),
    ]
    scores = [s for s in pe.SCORE_NAMES if s not in ("mvie_ratio", "outer_ratio")]
    frame = pe.sweep(dyn, tau_max=limit, candidates=candidates, directions=16, scores=scores)
    assert not frame["per_row"].any()
    estimated = 0
    for k in range(len(J)):
        row = pe.compare(
            pe.analyze(dyn[k], limit), 16, mvie=False, outer=False, candidates=candidates
        ).to_row()
        estimated += row["tilted_coverage_stderr"] > 0
        for name in ("coverage", "overreach", "coverage_stderr", "enclosing_scale"):
            for kind in ("tilted", "weighted"):
                column = f"{kind}_{name}"
                assert frame[column][k] == pytest.approx(row[column], rel=1e-12, abs=1e-15)
    assert estimated > 0


def test_the_default_scores_follow_the_optima_computed():
    # Found by the independent check: mvie=True, outer=True gave no ratio columns unless
    # scores named them (the README says mvie=True adds every mvie_ratio).
    q = np.random.default_rng(0).uniform(-3.0, 3.0, (3, 3))
    both = pe.sweep(ARM, q, mvie=True, outer=True, directions=8)
    assert {"chiacchio_mvie_ratio", "yoshikawa_outer_ratio", "mvie_outer_ratio"} <= set(both)
    neither = pe.sweep(ARM, q, directions=8)
    assert not [c for c in neither.columns if c.endswith(("_mvie_ratio", "_outer_ratio"))]
    assert "chiacchio_enclosing_scale" not in both  # a vertex enumeration: asked for by name


def test_a_weighted_candidate_in_a_force_sweep_is_said_and_nan():
    """A torque weighting defines no force ellipsoid: compare reports it undefined, the
    sweep warns (naming it) and leaves its columns NaN; a core-defined one is scored."""
    arm = pe.robots.load("chiacchio2000")
    weighted = pe.Candidate("wrist", weighting=np.diag([1.0, 1.0, 4.0]))
    core = pe.Candidate("disc", core=np.eye(2) * 1e-4)
    q = np.array([[0.3, 0.6, 0.9], [0.5, 0.2, 0.1]])
    with pytest.warns(pe.PolyellWarning, match=r"candidates \['wrist'\]: a weighting"):
        frame = pe.sweep(arm, q, capacity="force", candidates=[weighted, core])
    assert frame.filter(like="wrist_").drop(columns=["wrist_directions_used",
               "wrist_feasibility_mismatch"]).isna().all(axis=None)  # fmt: skip
    assert frame["disc_inscribed_scale"].notna().all()
    analysis = pe.analyze(arm.dynamics(q[0]), arm.tau_max, capacity="force")
    assert not pe.compare(analysis, candidates=[weighted])["wrist"].defined
    with warnings.catch_warnings():
        warnings.simplefilter("error", pe.PolyellWarning)
        pe.sweep(arm, q, candidates=[weighted])  # accelerations: defined, no warning


def test_the_per_row_note_of_a_dataset_is_counted_part_by_part(tmp_path):
    """The note of a sweep written to Parquet counts its parts one at a time (the whole
    column of 10^7 rows cost 180 MiB at once): the same note as the frame read whole."""
    from polyell.studies.sweep import per_row_note

    arm = pe.robots.load("chiacchio2000")
    q = np.array([[0.3, 0.6, 0.9], [0.3, 0.0, 0.0], [0.5, 0.2, 0.1], [0.1, 0.0, 0.0]])
    folder = pe.sweep(arm, q, out=tmp_path / "results", chunk=1, directions=16)
    frame = pd.read_parquet(folder)
    assert frame["per_row"].sum() == 2  # the two singular configurations
    assert per_row_note(folder, "acceleration") == per_row_note(frame, "acceleration")
    assert per_row_note(folder, "acceleration") == "acceleration: 2 of 4 rows per row (50.00 %)"


def test_named_directions_as_compare_reads_them():
    """``directions=["x", "y"]`` (its docstring: exactly as compare takes it) gives the rows
    of the unit vectors and of compare with the same names (it was refused)."""
    arm = pe.robots.load("chiacchio2000")
    q = np.array([[0.1, 0.2, 0.3], [0.5, 0.2, -0.4]])
    named = pe.sweep(arm, q, directions=["x", "y"])
    vectors = pe.sweep(arm, q, directions=np.eye(2))
    pd.testing.assert_frame_equal(named, vectors)
    row = pe.compare(pe.analyze(arm.dynamics(q[1]), arm.tau_max), ["x", "y"], mvie=False,
                     outer=False).to_row()  # fmt: skip
    assert named.loc[1, "chiacchio_direction_error_mean"] == pytest.approx(
        row["chiacchio_direction_error_mean"], rel=1e-12
    )
