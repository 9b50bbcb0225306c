"""Safe evaluation of the small numeric expressions users write for angles and limits.

``"pi/2"``, ``"-pi/6"``, ``"2*pi/3"``, ``"sqrt(3)/2"``, ``"1e-3"``: numbers, ``pi``,
``sqrt(...)``, ``+ - * /`` and ``**``; nothing else is evaluated.
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Callable, Sequence

from polyell.errors import InputError

__all__ = ["evaluate", "evaluate_list"]

_BINARY: dict[type, Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}
_FUNCTIONS: dict[str, Callable[[float], float]] = {"sqrt": math.sqrt}
_NAMES = {"pi": math.pi}
#: Longest expression accepted (a number typed with its derivation fits easily).
MAX_EXPRESSION_LENGTH = 200


def _value(node: ast.AST) -> float:
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in _NAMES:
        return _NAMES[node.id]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        value = _value(node.operand)
        return -value if isinstance(node.op, ast.USub) else value
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        return float(_BINARY[type(node.op)](_value(node.left), _value(node.right)))
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in _FUNCTIONS
        and len(node.args) == 1
        and not node.keywords
    ):
        return _FUNCTIONS[node.func.id](_value(node.args[0]))
    raise ValueError(ast.dump(node))


def evaluate(name: str, text: str | float | int) -> float:
    """Evaluate a number or a numeric expression such as ``"-pi/2"``.

    Raises
    ------
    InputError
        If ``text`` is not a number or an expression of numbers, ``pi``, ``sqrt``,
        ``+ - * / **``.
    """
    if isinstance(text, bool):
        raise InputError(
            name,
            "a number or an expression like 'pi/2'",
            repr(text),
            "write a number, e.g. 1.0, or an expression, e.g. 'pi/2' (true and false are not "
            "numbers)",
        )
    expected = "a number or an expression of numbers, pi, sqrt(), + - * / ** (e.g. '-pi/2')"
    if isinstance(text, int | float):
        value = float(text) if abs(text) < 2**1024 else math.inf  # an int beyond a double
    elif not isinstance(text, str) or len(text) > MAX_EXPRESSION_LENGTH:
        shown = repr(text) if len(repr(text)) <= 60 else f"{repr(text)[:57]}..."
        raise InputError(
            name,
            f"{expected}, of at most {MAX_EXPRESSION_LENGTH} characters",
            shown,
            f"write one number or a str of at most {MAX_EXPRESSION_LENGTH} characters, "
            "e.g. '-pi/2' or 1.5708",
        )
    else:
        try:
            value = _value(ast.parse(text.strip(), mode="eval").body)
        except (SyntaxError, ValueError, TypeError, ZeroDivisionError, OverflowError):
            # TypeError: a complex power such as (-8)**0.5
            raise InputError(
                name,
                expected,
                repr(text),
                "use only numbers, pi, sqrt(...) and + - * / ** (no division by zero, no "
                "root of a negative number), e.g. '-pi/2' or 'sqrt(3)/2'",
            ) from None
        except RecursionError:  # nesting too deep for the parser
            raise InputError(
                name,
                f"{expected}, not nested so deeply",
                repr(text[:60]),
                "remove the redundant parentheses, or give the value as a number, e.g. 0.5",
            ) from None
    if not math.isfinite(value):
        raise InputError(
            name,
            "a finite number",
            repr(text) if len(repr(text)) <= 60 else f"{repr(text)[:57]}...",
            "give a finite value, e.g. 1e3 rather than inf or 1e400 (beyond a double)",
        )
    return value


def evaluate_list(name: str, values: str | Sequence[str | float | int]) -> list[float]:
    """Evaluate a list of numbers/expressions, or one comma-separated string of them."""
    if not isinstance(values, str | list | tuple):
        raise InputError(
            name,
            "a list of numbers or expressions",
            f"{type(values).__name__} {values!r}"[:80],
            "pass a list such as [0.0, 'pi/2'], or one comma-separated str such as '0, pi/2'",
        )
    items = values.split(",") if isinstance(values, str) else list(values)
    return [evaluate(f"{name}[{i}]", item) for i, item in enumerate(items)]
