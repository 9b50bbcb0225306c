"""Benchmarks of the defaults: the sweep and a study as a new user runs them (issue 23).

Sections (h) to (l) of docs/performance.md, run by ``run_benchmarks.py``:

(h) the default sweep beside the same sweep at 64 directions, random arms and the Panda;
(i) the evidence behind the default direction count;
(j) the flop floor of each part of a default sweep, its measured time and their ratio;
(k) a 5,000-configuration random Panda study from the command line, total and sweep;
(l) the profile of a default sweep (its top lines).
"""

from __future__ import annotations

import cProfile
import io
import json
import math
import pstats
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from run_benchmarks import summary, timed_alternately

import polyell as pe
from polyell.comparison import directional
from polyell.geometry.directions import default_direction_count, sphere_directions
from polyell.studies import batch

__all__ = ["SECTIONS"]

ARM_SEED = 2026


def random_arms(count: int, m: int, n: int, seed: int = ARM_SEED):
    """Random arms as a batched Dynamics: J normal, B = A A^T + n I, gravity up to 2 N m."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(count, m, n))
    A = rng.normal(size=(count, n, n))
    B = A @ np.swapaxes(A, 1, 2) + n * np.eye(n)
    g = 2.0 * rng.normal(size=(count, n))
    return pe.Dynamics(J, B, g), rng.uniform(20.0, 40.0, n)


def _ratio(slow: list[float], fast: list[float]) -> str:
    paired = np.asarray(slow) / np.asarray(fast)
    median = np.median(slow) / np.median(fast)
    return f"{median:.2f}× (run by run {paired.min():.2f}–{paired.max():.2f}×)"


def bench_defaults(repeats: int) -> list[str]:
    """(h) ``pe.sweep`` at its defaults beside the same sweep at 64 directions."""
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    q = np.random.default_rng(3).uniform(low, high, (10_000, panda.nq))
    cases = [
        ("random 3x7 arms (batched Dynamics), 20,000", *random_arms(20_000, 3, 7), None),
        ("random 6x7 arms (batched Dynamics), 4,000", *random_arms(4_000, 6, 7), None),
        ("Panda robot, Pinocchio's dynamics included, 10,000", panda, None, q),
    ]
    rows, verdicts = [], []
    for name, source, tau_max, configurations in cases:
        count = len(source) if configurations is None else len(configurations)
        m = 3 if configurations is not None else source.m

        def run(directions, source=source, tau_max=tau_max, configurations=configurations):
            return lambda: pe.sweep(source, configurations, tau_max, directions=directions)

        default, at_64 = timed_alternately([run(None), run(64)], repeats)
        rates = [count / t for t in default], [count / t for t in at_64]
        rows.append(
            f"| {name} | {default_direction_count(m):,} | {summary(rates[0], digits=4)} | "
            f"{summary(rates[1], digits=4)} | {_ratio(default, at_64)} |"
        )
        verdicts.append((name, np.median(rates[0]), np.median(default) / np.median(at_64)))
    first = verdicts[0]
    return [
        "## (h) The default sweep",
        "",
        "`pe.sweep(source, tau_max=...)` with every other argument at its default (the "
        "default scores and the default direction set) beside the same call with "
        "`directions=64`, timed alternately on one core, "
        f"{repeats} repeats. Random arms: J normal, B = A Aᵀ + n I, gravity torques up to "
        "2 N m against limits of 20–40 N m (`tests/benchmarks/speed_defaults.py`).",
        "",
        "| configurations | default directions | default: configurations / s | "
        "64 directions: configurations / s | time, default / 64 |",
        "|---|---|---|---|---|",
        *rows,
        "",
        f"Targets on random 3x7 arms: at least 10,000 configurations / s (measured "
        f"{first[1]:,.0f}) and at most 2× the 64-direction sweep (measured {first[2]:.2f}×).",
        "",
    ]


STATISTICS = (
    "direction_error_mean",
    "direction_error_rms",
    "direction_bias",
    "direction_error_max",
)


def bench_directions(repeats: int) -> list[str]:
    """(i) How the direction statistics change with the direction count."""
    del repeats  # one run: the numbers are deterministic
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    q = np.random.default_rng(5).uniform(low, high, (1_000, panda.nq))
    reference = 16_384
    cases = [
        ("random 3x7 arms (1,000)", *random_arms(1_000, 3, 7), None, (64, 256, 1_000)),
        ("Panda (1,000 random configurations)", panda, None, q, (64, 256, 1_000)),
        ("random 6x7 arms (300)", *random_arms(300, 6, 7), None, (256, 2_000)),
    ]
    rows, at_256 = [], []
    for name, source, tau_max, configurations, counts in cases:
        frames = {
            k: pe.sweep(source, configurations, tau_max, directions=k, scores=STATISTICS)
            for k in (*counts, reference)
        }
        for k in counts:
            cells = []
            for statistic in STATISTICS:
                change = np.concatenate(
                    [
                        np.abs(
                            frames[k][f"{kind}_{statistic}"]
                            - frames[reference][f"{kind}_{statistic}"]
                        )
                        for kind in ("chiacchio", "yoshikawa")
                    ]
                )
                change = change[np.isfinite(change)]
                if k == 256 and "6x7" not in name and statistic != "direction_error_max":
                    at_256.append(change)
                p95 = np.percentile(change, 95)
                cells.append(f"{np.median(change):.1e} / {p95:.1e} / {change.max():.1e}")
            rows.append(f"| {name} | {k:,} | " + " | ".join(cells) + " |")
    pooled = np.concatenate(at_256)
    worst = np.percentile(pooled, [50, 95, 100])
    return [
        "## (i) The direction count",
        "",
        "How much the direction statistics of both ellipsoids change between k directions of "
        f"the default set and {reference:,} (absolute change of the relative errors: median / "
        "95th percentile / largest over configurations and both ellipsoids). The errors "
        "themselves are of order 0.1–1.",
        "",
        "| configurations | k | mean | RMS | bias | max |",
        "|---|---|---|---|---|---|",
        *rows,
        "",
        "The mean, RMS and bias are integrals over the sphere, which the Fibonacci lattice "
        "resolves fast: at 256 directions in 3-D they are within "
        f"{worst[0]:.1e} (median), {worst[1]:.1e} (95th percentile) and {worst[2]:.1e} (at "
        "worst) of their converged values -- 0.05 percentage points for 19 tables in 20 -- and "
        "256 is the 3-D default (1,000 before; about a third of the time, section (h)). "
        "The max is a sampled supremum and converges slowly at any count; "
        "pass more directions (`directions=1000` or more) when it is the number you "
        "report. In 6-D the default stays 2,000.",
        "",
    ]


def _floor_flops(m: int, n: int, k: int) -> dict[str, float]:
    """Floating-point operations per configuration of each part of a default sweep.

    Multiply-adds count 2, divisions and square roots 1.  The non-directional part counts
    what cannot be avoided: the Cholesky solve for M (n^3/3 + 2 m n^2), the SVD of M and of
    F (each about 4 m^2 n + 8 m^3), the facets (a normal of m^2 and an offset of 2 m n per
    pair), and the inscribed scales of both ellipsoids (2 m^2 per pair each).
    """
    C = math.comb(n, m - 1)
    svd = 4 * m * m * n + 8 * m**3
    return {
        "the rest (M, SVDs, facets, volumes, scales)": n**3 / 3
        + 2 * m * n * n
        + 2 * svd
        + C * (m * m + 2 * m * n)
        + 2 * 2 * C * m * m,
        f"polytope far ends (gauge), {k} directions": 2 * C * k * (2 * m + 1),
        f"ellipsoid far ends, both, {k} directions": 2 * k * (2 * m * m + 4 * m + 7),
        f"direction statistics, both, {k} directions": 2 * 8 * k,
    }


def _peak_rate() -> float:
    """This core's floating-point rate on a large dgemm (flop / s): the practical peak."""
    a = np.random.default_rng(0).normal(size=(1_000, 1_000))
    best = math.inf
    for _ in range(5):
        start = time.perf_counter()
        a @ a
        best = min(best, time.perf_counter() - start)
    return 2e9 / best


def bench_floor(repeats: int) -> list[str]:
    """(j) The flop floor of each part of a default sweep, its measured time, their ratio."""
    repeats = 5
    peak = _peak_rate()
    lines = [
        "## (j) The flop floor of a default sweep",
        "",
        "Each part of `pe.sweep` at its defaults, per configuration: the floating-point "
        "operations it cannot avoid (`_floor_flops` in `tests/benchmarks/speed_defaults.py` "
        "states the counts), the time they take at this core's dgemm rate "
        f"({peak / 1e9:.1f} GFLOP/s on 1000x1000, one thread), the measured time (median "
        f"(min – max) of {repeats} runs on 4,000 random arms; the directional parts timed "
        "on the arrays a sweep passes them) and the ratio of the two.",
        "",
    ]
    for m, n in ((3, 7), (6, 7)):
        dyn, tau = random_arms(4_000, m, n)
        k = default_direction_count(m)
        T = sphere_directions(k, m)
        captured = {}
        original = directional.direction_scores

        def spy(*args, original=original, captured=captured):
            captured.setdefault("args", args)
            return original(*args)

        batch.direction_scores = spy  # the arrays of the first block, as the sweep makes them
        try:
            batch.batch_rows(dyn[:512], tau, -tau, T)
        finally:
            batch.direction_scores = original
        normals, h, midpoints, slack, floor, ellipsoids, _ = captured["args"]
        rows = len(normals)
        Tt = np.ascontiguousarray(T.T)

        def rest(dyn=dyn, tau=tau, m=m):
            batch.batch_rows(dyn, tau, -tau, sphere_directions(1, m))

        def gauge(normals=normals, h=h, midpoints=midpoints, Tt=Tt, slack=slack, floor=floor):
            directional.polytope_far_ends(normals, h, midpoints, Tt, slack, floor)

        def ends(ellipsoids=ellipsoids, Tt=Tt):
            for center, axes, semi in ellipsoids:
                directional._ellipsoid_far_ends(center, axes, semi, Tt)

        hi_p, feasible_p = directional.polytope_far_ends(normals, h, midpoints, Tt, slack, floor)
        far = [directional._ellipsoid_far_ends(*e, Tt) for e in ellipsoids]
        scale = 1.0 / np.abs(hi_p)

        def statistics(far=far, hi_p=hi_p, feasible_p=feasible_p, scale=scale):
            for hi_e, feasible_e in far:
                directional._statistics(hi_e, feasible_e, hi_p, feasible_p, scale)

        def total(dyn=dyn, tau=tau, T=T):
            batch.batch_rows(dyn, tau, -tau, T)

        times = timed_alternately([rest, gauge, ends, statistics, total], repeats)
        per = [len(dyn), rows, rows, rows, len(dyn)]
        flops = _floor_flops(m, n, k)
        lines += [
            f"{m}x{n} arms, {k} directions ({math.comb(n, m - 1)} facet pairs):",
            "",
            "| part | floor, flop | floor, µs | measured, µs | measured / floor |",
            "|---|---|---|---|---|",
        ]
        total_flops = sum(flops.values())
        for (name, count), t, size in zip(flops.items(), times[:4], per[:4], strict=True):
            measured = np.asarray(t) / size * 1e6
            floor = count / peak * 1e6
            lines.append(
                f"| {name} | {count:,.0f} | {floor:.2f} | {summary(measured)} | "
                f"{np.median(measured) / floor:.0f}× |"
            )
        measured = np.asarray(times[4]) / per[4] * 1e6
        floor = total_flops / peak * 1e6
        lines += [
            f"| **the whole sweep (`batch_rows`)** | {total_flops:,.0f} | {floor:.2f} | "
            f"{summary(measured)} | {np.median(measured) / floor:.0f}× |",
            "",
        ]
    lines += [
        "The directional parts take a few to a few tens of times their flop floor: each "
        "numpy operation makes one pass over a (rows, directions) array held in cache, where "
        "the floor assumes every number stays in a register. The rest is numpy's cost per "
        "call on small matrices (SVDs and solves of 3x7 and 7x7 matrices, in blocks of 512 "
        "configurations), which only a compiled kernel would remove.",
        "",
    ]
    return lines


STUDY = """\
title = "Panda, 5,000 random configurations"
[robot]
library = "panda"
[random]
count = 5000
seed = 1
"""


def bench_study(repeats: int) -> list[str]:
    """(k) A 5,000-configuration random Panda study from the command line."""
    repeats = max(repeats, 5)
    totals, sweeps, insides = [], [], []
    with tempfile.TemporaryDirectory() as folder:
        spec = Path(folder) / "panda.toml"
        spec.write_text(STUDY)
        for index in range(repeats):
            out = Path(folder) / f"out{index}"
            start = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "polyell", "study", str(spec), "--out", str(out)],
                check=True,
                capture_output=True,
            )
            totals.append(time.perf_counter() - start)
            seconds = json.loads((out / "manifest.json").read_text())["seconds"]
            sweeps.append(seconds["sweep"])
            insides.append(seconds["total"])
    ratio = np.asarray(totals) / np.asarray(sweeps)
    return [
        "## (k) A study from the command line",
        "",
        "`polyell study panda.toml --out DIR` in a fresh process (`[robot] library = "
        '"panda"`, `[random] count = 5000`, everything else at its defaults: the MVIE and the '
        "outer ellipsoid, 256 directions, results.csv, the summary tables), "
        f"{repeats} runs. The sweep's time is the one the study writes into its "
        "`manifest.json` (`seconds.sweep`: Pinocchio's dynamics and every score).",
        "",
        "| | seconds, median (min – max) |",
        "|---|---|",
        f"| the whole command (interpreter, imports, outputs) | {summary(totals)} |",
        f"| `run_study` (the manifest's `seconds.total`) | {summary(insides)} |",
        f"| the sweep inside it | {summary(sweeps)} |",
        "",
        f"Whole command / sweep: **{np.median(ratio):.2f}×** (run by run "
        f"{ratio.min():.2f}–{ratio.max():.2f}×; target at most 2×).",
        "",
    ]


def bench_profile(repeats: int) -> list[str]:
    """(l) Where a default sweep spends its time: the profile's top lines."""
    del repeats
    dyn, tau = random_arms(20_000, 3, 7)
    pe.sweep(dyn[:100], tau_max=tau)
    profile = cProfile.Profile()
    profile.enable()
    pe.sweep(dyn, tau_max=tau)
    profile.disable()
    text = io.StringIO()
    pstats.Stats(profile, stream=text).sort_stats("tottime").print_stats(12)
    body = text.getvalue()
    body = body[body.index("ncalls") :].rstrip()
    body = body.replace(str(Path(pe.__file__).parents[1]) + "/", "")
    body = "\n".join(line[:150] for line in body.splitlines())
    return [
        "## (l) Profile of a default sweep",
        "",
        "`cProfile` of `pe.sweep(dyn, tau_max=tau)` on 20,000 random 3x7 arms, its 12 most "
        "expensive functions by own time (the profiler's overhead included):",
        "",
        "```text",
        body,
        "```",
        "",
    ]


SECTIONS = {
    "defaults": bench_defaults,
    "directions": bench_directions,
    "floor": bench_floor,
    "study": bench_study,
    "profile": bench_profile,
}
