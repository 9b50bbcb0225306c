"""Regressions of the third attack round: keys without effect, a reused or interrupted
output folder, labels as live HTML, undrawn figures, directions, ``--angle``."""

from __future__ import annotations

import json

import numpy as np
import pytest

import polyell as pe
from polyell.cli import main
from polyell.comparison.tables import format_comparison_table, format_limits_table
from polyell.studies import load_study, run_study

ROBOT = '[robot]\nlibrary = "chiacchio2000"\n'
FAST = "[compare]\nmvie = false\nouter = false\n"
POINT = '[[points]]\nname = "a"\nq = [0.1, 0.2, 0.3]\n'
POSTURE = '[posture]\nq0 = ["pi/2", "-pi/2", "-pi/2"]\ndirection = "x"\ncount = 6\n'
RANDOM = "[random]\ncount = 4\n"


def _load(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return load_study(path)


@pytest.mark.parametrize(
    ("body", "extra", "argument", "says"),
    [
        (POSTURE + FAST, 'split = "posture"', "output.split", "a posture study"),
        (POSTURE + FAST, "transpose = true", "output.transpose", "a posture study"),
        (POSTURE + FAST, 'scores = ["coverage"]', "output.scores", "a posture study"),
        (POSTURE + FAST, "percent = false", "output.percent", "a posture study"),
        (RANDOM + FAST, 'split = "posture"', "output.split", "a random study"),
        (RANDOM + FAST, "transpose = true", "output.transpose", "a random study"),
    ],
)
def test_output_keys_a_study_does_not_use_are_refused(tmp_path, body, extra, argument, says):
    text = f"{ROBOT}{body}[output]\nformats = []\n{extra}\n"
    with pytest.raises(pe.InputError, match=argument) as caught:
        _load(tmp_path, text)
    assert says in str(caught.value) and "Fix: drop" in str(caught.value)


def test_output_keys_a_points_study_uses_still_load(tmp_path):
    text = (
        f'{ROBOT}{POINT}{FAST}[output]\nformats = []\nsplit = "posture"\ntranspose = true\n'
        'percent = false\nscores = ["coverage"]\n'
    )
    spec = _load(tmp_path, text)
    assert spec.file.output.transpose and spec.file.output.split == "posture"


@pytest.mark.parametrize(
    ("body", "keys", "argument", "says"),
    [
        (POINT, 'capacities = ["force"]\nhorizon = 0.01', "compare.horizon", "acceleration"),
        (POINT, "braking = 50", "compare.braking", "horizon"),
        (POINT, "chunk = 7", "compare.chunk", "a study of points"),
        (POSTURE, "chunk = 7", "compare.chunk", "a posture study"),
    ],
)
def test_compare_keys_without_effect_are_refused(tmp_path, body, keys, argument, says):
    text = f"{ROBOT}{body}{FAST}{keys}\n[output]\nformats = []\n"
    with pytest.raises(pe.InputError, match=argument) as caught:
        _load(tmp_path, text)
    assert says in str(caught.value) and "Fix:" in str(caught.value)


def test_compare_keys_with_effect_still_load(tmp_path):
    spec = _load(tmp_path, f"{ROBOT}{RANDOM}{FAST}chunk = 2\nhorizon = 0.01\nbraking = 50\n")
    assert spec.file.compare.chunk == 2 and spec.file.compare.braking == 50


GRID = (
    f'{ROBOT}[grid]\nq1 = "pi/2"\nq2 = {{ start = "-pi", stop = "pi", num = 3 }}\n'
    'q3 = { start = "-pi", stop = "pi", num = 3 }\n'
    f"{FAST}directions = 16\n[output]\nformats = []\n"
)
POINTS = f"{ROBOT}{POINT}{FAST}[output]\nformats = []\n"


def test_a_points_study_replaces_a_grid_studys_dataset(tmp_path):
    out = tmp_path / "out"
    run_study(_load(tmp_path, GRID, "grid.toml"), out)
    assert (out / "results").is_dir()
    run_study(_load(tmp_path, POINTS, "points.toml"), out)
    assert not (out / "results").exists()
    manifest = json.loads((out / "manifest.json").read_text())
    assert "results/" in manifest["removed"] and manifest["datasets"] == []


def test_a_rerun_of_the_same_grid_study_keeps_its_dataset(tmp_path):
    out = tmp_path / "out"
    spec = _load(tmp_path, GRID, "grid.toml")
    run_study(spec, out)
    parts = sorted(p.name for p in (out / "results").iterdir())
    run_study(spec, out)
    assert sorted(p.name for p in (out / "results").iterdir()) == parts
    assert "removed" not in json.loads((out / "manifest.json").read_text())


def test_an_interrupted_run_is_marked_and_its_files_removed_by_the_next(tmp_path, monkeypatch):
    out = tmp_path / "out"
    first = _load(tmp_path, POINTS, "a.toml")
    run_study(first, out)
    second = _load(
        tmp_path,
        POINTS.replace('name = "a"', 'name = "b"').replace("formats = []", 'formats = ["png"]'),
        "b.toml",
    )
    import polyell.studies.runner as runner

    real = runner.write_point_tables

    def killed(*args, **kwargs):  # the figures are written, then the run dies
        raise KeyboardInterrupt

    monkeypatch.setattr(runner, "write_point_tables", killed)
    with pytest.raises(KeyboardInterrupt):
        run_study(second, out)
    monkeypatch.setattr(runner, "write_point_tables", real)
    marker = json.loads((out / "manifest.json").read_text())
    assert marker["complete"] is False and marker["study"] == second.title
    orphans = [p.name for p in out.iterdir() if p.name.startswith("sets_b")]
    assert orphans  # the killed run's figure, beside the first run's tables
    run_study(first, out)
    assert not [p.name for p in out.iterdir() if p.name.startswith("sets_b")]
    manifest = json.loads((out / "manifest.json").read_text())
    assert "complete" not in manifest and set(orphans) <= set(manifest["removed"])


LABELS = (
    "labels = { chiacchio = \"<script>alert('l')</script>\", "
    'coverage = "<img src=x onerror=alert(2)>" }\n'
)


def test_labels_are_no_live_html_in_the_markdown(tmp_path):
    out = tmp_path / "out"
    run_study(_load(tmp_path, POINTS + LABELS), out)
    for path in out.glob("*.md"):
        text = path.read_text()
        # numbers.md shows them inside a fenced code block only (shown, not rendered)
        if path.name == "numbers.md":
            text = "".join(text.split("```")[::2])
        assert "<script>" not in text and "<img" not in text, path.name
    assert "&lt;script&gt;" in (out / "comparison.md").read_text()


def test_format_tables_escape_labels_in_markdown():
    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics([0.1, 0.2, 0.3]), arm.tau_max)
    cmp = pe.compare(analysis, mvie=False, outer=False)
    layout = pe.TableLayout(labels={"chiacchio": "<b>x</b> & y", "coverage": "<i>c</i>"})
    for text in (
        format_comparison_table(cmp, "markdown", layout=layout),
        format_limits_table(pe.limits_table(cmp, ["x"]), "markdown", layout=layout),
    ):
        assert "<b>" not in text and "<i>" not in text
    assert "&lt;b&gt;x&lt;/b&gt; & y" in format_comparison_table(cmp, "markdown", layout=layout)


def test_a_force_figure_not_drawn_is_said(tmp_path, caplog):
    text = (
        f'{ROBOT}[[points]]\nname = "sing"\nq = ["pi/6", 0, 0]\n'
        '[[points]]\nname = "reg"\nq = [0.3, 0.6, 0.9]\n'
        f'{FAST}capacities = ["force"]\n[output]\nformats = ["png"]\n'
    )
    out = tmp_path / "out"
    with caplog.at_level("INFO", logger="polyell"):
        run_study(_load(tmp_path, text), out)
    assert (out / "sets_reg_force.png").exists() and not (out / "sets_sing_force.png").exists()
    notes = json.loads((out / "manifest.json").read_text())["notes"]
    assert any("sets_sing_force" in note and "unbounded" in note for note in notes)
    assert "sets_sing_force" in caplog.text


def test_posture_choice_refuses_a_non_unit_direction_as_limits_does():
    arm = pe.robots.load("chiacchio2000")
    motion = pe.self_motion(arm, [np.pi / 2, -np.pi / 2, -np.pi / 2], count=4)
    with pytest.raises(pe.InputError, match=r"direction.*norm 2\.0.*Fix: normalise"):
        pe.posture_choice(arm, motion, direction=[2.0, 0.0], mvie=False, outer=False)
    unit = pe.posture_choice(arm, motion, direction=[1.0, 0.0], mvie=False, outer=False)
    assert np.allclose(unit.direction, [1.0, 0.0])


@pytest.mark.parametrize("angle", ["1e300", "400", "-361"])
def test_analyze_refuses_an_angle_out_of_range(capsys, angle):
    assert main(["analyze", f"--angle={angle}", "--no-mvie"]) not in (0, None)
    err = capsys.readouterr().err
    assert "--angle" in err and "Fix:" in err


def test_analyze_takes_an_angle_within_a_turn(capsys):
    assert main(["analyze", "--angle", "-350", "--no-mvie"]) in (0, None)
    assert "polyell: error" not in capsys.readouterr().err


def test_interactive_titles_print_units_as_the_tables():
    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics([0.3, 0.6, 0.9]), arm.tau_max, capacity="force")
    from polyell.interactive import interactive_sets

    figure = interactive_sets(pe.compare(analysis, mvie=False, outer=False))
    text = json.dumps(figure.to_plotly_json(), default=str)
    assert "N^2" in text and "(N)^" not in text


def test_an_edited_sweep_study_keeps_a_dropped_capacitys_dataset_and_says_so(tmp_path):
    text = f"{ROBOT}{RANDOM}{FAST}directions = 8\ncapacities = {{}}\n[output]\nformats = []\n"
    out = tmp_path / "out"
    run_study(_load(tmp_path, text.format('["acceleration", "force"]')), out)
    run_study(_load(tmp_path, text.format('["acceleration"]')), out)
    manifest = json.loads((out / "manifest.json").read_text())
    assert (out / "results_force").is_dir() and "results_force/" in manifest["datasets"]
    assert any(note.startswith("kept results_force/") for note in manifest["notes"])


@pytest.mark.parametrize(
    ("text", "argument"),
    [
        (f"{ROBOT}{POINT}[output]\ndigits = 0\n", "output.digits"),
        (f'{ROBOT}{POINT}[output]\nhistograms = ["coverage"]\n', "output.histograms"),
        (
            f"{ROBOT}[grid]\nq1 = 0\nq2 = {{ start = 0, stop = 1, num = 0 }}\nq3 = 0\n",
            "grid.q2.num",
        ),
        (f"{ROBOT}", "s.toml"),
        (f"{ROBOT}{POINT}[compare]\ncapacities = []\n", "compare.capacities"),
    ],
)
def test_study_file_errors_carry_a_fix(tmp_path, text, argument):
    with pytest.raises(pe.InputError) as caught:
        _load(tmp_path, text)
    assert caught.value.argument == argument and caught.value.fix, str(caught.value)


def test_missing_study_file_and_interactive_errors_carry_a_fix(tmp_path):
    import pandas as pd

    from polyell.interactive import interactive_histogram, interactive_map

    with pytest.raises(pe.InputError, match="Fix: check the name"):
        load_study(tmp_path / "nope.toml")
    frame = pd.DataFrame({"q2": [0.0, 1.0], "q3": [0.0, 1.0], "chiacchio_coverage": [0.5, 0.6]})
    for call in (
        lambda: interactive_histogram(frame, None),
        lambda: interactive_map(frame, None, "q2", "q3"),
        lambda: interactive_map(frame, "chiacchio_coverage", "q2", "q2"),
        lambda: interactive_map(frame, "chiacchio_coverag", "q2", "q3"),
    ):
        with pytest.raises(pe.InputError) as caught:
            call()
        assert caught.value.fix, str(caught.value)


def test_a_refused_run_leaves_the_previous_runs_manifest_as_it_was(tmp_path):
    """The recheck's case: a finished grid study, then the same file with other torque
    limits into the same folder, refused (its dataset holds a different sweep); the folder
    keeps the first run's manifest, not one marked incomplete that the next run would have
    taken for its own (removing the first run's finished outputs)."""
    out = tmp_path / "out"
    run_study(_load(tmp_path, GRID, "grid.toml"), out)
    before = (out / "manifest.json").read_text()
    other = GRID.replace(
        'library = "chiacchio2000"', 'library = "chiacchio2000"\ntau_max = [50, 20, 5]'
    )
    assert other != GRID
    with pytest.raises(pe.InputError, match="holds a different sweep"):
        run_study(_load(tmp_path, other, "grid.toml"), out)
    assert (out / "manifest.json").read_text() == before
    assert json.loads(before).get("complete") is not False
