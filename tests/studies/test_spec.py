from __future__ import annotations

import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

import polyell as pe
from polyell.studies import load_robot_file, load_study
from reference import PAPER_ARM, planar_urdf

REPO = Path(__file__).resolve().parents[2]


def write(tmp_path: Path, text: str, name: str = "study.toml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


POINTS = """
    title = "t"
    [robot]
    library = "chiacchio2000"
    [[points]]
    name = "a"
    q = ["pi/2", "-pi/2", "-pi/2"]
"""


def test_the_shipped_studies_parse():
    paper = load_study(REPO / "studies" / "chiacchio2000.toml")
    assert [p.table.name for p in paper.points] == ["redundant", "singular"]
    np.testing.assert_allclose(paper.points[1].direction, [-0.5, np.sqrt(3) / 2])
    np.testing.assert_allclose(paper.robot.tau_max, [100, 30, 4])
    sweep = load_study(REPO / "studies" / "planar3r_sweep.toml")
    assert sweep.grid and sweep.configurations().shape == (61 * 61, 3)
    assert sweep.file.compare.mvie and "chiacchio_mvie_ratio" in sweep.file.output.maps
    path = load_study(REPO / "studies" / "planar3r_path.toml")
    assert path.trajectory is not None and path.trajectory.qd is not None
    assert len(path.trajectory) == 81 and path.file.series


def test_planar_robot_table_and_expressions(tmp_path):
    path = write(
        tmp_path,
        """
        [robot]
        planar = { lengths = [1, 1], masses = [1, 1], gravity = 0 }
        tau_max = [2, "sqrt(4)"]
        tau_min = [-1, -3]
        [grid]
        q1 = 0
        q2 = { start = 0, stop = "pi/2", num = 3 }
        """,
    )
    spec = load_study(path)
    assert spec.robot.model.gravity == 0.0
    np.testing.assert_allclose(spec.robot.tau_min, [-1, -3])
    np.testing.assert_allclose(spec.configurations()[:, 1], [0, np.pi / 4, np.pi / 2])


def test_robot_file(tmp_path):
    path = write(tmp_path, 'library = "chiacchio2000"\ntau_max = [10, 10, 10]\n', "r.toml")
    robot = load_robot_file(path)
    np.testing.assert_allclose(robot.tau_max, 10.0)


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        (POINTS + "[outputs]\n", "keys among ['title', 'description', 'robot'"),
        (POINTS.replace("library", "libary"), "unknown key(s) ['libary']"),
        (
            POINTS.replace('"chiacchio2000"', '"kuka"'),
            "robot.library: expected one of ['chiacchio2000',",
        ),
        (POINTS.replace('"-pi/2"]', '"-pi/2", 0]'), "points[0].q: expected 3 joint angles"),
        (POINTS.replace('"pi/2",', '"pi/two",'), "points[0].q[0]: expected a number"),
        (POINTS + "[compare]\ndirection = 3\n", "unknown key(s) ['direction']"),
        (POINTS + "[output]\nformats = ['jpg']\n", "output.formats[0]: expected one of"),
        (
            POINTS + "[output]\nmaps = ['chiacchio_coverage']\n",
            "varying joints (a map is over their plane), got a [points] study. Fix: drop maps",
        ),
        (POINTS + "[output]\nmaps = ['coverage']\n", "output.maps: expected names"),
        (
            POINTS + "[grid]\nq1 = 0\n",
            "exactly one of [[points]], [grid], [random], [trajectory] and [posture]",
        ),
        ("[robot]\nplanar = { lengths = [1] }\n[grid]\nq1 = 0\n", "a 'masses' list"),
        ("[robot]\nplanar = { lengths = [1], masses = [1] }\n[grid]\nq1 = 0\n", "torque limits"),
        ("[robot]\nlibrary = 'chiacchio2000'\n[grid]\nq1 = 0\nq2 = 0\n", "for every joint"),
        ("title = ", "valid TOML"),
    ],
)
def test_bad_study_files(tmp_path, text, fragment):
    with pytest.raises(pe.InputError) as info:
        load_study(write(tmp_path, text))
    assert fragment in str(info.value)


def test_missing_file():
    with pytest.raises(pe.InputError, match="existing TOML file"):
        load_study("no/such/study.toml")


def test_urdf_robot_table_relative_to_the_study(tmp_path):
    (tmp_path / "arm.urdf").write_text(planar_urdf(PAPER_ARM))
    path = write(
        tmp_path,
        """
        [robot]
        urdf = "arm.urdf"
        tip = "tip"
        task = "planar"
        gravity = [0, -9.81, 0]
        payload = { mass = 0.5 }
        tau_max = [100, 30, 4]
        [random]
        count = 4
        low = [0, 0, 0]
        high = [1, 1, 1]
        """,
    )
    spec = load_study(path)
    assert spec.robot.model.m == 2 and spec.configurations().max() <= 1


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        ("[random]\ncount = 0\n", "random.count: expected an integer from 1 to 10,000,000"),
        ("[random]\ncount = 3\nlow = [0, 0]\n", "low <= high with 3 entries"),
        ('[random]\ncount = 3\n[output]\nhistograms = ["cover"]\n', "output.histograms"),
    ],
)
def test_bad_random_studies(tmp_path, extra, fragment):
    text = '[robot]\nlibrary = "chiacchio2000"\n' + extra
    with pytest.raises(pe.InputError) as info:
        load_study(write(tmp_path, text))
    assert fragment in str(info.value)


def test_urdf_options_are_refused_for_a_planar_arm(tmp_path):
    text = (
        '[robot]\nplanar = { lengths = [1], masses = [1] }\ntip = "x"\ntau_max = [1]\n'
        "[random]\ncount = 1\n"
    )
    with pytest.raises(pe.InputError, match="no URDF options for a planar arm"):
        load_study(write(tmp_path, text))


@pytest.mark.parametrize("load", [load_study, load_robot_file])
def test_files_that_are_not_toml_text_are_refused_with_their_name(tmp_path, load):
    cases = {
        "a folder": (tmp_path, "a folder"),
        "non-UTF-8": (tmp_path / "latin1.toml", "byte 0xe9 at offset 9 is not UTF-8"),
        "deep": (tmp_path / "deep.toml", "nested deeper than the parser can follow"),
        "a name too long": (tmp_path / ("x" * 300 + ".toml"), "File name too long"),
        "not a path": (5, "got int"),
    }
    (tmp_path / "latin1.toml").write_bytes('title = "\u00e9"\n'.encode("latin-1"))
    (tmp_path / "deep.toml").write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    for path, fragment in cases.values():
        with pytest.raises(pe.InputError) as info:
            load(path)
        assert str(info.value).startswith("path: expected") and fragment in str(info.value)


def test_nesting_the_parser_follows_is_refused_by_the_keys_checks(tmp_path):
    nested = "[" * 50 + "1" + "]" * 50
    with pytest.raises(pe.InputError, match=r"points\[0\]\.q\[0\]: expected a number"):
        load_study(write(tmp_path, POINTS.replace('["pi/2", "-pi/2", "-pi/2"]', nested)))


def test_random_bounds_of_1e308_are_sampled_within_them(tmp_path):
    """high - low overflows to inf: the draws are made in the halved box, then doubled."""
    path = write(
        tmp_path,
        """
        [robot]
        library = "chiacchio2000"
        [random]
        count = 1000
        low = [-1e308, -1.7976931348623157e308, 0]
        high = [1e308, 1.7976931348623157e308, 1]
        """,
    )
    q = load_study(path).configurations()
    assert np.all(np.isfinite(q)) and np.all(np.abs(q[:, :2]) <= [1e308, np.finfo(float).max])
    assert np.all((q[:, 2] >= 0) & (q[:, 2] <= 1))
    assert np.all(q[:, :2] < 0, axis=0).sum() == 0 and np.all(q[:, :2] > 0, axis=0).sum() == 0


def test_payload_and_robot_tables_of_a_wrong_type(tmp_path):
    base = '[robot]\nlibrary = "panda"\n{extra}\n[random]\ncount = 1\n'
    for extra, fragment in (
        ("payload = 5", "robot.payload: expected a table"),
        ("payload = { mass = [1] }", "robot.payload.mass: expected a number"),
        ('payload = { mass = 1, com = "x" }', "robot.payload.com: expected a list"),
    ):
        with pytest.raises(pe.InputError) as info:
            load_study(write(tmp_path, base.format(extra=extra)))
        assert fragment in str(info.value)


@pytest.mark.parametrize("where", ["title", "points[0].title"])
def test_titles_with_math_matplotlib_cannot_typeset_are_refused_at_load(tmp_path, where):
    text = POINTS.replace('title = "t"', 'title = "{top}"').replace(
        '    name = "a"', '    name = "a"\n    title = "{point}"'
    )
    good = {"top": "$\\\\alpha$ at 50% & more", "point": "cost \\\\$5"}
    assert load_study(write(tmp_path, text.format(**good))).title == "$\\alpha$ at 50% & more"
    bad = good | {"top" if where == "title" else "point": "$x^$"}
    with pytest.raises(
        pe.InputError, match=rf"^{re.escape(where)}: expected text whose \$\.\.\.\$ parts are valid"
    ):
        load_study(write(tmp_path, text.format(**bad)))


def test_the_spec_reads_the_validated_file_and_adds_only_what_needs_the_robots():
    """Issue 31, item 6: one model of a study; nothing of the file is copied into the spec."""
    import copy
    import pickle
    from dataclasses import fields

    from polyell.studies.models import CompareTable, OutputTable, StudyFile
    from polyell.studies.spec import Point, Posture, StudySpec

    keys = {*CompareTable.model_fields, *OutputTable.model_fields, "title", "description"}
    assert {field.name for field in fields(StudySpec)}.isdisjoint(keys)
    assert {field.name for field in fields(Point)}.isdisjoint({"name", "inverse_at", "title"})
    assert [field.name for field in fields(Posture)] == ["table", "direction", "label"]
    spec = load_study(REPO / "studies" / "posture_paper.toml")
    assert isinstance(spec.file, StudyFile) and spec.posture is not None
    assert spec.posture.table is spec.file.posture
    assert (spec.posture.count, spec.posture.seed) == (spec.file.posture.count, 0)  # read through
    np.testing.assert_array_equal(spec.posture.starts[0], spec.file.posture.q0)
    for copied in (copy.deepcopy(spec.posture), pickle.loads(pickle.dumps(spec.posture))):
        np.testing.assert_array_equal(copied.direction, spec.posture.direction)
        assert copied.count == spec.posture.count
    with pytest.raises(AttributeError, match="cuont"):
        spec.posture.cuont  # noqa: B018
