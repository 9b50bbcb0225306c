"""A prismatic joint's position is headed in metres in the posture tables (issue 32).

No robot of ``pe.robots`` has a prismatic joint: a small URDF arm (a carriage sliding along x,
then a shoulder and an elbow about y, the task x and z: redundant) is written into
``tmp_path``.  Its posture study heads ``q1 [m]``, ``q2 [rad]``, ``q3 [rad]``; the API takes
``joint_units=`` and refuses bad ones by name.  Seeded, nothing written into the checkout.
"""

from __future__ import annotations

import importlib.util
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.interactive import interactive_map
from polyell.studies import load_study, run_study
from polyell.studies.posture_tables import (
    format_posture_table,
    joint_units,
    write_posture_tables,
)
from reference import PAPER_Q_REDUNDANT

needs_pinocchio = pytest.mark.skipif(
    importlib.util.find_spec("pinocchio") is None, reason="the robots extra (Pinocchio)"
)

SLIDER_URDF = """<?xml version="1.0"?>
<robot name="slider_arm">
  <link name="base"/>
  <link name="carriage">
    <inertial><origin xyz="0 0 0"/><mass value="2.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <link name="upper">
    <inertial><origin xyz="0 0 0.25"/><mass value="1.5"/>
      <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="fore">
    <inertial><origin xyz="0 0 0.2"/><mass value="0.8"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="tool"/>
  <joint name="slide" type="prismatic">
    <parent link="base"/><child link="carriage"/><axis xyz="1 0 0"/>
    <limit lower="-0.8" upper="0.8" effort="120" velocity="1.0"/>
  </joint>
  <joint name="shoulder" type="revolute">
    <parent link="carriage"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-3.0" upper="3.0" effort="60" velocity="2.0"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-3.0" upper="3.0" effort="30" velocity="3.0"/>
  </joint>
  <joint name="tool_joint" type="fixed">
    <parent link="fore"/><child link="tool"/><origin xyz="0 0 0.4"/>
  </joint>
</robot>
"""

STUDY = """
    title = "Slider arm"
    [robot]
    urdf = "slider.urdf"
    tip = "tool"
    task = ["x", "z"]
    [posture]
    q0 = [0.1, 0.6, 0.9]
    direction = "x"
    count = 12
    seed = 1
    [compare]
    mvie = false
    outer = false
    [output]
    formats = ["png"]
    dpi = 20
"""


def _header(markdown: str) -> list[str]:
    line = next(line for line in markdown.splitlines() if line.startswith("| set"))
    return [cell.strip() for cell in line.strip("|").split("|")]


@pytest.fixture(scope="module")
def paper_choice() -> pe.PostureChoice:
    arm = pe.robots.load("chiacchio2000")
    postures = pe.self_motion(arm, PAPER_Q_REDUNDANT, count=10, seed=0).configurations
    return pe.posture_choice(arm, postures, direction=np.array([1.0, 0.0]), mvie=False)


def test_a_planar_arms_joints_are_revolute():
    assert joint_units(pe.robots.load("chiacchio2000")) == ("rad", "rad", "rad")
    with pytest.raises(pe.InputError, match=r"^robot: expected a robot model"):
        joint_units("panda")


@needs_pinocchio
def test_a_urdf_robots_joint_units_follow_its_joint_kinds(tmp_path):
    (tmp_path / "slider.urdf").write_text(SLIDER_URDF)
    slider = pe.UrdfRobot(tmp_path / "slider.urdf", tip="tool", task=["x", "z"])
    assert joint_units(slider) == ("m", "rad", "rad")
    assert joint_units(pe.robots.load("panda")) == ("rad",) * 7  # fingers locked


@needs_pinocchio
def test_a_posture_study_heads_a_prismatic_joint_in_metres(tmp_path):
    (tmp_path / "slider.urdf").write_text(SLIDER_URDF)
    study = tmp_path / "slider.toml"
    study.write_text(textwrap.dedent(STUDY))
    out = tmp_path / "out"
    run_study(load_study(study), out)
    header = _header((out / "posture_choice.md").read_text())
    assert header[3:6] == ["q1 [m]", "q2 [rad]", "q3 [rad]"]
    assert "[rad]" not in " ".join(header[:3])
    # the CSV files keep their data columns (q1 .. q3), their values the joint positions
    values = pd.read_csv(out / "posture_values.csv", index_col="posture")
    assert list(values.columns[2:5]) == ["q1", "q2", "q3"]
    assert values["q1"].between(-0.8 - 1e-9, 0.8 + 1e-9).all()  # metres, within its limits


def test_the_api_takes_joint_units(paper_choice, tmp_path):
    table = paper_choice.table
    header = _header(format_posture_table(table, "markdown", joint_units=("m", "rad", "rad")))
    assert header[3:6] == ["q1 [m]", "q2 [rad]", "q3 [rad]"]
    # by default every joint is revolute, or as the table's attrs say
    assert _header(format_posture_table(table, "markdown"))[3] == "q1 [rad]"
    marked = table.copy()
    marked.attrs["joint_units"] = ("rad", "m", "rad")
    assert _header(format_posture_table(marked, "markdown"))[4] == "q2 [m]"
    written = write_posture_tables(table, tmp_path, joint_units=["rad", "rad", "m"])
    assert _header(Path(written["markdown"]).read_text())[5] == "q3 [m]"
    # LaTeX: the angles in a float of their own, each joint in its unit
    assert "$q_{3}$\\\\{}[m]" in Path(written["latex"]).read_text()


@pytest.mark.parametrize(
    ("units", "message"),
    [
        ("rad", r"^joint_units: expected a unit per joint, each among \['rad', 'm'\]"),
        (("rad", "deg", "rad"), r"^joint_units: expected a unit per joint.*'deg'"),
        (("rad", "rad"), r"^joint_units: expected a unit for each of the table's 3 joints"),
        (3, r"^joint_units: expected a unit per joint"),
    ],
)
def test_bad_joint_units_are_refused_by_name(paper_choice, units, message):
    with pytest.raises(pe.InputError, match=message) as raised:
        format_posture_table(paper_choice.table, "markdown", joint_units=units)
    assert raised.value.fix


GRID = """
    title = "Slider grid"
    [robot]
    urdf = "slider.urdf"
    tip = "tool"
    task = ["x", "z"]
    [grid]
    q1 = { start = -0.5, stop = 0.5, num = 3 }
    q2 = { start = 0.2, stop = 0.8, num = 3 }
    q3 = 0.9
    [compare]
    mvie = false
    outer = false
    [output]
    formats = ["png", "html"]
    dpi = 20
    maps = ["chiacchio_coverage"]
"""


@needs_pinocchio
def test_a_map_over_a_prismatic_joint_has_its_axis_in_metres(tmp_path, monkeypatch):
    """The heat map of a grid over the carriage: its axis in m, the elbow's in rad."""
    import polyell.figures as figures
    import polyell.interactive as interactive

    (tmp_path / "slider.urdf").write_text(SLIDER_URDF)
    study = tmp_path / "grid.toml"
    study.write_text(textwrap.dedent(GRID))
    seen: dict[str, object] = {}
    drawn, shown = figures.plot_score_map, interactive.interactive_map

    def recording_plot(*args, **kwargs):
        seen["static"] = (kwargs["xlabel"], kwargs["ylabel"])
        return drawn(*args, **kwargs)

    def recording_map(*args, **kwargs):
        figure = shown(*args, **kwargs)
        seen["report"] = (figure.layout.xaxis.title.text, figure.layout.yaxis.title.text)
        return figure

    monkeypatch.setattr(figures, "plot_score_map", recording_plot)
    monkeypatch.setattr(interactive, "interactive_map", recording_map)
    run_study(load_study(study), tmp_path / "out")
    # grid axes: rows y (the first varying joint, q1), columns x (q2)
    assert sorted(seen["static"]) == ["$q_1$ [m]", "$q_2$ [rad]"]
    assert sorted(seen["report"]) == ["q1 [m]", "q2 [rad]"]


def test_interactive_map_refuses_units_by_name():
    frame = pd.DataFrame({"q1": [0.0, 0.0, 1.0, 1.0], "q2": [0.0, 1.0, 0.0, 1.0],
                          "chiacchio_coverage": [0.5, 0.6, 0.7, 0.8]})  # fmt: skip
    with pytest.raises(pe.InputError, match=r"^units: "):
        interactive_map(frame, "chiacchio_coverage", "q1", "q2", units=("deg", "rad"))
    figure = interactive_map(frame, "chiacchio_coverage", "q1", "q2", units=("m", "rad"))
    assert figure.layout.xaxis.title.text == "q1 [m]"
