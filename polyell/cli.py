"""The ``polyell`` command line."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from polyell.analysis import analyze
from polyell.errors import PolyellError
from polyell.expressions import evaluate_list
from polyell.models.planar_arm import PlanarArm
from polyell.report import format_analysis

__all__ = ["main"]

#: The arm and torque limits of Chiacchio (2000), section 6.
PAPER_LENGTHS, PAPER_MASSES, PAPER_COM = [1.0, 0.8, 0.5], [4.0, 2.0, 0.6], [0.5, 0.4, 0.25]
PAPER_TAU_MAX = [100.0, 30.0, 4.0]
PAPER_Q = [np.pi / 2, -np.pi / 2, -np.pi / 2]


def _floats(text: str) -> list[float]:
    """Parse a comma-separated list of numbers, where ``pi`` may appear (``pi/2,-pi/2,0``)."""
    try:
        return evaluate_list("value", text)
    except PolyellError as exn:
        raise argparse.ArgumentTypeError(str(exn)) from None


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="polyell",
        description="Exact acceleration polytopes and dynamic manipulability ellipsoids.",
    )
    commands = parser.add_subparsers(dest="command", required=True)
    run = commands.add_parser(
        "analyze",
        help="analyze the planar arm of Chiacchio (2000) at one configuration",
        description="Print the polytope, both ellipsoids and the limits along a direction "
        "for the 3-link planar arm of Chiacchio (2000), section 6.",
    )
    run.add_argument("--q", type=_floats, default=PAPER_Q, help="joint angles [rad]")
    run.add_argument("--tau-max", type=_floats, default=PAPER_TAU_MAX, help="[N m]")
    run.add_argument("--tau-min", type=_floats, default=None, help="[N m], default -tau-max")
    run.add_argument(
        "--direction", type=_floats, default=[1.0, 0.0], help="unit task direction, default x"
    )
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    args = _parser().parse_args(argv)
    try:
        arm = PlanarArm(PAPER_LENGTHS, PAPER_MASSES, com=PAPER_COM)
        analysis = analyze(arm.dynamics(args.q), tau_max=args.tau_max, tau_min=args.tau_min)
        label = "x" if args.direction == [1.0, 0.0] else "t"
        print(f"Planar arm of Chiacchio (2000) at q = {np.round(args.q, 6).tolist()} rad")
        print(format_analysis(analysis, np.asarray(args.direction), label))
    except PolyellError as exn:
        print(f"polyell: error: {exn}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
