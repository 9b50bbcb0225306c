"""A trajectory study's memory and report do not grow with its samples (issue 20: ~2.3 kB of
memory and ~95 B of report.html per sample, 22 GiB and 1 GB for 10^7 samples).

Each size runs in a child process, which measures its peak resident memory around
``run_study``.  The sweep itself (already chunked, one Parquet part per chunk) is replaced
there by one that writes parts of the real schema from a template, so that 1e5 samples take
seconds; everything after it — the parts read one at a time, the tangent limits, results.csv,
the summary, the figures and the report — is the real code."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from polyell.interactive import DECIMATION_BUCKETS

CHILD = """
import json, resource, sys
from pathlib import Path
import numpy as np
import pandas as pd
import polyell.studies.runner as runner
from polyell.storage import part_path
from polyell.studies import load_study

K, folder = int(sys.argv[1]), Path(sys.argv[2])
t = np.arange(K) * 1e-3
q = np.column_stack([1.2 + 0.5 * np.sin(t), -1 + 0.4 * np.sin(2 * t), -0.8 + 0.6 * np.cos(t)])
qd = np.column_stack([0.5 * np.cos(t), 0.8 * np.cos(2 * t), -0.6 * np.sin(t)])
np.savez(folder / "path.npz", q=q, qd=qd, t=t)
del t, q, qd
(folder / "s.toml").write_text(
    'title = "path"\\n[robot]\\nlibrary = "chiacchio2000"\\n[trajectory]\\nfile = "path.npz"\\n'
    '[compare]\\ndirections = 16\\nmvie = false\\nouter = false\\nchunk = 5000\\n'
    '[output]\\nformats = ["html", "png"]\\ndpi = 30\\n'
)
real_sweep = runner.sweep

def fake_sweep(model, trajectory, *args, chunk, out, **kwargs):
    # the real sweep's schema, from its first rows; values tiled over every part
    template = real_sweep(model, trajectory.q[:64], *args, chunk=chunk, **kwargs)
    Path(out).mkdir()
    for index, start in enumerate(range(0, len(trajectory), chunk)):
        stop = min(start + chunk, len(trajectory))
        frame = template.iloc[np.arange(start, stop) % len(template)].reset_index(drop=True)
        frame["configuration"] = np.arange(start, stop)
        frame.insert(1, "t", trajectory.t[start:stop])
        for i in range(trajectory.n):
            frame[f"q{i + 1}"] = trajectory.q[start:stop, i]
        frame.to_parquet(part_path(Path(out), index), index=False)
    return Path(out)

runner.sweep = fake_sweep
spec = load_study(folder / "s.toml")
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
runner.run_study(spec, folder / "out")
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
rows = sum(1 for _ in open(folder / "out" / "results.csv")) - 1
print(json.dumps({
    "growth_kib": after - before,
    "report": (folder / "out" / "report.html").stat().st_size,
    "rows": rows,
    "page": (folder / "out" / "report.html").read_text()[-20000:],
}))
"""


def run_child(tmp_path, samples: int) -> dict:
    folder = tmp_path / str(samples)
    folder.mkdir()
    script = tmp_path / "child.py"
    script.write_text(textwrap.dedent(CHILD))
    run = subprocess.run(
        [sys.executable, str(script), str(samples), str(folder)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


#: Sample counts compared (results.csv of the larger takes most of the time: pandas
#: formats about half a million numbers a second).
SMALL, LARGE = 10_000, 100_000


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp_path = tmp_path_factory.mktemp("memory")
    return {k: run_child(tmp_path, k) for k in (SMALL, LARGE)}


def test_study_memory_does_not_grow_with_the_samples(runs):
    small, large = runs[SMALL], runs[LARGE]
    assert small["rows"] == SMALL and large["rows"] == LARGE  # nothing lost
    # What may grow with the samples, per sample: one score column read for the summary's
    # median (the Arrow buffer, the pandas column, its float copy, the finite mask and
    # selection, the median's sorted copy: at most 8 float64 copies, 64 B).  The trajectory
    # itself (56 B a sample for 3 joints) is read before the measurement starts.  Everything
    # else is per part (5,000 rows) or per decimated curve.  The old runner held every
    # column of every row and the whole CSV text: over 1 kB a sample.
    per_sample = 8 * 8
    # The peak resident size also moves, independently of the samples, by what glibc keeps
    # of freed blocks in its heap: blocks below its dynamic mmap threshold, at most 32 MiB
    # on 64-bit systems (DEFAULT_MMAP_THRESHOLD_MAX).  The old runner: ~90 MiB more here.
    slack = 32 * 2**20
    growth = (large["growth_kib"] - small["growth_kib"]) * 1024
    details = {k: v for k, v in large.items() if k != "page"}
    assert growth <= (LARGE - SMALL) * per_sample + slack, (growth, details)


def test_report_size_does_not_grow_with_the_samples(runs):
    small, large = runs[SMALL], runs[LARGE]
    # Both series are decimated to at most 3 * traces * DECIMATION_BUCKETS points (2 traces
    # without the MVIE and outer ellipsoid); each point is two numbers of at most 25
    # characters: that is all that can differ between the two pages, besides the counts.
    traces, series = 2, 2
    bound = series * 3 * traces * DECIMATION_BUCKETS * 2 * 25
    assert abs(large["report"] - small["report"]) <= bound
    assert f"{LARGE:,} samples, shown decimated to" in large["page"]
    assert f"{SMALL:,} samples, shown decimated to" in small["page"]
