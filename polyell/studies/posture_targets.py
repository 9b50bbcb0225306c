"""The posture choice over many task points: how much each index loses, median and worst.

For each target (a task point, given by a configuration that reaches it, or drawn at
random from seeded reachable configurations) the self-motion is sampled
(:func:`polyell.self_motion`) and the choice made (:func:`polyell.posture_choice`); the
regrets and rank correlations are then aggregated per (kind, criterion), so that a paper
can print "over 200 targets, choosing by the classic ellipsoid loses X % of the true
acceleration along d in the median case, Y % in the worst".
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.comparison.candidates import Candidate
from polyell.errors import InputError, SolverError
from polyell.models.self_motion import MAX_COUNT, check_step, self_motion
from polyell.studies.posture import posture_bar, posture_choice
from polyell.validation import check_array, check_integer

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = ["MAX_TARGETS", "PostureChoiceOverTargets", "posture_choice_over_targets"]

Array = NDArray[np.float64]

#: Most targets one call takes.
MAX_TARGETS = 100_000
#: A random start is kept if ``sigma_min / sigma_max`` of its Jacobian exceeds this (well
#: away from singular postures, where the self-motion branches).
START_RTOL = 1e-3
#: Random draws per requested target before giving up (starts refused as near-singular,
#: or whose self-motion is blocked by the joint limits).
DRAWS_PER_TARGET = 20


@dataclass(frozen=True)
class PostureChoiceOverTargets:
    """The posture choice aggregated over targets.

    Attributes
    ----------
    summary : DataFrame
        Indexed by (kind, criterion): ``median_regret``, ``worst_regret`` (the largest),
        ``mean_regret``, ``median_spearman``, ``median_kendall`` and ``targets`` (how
        many targets entered; a kind undefined at some target's every posture has fewer).
    tables : DataFrame
        Every target's choice table, indexed by (target, kind, criterion).
    starts : ndarray, shape (k, n)
        The configuration each target's self-motion starts from.
    targets : ndarray, shape (k, m)
        The task points (:attr:`polyell.SelfMotion.target`).
    """

    summary: pd.DataFrame
    tables: pd.DataFrame
    starts: Array
    targets: Array

    def __repr__(self) -> str:
        """A line: how many targets, joints and task rows, and the sets compared."""
        kinds = list(dict.fromkeys(self.summary.index.get_level_values(0)))
        k, n = np.shape(self.starts)
        return (
            f"PostureChoiceOverTargets(targets={k}, joints={n}, "
            f"task_rows={np.shape(self.targets)[-1]}, sets={kinds})"
        )


def _random_starts(robot: Any, count: int, rng: np.random.Generator) -> Array:
    """Seeded configurations within the joint limits, away from singular postures."""
    low, high = getattr(robot, "position_limits", (None, None))
    if low is None:
        low, high = np.full(robot.n, -np.pi), np.full(robot.n, np.pi)
    q = low + (high - low) * rng.random((count, robot.n))
    s = np.linalg.svd(robot.dynamics(q).J, compute_uv=False)
    keep: Array = q[s[:, -1] > START_RTOL * s[:, 0]]
    return keep


def posture_choice_over_targets(
    robot: Any,
    starts: ArrayLike | None = None,
    tau_max: ArrayLike | None = None,
    tau_min: ArrayLike | None = None,
    *,
    direction: ArrayLike,
    count: int | None = None,
    seed: int = 0,
    postures: int = 100,
    step: float | None = None,
    mvie: bool = True,
    outer: bool = True,
    candidates: Sequence[Candidate] = (),
    capacity: str = "acceleration",
    qd_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    progress: bool = False,
) -> PostureChoiceOverTargets:
    """The posture choice at many targets, aggregated: median and worst regret.

    At each target the postures are those of the self-motion's component through its start
    (:func:`polyell.self_motion`).

    Parameters
    ----------
    robot : PlanarArm or UrdfRobot
        A redundant arm (:func:`polyell.self_motion`).
    starts : array-like, shape (k, n), optional
        One configuration per target [rad or m]: the target is its task point, its
        self-motion is sampled from it.  Leave out to draw ``count`` targets at random.
    tau_max, tau_min : array-like, shape (n,), optional
        Torque limits [N m]; default the robot's own.
    direction : array-like, shape (m,)
        The task direction of the ``"limit"`` criterion.
    count : int, optional
        Without ``starts``: how many random reachable targets (configurations uniform
        within the joint limits, or in [-pi, pi] for a planar arm, kept away from singular
        postures; their self-motion must have room to move).
    seed : int, optional
        Seed of the random targets and of each target's random walk (target i uses
        ``seed + i``).
    postures : int, optional
        Postures sampled on each target's self-motion (at least 2).
    step : float, optional
        The self-motion's step (:func:`polyell.self_motion`).
    mvie, outer, candidates, capacity, qd_max, qd_min
        As in :func:`polyell.posture_choice`.
    progress : bool, optional
        Progress bars on standard error (tqdm), one step per target: sampling the
        targets' self-motions, then scoring their postures (``acceleration: scoring
        targets``).

    Returns
    -------
    PostureChoiceOverTargets

    Raises
    ------
    InputError
        For both or neither of ``starts`` and ``count``, a count or postures out of range,
        and every error of :func:`polyell.self_motion` and :func:`polyell.posture_choice`
        (a start that is singular or off the limits names ``starts[i]``).
    SolverError
        If too few random starts have a self-motion to sample.
    """
    if not (hasattr(robot, "dynamics") and hasattr(robot, "n")) or isinstance(robot, type):
        raise InputError(
            "robot",
            "a redundant robot (pe.PlanarArm, pe.UrdfRobot, pe.robots.load(...))",
            type(robot).__name__,
            "pass a robot with more joints than task rows, e.g. pe.robots.load('chiacchio2000').",
        )
    if (starts is None) == (count is None):
        raise InputError(
            "starts",
            "either starting configurations (k, n) or a count of random targets",
            "both" if starts is not None else "neither",
            "pass starts=... or count=... (with seed=...).",
        )
    if not isinstance(progress, bool):
        raise InputError(
            "progress",
            "True or False",
            repr(progress)[:60],
            "pass progress=True for progress bars, or False (the default) for none.",
        )
    seed = check_integer("seed", seed, 0, 2**62)
    postures = check_integer("postures", postures, 2, MAX_COUNT)
    step = None if step is None else check_step(step)  # (not each target's SolverError)
    motions = []
    if starts is not None:
        q = check_array("starts", starts, ("K", robot.n), what="joint positions")
        if len(q) == 0:
            raise InputError(
                "starts",
                "at least one configuration",
                "none",
                f"give at least one row of {robot.n} joint positions, or count=... for "
                "random targets instead.",
            )
        with posture_bar(len(q), f"{capacity}: sampling self-motions", progress, " targets") as bar:
            for i, start in enumerate(q):
                try:
                    motions.append(self_motion(robot, start, postures, seed=seed + i, step=step))
                except InputError as exn:
                    if exn.argument != "q0":
                        raise
                    raise InputError(f"starts[{i}]", exn.expected, exn.got, exn.fix) from None
                bar.update(1)
    else:
        assert count is not None
        wanted = check_integer("count", count, 1, MAX_TARGETS)
        rng = np.random.default_rng(seed)
        draws = 0
        with posture_bar(wanted, f"{capacity}: sampling self-motions", progress, " targets") as bar:
            while len(motions) < wanted and draws < DRAWS_PER_TARGET * wanted:
                batch = _random_starts(robot, wanted - len(motions), rng)
                draws += wanted - len(motions)
                for start in batch:
                    i = len(motions)
                    try:
                        motions.append(
                            self_motion(robot, start, postures, seed=seed + i, step=step)
                        )
                    except (InputError, SolverError):  # blocked by the limits, or stuck
                        continue
                    bar.update(1)
        if len(motions) < wanted:
            raise SolverError(
                f"posture_choice_over_targets: {len(motions)} of {wanted} random targets "
                f"after {draws} draws have a self-motion to sample; check the joint limits."
            )
    import pandas as pd

    tables = []
    with posture_bar(len(motions), f"{capacity}: scoring targets", progress, " targets") as bar:
        for motion in motions:
            choice = posture_choice(
                robot,
                motion,
                tau_max,
                tau_min,
                direction=direction,
                mvie=mvie,
                outer=outer,
                candidates=candidates,
                capacity=capacity,
                qd_max=qd_max,
                qd_min=qd_min,
            )
            tables.append(choice.table)
            bar.update(1)
    frame = pd.concat(tables, keys=range(len(tables)), names=["target"])
    grouped = frame.groupby(level=["kind", "criterion"], sort=False)
    summary = pd.DataFrame(
        {
            "median_regret": grouped["regret"].median(),
            "worst_regret": grouped["regret"].max(),
            "mean_regret": grouped["regret"].mean(),
            "median_spearman": grouped["spearman"].median(),
            "median_kendall": grouped["kendall"].median(),
            "targets": grouped["regret"].count(),
        }
    )
    summary.attrs["capacity"] = frame.attrs["capacity"] = capacity  # the sets' labels
    starts_array = np.array([motion.q0 for motion in motions])
    targets = np.array([motion.target for motion in motions])
    return PostureChoiceOverTargets(summary, frame, starts_array, targets)
