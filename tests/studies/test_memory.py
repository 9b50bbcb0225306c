"""Sweeps size their blocks from a memory budget (issue 15: a 6-D sweep of a 20-joint arm
needed over 4 GiB of temporaries with a fixed 512-row block)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap

from polyell.studies.batch import BLOCK, BLOCK_MEMORY, block_size

CHILD = """
import resource, sys
import numpy as np
import polyell as pe
sys.path.insert(0, sys.argv[1])
from reference import random_spd
rng = np.random.default_rng(0)
K, m, n = 48, 6, 20
dyn = pe.Dynamics(
    rng.normal(size=(K, m, n)),
    np.stack([random_spd(rng, n) for _ in range(K)]),
    rng.normal(size=(K, n)),
)
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
frame = pe.sweep(dyn, tau_max=np.full(n, 5.0), directions=16)
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
assert frame["chiacchio_coverage"].notna().all()
print((after - before) / 1024)
"""


def test_block_size_follows_the_budget():
    assert block_size(3, 7) == BLOCK  # the Panda: full blocks
    for m, n in [(6, 12), (6, 20), (6, 30), (3, 200)]:
        rows = block_size(m, n)
        assert 1 <= rows <= BLOCK
        assert rows == 1 or rows * 32 * math.comb(n, m - 1) * (m + n) <= BLOCK_MEMORY


def test_a_six_dimensional_sweep_of_twenty_joints_stays_within_its_budget(tmp_path):
    """48 configurations in one chunk: with 512-row blocks they were all one block."""
    script = tmp_path / "child.py"
    script.write_text(textwrap.dedent(CHILD))
    tests = str(__import__("pathlib").Path(__file__).resolve().parents[1])
    run = subprocess.run(
        [sys.executable, str(script), tests], capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    growth_mib = float(run.stdout.strip().splitlines()[-1])
    assert growth_mib < 1.5 * BLOCK_MEMORY / 2**20, growth_mib  # 590 MiB with 48-row blocks


# --- issue 33: a grid study's memory does not grow with its configurations -----------------

GRID_CHILD = """
import json, resource, sys
from pathlib import Path
import numpy as np
import polyell.studies.runner as runner
from polyell.storage import part_path
from polyell.studies import load_study

K, folder = int(sys.argv[1]), Path(sys.argv[2])
# The caps of what the figures keep, small enough that both sizes reach them: what is
# measured is then what a study holds besides (the CSV, the summary, the parts).
runner.MAP_AXIS_VALUES, runner.REPORT_MAP_AXIS_VALUES, runner.HISTOGRAM_ROWS = 40, 10, 2000
study = (
    'title = "grid"\\n[robot]\\nlibrary = "chiacchio2000"\\n[grid]\\nq1 = "pi/2"\\n'
    'q2 = {{ start = "-pi", stop = "pi", num = {rows} }}\\n'
    'q3 = {{ start = "-pi", stop = "pi", num = 100 }}\\n'
    '[compare]\\ndirections = 16\\nmvie = false\\nouter = false\\nchunk = 5000\\n'
    '[output]\\nformats = ["html", "png"]\\ndpi = 30\\ncsv = true\\n'
    'maps = ["chiacchio_coverage", "yoshikawa_coverage"]\\nhistograms = ["coverage"]\\n'
)
real_sweep = runner.sweep

def fake_sweep(model, configurations, *args, chunk, out, **kwargs):
    # the real sweep's schema, from its first rows; values tiled over every part
    def rows(start, stop):
        if hasattr(configurations, "rows"):
            return configurations.rows(start, stop)
        return np.asarray(configurations[start:stop])
    template = real_sweep(model, rows(0, 64), *args, chunk=chunk, **kwargs)
    Path(out).mkdir(parents=True)
    for index, start in enumerate(range(0, len(configurations), chunk)):
        stop = min(start + chunk, len(configurations))
        frame = template.iloc[np.arange(start, stop) % len(template)].reset_index(drop=True)
        frame["configuration"] = np.arange(start, stop)
        q = rows(start, stop)
        for i in range(q.shape[1]):
            frame[f"q{i + 1}"] = q[:, i]
        frame.to_parquet(part_path(Path(out), index), index=False)
    return Path(out)

runner.sweep = fake_sweep
(folder / "warm.toml").write_text(study.format(rows=2))
runner.run_study(load_study(folder / "warm.toml"), folder / "warm")  # every import, once
(folder / "s.toml").write_text(study.format(rows=K // 100))
spec = load_study(folder / "s.toml")
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
runner.run_study(spec, folder / "out")
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
rows = sum(1 for _ in open(folder / "out" / "results.csv")) - 1
print(json.dumps({"growth_kib": after - before, "rows": rows}))
"""

#: Configurations compared: ten times as many.
GRID_SMALL, GRID_LARGE = 20_000, 200_000


def run_grid_child(tmp_path, configurations: int) -> dict:
    folder = tmp_path / str(configurations)
    folder.mkdir()
    script = tmp_path / "grid_child.py"
    script.write_text(textwrap.dedent(GRID_CHILD))
    run = subprocess.run(
        [sys.executable, str(script), str(configurations), str(folder)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


def test_grid_study_memory_does_not_grow_with_the_configurations(tmp_path):
    """Ten times the configurations, the same memory: bounded by the chunk (issue 33).

    Each size runs in a child process (a seeded fake sweep writes parts of the real
    schema, so that 200,000 configurations take seconds); everything after the sweep is
    the real code: results.csv streamed, the summary's passes over the parts, the maps,
    the histograms and the report.  The runner before issue 33 held every row, its CSV
    text and their copies: its peak grew by about 88 MiB for the small and 520 MiB for
    the large study (a ratio of 5.9); now both hold a few parts (5,000 rows) and the
    summary's fixed-size counts (30 and 9 MiB, 0.26).
    """
    small = run_grid_child(tmp_path, GRID_SMALL)
    large = run_grid_child(tmp_path, GRID_LARGE)
    assert small["rows"] == GRID_SMALL and large["rows"] == GRID_LARGE  # nothing lost
    # What the peak resident size may move by, independently of the rows: the blocks glibc
    # keeps of freed memory below its dynamic mmap threshold (at most 32 MiB on 64-bit
    # systems, DEFAULT_MMAP_THRESHOLD_MAX); the growth of the small run is floored there.
    slack_kib = 32 * 1024
    ratio = large["growth_kib"] / max(small["growth_kib"], slack_kib)
    assert ratio < 1.5, (small, large)
