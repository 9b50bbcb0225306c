"""Study and robot descriptions in TOML: parsed strictly, with errors that list the valid keys.

A study file::

    title = "Chiacchio (2000), section 6"

    [robot]                      # a robot file has these keys at its top level
    library = "chiacchio2000"    # or: planar = { lengths = [...], masses = [...], ... }
    tau_max = [100, 30, 4]       # optional when the robot carries limits

    [[points]]                   # named configurations ...
    name = "redundant"
    q = ["pi/2", "-pi/2", "-pi/2"]
    direction = [1, 0]           # limits and inverse maps reported along it (default: x)
    inverse_at = "hi"            # the end of the new ellipsoid's interval for the inverses

    [grid]                       # ... or a grid: fixed values and ranges per joint
    q1 = "pi/2"
    q2 = { start = "-pi", stop = "pi", num = 41 }

    [trajectory]                 # ... or a path from a file: columns q1..qn, optionally
    file = "path.csv"            # qd1..qdn and t (CSV, Parquet, .npy or .npz)

    [random]                     # ... or seeded uniform samples within the joint limits
    count = 300
    seed = 1
    low = [...]                  # optional, default the URDF's limits (else -pi)
    high = [...]                 # optional, default the URDF's limits (else pi)

    [compare]
    directions = 360             # the default set's size
    mvie = true
    samples = 8192
    seed = 0
    chunk = 20000                # configurations per task of a grid or random study

    [output]
    formats = ["pdf", "png"]
    dpi = 300
    maps = ["chiacchio_coverage"]    # heat maps of a grid study (<ellipsoid>_<score>)
    histograms = ["coverage"]        # per score, both ellipsoids (grid or random study)
    series = ["coverage"]            # scores along a trajectory, each candidate

Numbers may be written as expressions: ``"pi/2"``, ``"sqrt(3)/2"``.
"""

from __future__ import annotations

import math
import os
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from polyell import robots
from polyell.comparison.candidates import Candidate, check_candidates
from polyell.comparison.comparison import (
    COMPARED_KINDS,
    MAX_SAMPLES,
    MAX_SEED,
    MIN_SAMPLES,
    SCORE_NAMES,
)
from polyell.errors import InputError
from polyell.expressions import evaluate, evaluate_list
from polyell.models.planar_arm import PlanarArm
from polyell.models.urdf import Payload, UrdfRobot
from polyell.studies.configurations import uniform_rows
from polyell.studies.file_format import keys
from polyell.studies.trajectory import Trajectory, load_trajectory
from polyell.validation import (
    MAX_DIRECTIONS,
    _describe,
    check_array,
    check_integer,
    check_torque_limits,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "GridAxis",
    "Point",
    "Robot",
    "StudySpec",
    "load_robot_file",
    "load_study",
    "robot_from_table",
]

_TOP_KEYS = keys("top")
_CANDIDATE_KEYS = keys("candidates")
_TRAJECTORY_KEYS = keys("trajectory")
_RANDOM_KEYS = keys("random")
_ROBOT_KEYS = keys("robot")
_PAYLOAD_KEYS = keys("payload")
_PLANAR_KEYS = keys("planar")
_POINT_KEYS = keys("points")
_RANGE_KEYS = ("start", "stop", "num")
_COMPARE_KEYS = keys("compare")
_OUTPUT_KEYS = keys("output")
#: Figure formats, and "html": one self-contained interactive report (plotly).
_FORMATS = ("pdf", "png", "svg", "html")


def _check_keys(where: str, table: object, valid: tuple[str, ...]) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise InputError(where, f"a table with keys among {list(valid)}", _describe(table))
    unknown = sorted(set(table) - set(valid))
    if unknown:
        raise InputError(
            where,
            f"keys among {list(valid)}",
            f"unknown key(s) {unknown}",
            "check the spelling against the valid keys.",
        )
    return table


#: A point's name becomes part of file names: letters, digits, ``_ . -``, not leading ``.``.
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")
#: Most configurations of a grid or random study (all held in memory for its tables;
#: larger sweeps go through pe.sweep(..., out=...)).
MAX_STUDY_CONFIGURATIONS = 10_000_000


def _string(where: str, value: object) -> str:
    if not isinstance(value, str):
        raise InputError(where, "a string", _describe(value))
    return value


def _figure_title(where: str, value: object) -> str:
    """A title that figures show, checked when the study loads (:func:`figures.check_title`).

    A typo in a ``$...$`` formula is refused with the key that holds it, instead of failing
    when the first figure is drawn.
    """
    title = _string(where, value)
    if "$" not in title:  # no mathtext: no need to load matplotlib
        return title
    from polyell.figures import check_title

    return check_title(title, where)


def _strings(where: str, value: object) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise InputError(where, "a list of strings", _describe(value))
    return tuple(value)


def _boolean(where: str, value: object) -> bool:
    if not isinstance(value, bool):
        raise InputError(where, "true or false", _describe(value))
    return value


def _file_name(where: str, value: object) -> str:
    """A name that can become part of a file name inside the output folder, and nothing else."""
    name = _string(where, value)
    if not _NAME.fullmatch(name):
        raise InputError(
            where,
            "1-64 letters, digits, '_', '.' or '-', not starting with '.' (it names files)",
            repr(name),
            "no '/' or '..': nothing a study says may write outside the output folder.",
        )
    return name


def _list(where: str, value: object) -> list[Any]:
    if not isinstance(value, list):
        raise InputError(where, "a list", _describe(value))
    return value


@dataclass(frozen=True)
class Robot:
    """A robot model with its torque limits, as described in a file."""

    model: PlanarArm | UrdfRobot
    tau_max: NDArray[np.float64]
    tau_min: NDArray[np.float64]


def _planar(table: object, where: str) -> PlanarArm:
    planar = _check_keys(where, table, _PLANAR_KEYS)
    for key in ("lengths", "masses"):
        if key not in planar:
            raise InputError(where, f"a '{key}' list", "no such key")
    lists = {
        key: evaluate_list(f"{where}.{key}", planar[key])
        for key in ("com", "inertia")
        if key in planar
    }
    return PlanarArm(
        evaluate_list(f"{where}.lengths", planar["lengths"]),
        evaluate_list(f"{where}.masses", planar["masses"]),
        com=lists.get("com"),
        inertia=lists.get("inertia"),
        gravity=evaluate(f"{where}.gravity", planar.get("gravity", 9.81)),
    )


def _urdf_options(table: dict[str, Any], where: str) -> dict[str, Any]:
    """Keyword arguments of UrdfRobot from the optional keys of a robot table."""
    options: dict[str, Any] = {}
    if "tip" in table:
        options["tip"] = _string(f"{where}.tip", table["tip"])
    if "task" in table:
        task = table["task"]
        options["task"] = task if isinstance(task, str) else _list(f"{where}.task", task)
    if "locked_joints" in table:
        options["locked_joints"] = _strings(f"{where}.locked_joints", table["locked_joints"])
    if "gravity" in table:
        options["gravity"] = evaluate_list(f"{where}.gravity", table["gravity"])
    if "weights" in table:
        options["weights"] = evaluate_list(f"{where}.weights", table["weights"])
    if "payload" in table:
        payload = _check_keys(f"{where}.payload", table["payload"], _PAYLOAD_KEYS)
        if "mass" not in payload:
            raise InputError(f"{where}.payload", "a 'mass' [kg]", "no such key")
        inertia = _list(f"{where}.payload.inertia", payload.get("inertia", [[0, 0, 0]] * 3))
        rows = [
            evaluate_list(f"{where}.payload.inertia[{i}]", _list(f"{where}.payload.inertia", row))
            for i, row in enumerate(inertia)
        ]
        options["payload"] = Payload(
            evaluate(f"{where}.payload.mass", payload["mass"]),
            tuple(
                check_array(
                    f"{where}.payload.com",
                    evaluate_list(
                        f"{where}.payload.com",
                        _list(f"{where}.payload.com", payload.get("com", [0, 0, 0])),
                    ),
                    (3,),
                )
            ),
            tuple(map(tuple, check_array(f"{where}.payload.inertia", rows, (3, 3)))),
        )
    return options


def robot_from_table(table: object, where: str = "robot", folder: Path | None = None) -> Robot:
    """Build a robot from a ``[robot]`` table.

    Exactly one of ``library`` (a name of :func:`polyell.robots.names`), ``planar`` (a
    link table) or ``urdf`` (a file, relative to ``folder``, with ``tip``); URDF robots
    also take ``task``, ``locked_joints``, ``gravity``, ``weights`` and ``payload``
    (``{ mass, com, inertia }``); every robot takes ``tau_max`` and ``tau_min``.
    """
    table = _check_keys(where, table, _ROBOT_KEYS)
    sources = [key for key in ("library", "planar", "urdf") if key in table]
    if len(sources) != 1:
        raise InputError(
            where,
            "exactly one of 'library' (a name), 'planar' (a link table), 'urdf' (a file)",
            f"keys {sorted(table)}",
            f'e.g. library = "chiacchio2000"; names: {robots.names()}.',
        )
    options = _urdf_options(table, where)
    model: PlanarArm | UrdfRobot
    if "planar" in table:
        if options:
            raise InputError(where, "no URDF options for a planar arm", f"{sorted(options)}")
        model = _planar(table["planar"], f"{where}.planar")
    elif "library" in table:
        model = robots.load(_string(f"{where}.library", table["library"]), **options)
    else:
        if "tip" not in options:
            raise InputError(where, "a 'tip' frame name for a URDF robot", "no tip key")
        path = Path(_string(f"{where}.urdf", table["urdf"]))
        if folder is not None and not path.is_absolute():
            path = folder / path
        model = UrdfRobot(path, **options)
    if "tau_max" in table:
        upper = evaluate_list(f"{where}.tau_max", table["tau_max"])
        lower = evaluate_list(f"{where}.tau_min", table["tau_min"]) if "tau_min" in table else None
        tau_max, tau_min = check_torque_limits(upper, lower, model.n)
    elif model.tau_max is not None and model.tau_min is not None:
        tau_max, tau_min = model.tau_max, model.tau_min
    else:
        raise InputError(
            f"{where}.tau_max", "torque limits for a robot without its own", "no tau_max key"
        )
    return Robot(model, tau_max, tau_min)


def _read_toml(path: str | os.PathLike[str], what: str = "study") -> dict[str, Any]:
    """The table of a TOML file; every way of failing is an InputError naming the file.

    A folder, an unreadable or non-UTF-8 file, invalid TOML and nesting too deep for the
    parser (a RecursionError in ``tomllib``) are all refused with what to do.
    """
    if not isinstance(path, str | os.PathLike):
        raise InputError("path", f"the path of a {what} TOML file", f"{type(path).__name__}")
    shown = repr(str(path))
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except FileNotFoundError:
        raise InputError("path", f"an existing TOML file describing a {what}", shown) from None
    except IsADirectoryError:
        raise InputError(
            "path", f"a TOML file describing a {what}", f"{shown}, a folder", "give a file."
        ) from None
    except OSError as exn:  # permissions, a device, a name too long, ...
        raise InputError(
            "path", f"a readable TOML file describing a {what}", f"{shown} ({exn.strerror or exn})"
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
        raise InputError("path", "valid TOML", f"{shown}: {exn}") from None
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
    """A named configuration with the direction its numbers are reported along."""

    name: str
    q: NDArray[np.float64]
    direction: NDArray[np.float64]
    inverse_at: Literal["lo", "hi"] = "hi"
    title: str = ""


@dataclass(frozen=True)
class GridAxis:
    """Values of one joint angle over a grid (a single value when it is fixed)."""

    name: str
    values: NDArray[np.float64]


@dataclass(frozen=True)
class StudySpec:
    """A parsed study: a robot, configurations (points or a grid), options and outputs."""

    path: Path
    title: str
    description: str
    robot: Robot
    points: tuple[Point, ...] = ()
    grid: tuple[GridAxis, ...] = ()
    samples_q: NDArray[np.float64] | None = None
    trajectory: Trajectory | None = None
    directions: int | None = None
    mvie: bool = True
    outer: bool = True
    candidates: tuple[Candidate, ...] = ()
    samples: int = 2**13
    seed: int = 0
    chunk: int = 20_000
    formats: tuple[str, ...] = ("pdf", "png")
    dpi: int = 300
    maps: tuple[str, ...] = field(default_factory=tuple)
    histograms: tuple[str, ...] = field(default_factory=tuple)
    series: tuple[str, ...] = field(default_factory=tuple)

    @property
    def figure_formats(self) -> tuple[str, ...]:
        """The static figure formats (all but ``"html"``)."""
        return tuple(f for f in self.formats if f != "html")

    @property
    def is_grid(self) -> bool:
        """True for a grid study."""
        return bool(self.grid)

    @property
    def is_batch(self) -> bool:
        """True for many configurations (a grid, random samples or a trajectory)."""
        return bool(self.grid) or self.samples_q is not None or self.trajectory is not None

    def configurations(self) -> NDArray[np.float64]:
        """All configurations: a grid's (the last joint fastest), random or a trajectory's."""
        if self.trajectory is not None:
            return self.trajectory.q
        if self.samples_q is not None:
            return self.samples_q
        mesh = np.meshgrid(*[axis.values for axis in self.grid], indexing="ij")
        return np.stack([m.ravel() for m in mesh], axis=1)


def _point(table: object, index: int, n: int) -> Point:
    where = f"points[{index}]"
    table = _check_keys(where, table, _POINT_KEYS)
    for key in ("name", "q"):
        if key not in table:
            raise InputError(where, f"a '{key}' key", f"keys {sorted(table)}")
    q = np.array(evaluate_list(f"{where}.q", table["q"]))
    if q.size != n:
        raise InputError(f"{where}.q", f"{n} joint angles", f"{q.size}")
    direction = np.array(evaluate_list(f"{where}.direction", table.get("direction", [1, 0])))
    if abs(np.linalg.norm(direction) - 1.0) > 1e-6:
        raise InputError(
            f"{where}.direction", "a unit vector", f"norm {np.linalg.norm(direction):.6g}"
        )
    inverse_at = table.get("inverse_at", "hi")
    if inverse_at not in ("lo", "hi"):
        raise InputError(f"{where}.inverse_at", "'lo' or 'hi'", _describe(inverse_at))
    end: Literal["lo", "hi"] = "lo" if inverse_at == "lo" else "hi"
    name = _file_name(f"{where}.name", table["name"])
    return Point(name, q, direction, end, _figure_title(f"{where}.title", table.get("title", "")))


def _grid(table: object, n: int) -> tuple[GridAxis, ...]:
    names = tuple(f"q{i + 1}" for i in range(n))
    table = _check_keys("grid", table, names)
    axes = []
    for name in names:
        if name not in table:
            raise InputError(
                "grid", f"a value or range for every joint {list(names)}", f"no {name}"
            )
        value = table[name]
        if isinstance(value, dict):
            spec = _check_keys(f"grid.{name}", value, _RANGE_KEYS)
            if set(spec) != set(_RANGE_KEYS):
                raise InputError(f"grid.{name}", "{ start, stop, num }", _describe(value))
            num = check_integer(f"grid.{name}.num", spec["num"], 1, MAX_STUDY_CONFIGURATIONS)
            values = np.linspace(
                evaluate(f"grid.{name}.start", spec["start"]),
                evaluate(f"grid.{name}.stop", spec["stop"]),
                num,
            )
        else:
            values = np.array([evaluate(f"grid.{name}", value)])
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


def _random(table: object, robot: Robot) -> NDArray[np.float64]:
    table = _check_keys("random", table, _RANDOM_KEYS)
    if "count" not in table:
        raise InputError("random", "a 'count' of configurations", "no such key")
    count = check_integer("random.count", table["count"], 1, MAX_STUDY_CONFIGURATIONS)
    seed = check_integer("random.seed", table.get("seed", 0), 0, MAX_SEED)
    model = robot.model
    limits = getattr(model, "position_limits", None)
    low, high = (
        limits if limits is not None else (np.full(model.n, -np.pi), np.full(model.n, np.pi))
    )
    if "low" in table:
        low = np.array(evaluate_list("random.low", table["low"]))
    if "high" in table:
        high = np.array(evaluate_list("random.high", table["high"]))
    if low.size != model.n or high.size != model.n or np.any(low > high):
        raise InputError(
            "random", f"low <= high with {model.n} entries each", f"low={low}, high={high}"
        )
    return uniform_rows(np.random.default_rng(seed), low, high, count)


def _matrix(where: str, value: object) -> NDArray[np.float64]:
    """A square matrix: a list of rows, or a list of numbers (its diagonal)."""
    rows = _list(where, value)
    if rows and all(isinstance(row, list) for row in rows):
        matrix = [evaluate_list(f"{where}[{i}]", row) for i, row in enumerate(rows)]
        if any(len(row) != len(matrix) for row in matrix):
            lengths = [len(row) for row in matrix]
            raise InputError(where, f"{len(matrix)} rows of {len(matrix)} numbers", f"{lengths}")
        return np.array(matrix)
    return np.diag(evaluate_list(where, rows))


def _candidate(table: object, index: int) -> Candidate:
    where = f"candidates[{index}]"
    candidate = _check_keys(where, table, _CANDIDATE_KEYS)
    if "name" not in candidate:
        raise InputError(where, "a 'name' (it prefixes the candidate's columns)", "no such key")
    name = _string(f"{where}.name", candidate["name"])
    matrices = {
        key: _matrix(f"{where}.{key}", candidate[key])
        for key in ("weighting", "core")
        if key in candidate
    }
    center = (
        np.array(evaluate_list(f"{where}.center", candidate["center"]))
        if "center" in candidate
        else None
    )
    return Candidate(name, center=center, **matrices)


def load_study(path: str | os.PathLike[str]) -> StudySpec:
    """Parse and check a study file.

    Raises
    ------
    InputError
        On a missing file, invalid TOML, an unknown key (the message lists the valid
        ones), or any bad value.
    """
    table = _read_toml(path)
    data = _check_keys(Path(path).name, table, _TOP_KEYS)
    if "robot" not in data:
        raise InputError(Path(path).name, "a [robot] table", "none")
    robot = robot_from_table(data["robot"], folder=Path(path).parent)
    n = robot.model.n
    if sum(key in data for key in ("points", "grid", "random", "trajectory")) != 1:
        raise InputError(
            Path(path).name,
            "exactly one of [[points]], [grid], [random] and [trajectory]",
            f"keys {sorted(data)}",
        )
    trajectory = None
    if "trajectory" in data:
        table = _check_keys("trajectory", data["trajectory"], _TRAJECTORY_KEYS)
        if "file" not in table:
            raise InputError("trajectory", "a 'file' (CSV, Parquet, .npy or .npz)", "no file key")
        file = Path(_string("trajectory.file", table["file"]))
        trajectory = load_trajectory(file if file.is_absolute() else Path(path).parent / file, n)
    points = tuple(_point(t, i, n) for i, t in enumerate(_list("points", data.get("points", []))))
    names = [point.name for point in points]
    if len(set(names)) != len(names):
        raise InputError("points", "distinct point names (they name files)", f"{names}")
    if "points" in data and not points:
        raise InputError("points", "at least one [[points]] table", "none")
    grid = _grid(data["grid"], n) if "grid" in data else ()
    samples_q = _random(data["random"], robot) if "random" in data else None
    compare = _check_keys("compare", data.get("compare", {}), _COMPARE_KEYS)
    output = _check_keys("output", data.get("output", {}), _OUTPUT_KEYS)
    formats = _strings("output.formats", output.get("formats", ["pdf", "png"]))
    if not formats or any(f not in _FORMATS for f in formats):
        raise InputError("output.formats", f"a list among {list(_FORMATS)}", _describe(formats))
    candidates = check_candidates(
        tuple(
            _candidate(t, i) for i, t in enumerate(_list("candidates", data.get("candidates", [])))
        )
    )
    kinds = (*COMPARED_KINDS, *(candidate.name for candidate in candidates))
    valid_maps = [f"{kind}_{score}" for kind in kinds for score in SCORE_NAMES]
    maps = _strings("output.maps", output.get("maps", []))
    for name in maps:
        if name not in valid_maps:
            raise InputError(
                "output.maps",
                "names <ellipsoid>_<score>",
                repr(name),
                f"for example 'chiacchio_coverage'; valid: {valid_maps}",
            )
    if maps and sum(axis.values.size > 1 for axis in grid) != 2:
        raise InputError(
            "output.maps", "a grid with exactly two varying joints", f"{len(grid)} grid axes"
        )
    histograms = _strings("output.histograms", output.get("histograms", []))
    for name in histograms:
        if name not in SCORE_NAMES:
            raise InputError(
                "output.histograms", f"score names among {list(SCORE_NAMES)}", _describe(name)
            )
    if histograms and "points" in data:
        raise InputError("output.histograms", "a grid or random study", "a study of points")
    default_series = ["coverage", "inscribed_scale"] if trajectory is not None else []
    series = _strings("output.series", output.get("series", default_series))
    for name in series:
        if name not in SCORE_NAMES:
            raise InputError(
                "output.series", f"score names among {list(SCORE_NAMES)}", _describe(name)
            )
    if series and trajectory is None:
        raise InputError("output.series", "a [trajectory] study", "another kind of study")
    return StudySpec(
        path=Path(path),
        title=_figure_title("title", data.get("title", Path(path).stem)),
        description=_string("description", data.get("description", "")),
        robot=robot,
        points=points,
        grid=grid,
        samples_q=samples_q,
        trajectory=trajectory,
        directions=(
            check_integer("compare.directions", compare["directions"], 1, MAX_DIRECTIONS)
            if "directions" in compare
            else None
        ),
        mvie=_boolean("compare.mvie", compare.get("mvie", True)),
        outer=_boolean("compare.outer", compare.get("outer", True)),
        candidates=candidates,
        samples=check_integer(
            "compare.samples", compare.get("samples", 2**13), MIN_SAMPLES, MAX_SAMPLES
        ),
        seed=check_integer("compare.seed", compare.get("seed", 0), 0, MAX_SEED),
        chunk=check_integer("compare.chunk", compare.get("chunk", 20_000), 1, 10_000_000),
        formats=formats,
        dpi=check_integer("output.dpi", output.get("dpi", 300), 10, 2400),
        maps=maps,
        histograms=histograms,
        series=series,
    )
