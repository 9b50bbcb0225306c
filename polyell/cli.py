"""The ``polyell`` command line: ``polyell analyze`` and ``polyell study``.

Bad input ends with a one-line ``polyell: error: ...`` on standard error and exit status
2, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from collections.abc import Sequence
from typing import NoReturn

import numpy as np

from polyell import robots
from polyell.analysis import analyze
from polyell.comparison import compare
from polyell.errors import InputError, PolyellError, ProjectedInputWarning
from polyell.expressions import evaluate_list
from polyell.report import analysis_to_json, format_analysis
from polyell.studies import load_robot_file, load_study, run_study
from polyell.studies.spec import Robot
from polyell.validation import check_torque_limits

__all__ = ["main"]

PAPER_Q = "pi/2,-pi/2,-pi/2"


def _floats(text: str) -> list[float]:
    """Parse a comma-separated list of numbers, where ``pi`` may appear (``pi/2,-pi/2,0``)."""
    try:
        return evaluate_list("value", text)
    except PolyellError as exn:
        raise argparse.ArgumentTypeError(str(exn)) from None


class _Parser(argparse.ArgumentParser):
    """argparse, with its errors on one line like the package's own."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"polyell: error: {message} (see '{self.prog} --help')\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="polyell",
        description="Exact acceleration polytopes and dynamic manipulability ellipsoids "
        "(Chiacchio 2000), compared.",
    )
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
    run.add_argument("--q", type=_floats, default=_floats(PAPER_Q), help="joint angles [rad]")
    run.add_argument("--tau-max", type=_floats, help="[N m], default: the robot's own")
    run.add_argument("--tau-min", type=_floats, help="[N m], default -tau-max")
    run.add_argument(
        "--direction",
        type=_floats,
        default=None,
        help="unit task direction, default the first task axis (x); write "
        "--direction=-0.5,0.866 for a leading '-'",
    )
    run.add_argument(
        "--inverse-at", choices=("lo", "hi"), default="hi", help="end of the new interval"
    )
    run.add_argument("--no-mvie", action="store_true", help="skip the log-det program")
    run.add_argument("--json", action="store_true", help="print JSON instead of text")
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
    if name.endswith(".toml"):
        robot = load_robot_file(name)
    else:
        model = robots.load(name)
        if model.tau_max is None or model.tau_min is None:
            raise InputError("--tau-max", "torque limits for this robot", "none given")
        robot = Robot(model, model.tau_max, model.tau_min)
    if tau_max is None:
        return robot
    upper, lower = check_torque_limits(tau_max, tau_min, robot.model.n)
    return Robot(robot.model, upper, lower)


def _analyze(args: argparse.Namespace) -> None:
    robot = _robot(args.robot, args.tau_max, args.tau_min)
    analysis = analyze(robot.model.dynamics(args.q), robot.tau_max, robot.tau_min)
    m = analysis.dynamics.m
    direction = np.eye(m)[0] if args.direction is None else np.asarray(args.direction)
    comparison = compare(analysis, mvie=not args.no_mvie)
    if args.json:
        result = {"robot": args.robot, "q": list(args.q)}
        result |= analysis_to_json(analysis, direction, comparison)
        print(json.dumps(result, indent=2))
        return
    label = "x" if args.direction is None else "t"
    print(f"{args.robot} at q = {np.round(args.q, 6).tolist()} rad")
    print(format_analysis(analysis, direction, label, args.inverse_at))
    print("\nScores against the polytope (pe.compare):\n")
    print(comparison.to_markdown())


def _study(args: argparse.Namespace) -> None:
    spec = load_study(args.spec)
    written = run_study(spec, args.out, progress=not args.quiet, scheduler=args.scheduler)
    print(f"{spec.title}: wrote {len(written)} files to {args.out}")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    args = _parser().parse_args(argv)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ProjectedInputWarning)
            _analyze(args) if args.command == "analyze" else _study(args)
    except PolyellError as exn:
        print(f"polyell: error: {exn}", file=sys.stderr)
        return 2
    finally:  # rounded input that was projected: one note each, after the output
        for note in dict.fromkeys(
            str(w.message) for w in caught if issubclass(w.category, ProjectedInputWarning)
        ):
            print(f"polyell: note: {note}", file=sys.stderr)
        for w in caught:
            if not issubclass(w.category, ProjectedInputWarning):
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
