"""Sweeps size their blocks from a memory budget (issue 15: a 6-D sweep of a 20-joint arm
needed over 4 GiB of temporaries with a fixed 512-row block)."""

from __future__ import annotations

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
