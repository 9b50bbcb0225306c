"""Units and labels follow the task: axis labels, tables, text and JSON (issue 11)."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.figures import plot_sets, plot_sets_3d
from polyell.report import analysis_to_json, format_analysis

Q_PANDA = [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8]


@pytest.fixture(scope="module")
def angular():
    robot = pe.robots.load("panda", task="angular")
    return pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)


def test_a_vertical_plane_task_labels_its_axes_x_and_z():
    robot = pe.robots.load("panda", task=["x", "z"])
    analysis = pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)
    assert analysis.dynamics.task == ("x", "z")
    ax = plot_sets(analysis).axes[0]
    assert ax.get_xlabel() == r"$\ddot x$ [m/s$^2$]"
    assert ax.get_ylabel() == r"$\ddot z$ [m/s$^2$]"


def test_an_angular_task_is_in_rad_per_s2_everywhere(angular):
    ax = plot_sets_3d(angular).axes[0]
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == [
        rf"$\dot\omega_{axis}$ [rad/s$^2$]" for axis in "xyz"
    ]
    table = pe.compare(angular, 16, mvie=False).to_markdown()
    assert "(rad/s^2)^3" in table and "m/s^2" not in table
    latex = pe.compare(angular, 16, mvie=False).to_latex()
    assert r"volume [(rad/s$^{2}$)$^{3}$]" in latex
    text = format_analysis(angular, np.array([1.0, 0.0, 0.0]), "t")
    assert "task rows wx, wy, wz [rad/s^2]" in text and "m/s^2" not in text
    data = analysis_to_json(angular, np.array([1.0, 0.0, 0.0]))
    assert data["task"] == ["wx", "wy", "wz"] and data["unit"] == "rad/s^2"


def test_mixed_rows_are_in_weighted_units():
    robot = pe.robots.load("panda", task=["x", "y", "z", "wz"], weights=[1, 1, 1, 0.5])
    analysis = pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)
    assert "weighted units" in pe.compare(analysis, 8, mvie=False).to_markdown()


def test_task_names_are_validated_and_kept_by_batches():
    J, B, g = np.ones((4, 2, 3)), np.broadcast_to(np.eye(3), (4, 3, 3)), np.zeros((4, 3))
    dyn = pe.Dynamics(J, B, g, task=("x", "z"))
    assert dyn[2].task == ("x", "z")
    assert pe.Dynamics(J[0], B[0], g[0]).task == ("x", "y")  # the default: linear rows
    with pytest.raises(pe.InputError, match="2 distinct row names"):
        pe.Dynamics(J[0], B[0], g[0], task=("x", "x"))
    with pytest.raises(pe.InputError, match="task"):
        pe.Dynamics(J[0], B[0], g[0], task="xz")


def test_a_study_of_an_angular_task_writes_its_unit(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "panda"\ntask = "angular"\n[[points]]\nname = "p"\n'
        f"q = {Q_PANDA}\ndirection = [1, 0, 0]\n"
        '[compare]\nmvie = false\ndirections = 16\n[output]\nformats = ["png"]\ndpi = 30\n'
    )
    pe.studies.run_study(pe.studies.load_study(spec), tmp_path / "out")
    text = (tmp_path / "out" / "comparison.md").read_text()
    assert "Volumes in (rad/s^2)^r" in text and "m/s^2" not in text
    assert "[rad/s^2]" in (tmp_path / "out" / "numbers.md").read_text()
