"""The study-file reference page (issue 14): generated from the table the parser checks keys
against, current in docs/, and every example in it loads."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

import polyell as pe
from polyell.studies import load_study
from polyell.studies.models import TABLES, keys, reference_page

ROOT = Path(__file__).resolve().parents[2]


def test_the_committed_page_is_current():
    page = (ROOT / "docs" / "study_format.md").read_text()
    assert page == reference_page(), "regenerate with: python docs/study_format.py"


@pytest.mark.parametrize("table", list(TABLES))
def test_every_example_loads(tmp_path, table):
    shutil.copy(ROOT / "studies" / "planar3r_path.csv", tmp_path)
    path = tmp_path / "example.toml"
    path.write_text(TABLES[table].example + "\n")
    spec = load_study(path)
    assert spec.robot.model.n >= 3


@pytest.mark.parametrize(
    ("table", "prefix"),
    [
        ("top", ""),
        ("robot", "[robot]\nlibrary = 'chiacchio2000'\n"),
        ("points", "[robot]\nlibrary = 'chiacchio2000'\n[[points]]\nname = 'p'\nq = [0, 0, 0]\n"),
        (
            "compare",
            "[robot]\nlibrary = 'chiacchio2000'\n[[points]]\nname = 'p'\nq = [0, 0, 0]\n"
            "[compare]\n",
        ),
        (
            "output",
            "[robot]\nlibrary = 'chiacchio2000'\n[[points]]\nname = 'p'\nq = [0, 0, 0]\n[output]\n",
        ),
        ("random", "[robot]\nlibrary = 'chiacchio2000'\n[random]\ncount = 2\n"),
    ],
)
def test_an_unknown_key_lists_exactly_the_documented_ones(tmp_path, table, prefix):
    path = tmp_path / "study.toml"
    path.write_text(prefix + "bogus_key = 1\n" + ("" if prefix else "[robot]\nlibrary = 'x'\n"))
    with pytest.raises(pe.InputError, match="unknown key") as caught:
        load_study(path)
    assert f"keys among {list(keys(table))}" in str(caught.value)


def test_every_key_of_a_leaf_table_appears_in_its_example():
    """The examples exercise the keys they document (the robot's sources exclude each other)."""
    exclusive = {
        "output": {"series", "split", "transpose"},  # trajectory / points studies only
        "points": {"direction", "qd"},  # the older form; a URDF robot in motion (its own tests)
        "robot": {
            "planar",
            "urdf",
            "tip",
            "locked_joints",
            "gravity",
            "weights",
            "tau_min",
            "tau_max",
            "qd_max",  # the three below: in the example of [robot.torque_speed]
            "qd_min",
            "torque_speed",
        },
        "torque_speed": {"speeds", "torques"},  # the other form: tested in tests/studies
    }
    for name, table in TABLES.items():
        if name in ("top", "grid"):
            continue
        for key in keys(name):
            if key not in exclusive.get(name, set()):
                assert f"{key} =" in table.example, f"{key} of {table.heading}"


def test_json_schemas_are_current_and_accept_every_shipped_file():
    import json

    import jsonschema
    import tomllib

    from polyell.studies.models import json_schema

    for kind in ("study", "robot"):
        committed = json.loads((ROOT / "docs" / f"{kind}.schema.json").read_text())
        assert committed == json_schema(kind), "regenerate with: python docs/study_format.py"
    study = json_schema("study")
    jsonschema.Draft202012Validator.check_schema(study)
    for path in sorted((ROOT / "studies").glob("*.toml")):
        jsonschema.validate(tomllib.loads(path.read_text()), study)
    for table in TABLES.values():
        jsonschema.validate(tomllib.loads(table.example), study)
    bad = tomllib.loads(TABLES["compare"].example.replace("samples", "sample"))
    with pytest.raises(jsonschema.ValidationError, match="sample"):
        jsonschema.validate(bad, study)
    robot = tomllib.loads('library = "panda"\ntask = ["x", "z"]\ntau_max = [1, 2, "3"]\n')
    jsonschema.validate(robot, json_schema("robot"))
