from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.studies import load_study, run_study
from reference import PAPER_Q_REDUNDANT, paper_analysis

REPO = Path(__file__).resolve().parents[2]

SMALL_GRID = """
    title = "small"
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = { start = "-pi/2", stop = 0, num = 3 }
    q3 = { start = "-pi/2", stop = "pi/2", num = 4 }
    [compare]
    directions = 36
    mvie = false
    [output]
    formats = ["png"]
    dpi = 50
    maps = ["chiacchio_coverage", "yoshikawa_inscribed_scale"]
"""


@pytest.fixture(scope="module")
def paper_study(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("paper")
    run_study(load_study(REPO / "studies" / "chiacchio2000.toml"), out)
    return out


def test_paper_study_writes_numbers_tables_and_figures(paper_study):
    manifest = json.loads((paper_study / "manifest.json").read_text())
    for name in (
        "numbers.md",
        "comparison.md",
        "comparison.tex",
        "comparison.csv",
        "sets_redundant.pdf",
        "sets_redundant.png",
        "sets_singular.pdf",
        "limits_redundant.png",
    ):
        assert name in manifest["files"] and (paper_study / name).stat().st_size > 0
    numbers = (paper_study / "numbers.md").read_text()
    for printed in ("-12.392", "[-43.401, 35.284]", "[-70.922, 52.69]", "1.5281", "61.806"):
        assert printed in numbers


def test_paper_study_table_equals_compare(paper_study):
    table = pd.read_csv(paper_study / "comparison.csv", index_col="ellipsoid")
    expected = pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 360)
    for name in pe.SCORE_NAMES:
        np.testing.assert_allclose(
            table.loc["redundant: new (eq. 32/38)", name], getattr(expected["chiacchio"], name)
        )
    assert np.isnan(table.loc["singular: classic (eq. 27)", "coverage"])


def test_grid_study_results_and_maps(tmp_path):
    spec_path = tmp_path / "grid.toml"
    spec_path.write_text(textwrap.dedent(SMALL_GRID))
    out = tmp_path / "out"
    run_study(load_study(spec_path), out)
    results = pd.read_csv(out / "results.csv")
    assert len(results) == 12
    arm = pe.robots.load("chiacchio2000")
    row = results.iloc[5]
    q = row[["q1", "q2", "q3"]].to_numpy(dtype=float)
    expected = pe.compare(pe.analyze(arm.dynamics(q), arm.tau_max), 36, mvie=False)
    assert row["chiacchio_coverage"] == pytest.approx(expected["chiacchio"].coverage)
    summary = pd.read_csv(out / "summary.csv", index_col=[0, 1])
    assert summary.loc[("chiacchio", "coverage"), "mean"] == pytest.approx(
        results["chiacchio_coverage"].mean()
    )
    assert (out / "map_chiacchio_coverage.png").exists()
    assert (out / "map_yoshikawa_inscribed_scale.png").exists()


def test_unwritable_output_folder(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(pe.InputError, match="out: expected a folder polyell can write to"):
        run_study(load_study(REPO / "studies" / "chiacchio2000.toml"), blocker / "sub")


RANDOM_PANDA = """
    title = "panda"
    [robot]
    library = "panda"
    [random]
    count = 6
    seed = 3
    [compare]
    directions = 50
    mvie = false
    [output]
    formats = ["png"]
    dpi = 40
    histograms = ["coverage", "witness_torque_max"]
"""


def test_random_study_of_a_real_robot(tmp_path):
    spec_path = tmp_path / "panda.toml"
    spec_path.write_text(textwrap.dedent(RANDOM_PANDA))
    spec = load_study(spec_path)
    q = spec.configurations()
    low, high = spec.robot.model.position_limits
    assert q.shape == (6, 7) and np.all((q >= low) & (q <= high))
    np.testing.assert_array_equal(q, load_study(spec_path).configurations())  # seeded
    out = tmp_path / "out"
    run_study(spec, out)
    results = pd.read_csv(out / "results.csv")
    robot = pe.robots.load("panda")
    expected = pe.compare(pe.analyze(robot.dynamics(q[2]), robot.tau_max), 50, mvie=False)
    assert results.loc[2, "yoshikawa_coverage"] == pytest.approx(expected["yoshikawa"].coverage)
    assert (out / "histogram_coverage.png").exists()
    assert (out / "histogram_witness_torque_max.png").exists()


def test_the_shipped_panda_study_parses():
    spec = load_study(REPO / "studies" / "panda_random.toml")
    assert spec.configurations().shape == (300, 7)
    assert spec.robot.model.joint_names[-1] == "panda_joint7"
