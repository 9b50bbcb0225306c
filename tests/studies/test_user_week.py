"""Regressions of a new user's independent check: tables a paper prints, the closing
message of ``polyell study``, progress, chunks and warnings.

Each test fails without its fix: split limits floats that did not name their posture,
posture tables without the picked joint angles in LaTeX, a closing message without the
figures and datasets, an all-zero mismatch row, text hyphens for a direction's minus,
equation numbers of the paper for any robot, silent posture studies, fixed 20,000-row
chunks, a warning printed twice and not recorded, and the cosmetics of units, rounding
noise, the polytope's own errors and captions.
"""

from __future__ import annotations

import json
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.cli import main
from polyell.comparison.latex_text import latex_unit
from polyell.comparison.layout import TableLayout
from polyell.comparison.summary import format_summary_table
from polyell.comparison.tables import format_comparison_table, format_limits_table
from polyell.errors import TableWidthWarning
from polyell.studies import load_study, run_study
from polyell.studies.posture import criterion_units
from polyell.studies.posture_tables import format_posture_table

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from latex_check import engine, fit_warnings

PAPER_Q = [np.pi / 2, -np.pi / 2, -np.pi / 2]
POSTURES = {
    "ready": PAPER_Q,
    "low": [0.3, 0.2, -0.2],
    "side": [1.0, -0.3, 0.4],
}
DIRECTIONS = ["x", "y", "xy", "-x", "-y"]


@pytest.fixture(scope="module")
def comparisons() -> dict[str, pe.Comparison]:
    arm = pe.robots.load("chiacchio2000")
    tau = [100.0, 30.0, 4.0]
    return {
        name: pe.compare(pe.analyze(arm.dynamics(q), tau), 16, samples=256, seed=0)
        for name, q in POSTURES.items()
    }


def _floats(tex: str) -> list[str]:
    return re.findall(r"\\begin\{table\}.*?\\end\{table\}", tex, re.S)


# ---- 1: a split limits table names each posture ------------------------------------------


def test_split_limits_floats_name_their_posture_without_a_caption(comparisons):
    frame = pe.limits_table(comparisons, DIRECTIONS)
    floats = _floats(format_limits_table(frame, "latex"))
    assert len(floats) == 3  # taller than a page: one float per posture
    for name, tex in zip(POSTURES, floats, strict=True):
        assert f"\\caption{{Directional limits at posture {name}.}}" in tex
        assert f"\\label{{tab:limits-{name}}}" in tex


def test_split_limits_captions_read_as_a_sentence(comparisons):
    frame = pe.limits_table(comparisons, DIRECTIONS)
    tex = format_limits_table(frame, "latex", caption="Limits.", label="tab:lim")
    assert re.findall(r"\\caption\{([^}]*)\}", tex) == [
        f"Limits at posture {name}." for name in POSTURES
    ]
    assert re.findall(r"\\label\{([^}]*)\}", tex) == [f"tab:lim-{name}" for name in POSTURES]
    assert "(ready)" not in tex


def test_a_short_combined_limits_table_is_one_float_with_posture_headings(comparisons):
    frame = pe.limits_table(comparisons, ["x", "y"])
    tex = format_limits_table(frame, "latex", caption="Limits.")
    assert len(_floats(tex)) == 1 and "\\caption{Limits.}" in tex
    for name in POSTURES:
        assert f"\\itshape {name}" in tex


# ---- 5, 10: a direction's minus; the polytope's own errors ------------------------------


def test_direction_names_have_a_math_minus_and_the_polytope_no_error(comparisons):
    frame = pe.limits_table(comparisons["ready"], ["x", "-y"])
    tex = format_limits_table(frame, "latex")
    rows = [line for line in tex.splitlines() if "polytope" in line]
    assert any(line.startswith("$-$y & polytope") for line in rows), rows
    assert not any(line.startswith("-y") for line in tex.splitlines())
    for line in rows:  # lower, upper, then blank errors (the reference)
        assert line.endswith("& {} & {} \\\\"), line
    markdown = format_limits_table(frame, "markdown")
    polytope = [line for line in markdown.splitlines() if "| polytope" in line]
    assert all(re.search(r"\|\s+\|\s+\|$", line) for line in polytope), polytope
    from polyell.comparison.latex_text import latex_direction

    assert latex_direction("[0.6, -0.8]") == "[0.6, $-$0.8]"
    assert latex_direction("pick-up") == "pick-up"


# ---- 4: an all-zero row is left out in both orientations --------------------------------


def test_all_zero_mismatch_row_left_out_in_both_orientations(comparisons):
    one = {"ready": comparisons["ready"]}
    assert (one["ready"].to_frame()["feasibility_mismatch"].fillna(0) == 0).all()
    default = format_comparison_table(one, "markdown")
    transposed = format_comparison_table(one, "markdown", layout=TableLayout(transpose=True))
    assert "feasibility mismatches" not in default
    assert "feasibility mismatches" not in transposed
    # a chosen score is shown, zero or not
    chosen = TableLayout(scores=["coverage", "feasibility_mismatch"])
    assert "feasibility mismatches" in format_comparison_table(one, "markdown", layout=chosen)


# ---- 10: units, rounding noise -------------------------------------------------------------


def test_volume_units_without_parentheses_around_one_symbol():
    assert latex_unit("N", "3") == "N$^{3}$"
    assert latex_unit("m/s^2", "3") == "(m/s$^{2}$)$^{3}$"
    assert latex_unit("N m", "2") == "(N m)$^{2}$"
    from polyell.comparison.latex_text import unit_power

    assert unit_power("N", 3) == "N^3" and unit_power("m/s^2", 3) == "(m/s^2)^3"
    assert criterion_units("N", 3)["volume"] == "N^3"


def test_summary_std_below_rounding_is_shown_as_zero():
    index = pd.MultiIndex.from_tuples(
        [("mvie", "inscribed_scale"), ("chiacchio", "coverage")], names=["ellipsoid", "score"]
    )
    summary = pd.DataFrame(
        {
            "defined": [3000, 3000],
            "mean": [1.0, 0.6],
            "std": [7.8e-16, 0.01],
            "min": [1.0, 0.5],
            "median": [1.0, 0.6],
            "max": [1.0000000000000002, 0.7],
        },
        index=index,
    )
    text = format_summary_table(summary, "markdown")
    line = next(line for line in text.splitlines() if "inscribed scale" in line)
    assert "e-16" not in line and re.search(r"\|\s+0\s+\|", line), line
    coverage = next(line for line in text.splitlines() if "coverage" in line)
    assert "1.00" in coverage  # a real spread (1 % in percent) is kept


# ---- 2, 5, 7, 10: the posture study -------------------------------------------------------

POSTURE_STUDY = """\
title = "posture"
[robot]
library = "chiacchio2000"
[posture]
q0 = ["pi/2", "-pi/2", "-pi/2"]
direction = "-y"
count = 12
seed = 3
[compare]
mvie = false
outer = false
[output]
formats = ["png"]
dpi = 20
"""


@pytest.fixture(scope="module")
def posture_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("posture")
    spec = folder / "posture.toml"
    spec.write_text(POSTURE_STUDY, encoding="utf-8")
    out = folder / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)
        run_study(load_study(spec), out)
    return out


def test_posture_latex_holds_the_picked_joint_angles(posture_run):
    tex = (posture_run / "posture_choice.tex").read_text(encoding="utf-8")
    floats = _floats(tex)
    assert len(floats) == 2
    angles = floats[1]
    assert "\\label{tab:posture-choice-q}" in angles
    for j in (1, 2, 3):
        assert f"$q_{{{j}}}$\\\\{{}}[rad]" in angles
    csv = pd.read_csv(posture_run / "posture_choice.csv", index_col=[0, 1])
    picked = csv.loc[("polytope", "limit")]
    row = next(line for line in angles.splitlines() if line.startswith("limit &"))
    cells = [c.strip().rstrip("\\").strip() for c in row.split("&")]
    assert cells[1] == str(int(picked["picked"]))
    q1 = f"{picked['q1']:.3g}".replace("-", "$-$")
    assert cells[2].startswith(q1[:5]), (cells, picked["q1"])


def test_posture_caption_has_a_math_minus_and_a_period(posture_run):
    tex = (posture_run / "posture_choice.tex").read_text(encoding="utf-8")
    captions = re.findall(r"\\caption\{(.*)\}", tex)
    assert captions[0] == "The posture each index picks (along $-$y, 12 postures)."
    assert all(caption.endswith(".") for caption in captions)
    assert "along -y" not in tex


@pytest.mark.skipif(engine("pdflatex") is None, reason="pdflatex is not installed")
def test_posture_tables_fit_a_one_column_page(posture_run, tmp_path):
    tex = (posture_run / "posture_choice.tex").read_text(encoding="utf-8")
    assert fit_warnings("pdflatex", [tex], tmp_path) == []


def test_panda_posture_angles_table_fits_the_width():
    pytest.importorskip("pinocchio")
    robot = pe.robots.load("panda")
    q0 = [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
    motion = pe.self_motion(robot, q0, count=12, seed=0)
    choice = pe.posture_choice(robot, motion, direction="-z", mvie=False, outer=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)  # width-checked, fits 345 pt
        tex = format_posture_table(choice.table, "latex", "Picks.", "tab:p", TableLayout(digits=3))
    assert len(_floats(tex)) == 2 and "$q_{7}$" in tex


def test_posture_choice_shows_progress_unless_quiet(capsys):
    arm = pe.robots.load("chiacchio2000")
    motion = pe.self_motion(arm, PAPER_Q, count=12, seed=3)
    pe.posture_choice(arm, motion, direction="x", mvie=False, outer=False, progress=True)
    err = capsys.readouterr().err
    assert "acceleration: scoring postures" in err and "12/12" in err
    pe.posture_choice(arm, motion, direction="x", mvie=False, outer=False)
    assert capsys.readouterr().err == ""


def test_posture_study_cli_progress_and_quiet(tmp_path, capsys):
    spec = tmp_path / "posture.toml"
    spec.write_text(POSTURE_STUDY.replace("seed = 3\n", "seed = 3\ntargets = 2\n"))
    assert main(["study", str(spec), "--out", str(tmp_path / "a")]) == 0
    err = capsys.readouterr().err
    assert "acceleration: scoring postures" in err
    assert "acceleration: scoring targets" in err
    assert main(["study", str(spec), "--out", str(tmp_path / "b"), "--quiet"]) == 0
    assert "scoring" not in capsys.readouterr().err


# ---- 3: the closing message lists every output --------------------------------------------


def test_closing_message_lists_figures_datasets_and_warnings(tmp_path):
    from polyell.cli import study_summary

    names = [
        "comparison.md",
        "comparison.tex",
        "comparison.csv",
        "scores.csv",
        "sets_low.png",
        "sets_low_force.png",
        "histogram_coverage.png",
        "summary.md",
        "odd.txt",
    ]
    (tmp_path / "manifest.json").write_text(
        json.dumps({"datasets": ["results/", "results_force/"], "warnings": ["W: x"]})
    )
    written = [tmp_path / name for name in names] + [tmp_path / "manifest.json"]
    text = "\n".join(study_summary("t", ["acceleration", "force"], written, tmp_path))
    for name in ("sets_low.png", "sets_low_force.png", "histogram_coverage.png", "odd.txt"):
        assert name in text
    assert f"{tmp_path / 'results'}/: every configuration" in text
    assert f"{tmp_path / 'results_force'}/: force: every configuration" in text
    assert text.splitlines()[-1] == (
        f"  {tmp_path / 'manifest.json'}: every file written, the datasets, notes and "
        "warnings (1 warning, printed below)"
    )


def test_random_study_lists_histograms_and_its_dataset(tmp_path, capsys):
    spec = tmp_path / "random.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 60\nseed = 7\n'
        "[compare]\nmvie = false\nouter = false\n"
        '[output]\nformats = ["png"]\ndpi = 20\nhistograms = ["coverage"]\n',
        encoding="utf-8",
    )
    out = tmp_path / "out"
    assert main(["study", str(spec), "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "histogram_coverage.png" in text
    assert f"{out / 'results'}/:" in text
    manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["datasets"] == ["results/"]


def test_points_study_lists_its_set_figures(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'
        '[compare]\nmvie = false\n[output]\nformats = ["png"]\ndpi = 20\n'
    )
    assert main(["study", str(spec), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    out = capsys.readouterr().out
    written = json.loads((tmp_path / "out" / "manifest.json").read_text())["files"]
    for name in written:  # every file is named (or said with its table's main format)
        stem = name.rsplit(".", 1)[0]
        assert name in out or f"{stem}.md" in out or name.startswith("scores"), name
    assert "sets_p.png" in out


# ---- 6: equation numbers of the paper ------------------------------------------------------


def test_equation_numbers_only_for_the_paper_arm_or_on_request(tmp_path, capsys):
    robot = tmp_path / "arm.toml"
    robot.write_text(
        "planar = { lengths = [1, 0.8, 0.5], masses = [4, 2, 0.6] }\ntau_max = [100, 30, 4]\n"
    )
    argv = ["analyze", "--robot", str(robot), "--q", "0.3,0.4,0.5", "--no-mvie", "--no-outer"]
    assert main(argv) == 0
    assert "(eq. " not in capsys.readouterr().out
    assert main([*argv, "--equations"]) == 0
    assert "xdd_g (eq. 8)" in capsys.readouterr().out
    assert main(["analyze", "--no-mvie", "--no-outer"]) == 0  # the paper's arm
    assert "xdd_g (eq. 8)" in capsys.readouterr().out


# ---- 8: chunks sized by time -------------------------------------------------------------


def test_study_chunks_are_sized_by_time_unless_given(tmp_path, monkeypatch):
    from polyell.studies import runner

    seen = []
    real = runner.sweep

    def spy(*args, **kwargs):
        seen.append(kwargs["chunk"])
        return real(*args, **kwargs)

    monkeypatch.setattr(runner, "sweep", spy)
    text = (
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 40\nseed = 1\n'
        '[compare]\nmvie = false\nouter = false\n[output]\nformats = ["png"]\n'
    )
    spec = tmp_path / "r.toml"
    spec.write_text(text, encoding="utf-8")
    loaded = load_study(spec)
    assert loaded.file.compare.chunk is None
    run_study(loaded, tmp_path / "a")
    spec.write_text(text.replace("outer = false\n", "outer = false\nchunk = 7\n"))
    run_study(load_study(spec), tmp_path / "b")
    assert seen == [None, 7]
    doc = (Path(__file__).resolve().parents[2] / "docs" / "study_format.md").read_text()
    row = next(line for line in doc.splitlines() if line.startswith("| `chunk`"))
    assert "| 20000 |" not in row and "2 s" in row


# ---- 9: a warning once, and in the manifest -----------------------------------------------


def test_joint_limit_warning_once_and_in_the_manifest(tmp_path, capsys):
    pytest.importorskip("pinocchio")
    spec = tmp_path / "deg.toml"
    spec.write_text(
        'title = "degrees"\n[robot]\nlibrary = "panda"\n[[points]]\nname = "ready"\n'
        "q = [0, -45, 0, -135, 0, 90, 45]\n[compare]\nmvie = false\nouter = false\n"
        '[output]\nformats = ["png"]\ndpi = 20\n',
        encoding="utf-8",
    )
    out = tmp_path / "out"
    assert main(["study", str(spec), "--out", str(out), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.err.count("polyell: warning: JointLimitWarning") == 1
    assert "1 warning" in captured.out
    manifest = json.loads((out / "manifest.json").read_text(encoding="utf-8"))
    assert len(manifest["warnings"]) == 1
    assert manifest["warnings"][0].startswith("JointLimitWarning: q: expected joint positions")
