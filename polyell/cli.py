"""The ``polyell`` command line."""

from __future__ import annotations

import argparse
import ast
import operator
import sys
from collections.abc import Sequence

import numpy as np

from polyell.analysis import analyze
from polyell.errors import PolyellError
from polyell.models.planar_arm import PlanarArm
from polyell.report import format_analysis

__all__ = ["main"]

#: The arm and torque limits of Chiacchio (2000), section 6.
PAPER_LENGTHS, PAPER_MASSES, PAPER_COM = [1.0, 0.8, 0.5], [4.0, 2.0, 0.6], [0.5, 0.4, 0.25]
PAPER_TAU_MAX = [100.0, 30.0, 4.0]
PAPER_Q = [np.pi / 2, -np.pi / 2, -np.pi / 2]


_OPERATORS = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}


def _number(node: ast.AST) -> float:
    """Evaluate a number, ``pi``, or + - * / of them; nothing else."""
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id == "pi":
        return float(np.pi)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        value = _number(node.operand)
        return -value if isinstance(node.op, ast.USub) else value
    if isinstance(node, ast.BinOp) and type(node.op) in _OPERATORS:
        return float(_OPERATORS[type(node.op)](_number(node.left), _number(node.right)))
    raise ValueError(ast.dump(node))


def _floats(text: str) -> list[float]:
    """Parse a comma-separated list of numbers, where ``pi`` may appear (``pi/2,-pi/2,0``)."""
    try:
        return [_number(ast.parse(item.strip(), mode="eval").body) for item in text.split(",")]
    except (SyntaxError, ValueError, ZeroDivisionError):
        raise argparse.ArgumentTypeError(
            f"expected comma-separated numbers (pi allowed, e.g. 'pi/2,-pi/2,0'), got {text!r}"
        ) from None


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
