"""Section (n): velocity and force polytopes against pycapacity, side by side in one run.

Each call builds the polytope from the arm's matrices and limits and asks for its vertices
and facets: polyell's ``pe.analyze(..., capacity=...).polytope`` with ``vertices``, ``A``,
``b`` (the Dynamics/Kinematics objects are built before timing, as pycapacity gets its
arrays), pycapacity's ``velocity_polytope(J, dq_max, dq_min)`` and ``force_polytope(J, t_max,
t_min, t_bias=g)``.  In the same run the sets are compared: each of pycapacity's vertices
against polyell's nearest (relative to the set's size), the volumes (Qhull of pycapacity's
vertices), and polyell's limits against one scipy LP per direction over the raw
half-spaces (50 directions).
"""

from __future__ import annotations

import numpy as np
from run_benchmarks import (
    POLYTOPE_COMMAND,
    README_POSTURE,
    below_target,
    capacity_version,
    cpu_timed_alternately,
    panda_configurations,
    stage_row,
    stage_times,
    summary,
    timed_alternately,
)
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.geometry.directions import sphere_directions


def random_arms(m: int, n: int, count: int, seed: int):
    rng = np.random.default_rng(seed)
    arms = []
    for _ in range(count):
        J = rng.normal(size=(m, n))
        g = 0.05 * rng.normal(size=n)
        arms.append((J, g))
    high = rng.uniform(1.0, 3.0, n)
    return arms, high, -high * rng.uniform(0.7, 1.0, n)


def panda_arms(count: int):
    panda = pe.robots.load("panda")
    arms = [(d.J, d.g) for d in (panda.dynamics(q) for q in panda_configurations(count, 1))]
    return arms, panda


def _line_lp(A: np.ndarray, b: np.ndarray, t: np.ndarray, M=None, c=None) -> tuple[float, float]:
    """[lo, hi] of {s : s t in P}: P = {A h <= b} (forces) or {M u + c, |u| <= 1}."""
    ends = []
    for sign in (1.0, -1.0):
        if M is None:
            result = linprog([sign], (A @ t)[:, None], b, bounds=[(None, None)])
        else:
            n = M.shape[1]
            result = linprog(
                np.r_[sign, np.zeros(n)],
                A_eq=np.hstack([-t[:, None], M]),
                b_eq=-c,
                bounds=[(None, None)] + [(-1.0, 1.0)] * n,
            )
        ends.append(result.x[0])
    return ends[0], ends[1]


def brute_force_vertices(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Vertices of {A x <= b} by solving every m-subset of rows and keeping the feasible."""
    from itertools import combinations

    m = A.shape[1]
    found = []
    for rows in combinations(range(len(A)), m):
        block = A[list(rows)]
        if abs(np.linalg.det(block)) < 1e-12:
            continue
        x = np.linalg.solve(block, b[list(rows)])
        if np.all(A @ x <= b + 1e-9 * np.abs(b).max()):
            found.append(x)
    return np.array(found)


def nearest(points: np.ndarray, others: np.ndarray, size: float) -> float:
    """Largest distance of a point to the nearest of ``others``, relative to ``size``."""
    return float(np.linalg.norm(points[:, None] - others[None], axis=2).min(axis=1).max() / size)


def compare_sets(ours, theirs_vertices: np.ndarray, lp_limits, reference) -> tuple[float, ...]:
    V = np.asarray(theirs_vertices).T
    size = float(np.ptp(V, axis=0).max())
    volume = abs(ours.volume - ConvexHull(V).volume) / ConvexHull(V).volume
    T = sphere_directions(50, V.shape[1])
    lo, hi = ours.limits(T)
    worst = 0.0
    for t, a, b in zip(T, lo, hi, strict=True):
        ref = lp_limits(t)
        worst = max(worst, abs(a - ref[0]) / size, abs(b - ref[1]) / size)
    exact = reference()  # brute force: are the differences polyell's or pycapacity's?
    return (
        nearest(V, ours.vertices, size),
        volume,
        worst,
        max(nearest(exact, ours.vertices, size), nearest(ours.vertices, exact, size)),
        nearest(V, exact, size),
    )


def bench_capacities(repeats: int) -> list[str]:
    import pycapacity.robot as capacity

    cases = []
    for label, (arms, high, low) in (
        ("random 3x7", random_arms(3, 7, 20, seed=1)),
        ("random 6x7", random_arms(6, 7, 10, seed=2)),
    ):
        cases.append((label, arms, high, low, high, low))
    arms, panda = panda_arms(20)
    cases.append(("Panda", arms, panda.tau_max, panda.tau_min, panda.qd_max, panda.qd_min))
    posture = panda.dynamics(README_POSTURE)
    limits = (panda.tau_max, panda.tau_min, panda.qd_max, panda.qd_min)
    cases.append(("Panda at the README's q", [(posture.J, posture.g)] * 20, *limits))
    rows, checks, stages, speeds = [], [], [], []
    for label, arms, t_max, t_min, v_max, v_min in cases:
        n = arms[0][0].shape[1]
        kinematics = [pe.Kinematics(J) for J, _ in arms]
        dynamics = [pe.Dynamics(J, np.eye(n), g) for J, g in arms]

        def ours_velocity(kinematics=kinematics, v_max=v_max, v_min=v_min):
            for kin in kinematics:
                P = pe.analyze(kin, capacity="velocity", qd_max=v_max, qd_min=v_min).polytope
                P.vertices, P.A, P.b  # noqa: B018

        def theirs_velocity(arms=arms, v_max=v_max, v_min=v_min):
            for J, _ in arms:
                capacity.velocity_polytope(J, v_max, v_min)

        def ours_force(dynamics=dynamics, t_max=t_max, t_min=t_min):
            for dyn in dynamics:
                P = pe.analyze(dyn, t_max, t_min, capacity="force").polytope
                P.vertices, P.A, P.b  # noqa: B018

        def theirs_force(arms=arms, t_max=t_max, t_min=t_min):
            for J, g in arms:
                capacity.force_polytope(J, t_max, t_min, t_bias=g)

        times = cpu_timed_alternately(
            [ours_velocity, theirs_velocity, ours_force, theirs_force], 3 * repeats
        )
        per = 1e3 / len(arms)
        for name, ours, theirs in (("velocity", times[0], times[1]), ("force", times[2], times[3])):
            speedup = np.median(theirs) / np.median(ours)
            rows.append(
                f"| {label} | {name} | {summary(ours, per)} | {summary(theirs, per)} | "
                f"{speedup:.1f}× |"
            )
            if not label.startswith("random 6x7"):  # the target's rows
                speeds.append((f"{label} {name}", np.median(ours) * per, np.median(theirs) * per))
        velocity_stages = stage_times(
            lambda kin, v_max=v_max, v_min=v_min: pe.analyze(
                kin, capacity="velocity", qd_max=v_max, qd_min=v_min
            ),
            kinematics,
            repeats,
        )
        force_stages = stage_times(
            lambda dyn, t_max=t_max, t_min=t_min: pe.analyze(dyn, t_max, t_min, capacity="force"),
            dynamics,
            repeats,
        )
        stages += [stage_row(f"{label} | velocity", velocity_stages)]
        stages += [stage_row(f"{label} | force", force_stages)]
        worst = np.zeros((2, 5))
        for (J, g), kin, dyn in list(zip(arms, kinematics, dynamics, strict=True))[:5]:
            velocity = pe.analyze(kin, capacity="velocity", qd_max=v_max, qd_min=v_min)
            force = pe.analyze(dyn, t_max, t_min, capacity="force")
            theirs_v = capacity.velocity_polytope(J, v_max, v_min).vertices
            theirs_f = capacity.force_polytope(J, t_max, t_min, t_bias=g).vertices
            A = np.vstack([J.T, -J.T])
            b = np.concatenate([t_max - g, g - t_min])
            M, c = J * (v_max - v_min) / 2, J @ (v_max + v_min) / 2
            corners = np.array(np.meshgrid(*[[-1.0, 1.0]] * n)).reshape(n, -1).T @ M.T + c
            worst[0] = np.maximum(
                worst[0],
                compare_sets(
                    velocity.polytope,
                    theirs_v,
                    lambda t, M=M, c=c: _line_lp(None, None, t, M, c),
                    lambda corners=corners: corners[ConvexHull(corners).vertices],
                ),
            )
            worst[1] = np.maximum(
                worst[1],
                compare_sets(
                    force.polytope,
                    theirs_f,
                    lambda t, A=A, b=b: _line_lp(A, b, t),
                    lambda A=A, b=b: brute_force_vertices(A, b),
                ),
            )
        for name, values in (("velocity", worst[0]), ("force", worst[1])):
            checks.append(
                f"| {label} | {name} | " + " | ".join(f"{value:.1e}" for value in values) + " |"
            )
    return [
        "## (n) Velocity and force polytopes against pycapacity",
        "",
        "Each call builds the polytope from the arm's matrices and limits and gives its vertices"
        " and facets: polyell `pe.analyze(..., capacity=...).polytope` with `vertices`, `A`, "
        "`b` (the `Kinematics`/`Dynamics` objects built before timing, as pycapacity gets its "
        f"arrays); pycapacity {capacity_version()} `velocity_polytope(J, dq_max, dq_min)` and "
        "`force_polytope(J, t_max, t_min, t_bias=g)`. Random arms: J normal, asymmetric "
        "limits, g = 0.05 N(0, 1); the Panda at 20 random configurations and at the README's "
        "q = (0, -0.5, 0, -2, 0, 1.6, 0.8) with its URDF limits. Timed alternately, "
        f"{3 * repeats} repeats, in CPU time on one core (`time.process_time`), by "
        f"`{POLYTOPE_COMMAND}`.",
        "",
        "| arms | polytope | polyell ms/config | pycapacity ms/config | speed-up |",
        "|---|---|---|---|---|",
        *rows,
        "",
        "Target: 20× on 3x7 arms and on the Panda. " + below_target(speeds),
        "",
        "Where polyell's time goes, µs per call (as in (a): `pe.analyze`, `.polytope`, its "
        "`vertices`, `A` and `b`; median over every call of "
        f"{repeats} passes after a warm-up, CPU time, without pycapacity's calls in "
        "between). A force set is enumerated when `.polytope` is built (its vertices and "
        "facets then cost nothing more); a zonotope's facets and vertices when they are "
        "first asked for.",
        "",
        "| arms | polytope | analysis | set | vertices and facets | total |",
        "|---|---|---|---|---|---|",
        *stages,
        "",
        "The same sets, first 5 configurations of "
        "each row (largest over them; target 1e-9; distances relative to the set's size): "
        "pycapacity's vertices against polyell's nearest; polyell's volume against Qhull of "
        "pycapacity's vertices (relative); polyell's limits along 50 directions against one "
        "scipy LP per direction over the raw joint limits; then both against an independent "
        "brute force (velocities: the hull of the 2^n images of the box's corners; forces: "
        "every m-subset of the 2n half-spaces solved, the feasible points kept) to say whose "
        "vertices a difference comes from.",
        "",
        "| arms | polytope | vertices vs pycapacity | volume | limits vs LP | polyell vs brute "
        "force | pycapacity vs brute force |",
        "|---|---|---|---|---|---|---|",
        *checks,
        "",
    ]


def sweep_rates(repeats: int) -> list[str]:
    """Section (o): pe.sweep at its defaults per capacity on random 3x7 arms, and the force cost.

    The three capacities and a force ``compare`` per configuration (the scalar path) are
    timed alternately in one run; then the force rows' time is split: the
    quasi-Monte-Carlo coverage of the ellipsoids that leave the set (``overlap``'s counts
    alone, on the same ellipsoids) and the rest of the batch path.
    """
    from polyell.comparison.caps import cap_share
    from polyell.comparison.metrics import enclosing_scale, inscribed_scale, inside_rtol
    from reference import qmc_count_inside, slacks

    rng = np.random.default_rng(3)
    K = 2000
    J = rng.normal(size=(K, 3, 7))
    dyn = pe.Dynamics(
        J, np.broadcast_to(np.eye(7), (K, 7, 7)).copy(), 0.05 * rng.normal(size=(K, 7))
    )
    high = rng.uniform(1.0, 3.0, 7)
    counts = {"acceleration": K, "velocity": K, "force": K, "force, one compare per row": 200}
    per_row = dyn[: counts["force, one compare per row"]]

    def one_compare_per_row() -> None:  # what a force sweep did before its batch path
        for k in range(len(per_row)):
            an = pe.analyze(per_row[k], high, capacity="force")
            pe.compare(an, mvie=False, outer=False).to_row()

    calls = {
        "acceleration": lambda: pe.sweep(dyn, tau_max=high),
        "velocity": lambda: pe.sweep(dyn, capacity="velocity", qd_max=high),
        "force": lambda: pe.sweep(dyn, tau_max=high, capacity="force"),
        "force, one compare per row": one_compare_per_row,
    }
    times = timed_alternately(list(calls.values()), repeats)
    lines = [
        "## (o) Sweeps per capacity",
        "",
        "Sweeps at their defaults (`pe.sweep(dyn, ..., capacity=...)`: 256 directions, "
        "2^13 x 8 quasi-Monte-Carlo points where an ellipsoid leaves the set and its caps "
        "meet, no MVIE or outer ellipsoid), random 3x7 arms with B = I, g = 0.05 N(0, 1), "
        "symmetric limits; "
        f"{K:,} configurations, and beside them `pe.compare(pe.analyze(..., "
        "capacity='force')).to_row()` one configuration at a time (the scalar path, what "
        f"force sweeps did before their batch path) on {counts['force, one compare per row']}; "
        f"{repeats} repeats alternately, one core, configurations/s median (min – max). "
        "Target for forces (issue 21): 10,000/s.",
        "",
        "| capacity | configurations/s |",
        "|---|---|",
    ]
    for (name, count), seconds in zip(counts.items(), times, strict=True):
        rates = count / np.asarray(seconds)
        lines.append(
            f"| {name} | {np.median(rates):,.0f} ({rates.min():,.0f} – {rates.max():,.0f}) |"
        )
    from polyell.studies.batch import BatchOptions
    from polyell.studies.force_batch import force_rows

    _, scalar = force_rows(dyn, high, -high, sphere_directions(256, 3), BatchOptions())
    analyses = [pe.analyze(dyn[k], high, capacity="force") for k in range(K)]
    crossing = []  # the ellipsoids neither inside nor around their set
    for an in analyses:
        if an.c_perp @ an.c_perp >= 1.0:
            continue
        P = an.polytope
        for kind in an.ellipsoid_kinds:
            E = an.ellipsoid(kind)
            tolerance = inside_rtol(E, P)
            if inscribed_scale(E, P) < 1 - tolerance and enclosing_scale(E, P) > 1 + tolerance:
                crossing.append((E, P.A, slacks(E, P)))
    shares = [cap_share((A @ E.axes) * E.semi_axes, slack) for E, A, slack in crossing]
    estimated = int(np.isnan(shares).sum())

    def count_points() -> None:  # what their coverage cost before cap_share
        for E, A, slack in crossing:
            qmc_count_inside(E.axes, E.semi_axes, A, slack, 2**13, 8, 0)

    (points_times,) = timed_alternately([count_points], repeats)
    total = np.median(times[2]) / K * 1e3
    points = np.median(points_times) / K * 1e3
    lines += [
        "",
        f"A force row takes {total:.3f} ms (median). Of its ellipsoids, "
        f"{len(crossing) / K:.2f} per configuration leave the set (the classic one nearly "
        "always, the static one sometimes; the gravity-consistent one is inside by "
        "construction). Their coverage is exact where their parts beyond the facets are "
        f"disjoint (`cap_share`): {len(crossing) - estimated:,} of {len(crossing):,} here; "
        f"{estimated:,} are estimated by quasi-Monte Carlo. Estimating them all at the "
        f"default 2^13 x 8 points would take {points:.3f} ms per configuration on its own "
        f"(a cap of {1.0 / points * 1e3:,.0f}/s). The batch leaves {int(scalar.sum())} of "
        f"{K:,} rows to the scalar path.",
        "",
    ]
    return lines


SECTIONS = {"capacities": bench_capacities, "capacity_sweeps": sweep_rates}
