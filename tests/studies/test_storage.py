"""Study data is never lost or mixed: fault injection on sweep datasets and studies (issue 15).

Every child process is bounded: it waits at most ``TIMEOUT`` seconds, and its chunks are
slowed by injection only where two runs must overlap.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from reference import planar_urdf

ARM = pe.robots.load("chiacchio2000")
GRID = pe.grid(0.3, (-2.5, 2.5, 6), (-2.5, 2.5, 5))  # 30 configurations
TIMEOUT = 120

CHILD = """
import importlib, os, resource, signal, sys, time
import numpy as np
import polyell as pe
sweep_module = importlib.import_module("polyell.studies.sweep")
out, chunk, fsize, go = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
if fsize >= 0:  # a full disk: writes past fsize bytes fail (SIGXFSZ ignored: EFBIG)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, resource.RLIM_INFINITY))
if go != "-":  # start together, and take a while per chunk, so that two runs overlap
    open(f"{go}.ready{chunk}", "w").close()
    deadline = time.monotonic() + 60
    while not os.path.exists(go) and time.monotonic() < deadline:
        time.sleep(0.01)
    original = sweep_module._Job.chunk
    def slow(self, start, stop):
        time.sleep(0.2)
        return original(self, start, stop)
    sweep_module._Job.chunk = slow
arm = pe.robots.load("chiacchio2000")
grid = pe.grid(0.3, (-2.5, 2.5, 6), (-2.5, 2.5, 5))
try:
    pe.sweep(arm, grid, out=out, chunk=chunk)
except pe.PolyellError as exn:
    print(type(exn).__name__, exn)
    sys.exit(3)
"""


def child(tmp_path: Path, out: Path, chunk: int, fsize: int = -1, go: str = "-"):
    script = tmp_path / "child.py"
    script.write_text(textwrap.dedent(CHILD))
    return subprocess.Popen(
        [sys.executable, str(script), str(out), str(chunk), str(fsize), go],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def expected(chunk: int = 4) -> pd.DataFrame:
    return pe.sweep(ARM, GRID, chunk=chunk)


def read(out: Path) -> pd.DataFrame:
    return pd.read_parquet(out).sort_values("configuration").reset_index(drop=True)


def test_two_sweeps_at_once_into_one_folder_never_mix(tmp_path):
    out, go = tmp_path / "shared", tmp_path / "go"
    runs = [child(tmp_path, out, chunk, go=str(go)) for chunk in (4, 5)]
    deadline = time.monotonic() + TIMEOUT
    while not all(Path(f"{go}.ready{chunk}").exists() for chunk in (4, 5)):
        assert time.monotonic() < deadline and all(run.poll() is None for run in runs)
        time.sleep(0.01)
    go.touch()  # both are imported and waiting: they start within milliseconds
    results = [run.communicate(timeout=TIMEOUT) for run in runs]
    codes = [run.returncode for run in runs]
    assert sorted(codes) == [0, 3], results
    loser = results[codes.index(3)][0]
    assert "InputError" in loser and "locked by a running sweep" in loser
    winner_chunk = (4, 5)[codes.index(0)]
    pd.testing.assert_frame_equal(read(out), expected(winner_chunk), check_dtype=False)
    assert json.loads((out / "_sweep.json").read_text())["chunks"] == -(-30 // winner_chunk)


@pytest.mark.parametrize("fsize", [0, 600, 6000])
def test_a_full_disk_loses_nothing_and_the_sweep_resumes(tmp_path, fsize):
    """0: not even the metadata fits; 600: the metadata fits, no part does; 6000: some do."""
    out = tmp_path / "full"
    run = child(tmp_path, out, 4, fsize=fsize)
    stdout, stderr = run.communicate(timeout=TIMEOUT)
    assert run.returncode == 3, stderr
    assert stdout.startswith("StorageError Could not write") and "free disk space" in stdout
    meta = out / "_sweep.json"
    if meta.exists():  # never torn: whole, or absent
        assert json.loads(meta.read_text())["chunks"] == 8
    assert not list(out.glob(".*.tmp"))  # no temporary file left behind
    pe.sweep(ARM, GRID, out=out, chunk=4)  # with space again: resumes, and completes
    pd.testing.assert_frame_equal(read(out), expected(), check_dtype=False)


@pytest.fixture
def finished(tmp_path) -> Path:
    out = tmp_path / "done"
    pe.sweep(ARM, GRID, out=out, chunk=4)
    return out


def test_truncated_and_empty_parts_are_computed_again(finished):
    first = finished / "part-000001.parquet"
    first.write_bytes(first.read_bytes()[: first.stat().st_size // 2])
    (finished / "part-000002.parquet").write_bytes(b"")
    untouched = (finished / "part-000000.parquet").stat().st_mtime_ns
    pe.sweep(ARM, GRID, out=finished, chunk=4)
    pd.testing.assert_frame_equal(read(finished), expected(), check_dtype=False)
    assert (finished / "part-000000.parquet").stat().st_mtime_ns == untouched


def test_a_torn_metadata_file_is_reported_with_its_fix(finished):
    (finished / "_sweep.json").write_text("")
    with pytest.raises(pe.InputError, match=r"torn .* delete .* to start over"):
        pe.sweep(ARM, GRID, out=finished, chunk=4)


def test_parts_without_metadata_or_beyond_the_count_are_never_read(finished):
    shutil.copy(finished / "part-000000.parquet", finished / "part-000099.parquet")
    with pytest.raises(pe.InputError, match="part 99"):
        pe.sweep(ARM, GRID, out=finished, chunk=4)
    os.unlink(finished / "part-000099.parquet")
    os.unlink(finished / "_sweep.json")
    with pytest.raises(pe.InputError, match="without one"):
        pe.sweep(ARM, GRID, out=finished, chunk=4)
    (finished / "part-x.parquet").write_bytes(b"")
    with pytest.raises(pe.InputError, match=r"stray file part-x\.parquet"):
        pe.sweep(ARM, GRID, out=finished, chunk=4)


def test_an_edited_urdf_is_another_sweep(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(planar_urdf(ARM))
    q = np.random.default_rng(0).uniform(-2, 2, size=(12, 3))
    out = tmp_path / "urdf"
    robot = pe.UrdfRobot(urdf, tip="tip", task="planar", gravity=[0, -9.81, 0])
    pe.sweep(robot, q, ARM.tau_max, out=out, chunk=5)
    heavier = pe.PlanarArm(ARM.lengths, ARM.masses * 2, ARM.com, ARM.inertia)
    urdf.write_text(planar_urdf(heavier))
    edited = pe.UrdfRobot(urdf, tip="tip", task="planar", gravity=[0, -9.81, 0])
    assert edited.content_digest != robot.content_digest
    with pytest.raises(pe.InputError, match="holds a different sweep"):
        pe.sweep(edited, q, ARM.tau_max, out=out, chunk=5)
    pe.sweep(robot, q, ARM.tau_max, out=tmp_path / "other", chunk=5)  # same text: resumes
    urdf.write_text(planar_urdf(ARM))  # the original text again: the same sweep
    restored = pe.UrdfRobot(urdf, tip="tip", task="planar", gravity=[0, -9.81, 0])
    assert pe.sweep(restored, q, ARM.tau_max, out=out, chunk=5) == out


GRID_STUDY = """
title = "grid"
[robot]
library = "chiacchio2000"
[grid]
q1 = 0.3
q2 = { start = -2.5, stop = 2.5, num = 6 }
q3 = { start = -2.5, stop = 2.5, num = 5 }
[compare]
directions = 16
mvie = false
chunk = 4
[output]
formats = ["png"]
dpi = 30
histograms = ["coverage"]
"""


def test_a_study_resumes_from_its_dataset(tmp_path, monkeypatch):
    spec_path = tmp_path / "grid.toml"
    spec_path.write_text(GRID_STUDY)
    out = tmp_path / "study"
    pe.studies.run_study(pe.studies.load_study(spec_path), out)
    results = pd.read_csv(out / "results.csv")
    assert len(list((out / "results").glob("part-*.parquet"))) == 8

    def nothing_left(*args):
        raise AssertionError("a finished chunk was computed again")

    sweep_module = sys.modules["polyell.studies.sweep"]
    monkeypatch.setattr(sweep_module._Job, "chunk", nothing_left)
    pe.studies.run_study(pe.studies.load_study(spec_path), out)
    pd.testing.assert_frame_equal(pd.read_csv(out / "results.csv"), results)


def test_a_study_on_a_full_disk_ends_in_one_line(tmp_path):
    spec_path = tmp_path / "grid.toml"
    spec_path.write_text(GRID_STUDY)
    script = (
        "import resource, signal, sys\n"
        "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (3000, resource.RLIM_INFINITY))\n"
        "from polyell.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    run = subprocess.run(
        [
            sys.executable,
            "-c",
            script,
            "study",
            str(spec_path),
            "--out",
            str(tmp_path / "o"),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("polyell: error: Could not write"), run.stderr


def test_outputs_get_the_permissions_of_normal_files(tmp_path):
    """Atomic writes go through a private temporary file; the result must not stay 0600."""
    import os

    from polyell.storage import write_text_atomically

    old = os.umask(0o022)
    try:
        path = write_text_atomically(tmp_path / "table.md", "x")
        assert path.stat().st_mode & 0o777 == 0o644
        os.umask(0o077)
        assert write_text_atomically(tmp_path / "private.md", "y").stat().st_mode & 0o777 == 0o600
    finally:
        os.umask(old)
