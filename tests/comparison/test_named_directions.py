"""Named directions ("x", "-z", "xy") wherever a direction is taken (issue 32).

Every entry point given names must equal the same call given the unit vectors typed out
here (``[0, 0, 1]``, ``[1, 1] / sqrt(2)``), not derived from the parser; the polytope's
interval along a diagonal is also checked against a linear program (scipy's HiGHS) on the
torque cube.  Bad names are refused naming the argument and the task's rows.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import optimize

import polyell as pe
from polyell.cli import main
from reference import PAPER_Q_REDUNDANT

ARM = pe.robots.load("chiacchio2000")
SQRT2 = np.sqrt(2.0)
#: Names of a 2-row task and the unit vectors they stand for, typed out.
PLANAR = {
    "x": [1.0, 0.0],
    "-y": [0.0, -1.0],
    "xy": [1.0 / SQRT2, 1.0 / SQRT2],
    "x-y": [1.0 / SQRT2, -1.0 / SQRT2],
    "-x+y": [-1.0 / SQRT2, 1.0 / SQRT2],
}
FRAME = ("x", "y", "z", "wx", "wy", "wz")
#: The Panda with the six rows of its frame Jacobian, angular rows weighted.
PANDA_Q0 = np.array([0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8])


def assert_same(found: pe.DirectionalLimits, expected: pe.DirectionalLimits) -> None:
    """Equal intervals: the same vector gives the same numbers, to the last bit."""
    np.testing.assert_array_equal(found.lo, expected.lo)
    np.testing.assert_array_equal(found.hi, expected.hi)


def lp_limits(M: np.ndarray, xg: np.ndarray, d: np.ndarray) -> tuple[float, float]:
    """min and max a subject to a d = xg + M u, |u|_inf <= 1 (variables u, a)."""
    n = M.shape[1]
    A_eq = np.hstack([M, -d[:, None]])
    ends = []
    for sign in (1.0, -1.0):
        c = np.zeros(n + 1)
        c[-1] = sign
        bounds = [(-1.0, 1.0)] * n + [(None, None)]
        result = optimize.linprog(c, A_eq=A_eq, b_eq=-xg, bounds=bounds, method="highs")
        assert result.status == 0
        ends.append(sign * result.fun)
    return ends[0], ends[1]


@pytest.fixture(scope="module")
def paper() -> pe.Analysis:
    return pe.analyze(ARM.dynamics(PAPER_Q_REDUNDANT), ARM.tau_max)


@pytest.fixture(scope="module")
def force() -> pe.Analysis:
    return pe.analyze(ARM.dynamics([0.3, 0.6, 0.9]), ARM.tau_max, capacity="force")


@pytest.fixture(scope="module")
def panda6() -> pe.UrdfRobot:
    return pe.robots.load("panda", task=list(FRAME), weights=[1, 1, 1, 0.1, 0.1, 0.1])


# --- the sets' limits ---------------------------------------------------------------------


def test_sets_of_an_analysis_take_names(paper, force):
    sets = [paper.polytope, paper.ellipsoid("chiacchio"), paper.ellipsoid("yoshikawa")]
    sets += [force.polytope, force.ellipsoid("static")]  # an HPolytope and its ellipsoid
    for S in sets:
        for name, vector in PLANAR.items():
            assert_same(S.limits(name), S.limits(vector))
            assert np.shape(S.limits(name).lo) == ()  # one direction
        names = list(PLANAR)
        assert_same(S.limits(names), S.limits([PLANAR[name] for name in names]))
        mixed = S.limits(["x", [0.6, 0.8]])  # names and vectors together
        assert_same(mixed, S.limits([[1.0, 0.0], [0.6, 0.8]]))
    by_lp = paper.polytope.limits(PLANAR["xy"], method="lp")
    assert_same(paper.polytope.limits("xy", method="lp"), by_lp)


def test_a_named_diagonal_matches_a_linear_program(paper):
    lo, hi = paper.polytope.limits("x-y")
    expected = lp_limits(paper.M, paper.xg, np.array([1.0, -1.0]) / SQRT2)
    np.testing.assert_allclose([lo, hi], expected, rtol=1e-9)
    np.testing.assert_allclose(paper.polytope.limits("x"), [-57.305, 53.700], atol=5e-4)


def test_bare_sets_read_names_as_x_y_z():
    rng = np.random.default_rng(32)
    P = pe.Polytope(rng.normal(size=(3, 5)), center=rng.normal(size=3))
    assert P.task is None
    third = 1.0 / np.sqrt(3.0)
    cases = {"z": [0, 0, 1.0], "-xz": [-1 / SQRT2, 0, 1 / SQRT2], "x-y+z": [third, -third, third]}
    for name, vector in cases.items():
        assert_same(P.limits(name), P.limits(vector))
    E = pe.Ellipsoid(center=[0.0, 1.0], axes=np.eye(2), semi_axes=[2.0, 1.0])
    assert_same(E.limits("-y"), E.limits([0.0, -1.0]))
    np.testing.assert_allclose(E.limits("y"), [0.0, 2.0])  # centre 1, semi-axis 1
    box = pe.HPolytope(np.vstack([np.eye(3), -np.eye(3)]), np.ones(6))
    np.testing.assert_allclose(box.limits("xyz"), [-np.sqrt(3.0), np.sqrt(3.0)])
    with pytest.raises(pe.InputError) as info:
        E.limits("z")  # a 2-D set: x and y only
    assert info.value.argument == "directions" and "(x, y)" in str(info.value)


def test_bare_sets_of_more_rows_refuse_names_until_told_their_rows():
    E = pe.Ellipsoid(np.zeros(6), np.eye(6), np.arange(1.0, 7.0))
    with pytest.raises(pe.InputError) as info:
        E.limits("wz")
    assert info.value.argument == "directions"
    assert "no task row names" in str(info.value) and "S.task = analysis.task" in str(info.value)
    E.task = FRAME
    assert_same(E.limits("wz"), E.limits(np.eye(6)[5]))
    np.testing.assert_allclose(E.limits("wz"), [-6.0, 6.0])
    np.testing.assert_allclose(E.limits("-wx"), [-4.0, 4.0])
    E.task = None  # back to a bare set
    with pytest.raises(pe.InputError, match="no task row names"):
        E.limits(["x", "wz"])


def test_a_set_reads_names_against_its_own_rows():
    P = pe.Polytope([[1.0, 0.0, 1.0], [0.0, 2.0, 1.0]], center=[0.0, -1.0])
    P.task = ("x", "z")  # a vertical plane
    assert_same(P.limits("z"), P.limits([0.0, 1.0]))
    assert_same(P.limits("x-z"), P.limits([1 / SQRT2, -1 / SQRT2]))
    with pytest.raises(pe.InputError) as info:
        P.limits("y")
    assert info.value.argument == "directions" and "(x, z)" in str(info.value)
    with pytest.raises(pe.InputError) as info:
        P.task = ("x", "y", "z")
    assert info.value.argument == "task" and "2 distinct row names" in str(info.value)
    with pytest.raises(pe.InputError) as info:
        P.task = ("x", "x")
    assert info.value.argument == "task"


@pytest.mark.parametrize("name", ["q", "xx", "z", "x+", "", "x y z", "wz"])
def test_bad_names_are_refused_naming_the_rows(paper, name):
    with pytest.raises(pe.InputError) as info:
        paper.polytope.limits(name)
    assert info.value.argument == "directions"
    assert "task rows (x, y)" in str(info.value) and repr(name) in str(info.value)


def test_a_bad_name_in_a_list_is_refused_by_its_index(paper):
    with pytest.raises(pe.InputError) as info:
        paper.ellipsoid("chiacchio").limits(["x", "y", "yy"])
    assert info.value.argument == "directions[2]" and "(x, y)" in str(info.value)


def test_sets_built_by_analyze_know_their_rows(panda6, force):
    analysis = pe.analyze(panda6.dynamics(PANDA_Q0), panda6.tau_max)
    assert analysis.polytope.task == FRAME
    assert analysis.ellipsoid("chiacchio").task == FRAME
    assert force.polytope.task == ("x", "y")
    assert_same(analysis.polytope.limits("wz"), analysis.polytope.limits(np.eye(6)[5]))


# --- a 6-row task -------------------------------------------------------------------------


def test_a_six_row_task(panda6):
    analysis = pe.analyze(panda6.dynamics(PANDA_Q0), panda6.tau_max)
    assert analysis.task == FRAME
    P, E = analysis.polytope, analysis.ellipsoid("chiacchio")
    for S in (P, E):
        S.task = analysis.task  # (see test_sets_built_by_analyze_know_their_rows)
        assert_same(S.limits("wz"), S.limits(np.eye(6)[5]))
        assert_same(S.limits("-wy"), S.limits(-np.eye(6)[4]))
        diagonal = np.array([0, 0, 1.0, 0, 0, 1.0]) / SQRT2
        assert_same(S.limits("z+wz"), S.limits(diagonal))
    lo, hi = P.limits("zwz")
    np.testing.assert_allclose([lo, hi], lp_limits(analysis.M, analysis.xg, diagonal), rtol=1e-8)
    with pytest.raises(pe.InputError) as info:
        P.limits("w")
    assert "(x, y, z, wx, wy, wz)" in str(info.value)

    table = pe.limits_table(pe.compare(analysis, mvie=False, outer=False), ["wz"])
    polytope = table[table["set"] == "polytope"].iloc[0]
    assert (polytope["lower"], polytope["upper"]) == tuple(P.limits(np.eye(6)[5]))

    q = np.array([PANDA_Q0, PANDA_Q0 + 0.1])
    named = pe.limits_along(panda6, q, ["wz", "x-wy"])
    vectors = pe.limits_along(panda6, q, [np.eye(6)[5], (np.eye(6)[0] - np.eye(6)[4]) / SQRT2])
    for kind in ("polytope", "chiacchio", "yoshikawa"):
        assert_same(named[kind], vectors[kind])
    np.testing.assert_allclose(named["polytope"].hi[0], P.limits("wz").hi, rtol=1e-12)


def test_a_six_row_posture_choice(panda6):
    postures = pe.self_motion(panda6, PANDA_Q0, count=4, seed=1).configurations
    named = pe.posture_choice(panda6, postures, direction="wz", mvie=False, outer=False)
    vector = pe.posture_choice(panda6, postures, direction=np.eye(6)[5], mvie=False, outer=False)
    np.testing.assert_array_equal(named.direction, np.eye(6)[5])
    np.testing.assert_array_equal(named.values.to_numpy(), vector.values.to_numpy())


# --- limits_along -------------------------------------------------------------------------


def test_limits_along_takes_a_name_per_row():
    q = np.array([PAPER_Q_REDUNDANT, [0.3, 0.2, 0.1], [0.9, -0.4, 1.2]])
    names = ["x", "-y", "xy"]
    named = pe.limits_along(ARM, q, names)
    vectors = pe.limits_along(ARM, q, [PLANAR[name] for name in names])
    for kind in ("polytope", "chiacchio", "yoshikawa"):
        assert_same(named[kind], vectors[kind])
    mixed = pe.limits_along(ARM, q, ["x", [0.0, -1.0], PLANAR["xy"]])
    assert_same(mixed["polytope"], vectors["polytope"])
    forces = pe.limits_along(ARM, q, names, capacity="force")
    by_vector = pe.limits_along(ARM, q, [PLANAR[name] for name in names], capacity="force")
    assert_same(forces["polytope"], by_vector["polytope"])
    # row by row as the analysis's own sets
    analysis = pe.analyze(ARM.dynamics(q[2]), ARM.tau_max)
    np.testing.assert_allclose(named["polytope"].lo[2], analysis.polytope.limits("xy").lo)


def test_limits_along_a_batched_dynamics_of_six_rows():
    rng = np.random.default_rng(7)
    K, n = 3, 7
    J = rng.normal(size=(K, 6, n))
    B = np.broadcast_to(np.eye(n) * 2.0, (K, n, n))
    dyn = pe.Dynamics(J, B, rng.normal(size=(K, n)), task=FRAME)
    names = ["wz", "-x", "ywx"]
    vectors = [np.eye(6)[5], -np.eye(6)[0], (np.eye(6)[1] + np.eye(6)[3]) / SQRT2]
    named = pe.limits_along(dyn, None, names, np.full(n, 10.0))
    expected = pe.limits_along(dyn, None, vectors, np.full(n, 10.0))
    for kind in ("polytope", "chiacchio", "yoshikawa"):
        assert_same(named[kind], expected[kind])


def test_limits_along_refuses_bad_names():
    q = np.array([PAPER_Q_REDUNDANT, [0.3, 0.2, 0.1]])
    with pytest.raises(pe.InputError) as info:
        pe.limits_along(ARM, q, ["x", "z"])
    assert info.value.argument == "directions[1]" and "(x, y)" in str(info.value)
    with pytest.raises(pe.InputError) as info:
        pe.limits_along(ARM, q, "x")  # one name for two configurations
    assert info.value.argument == "directions"
    assert "['x'] * 2" in str(info.value) and "['x', 'y']" in str(info.value)


# --- posture_choice -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def postures() -> np.ndarray:
    return pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=12).configurations


@pytest.mark.parametrize("name", ["x", "-y", "x-y"])
def test_posture_choice_takes_a_name(postures, name):
    options = {"mvie": False, "outer": False}
    named = pe.posture_choice(ARM, postures, direction=name, **options)
    vector = pe.posture_choice(ARM, postures, direction=PLANAR[name], **options)
    np.testing.assert_allclose(named.direction, PLANAR[name], rtol=0, atol=1e-15)
    assert named.values.equals(vector.values)
    assert named.table.equals(vector.table)


def test_posture_choice_refuses_a_bad_name(postures):
    with pytest.raises(pe.InputError) as info:
        pe.posture_choice(ARM, postures, direction="z", mvie=False, outer=False)
    assert info.value.argument == "direction" and "(x, y)" in str(info.value)


# --- the command line ---------------------------------------------------------------------


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["analyze", *argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize(
    ("name", "vector"),
    [
        ("y", "0,1"),
        ("-y", "0,-1"),
        ("x-y", "sqrt(2)/2,-sqrt(2)/2"),
        ("-x+y", "-0.5*sqrt(2),sqrt(1/2)"),
    ],
)
def test_cli_prints_the_same_numbers_for_a_name_and_its_vector(capsys, name, vector):
    code, by_name, _ = run(capsys, "--direction", name, "--no-mvie", "--no-outer")
    assert code == 0
    code, by_vector, _ = run(capsys, f"--direction={vector}", "--no-mvie", "--no-outer")
    assert code == 0
    assert f"along {name} = " in by_name  # labelled by its name
    assert by_name.replace(f"along {name} = ", "along t = ") == by_vector
    code, as_json, _ = run(capsys, f"--direction={name}", "--json", "--no-mvie", "--no-outer")
    assert code == 0
    code, vector_json, _ = run(capsys, "--direction", vector, "--json", "--no-mvie", "--no-outer")
    assert json.loads(as_json) == json.loads(vector_json)


def test_cli_default_direction_is_the_first_row(capsys):
    code, default, _ = run(capsys, "--no-mvie", "--no-outer")
    assert code == 0
    assert run(capsys, "--direction", "x", "--no-mvie", "--no-outer")[1] == default


def test_cli_names_of_a_three_row_task(capsys):
    q = ["--robot", "panda", "--q", "0,-0.3,0,-2.2,0,2.0,0.8", "--json", "--no-mvie"]
    code, by_name, _ = run(capsys, *q, "--no-outer", "--direction", "z")
    assert code == 0
    code, by_vector, _ = run(capsys, *q, "--no-outer", "--direction", "0,0,1")
    assert code == 0
    assert json.loads(by_name) == json.loads(by_vector)
    code, minus, _ = run(capsys, *q, "--no-outer", "--direction", "-z")  # joined as --direction=-z
    assert code == 0
    lo, hi = json.loads(by_name)["polytope"]["limits"]
    assert json.loads(minus)["polytope"]["limits"] == [-hi, -lo]


def test_cli_names_of_a_six_row_task(capsys, tmp_path):
    robot = tmp_path / "panda6.toml"
    robot.write_text(
        'library = "panda"\ntask = ["x", "y", "z", "wx", "wy", "wz"]\n'
        "weights = [1, 1, 1, 0.1, 0.1, 0.1]\n"
    )
    q = ["--robot", str(robot), "--q", "0,-0.3,0,-2.0,0,1.8,0.8", "--no-mvie", "--no-outer"]
    code, by_name, _ = run(capsys, *q, "--direction=-wz")
    assert code == 0
    code, by_vector, _ = run(capsys, *q, "--direction=0,0,0,0,0,-1")
    assert code == 0
    assert by_name.replace("along -wz = ", "along t = ") == by_vector


@pytest.mark.parametrize(
    ("value", "fragment"),
    [
        ("z", "task rows (x, y)"),
        ("xx", "each row at most once"),
        ("x,y", "--direction[0]: expected a number"),
        ("1,q", "--direction[1]: expected a number"),
    ],
)
def test_cli_refuses_a_bad_name_on_one_line(capsys, value, fragment):
    code, out, err = run(capsys, "--direction", value)
    assert code == 2 and out == ""
    assert err.startswith("polyell: error: --direction") and fragment in err
    assert len(err.strip().splitlines()) == 1


# --- the shared reader --------------------------------------------------------------------


def test_one_reader_for_every_form():
    from polyell.comparison.directions import direction_vectors, has_names

    task = ("x", "y", "z")
    assert has_names("z") and has_names(np.array("z")) and has_names(["x", [0, 0, 1.0]])
    assert has_names(np.array(["x", "y"])) and has_names(("x",))
    assert not has_names([0.0, 0.0, 1.0]) and not has_names(np.eye(3)) and not has_names([])
    np.testing.assert_array_equal(direction_vectors("z", task, "d"), [0.0, 0.0, 1.0])
    np.testing.assert_array_equal(direction_vectors(np.array("-y"), task, "d"), [0, -1.0, 0])
    found = direction_vectors(np.array(["x", "yz"]), task, "d")
    np.testing.assert_array_equal(found, [[1.0, 0, 0], [0, 1 / SQRT2, 1 / SQRT2]])
    mixed = direction_vectors(np.array(["x", [0.0, 0.6, 0.8]], dtype=object), task, "d")
    np.testing.assert_allclose(mixed, [[1.0, 0, 0], [0, 0.6, 0.8]], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(direction_vectors(np.eye(3), task, "d"), np.eye(3))
    with pytest.raises(pe.InputError) as info:
        direction_vectors(["x", [0.0, 2.0, 0.0]], task, "d")  # not of unit length
    assert info.value.argument == "d[1]"
    with pytest.raises(pe.InputError) as info:
        direction_vectors(np.array(["x", "q"]), task, "d")
    assert info.value.argument == "d[1]" and "got 'q'" in str(info.value)
