"""Benchmark of the posture choice (issue 22): section (m) of docs/performance.md.

A 7-joint arm (the Panda, 3-D position task), 1,000 postures on the self-motion of one
task point, every index (the polytope, both definitions, the MVIE and the outer
ellipsoid): the time of ``pe.posture_choice``, Pinocchio's dynamics included, the sampling
of the self-motion excluded (reported beside it).
"""

from __future__ import annotations

import time

import numpy as np

import polyell as pe

__all__ = ["SECTIONS", "bench_posture"]

POSTURES = 1000
Q0 = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
DIRECTION = np.array([1.0, 0.0, 0.0])


def _spread(values: list[float]) -> str:
    v = np.asarray(values)
    return f"{np.median(v):.3g} ({v.min():.3g} – {v.max():.3g})"


def bench_posture(repeats: int = 5) -> list[str]:
    """Markdown lines of section (m): median and spread of ``repeats`` runs."""
    panda = pe.robots.load("panda")
    start = time.perf_counter()
    motion = pe.self_motion(panda, Q0, count=POSTURES, seed=0)
    sampling = time.perf_counter() - start
    pe.posture_choice(panda, motion, direction=DIRECTION)  # warm-up (imports)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        choice = pe.posture_choice(panda, motion, direction=DIRECTION)
        times.append(time.perf_counter() - start)
    classic = choice.table.loc[("yoshikawa", "limit"), "regret"]
    new = choice.table.loc[("chiacchio", "limit"), "regret"]
    return [
        "## (m) Posture choice",
        "",
        f"`pe.posture_choice` on the Panda (7 joints, 3-D position task), {POSTURES:,} postures "
        "of one self-motion (`pe.self_motion`, seed 0), every index: the polytope's limits "
        "along x, radius and volume, and those of the new, classic, MVIE and outer "
        f"ellipsoids; one core, {repeats} runs.",
        "",
        "| | seconds, median (min – max) |",
        "| :-- | --: |",
        f"| `posture_choice`, {POSTURES:,} postures, all indices | {_spread(times)} |",
        f"| (sampling the self-motion, once) | {sampling:.3g} |",
        "",
        f"Target: under 2 s. Regret of the pick along x: classic {100 * classic:.1f} %, "
        f"new {100 * new:.1f} %.",
        "",
    ]


SECTIONS = {"posture": bench_posture}


if __name__ == "__main__":
    print("\n".join(bench_posture()))
