"""Every shipped study's LaTeX tables compile in a one-column article as they are, and fit.

Each study of ``studies/`` is run (smaller: fewer configurations and directions, cheap
figures; the tables keep their layout) and every ``.tex`` file it writes is compiled with
pdfLaTeX in a plain ``article`` with ``booktabs``, at the default margins: no error, no
overfull box, no float too large (:func:`latex_check.fit_warnings`).  Where no LaTeX engine
is installed the test skips and says so (``.ci/run`` installs one).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from latex_check import engine, fit_warnings

from polyell.studies import load_study, run_study

REPO = Path(__file__).resolve().parents[2]
SHIPPED = sorted((REPO / "studies").glob("*.toml"))
#: What makes a shipped study quick here without changing its tables' layout.
SMALLER = (
    (r"count = \d+", "count = 16"),
    (r"(?m)^directions = \d+", "directions = 32"),
    (r"formats = \[[^\]]*\]", 'formats = ["svg"]'),
    (r"dpi = \d+", "dpi = 20"),
)


def test_every_study_is_covered():
    names = {path.stem for path in SHIPPED}
    assert {"chiacchio2000", "panda_postures", "two_robots", "panda_random"} <= names


@pytest.mark.parametrize("study", SHIPPED, ids=lambda path: path.stem)
def test_shipped_study_tables_compile_and_fit_a_one_column_page(study, tmp_path):
    pdflatex = engine("pdflatex")
    if pdflatex is None:
        pytest.skip("pdflatex is not installed (.ci/run installs it)")
    text = study.read_text()
    for pattern, replacement in SMALLER:
        text = re.sub(pattern, replacement, text)
    copy = study.parent / study.name  # relative paths (trajectories) stay valid: same folder
    spec_path = tmp_path / study.name
    spec_path.write_text(text)
    for data in study.parent.glob(f"{study.stem}*"):  # a study's own data files
        if data.suffix != ".toml":
            (tmp_path / data.name).write_bytes(data.read_bytes())
    assert copy.exists()
    out = tmp_path / "out"
    run_study(load_study(spec_path), out)
    tables = sorted(out.glob("*.tex"))
    assert tables, "a study writes at least one LaTeX table"
    for table in tables:
        warnings = fit_warnings(pdflatex, [table.read_text()], tmp_path / f"tex_{table.stem}")
        assert not warnings, f"{study.stem}/{table.name}: {warnings}"
