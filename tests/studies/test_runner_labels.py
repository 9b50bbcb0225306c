"""A study names each set the same way in every output: tables, figures, summary, numbers, report.

Issue 32: ``[output] labels`` (a preset's name or a mapping) reaches the figures' legends
(read from the matplotlib figures the study saves, and from the SVG files), the summary
tables, ``numbers.md`` (:func:`polyell.report.format_analysis`), ``scores.csv`` and the
interactive report; the captions do not start with the study's title.  Every study here is
small and seeded (``[compare] seed``, ``[posture] seed``) and written into ``tmp_path``.
"""

from __future__ import annotations

import re
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import polyell.figures
from polyell.comparison.labels import LABEL_PRESETS, QUANTITIES, SET_LABELS, set_label
from polyell.studies import load_study, run_study

#: The custom labels of the tests: every set the studies draw, a candidate and a score.
CUSTOM = {
    "polytope": "exact set P",
    "chiacchio": "DME",
    "yoshikawa": "YME",
    "mvie": "best inscribed",
    "outer": "smallest enclosing",
    "heavy_wrist": "wrist-weighted",
    "coverage": "share covered",
}
SETS = ("polytope", "chiacchio", "yoshikawa", "mvie", "outer", "heavy_wrist")
#: The points study's comparison table is wider than a page with six sets (said, not failed).
pytestmark = pytest.mark.filterwarnings("ignore::polyell.errors.TableWidthWarning")


def _toml_labels(labels: dict[str, str] | str) -> str:
    if isinstance(labels, str):
        return f'"{labels}"'
    return "{ " + ", ".join(f'{key} = "{value}"' for key, value in labels.items()) + " }"


def _study(tmp_path: Path, name: str, body: str, labels: dict[str, str] | str | None) -> Path:
    """A study file in ``tmp_path``: ``body`` and an ``[output]`` with these ``labels``."""
    text = textwrap.dedent(body)
    if labels is not None:
        text += f"labels = {_toml_labels(labels)}\n"
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


POINTS = """
    title = "Label check"
    [robot]
    library = "chiacchio2000"
    [[points]]
    name = "redundant"
    q = ["pi/2", "-pi/2", "-pi/2"]
    directions = ["x", "y"]
    [[candidates]]
    name = "heavy_wrist"
    weighting = [1, 1, 4]
    [compare]
    directions = 36
    samples = 512
    seed = 3
    [output]
    formats = ["svg", "html"]
    dpi = 30
"""

GRID = """
    title = "Label grid"
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = { start = "-pi/2", stop = 0, num = 3 }
    q3 = { start = "-pi/2", stop = "pi/2", num = 3 }
    [[candidates]]
    name = "heavy_wrist"
    weighting = [1, 1, 4]
    [compare]
    directions = 24
    samples = 256
    seed = 5
    outer = false
    [output]
    formats = ["svg", "html"]
    dpi = 30
    maps = ["chiacchio_coverage", "heavy_wrist_coverage"]
    histograms = ["coverage"]
"""

TRAJECTORY = """
    title = "Label path"
    [robot]
    library = "chiacchio2000"
    [trajectory]
    file = "path.csv"
    [compare]
    directions = 12
    samples = 256
    mvie = false
    outer = false
    [output]
    formats = ["svg", "html"]
    dpi = 30
    series = ["coverage"]
"""

POSTURE = """
    title = "Label posture"
    [robot]
    library = "chiacchio2000"
    [posture]
    q0 = ["pi/2", "-pi/2", "-pi/2"]
    direction = "x"
    count = 12
    seed = 7
    [compare]
    mvie = false
    outer = false
    [output]
    formats = ["svg"]
    dpi = 30
"""


@pytest.fixture
def legends(monkeypatch: pytest.MonkeyPatch) -> dict[str, set[str]]:
    """The legend entries of every figure a study saves, by file stem (from matplotlib)."""
    seen: dict[str, set[str]] = {}
    save = polyell.figures.save_figure

    def capture(figure: Any, stem: Any, *args: Any, **kwargs: Any) -> Any:
        entries: set[str] = set()
        for legend in [*figure.legends, *(ax.get_legend() for ax in figure.axes)]:
            if legend is not None:
                entries |= {text.get_text() for text in legend.get_texts()}
        titles = {ax.get_title() for ax in figure.axes} | {ax.get_xlabel() for ax in figure.axes}
        seen[Path(stem).name] = entries | {f"title: {title}" for title in titles if title}
        return save(figure, stem, *args, **kwargs)

    monkeypatch.setattr(polyell.figures, "save_figure", capture)
    return seen


def _defaults_absent(text: str, kinds: tuple[str, ...]) -> None:
    """None of the default labels of ``kinds`` that the custom ones replace is in ``text``.

    The scores' labels that name a set (``"volume / MVIE volume"``) are a score's label,
    renamed by the score's key: they are left out of the check.
    """
    text = text.replace("\\u002f", "/")  # (plotly's JSON escapes the slash)
    names = {name for q in QUANTITIES.values() for name in (q.plain, q.latex)}
    for name in sorted(names, key=len, reverse=True):  # "volume / MVIE volume" first
        text = text.replace(name, "")
    for kind in kinds:
        default = SET_LABELS.get(kind, kind)
        if default != "polytope":  # (a word of the captions, too)
            assert default not in text, (kind, default)


def _svg_texts(path: Path) -> str:
    """The text of an SVG file of matplotlib: its glyphs carry the text as comments."""
    return " ".join(re.findall(r"<!-- (.*?) -->", path.read_text()))


def test_a_points_study_names_each_set_by_its_labels_everywhere(tmp_path, legends):
    out = tmp_path / "out"
    run_study(load_study(_study(tmp_path, "points", POINTS, CUSTOM)), out)
    custom_sets = {CUSTOM[kind] for kind in SETS}
    # figures: the legend of the sets' figure and of the polar plot name every set drawn
    for stem in ("sets_redundant", "limits_redundant"):
        assert custom_sets <= legends[stem], (stem, legends[stem])
        assert not {SET_LABELS[k] for k in SETS if k in SET_LABELS} & legends[stem] - {"polytope"}
        svg = _svg_texts(out / f"{stem}.svg")
        for label in custom_sets:
            assert label in svg, (stem, label)
    # tables, scores.csv, numbers.md and the report: the same names
    for name in ("comparison.md", "comparison.csv", "limits.md", "scores.csv", "numbers.md"):
        text = (out / name).read_text()
        for kind in ("chiacchio", "yoshikawa", "mvie", "heavy_wrist"):
            assert CUSTOM[kind] in text, (name, kind)
        _defaults_absent(text, ("chiacchio", "yoshikawa", "mvie", "outer"))
    numbers = (out / "numbers.md").read_text()
    assert "Ellipsoid DME: rank 2" in numbers and "Ellipsoid 'chiacchio'" not in numbers
    assert re.search(r"^  YME +\[", numbers, re.MULTILINE)  # a limit's line
    assert "eq." not in numbers  # the paper's equation numbers only with its preset
    assert "share covered [%]" in (out / "comparison.md").read_text()
    report = (out / "report.html").read_text()
    for label in custom_sets | {"share covered"}:
        assert label in report, label
    _defaults_absent(report, ("chiacchio", "yoshikawa", "mvie", "outer"))
    # the captions do not start with the study's title
    for name in ("comparison.tex", "limits.tex"):
        caption = re.search(r"\\caption\{(.*)\}", (out / name).read_text())
        assert caption is not None and not caption.group(1).startswith("Label check")


def test_the_papers_preset_names_the_sets_and_numbers_as_the_paper(tmp_path, legends):
    out = tmp_path / "out"
    run_study(load_study(_study(tmp_path, "points", POINTS, "chiacchio2000")), out)
    preset = LABEL_PRESETS["chiacchio2000"]
    names = {kind: str(preset[kind]) for kind in ("polytope", "chiacchio", "yoshikawa")}
    assert set(names.values()) <= legends["sets_redundant"]
    numbers = (out / "numbers.md").read_text()
    assert "xdd_g (eq. 8)" in numbers and "M (eq. 14)" in numbers
    assert f"{names['polytope'][:1].upper()}{names['polytope'][1:]}: dimension 2" in numbers
    assert f"Ellipsoid {names['chiacchio']}: rank 2" in numbers
    assert f"  {names['chiacchio']}, eq. 33/40: qdd = " in numbers
    assert f"  {names['yoshikawa']}, eq. 26: qdd = " in numbers
    for name in ("comparison.md", "limits.md", "scores.csv"):
        text = (out / name).read_text()
        assert names["chiacchio"] in text and names["yoshikawa"] in text, name
        assert "Chiacchio" not in text and "Yoshikawa" not in text, name
    # without labels: the default names, and no equation numbers
    plain = tmp_path / "plain"
    run_study(load_study(_study(tmp_path, "plain", POINTS, None)), plain)
    numbers = (plain / "numbers.md").read_text()
    assert f"Ellipsoid {set_label('chiacchio')}: rank 2" in numbers and "eq." not in numbers
    assert set_label("chiacchio") in legends["sets_redundant"]


def test_a_grid_study_labels_its_summary_maps_histograms_and_report(tmp_path, legends):
    out = tmp_path / "out"
    run_study(load_study(_study(tmp_path, "grid", GRID, CUSTOM)), out)
    kinds = ("chiacchio", "yoshikawa", "heavy_wrist")
    drawn = {entry.split(" (median ")[0] for entry in legends["histogram_coverage"]}
    assert {CUSTOM[k] for k in kinds} <= drawn  # "DME (median 59.7)"
    assert f"title: {CUSTOM['chiacchio']}: share covered [%]" in legends["map_chiacchio_coverage"]
    assert (
        f"title: {CUSTOM['heavy_wrist']}: share covered [%]" in legends["map_heavy_wrist_coverage"]
    )
    for name in ("summary.md", "summary.tex", "report.html"):
        text = (out / name).read_text()
        for kind in (*kinds, "mvie"):
            assert CUSTOM[kind] in text, (name, kind)
        assert "share covered" in text, name
        _defaults_absent(text, ("chiacchio", "yoshikawa", "mvie"))
    caption = re.search(r"\\caption\{(.*)\}", (out / "summary.tex").read_text())
    assert caption is not None and not caption.group(1).startswith("Label grid")
    assert "9 configurations" in caption.group(1)


def test_a_trajectory_and_a_posture_study_label_their_figures(tmp_path, legends):
    rng = np.random.default_rng(11)
    t = np.linspace(0.0, 0.4, 5)
    q = np.array([1.2, -1.0, -0.8]) + 0.1 * rng.standard_normal((5, 3))
    qd = rng.standard_normal((5, 3))
    rows = ["t,q1,q2,q3,qd1,qd2,qd3"]
    rows += [",".join(f"{v:.12g}" for v in (t[i], *q[i], *qd[i])) for i in range(5)]
    (tmp_path / "path.csv").write_text("\n".join(rows) + "\n")
    labels = {key: CUSTOM[key] for key in ("polytope", "chiacchio", "yoshikawa", "coverage")}
    out = tmp_path / "path"
    run_study(load_study(_study(tmp_path, "path", TRAJECTORY, labels)), out)
    drawn = {labels["chiacchio"], labels["yoshikawa"]}
    assert drawn <= legends["series_coverage"]
    assert drawn | {labels["polytope"]} <= legends["tangent_limits"]
    for name in ("summary.md", "report.html"):
        text = (out / name).read_text()
        assert all(label in text for label in drawn), name
        _defaults_absent(text, ("chiacchio", "yoshikawa"))
    out = tmp_path / "posture"
    run_study(load_study(_study(tmp_path, "posture", POSTURE, labels)), out)
    assert drawn <= legends["posture_indices"]
    assert f"{labels['polytope']} (truth)" in legends["posture_indices"]
    for name in ("posture_choice.md", "posture_choice.tex"):
        text = (out / name).read_text()
        assert all(label in text for label in drawn), name
        _defaults_absent(text, ("chiacchio", "yoshikawa"))
    tex = (out / "posture_choice.tex").read_text()
    caption = re.search(r"\\caption\{(.*)\}", tex)
    assert caption is not None and not caption.group(1).startswith("Label posture")
