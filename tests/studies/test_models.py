"""The typed study format (issue 24): directions, several robots, table layout, messages.

Named directions are checked against vectors written out by hand, joint counts and task
sizes against the library robots, and every refusal against the key path it must name.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.directions import named_direction
from polyell.comparison.layout import TableLayout
from polyell.studies import load_study

ROOT = Path(__file__).resolve().parents[2]
PANDA_Q = "[0, -0.5, 0, -2, 0, 1.6, 0.8]"
UR5_Q = "[0, -1.2, 1.5, -1.9, -1.57, 0]"
PAPER = '[robot]\nlibrary = "chiacchio2000"\n'
PANDA = '[robot]\nlibrary = "panda"\n'
TWO = '[[robots]]\nname = "panda"\nlibrary = "panda"\n[[robots]]\nname = "ur5"\nlibrary = "ur5"\n'


def load(tmp_path: Path, text: str) -> pe.studies.StudySpec:
    path = tmp_path / "study.toml"
    path.write_text(textwrap.dedent(text))
    return load_study(path)


def refused(tmp_path: Path, text: str) -> str:
    with pytest.raises(pe.InputError) as info:
        load(tmp_path, text)
    return str(info.value)


def test_import_polyell_does_not_import_pydantic():
    code = (
        "import sys, polyell, polyell.studies\n"
        "assert not [m for m in sys.modules if m.startswith('pydantic')], 'before'\n"
        "polyell.studies.load_study('studies/chiacchio2000.toml')\n"
        "assert 'pydantic' in sys.modules, 'after'\n"  # the check above can fail
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr


# --- directions ---------------------------------------------------------------------------


def test_named_directions_are_the_unit_vectors_written_out():
    r = 1 / np.sqrt(2)
    xyz = ("x", "y", "z")
    expected = {
        "x": [1, 0, 0],
        "-z": [0, 0, -1],
        "+y": [0, 1, 0],
        "xy": [r, r, 0],
        "yx": [r, r, 0],
        "-xz": [-r, 0, r],  # a sign belongs to the row after it, as the labels print it
        "-x-z": [-r, 0, -r],
        "x-y": [r, -r, 0],
        "xyz": [1 / np.sqrt(3)] * 3,
    }
    for name, vector in expected.items():
        np.testing.assert_allclose(named_direction(name, xyz)[0], vector, rtol=0, atol=1e-15)
        again = named_direction(named_direction(name, xyz)[1], xyz)[0]  # the label reads back
        np.testing.assert_allclose(again, vector, rtol=0, atol=1e-15)
    angular = ("wx", "wy", "wz")
    np.testing.assert_allclose(named_direction("-wx-wz", angular)[0], [-r, 0, -r], atol=1e-15)
    np.testing.assert_allclose(named_direction("wy", angular)[0], [0, 1, 0])
    six = ("x", "y", "z", "wx", "wy", "wz")
    np.testing.assert_allclose(named_direction("xwx", six)[0], [r, 0, 0, r, 0, 0], atol=1e-15)
    for bad in ("xx", "q", "-", "zw", ""):
        with pytest.raises(pe.InputError, match="direction: expected a direction named"):
            named_direction(bad, xyz)


@pytest.mark.parametrize(
    ("robot", "q", "rows"),
    [
        (PAPER, "[0.1, 0.2, 0.3]", ("x", "y")),
        (PANDA, PANDA_Q, ("x", "y", "z")),
        (PANDA + 'task = "angular"\n', PANDA_Q, ("wx", "wy", "wz")),
        (PANDA + 'task = ["x", "z"]\n', PANDA_Q, ("x", "z")),
        (
            PANDA + 'task = ["x", "y", "z", "wx", "wy", "wz"]\nweights = [1, 1, 1, 1, 1, 1]\n',
            PANDA_Q,
            ("x", "y", "z", "wx", "wy", "wz"),
        ),
    ],
)
def test_the_default_directions_are_the_tasks_axes_whatever_its_size(tmp_path, robot, q, rows):
    spec = load(tmp_path, f'{robot}[[points]]\nname = "p"\nq = {q}\n')
    (point,) = spec.points
    assert point.labels == rows
    np.testing.assert_array_equal(point.directions, np.eye(len(rows)))
    # and named ones resolve on the same rows
    named = load(
        tmp_path, f'{robot}[[points]]\nname = "p"\nq = {q}\ndirections = ["-{rows[-1]}"]\n'
    )
    np.testing.assert_array_equal(named.points[0].directions, -np.eye(len(rows))[-1:])


def test_directions_mix_names_and_vectors_with_expressions(tmp_path):
    spec = load(
        tmp_path,
        PANDA + f'[[points]]\nname = "p"\nq = {PANDA_Q}\n'
        'directions = ["z", "-xz", ["sqrt(1/2)", "-sqrt(1/2)", 0]]\n',
    )
    point = spec.points[0]
    r = 1 / np.sqrt(2)
    np.testing.assert_allclose(point.directions, [[0, 0, 1], [-r, 0, r], [r, -r, 0]], atol=1e-15)
    assert point.labels == ("z", "-x+z", "(0.7071, -0.7071, 0)")
    np.testing.assert_array_equal(point.direction, [0, 0, 1])  # the first


def test_the_older_direction_key_is_a_list_of_one(tmp_path):
    spec = load(
        tmp_path,
        PAPER + '[[points]]\nname = "p"\nq = [0, 0, 0]\ndirection = ["-1/2", "sqrt(3)/2"]\n',
    )
    np.testing.assert_allclose(spec.points[0].directions, [[-0.5, np.sqrt(3) / 2]])
    message = refused(
        tmp_path,
        PAPER + '[[points]]\nname = "p"\nq = [0, 0, 0]\ndirection = [1, 0]\ndirections = ["x"]\n',
    )
    assert message.startswith("points[0]: expected one of 'directions' (a list) and 'direction'")


@pytest.mark.parametrize(
    ("directions", "start"),
    [
        ('["x", [1, 0]]', "points[2].directions[1]: expected a unit vector of 3 numbers"),
        ("[[1, 1, 0]]", "points[2].directions[0]: expected a unit vector (norm within"),
        ('["x", "q"]', "points[2].directions[1]: expected a direction named after the task rows"),
        ('["xx"]', "points[2].directions[0]: expected a direction named"),
        ('"x"', "points[2].directions: expected a non-empty list of directions"),
        ("[]", "points[2].directions: expected a non-empty list of directions"),
        ('["x", "x"]', "points[2].directions: expected distinct directions"),
        ('["x", 5]', "points[2].directions[1]: expected a direction named by task rows"),
        ('["x", ["pi/0", 0, 0]]', "points[2].directions[1][0]: expected a number"),
        ('["x y"]', "points[2].directions[0]: expected a direction named by task rows"),
    ],
)
def test_bad_directions_are_refused_at_load_naming_the_key(tmp_path, directions, start):
    points = "".join(f'[[points]]\nname = "p{i}"\nq = {PANDA_Q}\n' for i in range(3))
    message = refused(tmp_path, PANDA + points + f"directions = {directions}\n")
    assert message.startswith(start), message


def test_a_2d_direction_on_a_3d_task_leaves_no_output_folder(tmp_path, capsys):
    """Issue 24: the documented default [1, 0] failed at run time, after the folder existed."""
    from polyell.cli import main

    path = tmp_path / "s.toml"
    path.write_text(PANDA + f'[[points]]\nname = "p"\nq = {PANDA_Q}\ndirection = [1, 0]\n')
    assert main(["study", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("polyell: error: points[0].direction: expected a unit vector of 3")
    assert len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


# --- several robots -----------------------------------------------------------------------


def test_points_of_two_robots_with_q_per_robot(tmp_path):
    spec = load(
        tmp_path,
        TWO + f'[[points]]\nname = "home"\nq = {{ panda = {PANDA_Q}, ur5 = {UR5_Q} }}\n'
        f'[[points]]\nname = "up"\nq = {{ ur5 = {UR5_Q}, panda = {PANDA_Q} }}\n'
        'directions = ["z"]\n',
    )
    assert [r.name for r in spec.robots] == ["panda", "ur5"] and spec.by_robot
    assert [p.label for p in spec.points] == ["panda/home", "ur5/home", "panda/up", "ur5/up"]
    assert [p.stem for p in spec.points] == ["panda.home", "ur5.home", "panda.up", "ur5.up"]
    assert [p.q.size for p in spec.points] == [7, 6, 7, 6]
    np.testing.assert_allclose(spec.points[1].q, [0, -1.2, 1.5, -1.9, -1.57, 0])
    with pytest.raises(pe.InputError, match=r"spec\.robot: expected a study of one robot"):
        spec.robot  # noqa: B018


def test_random_configurations_of_each_robot_lie_within_its_own_limits(tmp_path):
    spec = load(tmp_path, TWO + "[random]\ncount = 50\nseed = 4\n")
    for index, robot in enumerate(spec.robots):
        q = spec.configurations(index)
        low, high = robot.model.position_limits
        assert q.shape == (50, robot.model.n) and np.all((q >= low) & (q <= high))


@pytest.mark.parametrize(
    ("text", "start"),
    [
        (PAPER + TWO + "[random]\ncount = 1\n", "study.toml: expected one [robot] table, or"),
        ("[random]\ncount = 1\n", "study.toml: expected one [robot] table"),
        (
            TWO.replace('name = "ur5"\n', "") + "[random]\ncount = 1\n",
            "robots[1]: expected a 'name'",
        ),
        (
            TWO.replace('"ur5"', '"panda"', 1) + "[random]\ncount = 1\n",
            "robots: expected names whose output files differ",
        ),
        (TWO.replace('"ur5"', '"ur.5"', 1) + "[random]\ncount = 1\n", "robots[1].name: expected"),
        (
            TWO.replace("libary", "x").replace('library = "ur5"', 'libary = "ur5"'),
            "robots[1]: expected keys among",
        ),
        (TWO + "[grid]\nq1 = 0\n", "grid: expected robots with the same number of joints"),
        (
            TWO + "[random]\ncount = 1\nlow = [0, 0, 0, 0, 0, 0]\n",
            "random: expected robots with the same",
        ),
        (TWO + '[trajectory]\nfile = "p.csv"\n', "trajectory: expected one robot"),
        (
            TWO + f'[[points]]\nname = "p"\nq = {PANDA_Q}\n',
            "points[0].q: expected 6 joint angles (robot 'ur5')",
        ),
        (
            TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q}, ur6 = {UR5_Q} }}\n',
            "points[0].q: expected one list of joint angles per robot",
        ),
        (
            TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q} }}\n',
            "points[0].q: expected one list",
        ),
        (
            TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q}, ur5 = [0, 0] }}\n',
            "points[0].q.ur5: expected 6 joint angles",
        ),
        (
            PANDA + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q} }}\n',
            "points[0].q: expected a list of 7 joint angles",
        ),
        (
            TWO.replace('library = "ur5"', 'library = "ur5"\ntask = "angular"')
            + "[random]\ncount = 1\n",
            "robots: expected tasks of one unit",
        ),
        (
            TWO.replace('library = "ur5"', 'library = "ur5"\ntau_max = [1, 2]')
            + "[random]\ncount = 1\n",
            "robots[1].tau_max: expected",
        ),
    ],
)
def test_bad_robot_combinations_are_refused_naming_the_key(tmp_path, text, start):
    message = refused(tmp_path, text)
    assert message.startswith(start), message


def test_a_misspelled_robot_in_a_q_table_gets_a_suggestion(tmp_path):
    message = refused(
        tmp_path, TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q}, ur55 = {UR5_Q} }}\n'
    )
    assert "unknown robot(s) ['ur55']" in message and "did you mean 'ur5' for 'ur55'?" in message


def test_joint_counts_differ_so_a_shared_q_list_says_how_to_give_one_per_robot(tmp_path):
    message = refused(tmp_path, TWO + f'[[points]]\nname = "p"\nq = {PANDA_Q}\n')
    assert "Fix: give q per robot: q = { panda = [...], ur5 = [...] }." in message


# --- messages -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "start", "suggestion"),
    [
        (
            PAPER + '[[points]]\nname = "p"\nq = [0, 0, 0]\n[ouput]\n',
            "study.toml: expected keys among",
            "'output' for 'ouput'",
        ),
        (
            PAPER.replace("library", "libary") + "[random]\ncount = 1\n",
            "robot: expected keys among",
            "'library' for 'libary'",
        ),
        (
            PAPER + '[[points]]\nname = "p"\nq = [0, 0, 0]\ndirectons = ["x"]\n',
            "points[0]: expected keys",
            "'directions' for 'directons'",
        ),
        (
            PAPER + "[random]\ncount = 1\n[compare]\nsample = 3\n",
            "compare: expected keys among",
            "'samples' for 'sample'",
        ),
        (
            PAPER.replace("chiacchio2000", "pandas") + "[random]\ncount = 1\n",
            "robot.library: expected one of",
            "'panda' for 'pandas'",
        ),
        (
            PAPER + "[random]\ncount = 1\n[output]\nformats = ['hmtl']\n",
            "output.formats[0]: expected one of",
            "'html' for 'hmtl'",
        ),
        (
            PAPER + "[grid]\nq1 = 0\nq2 = 0\nq33 = 0\n",
            "grid: expected keys among ['q1', 'q2', 'q3']",
            "'q3' for 'q33'",
        ),
        (
            PAPER + '[[points]]\nname = "p"\nq = [0, 0, 0]\ninverse_at = "high"\n',
            "points[0].inverse_at: expected 'lo' or 'hi'",
            "'hi' for 'high'",
        ),
    ],
)
def test_misspellings_get_did_you_mean(tmp_path, text, start, suggestion):
    message = refused(tmp_path, text)
    assert message.startswith(start), message
    assert f"Fix: did you mean {suggestion}?" in message


def test_a_missing_key_names_its_table_and_shows_an_example(tmp_path):
    message = refused(tmp_path, PAPER + '[[points]]\nname = "p"\n')
    assert message == (
        "points[0]: expected a 'q' list of numbers or expressions, or a table of them per "
        'robot, got no such key. Fix: add q = ["pi/2", "-pi/2", "-pi/2"].'
    )
    message = refused(tmp_path, PAPER + "[grid]\nq1 = 0\nq2 = 0\nq3 = { start = 0, stop = 1 }\n")
    assert message.startswith(
        "grid.q3: expected a 'num' integer, got no such key. Fix: add num = 61"
    )


# --- table layout ---------------------------------------------------------------------------

LAYOUT = (
    PAPER
    + '[[points]]\nname = "p"\nq = [0.1, 0.2, 0.3]\n'
    + '[[candidates]]\nname = "disc"\ncore = [1e-3, 1e-3]\n[output]\n'
)


def test_the_output_layout_keys_reach_the_spec(tmp_path):
    assert load(tmp_path, LAYOUT).file.output.layout == TableLayout()
    spec = load(
        tmp_path,
        LAYOUT + 'sets = ["polytope", "disc", "chiacchio"]\nscores = ["coverage"]\n'
        'transpose = true\nsplit = "posture"\ndigits = 17\npercent = false\n',
    )
    assert spec.file.output.layout == TableLayout(
        sets=("polytope", "disc", "chiacchio"),
        scores=("coverage",),
        transpose=True,
        split="posture",
        digits=17,
        percent=False,
    )


@pytest.mark.parametrize(
    ("extra", "start"),
    [
        ("digits = 0", "output.digits: expected an integer from 1 to 17, got int 0"),
        ("digits = 18", "output.digits: expected an integer from 1 to 17"),
        ("digits = 3.0", "output.digits: expected an integer from 1 to 17, got float"),
        ('sets = ["chiachio"]', "output.sets: expected sets among ['polytope'"),
        ('sets = ["ghost"]', "output.sets: expected sets among"),
        ("sets = []", "output.sets: expected a non-empty list"),
        ('sets = ["mvie", "mvie"]', "output.sets: expected distinct names"),
        ('scores = ["cover"]', "output.scores[0]: expected one of"),
        ('split = "postures"', "output.split: expected 'posture' or 'combined'"),
        ('transpose = "yes"', "output.transpose: expected true or false"),
        ("percent = 1", "output.percent: expected true or false"),
    ],
)
def test_bad_layout_keys_are_refused(tmp_path, extra, start):
    message = refused(tmp_path, LAYOUT + extra + "\n")
    assert message.startswith(start), message
    if "chiachio" in extra:
        assert "did you mean 'chiacchio' for 'chiachio'?" in message


def test_every_shipped_study_loads_with_the_default_layout():
    # (the paper's studies name their sets by the paper's preset, labels = "chiacchio2000")
    for path in sorted((ROOT / "studies").glob("*.toml")):
        layout = load_study(path).file.output.layout
        assert layout.labels in (None, "chiacchio2000"), path.name
        assert replace(layout, labels=None) == TableLayout(), path.name


@pytest.mark.parametrize(
    ("output", "fragment"),
    [
        ('histograms = ["mvie_ratio"]', "output.histograms: expected no score of the MVIE"),
        ('histograms = ["outer_ratio"]', "output.histograms: expected no score of the outer"),
    ],
)
def test_a_score_of_an_optimum_not_computed_is_refused_at_load(tmp_path, output, fragment):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 4\nseed = 1\n'
        f"[compare]\nmvie = false\nouter = false\n[output]\n{output}\n"
    )
    with pytest.raises(pe.InputError) as info:
        pe.studies.load_study(spec)
    assert str(info.value).startswith(fragment), str(info.value)


# --- joint velocity limits and torque-speed curves (issue 21, items 1 and 5) -----------------

POINT = '[[points]]\nname = "p"\nq = [0.1, 0.2, 0.3]\n'
LINEAR = "torque_speed = { tau_stall = [150, 40, 6], qd_no_load = [4, 5, 8] }\n"
PLANAR = "[robot]\nplanar = { lengths = [1, 0.8, 0.5], masses = [4, 2, 0.6] }\n"


def test_velocity_limits_and_linear_curves_reach_the_robot(tmp_path):
    spec = load(tmp_path, PAPER + "qd_max = [3, 3, 5]\nqd_min = [-3, -2, 0]\n" + LINEAR + POINT)
    robot = spec.robot
    assert robot.model.torque_speed == pe.TorqueSpeed.linear([150, 40, 6], [4, 5, 8])
    np.testing.assert_array_equal(robot.model.qd_max, [3, 3, 5])
    np.testing.assert_array_equal(robot.velocity_limits()[1], [-3, -2, 0])
    np.testing.assert_array_equal(robot.tau_max, [100, 30, 4])  # the library's, kept
    qd = np.array([[2.0, -1.0, 0.0], [-3.0, 6.0, 1.0]])
    expected = robot.model.torque_speed.limits(qd, [100, 30, 4])
    for got, want in zip(robot.torque_limits(qd), expected, strict=True):
        np.testing.assert_array_equal(got, want)
    # joint 0 forward at 2 rad/s: 150 (1 - 2/4) = 75 < 100; joint 1 backward at 1: 32 > 30
    np.testing.assert_allclose(robot.torque_limits(qd[0])[0], [75.0, 30.0, 4.0], rtol=1e-15)


def test_tabulated_curves_shared_or_per_joint_speeds(tmp_path):
    torques = "[[150, 120, 0], [40, 30, 0], [6, 5, 0]]"
    shared = load(
        tmp_path, PAPER + f"torque_speed = {{ speeds = [0, 2, 4], torques = {torques} }}\n" + POINT
    )
    assert shared.robot.model.torque_speed == pe.TorqueSpeed.table(
        [0, 2, 4], [[150, 120, 0], [40, 30, 0], [6, 5, 0]]
    )
    per_joint = load(
        tmp_path,
        PAPER
        + 'torque_speed = { speeds = [[0, 2, 4], [0, 1, 3], [0, "pi", 8]], torques = '
        + torques
        + " }\n"
        + POINT,
    )
    np.testing.assert_array_equal(per_joint.robot.model.torque_speed.speeds[2], [0, np.pi, 8])


def test_curves_without_rated_limits_give_the_stall_torques(tmp_path):
    robot = load(tmp_path, PLANAR + LINEAR + POINT).robot
    np.testing.assert_array_equal(robot.tau_max, [150, 40, 6])
    np.testing.assert_array_equal(robot.tau_min, [-150, -40, -6])
    assert robot.model.qd_max is None


def test_a_urdf_robot_file_with_velocity_limits_and_curves(tmp_path):
    from polyell.studies import load_robot_file
    from reference import PAPER_ARM, planar_urdf

    (tmp_path / "arm.urdf").write_text(planar_urdf(PAPER_ARM))  # velocity="1", effort="50"
    curves = "torque_speed = { tau_stall = [150, 60, 60], qd_no_load = [4, 5, 8] }\n"
    head = 'urdf = "arm.urdf"\ntip = "tip"\ntask = "planar"\n'
    path = tmp_path / "arm.toml"
    path.write_text(head + curves)
    robot = load_robot_file(path)
    np.testing.assert_array_equal(robot.model.velocity_limits()[0], [1.0, 1.0, 1.0])
    np.testing.assert_array_equal(robot.tau_max, [50.0, 50.0, 50.0])
    path.write_text(head + "tau_max = [100, 30, 5]\nqd_max = [2, 2, 2]\n" + LINEAR)
    robot = load_robot_file(path)  # the file's tau_max, within the stall torques, replaces 50
    np.testing.assert_array_equal(robot.model.tau_max, [100, 30, 5])
    np.testing.assert_array_equal(robot.velocity_limits()[0], [2.0, 2.0, 2.0])
    path.write_text(head + LINEAR)  # effort 50 > stall 40
    with pytest.raises(pe.InputError) as info:
        load_robot_file(path)
    assert str(info.value).startswith(
        "arm.toml.tau_max: expected rated torque limits within the stall torques"
    )
    assert "got tau_max[1] = 50 N m against a stall torque of 40 N m" in str(info.value)


@pytest.mark.parametrize(
    ("text", "start"),
    [
        (
            PAPER + "torque_speed = { tau_stall = [1, 2, 3] }\n",
            "robot.torque_speed: expected either tau_stall and qd_no_load (linear derating), "
            "or speeds and torques (a table), got keys ['tau_stall']",
        ),
        (
            PAPER + "torque_speed = { tau_stall = [1], qd_no_load = [1], speeds = [0, 1] }\n",
            "robot.torque_speed: expected either tau_stall and qd_no_load",
        ),
        (PAPER + "torque_speed = {}\n", "robot.torque_speed: expected either"),
        (PAPER + "torque_speed = 5\n", "robot.torque_speed: expected a table"),
        (
            PAPER + "torque_speed = { stall = [1], no_load = [1] }\n",
            "robot.torque_speed: expected keys among ['tau_stall', 'qd_no_load', 'speeds', "
            "'torques'], got unknown key(s) ['no_load', 'stall']. Fix: did you mean",
        ),
        (
            PAPER + LINEAR.replace("40", "-40"),
            "robot.torque_speed.tau_stall: expected strictly positive values [N m], got "
            "tau_stall[1] = -40",
        ),
        (
            PAPER + LINEAR.replace("[4, 5, 8]", "[4, 5]"),
            "robot.torque_speed: expected tau_stall and qd_no_load of one length (one of each "
            "per joint), got 3 stall torques and 2 no-load speeds",
        ),
        (
            PAPER + 'torque_speed = { tau_stall = [1, "x", 3], qd_no_load = [1, 1, 1] }\n',
            "robot.torque_speed.tau_stall[1]: expected a number",
        ),
        (
            PAPER + "torque_speed = { speeds = [0, 1], torques = [1, 0] }\n",
            "robot.torque_speed.torques: expected a list of rows, one list of numbers per joint",
        ),
        (
            PAPER + "torque_speed = { speeds = [0, 1, 1], torques = [[3, 2, 0]] }\n",
            "robot.torque_speed.speeds: expected strictly increasing speeds",
        ),
        (
            PAPER + "torque_speed = { speeds = [0, 1], torques = [[3, 0], [2]] }\n",
            "robot.torque_speed.torques: expected an array of torques",
        ),
        (
            PAPER + "torque_speed = { tau_stall = [150, 40], qd_no_load = [4, 5] }\n",
            "robot.torque_speed: expected a torque-speed model of 3 joints",
        ),
        (
            PAPER + LINEAR.replace("40", "20"),
            "robot.tau_max: expected rated torque limits within the stall torques (-tau_stall "
            "<= tau_min, tau_max <= tau_stall): a drive gives at most its stall torque at rest, "
            "got tau_max[1] = 30 N m against a stall torque of 20 N m",
        ),
        (
            PLANAR + "tau_max = [100, 30, 4]\n" + LINEAR.replace("6]", "3]"),
            "robot.tau_max: expected rated torque limits within the stall torques",
        ),
        (
            PLANAR + "tau_max = [100, 30, 4]\nqd_max = [1, 0, 1]\n",
            "robot.qd_max: expected strictly positive upper joint velocities",
        ),
        (
            PAPER + "qd_max = [1, 1]\n",
            "robot.qd_max: expected an array of joint velocities [rad/s or m/s] with shape (3,)",
        ),
        (PAPER + 'qd_max = ["fast", 1, 1]\n', "robot.qd_max[0]: expected a number"),
        (
            PAPER + "qd_max = [1, 1, 1]\nqd_min = [-1, 1, -1]\n",
            "robot.qd_min: expected qd_min < qd_max for every joint [rad/s or m/s], got "
            "qd_min[1] = 1 >= qd_max[1] = 1",
        ),
        (
            PAPER + "qd_max = [1, -1, 1]\n",
            "robot.qd_max: expected strictly positive upper joint velocities [rad/s or m/s], got "
            "qd_max[1] = -1. Fix: without qd_min (it defaults to -qd_max)",
        ),
        (PAPER + "qd_min = [-1, -1, -1]\n", "robot.qd_min: expected qd_min only together"),
        (PLANAR + "tau_min = [-1, -1, -1]\n", "robot.tau_min: expected tau_min only with tau_max"),
        (
            TWO.replace('library = "ur5"', 'library = "ur5"\n' + LINEAR) + "[random]\ncount = 1\n",
            "robots[1].torque_speed: expected a torque-speed model of 6 joints",
        ),
    ],
)
def test_bad_velocity_limits_and_curves_are_refused_naming_the_key(tmp_path, text, start):
    message = refused(tmp_path, text + POINT if "[random]" not in text else text)
    assert message.startswith(start), message


def test_the_schema_knows_the_torque_speed_keys():
    import jsonschema
    import tomllib

    from polyell.studies.models import json_schema

    schema = json_schema("robot")
    for text in (
        'library = "chiacchio2000"\nqd_max = [1, 2, 3]\n' + LINEAR,
        'library = "chiacchio2000"\ntorque_speed = { speeds = [0, 1], torques = [[1, 0]] }\n',
        'library = "chiacchio2000"\ntorque_speed = { speeds = [[0, 1]], torques = [[1, 0]] }\n',
    ):
        jsonschema.validate(tomllib.loads(text), schema)
    with pytest.raises(jsonschema.ValidationError, match="stall"):
        jsonschema.validate(
            tomllib.loads('library = "chiacchio2000"\ntorque_speed = { stall = [1] }\n'), schema
        )


# --- issue 33: what the API answers, a study file answers ----------------------------------


@pytest.mark.parametrize(
    ("qd_max", "qd_min"),
    [
        ([2.0, 3.0, 4.0], [0.5, -3.0, -4.0]),
        ([2.0, 3.0, 4.0], [1.0, 0.5, 2.0]),
        ([-1.0, 3, 4], [-2.0, -3, -4]),
    ],
)
def test_a_velocity_box_the_api_takes_a_study_file_takes(tmp_path, qd_max, qd_min):
    """qd_min > 0 (a joint that must move forward) was answered by pe.analyze and refused by
    study files ("lower joint velocities of at most 0"): both take any qd_min < qd_max, and
    give the same numbers."""
    options = '[compare]\ncapacities = ["velocity"]\nmvie = false\nouter = false\n'
    text = PAPER + f"qd_max = {qd_max}\nqd_min = {qd_min}\n" + POINT + options
    spec = load(tmp_path, text + "directions = 16\nsamples = 64\n[output]\nformats = []\n")
    np.testing.assert_array_equal(spec.robot.velocity_limits()[1], qd_min)
    out = tmp_path / "out"
    pe.studies.run_study(spec, out)
    arm = pe.robots.load("chiacchio2000")
    by_api = pe.compare(
        pe.analyze(
            arm.dynamics(spec.points[0].q), capacity="velocity", qd_max=qd_max, qd_min=qd_min
        ),
        16,
        samples=64,
        mvie=False,
        outer=False,
    ).to_frame()
    import pandas as pd

    by_study = pd.read_csv(out / "scores_velocity.csv", index_col=0)
    assert list(by_study.columns) == list(by_api.columns)
    numbers = list(by_api.select_dtypes("number").columns)
    assert "volume" in numbers and "coverage" in numbers
    np.testing.assert_allclose(
        by_study[numbers].to_numpy(float), by_api[numbers].to_numpy(float), rtol=1e-12
    )
    # the robot of the API takes the same box
    robot = pe.robots.load("chiacchio2000", qd_max=qd_max, qd_min=qd_min)
    np.testing.assert_array_equal(robot.velocity_limits()[1], qd_min)


@pytest.mark.parametrize(
    ("qd_max", "qd_min", "start"),
    [
        ([1.0, 1.0, 1.0], [-1.0, 1.0, -1.0], "qd_min: expected qd_min < qd_max for every joint"),
        ([1.0, 0.0, 1.0], None, "qd_max: expected strictly positive upper joint velocities"),
    ],
)
def test_a_velocity_box_the_api_refuses_a_study_file_refuses(tmp_path, qd_max, qd_min, start):
    kin = pe.Kinematics(np.eye(2, 3))
    with pytest.raises(pe.InputError) as by_api:
        pe.analyze(kin, capacity="velocity", qd_max=qd_max, qd_min=qd_min)
    text = PAPER + f"qd_max = {qd_max}\n" + (f"qd_min = {qd_min}\n" if qd_min else "") + POINT
    message = refused(tmp_path, text)
    assert message.startswith(f"robot.{start}"), message
    assert str(by_api.value).split(":")[0] == start.split(":")[0]


TWO_KINDS = (
    '[[robots]]\nname = "arm"\nlibrary = "chiacchio2000"\n'
    '[[robots]]\nname = "panda"\nlibrary = "panda"\n'
    f'[[points]]\nname = "p"\nq = {{ arm = [0.1, 0.2, 0.3], panda = {PANDA_Q} }}\n'
)


def test_a_table_of_qd_per_robot_beside_a_planar_arm(tmp_path):
    """qd = { panda = [...] } beside a planar arm was refused ("qd for a planar arm"): a
    robot left out of the table is at rest, as a planar arm always is."""
    spec = load(tmp_path, TWO_KINDS + "qd = { panda = [0.5, 0, 0, 0, 0, 0, 0] }\n")
    by_robot = {point.robot: point for point in spec.points}
    assert by_robot["arm"].qd is None
    np.testing.assert_array_equal(by_robot["panda"].qd, [0.5, 0, 0, 0, 0, 0, 0])
    # zeros for the planar arm: at rest, the same study
    spec = load(tmp_path, TWO_KINDS + f"qd = {{ arm = [0, 0, 0], panda = {PANDA_Q} }}\n")
    assert {point.robot: point.qd is None for point in spec.points} == {"arm": True, "panda": False}


def test_a_moving_planar_arm_is_refused_saying_what_to_write(tmp_path):
    message = refused(tmp_path, TWO_KINDS + f"qd = {{ arm = [1, 0, 0], panda = {PANDA_Q} }}\n")
    assert message == (
        "points[0].qd.arm: expected a URDF robot (its Coriolis and centrifugal torques come "
        "from Pinocchio), or zero joint velocities for a planar arm (it is modelled at rest), "
        "got qd = [1.0, 0.0, 0.0]. Fix: leave 'arm' out of qd (a robot left out is at rest): "
        "qd = { panda = [...] }."
    )
    message = refused(tmp_path, PAPER + POINT + "qd = [0, 1, 0]\n")
    assert message.startswith("points[0].qd: expected a URDF robot"), message
    assert message.endswith("Fix: drop qd (or give zeros), or load a URDF robot."), message
    assert load(tmp_path, PAPER + POINT + "qd = [0, 0, 0]\n").points[0].qd is None
    # an unknown robot in the table is still refused, with the names
    message = refused(tmp_path, TWO_KINDS + "qd = { pand = [0, 0, 0, 0, 0, 0, 0] }\n")
    assert message.startswith("points[0].qd: expected lists of joint velocities by robot name"), (
        message
    )
    assert "did you mean 'panda' for 'pand'?" in message


def test_two_urdf_robots_one_of_them_left_out_of_qd_is_at_rest(tmp_path):
    spec = load(
        tmp_path,
        TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q}, ur5 = {UR5_Q} }}\n'
        "qd = { ur5 = [0.3, 0, 0, 0, 0, 0] }\n",
    )
    by_robot = {point.robot: point for point in spec.points}
    assert by_robot["panda"].qd is None and by_robot["ur5"].qd is not None
    # q still needs every robot
    message = refused(tmp_path, TWO + f'[[points]]\nname = "p"\nq = {{ panda = {PANDA_Q} }}\n')
    assert message.startswith("points[0].q: expected one list of joint angles per robot"), message


def test_output_labels_rename_the_sets_and_scores_of_every_table(tmp_path):
    spec = load(
        tmp_path,
        PAPER + POINT + '[[candidates]]\nname = "wrist"\nweighting = [1, 1, 4]\n'
        '[output]\nformats = ["png"]\ndpi = 20\n'
        'labels = { chiacchio = "DME", wrist = ["heavy wrist", "$W_4$"], coverage = "share" }\n'
        "[compare]\nmvie = false\nouter = false\ndirections = 16\nsamples = 64\n",
    )
    layout = spec.file.output.layout
    assert layout == TableLayout(
        labels={"chiacchio": "DME", "wrist": ("heavy wrist", "$W_4$"), "coverage": "share"}
    )
    out = tmp_path / "out"
    pe.studies.run_study(spec, out)
    markdown, latex = (out / "comparison.md").read_text(), (out / "comparison.tex").read_text()
    assert "DME" in markdown and "heavy wrist" in markdown and "share" in markdown
    assert "$W_4$" in latex
    assert load(
        tmp_path, PAPER + POINT + '[output]\nlabels = "chiacchio2000"\n'
    ).file.output.layout == TableLayout(labels="chiacchio2000")


@pytest.mark.parametrize(
    ("labels", "start"),
    [
        ("{ chiacchio = 3 }", "output.labels.chiacchio: expected a label: plain text, or a pair"),
        ('{ chiacchio = ["a", "$x"] }', "output.labels.chiacchio[1]: expected paired math"),
        ('{ chiachio = "x" }', "output.labels.chiachio: expected keys among the sets"),
        ('{ bogus = "x" }', "output.labels.bogus: expected a key that names a set"),
        ('"paper"', "output.labels: expected a preset among ['chiacchio2000']"),
        ("3", "output.labels: expected a table of set or score names to labels"),
    ],
)
def test_bad_output_labels_are_refused_naming_the_key(tmp_path, labels, start):
    message = refused(tmp_path, PAPER + POINT + f"[output]\nlabels = {labels}\n")
    assert message.startswith(start), message


@pytest.mark.parametrize(
    ("text", "start"),
    [
        (
            PAPER + '[random]\ncount = 2\n[output]\ncsv = "yes"\n',
            'output.csv: expected true, false or "auto"',
        ),
        (
            PAPER + POINT + "[output]\ncsv = true\n",
            "output.csv: expected a grid, random or trajectory study",
        ),
    ],
)
def test_bad_output_csv_is_refused_naming_the_key(tmp_path, text, start):
    message = refused(tmp_path, text)
    assert message.startswith(start), message


def test_the_reference_names_lists_of_numbers_apart_from_arrays_of_tables():
    """``posture.components`` is a list of lists of numbers, not an array of tables (the
    reference page said so); ``points`` is one."""
    from polyell.studies import models

    posture = models.PostureTable.model_fields["components"]
    assert models.phrase(posture.annotation, posture.metadata) == (
        "array, each item a list of numbers or expressions"
    )
    points = models.StudyFile.model_fields["points"]
    assert models.phrase(points.annotation, points.metadata) == "array of tables"
