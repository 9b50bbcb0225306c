"""What a posture choice answers with (issue 32, "Posture choice answers with a row number"):
the picked posture's joint angles beside its row number and the unit of the truth's values,
in ``PostureChoice.table`` and in the written tables; a short repr; and ``polyell study``'s
closing message listing the posture outputs."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.cli import main
from polyell.comparison.printable import rounded_text
from polyell.studies.posture import choice_table
from polyell.studies.posture_tables import format_posture_table
from reference import PAPER_Q_REDUNDANT

pytestmark = pytest.mark.filterwarnings("ignore::polyell.errors.TableWidthWarning")

ARM = pe.robots.load("chiacchio2000")
X = np.array([1.0, 0.0])
UNITS = {"limit": "m/s^2", "radius": "m/s^2", "volume": "(m/s^2)^2"}


@pytest.fixture(scope="module")
def postures() -> np.ndarray:
    return pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=16).configurations


@pytest.fixture(scope="module")
def choice(postures) -> pe.PostureChoice:
    return pe.posture_choice(ARM, postures, direction=X, mvie=False)


def _markdown_rows(text: str) -> list[list[str]]:
    lines = [line for line in text.splitlines() if line.startswith("|")]
    return [[cell.strip() for cell in line.strip("|").split("|")] for line in lines]


def test_the_table_gives_the_picked_joint_angles_beside_the_row_number(choice, postures):
    table = choice.table
    columns = list(table.columns)
    assert columns[:4] == ["picked", "q1", "q2", "q3"]
    for (kind, criterion), row in table.iterrows():
        picked = int(row["picked"])
        np.testing.assert_array_equal(
            row[["q1", "q2", "q3"]].to_numpy(dtype=float), postures[picked], (kind, criterion)
        )


def test_the_table_gives_each_criterion_its_unit(choice):
    table = choice.table
    columns = list(table.columns)
    assert columns.index("unit") == columns.index("true_best") + 1
    for (_, criterion), unit in table["unit"].items():
        assert unit == UNITS[criterion]
    assert choice.unit == "m/s^2"
    velocity = pe.posture_choice(
        ARM, choice.configurations[:4], direction=X, capacity="velocity", mvie=False, outer=False
    )
    units = velocity.table.xs("polytope")["unit"].to_dict()
    assert units == {"limit": "m/s", "radius": "m/s", "volume": "(m/s)^2"}


def test_no_pick_has_no_joint_angles(postures):
    """A torque weighting has no force ellipsoid: no posture picked, NaN angles, n/a shown."""
    weighted = pe.Candidate("w", weighting=np.diag([1.0, 1.0, 4.0]))
    choice = pe.posture_choice(
        ARM, postures[:4], direction=X, capacity="force", candidates=[weighted], mvie=False
    )
    row = choice.table.loc[("w", "limit")]
    assert row["picked"] is pd.NA and np.isnan(row[["q1", "q2", "q3"]].to_numpy(float)).all()
    assert row["unit"] == "N"
    lines = _markdown_rows(format_posture_table(choice.table, "markdown"))
    w = next(r for r in lines if r[0] == "w" and r[1].startswith("limit"))
    assert w[2:6] == ["n/a"] * 4, w


def test_written_tables_show_the_angles_and_units(tmp_path, choice):
    paths = pe.write_posture_tables(choice.table, tmp_path)
    # CSV: every digit of the angles, and the unit column
    back = pd.read_csv(paths["csv"], index_col=["kind", "criterion"])
    for column in ("q1", "q2", "q3"):
        np.testing.assert_array_equal(back[column], choice.table[column])
    assert back.loc[("polytope", "volume"), "unit"] == "(m/s^2)^2"
    # Markdown: the headers with their units, the angles rounded, the unit of each criterion
    rows = _markdown_rows(paths["markdown"].read_text())
    header = rows[0]
    assert header[:6] == ["set", "criterion", "posture picked", "q1 [rad]", "q2 [rad]", "q3 [rad]"]
    body = rows[2:]
    assert [row[1] for row in body[:3]] == [
        "limit [m/s^2]",
        "radius [m/s^2]",
        "volume [(m/s^2)^2]",
    ]
    for row, (_, record) in zip(body, choice.table.iterrows(), strict=True):
        assert row[2] == str(int(record["picked"]))
        assert row[3:6] == [rounded_text(float(record[f"q{j}"]), 3) for j in (1, 2, 3)]
    # LaTeX: the units and the volume's power; the angles in a second float (a
    # one-column page's width each)
    latex = paths["latex"].read_text()
    first, angles = latex.split("\\end{table}")[:2]
    assert "$q_{1}$" not in first and "[rad]" not in first
    assert "$q_{1}$\\\\{}[rad]" in angles and "Joint positions" in angles
    assert "limit [m/s$^{2}$]" in latex
    assert "volume [(m/s$^{2}$)$^{2}$]" in latex


def test_the_csv_style_writes_angles_in_full(choice):
    text = format_posture_table(choice.table, "csv")
    header, first = text.splitlines()[:2]
    assert header.split(",")[:6] == [
        "set",
        "criterion",
        "posture picked",
        "q1 [rad]",
        "q2 [rad]",
        "q3 [rad]",
    ]
    cells = first.split(",")
    assert cells[1] == "limit [m/s^2]"
    picked = int(choice.table.iloc[0]["picked"])
    assert [float(c) for c in cells[3:6]] == list(choice.configurations[picked])


def test_a_summary_over_targets_keeps_plain_criteria():
    over = pe.posture_choice_over_targets(
        ARM, [PAPER_Q_REDUNDANT], direction=X, postures=6, mvie=False, outer=False
    )
    assert "unit" not in over.summary.columns
    assert not any(str(c).startswith("q") for c in over.summary.columns)
    rows = _markdown_rows(format_posture_table(over.summary, "markdown"))
    assert [row[1] for row in rows[2:5]] == ["limit", "radius", "volume"]
    # each target's own table has the angles and units
    assert {"q1", "q2", "q3", "unit"} <= set(over.tables.columns)


def test_choice_table_checks_its_postures_and_unit(choice):
    values = choice.values
    plain = choice_table(values)  # without postures and unit: the columns as before
    assert list(plain.columns) == [
        "picked",
        "true_at_pick",
        "true_best",
        "regret",
        "spearman",
        "kendall",
    ]
    again = choice_table(values, configurations=choice.configurations, unit="m/s^2", dimension=2)
    pd.testing.assert_frame_equal(again, choice.table)
    with pytest.raises(pe.InputError, match=r"^configurations:"):
        choice_table(values, configurations=choice.configurations[:-1])
    with pytest.raises(pe.InputError, match=r"^unit:"):
        choice_table(values, unit="", dimension=2)
    with pytest.raises(pe.InputError, match=r"^dimension:"):
        choice_table(values, unit="m/s^2")
    with pytest.raises(pe.InputError, match=r"^dimension:"):
        choice_table(values, unit="m/s^2", dimension=0)
    three = choice_table(values, unit="N m", dimension=3)
    assert three.loc[("polytope", "volume"), "unit"] == "(N m)^3"
    one = choice_table(values, unit="m/s^2", dimension=1)
    assert one.loc[("polytope", "volume"), "unit"] == "m/s^2"


def test_a_junk_unit_is_refused_naming_the_column(choice):
    table = choice.table.copy()
    table["unit"] = table["unit"].astype(object)
    table.iloc[0, table.columns.get_loc("unit")] = 5
    with pytest.raises(pe.InputError, match=r"^table\['unit'\]:"):
        format_posture_table(table, "markdown")


def test_the_repr_is_short(choice):
    text = repr(choice)
    assert len(text) < 200 and "\n" not in text, text
    assert text.startswith("PostureChoice(capacity='acceleration', postures=16, joints=3")
    assert "unit='m/s^2'" in text and "'polytope'" in text
    assert "DataFrame" not in text and "array(" not in text


POSTURE = """\
title = "posture"
[robot]
library = "chiacchio2000"
[posture]
q0 = ["pi/2", "-pi/2", "-pi/2"]
direction = "x"
count = 6
seed = 3
targets = 2
[compare]
mvie = false
outer = false
capacities = ["acceleration", "velocity"]
[output]
formats = ["png"]
dpi = 20
"""


def test_the_closing_message_lists_the_posture_outputs(tmp_path, capsys):
    spec = tmp_path / "study.toml"
    spec.write_text(textwrap.dedent(POSTURE))
    out = tmp_path / "out"
    assert main(["study", str(spec), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    listed = {
        Path(line.split(": ", 1)[0].strip()).name: line.split(": ", 1)[1]
        for line in printed.splitlines()[1:]
        if line.startswith("  ")
    }
    for suffix in ("", "_velocity"):
        for name in (
            f"posture_choice{suffix}.md",
            f"posture_targets{suffix}.md",
            f"posture_values{suffix}.csv",
            f"posture_indices{suffix}.png",
        ):
            assert name in listed, (name, printed)
            assert (out / name).is_file()
    assert listed["posture_choice_velocity.md"].startswith("velocity: ")
    assert "joint angles" in listed["posture_choice.md"]
    assert "posture_indices.svg" not in listed and "posture_indices.pdf" not in listed
    assert re.search(r"wrote \d+ files", printed)


def test_an_unbounded_limit_is_inf_in_the_choice_and_its_tables(tmp_path):
    """A force posture choice along the ray of a singular posture's set: the polytope's
    limit there is inf, as ``limits`` says, not the largest float (numpy.nan_to_num turned
    inf into 1.797693e+308 and the tables printed 1.80 x 10^308)."""
    arm = pe.robots.load("chiacchio2000")
    q0 = np.array([0.3, 0.0, 0.0])  # stretched: rank J = 1, the force set has a line
    ray = pe.analyze(arm.dynamics(q0), arm.tau_max, capacity="force").polytope.rays[0]
    postures = q0 + np.array([[0.0, 0.0, 0.0], [0.0, 0.5, 0.5], [0.0, 1.0, 1.0]])
    choice = pe.posture_choice(
        arm, postures, direction=ray, capacity="force", mvie=False, outer=False
    )
    assert choice.values[("polytope", "limit")].iloc[0] == np.inf
    assert choice.table.loc[("polytope", "limit"), "true_best"] == np.inf
    for path in pe.write_posture_tables(choice.table, tmp_path).values():
        assert not re.search(r"308|1\.797", Path(path).read_text()), path


@pytest.mark.parametrize("step", [5.0, -0.1, 1e-12, float("nan")])
def test_posture_choice_over_random_targets_refuses_a_bad_step_by_name(step):
    """An invalid step made every random target's self-motion fail: a SolverError about
    the joint limits, without naming step."""
    arm = pe.robots.load("chiacchio2000")
    with pytest.raises(pe.InputError, match=r"^step: .*Fix: "):
        pe.posture_choice_over_targets(
            arm, direction="x", count=2, postures=5, step=step, mvie=False, outer=False
        )
