"""Section (p): every capacity's sweep on every library robot, at the defaults and the studies'.

For each of the library's real robots (Pinocchio's dynamics included in the timing) and for
random 3x7 arms (a batched Dynamics, no model), ``pe.sweep`` of each capacity over the same
seeded random configurations within the joint limits, at the sweep's defaults and with
``mvie=True, outer=True`` (a study file's defaults), the runs of one robot interleaved
(:func:`timed_alternately`).  Each line also gives how many rows left the batch for the
per-row path (the ``per_row`` column).
"""

from __future__ import annotations

import numpy as np
from run_benchmarks import timed_alternately
from speed_defaults import random_arms

import polyell as pe

__all__ = ["SECTIONS"]

ROBOTS = ("panda", "ur5", "kinova", "xarm7", "z1")
CAPACITIES = ("acceleration", "velocity", "force")
#: Configurations per sweep: at the defaults, and with the optimal ellipsoids.
COUNT, OPTIMAL_COUNT = 2_000, 500


def _cases():
    """(label, source, configurations or None, limits) of every benchmarked robot."""
    for name in ROBOTS:
        robot = pe.robots.load(name)
        low, high = robot.position_limits
        q = np.random.default_rng(7).uniform(low, high, (COUNT, robot.nq))
        yield name, robot, q, {}
    dyn, tau_max = random_arms(COUNT, 3, 7)
    yield "random 3x7 arms", dyn, None, {"tau_max": tau_max}


def _rate(count: int, seconds: list[float]) -> str:
    """Configurations per second: median (min - max) over the runs."""
    rates = count / np.asarray(seconds)
    return f"{np.median(rates):,.0f} ({rates.min():,.0f} – {rates.max():,.0f})"


def _limits(capacity: str, limits: dict) -> dict:
    if capacity == "velocity" and limits:  # the random arms' limits as velocity limits
        return {"qd_max": limits["tau_max"] / 10.0}
    return limits


def _sweeper(source, q, limits: dict, frames: dict, capacity: str, optimal: bool):
    """A call of one benchmarked sweep, keeping its frame in ``frames[capacity, optimal]``."""
    count = OPTIMAL_COUNT if optimal else COUNT

    def call() -> None:
        data, rows = (source[:count], None) if q is None else (source, q[:count])
        frames[capacity, optimal] = pe.sweep(
            data, rows, capacity=capacity, mvie=optimal, outer=optimal, **_limits(capacity, limits)
        )

    return call


def bench_robots(repeats: int) -> list[str]:
    """(p) Every capacity on every library robot: configurations/s and rows per row."""
    lines = [
        "## (p) Sweeps on every library robot",
        "",
        "From `python tests/benchmarks/run_benchmarks.py --sections robots`: `pe.sweep` of "
        f"{COUNT:,} random configurations within the joint limits (seed 7; Pinocchio's "
        f"dynamics included) at the defaults, and {OPTIMAL_COUNT} with `mvie=True, "
        "outer=True` (the study files' defaults); the random arms are a batched Dynamics "
        "(velocity limits a tenth of the torque limits). Configurations per second, median "
        f"(min – max) of {max(1, repeats // 2)} interleaved runs per robot; per row: the rows "
        "the batch left to `compare`, one configuration at a time.",
        "",
        "| robot | capacity | defaults /s | per row | mvie, outer /s | per row |",
        "|---|---|---|---|---|---|",
    ]
    runs = max(1, repeats // 2)
    for label, source, q, limits in _cases():
        frames: dict = {}
        calls = [
            (capacity, optimal, _sweeper(source, q, limits, frames, capacity, optimal))
            for capacity in CAPACITIES
            for optimal in (False, True)
        ]
        times = timed_alternately([call for *_, call in calls], runs)
        rates = {}
        for (capacity, optimal, _), seconds in zip(calls, times, strict=True):
            count = OPTIMAL_COUNT if optimal else COUNT
            per_row = int(frames[capacity, optimal]["per_row"].sum())
            rates[capacity, optimal] = (_rate(count, seconds), per_row, count)
        for capacity in CAPACITIES:
            (fast, fast_rows, n1), (slow, slow_rows, n2) = (
                rates[capacity, False],
                rates[capacity, True],
            )
            lines.append(
                f"| {label} | {capacity} | {fast} | {fast_rows} of {n1} | {slow} | "
                f"{slow_rows} of {n2} |"
            )
    return [*lines, ""]


SECTIONS = {"robots": bench_robots}
