"""Seeded property tests of the study loader: mutated TOML loads, or is refused in one
InputError whose argument is the key's path; ``polyell study`` exits 0, or prints one line
and exits 2.

Hypothesis draws (derandomized, see conftest) a base study (directions, several robots,
a q table per robot, a grid, random configurations, the table layout, candidates) and up
to three mutations: a key dropped, renamed or added, a value replaced by one of another
type, nested in lists, or a number scaled to extremes.  No other exception may escape
(KeyError, TypeError, pydantic's ValidationError, ...).
"""

from __future__ import annotations

import copy
import json
import math
import re
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell.studies import load_study

PANDA_Q = [0, -0.5, 0, -2, 0, 1.6, 0.8]
UR5_Q = [0, -1.2, 1.5, -1.9, -1.57, 0]
SMALL = {
    "compare": {"directions": 8, "samples": 64, "mvie": False, "outer": False},
    "output": {"formats": ["svg"], "dpi": 10},
}
BASES: list[dict[str, Any]] = [
    {
        "title": "points",
        "robot": {"library": "chiacchio2000", "tau_max": [100, 30, "4"]},
        "points": [
            {"name": "a", "q": ["pi/2", "-pi/2", "-pi/2"], "directions": ["x", "-xy", [0, 1]]},
            {"name": "b", "q": [0.1, 0.2, 0.3], "direction": ["-1/2", "sqrt(3)/2"]},
        ],
        "candidates": [{"name": "disc", "core": [1e-3, 1e-3]}],
        **SMALL,
        "output": {
            **SMALL["output"],
            "sets": ["polytope", "disc"],
            "scores": ["coverage"],
            "transpose": True,
            "split": "posture",
            "digits": 4,
            "percent": False,
        },
    },
    {
        "robots": [
            {"name": "panda", "library": "panda", "task": "linear"},
            {"name": "ur5", "library": "ur5", "tau_max": [150, 150, 150, 28, 28, 28]},
        ],
        "points": [{"name": "home", "q": {"panda": PANDA_Q, "ur5": UR5_Q}, "directions": ["z"]}],
        **SMALL,
    },
    {
        "robot": {
            "planar": {"lengths": [1, 0.8, 0.5], "masses": [4, 2, 0.6]},
            "tau_max": [9, 5, 1],
        },
        "grid": {
            "q1": "pi/2",
            "q2": {"start": "-pi", "stop": "pi", "num": 2},
            "q3": {"start": 0, "stop": 1, "num": 2},
        },
        **SMALL,
        "output": {**SMALL["output"], "maps": ["chiacchio_coverage"]},
    },
    {
        "robots": [
            {"name": "arm", "library": "chiacchio2000"},
            {"name": "ur5", "library": "ur5", "payload": {"mass": 1.0, "com": [0, 0, 0.05]}},
        ],
        "random": {"count": 2, "seed": 3},
        **SMALL,
        "output": {**SMALL["output"], "histograms": ["coverage"]},
    },
]

#: A key path: a top-level key, then ``[i]`` indices and ``.key`` steps.
KEY_PATH = re.compile(r"(study\.toml|path|[a-z_]+)(\[\d+\]|\.[A-Za-z0-9_-]+)*")

LEAF = st.one_of(
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["", "x", "-xz", "wx", "pi/2", "panda", "ur5", "posture", "q1", "\u00e9"]),
    st.text(alphabet="xyzw-+pi/2.() \u00e9", max_size=6),
)
VALUE = st.recursive(
    LEAF,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(st.sampled_from(["name", "q", "start", "num", "bogus"]), inner, max_size=3),
    ),
    max_leaves=6,
)


def toml_value(value: Any) -> str:
    """A value as TOML (inline tables and arrays; NaN and infinities as TOML writes them)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    return "{ " + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + " }"


def toml_text(document: dict[str, Any]) -> str:
    return "".join(f"{json.dumps(key)} = {toml_value(value)}\n" for key, value in document.items())


def nodes(value: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Paths to every value below ``value`` (dict keys and list indices)."""
    found = [path] if path else []
    if isinstance(value, dict):
        for key, item in value.items():
            found += nodes(item, (*path, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            found += nodes(item, (*path, i))
    return found


@st.composite
def mutated_studies(draw: st.DrawFn) -> str:
    document = copy.deepcopy(draw(st.sampled_from(BASES)))
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        paths = nodes(document)
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = document
        for step in path[:-1]:
            parent = parent[step]
        last = path[-1]
        action = draw(st.sampled_from(["drop", "value", "value", "key", "nest", "scale"]))
        if action == "drop":
            del parent[last]
        elif action == "value":
            parent[last] = draw(VALUE)
        elif action == "key" and isinstance(parent, dict):
            name = draw(st.sampled_from(["bogus", "directons", "robot", "robots", "q0", "", "é"]))
            parent[name] = parent[last]
        elif action == "nest":
            parent[last] = [parent[last]]
        elif isinstance(parent[last], int | float) and not isinstance(parent[last], bool):
            parent[last] = parent[last] * draw(st.sampled_from([-1, 0, 1e-300, 1e300]))
    return toml_text(document)


def check_loaded_or_refused(path: Path) -> pe.studies.StudySpec | None:
    """The spec, or None after an InputError naming a key path; anything else fails."""
    try:
        return load_study(path)
    except pe.InputError as exn:
        assert KEY_PATH.fullmatch(exn.argument), f"not a key path: {exn.argument!r} ({exn})"
        assert exn.expected and exn.got, str(exn)
        return None


def test_every_base_loads():
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "study.toml"
        for base in BASES:
            path.write_text(toml_text(base))
            assert load_study(path) is not None


def test_mutated_studies_load_or_are_refused_with_a_key_path():
    outcomes = {"loaded": 0, "refused": 0}

    @settings(max_examples=80)
    @given(text=mutated_studies())
    def check(text: str) -> None:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "study.toml"
            path.write_text(text)
            outcomes["loaded" if check_loaded_or_refused(path) else "refused"] += 1

    check()
    assert outcomes["loaded"] >= 5 and outcomes["refused"] >= 20, outcomes  # both exercised


@settings(max_examples=25)
@given(text=mutated_studies())
def test_polyell_study_on_mutated_files_exits_0_or_prints_one_line(text):
    from polyell.cli import main

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "study.toml"
        path.write_text(text)
        out = Path(folder) / "out"
        with pytest.MonkeyPatch.context() as patch:
            import io
            import sys

            err = io.StringIO()
            patch.setattr(sys, "stderr", err)
            patch.setattr(sys, "stdout", io.StringIO())
            try:
                code = main(["study", str(path), "--out", str(out), "--quiet"])
            except SystemExit as exit_:
                code = exit_.code if isinstance(exit_.code, int) else 1
        lines = err.getvalue().splitlines()
        if code == 0:
            assert all(line.startswith("polyell: note: ") for line in lines), lines
        else:
            assert code == 2, (code, lines)
            assert len(lines) == 1 and lines[0].startswith("polyell: error: "), lines
            assert "internal error" not in lines[0]
            if load_attempt_fails(path):
                assert not out.exists()  # refused when loading: no folder is made


def load_attempt_fails(path: Path) -> bool:
    return check_loaded_or_refused(path) is None
