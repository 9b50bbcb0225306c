"""``polyell analyze --horizon``: the set within the joint limits over a control period."""

from __future__ import annotations

import json

import numpy as np
import pytest

import polyell as pe
from polyell.cli import main

Q = "0,-0.5,0,-0.075,0,1.6,0.8"
QD = "0,0,0,0.5,0,0,0"


def test_the_horizon_set_is_the_analysis_of_the_robot(capsys):
    pytest.importorskip("pinocchio")
    code = main(
        ["analyze", "--robot", "panda", "--q", Q, "--qd", QD, "--horizon", "0.01",
         "--no-mvie", "--no-outer", "--json"]
    )  # fmt: skip
    captured = capsys.readouterr()
    assert code == 0 and "joints 1, 2, 3, 4, 5, 6, 7 cut the set" in captured.err
    printed = json.loads(captured.out)
    panda = pe.robots.load("panda")
    q, qd = (np.array([float(v) for v in text.split(",")]) for text in (Q, QD))
    analysis = panda.analyze(q, qd, horizon=0.01)
    assert printed["polytope"]["volume"] == pytest.approx(analysis.polytope.volume, rel=1e-12)


@pytest.mark.parametrize(
    ("arguments", "named"),
    [
        (["--horizon", "-1"], "--horizon"),
        (["--horizon", "0"], "--horizon"),
        (["--horizon", "nan"], "--horizon"),
        (["--horizon", "0.01", "--capacity", "force"], "--horizon"),
        (["--braking", "10"], "--braking"),
    ],
)
def test_bad_horizons_name_the_option(capsys, arguments, named):
    assert main(["analyze", *arguments]) != 0
    assert f"error: {named}:" in capsys.readouterr().err


def test_the_planar_arm_turns_freely_within_its_velocity_limits(capsys):
    assert main(["analyze", "--horizon", "0.01", "--no-mvie", "--no-outer"]) == 0
    assert "within the joint limits over the next 0.01 s" in capsys.readouterr().err
