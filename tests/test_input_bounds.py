"""Every input bounded, every refusal the package's own (issue 15, part 3).

Paths, sizes, types and ranges of study files and API arguments, and a seeded fuzz of both
with a bounded number of cases: anything but a result or a PolyellError is a defect.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import polyell as pe
from polyell.expressions import evaluate
from polyell.studies import load_study, run_study
from reference import PAPER_Q_REDUNDANT, paper_analysis, planar_urdf

ARM = pe.robots.load("chiacchio2000")
POINTS = '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.1, 0.2, 0.3]\n'


def write(tmp_path, text: str):
    path = tmp_path / "study.toml"
    path.write_text(text)
    return path


# --- nothing a study file says writes outside the output folder --------------------------


@pytest.mark.parametrize(
    "name", ["x/../../NAME", "sub/dir", "../up", ".hidden", "", "a" * 65, "tab\tname", "/abs"]
)
def test_point_names_cannot_leave_the_output_folder(tmp_path, name):
    text = POINTS.replace('name = "p"', f"name = {json.dumps(name)}")
    with pytest.raises(pe.InputError, match="names files"):
        load_study(write(tmp_path, text))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]


def test_a_plain_point_name_writes_inside(tmp_path):
    text = POINTS.replace('name = "p"', 'name = "run-1.a"') + (
        '[compare]\nmvie = false\ndirections = 8\n[output]\nformats = ["png"]\ndpi = 20\n'
    )
    written = run_study(load_study(write(tmp_path, text)), tmp_path / "out")
    assert all((tmp_path / "out") in path.parents for path in written)
    assert (tmp_path / "out" / "sets_run-1.a.png").exists()


@pytest.mark.parametrize("name", ["p", "P", "p_force", "P_Velocity"])
def test_point_names_whose_files_collide_are_refused(tmp_path, name):
    # The same name, equal up to case (one file on macOS and Windows), or another's with a
    # capacity suffix ("p" and "p_force" wrote different figures to sets_p_force.png).
    text = POINTS + f'[[points]]\nname = "{name}"\nq = [0, 0, 0]\n'
    with pytest.raises(pe.InputError, match="output files differ"):
        load_study(write(tmp_path, text))


# --- sizes ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        (
            '[[points]]\nname = "p"\nq = [0, 0, 0]\n[compare]\ndirections = 2000000000\n',
            "compare.directions: expected an integer",
        ),
        (
            "[grid]\nq1 = 0\nq2 = 0\nq3 = { start = 0, stop = 1, num = 1000000000000 }\n",
            "grid.q3.num: expected an integer from 1 to 10,000,000",
        ),
        (
            "[grid]\nq1 = { start = 0, stop = 1, num = 10000 }\nq2 = 0\n"
            "q3 = { start = 0, stop = 1, num = 10000 }\n",
            "grid: expected at most 10,000,000 configurations",
        ),
        ("[random]\ncount = 100000000000\n", "random.count: expected an integer"),
    ],
)
def test_sizes_are_bounded(tmp_path, extra, fragment):
    with pytest.raises(pe.InputError, match=fragment):
        load_study(write(tmp_path, '[robot]\nlibrary = "chiacchio2000"\n' + extra))


def test_direction_counts_are_bounded():
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    with pytest.raises(pe.InputError, match="at most 1,000,000"):
        pe.compare(analysis, 2_000_000_000)
    with pytest.raises(pe.InputError, match="at most 1,000,000"):
        pe.sweep(ARM, [[0.1, 0.2, 0.3]], directions=10**7)


# --- types and ranges of study files --------------------------------------------------------


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        ('[compare]\nchunk = "x"\n', "compare.chunk: expected an integer"),
        ("[compare]\nseed = -1\n", "compare.seed: expected an integer from 0"),
        ('[compare]\nmvie = "yes"\n', "compare.mvie: expected true or false"),
        ("[compare]\nsamples = 1\n", "compare.samples: expected an integer from 2"),
        ("[output]\ndpi = 0\n", "output.dpi: expected an integer from 10"),
        ('[output]\nformats = "png"\n', "output.formats: expected a list of strings"),
        ("title = 5\n", "title: expected a string"),
    ],
)
def test_study_values_of_the_wrong_type_or_range(tmp_path, extra, fragment):
    with pytest.raises(pe.InputError, match=fragment):
        load_study(write(tmp_path, POINTS + extra))


@pytest.mark.parametrize(
    ("robot", "fragment"),
    [
        ("task = 5", "robot.task: expected a list"),
        ("locked_joints = 5", "robot.locked_joints: expected a list of strings"),
        ("tip = 5", "robot.tip: expected a string"),
        ("payload = { mass = 1, inertia = [[1, 0], [0, 1]] }", "robot.payload.inertia"),
        ("payload = { mass = 1, com = [0, 0] }", "robot.payload.com"),
    ],
)
def test_robot_values_of_the_wrong_type(tmp_path, robot, fragment):
    text = f'[robot]\nlibrary = "panda"\n{robot}\n[random]\ncount = 2\n'
    with pytest.raises(pe.InputError, match=fragment):
        load_study(write(tmp_path, text))


@pytest.mark.parametrize(
    "text",
    ["(-8)**0.5", "sqrt(-1)", "1e400", "(" * 500 + "1" + ")" * 500, "1+" * 150 + "1", 10**400],
)
def test_expressions_that_are_not_real_numbers(text):
    with pytest.raises(pe.InputError, match="x: expected"):
        evaluate("x", text)


# --- API arguments ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "fragment"),
    [
        (lambda: pe.Dynamics([[1.0, 2.0], [3.0]], np.eye(2), [0, 0]), "J: expected"),
        (lambda: pe.Dynamics(np.ones((2, 2)) * 1j, np.eye(2), [0, 0]), "complex values"),
        (lambda: pe.analyze(ARM.dynamics([0.1, 0.2, 0.3]), [1, 1, 1j]), "complex values"),
        (lambda: ARM.dynamics(np.array([0.1, 0.2, 0.3]) + 0j), "complex values"),
        (
            lambda: pe.analyze(ARM.dynamics([0.1, 0.2, 0.3]), ARM.tau_max, rank_rtol="abc"),
            "rank_rtol: expected a relative tolerance",
        ),
        (lambda: pe.sweep(ARM, np.zeros((0, 3))), "at least one configuration"),
        (lambda: pe.grid(0.0, (0.0, 1.0, 5.0), 0.0), "q2 num: expected an integer"),
        (lambda: pe.grid(0.0, (0.0, 1.0), 0.0), "explicit values as a list"),
        (lambda: pe.grid(0.0, [], 0.0), "at least one value"),
        (lambda: pe.random_configurations(3, [0.0], [1.0], seed=-1), "seed: expected"),
        (  # one limit near zero: the classic ellipsoid's axis is beyond floating point
            lambda: pe.compare(pe.analyze(ARM.dynamics([0.3, 0.6, 0.9]), [1e-300, 1e3, 1e3])),
            "dyn or tau_max: .* yoshikawa ellipsoid",
        ),
    ],
)
def test_api_refusals_are_the_packages(call, fragment):
    with pytest.raises(pe.InputError, match=fragment):
        call()


def test_grid_num_may_be_a_numpy_integer():
    expected = pe.grid(0.0, (0.0, 1.0, 5), 0.0).rows(0, 5)
    np.testing.assert_array_equal(pe.grid(0.0, (0.0, 1.0, np.int64(5)), 0.0).rows(0, 5), expected)


def test_out_pointing_at_a_file(tmp_path):
    file = tmp_path / "file.txt"
    file.write_text("")
    with pytest.raises(pe.InputError, match="out: expected a folder"):
        pe.sweep(ARM, [[0.1, 0.2, 0.3]], out=file)
    with pytest.raises(pe.InputError, match="out: expected a folder"):
        run_study(load_study(write(tmp_path, POINTS)), file)


def test_a_one_joint_urdf_equals_the_planar_arm(tmp_path):
    arm = pe.PlanarArm([1.0], [2.0])
    urdf = tmp_path / "one.urdf"
    urdf.write_text(planar_urdf(arm))
    robot = pe.UrdfRobot(urdf, tip="tip", task="planar", gravity=[0, -9.81, 0])
    expected = arm.dynamics([0.3])
    dyn = robot.dynamics([0.3])
    for a, b in [(dyn.J, expected.J), (dyn.B, expected.B), (dyn.g, expected.g)]:
        np.testing.assert_allclose(a, b, atol=1e-12)
    assert pe.sweep(robot, [[0.1], [0.2]], [5.0]).shape[0] == 2


def test_a_dead_scheduler_is_an_input_error(monkeypatch):
    monkeypatch.setattr(sys.modules["polyell.studies.sweep"], "CONNECT_TIMEOUT", "1s")
    with pytest.raises(pe.InputError, match="scheduler: expected the address of a running"):
        pe.sweep(ARM, [[0.1, 0.2, 0.3]], scheduler="tcp://127.0.0.1:1")


def test_a_scheduler_for_a_points_study_is_refused(tmp_path):
    with pytest.raises(pe.InputError, match="no scheduler for a study of points"):
        run_study(load_study(write(tmp_path, POINTS)), tmp_path / "o", scheduler="processes")


@pytest.mark.parametrize(
    "argv",
    [[], ["analyze", "--bogus"], ["analyze", "--q"], ["study"], ["frobnicate"]],
)
def test_command_line_usage_errors_are_one_line(argv):
    run = subprocess.run(
        [sys.executable, "-m", "polyell.cli", *argv], capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("polyell: error: "), run.stderr


# --- seeded fuzz ---------------------------------------------------------------------------

GARBAGE = [
    -1,
    0,
    1,
    2**70,
    -(2**63),
    1e308,
    -1e-320,
    math.nan,
    math.inf,
    True,
    "x",
    "",
    "../../x",
    "a" * 300,
    "pi/0",
    "(-8)**0.5",
    [],
    [[]],
    [1, "x"],
    [[1, 2], [3]],
    {},
    {"a": 1},
    [0.1, 0.2],
    [0.1, 0.2, 0.3, 0.4],
]


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if math.isinf(value) else repr(value))
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + "}"


BASE = {
    "title": '"t"',
    "robot.library": '"chiacchio2000"',
    "robot.tau_max": "[100, 30, 4]",
    "grid.q1": "0.3",
    "grid.q2": "{ start = -1, stop = 1, num = 3 }",
    "grid.q3": "[0.1]",
    "compare.directions": "8",
    "compare.mvie": "false",
    "compare.samples": "64",
    "compare.seed": "0",
    "compare.chunk": "4",
    "output.formats": '["png"]',
    "output.dpi": "20",
    "output.histograms": '["coverage"]',
}


def study_text(entries: dict[str, str]) -> str:
    tables: dict[str, list[str]] = {}
    top = []
    for key, value in entries.items():
        if "." in key:
            table, name = key.split(".", 1)
            tables.setdefault(table, []).append(f"{name} = {value}")
        else:
            top.append(f"{key} = {value}")
    return "\n".join(top + [f"[{t}]\n" + "\n".join(lines) for t, lines in tables.items()]) + "\n"


def test_fuzz_study_files(tmp_path):
    """300 seeded single-key mutations of a valid grid study: loaded, or an InputError."""
    rng = np.random.default_rng(2026)
    keys = [*BASE, "grid.q3", "random.count", "points", "compare.bogus"]
    outcomes = {"loaded": 0, "refused": 0}
    for case in range(300):
        entries = dict(BASE)
        key = keys[rng.integers(len(keys))]
        garbage = GARBAGE[rng.integers(len(GARBAGE))]
        entries[key] = toml_value(garbage)
        if key.startswith("grid.q3") and rng.random() < 0.5:
            entries[key] = toml_value({"start": 0, "stop": 1, "num": garbage})
        path = tmp_path / f"fuzz{case}.toml"
        path.write_text(study_text(entries))
        try:
            spec = load_study(path)
        except pe.InputError:
            outcomes["refused"] += 1
            continue
        except Exception as exn:
            raise AssertionError(f"{key} = {entries[key]}: {exn!r}") from exn
        outcomes["loaded"] += 1
        assert len(spec.configurations()) <= 10_000_000
    assert outcomes["loaded"] > 0 and outcomes["refused"] > 100, outcomes


def test_fuzz_api(tmp_path):
    """400 seeded calls with one garbage argument each: a result, or a PolyellError."""
    rng = np.random.default_rng(15)
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    good = {"q": [0.1, 0.2, 0.3], "tau": [100.0, 30.0, 4.0], "t": [1.0, 0.0], "x": [1.0, -10.0]}
    calls = [
        lambda v: pe.analyze(ARM.dynamics(v), good["tau"]),
        lambda v: pe.analyze(ARM.dynamics(good["q"]), v),
        lambda v: pe.analyze(ARM.dynamics(good["q"]), good["tau"], v),
        lambda v: pe.analyze(ARM.dynamics(good["q"]), good["tau"], rank_rtol=v),
        lambda v: pe.analyze(ARM.dynamics(good["q"]), good["tau"], affine_rtol=v),
        lambda v: pe.Dynamics(v, np.eye(3), [0, 0, 0]),
        lambda v: pe.Dynamics(np.ones((2, 3)), v, [0, 0, 0]),
        lambda v: analysis.polytope.limits(v),
        lambda v: analysis.polytope.contains(v),
        lambda v: analysis.ellipsoid("chiacchio").limits(v),
        lambda v: analysis.ellipsoid(v),
        lambda v: analysis.inverse(v),
        lambda v: pe.compare(analysis, v, mvie=False),
        lambda v: pe.grid(v, 0.0, 0.0),
        lambda v: pe.grid(0.0, (0.0, 1.0, v), 0.0),
        lambda v: pe.random_configurations(v, [0.0], [1.0]),
        lambda v: pe.sweep(ARM, [[0.1, 0.2, 0.3]], chunk=v),
        lambda v: pe.sweep(ARM, [[0.1, 0.2, 0.3]], directions=v),
        lambda v: pe.Polytope(v, [0.0, 0.0]),
        lambda v: pe.Ellipsoid([0.0, 0.0], v, [1.0, 1.0]),
    ]
    pool = [*GARBAGE, np.array([1 + 1j, 0]), np.zeros((0, 3)), None, object()]
    for _ in range(400):
        call = calls[rng.integers(len(calls))]
        value = pool[rng.integers(len(pool))]
        try:
            call(value)
        except pe.PolyellError:
            pass
        except Exception as exn:
            raise AssertionError(f"call {calls.index(call)} with {value!r}: {exn!r}") from exn


def test_fuzz_candidates(tmp_path):
    """200 seeded mutations of a [[candidates]] table: a comparison, or a PolyellError."""
    rng = np.random.default_rng(12)
    good = {"name": '"w"', "weighting": "[1, 1, 4]", "core": "[[1e-3, 0], [0, 2e-3]]"}
    extra = [[1, 0, 0], [[1, 0], [0, -1]], [[1, 2], [2, 1]], [[1, 0], [0, 1], [0, 0]], "w w", "x1"]
    outcomes = {"scored": 0, "refused": 0}
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    for case in range(200):
        table = {"name": good["name"]}
        table |= {"weighting": good["weighting"]} if rng.random() < 0.5 else {"core": good["core"]}
        key = ["name", "weighting", "core", "center"][rng.integers(4)]
        pool = GARBAGE + extra
        table[key] = toml_value(pool[rng.integers(len(pool))])
        path = tmp_path / f"c{case}.toml"
        body = "\n".join(f"{k} = {v}" for k, v in table.items())
        path.write_text(POINTS + "[[candidates]]\n" + body + "\n")
        try:
            spec = load_study(path)
            pe.compare(analysis, 8, mvie=False, outer=False, candidates=spec.candidates)
        except pe.PolyellError:
            outcomes["refused"] += 1
            continue
        except Exception as exn:
            raise AssertionError(f"{key} = {table[key]}: {exn!r}") from exn
        outcomes["scored"] += 1
    assert outcomes["scored"] > 0 and outcomes["refused"] > 50, outcomes
