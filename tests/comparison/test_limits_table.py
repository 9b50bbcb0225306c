"""The directional-limits table against independent computations.

The polytope's limits come from linear programs in the normalised torques (Clarabel,
``polyell.geometry.linprog``), the ellipsoids' from the quadratic of eq. (23) on the core
``N`` (not the factors the package uses), and the errors are recomputed here.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.geometry.linprog import polytope_limits_lp
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis

Q_PANDA = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785]


@pytest.fixture(scope="module")
def paper() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 36, samples=256)


@pytest.fixture(scope="module")
def panda() -> pe.Comparison:
    robot = pe.robots.load("panda")
    return pe.compare(pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max), 64, samples=256)


def quadratic_limits(E: pe.Ellipsoid, t: np.ndarray) -> tuple[float, float]:
    """Roots of ``(a t - c)^T N (a t - c) = 1`` (eq. 23) from the core N."""
    N, c = E.core, E.center
    alpha, beta, gamma = t @ N @ t, t @ N @ c, c @ N @ c - 1.0
    root = np.sqrt(beta**2 - alpha * gamma)
    return (beta - root) / alpha, (beta + root) / alpha


def check_against_independent(comparison: pe.Comparison, table: pd.DataFrame, vectors) -> None:
    an = comparison.analysis
    lo_p, hi_p = polytope_limits_lp(an.polytope.generators, an.polytope.center, vectors)
    for k, direction in enumerate(dict.fromkeys(table["direction"])):
        rows = table[table["direction"] == direction].set_index("set")
        assert rows.loc["polytope", "lower"] == pytest.approx(lo_p[k], rel=1e-7, abs=1e-9)
        assert rows.loc["polytope", "upper"] == pytest.approx(hi_p[k], rel=1e-7, abs=1e-9)
        for kind in rows.index.drop("polytope"):
            lo, hi = quadratic_limits(comparison.ellipsoid(kind), vectors[k])
            assert rows.loc[kind, "lower"] == pytest.approx(lo, rel=1e-9)
            assert rows.loc[kind, "upper"] == pytest.approx(hi, rel=1e-9)
            assert rows.loc[kind, "lower_error"] == pytest.approx(
                (lo - lo_p[k]) / abs(lo_p[k]), rel=1e-6, abs=1e-9
            )
            assert rows.loc[kind, "upper_error"] == pytest.approx(
                (hi - hi_p[k]) / abs(hi_p[k]), rel=1e-6, abs=1e-9
            )
        assert rows.loc["polytope", ["lower_error", "upper_error"]].tolist() == [0.0, 0.0]


def test_planar_limits_match_linear_programs_and_eq_23(paper):
    table = paper.limits_table(["x", "-y", "xy", [0.6, 0.8]])
    assert list(table.columns) == [
        "direction", "set", "defined", "lower", "upper", "lower_error", "upper_error", "unit"
    ]  # fmt: skip
    assert list(dict.fromkeys(table["direction"])) == ["x", "-y", "x+y", "(0.6, 0.8)"]
    assert list(dict.fromkeys(table["set"])) == ["polytope", *pe.COMPARED_KINDS]
    assert set(table["unit"]) == {"m/s^2"} and table["defined"].all()
    vectors = np.array([[1, 0], [0, -1], [2**-0.5, 2**-0.5], [0.6, 0.8]])
    check_against_independent(paper, table, vectors)


def test_panda_limits_default_to_the_axes_and_match(panda):
    table = panda.limits_table()
    assert list(dict.fromkeys(table["direction"])) == ["x", "y", "z"]
    check_against_independent(panda, table, np.eye(3))


def test_a_negative_direction_swaps_and_negates_the_interval(panda):
    table = panda.limits_table(["z", "-z"]).set_index(["direction", "set"])
    for kind in ["polytope", *pe.COMPARED_KINDS]:
        plus, minus = table.loc[("z", kind)], table.loc[("-z", kind)]
        assert minus["lower"] == pytest.approx(-plus["upper"], rel=1e-12)
        assert minus["upper"] == pytest.approx(-plus["lower"], rel=1e-12)


def test_an_undefined_ellipsoid_is_kept_as_undefined():
    cmp = pe.compare(paper_analysis(PAPER_Q_SINGULAR), 16, mvie=False, samples=256)
    table = cmp.limits_table()
    assert "mvie" not in set(table["set"])  # not computed: left out by default
    classic = table[table["set"] == "yoshikawa"]
    assert not classic["defined"].any()
    assert classic[["lower", "upper", "lower_error", "upper_error"]].isna().all().all()
    new = table[table["set"] == "chiacchio"]
    assert new["defined"].all()
    with pytest.raises(pe.InputError, match="sets among") as info:
        cmp.limits_table(sets=["polytope", "mvi"])
    assert info.value.argument == "sets"


def test_several_postures_in_one_frame(paper, panda):
    robot = pe.robots.load("panda")
    q = np.array(Q_PANDA) + 0.3
    other = pe.compare(pe.analyze(robot.dynamics(q), robot.tau_max), 16, samples=256)
    table = pe.limits_table({"home": panda, "moved": other}, {"moved": ["xy"]}, sets=["polytope"])
    assert table[["posture", "direction"]].values.tolist() == [
        ["home", "x"], ["home", "y"], ["home", "z"], ["moved", "x+y"]
    ]  # fmt: skip
    _, hi = polytope_limits_lp(
        other.analysis.polytope.generators, other.analysis.polytope.center,
        np.array([[2**-0.5, 2**-0.5, 0]]),
    )  # fmt: skip
    assert table["upper"].iloc[-1] == pytest.approx(hi[0], rel=1e-7)
    with pytest.raises(pe.InputError) as info:
        pe.limits_table({"home": panda, "moved": other}, {"moved": ["x", "q"]})
    assert info.value.argument == "directions['moved'][1]"
    with pytest.raises(pe.InputError, match="postures"):
        pe.limits_table({"home": panda}, {"away": ["x"]})
    with pytest.raises(pe.InputError, match="comparisons"):
        pe.limits_table({"home": paper.analysis})  # type: ignore[dict-item]
    with pytest.raises(pe.InputError, match="comparisons"):
        pe.limits_table({})


def test_an_angular_task_is_in_rad_per_s2():
    robot = pe.robots.load("panda", task="angular")
    cmp = pe.compare(pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max), 16, samples=256)
    table = cmp.limits_table(["wx", "-wz"])
    assert set(table["unit"]) == {"rad/s^2"}
    assert list(dict.fromkeys(table["direction"])) == ["wx", "-wz"]
    with pytest.raises(pe.InputError, match="wx, wy, wz"):
        cmp.limits_table(["x"])


def test_one_table_holds_one_capacity():
    """Postures of different capacities have different ellipsoids and units: refused."""
    from polyell.comparison.tables import format_comparison_table

    J = [[1.0, 0.5, 0.2], [0.0, 1.0, 0.3]]
    acc = pe.compare(pe.analyze(pe.Dynamics(J, np.eye(3), np.zeros(3)), [1, 2, 3]), 8)
    vel = pe.compare(pe.analyze(pe.Kinematics(J), capacity="velocity", qd_max=[1, 2, 3]), 8)
    for call in (
        lambda: format_comparison_table({"a": acc, "v": vel}, "markdown"),
        lambda: pe.limits_table({"a": acc, "v": vel}),
    ):
        with pytest.raises(pe.InputError, match=r"comparisons\['v'\].*one capacity"):
            call()


def test_one_set_by_name_in_both_comparisons(paper):
    """``sets="mvie"`` is that set (it was read letter by letter: got ['m', 'v', 'i', 'e']),
    for a Comparison and a bare set's SetComparison alike, and a wrong name is refused by
    name in both."""
    for comparison in (paper, pe.compare(paper.polytope)):
        table = comparison.limits_table(["x"], sets="mvie")
        assert list(table["set"]) == ["mvie"]
        full = comparison.limits_table(["x"])
        np.testing.assert_allclose(
            table[["lower", "upper"]].to_numpy(),
            full.loc[full["set"] == "mvie", ["lower", "upper"]].to_numpy(),
            rtol=0,
        )
        with pytest.raises(pe.InputError, match=r"^sets: .*got \['mvi'\]\. Fix: pass names"):
            comparison.limits_table(["x"], sets=["mvi"])
