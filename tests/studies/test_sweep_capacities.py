"""pe.sweep over the velocity and force capacities: every row equals compare() of its own.

Velocities go through the batch path (the zonotope of an arm with B = I, no gravity and
the velocity limits as torque limits), forces through the scalar path; both are compared
column by column with ``pe.compare(pe.analyze(..., capacity=...)).to_row()`` at 1e-12
(relative for volumes and radii), singular rows mixed in.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from reference import random_spd

ARM = pe.robots.load("chiacchio2000")


def batch(seed: int, K: int, m: int, n: int) -> tuple[pe.Dynamics, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(K, m, n))
    J[1] = np.outer(rng.normal(size=m), rng.normal(size=n))  # a singular row (rank 1)
    B = np.stack([random_spd(rng, n) for _ in range(K)])
    g = 0.05 * rng.normal(size=(K, n))
    upper = rng.uniform(1.0, 3.0, n)
    lower = -upper * rng.uniform(0.7, 1.0, n)
    return pe.Dynamics(J, B, g), upper, lower


def assert_rows_equal(frame, analyses, directions: int, samples: int = 2**13) -> None:
    for k, an in enumerate(analyses):
        row = pe.compare(an, directions, samples=samples, mvie=False, outer=False).to_row()
        for name in frame.columns:
            if name == "configuration":
                continue
            value, expected = frame.loc[k, name], row[name]
            if not np.isfinite(expected):  # NaN (undefined) or inf (an unbounded set)
                assert value == expected or (np.isnan(value) and np.isnan(expected)), (k, name)
                continue
            scale = abs(expected) if ("volume" in name or "radius" in name) else 1.0
            assert abs(value - expected) <= 1e-12 * max(scale, 1e-300), (k, name, value, expected)


@pytest.mark.parametrize(("m", "n"), [(2, 4), (3, 7)])
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


@pytest.mark.parametrize(("m", "n"), [(2, 4), (3, 7)])
def test_force_sweep_equals_compare(m, n):
    dyn, upper, lower = batch(10 + m + n, 6, m, n)
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
