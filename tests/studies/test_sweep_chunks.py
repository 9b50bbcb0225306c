"""Chunk sizes of pe.sweep: sized by time, recorded, resumed, older datasets kept."""

from __future__ import annotations

import json
import sys
import warnings

import numpy as np
import pandas as pd
import pytest

import polyell as pe

ARM = pe.robots.load("chiacchio2000")
GRID = pe.grid(0.3, (-2.5, 2.5, 6), (-2.5, 2.5, 5))  # 30 configurations
FAST = {"directions": 8}
sweep_module = sys.modules["polyell.studies.sweep"]
OPTIONS = sweep_module.BatchOptions()


def record(out) -> dict:
    return json.loads((out / "_sweep.json").read_text())


def read(out) -> pd.DataFrame:
    return pd.read_parquet(out).sort_values("configuration").reset_index(drop=True)


@pytest.mark.parametrize(
    ("seconds", "chunk"),
    [
        (0.0, 20_000),  # a clock too coarse to see the pilot
        (1e-6, 20_000),  # at most MAX_CHUNK
        (55e-6, 20_000),
        (103e-6, 19_000),  # 19,417 down to two digits
        (300e-6, 6_600),
        (2.0 / 12_345, 12_000),
        (0.021, 95),
        (1.5, 1),
        (100.0, 1),  # never fewer than one
    ],
)
def test_chunk_for_takes_about_chunk_seconds(seconds, chunk):
    assert sweep_module.CHUNK_SECONDS == 2.0 and sweep_module.MAX_CHUNK == 20_000
    assert sweep_module.chunk_for(seconds) == chunk


class FakeClock:
    """A clock advanced by the fake chunks: ``cost`` seconds per configuration, plus
    ``overhead`` seconds per call."""

    def __init__(self, cost, overhead=0.0):
        self.now, self.cost, self.overhead, self.calls = 0.0, cost, overhead, []

    def perf_counter(self):
        return self.now

    def chunk(self, start, stop):
        self.calls.append((start, stop))
        self.now += self.overhead + self.cost * (stop - start)
        warnings.warn("a slip in the pilot", UserWarning, stacklevel=1)


@pytest.mark.parametrize(
    ("cost", "overhead", "calls", "chunk"),
    [
        (1e-3, 0.0, [16, 16, 64, 256], 2_000),  # 256 rows take 0.256 s >= 0.1 s
        (0.02, 0.0, [16, 16], 100),  # 16 rows take 0.32 s
        (1e-6, 0.0, [16, 16], 20_000),  # 16 rows already give the largest chunk
        (2e-4, 0.0, [16, 16, 64, 256, 1024], 10_000),  # 1024 rows take 0.2 s
        # 8 ms per call: 16 rows seem to take 0.55 ms each; from 16 and 64 rows, 50 us
        # and 8 ms per block of 512 rows: 66 us, the largest chunk
        (5e-5, 0.008, [16, 16, 64], 20_000),
        # the MVIE's solver, a large cost per block: 0.05 s per call and 0.2 ms per row;
        # 16 and 64 rows take 0.0532 s and 0.0628 s: 0.2 + 50 / 512 ms per row
        (2e-4, 0.05, [16, 16, 64, 256], 6_700),
        (2e-4, 0.1, [16, 16], 310),  # 16 rows take 0.1032 s: their average, 6.45 ms
    ],
)
def test_the_pilot_times_the_first_rows_after_a_warm_up(monkeypatch, cost, overhead, calls, chunk):
    clock = FakeClock(cost, overhead)
    monkeypatch.setattr(sweep_module.time, "perf_counter", clock.perf_counter)
    monkeypatch.setattr(sweep_module._Job, "chunk", lambda job, *rows: clock.chunk(*rows))
    job = sweep_module._job(ARM, np.zeros((100_000, 3)), None, None, ("coverage",), 8, OPTIONS)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the pilot's warnings are the first chunk's to give
        assert sweep_module._automatic_chunk(job) == chunk
    assert clock.calls == [(0, rows) for rows in calls]


def test_a_small_sweep_is_one_chunk_without_a_pilot(monkeypatch, tmp_path):
    def no_pilot(*args):
        raise AssertionError("no pilot for 16 configurations or fewer")

    q = np.asarray(GRID)[:16]
    monkeypatch.setattr(sweep_module.time, "perf_counter", no_pilot)
    job = sweep_module._job(ARM, q, None, None, ("coverage",), 8, OPTIONS)
    assert sweep_module._automatic_chunk(job) == 16
    pe.sweep(ARM, q, out=tmp_path / "d", **FAST)
    assert record(tmp_path / "d")["chunk"] == 16 and record(tmp_path / "d")["chunks"] == 1


def test_the_pilot_of_a_small_sweep_stops_once_it_is_one_chunk(monkeypatch):
    clock = FakeClock(2e-4)
    monkeypatch.setattr(sweep_module.time, "perf_counter", clock.perf_counter)
    monkeypatch.setattr(sweep_module._Job, "chunk", lambda job, *rows: clock.chunk(*rows))
    job = sweep_module._job(ARM, np.zeros((100, 3)), None, None, ("coverage",), 8, OPTIONS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert sweep_module._automatic_chunk(job) == 10_000  # 100 configurations: one chunk
    assert clock.calls == [(0, 16), (0, 16)]
    clock = FakeClock(0.01)  # 16 rows take 0.16 s: 2 s are 200 configurations
    monkeypatch.setattr(sweep_module.time, "perf_counter", clock.perf_counter)
    job = sweep_module._job(ARM, np.zeros((300, 3)), None, None, ("coverage",), 8, OPTIONS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert sweep_module._automatic_chunk(job) == 200
    assert clock.calls == [(0, 16), (0, 16)]


def test_an_automatic_chunk_is_recorded_and_gives_the_same_rows(monkeypatch, tmp_path):
    monkeypatch.setattr(sweep_module, "_automatic_chunk", lambda job: 7)
    out = pe.sweep(ARM, GRID, out=tmp_path / "d", **FAST)
    assert record(out)["chunk"] == 7 and record(out)["chunks"] == 5
    assert len(list(out.glob("part-*.parquet"))) == 5
    expected = pe.sweep(ARM, GRID, chunk=30, **FAST)
    pd.testing.assert_frame_equal(read(out), expected, check_dtype=False)
    frame = pe.sweep(ARM, GRID, progress=True, **FAST)  # in memory: the same rows in 7s
    pd.testing.assert_frame_equal(frame, expected)


def test_in_memory_without_a_bar_there_is_no_pilot(monkeypatch):
    def no_pilot(job):
        raise AssertionError("no pilot: the chunks' time matters to a bar or Dask only")

    monkeypatch.setattr(sweep_module, "_automatic_chunk", no_pilot)
    chunks = []
    compute = sweep_module._Job.chunk
    monkeypatch.setattr(
        sweep_module._Job, "chunk", lambda job, *rows: chunks.append(rows) or compute(job, *rows)
    )
    pe.sweep(ARM, GRID, **FAST)
    assert chunks == [(0, 30)]


def test_a_dataset_resumes_in_its_own_chunks(monkeypatch, tmp_path):
    monkeypatch.setattr(sweep_module, "_automatic_chunk", lambda job: 7)
    out = pe.sweep(ARM, GRID, out=tmp_path / "d", **FAST)
    expected = read(out)
    (out / "part-000002.parquet").unlink()

    def other_machine(job):
        raise AssertionError("a dataset's chunk size is its own, not this machine's")

    monkeypatch.setattr(sweep_module, "_automatic_chunk", other_machine)
    pe.sweep(ARM, GRID, out=out, **FAST)  # chunk=None: the dataset's 7
    pe.sweep(ARM, GRID, out=out, chunk=7, **FAST)  # the same, explicitly
    pd.testing.assert_frame_equal(read(out), expected)


def test_an_explicit_chunk_other_than_the_datasets_is_refused_naming_it(tmp_path):
    out = pe.sweep(ARM, GRID, chunk=7, out=tmp_path / "d", **FAST)
    with pytest.raises(pe.InputError, match=r"chunk: expected 7 .*got 10.*pass chunk=7") as info:
        pe.sweep(ARM, GRID, chunk=10, out=out, **FAST)
    assert info.value.argument == "chunk"
    with pytest.raises(pe.InputError, match="holds a different sweep"):  # not the chunk
        pe.sweep(ARM, GRID, chunk=10, out=out, directions=9)


def legacy(out):
    """Make a dataset look like one of the versions that did not record the chunk size."""
    meta = record(out)
    del meta["chunk"]
    (out / "_sweep.json").write_text(json.dumps(meta, indent=2) + "\n")


def test_a_dataset_of_the_old_default_chunk_resumes(monkeypatch, tmp_path):
    q = pe.random_configurations(20_005, [-np.pi] * 3, [np.pi] * 3, seed=3)
    out = pe.sweep(ARM, q, chunk=20_000, out=tmp_path / "d", **FAST)  # the old default
    legacy(out)
    expected = read(out)
    (out / "part-000001.parquet").unlink()

    def no_pilot(job):
        raise AssertionError("an old dataset keeps its chunks of 20,000")

    monkeypatch.setattr(sweep_module, "_automatic_chunk", no_pilot)
    pe.sweep(ARM, q, out=out, **FAST)
    assert sorted(p.name for p in out.glob("part-*")) == [
        "part-000000.parquet",
        "part-000001.parquet",
    ]
    pd.testing.assert_frame_equal(read(out), expected)


def test_an_old_dataset_of_another_chunk_says_which_chunks_fit(tmp_path):
    out = pe.sweep(ARM, GRID, chunk=7, out=tmp_path / "d", **FAST)
    legacy(out)
    with pytest.raises(pe.InputError, match=r"chunks other than 20,000.*chunk=6 to 7") as info:
        pe.sweep(ARM, GRID, out=out, **FAST)
    assert info.value.argument == "out"
    pe.sweep(ARM, GRID, chunk=7, out=out, **FAST)  # as it says
    one = pe.sweep(ARM, GRID, chunk=30, out=tmp_path / "one", **FAST)
    legacy(one)
    with pytest.raises(pe.InputError, match=r"chunk=30 or more"):
        pe.sweep(ARM, GRID, out=one, **FAST)


def test_an_old_dataset_of_the_default_chunk_refuses_another_naming_it(tmp_path):
    out = pe.sweep(ARM, GRID, chunk=20_000, out=tmp_path / "d", **FAST)
    legacy(out)
    with pytest.raises(pe.InputError, match=r"chunk: expected 20000 .*pass chunk=20000"):
        pe.sweep(ARM, GRID, chunk=10, out=out, **FAST)


def test_a_dataset_of_another_capacity_is_refused_as_such_before_its_chunk(tmp_path):
    out = pe.sweep(ARM, GRID, chunk=7, out=tmp_path / "d", **FAST)
    with pytest.raises(pe.InputError, match="holds the acceleration capacity's sweep"):
        pe.sweep(ARM, GRID, out=out, capacity="force", **FAST)
