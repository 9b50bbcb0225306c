"""The sets of an analysis carry its task rows, checked as the ``task`` setter checks them."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe


def test_every_set_of_an_analysis_knows_its_rows():
    dyn = pe.Dynamics(np.eye(3, 4) + 0.1, np.eye(4), np.zeros(4), task=("x", "y", "wz"))
    for capacity in ("acceleration", "velocity", "force"):
        limits = {"qd_max": np.ones(4)} if capacity == "velocity" else {"tau_max": np.ones(4)}
        analysis = pe.analyze(dyn, capacity=capacity, **limits)
        assert analysis.polytope.task == ("x", "y", "wz")
        assert analysis.ellipsoid().task == ("x", "y", "wz")


@pytest.mark.parametrize(
    ("rows", "message"),
    [(("x", "y"), "3 distinct row names"), ([["x"], "y", "z"], "3 row names such as")],
)
def test_rows_edited_by_hand_are_still_checked(rows, message):
    kin = pe.Kinematics(np.eye(3, 4) + 0.1)
    kin.task = rows  # wrong length; unhashable names
    with pytest.raises(pe.InputError, match=message):
        _ = pe.analyze(kin, capacity="velocity", qd_max=np.ones(4)).polytope


def test_rows_given_as_a_list_are_a_tuple_on_the_set():
    kin = pe.Kinematics(np.eye(3, 4) + 0.1)
    kin.task = ["x", "y", "z"]
    assert pe.analyze(kin, capacity="velocity", qd_max=np.ones(4)).polytope.task == ("x", "y", "z")
