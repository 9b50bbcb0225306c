"""pe.sweep over the velocity and force capacities: every row equals compare() of its own.

Velocities go through the batch path (the zonotope of an arm with B = I, no gravity and
the velocity limits as torque limits), forces through their own
(:mod:`polyell.studies.force_batch`); both are compared column by column with
``pe.compare(pe.analyze(..., capacity=...)).to_row()`` at 1e-12 (relative to the value or
1; the columns of a force set's volume to ten times ``VOLUME_RTOL``, the bound of its two
evaluations by Lawrence's formula) on 2x4, 3x7 and 6x7 arms, weak and strong gravity,
asymmetric limits, singular rows and an empty force set mixed in; the Parquet dataset
records its capacity and is not resumed with another.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.capacities import capacity_class
from polyell.studies.batch import score_columns
from polyell.studies.force_batch import VOLUME_RTOL
from reference import random_spd

ARM = pe.robots.load("chiacchio2000")
#: Columns computed from the polytope's volume.
VOLUME_COLUMNS = ("polytope_volume", "_coverage", "_coverage_stderr", "_overreach")


def batch(
    seed: int, K: int, m: int, n: int, gravity: float = 0.05
) -> tuple[pe.Dynamics, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(K, m, n))
    J[1] = np.outer(rng.normal(size=m), rng.normal(size=n))  # a singular row (rank 1)
    B = np.stack([random_spd(rng, n) for _ in range(K)])
    g = gravity * rng.normal(size=(K, n))
    upper = rng.uniform(1.0, 3.0, n)
    lower = -upper * rng.uniform(0.7, 1.0, n)
    return pe.Dynamics(J, B, g), upper, lower


def assert_rows_equal(frame, analyses, directions: int, samples: int = 2**13) -> None:
    for k, an in enumerate(analyses):
        row = pe.compare(an, directions, samples=samples, mvie=False, outer=False).to_row()
        for name in frame.columns:
            if name in ("configuration", "per_row"):
                continue
            value, expected = frame.loc[k, name], row[name]
            if not np.isfinite(expected):  # NaN (undefined) or inf (an unbounded set)
                assert value == expected or (np.isnan(value) and np.isnan(expected)), (k, name)
                continue
            scale = abs(expected) if "radius" in name else max(1.0, abs(expected))
            # the force path's volume (Lawrence's formula, its two evaluations agreeing to
            # VOLUME_RTOL) against Qhull's: the columns it enters to ten times that
            rtol = 10 * VOLUME_RTOL if name.endswith(VOLUME_COLUMNS) else 1e-12
            assert abs(value - expected) <= rtol * max(scale, 1e-300), (k, name, value, expected)


@pytest.mark.parametrize(("m", "n"), [(2, 4), (3, 7), (6, 7)])
def test_velocity_sweep_equals_compare(m, n):
    dyn, upper, lower = batch(m + n, 12, m, n)
    frame = pe.sweep(dyn, capacity="velocity", qd_max=upper, qd_min=lower, directions=48)
    assert [c for c in frame.columns if c.endswith("_coverage")] == ["yoshikawa_coverage"]
    analyses = [
        pe.analyze(pe.Kinematics(dyn.J[k]), capacity="velocity", qd_max=upper, qd_min=lower)
        for k in range(len(dyn))
    ]
    assert analyses[1].is_singular
    assert_rows_equal(frame, analyses, 48)


@pytest.mark.parametrize(("m", "n", "gravity"), [(2, 4, 0.05), (3, 7, 0.05), (6, 7, 0.8)])
def test_force_sweep_equals_compare(m, n, gravity):
    dyn, upper, lower = batch(10 + m + n, 6, m, n, gravity)
    frame = pe.sweep(
        dyn, tau_max=upper, tau_min=lower, capacity="force", directions=48, samples=256
    )
    assert "static_coverage" in frame.columns
    analyses = [pe.analyze(dyn[k], upper, lower, capacity="force") for k in range(len(dyn))]
    assert not analyses[1].polytope.is_bounded  # the singular row: unbounded, undefined
    assert frame.loc[1, "polytope_volume"] == np.inf and np.isnan(frame.loc[1, "static_coverage"])
    assert_rows_equal(frame, analyses, 48, samples=256)


def test_robot_velocity_limits_are_the_default_and_limits_are_checked(tmp_path):
    Q = pe.random_configurations(ARM, 8, seed=2)
    frame = pe.sweep(ARM, Q, capacity="velocity", directions=16)
    an = pe.analyze(ARM.dynamics(np.asarray(Q)[5]), capacity="velocity", qd_max=ARM.qd_max)
    expected = pe.compare(an, 16, mvie=False, outer=False)["yoshikawa"].coverage
    assert frame.loc[5, "yoshikawa_coverage"] == pytest.approx(expected, rel=1e-12)
    with pytest.raises(pe.InputError, match="tau_max: expected no torque limits"):
        pe.sweep(ARM, Q, ARM.tau_max, capacity="velocity")
    with pytest.raises(pe.InputError, match="qd_max: expected no joint velocity limits"):
        pe.sweep(ARM, Q, qd_max=ARM.qd_max)
    with pytest.raises(pe.InputError, match="did you mean 'velocity'"):
        pe.sweep(ARM, Q, capacity="velocities")
    dyn, _, _ = batch(1, 3, 2, 3)
    with pytest.raises(pe.InputError, match="qd_max: expected joint velocity limits"):
        pe.sweep(dyn, capacity="velocity")


def test_a_dataset_is_not_resumed_with_another_capacity(tmp_path):
    Q = pe.random_configurations(ARM, 6, seed=3)
    out = tmp_path / "sweep"
    pe.sweep(ARM, Q, capacity="velocity", directions=16, out=out, chunk=3)
    import pandas as pd

    frame = pd.read_parquet(out)
    assert "yoshikawa_coverage" in frame.columns and "chiacchio_coverage" not in frame.columns
    with pytest.raises(pe.PolyellError):
        pe.sweep(ARM, Q, capacity="force", directions=16, out=out, chunk=3)


def test_force_sweep_with_an_empty_set_equals_compare():
    # Row 2: a joint no task force loads (a zero column of J) whose gravity torque exceeds
    # its limit, so no force holds the arm: the force set is empty and every score undefined.
    dyn, upper, lower = batch(31, 4, 3, 7, gravity=0.05)
    J, g = dyn.J.copy(), dyn.g.copy()
    J[2][:, 3] = 0.0
    g[2][3] = 2.0 * upper[3]
    dyn = pe.Dynamics(J, dyn.B, g)
    analyses = [pe.analyze(dyn[k], upper, lower, capacity="force") for k in range(len(dyn))]
    assert analyses[2].polytope.is_empty and not analyses[0].polytope.is_empty
    frame = pe.sweep(
        dyn, tau_max=upper, tau_min=lower, capacity="force", directions=32, samples=128
    )
    assert frame.loc[2, "polytope_volume"] == 0.0 and np.isnan(frame.loc[2, "chiacchio_volume"])
    assert_rows_equal(frame, analyses, 32, samples=128)


@pytest.mark.parametrize("capacity", ["velocity", "force"])
def test_dataset_round_trips_with_its_capacity(tmp_path, capacity):
    import json

    import pandas as pd

    Q = pe.random_configurations(ARM, 7, seed=4)
    out = tmp_path / capacity
    written = pe.sweep(ARM, Q, capacity=capacity, directions=16, samples=64, out=out, chunk=3)
    frame = pe.sweep(ARM, Q, capacity=capacity, directions=16, samples=64)
    assert json.loads((written / "_sweep.json").read_text())["capacity"] == capacity
    stored = pd.read_parquet(written).sort_values("configuration").reset_index(drop=True)
    assert list(stored.columns) == list(frame.columns)
    scores = [c for c in frame.columns if c not in ("configuration", "per_row", "q1", "q2", "q3")]
    assert set(scores) <= set(score_columns((), capacity))
    assert {f"{k}_coverage" for k in capacity_class(capacity).ellipsoid_kinds} <= set(scores)
    pd.testing.assert_frame_equal(stored, frame, check_exact=True)
    # resumed with the same capacity and arguments: accepted
    assert pe.sweep(ARM, Q, capacity=capacity, directions=16, samples=64, out=out, chunk=3)
    other = "acceleration" if capacity == "force" else "force"
    with pytest.raises(pe.InputError, match=f"holds the {capacity} capacity.s sweep"):
        pe.sweep(ARM, Q, capacity=other, directions=16, samples=64, out=out, chunk=3)


def test_score_columns_follow_the_capacity():
    kinds = {
        capacity: {c.split("_")[0] for c in score_columns((), capacity) if "_" in c}
        for capacity in pe.CAPACITIES
    }
    assert kinds["force"] == {"polytope", "chiacchio", "yoshikawa", "static", "mvie", "outer"}
    assert kinds["velocity"] == {"polytope", "yoshikawa", "mvie", "outer"}
    assert kinds["acceleration"] == {"polytope", "chiacchio", "yoshikawa", "mvie", "outer"}
    with pytest.raises(pe.InputError, match="did you mean 'force'"):
        score_columns((), "forces")
