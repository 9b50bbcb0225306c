"""Benchmarks of polyell against the alternatives, side by side in one run.

Not part of the test suite (no wall-clock limit belongs in a unit test).  Run with the
bench extra installed (pycapacity, psutil)::

    pip install -e '.[test,bench]'
    python tests/benchmarks/run_benchmarks.py            # writes docs/performance.md

Every timing is repeated; the report gives the median and the spread (min-max) of the
repeats, and the machine it ran on.
"""

from __future__ import annotations

import os

# One BLAS thread: "per core" numbers are per core, and Dask workers do not oversubscribe.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import re  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pycapacity.robot as capacity  # noqa: E402
from scipy.spatial import ConvexHull  # noqa: E402

import polyell as pe  # noqa: E402
from polyell.geometry.directions import sphere_directions  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def timed(function, repeats: int) -> list[float]:
    """Wall-clock seconds of each of ``repeats`` calls (after one warm-up call)."""
    function()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return times


def timed_alternately(functions, repeats: int) -> list[list[float]]:
    """Like :func:`timed` for several functions, their calls interleaved repeat by repeat.

    The machine's speed drifts between runs; interleaving puts the drift on all of them.
    """
    for function in functions:
        function()
    times: list[list[float]] = [[] for _ in functions]
    for _ in range(repeats):
        for function, record in zip(functions, times, strict=True):
            start = time.perf_counter()
            function()
            record.append(time.perf_counter() - start)
    return times


def summary(values: list[float], scale: float = 1.0, digits: int = 3) -> str:
    v = np.asarray(values) * scale
    return f"{np.median(v):.{digits}g} ({np.min(v):.{digits}g} – {np.max(v):.{digits}g})"


def machine() -> str:
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, polyell {pe.__version__}"
    )


def panda_configurations(count: int, seed: int) -> np.ndarray:
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    return np.random.default_rng(seed).uniform(low, high, (count, panda.nq))


def cpu_timed_alternately(functions, repeats: int) -> list[list[float]]:
    """CPU seconds of each of ``repeats`` calls of every function, interleaved, on one core.

    As :func:`timed_alternately` (a warm-up call each, then the functions in turn, repeat by
    repeat), but in this process's CPU time (``time.process_time``): the time other
    processes take on a loaded machine is not counted.  The process is pinned to one core
    while it runs (numpy already has one BLAS thread).
    """
    pinned = hasattr(os, "sched_getaffinity")
    if pinned:
        cores = os.sched_getaffinity(0)
        os.sched_setaffinity(0, {max(cores)})
    try:
        for function in functions:
            function()
        times: list[list[float]] = [[] for _ in functions]
        for _ in range(repeats):
            for function, record in zip(functions, times, strict=True):
                start = time.process_time()
                function()
                record.append(time.process_time() - start)
    finally:
        if pinned:
            os.sched_setaffinity(0, cores)
    return times


#: The posture of the README's Panda examples.
README_POSTURE = (0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8)
#: The command that regenerates sections (a) and (n), as their text states it.
POLYTOPE_COMMAND = (
    "OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python tests/benchmarks/run_benchmarks.py "
    "--repeats 6 --sections polytope capacities --memory"
)


def stage_times(make_analysis, inputs, repeats: int) -> np.ndarray:
    """Where one polytope's time goes: µs per call of each stage, median over every call.

    ``make_analysis(x)`` builds the analysis of one configuration (``pe.analyze``); the
    stages are that call, ``analysis.polytope`` and the set's ``vertices``, ``A`` and
    ``b``, timed in turn in this process's CPU time (``time.process_time``, whose own
    calls add about 1 µs to the total), after a warm-up pass, configuration after
    configuration as the benchmark calls them.  Returns (analysis, set, vertices and
    facets, total).
    """
    clock = time.process_time
    times = []
    for repeat in range(repeats + 1):
        for x in inputs:
            start = clock()
            analysis = make_analysis(x)
            built = clock()
            P = analysis.polytope
            described = clock()
            P.vertices, P.A, P.b  # noqa: B018
            end = clock()
            if repeat:  # the first pass warms up
                times.append((built - start, described - built, end - described, end - start))
    return np.median(np.array(times), axis=0) * 1e6


def below_target(rows: list[tuple[str, float, float]], target: float = 20.0) -> str:
    """A sentence naming the rows below ``target``x and the time per call that reaches it.

    ``rows``: (label, polyell's and pycapacity's median ms per configuration).
    """
    short = [
        f"{label}, {ours:.3f} ms where {target:.0f}× needs {theirs / target:.3f} ms"
        for label, ours, theirs in rows
        if theirs / ours < target
    ]
    if not short:
        return f"Every row at {target:.0f}× or more in this run."
    return f"Below {target:.0f}× in this run: " + "; ".join(short) + "."


def stage_row(label: str, stages: np.ndarray) -> str:
    """A table row of :func:`stage_times`: ``| label | analysis | set | ... | total |``."""
    return f"| {label} | " + " | ".join(f"{value:.0f}" for value in stages) + " |"


def random_dynamics(m: int, n: int, count: int, seed: int) -> list[pe.Dynamics]:
    """Seeded random arms: J normal, B = A A^T + n I, g = 0.05 N(0, 1)."""
    rng = np.random.default_rng(seed)
    arms = []
    for _ in range(count):
        A = rng.normal(size=(n, n))
        arms.append(
            pe.Dynamics(rng.normal(size=(m, n)), A @ A.T + n * np.eye(n), 0.05 * rng.normal(size=n))
        )
    return arms


def bench_polytope(repeats: int) -> list[str]:
    panda = pe.robots.load("panda")
    rng = np.random.default_rng(4)
    high = rng.uniform(20.0, 40.0, 7)
    cases = {  # the arm's matrices built before timing, as pycapacity gets its arrays
        "Panda, 20 random configurations": (
            [panda.dynamics(q) for q in panda_configurations(20, seed=1)],
            panda.tau_max,
            panda.tau_min,
        ),
        "Panda at the README's q": (
            [panda.dynamics(README_POSTURE)] * 20,
            panda.tau_max,
            panda.tau_min,
        ),
        "random 3x7 arms (20)": (
            random_dynamics(3, 7, 20, seed=5),
            high,
            -high * rng.uniform(0.7, 1.0, 7),
        ),
    }
    rows, stages, speeds, worst = [], [], [], 0.0
    for label, (dynamics, tau_max, tau_min) in cases.items():

        def ours(dynamics=dynamics, tau_max=tau_max, tau_min=tau_min):
            for dyn in dynamics:
                P = pe.analyze(dyn, tau_max, tau_min).polytope
                P.vertices, P.A, P.b  # noqa: B018

        def theirs(dynamics=dynamics, tau_max=tau_max, tau_min=tau_min):
            for dyn in dynamics:
                capacity.acceleration_polytope(dyn.J, dyn.B, tau_max, tau_min, t_bias=dyn.g)

        mine, other = cpu_timed_alternately([ours, theirs], 3 * repeats)
        per = 1e3 / len(dynamics)
        speedup = np.median(other) / np.median(mine)
        rows.append(f"| {label} | {summary(mine, per)} | {summary(other, per)} | {speedup:.1f}× |")
        speeds.append((label, np.median(mine) * per, np.median(other) * per))
        stages.append(
            stage_row(
                label,
                stage_times(
                    lambda dyn, tau_max=tau_max, tau_min=tau_min: pe.analyze(dyn, tau_max, tau_min),
                    dynamics,
                    repeats,
                ),
            )
        )
        for dyn in dynamics:
            P = pe.analyze(dyn, tau_max, tau_min).polytope
            reference = capacity.acceleration_polytope(dyn.J, dyn.B, tau_max, tau_min, t_bias=dyn.g)
            volume = ConvexHull(np.asarray(reference.vertices).T).volume
            worst = max(worst, abs(P.volume - volume) / volume)
    return [
        "## (a) Polytope of a 7-joint arm, 3-D linear task",
        "",
        "Each call builds the acceleration polytope from J, B, g and the torque limits and "
        "gives its vertices and facets (polyell: `pe.analyze(dyn, tau_max, tau_min).polytope` "
        "with `vertices`, `A`, `b`, the `Dynamics` built before timing, as pycapacity gets its "
        f"arrays; pycapacity {capacity_version()}: `robot.acceleration_polytope`). Franka Panda "
        "(fingers locked) at 20 random configurations and at the README's q = (0, -0.5, 0, "
        "-2, 0, 1.6, 0.8) with its URDF limits; random 3x7 arms (J normal, B = A Aᵀ + 7 I, "
        "g = 0.05 N(0, 1), asymmetric limits of 20–40 N m). The two are timed alternately, "
        f"{3 * repeats} repeats each, in CPU time on one core (`time.process_time`), by "
        f"`{POLYTOPE_COMMAND}`.",
        "",
        "| arms | polyell ms/config | pycapacity ms/config | speed-up |",
        "|---|---|---|---|",
        *rows,
        "",
        "Target: 20×. " + below_target(speeds) + " Same sets: the largest relative "
        "difference between polyell's zonotope volume and the convex-hull volume of "
        f"pycapacity's vertices is {worst:.1e} (target 1e-9).",
        "",
        "Where polyell's time goes, µs per call (median over every call of "
        f"{repeats} passes after a warm-up, CPU time, without pycapacity's calls in "
        "between, so below the table's times): `pe.analyze` (the limits checked, M, xg "
        "and the SVD of eq. 35), `.polytope` (the set built), its `vertices`, `A` and `b` "
        "(the facets and vertices enumerated).",
        "",
        "| arms | analysis | set | vertices and facets | total |",
        "|---|---|---|---|---|",
        *stages,
        "",
    ]


def capacity_version() -> str:
    from importlib.metadata import version

    return version("pycapacity")


def bench_limits(repeats: int) -> list[str]:
    panda = pe.robots.load("panda")
    q = panda_configurations(1, seed=3)[0]
    P = pe.analyze(panda.dynamics(q), panda.tau_max).polytope
    T = sphere_directions(1000, 3)
    closed = timed(lambda: P.limits(T), repeats)
    sample = T[::20]  # 50 directions: one LP pair each is slow
    lp = timed(lambda: P.limits(sample, method="lp"), max(1, repeats // 3))
    a, b = P.limits(sample), P.limits(sample, method="lp")
    scale = np.maximum(np.abs(b.hi), 1.0)
    worst = max(np.max(np.abs(a.hi - b.hi) / scale), np.max(np.abs(a.lo - b.lo) / scale))
    per_closed = np.median(closed) / len(T)
    per_lp = np.median(lp) / len(sample)
    return [
        "## (b) Directional limits, 1000 directions",
        "",
        "Panda polytope; polyell's closed form (every facet against every line, vectorised) on "
        "1000 Fibonacci directions vs two LPs per direction (cvxpy + Clarabel, parameters "
        "reused) on 50 of them.",
        "",
        "| | µs per direction, median (min – max) |",
        "|---|---|",
        f"| closed form | {summary(closed, 1e6 / len(T))} |",
        f"| LP per direction | {summary(lp, 1e6 / len(sample))} |",
        "",
        f"Speed-up per direction: **{per_lp / per_closed:,.0f}×** (target 1000×). Largest "
        f"relative difference on the 50 shared directions: {worst:.1e} (target 1e-9).",
        "",
    ]


def bench_sweep(repeats: int) -> list[str]:
    from dask.distributed import LocalCluster

    panda = pe.robots.load("panda")
    Q = panda_configurations(80_000, seed=4)
    directional = (s for s in pe.SCORE_NAMES if s.startswith("direction"))
    scores = ("volume", "inscribed_scale", "coverage", *directional)
    half = Q[:40_000]
    dyn = panda.dynamics(half)
    batched, in_process = timed_alternately(
        [
            lambda: pe.sweep(
                dyn, scores=scores, tau_max=panda.tau_max, chunk=10_000, directions=64
            ),
            lambda: pe.sweep(panda, half, scores=scores, chunk=10_000, directions=64),
        ],
        repeats,
    )

    def on(cluster, parquet: bool = False):
        address = cluster.scheduler_address

        def run() -> None:
            if not parquet:  # the frames come back to this process
                pe.sweep(panda, Q, scores=scores, chunk=10_000, scheduler=address, directions=64)
                return
            with tempfile.TemporaryDirectory() as folder:  # the workers write the parts
                pe.sweep(
                    panda,
                    Q,
                    scores=scores,
                    chunk=10_000,
                    scheduler=address,
                    out=folder,
                    directions=64,
                )

        return run

    with pe.local_cluster(1) as single, pe.local_cluster(2) as double:
        one_worker, two_workers = timed_alternately([on(single), on(double)], repeats)
        one_parquet, two_parquet = timed_alternately(
            [on(single, parquet=True), on(double, parquet=True)], repeats
        )
        Qm = Q[:60]
        address = double.scheduler_address
        mvie_serial = timed(lambda: pe.sweep(panda, Qm, mvie=True, chunk=30, directions=64), 1)
        mvie_dask = timed(
            lambda: pe.sweep(panda, Qm, mvie=True, chunk=30, scheduler=address, directions=64), 1
        )
    options = {"threads_per_worker": 1, "processes": True, "host": "127.0.0.1"}
    with LocalCluster(n_workers=1, dashboard_address=None, **options) as default:
        default_worker = timed(on(default), max(3, repeats // 2))

    def rate(times: list[float], k: int) -> str:
        return summary([k / t for t in times], digits=4)

    def scaling(one: list[float], two: list[float]) -> str:
        paired = np.asarray(one) / np.asarray(two)
        return (
            f"**{np.median(one) / np.median(two):.2f}×** "
            f"(run by run {paired.min():.2f}–{paired.max():.2f}×)"
        )

    mvie_slowdown = (len(half) / np.median(batched)) / (60 / np.median(mvie_serial))
    return [
        "## (c) Sweep throughput",
        "",
        "Panda, random configurations within the joint limits; volume, inscribed scale, "
        "coverage and 64-direction errors for both ellipsoids.  'Batched Dynamics' starts from "
        "precomputed J, B, g (the polyell part alone); 'robot' includes Pinocchio's dynamics, "
        "one call per configuration.  The Dask clusters are `pe.local_cluster(1)` and "
        "`pe.local_cluster(2)` (one single-threaded worker process per core, on loopback), "
        "both running, timed alternately on 80,000 configurations in chunks of 10,000.",
        "",
        "| source | configurations / s, median (min – max) |",
        "|---|---|",
        f"| robot, 1 process (40,000 in chunks of 10,000) | {rate(in_process, len(half))} |",
        f"| batched Dynamics, 1 process (the same) | {rate(batched, len(half))} |",
        f"| robot, local Dask cluster, 1 worker | {rate(one_worker, len(Q))} |",
        f"| robot, local Dask cluster, 2 workers | {rate(two_workers, len(Q))} |",
        f"| robot, 1 worker, to a Parquet dataset | {rate(one_parquet, len(Q))} |",
        f"| robot, 2 workers, to a Parquet dataset | {rate(two_parquet, len(Q))} |",
        "| robot, 1 worker started with Dask's default environment (`MALLOC_TRIM_THRESHOLD_`) "
        f"| {rate(default_worker, len(Q))} |",
        f"| with MVIE, 1 process (60 configurations) | {rate(mvie_serial, 60)} |",
        f"| with MVIE, 2 Dask workers | {rate(mvie_dask, 60)} |",
        "",
        "2 Dask workers vs 1 Dask worker (target 1.7×): "
        f"{scaling(one_worker, two_workers)} returning the frames to this process, "
        f"{scaling(one_parquet, two_parquet)} writing a Parquet dataset (each worker writes "
        "its parts; the mode of large studies). A worker started with Dask's default "
        "`MALLOC_TRIM_THRESHOLD_=65536` is "
        f"{np.median(default_worker) / np.median(one_worker):.2f}× slower than one of "
        "`pe.local_cluster` (numpy's temporaries are then fresh page-faulting mappings). MVIE: "
        f"{np.median(mvie_serial) / np.median(mvie_dask):.2f}× faster on 2 workers than in this "
        "process, and about "
        f"{mvie_slowdown:,.0f}"
        "× slower than the batched path. Per core, the batched path targets 20,000 "
        "configurations / s.",
        "",
    ]


MEMORY_RUN = """
import resource, sys, time
import polyell as pe
panda = pe.robots.load("panda")
low, high = panda.position_limits
count = int(sys.argv[2])
start = time.perf_counter()
pe.sweep(panda, pe.random_configurations(count, low, high, seed=7), out=sys.argv[1], chunk=20_000,
         directions=64)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, time.perf_counter() - start)
"""


def bench_mvie(repeats: int) -> list[str]:
    """(e) The MVIE in sweeps: batched log-det solver against cvxpy + Clarabel, per core."""
    from polyell.geometry.mvie import max_volume_inscribed_ellipsoid

    panda = pe.robots.load("panda")
    Q = panda_configurations(4096, seed=12)
    dyn = panda.dynamics(Q)
    scores = ("coverage", "mvie_ratio")
    polytopes = [pe.analyze(dyn[k], panda.tau_max).polytope for k in range(24)]

    def batched() -> None:
        pe.sweep(dyn, tau_max=panda.tau_max, mvie=True, scores=scores, chunk=4096, directions=64)

    def without() -> None:
        pe.sweep(dyn, tau_max=panda.tau_max, scores=("coverage",), chunk=4096, directions=64)

    def with_outer() -> None:
        pe.sweep(
            dyn,
            tau_max=panda.tau_max,
            mvie=True,
            outer=True,
            scores=(*scores, "outer_ratio", "enclosing_scale"),
            chunk=4096,
            directions=64,
        )

    failures = set()

    def by_cvxpy() -> None:
        for k, P in enumerate(polytopes):
            try:
                max_volume_inscribed_ellipsoid(P, method="cvxpy")
            except pe.SolverError:  # Clarabel "inaccurate": counted, and timed all the same
                failures.add(k)

    def one_by_one() -> None:
        for P in polytopes:
            max_volume_inscribed_ellipsoid(P)

    with_mvie, no_mvie, both, cvx, single = timed_alternately(
        [batched, without, with_outer, by_cvxpy, one_by_one], max(3, repeats // 2)
    )

    def rate(times: list[float], k: int) -> str:
        return summary([k / t for t in times], digits=4)

    agreement = max(
        abs(
            max_volume_inscribed_ellipsoid(P).volume
            / max_volume_inscribed_ellipsoid(P, method="cvxpy").volume
            - 1.0
        )
        for k, P in enumerate(polytopes)
        if k not in failures
    )
    speedup = (np.median(cvx) / len(polytopes)) / (np.median(with_mvie) / len(Q))
    return [
        "## (e) The MVIE in sweeps",
        "",
        "Panda, linear task: the maximum-volume inscribed ellipsoid by the batched primal-dual "
        "interior-point solver of `pe.sweep` (whitened coordinates, certified gap 1e-8 in log "
        "det), against "
        "the same program through cvxpy + Clarabel one configuration at a time (the path of "
        "earlier versions), timed alternately.",
        "",
        "| path | configurations / s, median (min – max) |",
        "|---|---|",
        f"| sweep with MVIE scores, batched (4,096) | {rate(with_mvie, len(Q))} |",
        f"| sweep without MVIE (the same 4,096) | {rate(no_mvie, len(Q))} |",
        f"| sweep with MVIE and outer ellipsoid, enclosing scales (4,096) | {rate(both, len(Q))} |",
        f"| MVIE alone, the dedicated solver one at a time (24) | {rate(single, len(polytopes))} |",
        f"| MVIE alone, cvxpy + Clarabel one at a time (24) | {rate(cvx, len(polytopes))} |",
        "",
        f"Batched MVIE vs cvxpy: **{speedup:,.0f}×** "
        f"(target: 5,000 configurations / s with the MVIE scores on one core). Largest "
        f"relative volume difference to Clarabel: {agreement:.1e}, on the "
        f"{len(polytopes) - len(failures)} of {len(polytopes)} configurations where Clarabel "
        "certified an optimum (it stopped 'inaccurate' on the others; the dedicated solver "
        "certified every one).",
        "",
    ]


def bench_along(repeats: int) -> list[str]:
    """(f) Directional limits along a path, one direction per configuration."""
    panda = pe.robots.load("panda")
    Q = panda_configurations(20_000, seed=13)
    dyn = panda.dynamics(Q)
    rng = np.random.default_rng(14)
    T = rng.normal(size=(len(Q), 3))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    few = 300

    def batched() -> None:
        pe.limits_along(dyn, None, T, panda.tau_max)

    def from_robot() -> None:
        pe.limits_along(panda, Q, T)

    def per_row() -> None:
        for k in range(few):
            analysis = pe.analyze(dyn[k], panda.tau_max)
            analysis.polytope.limits(T[k])
            for kind in ("chiacchio", "yoshikawa"):
                analysis.ellipsoid(kind).limits(T[k])

    along, robot, rows = timed_alternately([batched, from_robot, per_row], repeats)

    def rate(times: list[float], k: int) -> str:
        return summary([k / t for t in times], digits=4)

    speedup = (np.median(rows) / few) / (np.median(along) / len(Q))
    return [
        "## (f) Directional limits along a path",
        "",
        "Panda, one unit direction per configuration (a path's tangents): the polytope's and "
        "both ellipsoids' intervals by `pe.limits_along` (vectorised, from precomputed J, B, g) "
        "and by the per-configuration API (`analyze`, `polytope.limits`, `ellipsoid(...).limits`), "
        "timed alternately.",
        "",
        "| path | rows / s, median (min – max) |",
        "|---|---|",
        f"| `pe.limits_along` from precomputed J, B, g (20,000 rows) | {rate(along, len(Q))} |",
        "| `pe.limits_along` from the robot, Pinocchio's dynamics included (the same) | "
        f"{rate(robot, len(Q))} |",
        f"| per row ({few} rows) | {rate(rows, few)} |",
        "",
        f"Speed-up **{speedup:,.0f}×** (target: 100,000 rows / s on one core).",
        "",
    ]


def bench_startup(repeats: int) -> list[str]:
    """(g) Start-up of the command line (a fresh process each time)."""
    polyell = str(Path(sys.executable).parent / "polyell")
    commands = {
        "`python -c pass` (the interpreter alone)": [sys.executable, "-c", "pass"],
        "`polyell --help`": [polyell, "--help"],
        "`polyell analyze --no-mvie`": [polyell, "analyze", "--no-mvie"],
        "`polyell analyze` (with the MVIE)": [polyell, "analyze"],
    }

    def runner(command: list[str]):
        return lambda: subprocess.run(command, check=True, capture_output=True)

    times = timed_alternately([runner(c) for c in commands.values()], repeats)
    rows = [f"| {name} | {summary(t, 1e3)} |" for name, t in zip(commands, times, strict=True)]
    first = []
    for _ in range(max(3, repeats)):  # the first compare of a force analysis, timed inside
        result = subprocess.run(
            [sys.executable, "-c", FIRST_FORCE_COMPARE], check=True, capture_output=True, text=True
        )
        first.append(float(result.stdout))
    rows.append(
        "| the first `pe.compare` of a force analysis (Panda at the README's q), timed inside "
        f"the process | {summary(first, 1e3)} |"
    )
    return [
        "## (g) Start-up of the command line",
        "",
        "Each command in a fresh process, timed alternately; cvxpy, scipy.stats and "
        "matplotlib are imported only where they are used (the coverage's samples of 2-D and "
        "3-D sets need no scipy.stats: the first force `compare` was 0.7–1.3 s, most of it "
        "that import). Target for the first force `compare`: < 0.3 s.",
        "",
        "| command | ms, median (min – max) |",
        "|---|---|",
        *rows,
        "",
    ]


#: The first compare of a force analysis in a fresh process (the robot loaded before timing).
FIRST_FORCE_COMPARE = """
import time
import polyell as pe
panda = pe.robots.load("panda")
analysis = pe.analyze(panda.dynamics([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8]), panda.tau_max,
                      capacity="force")
start = time.perf_counter()
pe.compare(analysis)
print(time.perf_counter() - start)
"""


def bench_memory(counts: list[int]) -> list[str]:
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        script = Path(folder) / "run.py"
        script.write_text(textwrap.dedent(MEMORY_RUN))
        for count in counts:
            out = Path(folder) / f"out{count}"
            result = subprocess.run(
                [sys.executable, str(script), str(out), str(count)],
                check=True,
                capture_output=True,
                text=True,
            )
            peak_kib, seconds = result.stdout.split()
            rows.append(f"| {count:,} | {int(peak_kib) / 1024:.0f} MiB | {float(seconds):.0f} s |")
    return [
        "## (d) Peak memory of a sweep to Parquet",
        "",
        "Panda, `pe.random_configurations` (lazy), `out=` a Parquet dataset, chunks of 20,000, "
        "one process; peak resident memory of the whole process (`ru_maxrss`).",
        "",
        "| configurations | peak memory | time |",
        "|---|---|---|",
        *rows,
        "",
        "Target: independent of the number of configurations, under 1 GB for 10⁶.",
        "",
    ]


def merge(old: str, new: list[str]) -> str:
    """The sections of ``old`` (a performance.md), those of ``new`` in place of their namesakes.

    Sections are the ``## (x) ...`` blocks, returned in letter order: a run of some
    sections keeps every other section of the file as it was.
    """

    def split(text: str) -> tuple[str, dict[str, str]]:
        head, *blocks = re.split(r"^(?=## \()", text, flags=re.MULTILINE)
        return head, {block[4]: block for block in blocks}

    _, fresh = split("\n".join(new))
    _, sections = split(old)
    sections |= fresh
    return "".join(sections[key].rstrip("\n") + "\n\n" for key in sorted(sections))


def main() -> None:
    from capacities_bench import SECTIONS as CAPACITY_SECTIONS
    from horizon_bench import SECTIONS as HORIZON_SECTIONS
    from posture_bench import SECTIONS as POSTURE_SECTIONS
    from robots_bench import SECTIONS as ROBOT_SECTIONS
    from scale_bench import SECTIONS as SCALE_SECTIONS
    from speed_defaults import SECTIONS as DEFAULT_SECTIONS

    parser_sections = {"polytope": bench_polytope, "limits": bench_limits, "sweep": bench_sweep}
    parser_sections["mvie"] = bench_mvie
    parser_sections["along"] = bench_along
    parser_sections["startup"] = bench_startup
    parser_sections |= DEFAULT_SECTIONS | POSTURE_SECTIONS | CAPACITY_SECTIONS | ROBOT_SECTIONS
    parser_sections |= HORIZON_SECTIONS | SCALE_SECTIONS
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--memory", type=int, nargs="*", default=[100_000, 1_000_000])
    parser.add_argument("--out", default=str(REPO / "docs" / "performance.md"))
    parser.add_argument("--sections", nargs="*", choices=list(parser_sections), default=None)
    args = parser.parse_args()
    head = [
        "# Performance",
        "",
        "Regenerated by `python tests/benchmarks/run_benchmarks.py` (extra `bench`); "
        "`--sections NAME ...` reruns some sections and keeps the others as they were "
        f"(names: {', '.join(parser_sections)}; `--memory` with no value skips (d)).",
        "",
        f"Machine: {machine()}, one BLAS thread per process. Timings are medians over "
        f"{args.repeats} repeats (or as a section says) with the min – max spread; the "
        "alternatives of a section are measured side by side in one run (a section rerun "
        "alone keeps the others as they were).",
        "",
    ]
    lines: list[str] = []
    chosen = args.sections or list(parser_sections)
    for section in (parser_sections[name] for name in chosen):
        lines += section(args.repeats)
        print(f"{section.__name__} done", file=sys.stderr)
    if args.memory:
        lines += bench_memory(args.memory)
    out = Path(args.out)
    text = "\n".join(head) + "\n" + merge(out.read_text() if out.exists() else "", lines)
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
