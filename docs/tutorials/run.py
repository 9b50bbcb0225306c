"""Run every tutorial and store what it prints next to it (``<name>.out``)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
TUTORIALS = ["quickstart", "paper", "real_robot", "sweep_heatmaps", "dask_scale", "planner_limits"]


def output(name: str) -> str:
    """What the tutorial ``name`` prints."""
    result = subprocess.run(
        [sys.executable, str(HERE / f"{name}.py")], check=True, capture_output=True, text=True
    )
    return result.stdout


if __name__ == "__main__":
    for name in TUTORIALS:
        (HERE / f"{name}.out").write_text(output(name))
        print("regenerated", f"{name}.out")
