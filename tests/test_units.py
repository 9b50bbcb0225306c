"""Units and labels follow the task: axis labels, tables, text and JSON (issue 11)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell.figures import plot_sets, plot_sets_3d
from polyell.report import analysis_to_json, format_analysis
from reference import random_arm

Q_PANDA = [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8]


@pytest.fixture(scope="module")
def angular():
    robot = pe.robots.load("panda", task="angular")
    return pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)


def test_a_vertical_plane_task_labels_its_axes_x_and_z():
    robot = pe.robots.load("panda", task=["x", "z"])
    analysis = pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)
    assert analysis.dynamics.task == ("x", "z")
    ax = plot_sets(analysis).axes[0]
    assert ax.get_xlabel() == r"$\ddot x$ [m/s$^2$]"
    assert ax.get_ylabel() == r"$\ddot z$ [m/s$^2$]"


def test_an_angular_task_is_in_rad_per_s2_everywhere(angular):
    ax = plot_sets_3d(angular).axes[0]
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == [
        rf"$\dot\omega_{axis}$ [rad/s$^2$]" for axis in "xyz"
    ]
    table = pe.compare(angular, 16, mvie=False).to_markdown()
    assert "(rad/s^2)^3" in table and "m/s^2" not in table
    latex = pe.compare(angular, 16, mvie=False).to_latex()
    assert r"volume [(rad/s$^{2}$)$^{3}$]" in latex
    text = format_analysis(angular, np.array([1.0, 0.0, 0.0]), "t")
    assert "task rows wx, wy, wz [rad/s^2]" in text and "m/s^2" not in text
    data = analysis_to_json(angular, np.array([1.0, 0.0, 0.0]))
    assert data["task"] == ["wx", "wy", "wz"] and data["unit"] == "rad/s^2"


def test_mixed_rows_are_in_weighted_units():
    robot = pe.robots.load("panda", task=["x", "y", "z", "wz"], weights=[1, 1, 1, 0.5])
    analysis = pe.analyze(robot.dynamics(Q_PANDA), robot.tau_max)
    assert "weighted units" in pe.compare(analysis, 8, mvie=False).to_markdown()


def test_task_names_are_validated_and_kept_by_batches():
    J, B, g = np.ones((4, 2, 3)), np.broadcast_to(np.eye(3), (4, 3, 3)), np.zeros((4, 3))
    dyn = pe.Dynamics(J, B, g, task=("x", "z"))
    assert dyn[2].task == ("x", "z")
    assert pe.Dynamics(J[0], B[0], g[0]).task == ("x", "y")  # the default: linear rows
    with pytest.raises(pe.InputError, match="2 distinct row names"):
        pe.Dynamics(J[0], B[0], g[0], task=("x", "x"))
    with pytest.raises(pe.InputError, match="task"):
        pe.Dynamics(J[0], B[0], g[0], task="xz")


def test_a_study_of_an_angular_task_writes_its_unit(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[robot]\nlibrary = "panda"\ntask = "angular"\n[[points]]\nname = "p"\n'
        f"q = {Q_PANDA}\ndirection = [1, 0, 0]\n"
        '[compare]\nmvie = false\ndirections = 16\n[output]\nformats = ["png"]\ndpi = 30\n'
    )
    pe.studies.run_study(pe.studies.load_study(spec), tmp_path / "out")
    text = (tmp_path / "out" / "comparison.md").read_text()
    assert "volume [(rad/s^2)^3]" in text and "m/s^2" not in text
    assert "[rad/s^2]" in (tmp_path / "out" / "numbers.md").read_text()


# --- Scale invariance (issue 20): no score depends on the units of torques or of the task.

#: Scores with a unit: the volume scales by s^r; every other score is a ratio or a count.
DIMENSIONAL = ("volume",)
EPS = float(np.finfo(float).eps)


def scaled_problem(seed: int, torque_unit: float, task_unit: float):
    """A random planar arm's Dynamics and limits, with torques and task rows rescaled.

    ``torque_unit`` multiplies the torque limits and the gravity torques together (N m to
    another unit); ``task_unit`` multiplies every row of J (accelerations in another unit).
    """
    arm, q, rng = random_arm(seed, 3)
    dyn = arm.dynamics(q)
    tau_max = rng.uniform(5.0, 100.0, 3)
    tau_min = -tau_max * rng.uniform(0.3, 1.5, 3)
    scaled = pe.Dynamics(dyn.J * task_unit, dyn.B, dyn.g * torque_unit)
    return scaled, tau_max * torque_unit, tau_min * torque_unit


def rounding_bound(analysis: pe.Analysis) -> float:
    """The stated rounding bound of a score: scores.scale_rtol of the worst ellipsoid.

    Multiplying the inputs by a power of ten rounds each of them (relative error eps): the
    scores move by at most the condition of the computation times eps, which scale_rtol
    states for the scales (16 (m + n) eps extent / s_min); the new ellipsoid's s_min (that
    of M) is the smallest of the ellipsoids here, the classic one's at most a factor
    |F| |F^-1| below it, so the bound is taken with s_min(M) / cond(F).
    """
    from polyell.comparison.scores import scale_rtol

    m, n = analysis.M.shape
    extent = max(np.linalg.norm(analysis.xg), np.linalg.norm(analysis.M, axis=0).sum())
    classic = analysis.ellipsoid("yoshikawa").semi_axes if not analysis.is_singular else []
    smallest = min([analysis.svd.sigma[-1], *classic])
    return float(scale_rtol(extent, smallest, m, n))


def assert_same_scores(base: pe.Comparison, scaled: pe.Comparison, unit: float) -> None:
    from polyell.geometry.mvie import MVIE_GAP

    bound = rounding_bound(base.analysis)
    hi_p = np.abs(base.polytope_limits.hi)
    smallest_hi = float(np.nanmin(hi_p[hi_p > 0])) if np.any(hi_p > 0) else 1.0
    extent = float(np.linalg.norm(base.analysis.M, axis=0).sum())
    for kind in base.kinds:
        a, b = base[kind], scaled[kind]
        assert a.defined == b.defined, kind
        if not a.defined:
            continue
        # The MVIE and the outer ellipsoid are optimal to their certified gap in log det
        # (volumes within MVIE_GAP / 2, axes within MVIE_GAP in relative terms).
        rtol = max(bound, MVIE_GAP) if kind in ("mvie", "outer") else bound
        for name in pe.SCORE_NAMES:
            x, y = getattr(a, name), getattr(b, name)
            if name in DIMENSIONAL:
                y = y / unit**a.dimension
            if name in ("coverage", "overreach") and getattr(a, f"{name}_stderr") > 0:
                # Monte Carlo with the same seed: the same points, up to those that the
                # rounding moves across a facet; within the stated standard error.
                stderr = max(getattr(a, f"{name}_stderr"), getattr(b, f"{name}_stderr"))
                assert abs(x - y) <= stderr, (kind, name, x, y)
            elif name.endswith("_stderr"):
                assert abs(x - y) <= 0.5 * max(x, y) + 1e-12, (kind, name, x, y)
            elif name.startswith("direction_"):
                # (hi_E - hi_P) / |hi_P|: absolute errors of rtol * extent in both ends,
                # divided by the smallest |hi_P| used.
                tolerance = 4 * rtol * extent / smallest_hi
                assert abs(x - y) <= tolerance * max(1.0, abs(x)) or (np.isnan(x) and np.isnan(y))
            elif isinstance(x, int):
                assert x == y, (kind, name, x, y)
            else:
                assert np.isclose(x, y, rtol=4 * rtol, atol=0.0) or (np.isnan(x) and np.isnan(y)), (
                    kind,
                    name,
                    x,
                    y,
                )


@given(seed=st.integers(0, 10_000), exponent=st.integers(-16, 16))
@settings(max_examples=12)
def test_every_score_is_invariant_under_the_torque_unit(seed, exponent):
    """Torque limits and gravity torques times any power of ten: the same scores."""
    base = pe.compare(pe.analyze(*scaled_problem(seed, 1.0, 1.0)), 32, samples=512)
    unit = 10.0**exponent
    scaled = pe.compare(pe.analyze(*scaled_problem(seed, unit, 1.0)), 32, samples=512)
    # tau = B qdd + g with B unchanged: the accelerations scale with the torques.
    assert_same_scores(base, scaled, unit)


@given(seed=st.integers(0, 10_000), exponent=st.integers(-16, 16))
@settings(max_examples=12)
def test_every_score_is_invariant_under_the_task_unit(seed, exponent):
    """J rows scaled by s (m/s^2 to another unit): accelerations scale by s, scores do not."""
    base = pe.compare(pe.analyze(*scaled_problem(seed, 1.0, 1.0)), 32, samples=512)
    unit = 10.0**exponent
    scaled = pe.compare(pe.analyze(*scaled_problem(seed, 1.0, unit)), 32, samples=512)
    assert_same_scores(base, scaled, unit)
    np.testing.assert_allclose(scaled.analysis.xg, unit * base.analysis.xg, rtol=1e-12)


@given(seed=st.integers(0, 10_000), torque=st.integers(-16, 16), task=st.integers(-16, 16))
@settings(max_examples=8)
def test_sweep_rows_are_invariant_under_both_units(seed, torque, task):
    rng = np.random.default_rng(seed)
    arm, _, _ = random_arm(seed, 3)
    dyn = arm.dynamics(rng.uniform(-np.pi, np.pi, (6, 3)))
    tau_max = rng.uniform(5.0, 100.0, 3)
    s_tau, s_task = 10.0**torque, 10.0**task
    rows = {}
    for key, (a, b) in {"base": (1.0, 1.0), "scaled": (s_tau, s_task)}.items():
        batch = pe.Dynamics(dyn.J * b, dyn.B, dyn.g * a)
        rows[key] = pe.sweep(batch, tau_max=tau_max * a, directions=32)
    for name in rows["base"].columns:
        x, y = rows["base"][name].to_numpy(), rows["scaled"][name].to_numpy()
        acceleration = s_tau * s_task  # qdd scales with the torques (B fixed), xdd with J
        if name.endswith("_volume"):
            y = y / acceleration ** rows["base"]["polytope_dim"].to_numpy()
        if name.endswith("_radius"):
            y = y / acceleration
        # Every row's bound: the batch works from the SVD of M like compare, so the
        # rounding bound of the scales holds; 1e-9 covers it for these well-conditioned
        # arms (cond(M) < 1e4 at random postures away from the stretched ones: 16 * 5 *
        # 2.2e-16 * 1e4 = 1.8e-10) except at direction statistics near hi_P = 0, where the
        # relative error divides by |hi_P|: compared with the same absolute tolerance.
        both_nan = np.isnan(x) & np.isnan(y)
        close = np.isclose(x, y, rtol=1e-9, atol=1e-9 if "direction" in name else 0.0)
        assert np.all(both_nan | close), (name, x, y)


@pytest.mark.parametrize(
    ("j", "b", "g", "tau"), [(1e300, 1.0, 1.0, 1e150), (1e300, 1.0, 1e300, 1e150)]
)
def test_a_sweep_whose_accelerations_overflow_is_refused_without_a_warning(j, b, g, tau):
    """A sweep whose M = J B^-1 L overflows: refused naming the dynamics, with no warning.

    The magnitude check refuses the inf that comes out; no RuntimeWarning is emitted on
    the way (warnings are errors here).
    """
    rng = np.random.default_rng(0)
    K, m, n = 3, 2, 3
    dyn = pe.Dynamics(
        rng.normal(size=(K, m, n)) * j, np.array([np.eye(n) * b] * K), rng.normal(size=(K, n)) * g
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(pe.InputError, match="dyn or tau_max: expected accelerations of size"):
            pe.sweep(dyn, tau_max=np.full(n, tau), directions=8)
