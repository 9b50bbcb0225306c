"""``[output] captions``, ``siunitx`` and ``text_width`` (issue 32): a study file lays out its
LaTeX tables as ``pe.TableLayout(captions=, siunitx=, text_width=)`` does.

Each key reaches every table a study writes (a points study's limits and comparison of every
capacity, a sweep's summary, a posture study's choice and its aggregate over targets); a bad
value is refused by name when the file loads, before anything is written.  Every study is
small, seeded and written into ``tmp_path``.
"""

from __future__ import annotations

import importlib.util
import re
import textwrap
import warnings
from pathlib import Path

import pytest
from latex_check import engine, fit_warnings

import polyell as pe
from polyell.comparison.layout import TEXT_WIDTH
from polyell.comparison.write_latex import table_width
from polyell.errors import TableWidthWarning
from polyell.studies import load_study, run_study

REPO = Path(__file__).resolve().parents[2]

POINTS = """
    title = "Output keys"
    [robot]
    library = "chiacchio2000"
    [[points]]
    name = "redundant"
    q = ["pi/2", "-pi/2", "-pi/2"]
    directions = ["x", "y"]
    [[points]]
    name = "other"
    q = [0.3, 0.8, -0.4]
    directions = ["x"]
    [compare]
    directions = 24
    samples = 256
    seed = 4
    capacities = ["acceleration", "force"]
    [output]
    formats = ["png"]
    dpi = 20
"""

GRID = """
    title = "Output keys grid"
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = { start = -1, stop = 0, num = 2 }
    q3 = { start = -1, stop = 1, num = 2 }
    [compare]
    directions = 12
    samples = 256
    seed = 2
    mvie = false
    outer = false
    [output]
    formats = ["png"]
    dpi = 20
"""

POSTURE = """
    title = "Output keys posture"
    [robot]
    library = "chiacchio2000"
    [posture]
    q0 = ["pi/2", "-pi/2", "-pi/2"]
    direction = "x"
    count = 8
    seed = 3
    targets = 2
    [compare]
    mvie = false
    outer = false
    [output]
    formats = ["png"]
    dpi = 20
"""


def _study(tmp_path: Path, body: str, output: str = "", name: str = "study") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(textwrap.dedent(body) + textwrap.dedent(output))
    return path


def _captions(tex: str) -> list[str]:
    return re.findall(r"^\\caption\{(.*)\}$", tex, flags=re.MULTILINE)


def _column_specs(tex: str) -> list[str]:
    return re.findall(r"^\\begin\{tabular\}\{(.*)\}$", tex, flags=re.MULTILINE)


def _widths(tex: str) -> list[float]:
    floats = re.findall(r"\\begin\{table\}.*?\\end\{table\}", tex, flags=re.S)
    return [table_width(block.splitlines()) for block in floats]


def test_a_points_study_writes_the_users_captions_and_siunitx_columns(tmp_path):
    output = r"""
    siunitx = true
    [output.captions]
    limits = "Accelerations along x and y."
    comparison_force = ["Force scores.", "Scores of the force sets, $h$ in N."]
    """
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)  # 345 pt: every table fits
        run_study(load_study(_study(tmp_path, POINTS, output)), out)
    limits, comparison = (out / "limits.tex").read_text(), (out / "comparison.tex").read_text()
    force = (out / "comparison_force.tex").read_text()
    assert _captions(limits) == ["Accelerations along x and y."]
    assert _captions(force) == ["Scores of the force sets, $h$ in N."]
    # a table without a caption of its own keeps its default (not another table's)
    assert _captions(comparison) == ["Scores of each ellipsoid against the exact polytope."]
    assert _captions((out / "limits_force.tex").read_text())[0].startswith("Directional force")
    # siunitx: S columns in every table (after the stub's l columns), negative numbers bare
    for name in ("limits", "comparison", "limits_force", "comparison_force"):
        specs = _column_specs((out / f"{name}.tex").read_text())
        assert specs and all(re.fullmatch(r"l+(?:S(?:\[[^\]]*\])?)+", spec) for spec in specs)
    assert re.search(r"& -[0-9]", limits) and not re.search(r"& \$-\$[0-9]", limits)
    # the Markdown shows the plain caption under its heading
    assert "Force scores." in (out / "comparison_force.md").read_text()


def test_text_width_is_the_threshold_of_the_width_warning(tmp_path):
    out = tmp_path / "narrow"
    with pytest.warns(TableWidthWarning, match=r"than the text width 200 pt") as caught:
        run_study(load_study(_study(tmp_path, POINTS, "text_width = 200\n", "narrow")), out)
    texts = [(out / f"{name}.tex").read_text() for name in ("limits", "comparison")]
    wide = [w for tex in texts for w in _widths(tex) if w > 200]
    assert wide and len(caught) >= len(wide)
    assert all(200 < w <= TEXT_WIDTH for w in wide)  # they fit 345 pt: 200 is the threshold
    # the default: r columns, checked against 345 pt (every table fits)
    default = tmp_path / "default"
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)
        run_study(load_study(_study(tmp_path, POINTS, "", "default")), default)
    limits = (default / "limits.tex").read_text()
    assert all(set(spec) <= set("lr") for spec in _column_specs(limits))
    # false: no check, no warning, and here the default's tables
    free = tmp_path / "unchecked"
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)
        run_study(load_study(_study(tmp_path, POINTS, "text_width = false\n", "free")), free)
    assert (free / "limits.tex").read_text() == limits


def test_a_grid_and_a_posture_study_caption_their_tables(tmp_path):
    output = (
        'captions = { summary = ["Scores over the grid.", "Scores over $q_2 \\\\times q_3$."] }\n'
    )
    output += "siunitx = true\ntext_width = 400\n"
    out = tmp_path / "grid"
    run_study(load_study(_study(tmp_path, GRID, output, "grid")), out)
    summary = (out / "summary.tex").read_text()
    assert _captions(summary) == [r"Scores over $q_2 \times q_3$."]
    assert "Scores over the grid." in (out / "summary.md").read_text()
    assert all("S[" in spec for spec in _column_specs(summary))
    output = 'captions = { posture_choice = "The pick of each index.", posture_targets = '
    output += '"Regret over two targets." }\nsiunitx = true\n'
    out = tmp_path / "posture"
    run_study(load_study(_study(tmp_path, POSTURE, output, "posture")), out)
    choice = (out / "posture_choice.tex").read_text()
    targets = (out / "posture_targets.tex").read_text()
    assert _captions(choice) == [  # (the picks' joint positions: a second float)
        "The pick of each index.",
        "Joint positions of each posture picked. The pick of each index.",
    ]
    assert _captions(targets) == ["Regret over two targets."]
    for tex in (choice, targets):
        assert all("S[" in spec for spec in _column_specs(tex))
    assert "The pick of each index." in (out / "posture_choice.md").read_text()


def test_several_robots_get_the_summary_caption_with_their_names(tmp_path):
    body = GRID.replace(
        '[robot]\n    library = "chiacchio2000"',
        '[[robots]]\n    name = "left"\n    library = "chiacchio2000"\n'
        '    [[robots]]\n    name = "right"\n    library = "chiacchio2000"\n'
        "    tau_max = [80, 30, 4]",
    )
    out = tmp_path / "two"
    run_study(load_study(_study(tmp_path, body, 'captions = { summary = "Scores." }\n')), out)
    assert _captions((out / "summary.tex").read_text()) == ["Scores. (left)", "Scores. (right)"]


@pytest.mark.parametrize(
    ("output", "message"),
    [
        ('captions = { limit = "x" }', r"output\.captions\.limit: expected a key that names"),
        ('captions = { limits = "" }', r"output\.captions\.limits: expected a caption that"),
        ('captions = { limits = ["x", " "] }', r"output\.captions\.limits\[1\]: expected a"),
        ('captions = { limits = ["x"] }', r"output\.captions\.limits: expected a caption"),
        ("captions = { limits = 3 }", r"output\.captions\.limits: expected a caption"),
        ('captions = { limits = ["x", "a & b"] }', r"output\.captions\.limits\[1\]: .*'&'"),
        ('captions = { limits = ["x", "{x"] }', r"output\.captions\.limits\[1\]: .*braces"),
        ('captions = "Limits."', r"output\.captions: expected a table of captions"),
        ('captions = { summary = "x" }', r"output\.captions\.summary: expected a table that a"),
        (
            'captions = { comparison_velocity = "x" }',
            r"output\.captions\.comparison_velocity: .*did you mean 'comparison_force'",
        ),
        ('siunitx = "yes"', r"output\.siunitx: expected true or false"),
        ("siunitx = 1", r"output\.siunitx: expected true or false"),
        ("text_width = 0", r"output\.text_width: expected a width in pt"),
        ("text_width = -345", r"output\.text_width: expected a width in pt"),
        ("text_width = 1e9", r"output\.text_width: expected a width in pt"),
        ("text_width = true", r"output\.text_width: expected a width in pt.*got bool"),
        ('text_width = "345pt"', r"output\.text_width: expected a width in pt.*got str"),
        ("text_width = nan", r"output\.text_width: expected a width in pt"),
        ("textwidth = 345", r"did you mean 'text_width' for 'textwidth'"),
        ("caption = {}", r"did you mean 'captions' for 'caption'"),
    ],
)
def test_bad_values_are_refused_by_name_when_the_file_loads(tmp_path, output, message):
    path = _study(tmp_path, POINTS, output + "\n")
    with pytest.raises(pe.InputError, match=message) as raised:
        load_study(path)
    error = raised.value
    assert error.argument.startswith("output") and error.expected and error.got
    assert error.fix, str(error)  # each message says how to mend the file


def test_a_posture_study_without_targets_refuses_their_caption(tmp_path):
    body = POSTURE.replace("targets = 2\n", "")
    path = _study(tmp_path, body, 'captions = { posture_targets = "x" }\n')
    with pytest.raises(
        pe.InputError, match=r"output\.captions\.posture_targets: .*\['posture_choice'\]"
    ):
        load_study(path)


@pytest.mark.skipif(importlib.util.find_spec("pinocchio") is None, reason="extra robots")
def test_the_panda_three_posture_tables_paste_into_a_one_column_article(tmp_path):
    """The README's workflow: studies/panda_postures.toml with forces beside accelerations.

    Every table fits 345 pt (no TableWidthWarning), and pdfLaTeX (where installed) sets
    them in a one-column ``article`` without an overfull box or a float too large.
    """
    shipped = (REPO / "studies" / "panda_postures.toml").read_text()
    text = shipped.replace(
        "outer = true\n", 'outer = true\ncapacities = ["acceleration", "force"]\n'
    )
    text = re.sub(r"formats = \[.*\]", 'formats = ["png"]', text).replace("dpi = 200", "dpi = 20")
    assert "capacities" in text
    study = tmp_path / "panda_postures.toml"
    study.write_text(text)
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("error", TableWidthWarning)
        run_study(load_study(study), out)
    names = ("limits", "comparison", "limits_force", "comparison_force")
    tables = [(out / f"{name}.tex").read_text() for name in names]
    widths = [width for tex in tables for width in _widths(tex)]
    assert len(widths) == 8 and max(widths) <= TEXT_WIDTH  # (limits: one float per posture)
    assert "$\\pm$" in tables[3]  # the force table's Monte Carlo estimates, with their errors
    program = engine("pdflatex")
    if program is None:
        pytest.skip("pdflatex is not installed; the width estimates were the check")
    assert fit_warnings(program, tables, tmp_path / "latex") == []
