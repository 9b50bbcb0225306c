"""Printed tables compile, keep every row, and fit a one-column page by default.

The fit is measured by pdfLaTeX in the standard article class (default margins,
``\\textwidth``): no overfull box and no float too large for the page.  Where pdfLaTeX is
missing these tests skip and say so (CI installs it); the parser checks of
test_print_writers.py run everywhere.
"""

from __future__ import annotations

import csv
import io
import re
from decimal import Decimal

import numpy as np
import pandas as pd
import pytest
from latex_check import compile_tables, engine, fit_warnings
from latex_numbers import parse_all as parse_tables
from latex_numbers import pdf_pattern

import polyell as pe
from polyell.comparison.point_tables import write_point_tables
from polyell.comparison.tables import format_comparison_table, format_limits_table
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis

POSTURES = {
    "home": [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785],
    "reach": [0.3, 0.2, 0.0, -1.5, 0.0, 1.8, 0.7],
    "low": [0.0, 0.5, 0.0, -1.0, 0.0, 1.5, 0.0],
}


def pdflatex() -> str:
    path = engine("pdflatex")
    if path is None:
        pytest.skip("pdflatex is not installed (CI installs it: .ci/run); the parser checks ran")
    return path


@pytest.fixture(scope="module")
def panda() -> dict[str, pe.Comparison]:
    robot = pe.robots.load("panda")
    return {
        name: pe.compare(pe.analyze(robot.dynamics(q), robot.tau_max), 64, samples=256)
        for name, q in POSTURES.items()
    }


@pytest.mark.parametrize("split", ["combined", "posture"])
def test_the_default_tables_of_three_postures_fit_a_one_column_page(panda, tmp_path, split):
    layout = pe.TableLayout(split=split)
    tables = [
        format_comparison_table(panda, "latex", layout=layout, caption="Scores", label="t:c"),
        format_limits_table(pe.limits_table(panda), "latex", layout=layout, caption="Limits"),
        format_limits_table(
            pe.limits_table(panda, ["x", "y", "z", "xy", "-z"]), "latex", layout=layout
        ),
    ]
    assert fit_warnings(pdflatex(), tables, tmp_path) == []


def test_a_transposed_table_is_wide_and_says_so_through_the_log(panda, tmp_path):
    # Sets as columns with four quantities each do not fit: the default is sets as rows.
    with pytest.warns(UserWarning, match=r"pt wide, \d+ pt wider than the text width 345 pt"):
        wide = format_limits_table(
            pe.limits_table(panda), "latex", layout=pe.TableLayout(transpose=True)
        )
    assert any("Overfull" in line for line in fit_warnings(pdflatex(), [wide], tmp_path))
    narrow = pe.TableLayout(
        transpose=True, sets=["polytope", "chiacchio"], scores=["lower", "upper"]
    )
    table = format_limits_table(pe.limits_table(panda), "latex", layout=narrow)
    assert fit_warnings(pdflatex(), [table], tmp_path / "narrow") == []


def numbers_in(text: str, cells: list[str]) -> bool:
    """Whether one line of the PDF's text holds the row's cells (numbers, n/a) in order."""
    pattern = r".*".join(pdf_pattern(cell.replace(" ± ", " ")) for cell in cells)
    flat = text.replace("\N{PLUS-MINUS SIGN}", " ")
    return any(re.search(pattern, line) for line in flat.splitlines())


@pytest.mark.filterwarnings("ignore:The LaTeX table")  # (transposed ones are wide, and say so)
def test_a_sample_of_layouts_compiles_and_every_row_survives_pdftotext(panda, tmp_path):
    program = pdflatex()
    rng = np.random.default_rng(24)
    hostile = r"a_b & 50% #1 {x} ~^ \input $"
    singular = pe.compare(paper_analysis(PAPER_Q_SINGULAR), 16, samples=256)
    paper = pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 16, samples=256)
    comparisons = {hostile: paper, "singular": singular}
    tables = []
    for _ in range(6):
        layout = pe.TableLayout(
            transpose=bool(rng.integers(2)),
            split=str(rng.choice(["combined", "posture"])),
            digits=int(rng.integers(1, 18)),
            percent=bool(rng.integers(2)),
        )
        tables.append(format_comparison_table(comparisons, "latex", layout=layout, caption=hostile))
        frame = pe.limits_table(comparisons, ["x", "-y", "xy"])
        tables.append(format_limits_table(frame, "latex", layout=layout, label="tab:x_1"))
    text = compile_tables(program, tables, tmp_path)
    if not text:
        pytest.skip("pdftotext is not installed; the engine's clean log was the check")
    for tex in tables:
        for table in parse_tables(tex):
            for row in table.rows:
                assert numbers_in(text, row[table.stub :]), row
    # pdftotext reads \_ as a space and ~ ^ as their accents
    assert "a b & 50% #1 {x} \N{SMALL TILDE}\N{MODIFIER LETTER CIRCUMFLEX ACCENT} \\input $" in text


def test_the_comparison_table_shows_the_scores_of_the_comparison(panda):
    records = list(csv.reader(io.StringIO(format_comparison_table(panda, "csv"))))
    header = records[0]
    assert header[:2] == ["posture", "score"]
    assert header[2:] == ["Chiacchio", "Yoshikawa", "MVIE", "outer (min. volume)"]
    kinds = ["chiacchio", "yoshikawa", "mvie", "outer"]
    checked = 0
    for posture, score, *values in records[1:]:
        if score.startswith("coverage"):
            for kind, text in zip(kinds, values, strict=True):
                exact = Decimal(text).scaleb(-2)
                assert float(exact) == panda[posture][kind].coverage
                checked += 1
    assert checked == 3 * 4
    markdown = format_comparison_table(
        panda, "markdown", layout=pe.TableLayout(scores=["coverage"])
    )
    coverage = panda["reach"]["chiacchio"].coverage
    assert f"{100 * coverage:.3g}" in markdown.splitlines()[3]
    assert len(markdown.splitlines()) == 2 + 3  # header, rule, one row per posture


def test_write_point_tables_writes_both_tables_in_each_format(panda, tmp_path):
    written = write_point_tables(
        panda, {"reach": ["xy"]}, tmp_path, pe.TableLayout(), "Panda", ["tex", "md", "csv"]
    )
    assert sorted(p.name for p in written) == sorted(
        f"{name}.{ext}" for name in ("limits", "comparison") for ext in ("tex", "md", "csv")
    )
    limits = pd.read_csv(tmp_path / "limits.csv")
    assert list(limits.columns[:3]) == ["posture", "direction", "set"]
    assert set(limits["direction"]) == {"x", "y", "z", "x+y"}
    reach = limits[(limits["posture"] == "reach") & (limits["set"] == "polytope")]
    expected = panda["reach"].limits_table(["xy"], sets=["polytope"])
    assert reach["upper [m/s^2]"].iloc[0] == expected["upper"].iloc[0]  # exact round trip
    markdown = (tmp_path / "limits.md").read_text()
    assert markdown.startswith("# Panda: directional limits")
    tex = [(tmp_path / f"{name}.tex").read_text() for name in ("limits", "comparison")]
    assert r"\label{tab:limits}" in tex[0] and r"\label{tab:comparison}" in tex[1]
    assert fit_warnings(pdflatex(), tex, tmp_path / "fit") == []


def test_write_point_tables_writes_nothing_on_bad_input(panda, tmp_path):
    with pytest.raises(pe.InputError) as info:
        write_point_tables(panda, {"home": ["x", "up"]}, tmp_path)
    assert info.value.argument == "directions['home'][1]"
    with pytest.raises(pe.InputError) as info:
        write_point_tables(panda, None, tmp_path, pe.TableLayout(sets=["polytope", "mvi"]))
    assert info.value.argument == "layout.sets"
    with pytest.raises(pe.InputError) as info:
        write_point_tables(panda, None, tmp_path, formats=["tex", "pdf"])
    assert info.value.argument == "formats"
    with pytest.raises(pe.InputError) as info:
        write_point_tables(panda, None, tmp_path / "missing")
    assert info.value.argument == "folder"
    assert list(tmp_path.iterdir()) == []
