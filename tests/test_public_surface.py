"""Every documented function, given one wrong argument: a polyell error or a result.

The public surface is what docs/api.md documents (``autofunction`` entries and the
``__all__`` of each ``automodule``), not only ``pe.__all__``.  Each function is called with
its required positional arguments all of one wrong kind (None, NaN, a str, empty
containers, 1e300, negative, 0, a bool, a 3-D array, 1e-300): it must raise
a :class:`~polyell.PolyellError` or return, never raise a raw Python exception (a
TypeError, AttributeError, KeyError, StopIteration...).
"""

from __future__ import annotations

import importlib
import inspect
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import polyell as pe

API = Path(__file__).resolve().parents[1] / "docs" / "api.md"
WRONG = [None, np.nan, "x", [], {}, 1e300, -1, 0, True, np.zeros((2, 2, 2)), 1e-300]


def _documented_functions() -> list[tuple[str, object]]:
    """(qualified name, callable) of every function and class docs/api.md documents."""
    text = API.read_text(encoding="utf-8")
    found: dict[str, object] = {}
    pattern = r"^\.\. (autofunction|automodule|autoclass):: (\S+)"
    for directive, target in re.findall(pattern, text, re.M):
        if directive == "automodule":
            module = importlib.import_module(target)
            for name in getattr(module, "__all__", []):
                value = getattr(module, name)
                if inspect.isfunction(value) or inspect.isclass(value):
                    found[f"{target}.{name}"] = value
        else:
            module_name, _, name = target.rpartition(".")
            found[target] = getattr(importlib.import_module(module_name), name)
    return sorted(found.items())


def _required(function: object) -> int | None:
    """How many positional arguments the function requires; None if it requires a keyword."""
    try:
        parameters = inspect.signature(function).parameters.values()  # type: ignore[arg-type]
    except ValueError:  # a builtin type without one (str subclasses): no argument to check
        return None
    required = [
        p
        for p in parameters
        if p.default is p.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]
    if any(p.kind is p.KEYWORD_ONLY for p in required):
        return None
    return len(required) or None


FUNCTIONS = [
    (name, f, _required(f))
    for name, f in _documented_functions()
    if _required(f) and not inspect.isabstract(f)
]


def test_the_surface_is_the_documented_one():
    """The list is read from the docs (not a fixed list that could go stale), and holds
    the submodules' functions as well as pe's."""
    names = [name for name, _, _ in FUNCTIONS]
    assert len(names) >= 40
    for module in ("polyell.figures", "polyell.interactive", "polyell.export", "polyell.robots"):
        assert any(name.startswith(module + ".") for name in names), module


@pytest.mark.parametrize("name, function, count", FUNCTIONS, ids=[f[0] for f in FUNCTIONS])
def test_wrong_arguments_give_a_polyell_error_or_a_result(
    name, function, count, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # a function that writes a file writes it here
    raw = []
    for value in WRONG:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                function(*[value] * count)
            except pe.PolyellError:
                pass
            except Exception as exn:  # the test's point: any other exception is a defect
                raw.append(f"{value!r:.30}: {type(exn).__name__}: {exn}"[:200])
    assert not raw, f"{name}:\n" + "\n".join(raw)
