"""Study data is never lost or mixed: fault injection on sweep datasets and studies (issue 15).

No test depends on timing: a child process that must be caught at some point of its run
pauses there and says so with a marker file, and the test acts on the marker.
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
#: Hang guard only (a child that never reaches its pause point): correctness never depends on
#: it, every step below waits for an event (a marker file, a process's exit), not for time.
HANG_GUARD = 600

CHILD = """
import importlib, os, resource, signal, sys, time
import numpy as np
import polyell as pe
sweep_module = importlib.import_module("polyell.studies.sweep")
out, chunk, fsize, go = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
if fsize >= 0:  # a full disk: writes past fsize bytes fail (SIGXFSZ ignored: EFBIG)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, resource.RLIM_INFINITY))
if go != "-":  # start together; the run that gets the lock holds it until released
    open(f"{go}.ready{chunk}", "w").close()
    while not os.path.exists(go):
        time.sleep(0.01)
    original = sweep_module._Job.chunk
    def held(self, start, stop):  # inside the lock: wait until the test releases it
        while not os.path.exists(f"{go}.release"):
            time.sleep(0.01)
        return original(self, start, stop)
    sweep_module._Job.chunk = held
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
    """Whichever run takes the lock holds it until the other has been refused and ended:
    the overlap is made by events, not by timing."""
    out, go = tmp_path / "shared", tmp_path / "go"
    runs = [child(tmp_path, out, chunk, go=str(go)) for chunk in (4, 5)]
    deadline = time.monotonic() + HANG_GUARD
    while not all(Path(f"{go}.ready{chunk}").exists() for chunk in (4, 5)):
        assert time.monotonic() < deadline and all(run.poll() is None for run in runs)
        time.sleep(0.01)
    go.touch()  # both are imported and waiting: both try the lock
    while all(run.poll() is None for run in runs):  # one is refused: it ends
        assert time.monotonic() < deadline, "hang guard"
        time.sleep(0.01)
    Path(f"{go}.release").touch()  # the other, still holding the lock, may finish
    results = [run.communicate(timeout=HANG_GUARD) for run in runs]
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
    stdout, stderr = run.communicate(timeout=HANG_GUARD)
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
        timeout=HANG_GUARD,
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


def wait_for(marker: Path, process: subprocess.Popen) -> None:
    """Wait until ``process`` has created ``marker``; fail if it ended before."""
    deadline = time.monotonic() + HANG_GUARD
    while not marker.exists():
        if process.poll() is not None:
            pytest.fail(f"the run ended before its pause point: {process.communicate()}")
        assert time.monotonic() < deadline, "hang guard"
        time.sleep(0.01)


KILLED_RUN = """
import importlib, os, signal, sys
import polyell as pe
from polyell import storage
sweep_module = importlib.import_module("polyell.studies.sweep")
out, phase, index = sys.argv[1], sys.argv[2], int(sys.argv[3])
target = "_sweep.json" if phase == "metadata" else f"part-{index:06d}.parquet"

def pause():  # say where the run stands, then wait for the SIGKILL
    open(out + ".paused", "w").close()
    while True:
        signal.pause()

compute = sweep_module._Job.chunk
def chunk(self, start, stop):  # killed while computing chunk `index`
    if phase == "computing" and start == 4 * index:
        pause()
    return compute(self, start, stop)

write = storage.write_atomically
def write_atomically(path, writer):  # killed with half of `target` in its temporary file
    def torn(name):
        writer(name)
        if phase != "computing" and os.path.basename(path) == target:
            os.truncate(name, os.path.getsize(name) // 2)
            pause()
    return write(path, torn)

sweep_module._Job.chunk = chunk
storage.write_atomically = sweep_module.write_atomically = write_atomically
arm = pe.robots.load("chiacchio2000")
grid = pe.grid(0.3, (-2.5, 2.5, 12), (-2.5, 2.5, 10))
pe.sweep(arm, grid, out=out, chunk=4, mvie=True, scores=("coverage", "mvie_ratio"))
"""
KILL_GRID = pe.grid(0.3, (-2.5, 2.5, 12), (-2.5, 2.5, 10))  # 120 configurations, 30 chunks
#: SIGKILL at seeded points: while writing the metadata, while computing a chunk, and while
#: writing a part (half of it in its temporary file).
KILL_POINTS = [("metadata", 0)] + [
    (phase, int(index))
    for phase, index in zip(
        ("computing", "writing", "writing"),
        np.random.default_rng(9).integers(0, 30, 3),
        strict=True,
    )
]


@pytest.mark.parametrize(("phase", "index"), KILL_POINTS)
def test_a_killed_run_resumes_to_every_configuration_exactly_once(tmp_path, phase, index):
    out = tmp_path / "killed"
    script = tmp_path / "run.py"
    script.write_text(KILLED_RUN)
    process = subprocess.Popen(
        [sys.executable, str(script), str(out), phase, str(index)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    wait_for(Path(f"{out}.paused"), process)
    process.kill()  # SIGKILL: no handler, no finally, no cleanup runs
    process.communicate()
    parts = sorted(out.glob("part-*.parquet"))
    assert len(parts) == (0 if phase == "metadata" else index)  # chunks run in order
    torn = list(out.glob(".*.tmp"))
    assert len(torn) == (0 if phase == "computing" else 1), torn  # what the kill left
    kept = {path.name: path.read_bytes() for path in parts}
    arguments = {"chunk": 4, "mvie": True, "scores": ("coverage", "mvie_ratio")}
    pe.sweep(ARM, KILL_GRID, out=out, **arguments)
    assert not list(out.glob(".*.tmp"))  # the dead run's temporary file is gone
    assert {path.name: path.read_bytes() for path in parts} == kept  # finished parts kept
    frame = read(out)
    assert frame["configuration"].tolist() == list(range(120))  # each exactly once
    # The same computation as an uninterrupted run (same chunks, same code, same machine).
    pd.testing.assert_frame_equal(frame, pe.sweep(ARM, KILL_GRID, **arguments), check_dtype=False)


def test_only_our_own_stale_temporary_files_are_removed(tmp_path):
    from polyell.storage import DATASET_FILES, remove_stale_temporaries

    ours = [".part-000003.parquet.k2j_x9q0.tmp", "._sweep.json.abcdefgh.tmp"]
    others = [
        ".notes.txt.abcdefgh.tmp",  # a temporary file of another name
        ".part-3.parquet.abcdefgh.tmp",  # not a part's name
        "part-000003.parquet.abcdefgh.tmp",  # not hidden: not ours
        ".part-000003.parquet.tmp",  # no random part
        "part-000001.parquet",
    ]
    for name in ours + others:
        (tmp_path / name).write_bytes(b"x")
    removed = remove_stale_temporaries(tmp_path, DATASET_FILES)
    assert sorted(path.name for path in removed) == sorted(ours)
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(others)


@pytest.mark.parametrize(
    ("name", "fragment"),
    [
        ("missing/table.md", "No such file or directory. Fix: create the folder first"),
        ("file/table.md", "Not a directory. Fix: a part of the path is a file"),
        ("x" * 256, "File name too long. Fix: choose a shorter file name"),
    ],
)
def test_a_file_that_cannot_be_created_is_a_storage_error_with_its_fix(tmp_path, name, fragment):
    from polyell.storage import write_text_atomically

    (tmp_path / "file").write_text("")
    with pytest.raises(pe.StorageError) as info:
        write_text_atomically(tmp_path / name, "x")
    assert f"Could not write {tmp_path / name}: " in str(info.value) and fragment in str(info.value)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["file"]  # nothing left


def test_a_name_at_the_limit_is_written_atomically(tmp_path):
    """255 bytes fit, though '.<name>.XXXXXXXX.tmp' would not: the temporary name is shortened."""
    from polyell.storage import write_text_atomically

    path = write_text_atomically(tmp_path / ("\u00e9" * 127 + "x"), "text")  # 255 bytes in UTF-8
    assert path.read_text() == "text" and [p.name for p in tmp_path.iterdir()] == [path.name]


def test_a_released_lock_leaves_no_file_and_no_second_holder(tmp_path):
    import fcntl

    from polyell.storage import _names_this_file, folder_lock

    with folder_lock(tmp_path, "x.lock", "study"):
        late = open(tmp_path / "x.lock", "a+")  # another process opened it just before
    assert not (tmp_path / "x.lock").exists()
    # that process now gets the lock of a file no longer in the folder, and must see so
    fcntl.flock(late, fcntl.LOCK_EX | fcntl.LOCK_NB)
    assert not _names_this_file(tmp_path / "x.lock", late)
    with folder_lock(tmp_path, "x.lock", "study"):  # the folder's lock is the current file
        with open(tmp_path / "x.lock") as current:
            assert _names_this_file(tmp_path / "x.lock", current)
        with pytest.raises(pe.InputError, match="locked by a running study"):
            with folder_lock(tmp_path, "x.lock", "study"):
                pass
    late.close()
