"""``sweep(..., horizon=)``: every row equals ``compare(robot.analyze(q, qd, horizon=))``."""

from __future__ import annotations

import logging

import numpy as np
import pytest

import polyell as pe
from polyell.errors import InputError
from polyell.studies.trajectory import Trajectory


def _approach(K=12):
    """The Panda's elbow driven towards its upper limit, slowing down."""
    panda = pe.robots.load("panda")
    q_max = panda.position_limits[1]
    q = np.tile([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8], (K, 1))
    q[:, 3] = q_max[3] - np.geomspace(0.5, 1e-4, K)
    qd = np.zeros((K, 7))
    qd[:, 3] = np.linspace(1.0, 0.2, K)
    return panda, Trajectory(q, qd)


def test_rows_equal_compare_along_a_path(caplog):
    panda, path = _approach()
    with caplog.at_level(logging.INFO, logger="polyell"):
        frame = pe.sweep(panda, path, horizon=0.01, directions=64)
    assert frame["per_row"].sum() >= 6 and "per row" in caplog.text.replace("-", " ")
    for k in range(len(path)):
        analysis = panda.analyze(path.q[k], path.qd[k], horizon=0.01)
        row = pe.compare(analysis, 64).to_row()
        for column in ("polytope_volume", "chiacchio_inscribed_scale", "yoshikawa_coverage"):
            np.testing.assert_allclose(frame[column][k], row[column], rtol=1e-12, equal_nan=True)
    # the set shrinks towards the limit; the ellipsoids do not know it
    volume = frame["polytope_volume"].to_numpy()
    assert volume[-1] < 0.75 * volume[0]


def test_without_a_cut_the_rows_are_the_sweep_without_horizon():
    panda = pe.robots.load("panda")
    q = pe.random_configurations(panda, 30, seed=3).rows(0, 30)
    q[:, 6] = 0.0  # (nothing near a limit)
    plain = pe.sweep(panda, q, directions=64)
    within = pe.sweep(panda, q, horizon=1e-3, q_min=q.min(0) - 1e3, q_max=q.max(0) + 1e3,
                      qd_max=np.full(7, 1e7), directions=64)  # fmt: skip
    assert not within["per_row"].any()
    columns = [c for c in plain.columns if c != "per_row"]
    np.testing.assert_array_equal(within[columns].to_numpy(), plain[columns].to_numpy())


def test_bad_input():
    panda, path = _approach(3)
    with pytest.raises(InputError) as error:
        pe.sweep(panda.dynamics(path.q), horizon=0.01)
    assert error.value.argument == "source"
    with pytest.raises(InputError) as error:
        pe.sweep(panda, path, horizon=0.01, capacity="velocity")
    assert error.value.argument == "horizon"
    with pytest.raises(InputError) as error:
        pe.sweep(panda, path, horizon=0.0)
    assert error.value.argument == "horizon"


def test_a_set_no_solver_builds_is_a_nan_row_and_a_warning(monkeypatch, caplog):
    """A SolverError in one cut row (a 6-D set with thousands of vertices) leaves that row
    NaN and names it in the log; the other rows are computed as before."""
    from polyell.capacities import horizon

    panda, path = _approach(4)
    expected = pe.sweep(panda, path, horizon=0.01, directions=16)
    built = horizon.cut_set
    calls = []

    def failing_once(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise pe.SolverError("the hull did not close (test)")
        return built(*args, **kwargs)

    monkeypatch.setattr(horizon, "cut_set", failing_once)
    with caplog.at_level(logging.WARNING, logger="polyell"):
        frame = pe.sweep(panda, path, horizon=0.01, directions=16)
    scores = [c for c in frame.columns if c.startswith(("polytope_", "chiacchio_", "yoshikawa_"))]
    failed = frame["polytope_dim"].isna().to_numpy()
    assert failed.sum() == 1 and frame.loc[failed, scores].isna().all(axis=None)
    k = int(np.flatnonzero(failed)[0])
    assert f"configuration {k}: every score NaN" in caplog.text and "(test)" in caplog.text
    np.testing.assert_array_equal(
        frame.loc[~failed, scores].to_numpy(), expected.loc[~failed, scores].to_numpy()
    )
