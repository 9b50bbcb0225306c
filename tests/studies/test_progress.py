"""The progress bar of pe.sweep: per configuration, named, absent when nothing is left."""

from __future__ import annotations

import sys
from typing import ClassVar

import numpy as np
import pytest

import polyell as pe

ARM = pe.robots.load("chiacchio2000")
GRID = pe.grid(0.3, (-2.5, 2.5, 6), (-2.5, 2.5, 5))  # 30 configurations
FAST = {"directions": 8}


class Recorder:
    """Stands in for tqdm: records the bar's arguments and its updates."""

    bars: ClassVar[list[Recorder]] = []

    def __init__(self, **kwargs):
        self.kwargs = kwargs
        self.updates: list[int] = []
        Recorder.bars.append(self)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def update(self, n=1):
        self.updates.append(n)


@pytest.fixture
def bars(monkeypatch):
    Recorder.bars = []
    monkeypatch.setattr(sys.modules["polyell.studies.sweep"], "tqdm", Recorder)
    return Recorder.bars


def test_the_bar_counts_configurations_advanced_by_each_chunk(bars):
    pe.sweep(ARM, GRID, chunk=7, progress=True, **FAST)
    (bar,) = bars
    assert bar.kwargs["total"] == 30 and bar.kwargs["initial"] == 0
    assert bar.updates == [7, 7, 7, 7, 2]
    assert bar.kwargs["desc"] == "acceleration" and not bar.kwargs["disable"]
    assert bar.kwargs["unit"].strip() == "configurations"


@pytest.mark.parametrize("capacity", ["velocity", "force"])
def test_the_bar_names_the_capacity(bars, capacity):
    pe.sweep(ARM, GRID, chunk=10, progress=True, capacity=capacity, **FAST)
    assert [bar.kwargs["desc"] for bar in bars] == [capacity]


def test_a_resumed_dataset_starts_the_bar_at_what_is_done(bars, tmp_path):
    out = tmp_path / "d"
    pe.sweep(ARM, GRID, chunk=7, out=out, **FAST)
    (out / "part-000001.parquet").unlink()
    (out / "part-000004.parquet").unlink()  # the last, short chunk
    pe.sweep(ARM, GRID, chunk=7, out=out, progress=True, **FAST)
    bar = bars[-1]
    assert bar.kwargs["total"] == 30 and bar.kwargs["initial"] == 30 - 7 - 2
    assert sorted(bar.updates) == [2, 7] and not bar.kwargs["disable"]


def test_a_finished_dataset_shows_no_bar(tmp_path, capfd):
    out = tmp_path / "d"
    pe.sweep(ARM, GRID, chunk=7, out=out, **FAST)
    capfd.readouterr()
    pe.sweep(ARM, GRID, chunk=7, out=out, progress=True, **FAST)
    assert capfd.readouterr().err == ""


def test_the_real_bar_says_the_capacity_and_the_configurations(capfd):
    pe.sweep(ARM, GRID, chunk=7, progress=True, capacity="velocity", **FAST)
    err = capfd.readouterr().err
    assert "velocity" in err and "30/30" in err and "configurations/s" in err
    assert "chunk" not in err


def test_several_robots_name_each_bar(bars, tmp_path):
    robots = {"left": ARM, "right": ARM}
    pe.sweep(robots, GRID, chunk=10, progress=True, capacity="force", **FAST)
    assert [bar.kwargs["desc"] for bar in bars] == ["left force", "right force"]
    pe.sweep(robots, GRID, chunk=10, progress=True, out=tmp_path / "d", **FAST)
    assert [bar.kwargs["desc"] for bar in bars[2:]] == ["left acceleration", "right acceleration"]


def test_a_dataset_of_one_robot_among_several_names_it(bars, tmp_path):
    # polyell study writes each robot's dataset to robot=<name>/ with one sweep each
    pe.sweep(ARM, GRID, chunk=10, progress=True, out=tmp_path / "robot=ur5", **FAST)
    assert [bar.kwargs["desc"] for bar in bars] == ["ur5 acceleration"]


def test_without_progress_the_bar_is_disabled(bars):
    pe.sweep(ARM, GRID, chunk=10, **FAST)
    assert [bar.kwargs["disable"] for bar in bars] == [True]


def test_a_large_sweep_scales_the_counts(bars):
    module = sys.modules["polyell.studies.sweep"]
    dynamics = ARM.dynamics(np.zeros((10_000, 3)))
    job = module._job(dynamics, None, ARM.tau_max, None, ("coverage",), 8, module.BatchOptions())
    module._progress_bar(job, [0], 10_000, True, "")
    small = module._job(dynamics[:30], None, ARM.tau_max, None, ("coverage",), 8, job.options)
    module._progress_bar(small, [0], 30, True, "")
    # 46.6k/200k rather than 46600/200000; but 30/30, not 30.0/30.0
    assert [bar.kwargs["unit_scale"] for bar in bars] == [True, False]


def test_a_dask_sweep_advances_the_bar_by_each_chunk(bars):
    distributed = pytest.importorskip("distributed")
    with pe.local_cluster(1) as cluster, distributed.Client(cluster):
        pe.sweep(ARM, GRID, chunk=7, progress=True, scheduler=cluster.scheduler_address, **FAST)
    (bar,) = bars
    assert bar.kwargs["total"] == 30 and sorted(bar.updates) == [2, 7, 7, 7, 7]
