r"""Real robots from URDF, with the rigid-body dynamics of Pinocchio.

Needs the optional extra ``polyell[robots]`` (the ``pin`` distribution).  At a
configuration :math:`q` (and joint velocity :math:`\dot q`, zero by default):

* ``J``: rows of the 6-D frame Jacobian of the tip, in the world-aligned frame at the tip
  (``LOCAL_WORLD_ALIGNED``: linear rows x, y, z, then angular rows wx, wy, wz);
* ``B``: the joint-space inertia matrix (CRBA);
* ``g``: the gravity torques; for :math:`\dot q \ne 0` the nonlinear effects
  :math:`c(q, \dot q) + g(q)`, and ``xdd_bias`` :math:`= \dot J \dot q`, the classical
  acceleration of the tip at zero joint acceleration (eq. 2-3 of the paper).

Joint positions outside the URDF's position limits are evaluated, with a
:class:`~polyell.JointLimitWarning` (once per call, naming the joints; a hint at degrees
where revolute joints are beyond a full turn).  A robot with a torque-speed model in motion
gives its :class:`~polyell.Dynamics` the torque limits at ``qd``
(:class:`~polyell.models.dynamics.MotionLimits`): an analysis with the rated ones warns
(:class:`~polyell.DeratingWarning`); :meth:`UrdfRobot.analyze` uses the limits at ``qd``.
"""

from __future__ import annotations

import hashlib
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.cached import cached_property
from polyell.errors import InputError, JointLimitWarning, MissingDependencyError, install_hint
from polyell.models.dynamics import Dynamics, MotionLimits
from polyell.models.joint_limits import JointLimits, check_torque_speed
from polyell.models.torque_speed import TorqueSpeed
from polyell.validation import (
    array_ndim,
    check_array,
    check_spd,
    check_torque_limits,
    check_velocity_limits,
)

if TYPE_CHECKING:
    from polyell.capacities.base import Analysis

__all__ = [
    "POSITION_LIMIT_TOL",
    "TASKS",
    "TASK_ROWS",
    "Payload",
    "UrdfRobot",
    "import_pinocchio",
]

#: Rows of the 6-D frame Jacobian by name.
TASK_ROWS = {"x": 0, "y": 1, "z": 2, "wx": 3, "wy": 4, "wz": 5}
#: Named task spaces.
TASKS = {"linear": ("x", "y", "z"), "angular": ("wx", "wy", "wz"), "planar": ("x", "y")}
#: How far [rad or m] a joint position may be beyond its URDF limit without a
#: :class:`~polyell.JointLimitWarning`: rounding, or a limit printed to 6 digits.
POSITION_LIMIT_TOL = 1e-5


def import_pinocchio() -> ModuleType:
    """Import Pinocchio, or explain which extra provides it."""
    try:
        import pinocchio
    except ImportError as exn:
        raise MissingDependencyError(
            "Real robots need Pinocchio, which is not installed. Fix: "
            f"{install_hint('robots')} (the 'pin' distribution on PyPI)."
        ) from exn
    return pinocchio


@dataclass(frozen=True)
class Payload:
    """A rigid payload carried at the tip frame.

    Parameters
    ----------
    mass : float
        [kg], positive.
    com : array-like, shape (3,)
        Centre of mass in the tip frame [m].
    inertia : array-like, shape (3, 3)
        Rotational inertia about the centre of mass, in the tip frame [kg m^2]
        (symmetric positive semidefinite; default zero: a point mass).
    """

    mass: float
    com: Sequence[float] = (0.0, 0.0, 0.0)
    inertia: Sequence[Sequence[float]] = ((0.0,) * 3,) * 3


def _task_rows(task: str | Sequence[str | int]) -> list[int]:
    if isinstance(task, str):
        if task not in TASKS:
            raise InputError(
                "task",
                f"one of {list(TASKS)} or a list of rows among {list(TASK_ROWS)}",
                repr(task),
                "pass a named task, e.g. task='linear', or a list of rows, e.g. task=['x', 'z']",
            )
        return [TASK_ROWS[name] for name in TASKS[task]]
    if not isinstance(task, list | tuple):
        raise InputError(
            "task",
            f"one of {list(TASKS)} or a list of rows among {list(TASK_ROWS)}",
            f"{type(task).__name__} {task!r}",
            "pass a named task, e.g. task='linear', or convert the rows to a list, "
            "e.g. task=list(rows) or task=['x', 'z']",
        )
    rows = []
    for item in task:
        if isinstance(item, str) and item in TASK_ROWS:
            rows.append(TASK_ROWS[item])
        elif isinstance(item, int | np.integer) and not isinstance(item, bool) and 0 <= item < 6:
            rows.append(int(item))
        else:
            raise InputError(
                "task",
                f"rows among {list(TASK_ROWS)} or indices 0..5",
                f"row {item!r}",
                "name each row as 'x', 'y', 'z', 'wx', 'wy' or 'wz' (or its index 0..5), "
                "e.g. task=['x', 'z']",
            )
    if not rows or len(set(rows)) != len(rows):
        raise InputError(
            "task",
            "a non-empty list of distinct rows",
            repr(list(task)),
            "list each row once, e.g. task=['x', 'z']",
        )
    return rows


class UrdfRobot(JointLimits):
    """A fixed-base arm described by URDF, with dynamics from Pinocchio.

    Parameters
    ----------
    urdf : str or Path
        A URDF file (or a URDF document as a string starting with ``<``).
    tip : str
        Name of the frame (link or joint) whose acceleration is the task.
    task : str or sequence, optional
        ``"linear"`` (x, y, z), ``"angular"`` (wx, wy, wz), ``"planar"`` (x, y), or a list
        of rows among ``x y z wx wy wz``.  Mixing linear and angular rows needs
        ``weights`` (the paper's Euclidean metric is otherwise meaningless, section 1).
    locked_joints : sequence of str, optional
        Joints held at their neutral position (e.g. gripper fingers), removed with
        Pinocchio's reduced model.
    gravity : array-like, shape (3,), optional
        Gravity in the world frame [m/s^2].
    tau_max, tau_min : array-like, shape (n,), optional
        Torque limits [N m]; default the URDF's effort limits (``tau_min = -tau_max``).
    weights : array-like, optional
        One positive scale per task row (its unit becomes weight x native unit); required
        to mix linear and angular rows.
    payload : Payload, optional
        Mass carried at the tip frame.
    qd_max, qd_min : array-like, shape (n,), optional
        Joint velocity limits [rad/s or m/s], a box ``qd_min < qd_max`` (usually
        ``qd_min <= 0 < qd_max``); default the
        URDF's ``velocity`` limits (Pinocchio's ``velocityLimit``; ``qd_min = -qd_max``).
        Where the URDF gives none for a joint (no ``<limit>``, or ``velocity="0"``),
        :attr:`qd_max` is None and :meth:`velocity_limits` says which joints lack one.
    torque_speed : TorqueSpeed, optional
        The joints' torque-speed curves: :meth:`torque_limits` gives the torque limits
        at a joint velocity.  Its stall torques must hold ``tau_max`` and ``tau_min``.

    Examples
    --------
    >>> import polyell as pe
    >>> robot = pe.robots.load("panda")  # doctest: +SKIP
    >>> robot.nq, robot.joint_names[0]  # doctest: +SKIP
    (7, 'panda_joint1')
    """

    def __init__(
        self,
        urdf: str | os.PathLike[str],
        tip: str,
        task: str | Sequence[str | int] = "linear",
        locked_joints: Sequence[str] = (),
        gravity: ArrayLike = (0.0, 0.0, -9.81),
        *,
        tau_max: ArrayLike | None = None,
        tau_min: ArrayLike | None = None,
        weights: ArrayLike | None = None,
        payload: Payload | None = None,
        qd_max: ArrayLike | None = None,
        qd_min: ArrayLike | None = None,
        torque_speed: TorqueSpeed | None = None,
    ) -> None:
        pin = import_pinocchio()
        if not isinstance(locked_joints, list | tuple) or not all(
            isinstance(name, str) for name in locked_joints
        ):
            raise InputError(
                "locked_joints",
                "a list of joint names",
                repr(locked_joints),
                "pass the joint names as a list of str, e.g. locked_joints=['panda_finger_joint1']",
            )
        if not isinstance(tip, str):
            raise InputError(
                "tip",
                "a frame name",
                repr(tip),
                "pass the name of the tip's link or joint as a str, e.g. tip='panda_hand'",
            )
        self._pin = pin
        self._arguments = {
            "urdf": urdf if str(urdf).lstrip().startswith("<") else str(urdf),
            "tip": tip,
            "task": task,
            "locked_joints": tuple(locked_joints),
            "gravity": gravity,
            "tau_max": tau_max,
            "tau_min": tau_min,
            "weights": weights,
            "payload": payload,
            "qd_max": qd_max,
            "qd_min": qd_min,
            "torque_speed": torque_speed,
        }
        full = self._build(pin, urdf)
        text = str(urdf) if str(urdf).lstrip().startswith("<") else Path(urdf).read_bytes()
        #: SHA-256 of the URDF's text as loaded: what a resumed sweep checks, since the
        #: robot pickles by its file's path (an edited file is another robot).
        self.content_digest = hashlib.sha256(
            text.encode() if isinstance(text, str) else text
        ).hexdigest()
        locked = []
        for name in locked_joints:
            if not full.existJointName(name):
                raise InputError(
                    "locked_joints",
                    f"joint names among {list(full.names)[1:]}",
                    repr(name),
                    f"use one of the joint names listed, e.g. {list(full.names)[-1]!r}",
                )
            locked.append(full.getJointId(name))
        model = pin.buildReducedModel(full, locked, pin.neutral(full)) if locked else full
        for joint in list(model.joints)[1:]:
            if joint.nv != 1 or joint.nq not in (1, 2):
                raise InputError(
                    "urdf",
                    "a fixed-base arm of revolute or prismatic joints",
                    f"a joint of type {joint.shortname()}",
                    "lock it, or describe the arm without a floating base.",
                )
        matches = [i for i, frame in enumerate(model.frames) if frame.name == tip]
        if not matches:
            frames = [f.name for f in model.frames]
            raise InputError(
                "tip",
                f"a frame of the robot, e.g. {frames[-3:]}",
                repr(tip),
                f"use the name of one of the robot's links or joints, e.g. tip={frames[-1]!r}",
            )
        # A link and its parent joint may share a name: the link (body) frame is the tip.
        bodies = [i for i in matches if model.frames[i].type == pin.FrameType.BODY]
        self.tip = tip
        self._frame = (bodies or matches)[0]
        self.rows = _task_rows(task)
        self.task = task
        #: The task rows by name, in order (x, z, wx, ...).
        self.row_names = tuple(next(k for k, v in TASK_ROWS.items() if v == r) for r in self.rows)
        linear = any(r < 3 for r in self.rows)
        angular = any(r >= 3 for r in self.rows)
        if weights is None:
            if linear and angular:
                raise InputError(
                    "task",
                    "rows that are all linear or all angular (the Euclidean metric of the "
                    "ellipsoids is meaningless across units)",
                    f"mixed rows {[k for k, v in TASK_ROWS.items() if v in self.rows]}",
                    "pass weights=[...], one positive scale per row, to make the metric explicit.",
                )
            self.weights = np.ones(len(self.rows))
        else:
            self.weights = check_array("weights", weights, (len(self.rows),))
            if np.any(self.weights <= 0):
                raise InputError(
                    "weights",
                    "positive scales",
                    f"{self.weights}",
                    f"give every one of the {len(self.rows)} rows a scale > 0, "
                    f"e.g. weights={[1.0] * len(self.rows)}",
                )
        model.gravity.linear = check_array("gravity", gravity, (3,))
        if payload is not None:
            if not isinstance(payload, Payload):
                raise InputError(
                    "payload",
                    "a pe.Payload(mass, com, inertia)",
                    f"{type(payload).__name__} {payload!r}"[:120],
                    "wrap the values: payload=pe.Payload(mass=1.0, com=[0, 0, 0.05]).",
                )
            self._attach(pin, model, payload)
        self.model = model
        self._data = model.createData()
        self.joint_names: list[str] = list(model.names)[1:]
        if tau_max is None:
            effort = np.array(model.effortLimit, dtype=float)
            missing = [
                n for n, e in zip(self.joint_names, effort, strict=True) if not 0 < e < np.inf
            ]
            if missing:
                raise InputError(
                    "tau_max",
                    "effort limits in the URDF for every joint",
                    f"none for {missing}",
                    "pass tau_max=[...] explicitly.",
                )
            tau_max = effort
        self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, self.nq)
        self.qd_max: NDArray[np.float64] | None = None
        self.qd_min: NDArray[np.float64] | None = None
        if qd_max is None:
            if qd_min is not None:
                raise InputError(
                    "qd_min", "qd_min only together with qd_max", "qd_min alone", "give both."
                )
            velocity = np.array(model.velocityLimit, dtype=float)
            lacking = [
                name
                for name, v in zip(self.joint_names, velocity, strict=True)
                if not 0 < v < np.inf
            ]
            if lacking:
                self._no_velocity_limits = (
                    f"none in the URDF for {lacking} (no <limit velocity=...>, or 0)"
                )
            else:
                qd_max = velocity
        if qd_max is not None:
            self.qd_max, self.qd_min = check_velocity_limits(qd_max, qd_min, self.nq)
            self.qd_max.flags.writeable = self.qd_min.flags.writeable = False
        self.torque_speed = check_torque_speed(torque_speed, self.nq, self.tau_max, self.tau_min)

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle by the constructor's arguments (Pinocchio's objects are rebuilt)."""
        return (_rebuild, (self._arguments,))

    @staticmethod
    def _build(pin: ModuleType, urdf: str | os.PathLike[str]) -> Any:
        text = str(urdf)
        document = text.lstrip().startswith("<")
        if not document and not Path(text).is_file():  # outside the try: not re-wrapped below
            raise InputError(
                "urdf",
                "an existing URDF file",
                repr(text),
                "check the path (relative paths start at os.getcwd()), or pass the URDF "
                "document itself as a str starting with '<'",
            )
        try:
            if document:
                return pin.buildModelFromXML(text)
            return pin.buildModelFromUrdf(text)
        except (ValueError, RuntimeError) as exn:
            raise InputError(
                "urdf",
                "a valid URDF description",
                f"{exn}"[:200],
                "correct the URDF where the parser's message points (e.g. an unclosed tag), "
                "then load it again",
            ) from None

    def _attach(self, pin: ModuleType, model: Any, payload: Payload) -> None:
        mass = float(check_array("payload.mass", payload.mass, ()))
        if mass <= 0:
            raise InputError(
                "payload.mass",
                "a positive mass [kg]",
                f"{mass}",
                "give the payload's mass in kg, e.g. pe.Payload(mass=1.0), or pass payload=None",
            )
        com = check_array("payload.com", payload.com, (3,))
        inertia = np.asarray(check_array("payload.inertia", payload.inertia, (3, 3)))
        if np.any(inertia):
            inertia = check_spd("payload.inertia", inertia + 0.0, 3)
        frame = model.frames[self._frame]
        body = pin.Inertia(mass, com, inertia)
        joint = frame.parentJoint
        model.inertias[joint] = model.inertias[joint] + frame.placement.act(body)

    @property
    def nq(self) -> int:
        """Number of joints (one angle or displacement each)."""
        return int(self.model.nv)

    @property
    def n(self) -> int:
        """Number of joints (alias of :attr:`nq`)."""
        return self.nq

    @property
    def m(self) -> int:
        """Task-space dimension."""
        return len(self.rows)

    @property
    def position_limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper joint positions from the URDF, shape (nq,) each.

        Unbounded (continuous) joints get ``[-pi, pi]``.
        """
        low, high = np.full(self.nq, -np.pi), np.full(self.nq, np.pi)
        for joint in list(self.model.joints)[1:]:
            if joint.nq == 1:
                low[joint.idx_v] = self.model.lowerPositionLimit[joint.idx_q]
                high[joint.idx_v] = self.model.upperPositionLimit[joint.idx_q]
        return low, high

    @cached_property
    def _position_bounds(
        self,
    ) -> tuple[NDArray[Any], ...]:
        """The limits :class:`~polyell.JointLimitWarning` checks, shape (nq,) each.

        ``(low, high, low - tol, high + tol)`` with ``tol`` :data:`POSITION_LIMIT_TOL`, and
        which joints are revolute.  Continuous joints, and joints whose URDF gives no range
        (not finite, or ``lower >= upper``), are unbounded (``+-inf``).
        """
        low, high = np.full(self.nq, -np.inf), np.full(self.nq, np.inf)
        revolute = np.zeros(self.nq, dtype=bool)
        lower, upper = self.model.lowerPositionLimit, self.model.upperPositionLimit
        for joint in list(self.model.joints)[1:]:
            kind = joint.shortname()
            revolute[joint.idx_v] = not (kind.startswith("JointModelP") or "Prismatic" in kind)
            if joint.nq != 1:
                continue  # (cos, sin): a continuous joint, no limits
            a, b = float(lower[joint.idx_q]), float(upper[joint.idx_q])
            if np.isfinite(a) and np.isfinite(b) and a < b:
                low[joint.idx_v], high[joint.idx_v] = a, b
        bounds = (low, high, low - POSITION_LIMIT_TOL, high + POSITION_LIMIT_TOL, revolute)
        for array in bounds:
            array.flags.writeable = False
        return bounds

    def check_positions(self, q: ArrayLike, *, stacklevel: int = 1) -> NDArray[np.float64]:
        """Warn once if joint positions are outside the URDF's limits; return them checked.

        What :meth:`dynamics` and :meth:`tip_kinematics` do first: a caller that evaluates
        a batch in chunks checks it once here and passes ``check_limits=False`` per chunk.

        Parameters
        ----------
        q : array-like, shape (nq,) or (K, nq)
            Joint positions [rad or m].
        stacklevel : int, optional
            Which line the warning names, as :func:`warnings.warn`'s but counted from the
            caller (1: the line that called this method, 2: its caller's).

        Returns
        -------
        ndarray, shape (nq,) or (K, nq)
            ``q`` as a finite float array.

        Warns
        -----
        JointLimitWarning
            Where a joint is beyond its range by more than :data:`POSITION_LIMIT_TOL`
            (continuous joints have none).

        Raises
        ------
        InputError
            On a wrong shape or a non-finite value.
        """
        shape = ("K", self.nq) if array_ndim(q) == 2 else (self.nq,)
        positions = check_array("q", q, shape, what="joint positions [rad or m]")
        self._check_positions(np.atleast_2d(positions), stacklevel=stacklevel + 1)
        return positions

    def _check_positions(self, positions: NDArray[np.float64], stacklevel: int) -> None:
        """Warn (JointLimitWarning) once if checked positions (K, nq) leave the limits.

        ``stacklevel`` as :func:`warnings.warn`'s, counted from this function's caller (1:
        the line that called this function, 2: the line that called that caller).
        """
        low, high, lowest, highest, revolute = self._position_bounds
        below, above = positions < lowest, positions > highest
        if not (below.any() or above.any()):
            return
        rows = len(positions)
        parts, joints, degrees = [], [], False
        for j in np.flatnonzero(below.any(axis=0) | above.any(axis=0)):
            excess = np.maximum(low[j] - positions[:, j], positions[:, j] - high[j])
            k = int(np.argmax(excess))
            value, unit = positions[k, j], "rad" if revolute[j] else "m"
            side = "below" if value < low[j] else "above"
            bad = below[:, j] | above[:, j]
            beyond = f"{excess[k]:.4g} {unit} {side} its range [{low[j]:.6g}, {high[j]:.6g}]"
            parts.append(
                f"{self.joint_names[j]} in {int(bad.sum())} of {rows} configurations (worst: "
                f"row {k}, q = {value:.6g} {unit}, {beyond})"
                if rows > 1
                else f"{self.joint_names[j]} = {value:.6g} {unit} ({beyond})"
            )
            joints.append(self.joint_names[j])
            degrees |= bool(revolute[j] and np.any(np.abs(positions[bad, j]) > 2 * np.pi))
        hint = (
            " Revolute joints beyond a full turn (|q| > 2 pi rad): these look like degrees; "
            "convert them with np.deg2rad(q) (polyell analyze: --deg)."
            if degrees
            else ""
        )
        message = (
            f"q: expected joint positions within the robot's limits (its URDF's), got "
            f"{'; '.join(parts)}.{hint} The values are computed anyway. Fix: keep q within "
            "robot.position_limits (pe.random_configurations draws within them), or silence "
            "this with warnings.simplefilter('ignore', pe.JointLimitWarning)."
        )
        warnings.warn(JointLimitWarning(message, tuple(joints), degrees), stacklevel=stacklevel + 1)

    def _check_velocities(self, velocities: NDArray[np.float64], stacklevel: int) -> None:
        """Warn (JointLimitWarning) once if checked velocities (K, nq) leave the limits.

        The robot's velocity limits (:attr:`qd_max`, :attr:`qd_min`; none known: no
        check), with the positions' relative slack; where the velocities scaled from
        degrees per second to radians would lie within them, the message says so.
        """
        if self.qd_max is None or self.qd_min is None:
            return
        slack = POSITION_LIMIT_TOL * np.maximum(np.abs(self.qd_max), np.abs(self.qd_min))
        below, above = velocities < self.qd_min - slack, velocities > self.qd_max + slack
        if not (below.any() or above.any()):
            return
        rows, (_, _, _, _, revolute) = len(velocities), self._position_bounds
        parts, joints = [], []
        for j in np.flatnonzero(below.any(axis=0) | above.any(axis=0)):
            excess = np.maximum(
                self.qd_min[j] - velocities[:, j], velocities[:, j] - self.qd_max[j]
            )
            k = int(np.argmax(excess))
            unit = "rad/s" if revolute[j] else "m/s"
            within = f"its limits [{self.qd_min[j]:.6g}, {self.qd_max[j]:.6g}] {unit}"
            count = int((below[:, j] | above[:, j]).sum())
            parts.append(
                f"{self.joint_names[j]} in {count} of {rows} states (worst: row {k}, "
                f"qd = {velocities[k, j]:.6g} {unit}, beyond {within})"
                if rows > 1
                else f"{self.joint_names[j]} = {velocities[k, j]:.6g} {unit} (beyond {within})"
            )
            joints.append(self.joint_names[j])
        # degrees per second: far beyond the limits (5x or more), within them in radians
        scaled, outside = np.deg2rad(velocities), below | above
        reach = np.maximum(np.abs(self.qd_max), np.abs(self.qd_min))
        degrees = bool(
            np.all(revolute[outside.any(axis=0)])
            and np.any(np.abs(velocities) > 5.0 * reach)
            and np.all((scaled >= self.qd_min - slack) & (scaled <= self.qd_max + slack))
        )
        hint = (
            " In radians these would lie within the limits: they look like degrees per "
            "second; convert them with np.deg2rad(qd)."
            if degrees
            else ""
        )
        message = (
            f"qd: expected joint velocities within the robot's velocity limits, got "
            f"{'; '.join(parts)}.{hint} The values are computed anyway (the arm cannot "
            "move that fast: the Coriolis terms and any torque-speed derating are "
            "extrapolated). Fix: keep qd within robot.velocity_limits(), or silence this "
            "with warnings.simplefilter('ignore', pe.JointLimitWarning)."
        )
        warnings.warn(JointLimitWarning(message, tuple(joints), degrees), stacklevel=stacklevel + 1)

    def __repr__(self) -> str:
        return (
            f"UrdfRobot(model={self.model.name!r}, nq={self.nq}, tip={self.tip!r}, "
            f"task={self.task!r})"
        )

    def configuration(self, q: ArrayLike) -> NDArray[np.float64]:
        """Pinocchio's configuration vector for joint angles ``q``.

        Unbounded (continuous) revolute joints are stored by Pinocchio as (cos, sin).

        Parameters
        ----------
        q : array-like, shape (nq,) or (K, nq)
            Joint positions [rad or m].

        Returns
        -------
        ndarray, shape (model.nq,) or (K, model.nq)
        """
        shape = ("K", self.nq) if array_ndim(q) == 2 else (self.nq,)
        angles = check_array("q", q, shape, what="joint positions [rad or m]")
        return self._configurations(np.atleast_2d(angles)).reshape(*angles.shape[:-1], -1)

    @cached_property
    def _joint_slots(self) -> tuple[NDArray[np.int_], ...]:
        """Where the joint angles go in the configuration vector.

        ``(to, from)`` indices for one-coordinate joints, then for (cos, sin) joints.
        """
        joints = list(self.model.joints)[1:]
        plain = [(j.idx_q, j.idx_v) for j in joints if j.nq == 1]
        circle = [(j.idx_q, j.idx_v) for j in joints if j.nq == 2]
        to, source = np.array(plain, dtype=int).reshape(-1, 2).T
        circle_to, circle_source = np.array(circle, dtype=int).reshape(-1, 2).T
        return to, source, circle_to, circle_source

    def _configurations(self, angles: NDArray[np.float64]) -> NDArray[np.float64]:
        """Configuration vectors of checked angles (K, nq): shape (K, model.nq)."""
        to, source, circle_to, circle_source = self._joint_slots
        config = np.empty((len(angles), self.model.nq))
        config[:, to] = angles[:, source]
        config[:, circle_to] = np.cos(angles[:, circle_source])
        config[:, circle_to + 1] = np.sin(angles[:, circle_source])
        return config

    def tip_kinematics(
        self, q: ArrayLike, *, check_limits: bool = True
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Where the tip frame is at ``q``, and the task Jacobian: the task's coordinates.

        The linear rows of ``J`` are the derivatives of the position, the angular rows the
        world angular velocity of the rotation (``LOCAL_WORLD_ALIGNED``).  Cheaper than
        :meth:`dynamics` (no inertia, no gravity).

        Parameters
        ----------
        q : array-like, shape (nq,)
            Joint positions [rad or m].
        check_limits : bool, optional
            Warn (:class:`~polyell.JointLimitWarning`) where ``q`` is outside the URDF's
            position limits (default); False for a caller that probes beyond them on
            purpose (and checks them itself).

        Returns
        -------
        position : ndarray, shape (3,)
            The tip's origin in the world frame [m].
        rotation : ndarray, shape (3, 3)
            Its orientation, world from tip.
        J : ndarray, shape (m, nq)
            The task rows of the frame Jacobian times their weights, as ``dynamics(q).J``.
        """
        pin, model, data = self._pin, self.model, self._data
        angles = check_array("q", q, (self.nq,), what="joint positions [rad or m]")
        if check_limits:
            self._check_positions(angles[None], stacklevel=2)
        config = self._configurations(angles[None])[0]
        pin.computeJointJacobians(model, data, config)
        pin.updateFramePlacements(model, data)
        J = np.reshape(
            pin.getFrameJacobian(model, data, self._frame, pin.LOCAL_WORLD_ALIGNED), (6, self.nq)
        )
        placement = data.oMf[self._frame]
        return (
            np.array(placement.translation, dtype=float),
            np.array(placement.rotation, dtype=float),
            J[self.rows] * self.weights[:, None],
        )

    def dynamics(
        self, q: ArrayLike, qd: ArrayLike | None = None, *, check_limits: bool = True
    ) -> Dynamics:
        """Jacobian, inertia and gravity (or nonlinear) torques at ``q``.

        Parameters
        ----------
        q : array-like, shape (nq,) or (K, nq)
            Joint positions [rad or m]; a 2-D array gives a batched :class:`Dynamics`.
            Positions outside the URDF's limits are evaluated with one
            :class:`~polyell.JointLimitWarning` per call (a batch included).
        qd : array-like, same shape as ``q``, optional
            Joint velocities [rad/s or m/s]; nonzero adds the Coriolis and centrifugal
            torques to ``g`` and ``Jdot qdot`` as ``xdd_bias``.  With a
            :attr:`torque_speed` model, the Dynamics carries the torque limits at ``qd``
            (``motion``, a :class:`~polyell.models.dynamics.MotionLimits`): an analysis
            given larger ones (the rated limits) warns with a
            :class:`~polyell.DeratingWarning`.
        check_limits : bool, optional
            Warn where ``q`` is outside the position limits (default); False for a caller
            that probes beyond them on purpose (and checks them itself).

        Returns
        -------
        Dynamics
        """
        return self._dynamics(q, qd, check_limits, stacklevel=3)

    def _dynamics(
        self, q: ArrayLike, qd: ArrayLike | None, check_limits: bool, stacklevel: int
    ) -> Dynamics:
        """:meth:`dynamics`; a JointLimitWarning names the frame ``stacklevel`` up from here.

        (1: this function's line, 2: the line that called it, 3: that caller's caller.)
        """
        shape = ("K", self.nq) if array_ndim(q) == 2 else (self.nq,)
        positions = check_array("q", q, shape, what="joint positions")
        velocities = (
            None if qd is None else check_array("qd", qd, positions.shape, what="joint velocities")
        )
        if velocities is not None and not np.any(velocities):
            velocities = None
        if check_limits:
            self._check_positions(np.atleast_2d(positions), stacklevel=stacklevel)
            if velocities is not None:
                self._check_velocities(np.atleast_2d(velocities), stacklevel=stacklevel)
        terms = self._terms(
            np.atleast_2d(positions), None if velocities is None else np.atleast_2d(velocities)
        )
        J, B, g, bias = (t if positions.ndim == 2 else t[0] for t in terms)
        motion = None if velocities is None else self._motion_limits(velocities)
        return Dynamics(J, B, g, bias, task=self.row_names, motion=motion)

    def _motion_limits(self, velocities: NDArray[np.float64]) -> MotionLimits | None:
        """The torque limits at checked nonzero ``velocities`` with a torque-speed model.

        None without a model, or where :meth:`torque_limits` refuses the velocities (past
        a tabulated curve: it says so to whoever asks for the limits).
        """
        if self.torque_speed is None:
            return None
        try:
            upper, lower = self.torque_limits(velocities)
        except InputError:
            return None
        rated_max, rated_min = self.torque_limits()
        return MotionLimits(velocities, upper, lower, rated_max, rated_min, self.joint_names)

    def analyze(
        self,
        q: ArrayLike,
        qd: ArrayLike | None = None,
        *,
        capacity: str = "acceleration",
        rank_rtol: float | None = None,
        affine_rtol: float | None = None,
        horizon: float | None = None,
        braking: ArrayLike | None = None,
    ) -> Analysis:
        """A capacity of the robot at ``q``, moving at ``qd``, within its own joint limits.

        The torque limits are those at ``qd``: derated by the robot's
        :attr:`torque_speed` model (:meth:`torque_limits`), the rated ones at rest or
        without a model.  The same as ``pe.analyze(robot.dynamics(q, qd),
        *robot.torque_limits(qd), capacity=capacity)``; the velocity capacity takes
        :meth:`velocity_limits` (and no ``qd``: its set is every joint velocity within
        them).

        Parameters
        ----------
        q : array-like, shape (nq,)
            Joint positions [rad or m] (a :class:`~polyell.JointLimitWarning` outside the
            URDF's limits).
        qd : array-like, shape (nq,), optional
            Joint velocities [rad/s or m/s]; default at rest.
        capacity : {"acceleration", "velocity", "force"}, optional
            As :func:`polyell.analyze`.
        horizon : float, optional
            A control period [s]: the accelerations that also keep every joint within
            :attr:`position_limits` over it and within :meth:`velocity_limits` at its end,
            from ``(q, qd)`` (:class:`~polyell.capacities.horizon.HorizonAnalysis`).
        braking : float or array-like, shape (nq,), optional
            With ``horizon``: viability, the deceleration [rad/s^2] each joint can still
            brake with after the period.
        rank_rtol, affine_rtol : float, optional
            As :func:`polyell.analyze` (default its defaults).

        Returns
        -------
        Analysis

        Raises
        ------
        InputError
            On a bad ``q``, ``qd`` or ``capacity``; a robot without the limits of the
            capacity; a ``qd`` past a tabulated torque-speed curve; joint velocities
            for the velocity capacity.

        Examples
        --------
        >>> import numpy as np, polyell as pe
        >>> drives = pe.TorqueSpeed.linear([87.0] * 4 + [12.0] * 3, [3.0] * 4 + [4.0] * 3)
        >>> robot = pe.robots.load("panda", torque_speed=drives)  # doctest: +SKIP
        >>> q, qd = [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8], [0.0, 1.5, 0.0, -1.5, 0.0, 0.0, 0.0]
        >>> moving = robot.analyze(q, qd)  # doctest: +SKIP
        >>> float(moving.tau_max[1]), float(moving.tau_min[3])  # doctest: +SKIP
        (43.5, -43.5)
        """
        from polyell.capacities import analyze, capacity_class

        cls = capacity_class(capacity)
        if array_ndim(q) == 2:
            raise InputError(
                "q",
                f"the joint positions of one configuration, shape ({self.nq},)",
                f"a batch of shape {np.shape(q)}",
                "analyze one row at a time, or call pe.sweep(robot, q) for the batch.",
            )
        dynamics = self._dynamics(q, qd, True, stacklevel=3)
        if not cls.in_motion and qd is not None and np.any(np.asarray(qd, dtype=float)):
            raise InputError(
                "qd",
                f"no joint velocities for the {cls.capacity} capacity (its set is every joint "
                "velocity within the limits, whatever the robot's motion)",
                "nonzero joint velocities",
                "leave qd out, or analyse accelerations or forces of the robot in motion.",
            )
        limits = cls.limit_arguments(*cls._robot_limits(self, qd if cls.in_motion else None))
        tolerances: dict[str, Any] = {
            name: value
            for name, value in (("rank_rtol", rank_rtol), ("affine_rtol", affine_rtol))
            if value is not None
        }
        if horizon is not None or braking is not None:
            from polyell.capacities import state_of

            if horizon is None:
                raise InputError(
                    "braking",
                    "braking only with a horizon",
                    f"{braking!r}",
                    "pass the control period too, e.g. horizon=0.01, or leave braking out",
                )
            from polyell.capacities.horizon import robot_horizon

            state_of(cls, horizon)  # accelerations only
            moving = np.zeros(self.nq) if qd is None else qd
            tolerances |= robot_horizon(self, horizon, braking=braking).at(q, moving).arguments()
        analysis: Analysis = analyze(dynamics, capacity=cls.capacity, **limits, **tolerances)
        return analysis

    def _terms(
        self, positions: NDArray[np.float64], velocities: NDArray[np.float64] | None
    ) -> tuple[NDArray[np.float64], ...]:
        """``(J, B, g, xdd_bias)`` for checked positions (K, nq): one Pinocchio call per row."""
        pin, model, data, frame = self._pin, self.model, self._data, self._frame
        world = pin.LOCAL_WORLD_ALIGNED
        configs = self._configurations(positions)
        K, n = len(configs), self.nq
        J, B, g = np.empty((K, 6, n)), np.empty((K, n, n)), np.empty((K, n))
        bias = np.zeros((K, 6))
        for k, config in enumerate(configs):
            pin.computeJointJacobians(model, data, config)
            pin.updateFramePlacements(model, data)
            # (Pinocchio returns a 1-joint model's Jacobian and inertia with fewer axes)
            J[k] = np.reshape(pin.getFrameJacobian(model, data, frame, world), (6, n))
            B[k] = np.reshape(pin.crba(model, data, config), (n, n))
            if velocities is None:
                g[k] = pin.computeGeneralizedGravity(model, data, config)
                continue
            g[k] = pin.nonLinearEffects(model, data, config, velocities[k])
            pin.forwardKinematics(model, data, config, velocities[k], np.zeros(n))
            acceleration = pin.getFrameClassicalAcceleration(model, data, frame, world)
            bias[k, :3], bias[k, 3:] = acceleration.linear, acceleration.angular
        B = np.triu(B) + np.swapaxes(np.triu(B, 1), 1, 2)  # Pinocchio fills the upper triangle
        return J[:, self.rows] * self.weights[:, None], B, g, bias[:, self.rows] * self.weights


def _rebuild(arguments: dict[str, Any]) -> UrdfRobot:
    """Unpickle a :class:`UrdfRobot`."""
    return UrdfRobot(**arguments)
