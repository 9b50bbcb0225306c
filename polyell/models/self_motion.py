r"""Self-motion: the configurations of a redundant arm that keep its task coordinates.

An arm with n joints and an m-dimensional task (m < n) reaches the task point
:math:`x_0 = x(q_0)` in a continuum of postures, its self-motion manifold
:math:`\{q : x(q) = x_0\}`, of dimension n - m where the Jacobian has full rank.
:func:`self_motion` samples it (DESIGN.md section 7):

* a step :math:`\delta q = h N z` along an orthonormal basis N of Ker J keeps x to first
  order; a Newton correction :math:`\delta q = -J^+ (x(q) - x_0)` after each step puts it
  back (to about 1e-12);
* a 1-D manifold (a planar 3R arm with its 2-D position task, a 7-joint arm with a 6-D
  pose task) is *traced* from q0 both ways, until it meets a joint limit, a singular
  configuration, or closes on itself (a loop, traced once), then resampled at ``count``
  points equally spaced in arc length;
* a manifold of higher dimension (a 7-joint arm with a 3-D position task has 4) is sampled
  by a seeded random walk: a chain of null-space steps in random directions, each
  corrected, one sample every :data:`WALK_STEPS` steps.

Every returned configuration is checked: its task coordinates differ from ``x(q0)`` by at
most :data:`RESIDUAL_RTOL` times the arm's length scale (the larger of ``|x(q0)|`` and
``|J(q0)|``, so that the check holds in any unit of length); the largest difference is
reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError, SolverError
from polyell.models.planar_arm import PlanarArm
from polyell.models.urdf import UrdfRobot
from polyell.validation import check_array, check_integer

__all__ = [
    "MAX_COUNT",
    "MIN_STEP",
    "RESIDUAL_RTOL",
    "SINGULAR_RTOL",
    "WALK_STEPS",
    "SelfMotion",
    "check_step",
    "self_motion",
]

Array = NDArray[np.float64]

#: Largest difference of task coordinates a returned configuration may have, relative to
#: the arm's length scale (the larger of ``|x(q0)|`` and ``|J(q0)|``, in task units).
RESIDUAL_RTOL = 1e-9
#: A configuration with ``sigma_min(J) <= SINGULAR_RTOL sigma_max(J)`` is singular: its
#: self-motion is not a manifold of dimension n - m there.
SINGULAR_RTOL = 1e-8
#: Most configurations one call returns.
MAX_COUNT = 100_000
#: Smallest step along the manifold [rad]: a million times the spacing of doubles at 1 rad,
#: so that a step moves the joints by more than their rounding.
MIN_STEP = 1e-9
#: Null-space steps between two samples of a random walk.
WALK_STEPS = 10
#: Default step along the manifold [rad]: tracing a curve, and each step of a random walk.
TRACE_STEP, WALK_STEP = 0.01, 0.05
#: Steps in one direction of a trace before it gives up (a curve that neither closes nor
#: meets a limit within 10^5 steps is reported as such, ``stops``).
MAX_TRACE_STEPS = 100_000
#: Newton iterations of one correction, and the tolerance it aims for (relative to the
#: arm's length scale, as :data:`RESIDUAL_RTOL`).
NEWTON_ITERATIONS, NEWTON_RTOL = 30, 1e-13
#: A trace closes when it comes back within this many steps of q0 after leaving by more
#: than CLOSE_AFTER steps.
CLOSE_WITHIN, CLOSE_AFTER = 0.75, 3.0
#: A closed self-motion smaller than this [rad] (every point within it of q0) is refused:
#: near a singular posture, where it shrinks to a point, the corrector's rounding is a share
#: of it (:func:`self_motion`). Larger loops below the step are traced again at a tenth of
#: their extent.
SMALLEST_LOOP = 1e-5
#: Consecutive failed walks (every step refused) before a random walk gives up.
MAX_FAILED_WALKS = 50


@dataclass(frozen=True)
class SelfMotion:
    """Configurations on the self-motion manifold of ``q0``.

    Attributes
    ----------
    configurations : ndarray, shape (k, n)
        Joint configurations [rad or m], ordered along the manifold for a traced curve,
        in the order of the walk otherwise.  ``q0`` itself is not among them (unless a
        sample falls on it).
    q0 : ndarray, shape (n,)
        The starting configuration.
    target : ndarray, shape (m,)
        The task coordinates kept: the end-effector position [m] (a planar arm, the
        linear rows of a URDF robot's task) and, for a task with the angular rows, the
        rotation vector of the tip's orientation [rad].
    residual : float
        Largest difference between the task coordinates of a configuration and
        ``target`` (max norm, task units); at most :data:`RESIDUAL_RTOL` times the arm's
        length scale.
    dimension : int
        Dimension n - m of the manifold.
    method : {"trace", "random walk"}
        How it was sampled.
    position : ndarray, shape (k,)
        The arc length [rad] along the traced curve from q0 (negative: the other way; a
        closed curve: from 0 to its length), for the figures of a study.  For a random
        walk, the distance ``|q - q0|`` [rad].
    length : float
        The traced curve's length [rad] (NaN for a random walk).
    closed : bool
        Whether the traced curve closed on itself (then it was traced once).
    stops : tuple of str
        Why the trace stopped each way (``"joint limit"``, ``"singular"``, ``"closed"``,
        ``"step limit"``); empty for a random walk.
    """

    configurations: Array
    q0: Array
    target: Array
    residual: float
    dimension: int
    method: str
    position: Array
    length: float
    closed: bool
    stops: tuple[str, ...]

    def __len__(self) -> int:
        return len(self.configurations)


class _Task:
    """The task coordinates of a robot, their Jacobian and its joint limits."""

    def __init__(self, robot: Any) -> None:
        self.robot = robot
        if isinstance(robot, PlanarArm):
            n, self.m = robot.n, 2
            self.lower, self.upper = np.full(n, -np.inf), np.full(n, np.inf)
            self.periodic = np.ones(n, dtype=bool)  # angles: the loop closes modulo 2 pi
            self.linear, self.angular = np.arange(2), np.zeros(0, dtype=int)
            self.weights = np.ones(2)
        elif isinstance(robot, UrdfRobot):
            n, self.m = robot.nq, robot.m
            self.lower, self.upper = robot.position_limits
            self.periodic = np.zeros(n, dtype=bool)
            rows = np.asarray(robot.rows)
            self.linear, self.angular = np.flatnonzero(rows < 3), np.flatnonzero(rows >= 3)
            if self.angular.size not in (0, 3):
                raise InputError(
                    "robot",
                    "a task with coordinates: linear rows, with or without all three "
                    "angular rows (wx, wy, wz)",
                    f"the task rows {list(robot.row_names)}",
                    "an orientation has no coordinates of its own: constrain all three "
                    "angular rows or none (pe.robots.load(name, task=...)).",
                )
            self.rows = rows
            self.weights = np.asarray(robot.weights, dtype=float)
        else:
            raise InputError(
                "robot",
                "a pe.PlanarArm or a pe.UrdfRobot (e.g. pe.robots.load('panda'))",
                type(robot).__name__,
                "pass the robot itself, not its Dynamics or Kinematics, "
                "e.g. pe.robots.load('panda')",
            )
        self.n = n

    def coordinates(self, q: Array) -> tuple[Array, Array | None, Array]:
        """The task's position rows [m], its rotation (or None) and unweighted Jacobian."""
        if isinstance(self.robot, PlanarArm):
            return self.robot.forward_kinematics(q), None, self.robot.jacobian(q)
        position, rotation, J = self.robot.tip_kinematics(q, check_limits=False)  # q0: checked
        rotation = rotation if self.angular.size else None
        return position[self.rows[self.linear]], rotation, J / self.weights[:, None]

    def error(self, q: Array, target: tuple[Array, Array | None]) -> tuple[Array, Array]:
        """``x(q) - x0`` in the rows' order, unweighted [m, rad], and the Jacobian at q."""
        position, rotation, J = self.coordinates(q)
        error = np.empty(self.m)
        error[self.linear] = position - target[0]
        if rotation is not None:
            assert target[1] is not None
            # R = exp([w]) R0 to first order, with w the world angular velocity times dt.
            axis = self.rows[self.angular] - 3
            error[self.angular] = _rotation_vector(rotation @ target[1].T)[axis]
        return error, J

    def inside(self, q: Array) -> bool:
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))


def _rotation_vector(R: Array) -> Array:
    """The rotation vector (axis times angle) of a rotation matrix near the identity."""
    from scipy.spatial.transform import Rotation

    vector: Array = Rotation.from_matrix(R).as_rotvec()
    return vector


def _rank_ratio(J: Array) -> tuple[float, Array]:
    """``sigma_min / sigma_max`` of J and its right singular vectors (rows)."""
    _, s, Vt = np.linalg.svd(J)
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0, Vt


def check_step(step: object) -> float:
    """A step along the self-motion manifold [rad], from :data:`MIN_STEP` to 1.

    Else an InputError naming ``step``.
    """
    if (
        isinstance(step, bool)
        or not isinstance(step, int | float | np.integer | np.floating)
        or not MIN_STEP <= float(step) <= 1.0
    ):
        raise InputError(
            "step",
            f"a step along the manifold from {MIN_STEP:g} to 1 rad (below it a joint angle "
            "of about 1 rad does not change in double precision)",
            repr(step),
            f"leave it out (default {TRACE_STEP:g} for a one-dimensional self-motion, "
            f"{WALK_STEP:g} above).",
        )
    return float(step)


def self_motion(
    robot: PlanarArm | UrdfRobot,
    q0: ArrayLike,
    count: int = 100,
    *,
    seed: int = 0,
    step: float | None = None,
) -> SelfMotion:
    """Configurations with the same task coordinates as ``q0``, spread along its self-motion.

    The samples are of the connected component through ``q0``.  A self-motion may have
    several (the paper's arm at its redundant point has two closed loops, the elbow
    branches, which share no posture): start another component from one of its own
    postures and pool the samples (``components`` in a ``[posture]`` study).

    Parameters
    ----------
    robot : PlanarArm or UrdfRobot
        A redundant arm (more joints than task rows).  A URDF robot's task may mix linear
        rows with all three angular rows, not with some of them (an orientation has no
        coordinates of its own); its joint limits (``position_limits``) bound the
        manifold.  A planar arm has no joint limits.
    q0 : array-like, shape (n,)
        A non-singular configuration within the joint limits [rad or m].
    count : int, optional
        How many configurations to return, from 1 to :data:`MAX_COUNT`.
    seed : int, optional
        Seed of the random walk (a manifold of dimension > 1); a traced curve ignores it.
    step : float, optional
        Step along the manifold [rad], from :data:`MIN_STEP` to 1: default 0.01 for a trace
        (its resolution), 0.05 for a walk (:data:`WALK_STEPS` steps per sample).

    Returns
    -------
    SelfMotion
        ``configurations`` (k, n) with ``k = count``, their largest task residual, and the
        positions along the manifold.

    Raises
    ------
    InputError
        For a robot with no redundancy for its task, a ``q0`` of the wrong size, off the
        joint limits or singular, a ``q0`` whose self-motion is blocked both ways by the
        limits, a ``count``, ``seed`` or ``step`` out of range.
    SolverError
        If the Newton correction cannot bring a configuration back to the task point
        (a random walk that is stuck), or a configuration misses it by more than
        :data:`RESIDUAL_RTOL` relative (never expected).

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> q0 = [np.pi / 2, -np.pi / 2, -np.pi / 2]
    >>> motion = pe.self_motion(arm, q0, count=50)
    >>> motion.configurations.shape, motion.closed, motion.residual < 1e-9
    ((50, 3), True, True)
    """
    task = _Task(robot)
    n, m = task.n, task.m
    if n <= m:
        raise InputError(
            "robot",
            "a redundant arm: more joints than task rows",
            f"{n} joints for {m} task rows",
            "use a task with fewer rows, or an arm with more joints.",
        )
    q = check_array("q0", q0, (n,), what="joint positions [rad or m]")
    if isinstance(robot, PlanarArm):
        robot.forward_kinematics(q)  # the arm's own check of the angles' size
    outside = np.flatnonzero((q < task.lower) | (q > task.upper))
    if outside.size:
        i = int(outside[0])
        raise InputError(
            "q0",
            "joint positions within the robot's limits",
            f"q0[{i}] = {q[i]:.6g} outside [{task.lower[i]:.6g}, {task.upper[i]:.6g}]",
            "start from a configuration inside robot.position_limits.",
        )
    position, rotation, J = task.coordinates(q)
    ratio, _ = _rank_ratio(J)
    if ratio <= SINGULAR_RTOL:
        raise InputError(
            "q0",
            f"a non-singular configuration (sigma_min / sigma_max of J above {SINGULAR_RTOL:g})",
            f"sigma_min / sigma_max = {ratio:.3g}",
            "start from a configuration away from the singularity; its self-motion is not "
            "a manifold there.",
        )
    count = check_integer("count", count, 1, MAX_COUNT)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    dimension = n - m
    default = TRACE_STEP if dimension == 1 else WALK_STEP
    step = default if step is None else check_step(step)
    target = (position, rotation)
    # The arm's length scale: lengths in any unit (J's entries are lengths per radian).
    scale = max(float(np.linalg.norm(position)), float(np.linalg.norm(J, 2)))
    tracer = _Tracer(task, target, NEWTON_RTOL * scale)
    if dimension == 1:
        result = _trace(tracer, q, count, float(step))
    else:
        result = _walk(tracer, q, count, float(step), seed)
    configurations = result[0]
    residuals = np.array([np.max(np.abs(task.error(c, target)[0])) for c in configurations])
    worst = float(residuals.max())
    if not worst <= RESIDUAL_RTOL * scale:
        raise SolverError(
            f"self_motion: a configuration misses the task point by {worst:.3g} "
            f"(more than {RESIDUAL_RTOL:g} of the arm's length scale {scale:.3g}); try a "
            "smaller step."
        )
    target_vector = np.empty(m)
    target_vector[task.linear] = position
    if rotation is not None:
        target_vector[task.angular] = _rotation_vector(rotation)[task.rows[task.angular] - 3]
    for array in (configurations, q, target_vector, result[1]):
        array.flags.writeable = False
    return SelfMotion(
        configurations=configurations,
        q0=q,
        target=target_vector,
        residual=worst,
        dimension=dimension,
        method="trace" if dimension == 1 else "random walk",
        position=result[1],
        length=result[2],
        closed=result[3],
        stops=result[4],
    )


class _Tracer:
    """Null-space steps with a Newton correction onto the task point."""

    def __init__(self, task: _Task, target: tuple[Array, Array | None], tol: float) -> None:
        self.task, self.target, self.tol = task, target, tol

    def correct(self, q: Array) -> tuple[Array, Array] | None:
        """Newton's iteration ``q <- q - J^+ (x(q) - x0)``: the point and its Jacobian.

        None if it does not converge within NEWTON_ITERATIONS.
        """
        for _ in range(NEWTON_ITERATIONS):
            error, J = self.task.error(q, self.target)
            if np.linalg.norm(error) <= self.tol:
                return q, J
            q = q - np.linalg.lstsq(J, error, rcond=None)[0]
            if not np.all(np.isfinite(q)):
                return None
        return None

    def null_space(self, J: Array) -> Array | None:
        """An orthonormal basis of Ker J (rows, shape (n - m, n)), None where J is singular."""
        ratio, Vt = _rank_ratio(J)
        return None if ratio <= SINGULAR_RTOL else Vt[self.task.m :]

    def advance(
        self, q: Array, direction: Array, step: float
    ) -> tuple[tuple[Array, Array] | None, str]:
        """One corrected step of about ``step`` along ``direction`` (unit, in Ker J).

        Halves the step where the correction fails, jumps off the curve or leaves the
        joint limits; returns (None, why) when even a step of 1/1024 of it fails.  The
        point comes with its Jacobian.
        """
        h, why = step, "newton"
        while h >= step / 1024:
            found = self.correct(q + h * direction)
            if found is None or np.linalg.norm(found[0] - q) > 2.0 * h:
                why = "newton"
            elif not self.task.inside(found[0]):
                why = "joint limit"
            else:
                return found, ""
            h /= 2
        return None, why


def _wrapped_distance(task: _Task, a: Array, b: Array) -> float:
    """``|a - b|`` with the periodic joints' differences taken modulo 2 pi."""
    difference = a - b
    periodic = task.periodic
    difference[periodic] = (difference[periodic] + np.pi) % (2 * np.pi) - np.pi
    return float(np.linalg.norm(difference))


def _trace_one_way(
    tracer: _Tracer, q0: Array, J0: Array, sign: float, step: float
) -> tuple[list[Array], str]:
    """The curve from q0 one way: the points after q0, and why it stopped."""
    basis = tracer.null_space(J0)
    assert basis is not None
    previous = sign * basis[0]
    points: list[Array] = []
    q, J, travelled = q0, J0, 0.0
    for _ in range(MAX_TRACE_STEPS):
        basis = tracer.null_space(J)
        if basis is None:
            return points, "singular"
        direction = basis[0] if basis[0] @ previous >= 0 else -basis[0]
        found, why = tracer.advance(q, direction, step)
        if found is None:
            return points, why
        travelled += float(np.linalg.norm(found[0] - q))
        previous, (q, J) = direction, found
        if (
            travelled > CLOSE_AFTER * step
            and _wrapped_distance(tracer.task, q, q0) < CLOSE_WITHIN * step
        ):
            return points, "closed"
        points.append(q)
    return points, "step limit"


def _trace(
    tracer: _Tracer, q0: Array, count: int, step: float
) -> tuple[Array, Array, float, bool, tuple[str, ...]]:
    """Trace a 1-D manifold both ways (or once round a loop), resample ``count`` points."""
    J0 = tracer.task.error(q0, tracer.target)[1]
    forward, why_forward = _trace_one_way(tracer, q0, J0, 1.0, step)
    if why_forward == "closed":
        # A loop smaller than the step (near a singular posture, where the self-motion
        # shrinks to a point): its points zig-zag on it and their sum is no length. Traced
        # again at a tenth of its extent; below SMALLEST_LOOP, refused (the corrector's
        # rounding is then a share of the loop).
        spread = max(
            (float(np.linalg.norm(_shortest(tracer.task, p - q0))) for p in forward),
            default=0.0,
        )
        if spread < SMALLEST_LOOP:
            raise InputError(
                "q0",
                f"a configuration whose self-motion reaches {SMALLEST_LOOP:g} rad or more from it",
                f"a loop of extent {spread:.2g} rad at q0 = {np.round(q0, 9).tolist()} (the "
                "self-motion shrinks to a point at a singular posture nearby)",
                "start further from the singular posture (e.g. 1e-3 rad in a joint), or "
                "take q0 as its one posture",
            )
        if spread < step:
            return _trace(tracer, q0, count, spread / 10.0)
        # The loop: q0, the points, and back to q0 (shifted by the turns of the periodic
        # joints, so that the closing segment is short).
        last = forward[-1] if forward else q0
        closing = last + _shortest(tracer.task, q0 - last)
        curve = np.array([q0, *forward, closing])
        stops: tuple[str, ...] = ("closed",)
        closed = True
    else:
        backward, why_backward = _trace_one_way(tracer, q0, J0, -1.0, step)
        curve = np.array([*backward[::-1], q0, *forward])
        stops = (why_backward, why_forward)
        closed = False
        start = len(backward)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    length = float(arc[-1])
    if not length > 0:
        raise InputError(
            "q0",
            "a configuration whose self-motion has room to move",
            f"joint limits blocking it both ways at q0 = {np.round(q0, 6).tolist()}",
            "start from a configuration further inside the joint limits.",
        )
    if closed:
        where = length * np.arange(count) / count
        origin = 0.0
    else:
        where = np.linspace(0.0, length, count) if count > 1 else np.array([arc[start]])
        origin = float(arc[start])
    samples = np.empty((count, len(q0)))
    for j, s in enumerate(where):
        i = min(int(np.searchsorted(arc, s, side="right")) - 1, len(arc) - 2)
        fraction = (s - arc[i]) / (arc[i + 1] - arc[i]) if arc[i + 1] > arc[i] else 0.0
        guess = curve[i] + fraction * (curve[i + 1] - curve[i])
        found = tracer.correct(guess)
        if found is None or not tracer.task.inside(found[0]):
            samples[j] = curve[i] if fraction < 0.5 else curve[i + 1]  # a traced point
        else:
            samples[j] = found[0]
    return samples, where - origin, length, closed, stops


def _shortest(task: _Task, difference: Array) -> Array:
    """``difference`` with its periodic joints' entries reduced to [-pi, pi)."""
    out = difference.copy()
    out[task.periodic] = (out[task.periodic] + np.pi) % (2 * np.pi) - np.pi
    return out


def _walk(
    tracer: _Tracer, q0: Array, count: int, step: float, seed: int
) -> tuple[Array, Array, float, bool, tuple[str, ...]]:
    """A seeded random walk on the manifold: a sample every WALK_STEPS corrected steps."""
    rng = np.random.default_rng(seed)
    samples = np.empty((count, len(q0)))
    q, J = q0, tracer.task.error(q0, tracer.target)[1]
    failed, k = 0, 0
    while k < count:
        moved = False
        for _ in range(WALK_STEPS):
            basis = tracer.null_space(J)
            assert basis is not None  # q0 is not singular; steps onto a singularity are refused
            z = rng.standard_normal(len(basis))
            direction = z @ basis / np.linalg.norm(z)
            found, _ = tracer.advance(q, direction, step)
            if found is not None and tracer.null_space(found[1]) is not None:
                (q, J), moved = found, True
        if not moved:
            failed += 1
            if failed > MAX_FAILED_WALKS:
                raise SolverError(
                    f"self_motion: the random walk is stuck after {k} of {count} samples "
                    "(every step leaves the joint limits or fails to converge); try a "
                    "smaller step or another q0."
                )
            continue
        failed = 0
        samples[k] = q
        k += 1
    return samples, np.linalg.norm(samples - q0, axis=1), float("nan"), False, ()
