"""pe.sweep over several robots: one frame with a robot column, one dataset per robot."""

from __future__ import annotations

import logging
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import polyell as pe

ARM = pe.robots.load("chiacchio2000")
TWO_LINK = pe.PlanarArm(lengths=[1.0, 0.8], masses=[3.0, 2.0], tau_max=[40.0, 20.0])


def sets(count: int = 12):
    return {
        "paper": pe.random_configurations(count, [-np.pi] * 3, [np.pi] * 3, seed=1),
        "two_link": pe.random_configurations(count, [-np.pi] * 2, [np.pi] * 2, seed=2),
    }


def test_each_robot_gets_its_own_sweep_in_one_frame():
    configurations = sets()
    frame = pe.sweep({"paper": ARM, "two_link": TWO_LINK}, configurations, directions=16)
    assert frame.columns[0] == "robot"
    assert frame["robot"].value_counts().to_dict() == {"paper": 12, "two_link": 12}
    for name, robot in (("paper", ARM), ("two_link", TWO_LINK)):
        alone = pe.sweep(robot, configurations[name], directions=16)
        rows = frame[frame["robot"] == name].drop(columns="robot").reset_index(drop=True)
        rows = rows[alone.columns]  # the other robot's joints are NaN columns here
        pd.testing.assert_frame_equal(rows, alone)


def test_a_list_is_named_by_position_and_shares_one_set_of_the_same_joint_count():
    q = pe.random_configurations(5, [-np.pi] * 3, [np.pi] * 3, seed=3)
    frame = pe.sweep([ARM, ARM], q, directions=8)
    assert frame["robot"].tolist() == ["0"] * 5 + ["1"] * 5
    first, second = (frame[frame["robot"] == r].drop(columns="robot") for r in ("0", "1"))
    np.testing.assert_array_equal(first.to_numpy(float), second.to_numpy(float))


@pytest.mark.parametrize("names", [("paper", "two_link"), ("b_paper", "a_two_link")])
def test_datasets_per_robot_read_back_whole_with_the_robot_column(tmp_path, names):
    """Every robot's dataset has the same q columns (NaN beyond its joints), so pyarrow,
    which takes the first file's schema, keeps q3 whichever robot sorts first (found by the
    independent check: a 2-joint robot sorting first dropped q3)."""
    configurations = dict(zip(names, sets(6).values(), strict=True))
    robots = dict(zip(names, (ARM, TWO_LINK), strict=True))
    in_memory = pe.sweep(robots, configurations, directions=8)
    folder = pe.sweep(robots, configurations, directions=8, out=tmp_path / "d")
    assert sorted(p.name for p in folder.iterdir() if p.is_dir()) == sorted(
        f"robot={n}" for n in names
    )
    back = pd.read_parquet(folder)
    back["robot"] = back["robot"].astype(str)
    back = back.sort_values(["robot", "configuration"]).reset_index(drop=True)
    expected = in_memory.sort_values(["robot", "configuration"]).reset_index(drop=True)
    assert set(back.columns) == set(expected.columns)
    pd.testing.assert_frame_equal(back[expected.columns], expected)


def test_a_dataset_folder_holds_one_kind_of_sweep(tmp_path):
    q = sets(6)
    robots = {"paper": ARM, "two_link": TWO_LINK}
    pe.sweep(robots, q, directions=8, out=tmp_path / "several")
    with pytest.raises(pe.InputError, match="several robots"):
        pe.sweep(ARM, q["paper"], directions=8, out=tmp_path / "several")
    with pytest.raises(pe.InputError, match="robots"):  # fewer robots: stale rows would stay
        pe.sweep({"paper": ARM}, {"paper": q["paper"]}, directions=8, out=tmp_path / "several")
    pe.sweep(ARM, q["paper"], directions=8, out=tmp_path / "one")
    with pytest.raises(pe.InputError, match="one robot"):
        pe.sweep(robots, q, directions=8, out=tmp_path / "one")
    pe.sweep(robots, q, directions=8, out=tmp_path / "several")  # the same: resumes


def test_an_error_names_the_robot():
    with pytest.raises(pe.InputError, match="robot 'two_link'"):
        pe.sweep({"paper": ARM, "two_link": TWO_LINK}, {"paper": np.zeros((2, 3)),
                  "two_link": np.zeros((2, 3))})  # fmt: skip


@pytest.mark.parametrize(
    ("source", "configurations", "kwargs", "fragment"),
    [
        ({}, None, {}, "at least one"),
        ({"a/b": ARM}, None, {}, "folder name"),
        ({"a": ARM}, {"b": np.zeros((1, 3))}, {}, "one set per robot"),
        ({"a": ARM}, np.zeros((1, 3)), {"tau_max": [1.0, 1.0, 1.0]}, "own limits"),
        ({"a": "panda"}, np.zeros((1, 3)), {}, "a robot"),
    ],
)
def test_bad_robot_collections_are_refused(source, configurations, kwargs, fragment):
    with pytest.raises(pe.InputError, match=fragment):
        pe.sweep(source, configurations, **kwargs)


def test_a_resumed_dataset_says_how_far_it_had_come(tmp_path, caplog):
    q = pe.random_configurations(30, [-np.pi] * 3, [np.pi] * 3, seed=4)
    pe.sweep(ARM, q, directions=8, chunk=10, out=tmp_path / "d")
    (tmp_path / "d" / "part-000001.parquet").unlink()
    with caplog.at_level(logging.INFO, logger="polyell"):
        pe.sweep(ARM, q, directions=8, chunk=10, out=tmp_path / "d")
    assert "2 of 3 chunks done" in caplog.text


def test_the_command_line_says_a_study_resumes(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 30\nseed = 1\n'
        "[compare]\nchunk = 10\ndirections = 8\nmvie = false\nouter = false\n"
    )
    command = [sys.executable, "-m", "polyell", "study", str(spec), "--out", str(tmp_path / "o")]
    first = subprocess.run(command, capture_output=True, text=True, check=True)
    assert "resuming" not in first.stderr
    (tmp_path / "o" / "results" / "part-000002.parquet").unlink()
    again = subprocess.run(command, capture_output=True, text=True, check=True)
    assert "polyell: resuming" in again.stderr and "2 of 3 chunks done" in again.stderr
