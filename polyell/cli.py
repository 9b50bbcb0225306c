"""The ``polyell`` command line: ``polyell analyze`` and ``polyell study``.

Bad input ends with a one-line ``polyell: error: ...`` on standard error and exit status
2, never a traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import logging
import math
import os
import re
import sys
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np
from numpy.typing import NDArray

from polyell import __version__, robots
from polyell.capacities import Analysis, analyze, capacity_class, check_capacity, takes_horizon
from polyell.capacities.horizon import check_horizon, robot_horizon
from polyell.comparison import compare
from polyell.comparison.directions import named_direction
from polyell.errors import InputError, PolyellError, ProjectedInputWarning
from polyell.expressions import evaluate_list
from polyell.geometry.subspace import scaled_norm
from polyell.models import UrdfRobot
from polyell.report import analysis_to_json, format_analysis
from polyell.studies import load_robot_file, load_study, run_study
from polyell.studies.spec import Robot
from polyell.validation import (
    DIRECTION_NORM_RTOL,
    check_directions,
    check_joint_velocities,
    check_points,
    check_torque_limits,
)

if TYPE_CHECKING:
    from _typeshed import SupportsWrite

__all__ = ["main"]

PAPER_Q = "pi/2,-pi/2,-pi/2"
#: The largest |--angle| [deg]: one turn either way (a direction repeats beyond).
MAX_ANGLE_DEG = 360.0
#: The outputs a study's summary points to, with what they hold.
MAIN_OUTPUTS = {
    "numbers.md": "every number of each configuration (sets, limits, inverse maps)",
    "comparison.md": "the scores of each ellipsoid (also .tex, .csv; scores.csv: every digit)",
    "limits.md": "the directional limits along each point's directions (also .tex, .csv)",
    "summary.md": "the scores' statistics over all configurations (also .tex, .csv)",
    "results.csv": "one row of scores per configuration",
    "posture_choice.md": "the posture each index picks, its joint angles (also .tex, .csv)",
    "posture_targets.md": "each index's regret over random targets (also .tex, .csv)",
    "posture_values.csv": "one row per posture: its joint angles and every set's values",
    **{
        f"posture_indices.{extension}": "the figure of every index over the postures"
        for extension in ("pdf", "png", "svg")
    },
    "report.html": "the interactive report (open it in a browser; works offline)",
    "manifest.json": "every file written, the datasets, notes and warnings",
}
#: The figures of a study by the start of their names (``sets_ready.png``), with what
#: each kind shows; the closing message names every one.
FIGURE_OUTPUTS = {
    "sets": "a point's sets (figure)",
    "limits": "a point's directional limits (figure)",
    "map": "a heat map of a score over the grid",
    "series": "a score along the path",
    "histogram": "a histogram of a score over the configurations",
}
_FIGURES = (".pdf", ".png", ".svg")
#: What a study's Parquet dataset holds (``results/``: a grid, random or trajectory study).
DATASET_OUTPUT = (
    "every configuration's scores, a Parquet dataset (pd.read_parquet; a killed run "
    "resumes from it)"
)
#: The outputs a study writes once, whatever its capacities.
_SHARED_OUTPUTS = ("numbers.md", "report.html", "manifest.json")
#: Options whose value is a list of numbers, which may start with '-' (--q -pi/2,0,0).
_LIST_OPTIONS = ("--q", "--qd", "--qd-max", "--qd-min", "--tau-max", "--tau-min", "--direction")


def _join_list_options(argv: Sequence[str]) -> list[str]:
    """``--q -pi/2,0`` as ``--q=-pi/2,0``: argparse would take ``-pi/2,0`` for an option."""
    joined: list[str] = []
    for item in argv:
        if joined and joined[-1] in _LIST_OPTIONS and item.startswith("-"):
            joined[-1] = f"{joined[-1]}={item}"
        else:
            joined.append(item)
    return joined


def _floats(text: str) -> list[float]:
    """Parse a comma-separated list of numbers, where ``pi`` may appear (``pi/2,-pi/2,0``)."""
    try:
        return evaluate_list("value", text)
    except PolyellError as exn:
        raise argparse.ArgumentTypeError(str(exn)) from None


class _Parser(argparse.ArgumentParser):
    """argparse, with its errors on one line like the package's own."""

    def _print_message(self, message: str, file: SupportsWrite[str] | None = None) -> None:
        """Write help and usage; unlike argparse's, a failed write is not ignored."""
        if message:
            (sys.stderr if file is None else file).write(message)

    def error(self, message: str) -> NoReturn:
        self.exit(2, _line(f"polyell: error: {message} (see '{self.prog} --help')") + "\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="polyell",
        description="Exact acceleration polytopes and dynamic manipulability ellipsoids "
        "(Chiacchio 2000), compared.",
    )
    parser.add_argument("--version", action="version", version=f"polyell {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = commands.add_parser(
        "analyze",
        help="analyze one robot at one configuration: sets, limits and scores",
        description="Print the polytope, both ellipsoids, the limits along a direction, the "
        "inverse maps and the comparison scores. Default: the 3-link planar arm of "
        "Chiacchio (2000) at q = (pi/2, -pi/2, -pi/2).",
    )
    run.add_argument(
        "--robot",
        default="chiacchio2000",
        help=f"a library name ({', '.join(robots.names())}; all but the first need "
        "polyell[robots]) or a robot TOML file",
    )
    run.add_argument(
        "--q",
        type=_floats,
        default=None,
        help=f"joint angles [rad, or deg with --deg]; default {PAPER_Q} for chiacchio2000, "
        "required for every other robot",
    )
    run.add_argument("--deg", action="store_true", help="--q is in degrees")
    run.add_argument(
        "--capacity",
        default="acceleration",
        help="acceleration (default, the paper's), velocity or force",
    )
    run.add_argument(
        "--qd-max", type=_floats, help="velocity capacity: [rad/s], default the robot's own"
    )
    run.add_argument("--qd-min", type=_floats, help="velocity capacity: [rad/s], default -qd-max")
    run.add_argument(
        "--qd",
        type=_floats,
        default=None,
        help="URDF robots in motion: joint velocities [rad/s, or deg/s with --deg]; the "
        "torque limits are taken at them (the robot's torque-speed curves)",
    )
    run.add_argument(
        "--horizon",
        type=float,
        default=None,
        help="accelerations: a control period [s]; the set then also keeps every joint within "
        "the robot's position limits over it and its velocity limits at its end, from the "
        "state (--q, --qd)",
    )
    run.add_argument(
        "--braking",
        type=float,
        default=None,
        help="with --horizon: the deceleration [rad/s^2] every joint can still brake with "
        "after the period (viability)",
    )
    run.add_argument("--tau-max", type=_floats, help="[N m], default: the robot's own")
    run.add_argument("--tau-min", type=_floats, help="[N m], default -tau-max (or the robot's own)")
    aim = run.add_mutually_exclusive_group()
    aim.add_argument(
        "--direction",
        default=None,
        help="the task direction of the limits: a name of the task rows (x, -z, xy, wz) "
        "or a unit vector (0,0,1); default the first task row",
    )
    aim.add_argument(
        "--angle",
        type=_floats,
        default=None,
        help="2-D tasks: the direction as an angle from the first axis [deg]",
    )
    run.add_argument(
        "--normalize", action="store_true", help="scale --direction to unit length (said)"
    )
    run.add_argument(
        "--inverse-at", choices=("lo", "hi"), default="hi", help="end of the new interval"
    )
    run.add_argument(
        "--no-mvie", action="store_true", help="skip the maximum-volume inscribed ellipsoid"
    )
    run.add_argument(
        "--no-outer", action="store_true", help="skip the minimum-volume enclosing ellipsoid"
    )
    run.add_argument("--json", action="store_true", help="print JSON instead of text")
    run.add_argument(
        "--equations",
        action="store_true",
        help="label the output with the equation numbers of Chiacchio (2000), 'xdd_g (eq. 8)' "
        "(default: only for its own arm, --robot chiacchio2000)",
    )
    run.add_argument(
        "--mesh",
        default=None,
        metavar="FILE",
        help="also write the sets as meshes: FILE.obj (one file) or FILE.ply (one per set)",
    )
    study = commands.add_parser(
        "study",
        help="run a study from a TOML file and write its tables and figures",
        description="Run a scripted study (see studies/*.toml) and write its tables "
        "(Markdown, LaTeX, CSV) and figures (PDF, PNG) to --out.",
    )
    study.add_argument("spec", help="the study TOML file")
    study.add_argument("--out", required=True, help="output folder (created if needed)")
    study.add_argument("--quiet", action="store_true", help="no progress bar")
    study.add_argument(
        "--scheduler",
        default=None,
        help="grid and random studies: 'processes' (a local Dask cluster) or a scheduler "
        "address tcp://host:port; default in this process",
    )
    return parser


def _robot(name: str, tau_max: list[float] | None, tau_min: list[float] | None) -> Robot:
    if name.endswith(".toml") or os.sep in name or (os.altsep or os.sep) in name:
        robot = load_robot_file(name)  # a path: library names have no separator
    else:
        model = robots.load(name)
        if model.tau_max is None or model.tau_min is None:
            raise InputError(
                "--tau-max",
                "torque limits for this robot",
                "none given",
                "give them with --tau-max (and --tau-min) [N m], one per joint.",
            )
        robot = Robot(model, model.tau_max, model.tau_min)
    if tau_max is None and tau_min is None:
        return robot
    # --tau-min alone keeps the robot's own upper limits
    upper, lower = check_torque_limits(
        robot.tau_max if tau_max is None else tau_max, tau_min, robot.model.n
    )
    return Robot(robot.model, upper, lower)


def _configuration(args: argparse.Namespace, robot: Robot) -> NDArray[np.float64]:
    """``--q`` in radians: the paper's posture by default for its arm, else required."""
    if args.q is None:
        if args.robot != "chiacchio2000":
            n = robot.model.n
            raise InputError(
                "--q",
                f"{n} joint angles for {args.robot}",
                "none",
                f"e.g. --q {','.join(['0'] * n)} (radians; --deg for degrees).",
            )
        return np.array(_floats(PAPER_Q))
    q = np.asarray(args.q, dtype=float)
    return np.deg2rad(q) if args.deg else q


def _named_or_numbers(
    text: str, task: tuple[str, ...]
) -> tuple[NDArray[np.float64], str] | list[float]:
    """``--direction`` as a name of the task rows ``(unit vector, label)``, or its numbers.

    Numbers when every comma-separated item evaluates (``0,0,1``, ``-0.5,sqrt(3)/2``);
    else a name (:func:`~polyell.comparison.directions.named_direction`: ``z``, ``-z``,
    ``xy``).  A text that is neither gets the numbers' error if it has a comma or starts
    like a number, the name's (which lists the task rows) otherwise.
    """
    try:
        return evaluate_list("--direction", text)
    except InputError:
        if "," in text or re.match(r"\s*[-+]?\s*[\d.]", text):
            raise
    return named_direction(text, task, "--direction")


def _direction(
    args: argparse.Namespace, task: tuple[str, ...]
) -> tuple[NDArray[np.float64], str, list[str]]:
    """The direction of the limits, its label, and notes on what was done to it."""
    m = len(task)
    if args.angle is not None:
        if m != 2 or len(args.angle) != 1:
            raise InputError(
                "--angle",
                "one angle [deg] for a 2-D task",
                f"{args.angle}, m = {m}",
                "give one angle such as --angle 30, or --direction (a name or a unit "
                "vector) for another task.",
            )
        degrees = float(args.angle[0])
        if not np.isfinite(degrees) or abs(degrees) > MAX_ANGLE_DEG:
            raise InputError(
                "--angle",
                f"an angle from -{MAX_ANGLE_DEG:g} to {MAX_ANGLE_DEG:g} deg (one turn either "
                "way: a larger one is a slip, or rounds its direction away)",
                repr(args.angle[0]),
                f"give the angle modulo 360, e.g. --angle {math.fmod(degrees, 360.0):g}"
                if np.isfinite(degrees)
                else "give a finite angle in degrees, e.g. --angle 30.",
            )
        angle = np.deg2rad(degrees)
        return np.array([np.cos(angle), np.sin(angle)]), "t", []
    if args.direction is None:  # the first task row
        return np.eye(m)[0], task[0], []
    values = _named_or_numbers(args.direction, task)
    if isinstance(values, tuple):  # a name: a unit vector already
        return values[0], values[1], []
    direction = check_points("--direction", values, m)
    norm = float(scaled_norm(direction))  # (no underflow of the squares at 1e-300)
    if not args.normalize and abs(norm - 1.0) > DIRECTION_NORM_RTOL:
        raise InputError(
            "--direction",
            "a unit vector",
            f"{values} of norm {norm:.6g}",
            "add --normalize to scale it to unit length, or give --angle DEG (2-D tasks).",
        )
    if norm == 0 or abs(norm - 1.0) <= 1e-12:
        return check_directions("--direction", direction, m), "t", []  # or an InputError
    unit = direction / norm
    return unit, "t", [f"--direction normalised to {_rounded(unit, 6)}"]


def _velocities(
    args: argparse.Namespace, robot: Robot, capacity: type[Analysis]
) -> tuple[NDArray[np.float64], bool]:
    """``--qd`` in rad/s (zeros without it) and whether the robot moves."""
    if args.qd is None:
        return np.zeros(robot.model.n), False
    if not capacity.in_motion:
        raise InputError(
            "--qd",
            f"no joint velocities for the {capacity.capacity} capacity (its set is every velocity)",
            "--qd",
            "drop --qd, or analyze accelerations or forces of the moving robot.",
        )
    if not isinstance(robot.model, UrdfRobot):
        raise InputError(
            "--qd",
            "a URDF robot (its Coriolis and centrifugal torques come from Pinocchio)",
            f"--qd for the planar arm {args.robot}",
            "the planar arm is modelled at rest: drop --qd, or load a URDF robot.",
        )
    qd = np.deg2rad(args.qd) if args.deg else args.qd
    return check_joint_velocities("--qd", qd, robot.model.n), True


def _velocity_limits(
    args: argparse.Namespace, robot: Robot
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """``--qd-max``/``--qd-min``, else the robot's own (its upper ones if only --qd-min)."""
    if args.qd_max is None and args.qd_min is None:
        return robot.velocity_limits()
    upper = robot.velocity_limits()[0] if args.qd_max is None else args.qd_max
    return np.asarray(upper, dtype=float), args.qd_min


def _limits_lines(analysis: Analysis, moving: bool) -> list[str]:
    """The joint limits the analysis used, stated when they are not the defaults."""
    if not moving:
        return []
    return [
        "torque limits at these joint velocities [N m]: "
        + "; ".join(
            f"{name} {_rounded(value, 6)}" for name, value in analysis.joint_limits().items()
        )
    ]


def _rounded(values: NDArray[np.float64], digits: int) -> list[float]:
    """Values rounded to ``digits`` decimals for display, without numpy's overflow.

    ``np.round(1e308, 6)`` multiplies by 1e6 first and gives inf; Python's ``round`` is
    correctly rounded for every float.
    """
    return [round(float(value), digits) for value in values]


def _analyze(args: argparse.Namespace) -> list[str]:
    """Print the analysis and return notes for standard error.

    Nothing is printed before everything has been computed: an error never follows a
    partial result.
    """
    robot = _robot(args.robot, args.tau_max, args.tau_min)
    q = _configuration(args, robot)
    capacity = check_capacity(args.capacity, "--capacity")
    cls = capacity_class(capacity)
    qd, moving = _velocities(args, robot, cls)
    if (args.horizon is not None or args.braking is not None) and not takes_horizon(capacity):
        raise InputError(
            "--horizon" if args.horizon is not None else "--braking",
            "a horizon only for accelerations",
            f"--capacity {capacity}",
            "leave --horizon and --braking out.",
        )
    if args.braking is not None and args.horizon is None:
        raise InputError(
            "--braking",
            "--braking only with --horizon",
            "no --horizon",
            "add --horizon SECONDS (your control period), or leave --braking out.",
        )
    if "qd_max" in cls.limit_keywords:  # joint velocity limits: --qd-max, --qd-min
        if args.tau_max is not None or args.tau_min is not None:
            raise InputError(
                "--tau-max",
                f"no torque limits for the {capacity} capacity",
                "--tau-max/--tau-min",
                "give joint velocity limits with --qd-max (and --qd-min).",
            )
        qd_max, qd_min = _velocity_limits(args, robot)
        analysis = analyze(robot.model.dynamics(q), capacity=capacity, qd_max=qd_max, qd_min=qd_min)
    else:
        if args.qd_max is not None or args.qd_min is not None:
            raise InputError(
                "--qd-max",
                f"no joint velocity limits for the {capacity} capacity",
                "--qd-max/--qd-min",
                "add --capacity velocity to analyze velocities.",
            )
        tau_max, tau_min = robot.torque_limits(qd)
        model = robot.model
        dynamics = model.dynamics(q, qd) if isinstance(model, UrdfRobot) else model.dynamics(q)
        within: dict[str, Any] = {}
        if args.horizon is not None:  # the state's joint limits over the period
            state = robot_horizon(model, _horizon(args.horizon), braking=args.braking)
            within = state.at(q, np.zeros_like(q) if qd is None else qd).arguments()
        analysis = analyze(dynamics, tau_max, tau_min, capacity=capacity, **within)
    direction, label, notes = _direction(args, analysis.task)
    if args.horizon is not None:
        notes = [*notes, _horizon_note(analysis)]
    comparison = compare(analysis, mvie=not args.no_mvie, outer=not args.no_outer)
    if args.mesh is not None:
        from polyell.export import export_comparison

        notes = [*notes, *(f"wrote {path}" for path in export_comparison(comparison, args.mesh))]
    if args.json:
        result = {"robot": args.robot, "q": q.tolist()}
        if moving:
            result["qd"] = qd.tolist()
        result |= analysis_to_json(analysis, direction, comparison, args.inverse_at)
        text = json.dumps(result, indent=2)
    else:
        text = "\n".join(
            [
                f"{args.robot} at q = {_rounded(q, 6)} rad"
                + (f", qd = {_rounded(qd, 6)} rad/s" if moving else ""),
                *_limits_lines(analysis, moving),
                format_analysis(
                    analysis, direction, label, args.inverse_at, equations=_equations(args)
                ),
                "\nScores against the polytope (pe.compare):\n",
                comparison.to_markdown(),
            ]
        )
    _emit(text)
    return notes


#: The robot of the paper: its text output carries the paper's equation numbers.
PAPER_ROBOT = "chiacchio2000"


def _equations(args: argparse.Namespace) -> bool:
    """The paper's equation numbers in the text: for its own arm, or with ``--equations``."""
    return bool(args.equations) or args.robot == PAPER_ROBOT


def _horizon(value: float) -> float:
    """``--horizon``, checked (a positive number of seconds)."""
    return check_horizon("--horizon", value)


def _horizon_note(analysis: Any) -> str:
    """What the horizon did: the joints that cut the set, or why it is empty."""
    period = f"over the next {analysis.state.horizon:g} s"
    if analysis.empty_reason:
        return f"within the joint limits {period}: no acceleration ({analysis.empty_reason})"
    cut = [str(j + 1) for j in np.flatnonzero(analysis.cut)]
    if not cut:
        return f"within the joint limits {period}: no joint's limits cut the set"
    return f"within the joint limits {period}: joints {', '.join(cut)} cut the set"


def _study(args: argparse.Namespace) -> None:
    spec = load_study(args.spec)
    written = run_study(spec, args.out, progress=not args.quiet, scheduler=args.scheduler)
    _emit("\n".join(study_summary(spec.title, spec.capacities, written, args.out)))


def study_summary(
    title: str, capacities: Sequence[str], written: Sequence[Path], out: str | Path
) -> list[str]:
    """The closing lines of ``polyell study``: every output, what it holds, and warnings.

    The main outputs one a line (:data:`MAIN_OUTPUTS`); each figure, said by its kind
    (:data:`FIGURE_OUTPUTS`); any other file by name; the resumable Parquet
    datasets (``results/``, ``results_force/``) and the warnings of the run, from its
    ``manifest.json``.
    """
    names = {path.name for path in written}
    manifest_path = next((path for path in written if path.name == "manifest.json"), None)
    manifest: dict[str, Any] = {}
    if manifest_path is not None:
        with contextlib.suppress(OSError, ValueError):
            manifest = json.loads(Path(manifest_path).read_text(encoding="utf-8"))
    folder = Path(out)
    lines = [f"{title}: wrote {len(written)} files to {out}"]
    suffixes = {capacity: capacity_class(capacity).output_suffix for capacity in capacities}
    covered: set[str] = set()
    for name, what in MAIN_OUTPUTS.items():
        if name == "manifest.json":  # last, after the figures and datasets
            continue
        if name in _SHARED_OUTPUTS:  # one of each, whatever the capacities
            shown = {name: what}
        else:  # each capacity's; another capacity's carry its name (comparison_force.md)
            stem, extension = name.rsplit(".", 1)
            shown = {
                f"{stem}{suffix}.{extension}": f"{capacity}: {what}" if suffix else what
                for capacity, suffix in suffixes.items()
            }
        for shown_name, said in shown.items():
            if shown_name not in names:
                continue
            stem = shown_name.rsplit(".", 1)[0]
            # the same table in the other formats, and scores.csv (said with comparison.md)
            covered |= {n for n in names if n.rsplit(".", 1)[0] == stem}
            if stem.startswith("comparison"):
                covered.add(f"scores{stem.removeprefix('comparison')}.csv")
            lines.append(f"  {folder / shown_name}: {said}")
    covered.add("manifest.json")
    for kind, what in FIGURE_OUTPUTS.items():
        figures = sorted(
            n for n in names - covered if n.startswith(f"{kind}_") and n.endswith(_FIGURES)
        )
        covered |= set(figures)
        lines += [f"  {folder / name}: {what}" for name in figures]
    lines += [f"  {folder / name}" for name in sorted(names - covered)]
    for dataset in manifest.get("datasets", []):
        stem = dataset.rstrip("/")
        capacity = next((c for c, suffix in suffixes.items() if f"results{suffix}" == stem), "")
        said = f"{capacity}: {DATASET_OUTPUT}" if suffixes.get(capacity) else DATASET_OUTPUT
        lines.append(f"  {folder / stem}/: {said}")
    raised = manifest.get("warnings", [])
    if "manifest.json" in names:  # with the run's warnings (printed after these lines)
        said = MAIN_OUTPUTS["manifest.json"]
        if raised:
            said += f" ({len(raised)} warning{'s' if len(raised) > 1 else ''}, printed below)"
        lines.append(f"  {folder / 'manifest.json'}: {said}")
    return lines


class _OutputError(Exception):
    """Standard output could not be written (a full disk, a closed pipe)."""

    def __init__(self, error: OSError) -> None:
        super().__init__(error.strerror or str(error))
        self.error = error


def _emit(text: str) -> None:
    """Print ``text`` and flush it, so that a failed write is seen here and not at exit."""
    try:
        try:
            print(text)
        except UnicodeEncodeError:  # a file name of undecodable bytes, a narrow encoding
            encoding = sys.stdout.encoding or "utf-8"
            print(text.encode(encoding, "backslashreplace").decode(encoding))
        sys.stdout.flush()
    except OSError as exn:
        raise _OutputError(exn) from None


def _detach_stdout() -> None:
    """Point standard output at the null device.

    Output that could not be written is dropped there, and the interpreter's last flush
    has nothing left to fail on.
    """
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError):  # no file descriptor (standard output replaced in-process)
        pass


def _line(text: str) -> str:
    """One line of standard error: line breaks in a message are shown escaped.

    They come from user text quoted in a message: a file name, a TOML value.
    """
    return text.replace("\r", "\\r").replace("\n", "\\n")


def _fail(message: str) -> int:
    print(_line(f"polyell: error: {message}"), file=sys.stderr)
    return 2


#: Exit status after Ctrl-C (128 + SIGINT), as shells report it.
EXIT_INTERRUPTED = 130


@contextlib.contextmanager
def _notes_on_stderr() -> Iterator[None]:
    """Show polyell's progress notes (logger "polyell", INFO) as ``polyell: ...`` lines."""
    logger = logging.getLogger("polyell")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("polyell: %(message)s"))
    level = logger.level
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(level)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    0 on success; 2 after one line ``polyell: error: ...`` on standard error (bad input, a
    file that cannot be read or written, standard output that cannot be written, or an
    internal error); 130 after one line ``polyell: interrupted`` (Ctrl-C).  Never a
    traceback.
    """
    try:
        try:
            args = _parser().parse_args(_join_list_options(sys.argv[1:] if argv is None else argv))
        finally:  # what --help, --version or a usage error printed must arrive
            sys.stdout.flush()
    except OSError as exn:
        _detach_stdout()
        if exn.errno == errno.EPIPE:
            return 0
        return _fail(f"could not write to standard output: {exn.strerror or exn}.")
    notes: list[str] = []
    caught: list[warnings.WarningMessage] = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ProjectedInputWarning)
            if args.command == "analyze":
                notes = _analyze(args)
            else:
                with _notes_on_stderr():
                    _study(args)
    except PolyellError as exn:
        return _fail(str(exn))
    except _OutputError as exn:
        _detach_stdout()
        if exn.error.errno == errno.EPIPE:  # the reader left (polyell analyze | head)
            return 0
        return _fail(
            f"could not write to standard output: {exn}. Fix: free disk space, or "
            "redirect the output elsewhere."
        )
    except KeyboardInterrupt:
        resume = "; run the same command again to resume" if args.command == "study" else ""
        print(f"polyell: interrupted{resume}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except MemoryError:
        return _fail(
            "out of memory. Fix: make the study smaller (fewer configurations, "
            "directions or samples, a smaller chunk)."
        )
    except Exception as exn:  # a bug: still one line, with what to report
        return _fail(
            f"internal error, {type(exn).__name__}: {str(exn)[:300]}. This is a bug in "
            f"polyell {__version__}: please report it with the command that caused it."
        )
    # Rounded input that was projected: one note each, after the output.
    notes += [str(w.message) for w in caught if issubclass(w.category, ProjectedInputWarning)]
    others = [w for w in caught if not issubclass(w.category, ProjectedInputWarning)]
    # each warning once (a study's joint positions are checked as it loads and as it runs)
    others = list({(w.category, str(w.message)): w for w in others}.values())
    try:
        for note in dict.fromkeys(notes):
            print(_line(f"polyell: note: {note}"), file=sys.stderr)
        for w in others:
            print(_line(f"polyell: warning: {w.category.__name__}: {w.message}"), file=sys.stderr)
    except OSError:  # standard error is gone too: nothing more can be said
        pass
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
