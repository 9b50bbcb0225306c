"""pe.posture_choice and its aggregate over targets (issue 22, items 2, 3 and 5).

Independent recomputation, posture by posture: the polytope's limits by a linear program
(scipy's HiGHS) on the torque cube, its radius about the origin and its volume from the
convex hull (Qhull) of the 2^n corners ``xg + M sigma``; each ellipsoid from the scalar
path (``pe.analyze`` and the scalar MVIE / outer solvers) with its radius by minimising
its support function over the unit circle; then the picks, regrets and rank correlations
by numpy and scipy here.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize, stats
from scipy.spatial import ConvexHull

import polyell as pe
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from polyell.geometry.outer import min_volume_enclosing_ellipsoid
from polyell.studies.posture import CRITERIA
from reference import PAPER_Q_REDUNDANT

ARM = pe.robots.load("chiacchio2000")
X = np.array([1.0, 0.0])
HEAVY_WRIST = pe.Candidate("heavy_wrist", weighting=np.diag([1.0, 1.0, 4.0]))
KINDS = ("polytope", "chiacchio", "yoshikawa", "mvie", "outer", "heavy_wrist")


@pytest.fixture(scope="module")
def paper_postures() -> np.ndarray:
    return pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=48).configurations


@pytest.fixture(scope="module")
def paper_choice(paper_postures) -> pe.PostureChoice:
    return pe.posture_choice(ARM, paper_postures, direction=X, candidates=[HEAVY_WRIST])


def lp_limits(M: np.ndarray, xg: np.ndarray, d: np.ndarray) -> tuple[float, float]:
    """min and max a subject to a d = xg + M u, |u|_inf <= 1 (variables u, a)."""
    n = M.shape[1]
    A_eq = np.hstack([M, -d[:, None]])
    bounds = [(-1.0, 1.0)] * n + [(None, None)]
    ends = []
    for sign in (1.0, -1.0):
        c = np.zeros(n + 1)
        c[-1] = sign
        result = optimize.linprog(c, A_eq=A_eq, b_eq=-xg, bounds=bounds, method="highs")
        assert result.status == 0
        ends.append(sign * result.fun)
    return ends[0], ends[1]


def hull_radius_and_volume(M: np.ndarray, xg: np.ndarray) -> tuple[float, float]:
    corners = np.array(list(itertools.product([-1.0, 1.0], repeat=M.shape[1])))
    hull = ConvexHull(xg + corners @ M.T)
    offsets = hull.equations[:, -1]  # n . x + offset <= 0 inside, |n| = 1
    return max(0.0, float(np.min(-offsets))), float(hull.volume)


def ellipsoid_radius(E: pe.Ellipsoid) -> float:
    """min over unit n of the support function n . c + |S U^T n| (2-D): a grid, then Brent."""

    def support(angle: float) -> float:
        n = np.array([np.cos(angle), np.sin(angle)])
        return float(n @ E.center + np.linalg.norm(E.semi_axes * (E.axes.T @ n)))

    grid = np.linspace(0.0, 2 * np.pi, 721)
    best = grid[np.argmin([support(a) for a in grid])]
    step = grid[1]
    found = optimize.minimize_scalar(
        support, bracket=(best - step, best, best + step), tol=1e-12, method="brent"
    )
    return max(0.0, float(found.fun))


def independent_values(postures: np.ndarray, d: np.ndarray) -> dict[str, dict[str, np.ndarray]]:
    values = {kind: {c: np.empty(len(postures)) for c in CRITERIA} for kind in KINDS}
    for k, q in enumerate(postures):
        analysis = pe.analyze(ARM.dynamics(q), ARM.tau_max)
        M, xg = analysis.M, analysis.xg
        lo, hi = lp_limits(M, xg, d)
        radius, volume = hull_radius_and_volume(M, xg)
        values["polytope"]["limit"][k] = max(0.0, min(-lo, hi))
        values["polytope"]["radius"][k] = radius
        values["polytope"]["volume"][k] = volume
        ellipsoids = {
            "chiacchio": analysis.ellipsoid("chiacchio"),
            "yoshikawa": analysis.ellipsoid("yoshikawa"),
            "mvie": max_volume_inscribed_ellipsoid(analysis.polytope),
            "outer": min_volume_enclosing_ellipsoid(analysis.polytope),
            "heavy_wrist": HEAVY_WRIST.ellipsoid(analysis),
        }
        for kind, E in ellipsoids.items():
            lo, hi = E.limits(d)
            values[kind]["limit"][k] = max(0.0, min(-lo, hi))
            values[kind]["radius"][k] = ellipsoid_radius(E)
            values[kind]["volume"][k] = E.volume
    return values


def independent_table(values: dict[str, dict[str, np.ndarray]]) -> dict[tuple[str, str], tuple]:
    rows = {}
    for kind, criteria in values.items():
        for criterion, index in criteria.items():
            truth = values["polytope"][criterion]
            picked = int(np.argmax(index))
            regret = 1.0 - truth[picked] / truth.max()
            rho = stats.spearmanr(index, truth).statistic
            tau = stats.kendalltau(index, truth).statistic
            rows[(kind, criterion)] = (picked, truth[picked], truth.max(), regret, rho, tau)
    return rows


def test_paper_arm_values_equal_an_independent_recomputation(paper_postures, paper_choice):
    values = independent_values(paper_postures, X)
    for kind in KINDS:
        for criterion, expected in values[kind].items():
            got = paper_choice.values[(kind, criterion)].to_numpy()
            scale = np.max(np.abs(expected))
            # MVIE and outer: two log-det solvers, each certified to a relative 1e-8 in volume
            rtol = 1e-7 if kind in ("mvie", "outer") else 1e-9
            np.testing.assert_allclose(got, expected, rtol=0, atol=rtol * scale, err_msg=kind)


def test_paper_arm_table_equals_an_independent_recomputation(paper_postures, paper_choice):
    expected = independent_table(independent_values(paper_postures, X))
    table = paper_choice.table
    assert list(table.index) == list(expected)
    for key, (picked, at_pick, best, regret, rho, tau) in expected.items():
        row = table.loc[key]
        rtol = 1e-9
        if key[0] in ("mvie", "outer"):  # two log-det solvers, certified to 1e-8 in volume
            rtol = 1e-6
        assert row["picked"] == picked, key
        np.testing.assert_allclose(
            row[["true_at_pick", "true_best", "regret", "spearman", "kendall"]].to_numpy(float),
            [at_pick, best, regret, rho, tau],
            rtol=rtol,
            atol=rtol,
            err_msg=str(key),
        )


def test_paper_arm_polytope_rows_have_no_regret(paper_choice):
    polytope = paper_choice.table.loc["polytope"]
    assert (polytope["regret"] == 0.0).all()
    assert (polytope["spearman"] == 1.0).all() and (polytope["kendall"] == 1.0).all()


def test_panda_batch_equals_the_scalar_path():
    """A 7-joint arm, 3-D task: the batch against LPs, Qhull and the scalar ellipsoids."""
    panda = pe.robots.load("panda")
    q0 = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
    postures = pe.self_motion(panda, q0, count=8, seed=3).configurations
    d = np.array([0.0, 0.6, 0.8])
    choice = pe.posture_choice(panda, postures, direction=d, mvie=False, outer=False)
    for k, q in enumerate(postures):
        analysis = pe.analyze(panda.dynamics(q), panda.tau_max)
        lo, hi = lp_limits(analysis.M, analysis.xg, d)
        radius, volume = hull_radius_and_volume(analysis.M, analysis.xg)
        row = choice.values.loc[k]
        np.testing.assert_allclose(row[("polytope", "lo")], lo, rtol=1e-9)
        np.testing.assert_allclose(row[("polytope", "hi")], hi, rtol=1e-9)
        np.testing.assert_allclose(row[("polytope", "radius")], radius, rtol=1e-9)
        np.testing.assert_allclose(row[("polytope", "volume")], volume, rtol=1e-9)
        for kind in ("chiacchio", "yoshikawa"):
            E = analysis.ellipsoid(kind)
            np.testing.assert_allclose(row[(kind, "volume")], E.volume, rtol=1e-9)
            np.testing.assert_allclose(
                [row[(kind, "lo")], row[(kind, "hi")]], E.limits(d), rtol=1e-9
            )

            # the radius: the support function's minimum over the sphere (many starts)
            def support(n, E=E):
                n = n / np.linalg.norm(n)
                return n @ E.center + np.linalg.norm(E.semi_axes * (E.axes.T @ n))

            starts = np.random.default_rng(k).normal(size=(30, 3))
            best = min(
                optimize.minimize(
                    support,
                    s,
                    method="Nelder-Mead",
                    options={"xatol": 1e-12, "fatol": 1e-13, "maxiter": 20000},
                ).fun
                for s in starts
            )
            np.testing.assert_allclose(row[(kind, "radius")], max(best, 0.0), rtol=1e-8)


def test_panda_direction_by_name():
    """issue 32: direction="z" is the unit vector (0, 0, 1) of the Panda's task rows."""
    panda = pe.robots.load("panda")
    q0 = np.array([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8])
    postures = pe.self_motion(panda, q0, count=4, seed=3).configurations
    options = {"mvie": False, "outer": False}
    named = pe.posture_choice(panda, postures, direction="-z", **options)
    vector = pe.posture_choice(panda, postures, direction=[0.0, 0.0, -1.0], **options)
    np.testing.assert_array_equal(named.direction, [0.0, 0.0, -1.0])
    assert named.values.equals(vector.values) and named.table.equals(vector.table)
    for k, q in enumerate(postures):  # against the LP of each posture
        analysis = pe.analyze(panda.dynamics(q), panda.tau_max)
        lo, hi = lp_limits(analysis.M, analysis.xg, np.array([0.0, 0.0, -1.0]))
        row = named.values.loc[k]
        np.testing.assert_allclose([row[("polytope", "lo")], row[("polytope", "hi")]], [lo, hi])
    with pytest.raises(pe.InputError) as info:
        pe.posture_choice(panda, postures, direction="wz", **options)
    assert info.value.argument == "direction" and "(x, y, z)" in str(info.value)


def test_singular_postures_take_the_scalar_path():
    """At the stretched arm the classic ellipsoid is undefined; nothing is flat-but-counted."""
    postures = np.array([[np.pi / 6, 0.0, 0.0], PAPER_Q_REDUNDANT, [0.3, 0.9, -0.4]])
    choice = pe.posture_choice(ARM, postures, direction=X)
    assert np.isnan(choice.values.loc[0, ("yoshikawa", "limit")])
    for kind in ("polytope", "chiacchio", "mvie", "outer"):
        assert choice.values.loc[0, (kind, "volume")] == 0.0
        assert choice.values.loc[0, (kind, "radius")] == 0.0
    assert choice.table.loc[("yoshikawa", "volume"), "picked"] in (1, 2)


def test_a_self_motion_object_is_accepted(paper_postures):
    motion = pe.self_motion(ARM, PAPER_Q_REDUNDANT, count=12)
    a = pe.posture_choice(ARM, motion, direction=X, mvie=False, outer=False)
    b = pe.posture_choice(ARM, motion.configurations, direction=X, mvie=False, outer=False)
    pd.testing.assert_frame_equal(a.table, b.table)


# --- properties -------------------------------------------------------------------------------


@st.composite
def problems(draw, gravity=(0.0, 9.81)):
    n = draw(st.integers(3, 4))
    lengths = draw(st.lists(st.floats(0.3, 1.5), min_size=n, max_size=n))
    masses = draw(st.lists(st.floats(0.5, 5.0), min_size=n, max_size=n))
    arm = pe.PlanarArm(lengths, masses, gravity=draw(st.sampled_from(gravity)))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (draw(st.integers(2, 7)), n))
    tau = rng.uniform(5.0, 60.0, n)
    angle = draw(st.floats(0.0, 2 * np.pi))
    return arm, q, tau, np.array([np.cos(angle), np.sin(angle)])


@settings(max_examples=25, deadline=None)
@given(problems())
def test_regret_is_a_fraction_and_the_polytope_has_none(problem):
    arm, q, tau, d = problem
    table = pe.posture_choice(arm, q, tau, direction=d, outer=False).table
    regret = table["regret"].dropna()
    assert ((regret >= 0.0) & (regret <= 1.0)).all()
    assert (table.loc["polytope", "regret"] == 0.0).all()


@settings(max_examples=25, deadline=None)
@given(problems(gravity=(0.0,)), st.floats(0.05, 20.0))
def test_picks_do_not_change_with_the_scale_of_the_torques(problem, factor):
    """Without gravity every set scales with the torque limits: the picks stay.

    (With gravity they need not: the centre xg does not scale, so the ranking can change.)
    """
    arm, q, tau, d = problem
    a = pe.posture_choice(arm, q, tau, direction=d, outer=False).table
    b = pe.posture_choice(arm, q, factor * tau, direction=d, outer=False).table
    pd.testing.assert_series_equal(a["picked"], b["picked"])
    np.testing.assert_allclose(a["regret"], b["regret"], atol=1e-9)


# --- bad input --------------------------------------------------------------------------------


@given(
    st.one_of(
        st.lists(st.floats(-2, 2), min_size=0, max_size=1),
        st.lists(st.floats(-2, 2), min_size=3, max_size=5),
        st.just([0.0, 0.0]),
        st.just([np.nan, 1.0]),
        st.just([[1.0, 0.0]]),
    )
)
def test_bad_directions_are_refused(direction):
    with pytest.raises(pe.InputError) as info:
        pe.posture_choice(ARM, np.array([[0.1, 0.5, 0.2], [0.2, 0.4, 0.1]]), direction=direction)
    assert info.value.argument == "direction"


@pytest.mark.parametrize(
    ("configurations", "argument"),
    [
        ([[0.1, 0.2, 0.3]], "configurations"),  # one posture: nothing to choose
        (np.zeros((0, 3)), "configurations"),
        ([[0.1, 0.2], [0.3, 0.4]], "configurations"),
        ([[0.1, 0.2, np.inf], [0.3, 0.4, 0.5]], "configurations"),
    ],
)
def test_bad_configurations_are_refused(configurations, argument):
    with pytest.raises(pe.InputError) as info:
        pe.posture_choice(ARM, configurations, direction=X)
    assert info.value.argument == argument


def test_other_bad_arguments_are_refused():
    q = [[0.1, 0.5, 0.2], [0.2, 0.4, 0.1]]
    with pytest.raises(pe.InputError, match=r"^mvie:"):
        pe.posture_choice(ARM, q, direction=X, mvie=1)
    with pytest.raises(pe.InputError, match=r"^robot:"):
        pe.posture_choice("panda", q, direction=X)
    with pytest.raises(pe.InputError, match=r"^tau_max:"):
        pe.posture_choice(ARM, q, [1.0, 2.0], direction=X)


# --- over many targets ------------------------------------------------------------------------


def test_over_targets_aggregates_each_targets_choice():
    starts = np.array([PAPER_Q_REDUNDANT, [0.4, 1.1, -0.7]])
    result = pe.posture_choice_over_targets(
        ARM, starts, direction=X, postures=30, mvie=False, outer=False
    )
    regrets = []
    for start in starts:
        motion = pe.self_motion(ARM, start, count=30)
        table = pe.posture_choice(ARM, motion, direction=X, mvie=False, outer=False).table
        regrets.append(table["regret"])
    both = pd.concat(regrets, axis=1).to_numpy()
    np.testing.assert_allclose(result.summary["median_regret"], np.median(both, axis=1))
    np.testing.assert_allclose(result.summary["worst_regret"], both.max(axis=1))
    assert (result.summary["targets"] == 2).all()
    np.testing.assert_allclose(result.targets[1], ARM.forward_kinematics(starts[1]))
    assert repr(result) == (  # one line, no arrays
        "PostureChoiceOverTargets(targets=2, joints=3, task_rows=2, "
        "sets=['polytope', 'chiacchio', 'yoshikawa'])"
    )


def test_random_targets_are_seeded():
    a = pe.posture_choice_over_targets(
        ARM, count=3, seed=5, direction=X, postures=20, mvie=False, outer=False
    )
    b = pe.posture_choice_over_targets(
        ARM, count=3, seed=5, direction=X, postures=20, mvie=False, outer=False
    )
    np.testing.assert_array_equal(a.starts, b.starts)
    pd.testing.assert_frame_equal(a.summary, b.summary)
    assert len(a.starts) == 3 and (a.summary["worst_regret"] <= 1.0).all()


def test_over_targets_refuses_both_or_neither():
    with pytest.raises(pe.InputError, match=r"^starts:"):
        pe.posture_choice_over_targets(ARM, direction=X)
    with pytest.raises(pe.InputError, match=r"^starts:"):
        pe.posture_choice_over_targets(ARM, [PAPER_Q_REDUNDANT], count=2, direction=X)
    with pytest.raises(pe.InputError, match=r"^starts\[0\]:"):
        pe.posture_choice_over_targets(ARM, [[np.pi / 6, 0.0, 0.0]], direction=X)


# --- tables -----------------------------------------------------------------------------------


def test_tables_are_written(tmp_path, paper_choice):
    paths = pe.write_posture_tables(paper_choice.table, tmp_path, "Paper arm | x_dd & 100%")
    latex = paths["latex"].read_text()
    assert r"\toprule" in latex and r"\bottomrule" in latex
    assert r"Paper arm \textbar{} x\_dd \& 100\%" in latex
    assert "heavy\\_wrist" in latex
    markdown = paths["markdown"].read_text()
    assert r"Paper arm \| x\_dd & 100%" in markdown and r"heavy\_wrist" in markdown
    back = pd.read_csv(paths["csv"], index_col=[0, 1])
    np.testing.assert_allclose(back["regret"], paper_choice.table["regret"], rtol=1e-15)


def test_tables_refuse_a_missing_folder(tmp_path, paper_choice):
    with pytest.raises(pe.InputError, match=r"^folder:"):
        pe.write_posture_tables(paper_choice.table, tmp_path / "nowhere")


def _support_radius(center: np.ndarray, shape: np.ndarray) -> float:
    """min over unit n of n . c + sqrt(n^T Q n): the ball about 0 inside {c + Q^1/2 u}."""
    w, V = np.linalg.eigh(shape)
    return ellipsoid_radius(pe.Ellipsoid(center, V, np.sqrt(w)))


def _quadratic_limit(center: np.ndarray, shape: np.ndarray, d: np.ndarray) -> float:
    """min(-lo, hi) of {s : (s d - c)^T Q^-1 (s d - c) <= 1}, 0 if it misses 0 or the line."""
    Qi = np.linalg.inv(shape)
    a, b, c = d @ Qi @ d, -2.0 * d @ Qi @ center, center @ Qi @ center - 1.0
    disc = b * b - 4 * a * c
    if disc < 0:
        return 0.0
    lo, hi = (-b - np.sqrt(disc)) / (2 * a), (-b + np.sqrt(disc)) / (2 * a)
    return max(0.0, min(-lo, hi))


def test_velocity_choice_equals_an_independent_recomputation(paper_postures):
    """Velocities: the zonotope of the joint velocity box (LP, Qhull over 2^n corners) and
    Yoshikawa's ellipsoid {J qd_c + J L u}, from the robot's own velocity limits."""
    choice = pe.posture_choice(ARM, paper_postures, direction=X, capacity="velocity")
    assert choice.unit == "m/s"
    assert list(dict.fromkeys(choice.values.columns.get_level_values(0))) == [
        "polytope",
        "yoshikawa",
        "mvie",
        "outer",
    ]
    centre, half = (ARM.qd_max + ARM.qd_min) / 2, (ARM.qd_max - ARM.qd_min) / 2
    for k, q in enumerate(paper_postures):
        J = ARM.dynamics(q).J
        M, xg = J * half, J @ centre
        lo, hi = lp_limits(M, xg, X)
        radius, volume = hull_radius_and_volume(M, xg)
        expected = {
            ("polytope", "limit"): max(0.0, min(-lo, hi)),
            ("polytope", "radius"): radius,
            ("polytope", "volume"): volume,
            ("yoshikawa", "limit"): _quadratic_limit(xg, M @ M.T, X),
            ("yoshikawa", "radius"): _support_radius(xg, M @ M.T),
            ("yoshikawa", "volume"): np.pi * np.sqrt(np.linalg.det(M @ M.T)),
        }
        analysis = pe.analyze(
            ARM.dynamics(q), capacity="velocity", qd_max=ARM.qd_max, qd_min=ARM.qd_min
        )
        for kind, solve in (
            ("mvie", max_volume_inscribed_ellipsoid),
            ("outer", min_volume_enclosing_ellipsoid),
        ):
            expected[(kind, "volume")] = solve(analysis.polytope).volume
        for key, value in expected.items():
            rtol = 1e-7 if key[0] in ("mvie", "outer") else 1e-9
            assert choice.values.loc[k, key] == pytest.approx(value, rel=rtol, abs=1e-12), (k, key)
    table = choice.table
    assert (table.loc["polytope", "regret"] == 0).all()
    assert ((table["regret"] >= 0) & (table["regret"] <= 1)).all()


def test_force_choice_equals_an_independent_recomputation(paper_postures):
    """Forces: {h : tau_min <= J^T h + g <= tau_max} from every two rows (Qhull, LP), and
    the three force ellipsoids from their shape matrices (the theory page's derivations)."""
    postures = paper_postures[::4]
    choice = pe.posture_choice(
        ARM, postures, direction=X, capacity="force", mvie=False, outer=False
    )
    assert choice.unit == "N"
    upper, lower = ARM.tau_max, ARM.tau_min
    centre, half = (upper + lower) / 2, (upper - lower) / 2
    for k, q in enumerate(postures):
        dyn = ARM.dynamics(q)
        J, g = dyn.J, dyn.g
        A = np.vstack([J.T, -J.T])
        b = np.concatenate([upper - g, g - lower])
        points = []
        for i, j in itertools.combinations(range(len(A)), 2):
            if abs(np.linalg.det(A[[i, j]])) > 1e-12:
                h = np.linalg.solve(A[[i, j]], b[[i, j]])
                if np.all(A @ h <= b + 1e-9):
                    points.append(h)
        hull = ConvexHull(np.array(points))
        inside = bool(np.all(b > 0))
        radius = float(np.min(b / np.linalg.norm(A, axis=1))) if inside else 0.0
        ends = []
        for sign in (1.0, -1.0):  # max and min of s with s X in the set
            result = optimize.linprog([-sign], A_ub=(A @ X)[:, None], b_ub=b, bounds=[(None, None)])
            ends.append(sign * -result.fun)
        P, qv = J.T / half[:, None], (g - centre) / half  # |P h + q| <= 1
        G = P.T @ P
        h0 = -np.linalg.solve(G, P.T @ qv)
        shrink = 1.0 - (qv @ qv - (P.T @ qv) @ np.linalg.solve(G, P.T @ qv))
        pinv = np.linalg.pinv(J.T)
        shapes = {
            "chiacchio": (h0, shrink * np.linalg.inv(G)),
            "yoshikawa": (-pinv @ (g - centre), pinv @ np.diag(half**2) @ pinv.T),
            "static": (np.zeros(2), np.linalg.inv(G)),
        }
        expected = {
            ("polytope", "limit"): max(0.0, min(-ends[1], ends[0])),
            ("polytope", "radius"): radius,
            ("polytope", "volume"): hull.volume,
        }
        for kind, (c, Q) in shapes.items():
            expected[(kind, "limit")] = _quadratic_limit(c, Q, X)
            expected[(kind, "radius")] = _support_radius(c, Q)
            expected[(kind, "volume")] = np.pi * np.sqrt(np.linalg.det(Q))
        for key, value in expected.items():
            assert choice.values.loc[k, key] == pytest.approx(value, rel=1e-8, abs=1e-9), (k, key)
    assert (choice.table.loc["polytope", "regret"] == 0).all()


def test_capacity_arguments_are_checked(paper_postures):
    with pytest.raises(pe.InputError, match="tau_max"):
        pe.posture_choice(ARM, paper_postures, ARM.tau_max, direction=X, capacity="velocity")
    with pytest.raises(pe.InputError, match="qd_max"):
        pe.posture_choice(ARM, paper_postures, direction=X, qd_max=ARM.qd_max)
    with pytest.raises(pe.InputError, match="capacity"):
        pe.posture_choice(ARM, paper_postures, direction=X, capacity="speed")


def test_a_set_undefined_at_every_posture_is_written_as_such(tmp_path, paper_postures):
    """A torque weighting has no force ellipsoid: no posture picked, the tables still written."""
    weighted = pe.Candidate("w", weighting=np.diag([1.0, 1.0, 4.0]))
    choice = pe.posture_choice(
        ARM,
        paper_postures[:6],
        direction=X,
        capacity="force",
        candidates=[weighted],
        mvie=False,
        outer=False,
    )
    assert choice.table.loc[("w", "limit"), "picked"] is pd.NA
    files = pe.write_posture_tables(choice.table, tmp_path)
    assert "| w " in files["markdown"].read_text()


def test_the_regret_beside_an_unbounded_force_set():
    # The third attack (issue 33): at a singular posture the force set is unbounded (volume
    # inf): the truth's own pick had regret 1 - inf / inf = NaN. It is 0 at the best, and a
    # finite pick beside an infinite best loses all of it: 1.
    arm = pe.robots.load("chiacchio2000")
    postures = np.array(
        [[np.pi / 2, -np.pi / 2, -np.pi / 2], [np.pi / 2, 0.0, 0.0], [np.pi / 2, -1.0, -0.5]]
    )
    choice = pe.posture_choice(arm, postures, direction=[1.0, 0.0], capacity="force")
    volume = choice.values[("polytope", "volume")]
    assert np.isinf(volume[1]) and np.isfinite(volume[[0, 2]]).all()
    table = choice.table
    assert table.loc[("polytope", "volume"), "regret"] == 0.0
    for kind in ("static", "mvie"):
        picked = table.loc[(kind, "volume"), "picked"]
        expected = 0.0 if picked == 1 else 1.0
        assert table.loc[(kind, "volume"), "regret"] == expected
    assert not table["regret"].isna().any()
