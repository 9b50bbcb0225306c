"""Cost per configuration of ``pe.sweep`` on the Panda, per capacity and option set.

What the automatic chunk size of ``pe.sweep`` (``chunk=None``: as many configurations as
take ``CHUNK_SECONDS``, measured by a pilot run) comes to, and the cost of the study files'
defaults (``mvie = true``, ``outer = true``) against ``pe.sweep``'s.  Configurations per
second of the process's CPU time (one core, one BLAS thread; CPU time rather than
wall-clock time, so that a shared machine counts less), Pinocchio's dynamics included, at
the default direction set (256 in 3-D, 2,000 in 6-D); every capacity and option set timed
in turn within each repeat (interleaved); the median and the min - max of the repeats.  A
second table times the same default sweep into a Parquet dataset at several chunk sizes
(the cost of a chunk).

Usage::

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/sweep_costs.py
        [--count 2000] [--optima-count 500] [--repeats 5]
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import polyell as pe
from polyell.studies.sweep import chunk_for

CAPACITIES = ("acceleration", "velocity", "force")
OPTIONS = {
    "defaults": {},
    "mvie": {"mvie": True},
    "outer": {"outer": True},
    "mvie, outer": {"mvie": True, "outer": True},
}
#: The Panda's tasks: its 3-D position (the library's default) and the 6-D twist, angular
#: rows weighted 0.2 m (256 and 2,000 default directions).
TASKS = {
    "3-D": {},
    "6-D": {"task": ["x", "y", "z", "wx", "wy", "wz"], "weights": [1, 1, 1, 0.2, 0.2, 0.2]},
}


def _rate(robot: object, configurations: object, count: int, **kwargs: object) -> float:
    """Configurations per second of this process's CPU time (the machine may be shared)."""
    started = time.process_time()
    pe.sweep(robot, configurations, **kwargs)
    return count / (time.process_time() - started)


def costs(
    task: str, count: int, optima_count: int, repeats: int
) -> dict[tuple[str, str], list[float]]:
    """Configurations per second of every capacity and option set, ``repeats`` each."""
    robot = pe.robots.load("panda", **TASKS[task])
    for capacity in CAPACITIES:  # warm-up: imports, caches
        pe.sweep(robot, pe.random_configurations(robot, 50, seed=1), capacity=capacity)
    rates: dict[tuple[str, str], list[float]] = {}
    for _ in range(repeats):
        for capacity in CAPACITIES:
            for name, options in OPTIONS.items():
                k = count if name == "defaults" else optima_count
                configurations = pe.random_configurations(robot, k, seed=7)
                rate = _rate(robot, configurations, k, capacity=capacity, **options)
                rates.setdefault((capacity, name), []).append(rate)
    return rates


def chunk_costs(count: int, chunks: list[int], repeats: int) -> dict[int, list[float]]:
    """Configurations per second of a default acceleration sweep to Parquet, per chunk size."""
    robot = pe.robots.load("panda")
    configurations = pe.random_configurations(robot, count, seed=7)
    rates: dict[int, list[float]] = {}
    work = Path(tempfile.mkdtemp(prefix="polyell-chunks-"))
    try:
        for _ in range(repeats):
            for chunk in chunks:
                out = work / f"chunk-{chunk}"
                rate = _rate(robot, configurations, count, chunk=chunk, out=out)
                rates.setdefault(chunk, []).append(rate)
                shutil.rmtree(out)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return rates


def _summary(values: list[float]) -> str:
    return f"{statistics.median(values):,.0f} ({min(values):,.0f} – {max(values):,.0f})"


def main(argv: list[str] | None = None) -> int:
    """Print both tables in Markdown."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=2000)
    parser.add_argument("--optima-count", type=int, default=500)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--tasks", nargs="*", choices=list(TASKS), default=list(TASKS))
    parser.add_argument("--six-d-divisor", type=int, default=10, help="fewer rows in 6-D")
    parser.add_argument("--chunk-count", type=int, default=20_000)
    parser.add_argument("--chunks", type=int, nargs="*", default=[1000, 2500, 5000, 20_000])
    args = parser.parse_args(argv)
    print(
        "| task | capacity | options | configurations/s | µs per configuration "
        "| × defaults | automatic chunk | a chunk of 20,000 |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for task in args.tasks:
        scale = 1 if task == "3-D" else args.six_d_divisor
        rates = costs(task, args.count // scale, args.optima_count // scale, args.repeats)
        for capacity in CAPACITIES:
            base = statistics.median(rates[(capacity, "defaults")])
            for name in OPTIONS:
                values = rates[(capacity, name)]
                median = statistics.median(values)
                print(
                    f"| {task} | {capacity} | {name} | {_summary(values)} "
                    f"| {1e6 / median:,.0f} | {base / median:.1f}× "
                    f"| {chunk_for(1.0 / median):,} | {20_000 / median:,.1f} s |"
                )
    if args.chunks:
        by_chunk = chunk_costs(args.chunk_count, args.chunks, args.repeats)
        print()
        print("| chunk | configurations/s to Parquet |")
        print("|---|---|")
        for chunk, values in by_chunk.items():
            print(f"| {chunk:,} | {_summary(values)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
