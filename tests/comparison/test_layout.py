"""TableLayout: the defaults the table writers rely on, and a validating constructor."""

from __future__ import annotations

import dataclasses

import pytest

import polyell as pe
from polyell.comparison.layout import LAYOUT_SETS, TableLayout


def test_fields_and_defaults():
    fields = {f.name: f.default for f in dataclasses.fields(TableLayout)}
    assert fields == {
        "sets": None,
        "scores": None,
        "transpose": False,
        "split": "combined",
        "digits": 3,
        "percent": True,
        "labels": None,
        "captions": None,
        "siunitx": False,
        "text_width": 345.0,
    }
    assert LAYOUT_SETS == ("polytope", "chiacchio", "yoshikawa", "mvie", "outer", "static")
    with pytest.raises(dataclasses.FrozenInstanceError):
        TableLayout().digits = 4  # type: ignore[misc]


def test_lists_become_tuples_and_candidate_names_are_sets():
    layout = TableLayout(sets=["outer", "heavy_wrist"], scores=["coverage", "overreach"])
    assert layout.sets == ("outer", "heavy_wrist") and layout.scores == ("coverage", "overreach")
    assert TableLayout(digits=1).digits == 1 and TableLayout(digits=17).digits == 17


@pytest.mark.parametrize(
    ("arguments", "start"),
    [
        ({"sets": "polytope"}, "layout.sets: expected a non-empty list of set names"),
        ({"sets": []}, "layout.sets: expected a non-empty list"),
        ({"sets": ["Polytope"]}, "layout.sets: expected set names among"),
        ({"sets": ["mvie", "mvie"]}, "layout.sets: expected distinct set names"),
        ({"scores": ["heavy_wrist"]}, "layout.scores: expected score names among"),
        ({"scores": [1]}, "layout.scores: expected score names among"),
        ({"transpose": 1}, "layout.transpose: expected True or False"),
        ({"percent": "yes"}, "layout.percent: expected True or False"),
        ({"split": "postures"}, "layout.split: expected 'posture' (one table per posture)"),
        ({"digits": 0}, "layout.digits: expected an integer from 1 to 17"),
        ({"digits": 18}, "layout.digits: expected an integer from 1 to 17"),
        ({"digits": 3.0}, "layout.digits: expected an integer from 1 to 17"),
        ({"digits": True}, "layout.digits: expected an integer from 1 to 17"),
        ({"labels": "paper"}, "layout.labels: expected a preset among ['chiacchio2000']"),
        ({"labels": ["chiacchio"]}, "layout.labels: expected a mapping of set or score names"),
        ({"labels": {"chiachio": "DME"}}, "layout.labels: expected keys among the sets"),
        ({"labels": {"Coverage": "c"}}, "layout.labels: expected keys that are set names"),
        ({"labels": {"coverage": ""}}, "layout.labels['coverage']: expected a label that is"),
        ({"labels": {"coverage": 3}}, "layout.labels['coverage']: expected a label: plain"),
        ({"labels": {"coverage": ("c", "50%")}}, "layout.labels['coverage'][1]: expected LaTeX"),
        ({"labels": {"coverage": ("c", "{x")}}, "layout.labels['coverage'][1]: expected balanced"),
        ({"labels": {"coverage": ("c", "$x")}}, "layout.labels['coverage'][1]: expected paired"),
        ({"labels": {"coverage": ("c", r"a\\b")}}, "layout.labels['coverage'][1]: expected LaTeX"),
        ({"captions": {"limit": "x"}}, "layout.captions: expected keys among ['comparison'"),
        ({"captions": "x"}, "layout.captions: expected a mapping of table names"),
        ({"siunitx": 1}, "layout.siunitx: expected True or False"),
        ({"text_width": 0}, "layout.text_width: expected a width in pt above 0"),
        ({"text_width": float("nan")}, "layout.text_width: expected a width in pt above 0"),
        ({"text_width": True}, "layout.text_width: expected a width in pt above 0"),
    ],
)
def test_bad_fields_are_refused_by_name(arguments, start):
    with pytest.raises(pe.InputError) as info:
        TableLayout(**arguments)
    assert str(info.value).startswith(start), str(info.value)


def test_suggestions():
    with pytest.raises(pe.InputError, match="did you mean 'posture'"):
        TableLayout(split="postures")
    with pytest.raises(pe.InputError, match="did you mean 'coverage'"):
        TableLayout(scores=["coverag"])


def test_labels_and_captions_are_kept_read_only_and_the_layout_stays_hashable():
    from dataclasses import replace

    layout = TableLayout(
        labels={"chiacchio": "DME", "coverage": ("share", r"$\eta$")},
        captions={"limits": "Limits."},
    )
    assert layout.set_label("chiacchio") == "DME" and layout.set_label("mvie") == "MVIE"
    assert layout.quantity("coverage").latex == r"$\eta$"
    assert layout.caption("limits").plain == "Limits." and layout.caption("summary") is None
    with pytest.raises(TypeError):
        layout.labels["chiacchio"] = "x"  # type: ignore[index]
    assert hash(layout) == hash(replace(layout)) and replace(layout) == layout
    assert TableLayout(labels="chiacchio2000").set_label("yoshikawa") == "classic (eq. 27)"
    assert TableLayout(text_width=252).text_width == 252.0
    assert TableLayout(text_width=None).text_width is None
