"""Every capacity through the outputs: the command line, study files, tables, figures."""

from __future__ import annotations

import json

import numpy as np
import pytest

import polyell as pe
from polyell.cli import main
from polyell.comparison.labels import set_label
from polyell.comparison.latex_text import unit_power
from polyell.comparison.summary import format_summary_table, summarize
from polyell.studies import load_study, run_study

PAPER_ARM = pe.robots.load("chiacchio2000")
Q = [0.3, 0.6, 0.9]


@pytest.mark.parametrize(
    ("capacity", "unit", "first_kind"),
    [
        ("acceleration", "m/s^2", "chiacchio"),
        ("velocity", "m/s", "yoshikawa"),
        ("force", "N", "chiacchio"),
    ],
)
def test_cli_analyzes_each_capacity_in_its_units(capsys, capacity, unit, first_kind):
    assert main(["analyze", "--capacity", capacity, "--q", "0.3,0.6,0.9", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["capacity"] == capacity and data["unit"] == unit
    assert first_kind in data["ellipsoids"]
    kwargs = {"qd_max": PAPER_ARM.qd_max} if capacity == "velocity" else {}
    limits = [] if capacity == "velocity" else [PAPER_ARM.tau_max]
    an = pe.analyze(PAPER_ARM.dynamics(Q), *limits, capacity=capacity, **kwargs)
    lo, hi = an.polytope.limits([1.0, 0.0])
    assert data["polytope"]["limits"] == pytest.approx([float(lo), float(hi)], rel=1e-12)
    assert main(["analyze", "--capacity", capacity, "--q", "0.3,0.6,0.9"]) == 0
    text = capsys.readouterr().out
    assert f"[{unit}]" in text


def test_cli_refuses_unknown_capacities_and_misplaced_limits(capsys):
    assert main(["analyze", "--capacity", "forces"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you mean 'force'" in err[0]
    assert main(["analyze", "--qd-max", "1,1,1"]) == 2
    assert "--qd-max" in capsys.readouterr().err
    assert main(["analyze", "--capacity", "velocity", "--qd", "1,1,1"]) == 2
    assert "--qd" in capsys.readouterr().err
    assert main(["analyze", "--qd", "1,1,1"]) == 2  # the planar arm is modelled at rest
    assert "URDF" in capsys.readouterr().err


def test_cli_velocity_limits_override_the_robots(capsys):
    assert main(["analyze", "--capacity", "velocity", "--qd-max", "1,1,1", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["qd_max"] == [1.0, 1.0, 1.0] and data["qd_min"] == [-1.0, -1.0, -1.0]


def test_labels_follow_the_capacity():
    assert set_label("chiacchio") == "Chiacchio"
    assert set_label("chiacchio", "force") == "Chiacchio"
    assert set_label("static", "force") == "static (no gravity)"
    assert set_label("yoshikawa", "velocity") == "Yoshikawa"  # one name per kind
    an = pe.analyze(PAPER_ARM.dynamics(Q), PAPER_ARM.tau_max, capacity="force")
    table = pe.compare(an, 16, mvie=False, outer=False).to_markdown()
    assert "Chiacchio" in table and "volume [N^2]" in table  # (no parentheses for one unit)


def test_witness_labels_name_the_capacitys_joint_quantity():
    # the velocity ellipsoids' witness is a normalized joint velocity, not a torque
    kinematics = pe.Kinematics(PAPER_ARM.dynamics(Q).J)
    an = pe.analyze(kinematics, capacity="velocity", qd_max=np.ones(3))
    comparison = pe.compare(an, 16, mvie=False, outer=False)
    for text in (comparison.to_markdown(), comparison.to_latex()):
        assert "joint velocity witness" in text
        assert "torque" not in text
    batch = pe.Dynamics(kinematics.J[None], np.eye(3)[None], np.zeros((1, 3)))
    rows = pe.sweep(batch, capacity="velocity", qd_max=np.ones(3))
    text = format_summary_table(summarize(rows), "markdown", capacity="velocity")
    assert "joint velocity witness" in text and "torque" not in text
    from polyell.figures import plot_score_histogram

    figure = plot_score_histogram(rows, "witness_torque_max", capacity="velocity")
    assert figure.axes[0].get_xlabel() == "joint velocity witness"
    for capacity in ("acceleration", "force"):
        an = pe.analyze(PAPER_ARM.dynamics(Q), PAPER_ARM.tau_max, capacity=capacity)
        assert "torque witness" in pe.compare(an, 16, mvie=False, outer=False).to_markdown()


STUDY = """
[robot]
library = "chiacchio2000"
[[points]]
name = "bent"
q = [0.3, 0.6, 0.9]
[compare]
capacities = {capacities}
directions = 16
samples = 256
[output]
formats = ["png"]
"""


def test_a_study_of_capacities_writes_each_capacitys_tables_equal_to_compare(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(capacities='["acceleration", "force", "velocity"]'))
    written = {p.name for p in run_study(load_study(path), tmp_path / "out")}
    for suffix in ("", "_force", "_velocity"):
        for name in ("comparison", "limits"):
            assert f"{name}{suffix}.tex" in written and f"{name}{suffix}.md" in written
        assert f"scores{suffix}.csv" in written and f"sets_bent{suffix}.png" in written
    import pandas as pd

    scores = pd.read_csv(tmp_path / "out" / "scores_force.csv", index_col="ellipsoid")
    an = pe.analyze(PAPER_ARM.dynamics(Q), PAPER_ARM.tau_max, capacity="force")
    cmp = pe.compare(an, 16, samples=256)
    for kind in cmp.kinds:
        row = scores.loc[f"bent: {set_label(kind, 'force')}"]
        for score in ("inscribed_scale", "coverage", "direction_error_mean", "volume"):
            assert row[score] == pytest.approx(getattr(cmp[kind], score), rel=1e-12)


@pytest.mark.parametrize(
    ("capacities", "message"),
    [
        ('["forces"]', r"compare\.capacities\[0\].*did you mean 'force'"),
        ('["force", "force"]', "distinct capacity names"),
    ],
)
def test_study_capacities_are_checked_at_load(tmp_path, capacities, message):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.format(capacities=capacities))
    with pytest.raises(pe.InputError, match=message):
        load_study(path)


def test_posture_studies_take_every_capacity_and_velocities_need_limits(tmp_path):
    path = tmp_path / "posture.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[posture]\nq0 = [0.3, 0.6, 0.9]\ndirection = "x"\n'
        '[compare]\ncapacities = ["force"]\n'
    )
    assert load_study(path).capacities == ("force",)
    planar = "[robot]\ntau_max = [5, 5, 5]\n[robot.planar]\nlengths = [1.0, 1.0, 1.0]\n"
    planar += "masses = [1.0, 1.0, 1.0]\n"
    for where in (
        '[[points]]\nname = "p"\nq = [0.3, 0.6, 0.2]\n',
        '[posture]\nq0 = [0.3, 0.6, 0.9]\ndirection = "x"\n',
    ):
        path = tmp_path / "noqd.toml"
        path.write_text(planar + where + '[compare]\ncapacities = ["velocity"]\n')
        with pytest.raises(pe.InputError, match=r"robot\.qd_max"):
            load_study(path)


def test_force_figures_refuse_an_unbounded_set():
    from polyell.figures import plot_sets

    singular = pe.analyze(PAPER_ARM.dynamics([0.3, 0.0, 0.0]), PAPER_ARM.tau_max, capacity="force")
    assert not singular.polytope.is_bounded
    with pytest.raises(pe.InputError, match="unbounded along 2 ray"):
        plot_sets(singular)
    bounded = pe.analyze(PAPER_ARM.dynamics(Q), PAPER_ARM.tau_max, capacity="force")
    figure = plot_sets(bounded)
    labels = [line.get_label() for line in figure.axes[0].get_lines()]
    assert "Chiacchio" in labels and "static (no gravity)" in labels
    vertices = bounded.polytope.vertices  # counter-clockwise, as drawn
    a, b = np.roll(vertices, -1, axis=0) - vertices, np.roll(vertices, -2, axis=0) - vertices
    assert np.all(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] > 0)


@pytest.mark.parametrize("capacity", ["force", "velocity"])
def test_interactive_view_and_meshes_of_other_capacities(tmp_path, capacity):
    from polyell.export import export_comparison, mesh
    from polyell.interactive import interactive_sets

    limits = {"qd_max": PAPER_ARM.qd_max} if capacity == "velocity" else {}
    torques = [] if capacity == "velocity" else [PAPER_ARM.tau_max]
    an = pe.analyze(PAPER_ARM.dynamics(Q), *torques, capacity=capacity, **limits)
    cmp = pe.compare(an, 16, samples=256)
    names = [trace.name for trace in interactive_sets(cmp).data]
    assert names[0].startswith("polytope, volume") and unit_power(an.unit(), 2) in names[0]
    assert set_label(an.ellipsoid_kinds[0], capacity) in names
    P = an.polytope
    surface = mesh(P)
    assert len(surface.vertices) == len(P.vertices) and len(surface.faces) == len(P.vertices) - 2
    written = export_comparison(cmp, tmp_path / "sets.obj")
    assert written and all(path.stat().st_size > 0 for path in written)
    header = written[0].read_text().splitlines()[:2]  # the capacity and its unit
    assert f"{capacity} sets in the task frame (x, y)" in header[0]
    assert header[1] == f"# units: {an.unit()} on every axis"
    assert an.unit() == {"force": "N", "velocity": "m/s"}[capacity]
    plies = export_comparison(cmp, tmp_path / "sets.ply")
    assert {path.name for path in plies} >= {f"sets_{kind}.ply" for kind in an.ellipsoid_kinds}
    assert f"comment units: {an.unit()} on every axis" in plies[0].read_text()


def test_cli_refuses_torque_limits_for_velocities(capsys):
    """Found by the independent check: --tau-max was ignored by --capacity velocity."""
    assert main(["analyze", "--capacity", "velocity", "--tau-max", "1,1,1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--tau-max: expected no torque limits" in err[0]
