"""The interactive figures take ``labels=`` (issue 32): the names of sets and scores in their
legends, hover texts, titles, menus and axes, as a table layout's ``labels`` (or the layout).

One place labels the figures: the functions of :mod:`polyell.interactive`; the study runner
passes its layout to them (it no longer relabels figures afterwards).  Seeded comparisons of
the paper's arm; nothing is written.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import polyell as pe
import polyell.studies.runner as runner
from polyell.comparison.labels import SET_LABELS
from polyell.interactive import (
    interactive_histogram,
    interactive_map,
    interactive_series,
    interactive_sets,
)
from reference import PAPER_Q_REDUNDANT

LABELS = {
    "polytope": "exact set P",
    "chiacchio": "DME",
    "yoshikawa": "YME",
    "mvie": "best inscribed",
    "coverage": "share covered",
    "inscribed_scale": ("inside scale", r"$s_\mathrm{in}$"),
}


@pytest.fixture(scope="module")
def comparison() -> pe.Comparison:
    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics(PAPER_Q_REDUNDANT), arm.tau_max)
    return pe.compare(analysis, 36, samples=256, seed=1, outer=False)


@pytest.fixture(scope="module")
def results() -> pd.DataFrame:
    arm = pe.robots.load("chiacchio2000")
    grid = pe.grid(np.pi / 2, (-1.0, 0.0, 3), (-1.0, 1.0, 3))
    frame = pe.sweep(arm, grid, directions=12, samples=256, seed=2)
    return frame.assign(t=np.linspace(0.0, 1.0, len(frame)))


def _names(figure) -> set[str]:
    return {trace.name for trace in figure.data if trace.name}


def _hover(figure) -> str:
    texts = []
    for trace in figure.data:
        for key in ("text", "hovertext"):
            value = getattr(trace, key, None)
            if isinstance(value, str):
                texts.append(value)
            elif value is not None:
                texts += [str(item) for item in value]
    return "\n".join(texts)


@pytest.mark.parametrize("form", ["mapping", "layout"])
def test_the_sets_figure_names_every_set_and_score_by_the_labels(comparison, form):
    labels = LABELS if form == "mapping" else pe.TableLayout(labels=LABELS, digits=4)
    figure = interactive_sets(comparison, labels=labels)
    names = _names(figure)
    assert {"DME", "YME", "best inscribed"} <= names
    assert any(name.startswith("exact set P, volume ") for name in names)
    assert not {SET_LABELS[k] for k in ("chiacchio", "yoshikawa", "mvie")} & names
    hover = _hover(figure)
    assert "<b>DME</b>" in hover and "<b>YME</b>" in hover
    assert "share covered [%]" in hover and "inside scale " in hover  # the plain text
    assert "Chiacchio" not in hover
    # the defaults without labels
    plain = _names(interactive_sets(comparison))
    assert {"Chiacchio", "Yoshikawa", "MVIE"} <= plain


def test_a_preset_names_the_sets_as_the_paper(comparison):
    names = _names(interactive_sets(comparison, labels="chiacchio2000"))
    assert {"new (eq. 32/38)", "classic (eq. 27)"} <= names


def test_maps_histograms_and_series_take_the_labels(results):
    columns = ["chiacchio_coverage", "yoshikawa_coverage"]
    figure = interactive_map(results, columns, "q3", "q2", labels=LABELS)
    assert figure.layout.title.text == "DME: share covered [%]"
    assert figure.data[0].colorbar.title.text == "share covered [%]"
    menu = [button.label for button in figure.layout.updatemenus[0].buttons]
    assert menu == ["DME: share covered [%]", "YME: share covered [%]"]
    histogram = interactive_histogram(results, "coverage", labels=pe.TableLayout(labels=LABELS))
    assert {"DME", "YME"} <= _names(histogram)
    assert histogram.layout.xaxis.title.text == "share covered [%]"
    series = interactive_series(results, "inscribed_scale", ["chiacchio"], labels=LABELS)
    assert _names(series) == {"DME"}
    assert series.layout.yaxis.title.text == "inside scale"
    # the defaults
    assert interactive_map(results, columns[0], "q3", "q2").layout.title.text.startswith(
        "Chiacchio: "
    )


def test_a_label_is_shown_as_text_not_markup(comparison):
    figure = interactive_sets(comparison, labels={"chiacchio": "<b>DME</b> & co"})
    assert "&lt;b&gt;DME&lt;/b&gt; &amp; co" in _names(figure)
    assert "<b>&lt;b&gt;DME&lt;/b&gt; &amp; co</b>" in _hover(figure)


@pytest.mark.parametrize(
    ("labels", "message"),
    [
        (3, r"^labels: expected a pe\.TableLayout, a mapping .* got int 3"),
        (["DME"], r"^labels: expected a pe\.TableLayout"),
        ("chiacchio2001", r"^labels: expected a preset among \['chiacchio2000'\].*did you mean"),
        ({"chiachio": "DME"}, r"^labels: .*did you mean 'chiacchio'"),
        ({"chiacchio": ""}, r"^labels\['chiacchio'\]: expected a label that is not blank"),
        ({"chiacchio": 3}, r"^labels\['chiacchio'\]: expected a label"),
        ({"chiacchio": ("DME", "a & b")}, r"^labels\['chiacchio'\]\[1\]: .*'&'"),
    ],
)
def test_bad_labels_are_refused_by_name(comparison, results, labels, message):
    with pytest.raises(pe.InputError, match=message):
        interactive_sets(comparison, labels=labels)
    with pytest.raises(pe.InputError, match=message):
        interactive_histogram(results, "coverage", labels=labels)
    with pytest.raises(pe.InputError, match=message):
        interactive_map(results, "chiacchio_coverage", "q3", "q2", labels=labels)
    with pytest.raises(pe.InputError, match=message):
        interactive_series(results, "coverage", labels=labels)


def test_the_runner_labels_figures_in_one_place():
    assert not hasattr(runner, "_relabeled")
