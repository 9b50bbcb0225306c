"""A seeded fuzz of the command line: exit 0, or one line on standard error and exit 2.

Arguments (random flag combinations, bad values, unicode, huge numbers) and study and robot
files mutated from every shipped study (keys dropped, duplicated or added, values of another
type, NaN, inf, 1e308, -1, 0, deep nesting, truncation, bytes that are not UTF-8) go through
``polyell.cli.main`` in this process; a few go through the ``polyell`` entry point.  Nothing
may print a traceback or a warning: a run either succeeds (standard error holds only
``polyell: note:`` lines) or is refused in one ``polyell: error:`` line that is not an
internal error.  The shipped studies are shrunk first (a few configurations, few
directions, small SVG figures) so that a mutation that still runs is fast.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import tomllib

from polyell.cli import main

ROOT = Path(__file__).resolve().parents[1]
STUDIES = sorted((ROOT / "studies").glob("*.toml"))
POLYELL = Path(sys.executable).parent / "polyell"


#: The exit status of every call of :func:`outcome`, in order.
CODES: list[int] = []


def _said(line: str) -> bool:
    """A polyell warning (a slip the run went on with: joint angles out of range, a table
    wider than the page), as the command line words it: one line."""
    import polyell as pe

    names = {cls.__name__ for cls in vars(pe).values() if isinstance(cls, type)}
    polyell_warnings = {n for n in names if issubclass(getattr(pe, n), pe.PolyellWarning)}
    head = line.removeprefix("polyell: warning: ").split(":", 1)[0]
    return line.startswith("polyell: warning: ") and head in polyell_warnings


def outcome(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str | None:
    """None if ``main(argv)`` kept the contract, else what it did wrong."""
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse: --help, --version, usage errors
        code = exit_.code if isinstance(exit_.code, int) else 1
    except BaseException as exn:  # the contract: nothing escapes main
        return f"raised {type(exn).__name__}: {exn}"
    err = capsys.readouterr().err
    CODES.append(code)
    lines = err.splitlines()
    if code == 0:
        if all(line.startswith("polyell: note: ") or _said(line) for line in lines):
            return None
        return f"exit 0 with {err!r}"
    if (
        code == 2
        and len(lines) == 1
        and err.endswith("\n")
        and lines[0].startswith("polyell: error: ")
        and "internal error" not in lines[0]
    ):
        return None
    return f"exit {code} with {err!r}"


# ---------------------------------------------------------------------------------------
# Arguments

NUMBERS = [
    "0",
    "1",
    "-1",
    "pi/2",
    "-pi/2",
    "1e308",
    "-1e308",
    "1e-308",
    "nan",
    "inf",
    "-inf",
    "1e999",
    "9" * 400,
    "sqrt(-1)",
    "1/0",
    "2**2**2**2**2",
    "\u03c0/2",  # unicode pi
    "\uff11",  # full-width digit one
    "",
    "0x10",
    "1_000",
    "(" * 300 + "1" + ")" * 300,
    "__import__('os')",
]


def number_list(rng: np.random.Generator, valid: list[float]) -> str:
    """``valid`` written out, or (a quarter of the time) with entries changed or a wrong length."""
    values = [f"{value:.17g}" for value in valid]
    if rng.random() < 0.25:
        if rng.random() < 0.2:
            values = values[: int(rng.integers(len(values) + 1))] or values + values
        for i in rng.choice(len(values), size=int(rng.integers(1, 3)), replace=True):
            values[int(i) % len(values)] = str(rng.choice(NUMBERS))
    return ",".join(values)


#: Joints and task rows of the robots the fuzz names (a robot file is a 3-link arm).
ROBOTS = {"chiacchio2000": (3, 2), "r.toml": (3, 2), "panda": (7, 3)}


def analyze_argv(rng: np.random.Generator, tmp_path: Path) -> list[str]:
    robots = ["chiacchio2000", "r.toml", "panda", "kuka", "\u00e9"]
    robot = str(rng.choice(robots, p=[0.45, 0.25, 0.2, 0.05, 0.05]))
    n, m = ROBOTS.get(robot, (3, 2))
    argv = ["analyze"]
    if robot != "chiacchio2000" or rng.random() < 0.5:
        argv += ["--robot", str(tmp_path / robot) if robot.endswith(".toml") else robot]
    direction = rng.normal(size=m)
    limits = rng.uniform(1.0, 100.0, n)
    options: dict[str, Any] = {
        "--q": lambda: number_list(rng, list(rng.uniform(-3, 3, n))),
        "--tau-max": lambda: number_list(rng, list(limits)),
        "--tau-min": lambda: number_list(rng, list(-limits * rng.uniform(0.1, 0.9, n))),
        "--direction": lambda: number_list(rng, list(direction / np.linalg.norm(direction))),
        "--angle": lambda: number_list(rng, [float(rng.uniform(-360, 360))]),
        "--inverse-at": lambda: str(rng.choice(["lo", "hi", "hi", "mid", ""])),
        "--capacity": lambda: str(
            rng.choice(["acceleration", "velocity", "velocity", "force", "force", "forces"])
        ),
        "--qd-max": lambda: number_list(rng, list(rng.uniform(0.5, 3.0, n))),
        "--qd-min": lambda: number_list(rng, list(-rng.uniform(0.5, 3.0, n))),
        "--qd": lambda: number_list(rng, list(rng.uniform(-2.0, 2.0, n))),
        "--mesh": lambda: str(
            rng.choice(
                [
                    str(tmp_path / "m.obj"),
                    str(tmp_path / "m.ply"),
                    str(tmp_path / "m.stl"),
                    str(tmp_path / "missing" / "m.obj"),
                    str(tmp_path / ("x" * 300 + ".obj")),
                ]
            )
        ),
    }
    chance = {"--q": 0.9 if robot != "chiacchio2000" else 0.5, "--mesh": 0.15}
    chance |= {"--capacity": 0.3, "--qd-max": 0.06, "--qd-min": 0.04, "--qd": 0.05}
    aim = rng.choice(["--direction", "--angle", "both"], p=[0.6, 0.3, 0.1])  # exclusive
    if aim != "both":
        chance[str({"--direction": "--angle", "--angle": "--direction"}[aim])] = 0.0
    for flag, value in options.items():
        if rng.random() < chance.get(flag, 0.3):
            argv += [flag, value()] if rng.random() < 0.95 else [flag]
    flags = ["--deg", "--normalize", "--no-mvie", "--no-outer", "--json", "--help", "--bogus"]
    for flag in flags:
        if rng.random() < (0.02 if flag in ("--help", "--bogus") else 0.3):
            argv.append(flag)
    if "--no-mvie" not in argv and rng.random() < 0.8:  # the MVIE is the slow part
        argv.append("--no-mvie")
    return argv


def study_argv(rng: np.random.Generator, tmp_path: Path) -> list[str]:
    spec = str(rng.choice(["s.toml", "missing.toml", "", ".", "s.toml\u00e9"]))
    argv = ["study"] + ([str(tmp_path / spec)] if spec else [])
    if rng.random() < 0.9:
        out = str(rng.choice(["out", "r.toml/sub", "\u00e9\u00e8", "x" * 300]))
        argv += ["--out", str(tmp_path / out)]
    if rng.random() < 0.5:
        argv.append("--quiet")
    if rng.random() < 0.3:
        argv += ["--scheduler", str(rng.choice(["tcp://a:b", "tcp://[::1", "threads", "", "9"]))]
    return argv


ROBOT_FILE = "planar = { lengths = [1, 0.8, 0.5], masses = [4, 2, 0.6] }\ntau_max = [100, 30, 4]\n"
POINTS_STUDY = (
    'title = "fuzz"\n[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\n'
    "q = [0.3, 0.5, 0.7]\n[compare]\ndirections = 8\nmvie = false\nouter = false\n"
    '[output]\nformats = ["svg"]\ndpi = 10\n'
)


def test_random_arguments_keep_the_contract(tmp_path, capsys):
    (tmp_path / "r.toml").write_text(ROBOT_FILE)
    (tmp_path / "s.toml").write_text(POINTS_STUDY)
    rng = np.random.default_rng(20)
    failures, codes = [], []
    for case in range(200):
        if rng.random() < 0.85:
            argv = analyze_argv(rng, tmp_path)
        elif rng.random() < 0.7:
            argv = study_argv(rng, tmp_path)
        else:
            argv = [str(rng.choice(["", "--version", "anal", "\u00e9", "-", "--"]))]
        problem, code = outcome(argv, capsys), CODES[-1]
        codes.append(code)
        if problem is not None:
            failures.append((case, argv, problem))
    assert not failures, "\n".join(map(str, failures))
    print(f"exit 0: {codes.count(0)}, exit 2: {codes.count(2)} of {len(codes)}")
    assert codes.count(0) >= 50 and codes.count(2) >= 50  # both outcomes well exercised


# ---------------------------------------------------------------------------------------
# Study and robot files


def shrink(study: dict[str, Any]) -> dict[str, Any]:
    """The study made small: 1 or 2 configurations, 8 directions, small SVG figures, no
    log-det programs at single points."""
    for axis in study.get("grid", {}).values():
        if isinstance(axis, dict):
            axis["num"] = 2
    if "random" in study:
        study["random"]["count"] = 2
    compare = study.setdefault("compare", {})
    compare["directions"], compare["samples"] = 8, 64
    if "points" in study:  # log-det programs and figures per point: its slow part
        compare["mvie"] = compare["outer"] = False
        study["points"] = study["points"][:1]
    output = study.setdefault("output", {})
    output["formats"], output["dpi"] = ["svg"], 10
    for key, keep in (("maps", 2), ("histograms", 1), ("series", 2)):
        if key in output:
            output[key] = output[key][:keep]
    return study


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
    assert isinstance(value, dict)
    return "{ " + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + " }"


def toml_text(document: dict[str, Any]) -> str:
    return "".join(f"{json.dumps(key)} = {toml_value(value)}\n" for key, value in document.items())


VALUES: list[Any] = [
    math.nan,
    math.inf,
    -math.inf,
    1e308,
    -1e308,
    -1,
    0,
    1,
    0.5,
    2**31,
    2**63 - 1,
    -(2**63),
    True,
    "",
    "pi/2",
    "\u03c0",
    "\u202e\U0001f600",
    "../../etc/passwd",
    "$x^$",  # mathtext that does not parse
    "50% & _# \\input{x}",  # LaTeX's special characters
    "two\nlines",
    "nan",
    [],
    [1, 2],
    [[1, 2], [3]],
    {},
    {"a": 1},
    ["x", 1, [2]],
]


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


def mutate(document: dict[str, Any], rng: np.random.Generator) -> dict[str, Any]:
    """One random change of a key or value somewhere in ``document``."""
    paths = nodes(document)
    path = paths[int(rng.integers(len(paths)))]
    parent = document
    for step in path[:-1]:
        parent = parent[step]
    last = path[-1]
    action = rng.choice(["drop", "value", "nest", "key", "scale"])
    if action == "drop":
        del parent[last]
    elif action == "value":
        parent[last] = VALUES[int(rng.integers(len(VALUES)))]
    elif action == "nest":  # within what the parser follows; deeper is a test of its own
        value = parent[last]
        for _ in range(int(rng.choice([1, 2, 5, 50]))):
            value = [value]
        parent[last] = value
    elif action == "key" and isinstance(parent, dict):
        parent[str(rng.choice(["bogus", "Title", "q0", "\u00e9", ""]))] = parent[last]
    elif isinstance(parent[last], int | float) and not isinstance(parent[last], bool):
        parent[last] = parent[last] * float(rng.choice([-1, 0, 1e-300, 1e300]))
    return document


def mutate_text(text: str, rng: np.random.Generator) -> bytes:
    """A change of the file's bytes: truncated, a line duplicated, bytes not UTF-8."""
    data = text.encode()
    action = rng.choice(["truncate", "duplicate", "bytes"])
    if action == "truncate":
        return data[: int(rng.integers(len(data)))]
    if action == "duplicate":  # a key twice: invalid TOML
        lines = text.splitlines(keepends=True)
        i = int(rng.integers(len(lines)))
        return "".join([*lines[: i + 1], lines[i], *lines[i + 1 :]]).encode()
    i = int(rng.integers(len(data)))
    return data[:i] + bytes(rng.choice([b"\xff", b"\xc3", b"\xe2\x82", b"\x00"])) + data[i:]


def mutations(rng: np.random.Generator, base: dict[str, Any], count: int) -> list[bytes]:
    files = []
    for _ in range(count):
        document = json.loads(json.dumps(base))  # a deep copy
        if rng.random() < 0.25:
            files.append(mutate_text(toml_text(document), rng))
            continue
        for _ in range(int(rng.choice([1, 1, 2, 3]))):
            if nodes(document):
                document = mutate(document, rng)
        files.append(toml_text(document).encode())
    return files


@pytest.mark.parametrize("study", STUDIES, ids=[path.stem for path in STUDIES])
def test_mutated_shipped_studies_keep_the_contract(tmp_path, capsys, study):
    rows = (ROOT / "studies" / "planar3r_path.csv").read_text().splitlines(keepends=True)
    (tmp_path / "planar3r_path.csv").write_text("".join(rows[:3]))  # two configurations
    base = shrink(tomllib.loads(study.read_text()))
    path = tmp_path / "study.toml"
    path.write_text(toml_text(base))  # the shrunk study itself runs
    assert outcome(["study", str(path), "--out", str(tmp_path / "base"), "--quiet"], capsys) is None
    rng = np.random.default_rng([21, STUDIES.index(study)])
    failures = []
    for case, data in enumerate(mutations(rng, base, 16)):
        path.write_bytes(data)
        out = tmp_path / f"out{case}"
        problem = outcome(["study", str(path), "--out", str(out), "--quiet"], capsys)
        if problem is not None:
            failures.append((case, data.decode(errors="replace"), problem))
        shutil.rmtree(out, ignore_errors=True)
    assert not failures, "\n".join(map(str, failures))


def test_mutated_robot_files_keep_the_contract(tmp_path, capsys):
    bases = [
        tomllib.loads(ROBOT_FILE),
        {"library": "panda", "task": "linear", "payload": {"mass": 1.0, "com": [0, 0, 0.05]}},
    ]
    rng = np.random.default_rng(22)
    path = tmp_path / "robot.toml"
    failures = []
    for b, base in enumerate(bases):
        q = "0.3,0.5,0.7" if b == 0 else "0,-0.5,0,-2,0,1.6,0.8"
        for case, data in enumerate(mutations(rng, base, 30)):
            path.write_bytes(data)
            argv = ["analyze", "--robot", str(path), "--q", q, "--no-mvie", "--no-outer"]
            problem = outcome(argv, capsys)
            if problem is not None:
                failures.append((b, case, data.decode(errors="replace"), problem))
    assert not failures, "\n".join(map(str, failures))


def test_deep_nesting_anywhere_is_one_line(tmp_path, capsys):
    base = shrink(tomllib.loads(STUDIES[0].read_text()))
    path = tmp_path / "study.toml"
    failures = []
    for where in nodes(base):
        document = json.loads(json.dumps(base))
        parent = document
        for step in where[:-1]:
            parent = parent[step]
        parent[where[-1]] = "@deep@"
        path.write_text(toml_text(document).replace('"@deep@"', "[" * 3000 + "1" + "]" * 3000))
        problem = outcome(["study", str(path), "--out", str(tmp_path / "o"), "--quiet"], capsys)
        if problem is not None:
            failures.append((where, problem))
    assert not failures, "\n".join(map(str, failures))


@pytest.mark.parametrize(
    "argv",
    [
        ["analyze", "--q", "1e308,0,0", "--no-mvie"],
        ["study", "\udcff.toml", "--out", "o"],  # a file name of undecodable bytes
        ["analyze", "--robot", "/"],
    ],
)
def test_the_entry_point_keeps_the_contract(tmp_path, argv):
    result = subprocess.run(
        [str(POLYELL), *argv], capture_output=True, cwd=tmp_path, timeout=300, errors="replace"
    )
    lines = result.stderr.splitlines()
    assert result.returncode in (0, 2), result.stderr
    if result.returncode == 2:
        assert len(lines) == 1 and lines[0].startswith("polyell: error: "), result.stderr
        assert "internal error" not in lines[0]
    else:
        assert all(line.startswith("polyell: note: ") for line in lines), result.stderr
