"""Study and robot files: read, validated by the typed models, loaded into a :class:`StudySpec`.

The format itself (keys, types, defaults, messages, the reference page and the JSON
Schemas) is :mod:`polyell.studies.models`, and the validated :class:`StudyFile
<polyell.studies.models.StudyFile>` is what a study reads its keys from.  This module reads
the TOML file, has the models validate it, and derives what needs the robots or other files
(the robot models, the points' joint vectors and directions, the grid's axes, the random
configurations, the trajectory, the posture's direction, the candidates), checking it before
anything is written.  ``docs/study_format.md`` describes the format.
"""

from __future__ import annotations

import math
import os
import re
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell import robots
from polyell.capacities import capacity_class
from polyell.capacities.horizon import robot_horizon
from polyell.comparison.candidates import Candidate, check_candidates
from polyell.comparison.directions import named_direction
from polyell.errors import InputError
from polyell.models.planar_arm import PlanarArm
from polyell.models.task import task_unit
from polyell.models.urdf import Payload, UrdfRobot
from polyell.studies.configurations import (
    ConfigurationSet,
    Grid,
    RandomConfigurations,
    uniform_rows,
)
from polyell.studies.trajectory import Trajectory, load_trajectory
from polyell.validation import array_ndim, check_array, check_joint_velocities

if TYPE_CHECKING:  # pydantic is imported where study files are read (start-up time)
    from polyell.studies import models

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "GridAxis",
    "Point",
    "Posture",
    "Robot",
    "SeededRows",
    "StudySpec",
    "load_robot_file",
    "load_study",
    "robot_from_table",
]


@contextmanager
def _within(where: str, outer: tuple[str, ...] = ()) -> Iterator[None]:
    """Name the key ``where`` in an InputError raised inside (``tau_max``: ``robot.tau_max``).

    Errors about the keys ``outer`` (keys of the enclosing table that the constructor
    called inside also takes) pass unchanged, for the enclosing ``_within`` to name.
    """
    try:
        yield
    except InputError as exn:
        if re.match(r"[A-Za-z_]*", exn.argument)[0] in outer:  # type: ignore[index]
            raise
        argument = exn.argument if exn.argument.startswith(where) else f"{where}.{exn.argument}"
        raise InputError(argument, exn.expected, exn.got, exn.fix) from None


#: The keys of a robot table on its joint limits, which every robot model takes.
LIMIT_KEYS = ("tau_max", "tau_min", "qd_max", "qd_min", "torque_speed")


@dataclass(frozen=True)
class Robot:
    """A robot model with its torque limits, as described in a file.

    ``name`` labels its outputs in a study of several robots (``""``: the study's only one).
    The model carries the file's velocity limits and torque-speed curves
    (``model.qd_max``, ``model.qd_min``, ``model.torque_speed``).
    """

    model: PlanarArm | UrdfRobot
    tau_max: NDArray[np.float64]
    tau_min: NDArray[np.float64]
    name: str = ""

    def torque_limits(
        self, qd: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The robot's torque limits ``(tau_max, tau_min)`` [N m], at rest or at ``qd``.

        ``tau_max`` and ``tau_min`` derated at the joint velocity ``qd`` (shape (n,) or
        (K, n)) by the model's torque-speed curves (:meth:`pe.TorqueSpeed.limits`);
        without ``qd`` or curves, the rated limits (repeated along a batch of ``qd``).
        """
        curves = self.model.torque_speed
        if curves is not None and qd is not None:
            return curves.limits(qd, self.tau_max, self.tau_min)
        if qd is None:
            return self.tau_max.copy(), self.tau_min.copy()
        n = self.model.n
        shape = ("K", n) if array_ndim(qd) == 2 else (n,)
        velocity = check_array("qd", qd, shape, what="joint velocities [rad/s or m/s]")
        return (
            np.broadcast_to(self.tau_max, velocity.shape).copy(),
            np.broadcast_to(self.tau_min, velocity.shape).copy(),
        )

    def velocity_limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The model's joint velocity limits ``(qd_max, qd_min)``; see its method."""
        return self.model.velocity_limits()


def _given(table: models.Table, names: tuple[str, ...]) -> dict[str, Any]:
    """The keys ``names`` that a validated table gives (not None), with their values."""
    return {name: getattr(table, name) for name in names if getattr(table, name) is not None}


def _build_robot(table: models.RobotTable, where: str, folder: Path | None) -> Robot:
    """The robot of a validated robot table; model errors name the key (``robot.tau_max``)."""
    options = _given(table, ("tip", "task", "locked_joints", "gravity", "weights"))
    if table.payload is not None:
        payload = table.payload
        with _within(f"{where}.payload"):
            options["payload"] = Payload(payload.mass, payload.com, payload.inertia)
    # The joint limits go to the model, which checks them together (the torque-speed
    # curves against the rated limits); errors name the robot table's keys.
    limits = _given(table, ("tau_max", "tau_min", "qd_max", "qd_min"))
    if table.torque_speed is not None:
        limits["torque_speed"] = table.torque_speed.build()
    model: PlanarArm | UrdfRobot
    with _within(where):
        if table.tau_min is not None and table.tau_max is None:
            raise InputError("tau_min", "tau_min only with tau_max", "tau_min alone", "give both.")
        if table.planar is not None:
            planar = table.planar
            with _within(f"{where}.planar", outer=LIMIT_KEYS):
                model = PlanarArm(
                    planar.lengths,
                    planar.masses,
                    com=planar.com,
                    inertia=planar.inertia,
                    gravity=planar.gravity,
                    **limits,
                )
        elif table.library is not None:
            model = robots.load(table.library, **options, **limits)
        else:
            assert table.urdf is not None
            path = Path(table.urdf)
            if folder is not None and not path.is_absolute():
                path = folder / path
            model = UrdfRobot(path, **options, **limits)
        if model.tau_max is None and model.torque_speed is None:
            raise InputError(
                "tau_max",
                "torque limits for a robot without its own",
                "no tau_max key",
                "add tau_max = [...] (N m, one per joint), or torque_speed = { ... }.",
            )
        # Without rated limits, the stall torques of the curves are the limits at rest.
        tau_max, tau_min = model.torque_limits()
    return Robot(model, tau_max, tau_min, table.name or "")


def robot_from_table(table: object, where: str = "robot", folder: Path | None = None) -> Robot:
    """Build a robot from a ``[robot]`` table (a dict, as TOML gives it).

    Exactly one of ``library`` (a name of :func:`polyell.robots.names`), ``planar`` (a
    link table) or ``urdf`` (a file, relative to ``folder``, with ``tip``); URDF robots
    also take ``task``, ``locked_joints``, ``gravity``, ``weights`` and ``payload``
    (``{ mass, com, inertia }``); every robot takes ``tau_max`` and ``tau_min``.

    Raises
    ------
    InputError
        Naming the key (``robot.tau_max``) on any bad value.
    """
    from polyell.studies.models import parse_robot

    return _build_robot(parse_robot(table, where), where, folder)


def _read_toml(path: str | os.PathLike[str], what: str = "study") -> dict[str, Any]:
    """The table of a TOML file; every way of failing is an InputError naming the file.

    A folder, an unreadable or non-UTF-8 file, invalid TOML and nesting too deep for the
    parser (a RecursionError in ``tomllib``) are all refused with what to do.
    """
    if not isinstance(path, str | os.PathLike):
        raise InputError(
            "path",
            f"the path of a {what} TOML file",
            f"{type(path).__name__}",
            "pass a str or pathlib.Path, e.g. 'study.toml'.",
        )
    shown = repr(str(path))
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except FileNotFoundError:
        raise InputError(
            "path",
            f"an existing TOML file describing a {what}",
            shown,
            f"check the name and the folder (relative paths start at {os.getcwd()!r}).",
        ) from None
    except IsADirectoryError:
        raise InputError(
            "path", f"a TOML file describing a {what}", f"{shown}, a folder", "give a file."
        ) from None
    except OSError as exn:  # permissions, a device, a name too long, ...
        raise InputError(
            "path",
            f"a readable TOML file describing a {what}",
            f"{shown} ({exn.strerror or exn})",
            "check the file's permissions, or copy it somewhere readable.",
        ) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exn:
        raise InputError(
            "path",
            "a TOML file in UTF-8 (the encoding TOML prescribes)",
            f"{shown}: byte {data[exn.start]:#04x} at offset {exn.start} is not UTF-8",
            "save the file as UTF-8.",
        ) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exn:
        raise InputError(
            "path",
            "valid TOML",
            f"{shown}: {exn}",
            "correct the file at that line and column (strings in quotes, one key = value "
            "per line; docs/study_format.md has an example of each table).",
        ) from None
    except RecursionError:  # tomllib parses nested arrays and inline tables recursively
        raise InputError(
            "path",
            "TOML whose arrays and inline tables are nested at most a few hundred levels",
            f"{shown}, nested deeper than the parser can follow",
            "flatten the nesting: no value of a study file is nested more than 3 levels.",
        ) from None


def load_robot_file(path: str | os.PathLike[str]) -> Robot:
    """A robot file: TOML with the keys of a study's ``[robot]`` table at the top level."""
    table = _read_toml(path, "robot")
    return robot_from_table(table, where=Path(path).name, folder=Path(path).parent)


@dataclass(frozen=True)
class Point:
    """A ``[[points]]`` table on one robot, its joint vectors and directions resolved there.

    Attributes
    ----------
    table : PointTable
        The point as the file gives it (its ``name``, ``inverse_at`` and ``title``).
    robot : str
        The robot's name in a study of several robots, ``""`` in a study of one.
    q : ndarray, shape (n,)
        Joint angles [rad] on that robot.
    directions : ndarray, shape (k, m)
        Unit directions of the task space, one per row.
    labels : tuple of str, length k
        Their names: a task-row name (``"x"``, ``"-xz"``) or the vector, rounded.
    qd : ndarray, shape (n,), or None
        Joint velocities [rad/s] of a robot in motion (a URDF robot); None: at rest.
    """

    table: models.PointTable
    robot: str
    q: NDArray[np.float64]
    directions: NDArray[np.float64]
    labels: tuple[str, ...]
    qd: NDArray[np.float64] | None = None

    @property
    def direction(self) -> NDArray[np.float64]:
        """The first direction, shape (m,)."""
        return self.directions[0]

    @property
    def label(self) -> str:
        """``robot/name`` in a study of several robots, else ``name``."""
        return f"{self.robot}/{self.table.name}" if self.robot else self.table.name

    @property
    def stem(self) -> str:
        """The point's part of file names: ``robot.name`` (robot names hold no ``.``)."""
        return f"{self.robot}.{self.table.name}" if self.robot else self.table.name


@dataclass(frozen=True)
class Posture:
    """The ``[posture]`` table, with its direction resolved on the robot's task rows.

    Its keys are those of ``table`` (also read through the posture: ``posture.count``).

    Attributes
    ----------
    table : PostureTable
        The table as the file gives it.
    direction : ndarray, shape (m,)
        The unit task direction of the ``"limit"`` criterion.
    label : str
        Its name (``"x"``) or the vector, rounded.
    """

    table: models.PostureTable
    direction: NDArray[np.float64]
    label: str

    @property
    def starts(self) -> tuple[NDArray[np.float64], ...]:
        """q0, then the start of every further component, as arrays."""
        starts = (self.table.q0, *(self.table.components or ()))
        return tuple(np.array(q, dtype=float) for q in starts)

    def __getattr__(self, name: str) -> Any:
        """A key of the table (``q0``, ``count``, ``seed``, ``targets``, ``components``)."""
        if name.startswith("_") or name == "table":  # (copy and pickle look before table)
            raise AttributeError(name)
        return getattr(self.table, name)


@dataclass(frozen=True)
class GridAxis:
    """Values of one joint angle over a grid (a single value when it is fixed)."""

    name: str
    values: NDArray[np.float64]


@dataclass(frozen=True)
class StudySpec:
    """A loaded study: the validated file, and what was derived from it with the robots.

    Every key of the study is read on ``file`` (``spec.file.compare.samples``,
    ``spec.file.output.layout``); the other fields hold what needs the robots or other files.

    Attributes
    ----------
    file : StudyFile
        The study file, validated (:class:`polyell.studies.models.StudyFile`).
    path : Path
        The file's path.
    robots : tuple of Robot
        The robots built from ``[robot]`` or ``[[robots]]``, in file order.
    candidates : tuple of Candidate
        The ``[[candidates]]``, built and checked against every robot.
    points : tuple of Point
        Every point on every robot (point by point, robots in file order).
    grid : tuple of GridAxis
        A grid study's axes, one per joint.
    random_q : tuple of ConfigurationSet
        A random study's configurations, one lazy set per robot (:class:`SeededRows`:
        ``np.asarray`` gives the (count, n) array, ``rows(start, stop)`` a range of it).
    trajectory : Trajectory or None
        A trajectory study's path, loaded.
    posture : Posture or None
        A posture study's settings, checked against the robot.
    """

    file: models.StudyFile
    path: Path
    robots: tuple[Robot, ...]
    candidates: tuple[Candidate, ...] = ()
    points: tuple[Point, ...] = ()
    grid: tuple[GridAxis, ...] = ()
    random_q: tuple[ConfigurationSet, ...] = ()
    trajectory: Trajectory | None = None
    posture: Posture | None = None

    @property
    def title(self) -> str:
        """The study's title: its ``title`` key, else the file's name without suffix."""
        return self.file.title if self.file.title is not None else self.path.stem

    @property
    def capacities(self) -> tuple[str, ...]:
        """The compared capacities (``[compare] capacities``)."""
        return self.file.compare.capacities

    @property
    def by_robot(self) -> bool:
        """True for a study of ``[[robots]]`` (its outputs are labelled by robot)."""
        return self.file.robots is not None

    @property
    def robot(self) -> Robot:
        """The study's robot (a study of several: see :attr:`robots`)."""
        if len(self.robots) != 1:
            raise InputError(
                "spec.robot",
                "a study of one robot",
                f"{len(self.robots)} robots {[r.name for r in self.robots]}",
                "use spec.robots.",
            )
        return self.robots[0]

    @property
    def is_batch(self) -> bool:
        """True for many configurations (a grid, random samples or a trajectory)."""
        return bool(self.grid) or bool(self.random_q) or self.trajectory is not None

    def configurations(self, robot: int = 0) -> NDArray[np.float64]:
        """All configurations of robot number ``robot``, shape (K, n).

        A grid's (the last joint fastest), the robot's random ones, or a trajectory's, as
        one array (:meth:`configuration_set` makes them on demand instead).
        """
        return np.asarray(self.configuration_set(robot))

    def configuration_set(self, robot: int = 0) -> ConfigurationSet | NDArray[np.float64]:
        """The configurations of robot number ``robot``, made a range of rows at a time.

        A grid study's :class:`~polyell.studies.configurations.Grid` and a random study's
        :class:`SeededRows` (the rows of :meth:`configurations`, never all in memory:
        what the study passes to :func:`polyell.sweep`); a trajectory's array.
        """
        if self.trajectory is not None:
            return self.trajectory.q
        if self.random_q:
            return self.random_q[robot]
        return Grid([axis.values for axis in self.grid])


# ---------------------------------------------------------------------------------------
# What needs the robots


def _rows(model: PlanarArm | UrdfRobot) -> tuple[str, ...]:
    """The names of the robot's task rows (x, y, ...; wx, wy, wz angular)."""
    if isinstance(model, UrdfRobot):
        return tuple(model.row_names)
    return tuple(model.dynamics(np.zeros(model.n)).task)


def _directions(
    table: models.PointTable, rows: tuple[str, ...], where: str
) -> tuple[NDArray[np.float64], tuple[str, ...]]:
    """The point's directions (k, m) and their labels; default the task's axes."""
    m = len(rows)
    if table.directions is not None:
        items, key = list(table.directions), f"{where}.directions"
    elif table.direction is not None:
        items, key = [table.direction], f"{where}.direction"
    else:
        return np.eye(m), rows
    vectors, labels = [], []
    for j, item in enumerate(items):  # as pe.limits_table reads them: one rule, one label
        at = f"{key}[{j}]" if table.directions is not None else key
        vector, label = named_direction(item, rows, argument=at)
        vectors.append(vector)
        labels.append(label)
    if len(set(labels)) != len(labels):
        raise InputError(key, "distinct directions", f"{labels}", "list each direction once.")
    return np.array(vectors), tuple(labels)


def _by_robot(field: str, names: Sequence[str]) -> str:
    """A key given per robot, in TOML: ``q = { panda = [...], ur5 = [...] }``."""
    return f"{field} = {{ " + ", ".join(f"{name} = [...]" for name in names) + " }"


def _point_q(
    table: models.PointTable,
    where: str,
    robot: Robot,
    names: list[str] | None,
    field: Literal["q", "qd"] = "q",
) -> NDArray[np.float64] | None:
    """The point's joint angles (or ``qd``) on ``robot`` (``names``: those of ``[[robots]]``).

    A table of ``q`` per robot names every robot; one of ``qd`` may leave robots out
    (None: that robot is at rest).
    """
    n = robot.model.n
    key = f"{where}.{field}"
    given = table.q if field == "q" else table.qd
    what = "joint angles" if field == "q" else "joint velocities"
    if isinstance(given, dict):
        if names is None:
            raise InputError(
                key,
                f"a list of {n} {what} (a table of them per robot needs [[robots]])",
                f"a table with keys {sorted(given)}",
                f"give {field} as one list, e.g. {field} = [{', '.join(['0.0'] * n)}], or list "
                "the robots in [[robots]] to give one per robot.",
            )
        unknown = sorted(set(given) - set(names))
        missing = [name for name in names if name not in given]
        if unknown or (missing and field == "q"):
            from polyell.studies.models import did_you_mean

            raise InputError(
                key,
                f"one list of {what} per robot {names}"
                if field == "q"
                else f"lists of {what} by robot name, among {names} (robots left out are at rest)",
                f"unknown robot(s) {unknown}" if unknown else f"none for {missing}",
                did_you_mean(unknown, names)
                or f"give {field} by the names of [[robots]]: {_by_robot(field, names)}.",
            )
        if robot.name not in given:  # (qd only) a robot left out of the table is at rest
            return None
        values, key = given[robot.name], f"{key}.{robot.name}"
    else:
        assert given is not None
        values = given
    if len(values) != n:
        several = names is not None and len(names) > 1
        raise InputError(
            key,
            f"{n} {what}" + (f" (robot {robot.name!r})" if several else ""),
            f"{len(values)}",
            f"give {field} per robot: {_by_robot(field, names or ())}."
            if several and not isinstance(given, dict)
            else f"give one value per joint: {n} {what}"
            + (f" for robot {robot.name!r}" if several else "")
            + ".",
        )
    return np.array(values, dtype=float)


def _points(
    tables: list[models.PointTable], robots_: tuple[Robot, ...], several: bool
) -> tuple[Point, ...]:
    names = [robot.name for robot in robots_] if several else None
    points = []
    for index, table in enumerate(tables):
        where = f"points[{index}]"
        for robot in robots_:
            q = _point_q(table, where, robot, names)
            assert q is not None  # (every robot has its q: checked)
            with _within(f"{where}.q"):
                rows = tuple(robot.model.dynamics(q).task)
            directions, labels = _directions(table, rows, where)
            qd = None if table.qd is None else _point_qd(table, where, robot, robots_, names)
            points.append(Point(table, robot.name if several else "", q, directions, labels, qd))
    return tuple(points)


def _point_qd(
    table: models.PointTable,
    where: str,
    robot: Robot,
    robots_: tuple[Robot, ...],
    names: list[str] | None,
) -> NDArray[np.float64] | None:
    """A moving point's joint velocities [rad/s] on ``robot``; None where it is at rest.

    A URDF robot moves (Pinocchio's Coriolis terms, the torque limits at ``qd``).  A
    planar arm is modelled at rest: zero velocities are accepted as rest, and in a table of
    ``qd`` per robot it is left out (a robot left out of the table is at rest).
    """
    values = _point_q(table, where, robot, names, "qd")
    if values is None:
        return None
    key = f"{where}.qd" + (f".{robot.name}" if isinstance(table.qd, dict) else "")
    qd = check_joint_velocities(key, values, robot.model.n)
    if not isinstance(robot.model, UrdfRobot):
        if not qd.any():  # exactly at rest: the planar arm's own model
            return None
        moving = [r.name for r in robots_ if isinstance(r.model, UrdfRobot)]
        if names is not None and len(names) > 1:
            fix = f"leave {robot.name!r} out of qd (a robot left out is at rest): " + (
                f"{_by_robot('qd', moving)}."
                if moving
                else "drop qd (no robot of the study is a URDF robot)."
            )
        else:
            fix = "drop qd (or give zeros), or load a URDF robot."
        raise InputError(
            key,
            "a URDF robot (its Coriolis and centrifugal torques come from Pinocchio), or "
            "zero joint velocities for a planar arm (it is modelled at rest)",
            f"qd = {np.round(qd, 6).tolist()}",
            fix,
        )
    with _within(where):  # the curves' refusals name "qd": points[i].qd
        robot.torque_limits(qd)  # the torque-speed curves accept it (in their range)
    return qd


def _same_joint_count(robots_: tuple[Robot, ...], where: str, what: str) -> int:
    counts = {robot.name: robot.model.n for robot in robots_}
    if len(set(counts.values())) != 1:
        raise InputError(
            where,
            f"robots with the same number of joints ({what})",
            f"joint counts {counts}",
            "use [random] without low and high (each robot samples within its own joint "
            "limits) or [[points]] with q per robot, or one study per robot.",
        )
    return robots_[0].model.n


def _grid(table: dict[str, Any], robots_: tuple[Robot, ...]) -> tuple[GridAxis, ...]:
    from polyell.studies.models import MAX_STUDY_CONFIGURATIONS, did_you_mean

    n = _same_joint_count(robots_, "grid", "a grid's q1..qn are shared")
    names = tuple(f"q{i + 1}" for i in range(n))
    if set(table) != set(names):
        unknown = sorted(set(table) - set(names))
        missing = [name for name in names if name not in table]
        raise InputError(
            "grid",
            f"keys among {list(names)} (a value or range for every joint)",
            f"unknown key(s) {unknown}" if unknown else f"no {missing[0]}",
            did_you_mean(unknown, names) or f"the robot has {n} joints.",
        )
    axes = []
    for name in names:
        value = table[name]
        if isinstance(value, float):
            values = np.array([value])
        else:
            values = np.linspace(value.start, value.stop, value.num)
        axes.append(GridAxis(name, values))
    total = math.prod(axis.values.size for axis in axes)
    if total > MAX_STUDY_CONFIGURATIONS:
        raise InputError(
            "grid",
            f"at most {MAX_STUDY_CONFIGURATIONS:,} configurations in a study",
            f"{total:,}",
            "use pe.sweep(robot, pe.grid(...), out=folder) for larger sets (lazy, on disk).",
        )
    return tuple(axes)


class SeededRows(RandomConfigurations):
    """The rows of ``uniform_rows(np.random.default_rng(seed), low, high, count)``, lazily.

    A ``[random]`` study's configurations: row ``i`` is made on demand, by advancing a
    fresh generator of the seed past the ``i * n`` numbers before it (PCG64 advances in
    constant time), so that a study of millions of rows never holds them all and its rows
    are those the seed always gave.

    Parameters
    ----------
    count : int
        Rows, at least 1.
    low, high : array-like, shape (n,)
        The box, ``low <= high``.
    seed : int
        Seed of ``np.random.default_rng``, 0 or more.

    Raises
    ------
    InputError
        Naming the argument, for a bad count, box or seed (as
        :class:`~polyell.studies.configurations.RandomConfigurations`, whose rows are
        drawn in seeded blocks instead).
    """

    def rows(self, start: int, stop: int) -> NDArray[np.float64]:
        """Rows ``start`` to ``stop - 1`` (clipped to the set), shape (stop - start, n)."""
        start, stop = max(0, int(start)), min(int(stop), self.count)
        if stop <= start:
            return np.zeros((0, self.n))
        generator = np.random.default_rng(self.seed)
        generator.bit_generator.advance(start * self.n)  # type: ignore[attr-defined]
        return uniform_rows(generator, self.low, self.high, stop - start)

    def __repr__(self) -> str:
        return f"SeededRows(count={self.count}, seed={self.seed})"


def _random(table: models.RandomTable, robots_: tuple[Robot, ...]) -> tuple[SeededRows, ...]:
    if (table.low is not None or table.high is not None) and len(robots_) > 1:
        _same_joint_count(robots_, "random", "low and high are shared")
    samples = []
    for robot in robots_:
        model = robot.model
        limits = getattr(model, "position_limits", None)
        low, high = (
            limits if limits is not None else (np.full(model.n, -np.pi), np.full(model.n, np.pi))
        )
        if table.low is not None:
            low = np.array(table.low)
        if table.high is not None:
            high = np.array(table.high)
        if low.size != model.n or high.size != model.n or np.any(low > high):
            raise InputError(
                "random",
                f"low <= high with {model.n} entries each",
                f"low={low}, high={high}",
                f"give low and high {model.n} values each, every low at most its high.",
            )
        samples.append(SeededRows(table.count, low, high, table.seed))
    return tuple(samples)


def _posture(table: models.PostureTable, robot: Robot) -> Posture:
    """The posture study's settings, checked as :func:`polyell.self_motion` checks them.

    The robot's redundancy, q0's size, joint limits and rank, and that its self-motion is
    not blocked both ways, are checked by sampling two postures (a few Newton steps).
    """
    from polyell.models.self_motion import self_motion

    model = robot.model
    starts = {"posture.q0": table.q0}
    starts |= {f"posture.components[{i}]": q for i, q in enumerate(table.components or ())}
    targets = []
    for key, q in starts.items():
        if len(q) != model.n:
            raise InputError(
                key,
                f"{model.n} joint angles",
                f"{len(q)}",
                f"give one angle per joint ({model.n}).",
            )
        try:
            motion = self_motion(model, np.array(q, dtype=float), 2, seed=table.seed)
        except InputError as exn:
            where = {"q0": key, "robot": "robot" if not robot.name else "robots[0]"}
            argument = where.get(exn.argument, f"posture.{exn.argument}")
            raise InputError(argument, exn.expected, exn.got, exn.fix) from None
        targets.append(motion.target)
        if np.max(np.abs(motion.target - targets[0])) > 1e-9 * (1.0 + np.abs(targets[0]).max()):
            raise InputError(
                key,
                "a posture with q0's task coordinates (another component of its self-motion)",
                f"task coordinates {np.round(motion.target, 6).tolist()}, q0's "
                f"{np.round(targets[0], 6).tolist()}",
                f"give {key} a posture reaching q0's task coordinates (e.g. q0's other elbow "
                "branch, found with pe.self_motion), or drop it from posture.components.",
            )
    q0 = np.array(table.q0, dtype=float)
    with _within("posture.q0"):
        rows = tuple(model.dynamics(q0).task)
    direction, label = named_direction(table.direction, rows, argument="posture.direction")
    return Posture(table, direction, label)


def _candidates(
    tables: list[models.CandidateTable], robots_: tuple[Robot, ...], m: dict[str, int]
) -> tuple[Candidate, ...]:
    candidates = []
    for index, table in enumerate(tables):
        where = f"candidates[{index}]"
        matrices = {
            key: np.array(value) for key, value in _given(table, ("weighting", "core")).items()
        }
        center = np.array(table.center) if table.center is not None else None
        with _within(where):
            candidate = Candidate(table.name, center=center, **matrices)
        for robot in robots_:
            try:
                candidate.check_sizes(m[robot.name], robot.model.n)
            except InputError as exn:
                key = exn.argument.split(".")[-1]
                on = f" of robot {robot.name!r}" if robot.name else ""
                size, rows = (
                    (robot.model.n, "joint") if key == "weighting" else (m[robot.name], "task row")
                )
                raise InputError(
                    f"{where}.{key}",
                    exn.expected + on,
                    exn.got,
                    f"give {key} {size} rows of {size} numbers (one per {rows}), or its "
                    f"diagonal, e.g. {key} = {[1] * size}.",
                ) from None
        candidates.append(candidate)
    with _within("candidates"):
        return check_candidates(tuple(candidates))


def load_study(path: str | os.PathLike[str]) -> StudySpec:
    """Parse and check a study file (the format: ``docs/study_format.md``).

    Everything is checked here, before a study writes anything: the keys and values
    (:mod:`polyell.studies.models`), and what needs the robots (joint counts, the task's
    rows for named directions, joint limits, candidate sizes).

    Raises
    ------
    InputError
        On a missing file, invalid TOML, an unknown key (the message lists the valid ones
        and the closest), or any bad value; the message names the key's path
        (``points[2].directions[0]``).
    """
    from polyell.studies.models import parse_study

    table = _read_toml(path)
    study = parse_study(table, Path(path).name)
    folder = Path(path).parent
    several = study.robots is not None
    if study.robots is None:
        assert study.robot is not None
        listed = {"robot": study.robot}
    else:
        listed = {f"robots[{i}]": table for i, table in enumerate(study.robots)}
    robots_ = tuple(_build_robot(table, where, folder) for where, table in listed.items())
    rows = {robot.name: _rows(robot.model) for robot in robots_}
    units = {name: task_unit(task) for name, task in rows.items()}
    if len(set(units.values())) > 1:
        raise InputError(
            "robots",
            "tasks of one unit (their numbers share the tables)",
            f"units {units}",
            'give every robot the same kind of task (e.g. task = "linear").',
        )
    candidates = _candidates(study.candidates, robots_, {k: len(v) for k, v in rows.items()})
    points = _points(study.points, robots_, several) if study.points is not None else ()
    grid = _grid(study.grid, robots_) if study.grid is not None else ()
    random_q = _random(study.random, robots_) if study.random is not None else ()
    trajectory = None
    if study.trajectory is not None:
        file = Path(study.trajectory.file)
        trajectory = load_trajectory(
            file if file.is_absolute() else folder / file, robots_[0].model.n
        )
    posture = _posture(study.posture, robots_[0]) if study.posture is not None else None
    output = study.output
    varying = sum(axis.values.size > 1 for axis in grid)
    if output.maps and varying != 2:
        sampled = next(
            (f"a [{name}] study" for name in ("random", "trajectory", "points", "posture")
             if getattr(study, name) is not None), "no [grid]"
        )  # fmt: skip
        raise InputError(
            "output.maps",
            "a [grid] study with exactly two varying joints (a map is over their plane)",
            f"{varying} varying of {len(grid)} grid axes" if grid else sampled,
            "give two joints a range (start, stop, num) and the others one value, or drop "
            "maps (histograms show any grid)"
            if grid
            else "drop maps = true (histograms show any sample), or sample a [grid] instead",
        )
    with _within("output"):  # the layout's own checks, before anything is written
        output.layout  # noqa: B018
    compare = study.compare
    moving = [point.label for point in points if point.qd is not None]
    still = [c for c in compare.capacities if not capacity_class(c).in_motion]
    if moving and still:
        raise InputError(
            "compare.capacities",
            f"no {still[0]!r} with points in motion (the {still[0]} set is every joint velocity)",
            f"{still[0]!r} and qd at {moving}",
            "drop qd from those points, or study velocities in a file of their own.",
        )
    if candidates and len(compare.capacities) > 1:
        raise InputError(
            "candidates",
            "a study of one capacity (a candidate's core and centre are in its units: "
            "m/s^2, m/s or N)",
            f"candidates beside compare.capacities = {list(compare.capacities)}",
            "compare the candidates in a study of the capacity they describe.",
        )
    if any("qd_max" in capacity_class(c).limit_keywords for c in compare.capacities):
        # every robot needs its joint velocity limits
        for number, robot in enumerate(robots_):
            if robot.model.qd_max is None:
                where = "robot" if len(robots_) == 1 else f"robots[{number}]"
                raise InputError(
                    f"{where}.qd_max",
                    "joint velocity limits [rad/s] for compare.capacities = [..., 'velocity']",
                    "none",
                    "add qd_max = [...] to the robot table (a URDF's velocity limits are read "
                    "when every joint has one).",
                )
    if compare.horizon is not None:  # the robots' own position and velocity limits
        for number, robot in enumerate(robots_):
            where = "robot" if len(robots_) == 1 else f"robots[{number}]"
            try:
                robot_horizon(robot.model, compare.horizon, braking=compare.braking)
            except InputError as error:
                raise InputError(
                    "compare.horizon",
                    "robots with joint velocity limits (the horizon's; position limits too "
                    "where the robot has them)",
                    f"{where} without {error.argument}",
                    "add qd_max = [...] to the robot table, or drop horizon.",
                ) from None
    return StudySpec(
        study, Path(path), robots_, candidates, points, grid, random_q, trajectory, posture
    )
