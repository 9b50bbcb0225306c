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

import time
from functools import partial

import numpy as np
from run_benchmarks import summary, timed_alternately

import polyell as pe
from polyell.capacities.horizon import horizon_block, robot_horizon
from polyell.geometry.bounded_lp import dual_simplex

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
        "rate, far from the sweep without a horizon: the second table says where a cut "
        "row's time goes.",
        "",
        "| robot | limits_along /s | 1 ms /s | cut | 10 ms /s | cut | sweep /s | 1 ms /s | cut |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    costs = []
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
        costs.append((name, _cut_row_costs(robot, rest, runs), np.median(times[3])))
    lines += [
        "",
        f"Where a cut row's time goes, the same {SWEEP_COUNT} configurations at rest with "
        "a 1 ms horizon, ms per cut row, median (min – max) over the cut rows: the set "
        "(`HorizonAnalysis.polytope`: the hull grown from support points, a batch of LPs "
        "per round) and its scores (`pe.compare` of the built set at the sweep's defaults, "
        "`mvie=False, outer=False`: most of it the coverages' cap unions); its facets; "
        "and a floor no hull of support points "
        "can go below: one batched dual simplex of every cut row's final facet normals "
        "alone (the LPs that certify the facets, without those that find them), per row, "
        f"median of {runs} runs. The budget: 3x the sweep's time per row without a horizon "
        "(issue 34's target), from the first table's run.",
        "",
        "| robot | set ms | scores ms | facets | certifying LPs ms | 3x budget ms |",
        "|---|---|---|---|---|---|",
    ]
    for name, (built, scored, facets, floor), plain in costs:
        if not np.isfinite(floor):  # no row cut: nothing to measure
            lines.append(f"| {name} | no cut row | | | | {3e3 * plain / SWEEP_COUNT:.3g} |")
            continue
        lines.append(
            f"| {name} | {summary(built, 1e3)} | {summary(scored, 1e3)} | "
            f"{np.median(facets):.0f} ({min(facets)} – {max(facets)}) | {floor * 1e3:.3g} | "
            f"{3e3 * plain / SWEEP_COUNT:.3g} |"
        )
    return [*lines, ""]


def _cut_row_costs(robot, q, runs):
    """Per cut row at rest, 1 ms: seconds of the set and of its scores, its facet count,
    and the seconds per row of one batched dual simplex over every row's final facets."""
    built, scored, facets, problems = [], [], [], []
    for row in q:
        analysis = robot.analyze(row, np.zeros_like(row), horizon=1e-3)
        if not analysis.cut.any():
            continue
        start = time.perf_counter()
        polytope = analysis.polytope
        middle = time.perf_counter()
        if analysis.empty_reason is not None:  # (decided with the set)
            continue
        pe.compare(analysis, mvie=False, outer=False)  # the sweep's defaults
        built.append(middle - start)
        scored.append(time.perf_counter() - middle)
        facets.append(len(polytope.A))
        problems.append(_certifying_problems(analysis, polytope.A))
    if not problems:
        return [np.nan], [np.nan], [0], np.nan
    G, lower, upper, d = (np.concatenate(part) for part in zip(*problems, strict=True))
    basis = np.broadcast_to(np.arange(G.shape[-1]), (len(d), G.shape[-1]))
    signs = np.where(d >= 0, 1.0, -1.0)
    floor = min(
        timed_alternately([lambda: dual_simplex(d, G, lower, upper, basis, signs)], runs)[0]
    )
    return built, scored, facets, floor / len(problems)


def _certifying_problems(analysis, normals):
    """The cut cube's LPs along a set's facet normals, as ``cut_set`` poses them."""
    n = analysis.W.shape[0]
    norms = np.linalg.norm(analysis.W, axis=1)
    norms = np.where(norms > 0, norms, 1.0)
    k = len(normals)
    G = np.vstack([np.eye(n), analysis.W / norms[:, None]])
    low = np.concatenate([-np.ones(n), (analysis.qdd_lo - analysis.a0) / norms])
    high = np.concatenate([np.ones(n), (analysis.qdd_hi - analysis.a0) / norms])
    return (
        np.broadcast_to(G, (k, *G.shape)),
        np.broadcast_to(low, (k, 2 * n)),
        np.broadcast_to(high, (k, 2 * n)),
        normals @ analysis.M,
    )


SECTIONS = {"horizon": bench_horizon}
