"""Section (r): the acceleration set within the joint limits over a horizon (issue 34).

On every library robot (Pinocchio's dynamics included), at seeded random states within the
joint limits: ``pe.limits_along`` of the polytope and both ellipsoids along one random unit
direction per state, without a horizon (at rest) and with one of 1 ms and 10 ms (joint
velocities half-way to their limits at random, so that the dynamics include the velocity
terms); and ``pe.sweep`` at rest without and with a 1 ms horizon.  Each line says how many
rows the joints' intervals cut (those of ``limits_along`` take the batched dual simplex,
those of ``sweep`` the per-row path).
"""

from __future__ import annotations

from functools import partial

import numpy as np
from run_benchmarks import timed_alternately

import polyell as pe
from polyell.capacities.horizon import horizon_block, robot_horizon

__all__ = ["SECTIONS"]

ROBOTS = ("panda", "ur5", "kinova", "xarm7", "z1")
#: States of limits_along; configurations of a sweep.
COUNT, SWEEP_COUNT = 5_000, 300


def _states(robot, count):
    rng = np.random.default_rng(11)
    low, high = robot.position_limits
    qd_max, qd_min = robot.velocity_limits()
    q = rng.uniform(low, high, (count, robot.nq))
    qd = 0.5 * rng.uniform(qd_min, qd_max, (count, robot.nq))
    T = rng.normal(size=(count, 3))
    return q, qd, T / np.linalg.norm(T, axis=1, keepdims=True)


def _cut(robot, q, qd, horizon):
    """How many states the joints' intervals cut (or leave no acceleration)."""
    state = robot_horizon(robot, horizon).at(q, qd)
    dyn = robot.dynamics(q, qd) if qd.any() else robot.dynamics(q)
    upper, lower = robot.torque_limits()
    return int(horizon_block(dyn, state, upper, lower).cut.sum())


def _rate(count, seconds):
    rates = count / np.asarray(seconds)
    return f"{np.median(rates):,.0f} ({rates.min():,.0f} – {rates.max():,.0f})"


def bench_horizon(repeats: int) -> list[str]:
    """(r) limits_along and sweep with and without a horizon, on every library robot."""
    runs = max(1, repeats // 2)
    lines = [
        "## (r) The set within the joint limits over a horizon",
        "",
        "From `python tests/benchmarks/run_benchmarks.py --sections horizon`: on each library "
        f"robot, {COUNT:,} seeded random states (positions within the joint limits, "
        "velocities half-way to theirs at random, one random unit direction each; "
        "Pinocchio's dynamics included). `pe.limits_along` (the polytope and both "
        "ellipsoids) at rest without a horizon, and with `horizon=` 1 ms and 10 ms and "
        f"the states' velocities; `pe.sweep` of {SWEEP_COUNT} configurations at rest "
        "without and with a 1 ms horizon. Rows per second, median (min – max) of "
        f"{runs} interleaved runs per robot; cut: the rows whose set the joints' intervals "
        "cut (`limits_along`: the batched dual simplex; `sweep`: one `compare` per row). "
        "Where most rows are cut (the cut columns) the sweep runs at the per-row path's "
        "rate, most of it the scores of a set of 40 to 70 facets (its cap union), far "
        "from the sweep without a horizon.",
        "",
        "| robot | limits_along /s | 1 ms /s | cut | 10 ms /s | cut | sweep /s | 1 ms /s | cut |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name in ROBOTS:
        robot = pe.robots.load(name)
        q, qd, T = _states(robot, COUNT)
        rest = q[:SWEEP_COUNT]
        calls = [
            partial(pe.limits_along, robot, q, T),
            partial(pe.limits_along, robot, q, T, horizon=1e-3, qd=qd),
            partial(pe.limits_along, robot, q, T, horizon=1e-2, qd=qd),
            partial(pe.sweep, robot, rest),
            partial(pe.sweep, robot, rest, horizon=1e-3),
        ]
        times = timed_alternately(calls, runs)
        counts = (COUNT, COUNT, COUNT, SWEEP_COUNT, SWEEP_COUNT)
        rates = [_rate(c, t) for c, t in zip(counts, times, strict=True)]
        cut = [
            _cut(robot, q, qd, 1e-3),
            _cut(robot, q, qd, 1e-2),
            _cut(robot, rest, np.zeros_like(rest), 1e-3),
        ]
        lines.append(
            f"| {name} | {rates[0]} | {rates[1]} | {cut[0]:,} | {rates[2]} | {cut[1]:,} | "
            f"{rates[3]} | {rates[4]} | {cut[2]} of {SWEEP_COUNT} |"
        )
    return [*lines, ""]


SECTIONS = {"horizon": bench_horizon}
