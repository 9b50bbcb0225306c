"""The command line where it surprised (issue 13), through the real `polyell` entry point."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe

POLYELL = Path(sys.executable).parent / "polyell"


def run(*args: str, stdin_pipe: str | None = None) -> subprocess.CompletedProcess[str]:
    command = [str(POLYELL), *args]
    if stdin_pipe is not None:  # e.g. "| head -2"
        return subprocess.run(
            " ".join(command) + " " + stdin_pipe,
            shell=True,
            capture_output=True,
            text=True,
            timeout=300,
        )
    return subprocess.run(command, capture_output=True, text=True, timeout=300)


def test_the_entry_point_exists():
    assert POLYELL.exists(), "pip install the package: the console script is what users run"


def test_version():
    result = run("--version")
    assert result.returncode == 0 and result.stdout.strip() == f"polyell {pe.__version__}"


def test_negative_leading_values_and_degrees():
    radians = run("analyze", "--q", "-pi/2,0,0", "--no-mvie")
    assert radians.returncode == 0, radians.stderr
    assert "at q = [-1.570796, 0.0, 0.0] rad" in radians.stdout
    degrees = run("analyze", "--q", "-90,0,0", "--deg", "--no-mvie")
    assert degrees.stdout == radians.stdout


def test_tau_min_alone_keeps_the_robots_upper_limits():
    alone = json.loads(run("analyze", "--tau-min", "-50,-10,-2", "--no-mvie", "--json").stdout)
    both = run("analyze", "--tau-max", "100,30,4", "--tau-min", "-50,-10,-2", "--no-mvie", "--json")
    both = json.loads(both.stdout)
    assert alone["tau_min"] == [-50.0, -10.0, -2.0] and alone["tau_max"] == [100.0, 30.0, 4.0]
    assert alone["xg"] == both["xg"]


def test_a_robot_other_than_the_papers_needs_its_q():
    result = run("analyze", "--robot", "ur5", "--no-mvie")
    assert result.returncode == 2 and result.stdout == ""
    assert "--q: expected 6 joint angles for ur5" in result.stderr
    assert "--q 0,0,0,0,0,0" in result.stderr and len(result.stderr.splitlines()) == 1


def test_direction_normalised_or_as_an_angle_and_nothing_before_an_error():
    normalised = run("analyze", "--direction", "1,1", "--normalize", "--no-mvie")
    assert "along t = [0.707107, 0.707107]" in normalised.stdout
    assert "polyell: note: --direction normalised to [0.707107, 0.707107]" in normalised.stderr
    angle = run("analyze", "--angle", "45", "--no-mvie")
    assert "along t = [0.707107, 0.707107]" in angle.stdout
    refused = run("analyze", "--direction", "1,1", "--no-mvie")
    assert refused.returncode == 2 and refused.stdout == ""
    assert "add --normalize" in refused.stderr
    # a tiny vector is scaled before its norm (its square underflowed: norm 0, then a
    # refusal that contradicted the fix it had given)
    tiny = run("analyze", "--direction", "1e-300,0", "--normalize", "--no-mvie")
    assert "along t = [1.0, 0.0]" in tiny.stdout, tiny.stderr
    assert "--direction normalised to [1.0, 0.0]" in tiny.stderr


def test_a_closed_pipe_is_not_an_error():
    result = run("analyze", "--no-mvie", stdin_pipe="| head -2")
    assert result.stdout.count("\n") == 2 and "Error" not in result.stderr, result.stderr


def test_dead_scheduler_and_points_study_scheduler(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text('[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0, 0, 1]\n')
    result = run("study", str(spec), "--out", str(tmp_path / "o"), "--scheduler", "processes")
    assert result.returncode == 2 and "no scheduler for a study of points" in result.stderr


def test_json_holds_the_whole_analysis():
    text = run("analyze", "--no-mvie").stdout
    data = json.loads(run("analyze", "--no-mvie", "--json").stdout)
    for key in (
        "task",
        "unit",
        "xg",
        "M",
        "tau_max",
        "tau_min",
        "direction",
        "polytope",
        "ellipsoids",
        "inverse",
        "scores",
    ):
        assert key in data, key
    assert data["inverse"]["at"] == "hi"
    qdd = np.round(data["inverse"]["chiacchio"]["qdd"], 5).tolist()
    assert f"qdd = {qdd}" in text  # the same inverse map as the text shows
    lo, hi = data["polytope"]["limits"]
    assert f"polytope   [{lo:.5g}, {hi:.5g}]" in text


def test_study_summary_says_where_the_outputs_are(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'
        '[compare]\nmvie = false\n[output]\nformats = ["png"]\ndpi = 30\n'
    )
    result = run("study", str(spec), "--out", str(tmp_path / "o"), "--quiet")
    assert result.returncode == 0, result.stderr
    assert f"{tmp_path / 'o' / 'comparison.md'}: the scores" in result.stdout
    assert f"{tmp_path / 'o' / 'numbers.md'}: every number" in result.stdout


@pytest.mark.parametrize("args", [("--help",), ("analyze", "--help")])
def test_help_runs(args):
    result = run(*args)
    assert result.returncode == 0 and "usage: polyell" in result.stdout


def test_import_leaves_the_heavy_libraries_alone():
    code = (
        "import sys, polyell\n"
        "heavy = ('cvxpy', 'matplotlib', 'pandas', 'scipy.stats')\n"
        "print(sorted(m for m in heavy if m in sys.modules))"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.stdout.strip() == "[]", result.stdout + result.stderr


def one_error_line(result: subprocess.CompletedProcess[str], fragment: str) -> None:
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith("polyell: error: ") and fragment in result.stderr
    assert len(result.stderr.splitlines()) == 1, result.stderr


@pytest.mark.parametrize(
    "argv",
    [("analyze", "--no-mvie"), ("analyze", "--json", "--no-mvie"), ("--help",), ("--version",)],
)
def test_a_full_standard_output_is_one_line_and_exit_2(argv):
    with open("/dev/full", "w") as full:
        result = subprocess.run(
            [str(POLYELL), *argv], stdout=full, stderr=subprocess.PIPE, text=True, timeout=300
        )
    one_error_line(result, "could not write to standard output: No space left on device")


def test_malformed_scheduler_addresses_are_one_line(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text('[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 2\n')
    for address in ("tcp://foo:bar", "tcp://[::1", "tcp://h:99999"):
        result = run("study", str(spec), "--out", str(tmp_path / "o"), "--scheduler", address)
        one_error_line(result, "scheduler: expected None, 'processes' or a Dask scheduler address")
    assert not (tmp_path / "o").exists()  # refused before anything was written


def test_folders_and_binary_files_as_study_or_robot_are_one_line(tmp_path):
    binary = tmp_path / "image.toml"
    binary.write_bytes(bytes(range(256)))
    for argv in (
        ("study", str(tmp_path), "--out", str(tmp_path / "o")),
        ("study", str(binary), "--out", str(tmp_path / "o")),
        ("analyze", "--robot", str(binary)),
    ):
        result = run(*argv)
        one_error_line(result, "path: expected ")


#: A study whose first run is interrupted by Ctrl-C (SIGINT) while it computes its third
#: chunk: the run says where it stopped with a marker file and waits there for the signal.
INTERRUPTED = """
import importlib, os, signal, sys, time
from polyell.cli import main
# Ctrl-C's default, even where the runner started us with SIGINT ignored (a background job)
signal.signal(signal.SIGINT, signal.default_int_handler)
sweep_module = importlib.import_module("polyell.studies.sweep")
marker = sys.argv[1]
compute = sweep_module._Job.chunk
def chunk(self, start, stop):
    if start == 4 and not os.path.exists(marker):
        open(marker, "w").close()
        time.sleep(600)  # Ctrl-C arrives here
    return compute(self, start, stop)
sweep_module._Job.chunk = chunk
sys.exit(main(sys.argv[2:]))
"""


def test_ctrl_c_during_a_study_is_one_line_and_the_next_run_resumes(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 12\n'
        "[compare]\ndirections = 8\nmvie = false\nouter = false\nchunk = 2\n"
        '[output]\nformats = ["svg"]\n'
    )
    out, marker = tmp_path / "o", tmp_path / "interrupted"
    script = tmp_path / "run.py"
    script.write_text(INTERRUPTED)
    argv = ["study", str(spec), "--out", str(out), "--quiet"]
    process = subprocess.Popen(
        [sys.executable, str(script), str(marker), *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    while not marker.exists():  # wait for the run to be inside its third chunk
        assert process.poll() is None, process.communicate()
        try:
            process.wait(0.01)  # a pause between looks, not a time limit
        except subprocess.TimeoutExpired:
            pass
    process.send_signal(signal.SIGINT)
    stdout, stderr = process.communicate(timeout=300)
    assert process.returncode == 130
    assert stderr == "polyell: interrupted; run the same command again to resume\n"
    assert stdout == ""
    parts = sorted((out / "results").glob("part-*.parquet"))
    assert [path.name for path in parts] == ["part-000000.parquet", "part-000001.parquet"]
    assert not list(out.rglob(".*.tmp"))
    kept = {path: path.stat().st_mtime_ns for path in parts}
    again = run(*argv)  # the same command, through the entry point
    resumed = f"polyell: resuming {out / 'results'}: 2 of 6 chunks done\n"
    assert again.returncode == 0 and again.stderr == resumed, again.stderr
    assert {path: path.stat().st_mtime_ns for path in parts} == kept  # not computed again
    results = pd.read_csv(out / "results.csv")
    assert results["configuration"].tolist() == list(range(12))
