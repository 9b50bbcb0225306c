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
