"""Property suite over the public API (issue 20): a PolyellError or a valid result.

Every public function of the core API is called with seeded, hypothesis-drawn arguments:
valid ones at magnitudes from 1e-300 to 1e300, and the same with one argument broken
(wrong type or shape, NaN, inf, 0, negative, 1e-300, 1e300).  The invariant: the call
raises a :class:`polyell.PolyellError`, or returns a valid result -- intervals with
``lo <= hi`` or both NaN, fractions in [0, 1], volumes >= 0, inscribed sets inside the
polytope, no NaN where a number is promised -- and no warning escapes (warnings are
errors inside every test, except the package's own ProjectedInputWarning, which says that
rounded input was projected).  The run time is bounded by the profile of conftest.py
(derandomized, 40 examples a test) and by small sizes (m <= 3, n <= 4).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell.comparison.metrics import inside_rtol
from polyell.geometry.directions import directions_in, sphere_directions
from polyell.validation import magnitude_limit

#: Values that break an argument.
SPECIAL = [np.nan, np.inf, -np.inf, 0.0, -1.0, 1e-300, -1e-300, 1e300, -1e300, 1e308]
#: Arguments of the wrong kind.
JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3]
#: Scales of valid data (units): from 1e-300 to 1e300.
MAGNITUDES = [1e-300, 1e-150, 1e-16, 1e-3, 1.0, 1e3, 1e16, 1e150, 1e300]

EPS = float(np.finfo(float).eps)


def calm(call: Callable[[], Any]) -> Any:
    """Run ``call`` with every warning an error (but ProjectedInputWarning); None on refusal."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", pe.ProjectedInputWarning)
        try:
            return call()
        except pe.PolyellError:
            return None


def assert_interval(lo: np.ndarray, hi: np.ndarray) -> None:
    lo, hi = np.asarray(lo), np.asarray(hi)
    assert lo.shape == hi.shape
    assert np.array_equal(np.isnan(lo), np.isnan(hi))
    ok = ~np.isnan(lo)
    assert np.all(np.isfinite(lo[ok])) and np.all(np.isfinite(hi[ok]))
    # lo <= hi; a grazing line gives one point, (lo + hi) / 2 of both, within rounding
    assert np.all(lo[ok] <= hi[ok] + 4 * EPS * np.maximum(np.abs(lo[ok]), np.abs(hi[ok])))


@st.composite
def problems(draw: st.DrawFn) -> dict[str, Any]:
    """A valid problem (J, B, g, limits) of random size, rank and magnitude."""
    m = draw(st.integers(1, 3))
    n = draw(st.integers(1, 4))
    rank = draw(st.integers(0, min(m, n)))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    U = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :rank]
    V = np.linalg.qr(rng.normal(size=(n, n)))[0][:, :rank]
    J = (U * rng.uniform(0.3, 3.0, rank)) @ V.T if rank else np.zeros((m, n))
    if rank == 0 and draw(st.booleans()):
        J = rng.normal(size=(m, n))  # full rank after all
    Q = np.linalg.qr(rng.normal(size=(n, n)))[0]
    B = (Q * rng.uniform(0.5, 5.0, n)) @ Q.T
    tau_max = rng.uniform(1.0, 10.0, n)
    asymmetric = draw(st.booleans())
    tau_min = -tau_max * rng.uniform(0.2, 1.5, n) if asymmetric else None
    g = rng.normal(size=n) * tau_max * draw(st.sampled_from([0.0, 0.1, 1.0, 3.0]))
    task, torque, inertia = (draw(st.sampled_from(MAGNITUDES)) for _ in range(3))
    return {
        "J": J * task,
        "B": B * inertia,
        "g": g * torque,
        "tau_max": tau_max * torque,
        "tau_min": None if tau_min is None else tau_min * torque,
        "seed": seed,
    }


@st.composite
def broken(draw: st.DrawFn, value: Any) -> Any:
    """``value`` itself, or a broken copy: a special entry, a wrong shape, or junk."""
    how = draw(st.sampled_from(["same", "special", "shape", "junk", "scale"]))
    if how == "same" or (value is None and how in ("special", "shape", "scale")):
        return value
    if how == "junk":
        return draw(st.sampled_from(JUNK))
    array = np.array(value, dtype=float, copy=True)
    if array.ndim == 0:  # a scalar argument: a special value, or an array of one
        return draw(st.sampled_from([*SPECIAL, array[None]]))
    if how == "shape":
        return draw(st.sampled_from([array.ravel(), array[..., :-1], array[None], array.T]))
    if how == "scale":
        with np.errstate(over="ignore"):  # 1e300 * 1e300: inf, a value to refuse
            return array * draw(st.sampled_from(SPECIAL[3:]))
    if array.size:
        index = draw(st.integers(0, array.size - 1))
        array.flat[index] = draw(st.sampled_from(SPECIAL))
    return array


def build(problem: dict[str, Any]) -> pe.Analysis | None:
    def make() -> pe.Analysis:
        dyn = pe.Dynamics(problem["J"], problem["B"], problem["g"])
        return pe.analyze(dyn, problem["tau_max"], problem["tau_min"])

    result: pe.Analysis | None = calm(make)
    event("analysis built" if result is not None else "analysis refused")
    return result


def check_analysis(an: pe.Analysis) -> None:
    assert np.all(np.isfinite(an.M)) and np.all(np.isfinite(an.xg))
    P = an.polytope
    assert np.isfinite(P.volume) and P.volume >= 0
    assert np.all(np.isfinite(P.vertices))
    assert P.ball_radius >= 0
    assert np.isnan(P.origin_radius) or P.origin_radius >= 0
    T = directions_in(P.affine_set, 12) if P.dim else sphere_directions(4, an.dynamics.m)
    if len(T):
        assert_interval(*calm(lambda: P.limits(T)))


def boundary_points(E: pe.Ellipsoid, count: int, seed: int) -> np.ndarray:
    u = np.random.default_rng(seed).normal(size=(count, E.rank))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    points: np.ndarray = E.center + (u * E.semi_axes) @ E.axes.T
    return points


def assert_inside(E: pe.Ellipsoid, P: pe.Polytope, seed: int) -> None:
    """Boundary points of an inscribed set belong to P (within the scales' stated bound)."""
    if E.rank == 0:
        assert P.contains(E.center)
        return
    shrink = 1.0 - inside_rtol(E, P)
    points = E.center + shrink * (boundary_points(E, 64, seed) - E.center)
    assert np.all(P.contains(points))


# --- pe.Dynamics, pe.analyze, Analysis and its sets


@given(problem=problems(), data=st.data())
def test_analyze_with_any_argument_broken(problem, data):
    name = data.draw(st.sampled_from(["J", "B", "g", "tau_max", "tau_min", "none"]))
    if name != "none":
        problem[name] = data.draw(broken(problem[name]))
    an = build(problem)
    if an is not None:
        check_analysis(an)


@given(problem=problems(), kind=st.sampled_from(["chiacchio", "yoshikawa", "mvie", 3, None]))
def test_ellipsoids_are_inside_the_polytope(problem, kind):
    an = build(problem)
    if an is None:
        return
    E = calm(lambda: an.ellipsoid(kind))
    if E is None:
        return
    assert np.isfinite(E.volume) and E.volume >= 0
    assert np.all(np.isfinite(E.semi_axes)) and np.all(E.semi_axes > 0)
    assert_inside(E, an.polytope, problem["seed"])
    T = directions_in(an.polytope.affine_set, 12) if E.rank else np.zeros((0, E.ambient_dim))
    if len(T):
        lo, hi = calm(lambda: E.limits(T))
        assert_interval(lo, hi)
        P_lo, P_hi = an.polytope.limits(T)
        # E inside P: its interval inside P's, to the rounding of both ends
        scale = np.maximum(np.abs(P_hi), np.abs(P_lo)) + np.linalg.norm(an.xg)
        tolerance = 1e-7 * scale
        assert np.all((hi <= P_hi + tolerance) | np.isnan(hi))


@given(problem=problems(), data=st.data())
def test_inverse_with_any_point(problem, data):
    an = build(problem)
    if an is None:
        return
    kind = data.draw(st.sampled_from(["chiacchio", "yoshikawa", "x", None]))
    point = an.xg + an.M @ np.random.default_rng(problem["seed"]).uniform(-1, 1, an.M.shape[1])
    xdd = data.draw(broken(point))
    result = calm(lambda: an.inverse(xdd, kind))
    if result is not None:
        assert np.all(np.isfinite(result.qdd)) and np.all(np.isfinite(result.tau_n))
        if kind == "chiacchio" and np.array_equal(np.asarray(xdd, dtype=float), point):
            # a point of P is reached with |tau_n|_inf <= 1 by the minimum-norm torque?
            # Not in general (that is the witness score); its torques are finite.
            assert result.tau_n.shape == (an.M.shape[1],)


# --- pe.compare and pe.Candidate


def check_scores(cmp: pe.Comparison, seed: int) -> None:
    P = cmp.analysis.polytope
    for kind in cmp.kinds:
        s = cmp[kind]
        if not s.defined:
            assert s.reason
            continue
        for name in ("coverage", "overreach"):
            value = getattr(s, name)
            assert 0.0 <= value <= 1.0, (kind, name, value)
            assert getattr(s, f"{name}_stderr") >= 0
        assert np.isfinite(s.volume) and s.volume >= 0
        assert not np.isnan(s.inscribed_scale) and not np.isnan(s.enclosing_scale)
        assert np.isfinite(s.witness_torque_max) and s.witness_torque_max >= 0
        if s.directions_used:
            stats = (s.direction_error_mean, s.direction_error_max, s.direction_error_rms)
            assert all(np.isfinite(stats)) and min(stats) >= 0
        if kind in ("chiacchio", "yoshikawa", "mvie"):
            assert s.inscribed_scale >= 1.0 - inside_rtol(cmp.ellipsoid(kind), P)
            assert_inside(cmp.ellipsoid(kind), P, seed)
        if kind == "chiacchio":  # tau_n = M^# (x - xg): |tau_n|_2 <= 1 on the ellipsoid
            assert s.witness_torque_max <= 1.0 + 1e-9


@given(problem=problems(), data=st.data())
def test_compare_with_any_argument_broken(problem, data):
    an = build(problem)
    if an is None:
        return
    arguments: dict[str, Any] = {"directions": 16, "samples": 256, "seed": 0}
    name = data.draw(st.sampled_from(["directions", "samples", "seed", "mvie", "none"]))
    if name == "directions":
        T = sphere_directions(5, an.dynamics.m)
        arguments[name] = data.draw(st.one_of(st.just(T), broken(T), st.sampled_from(JUNK)))
    elif name != "none":
        arguments[name] = data.draw(st.one_of(broken(arguments.get(name, True)), st.just(0)))
    cmp = calm(lambda: pe.compare(an, **arguments))
    event("compared" if cmp is not None else "compare refused")
    if cmp is not None:
        check_scores(cmp, problem["seed"])


@given(problem=problems(), data=st.data())
def test_candidates_with_any_matrix(problem, data):
    an = build(problem)
    if an is None:
        return
    m, n = an.M.shape
    which = data.draw(st.sampled_from(["weighting", "core"]))
    size = n if which == "weighting" else m
    rng = np.random.default_rng(problem["seed"])
    Q = np.linalg.qr(rng.normal(size=(size, size)))[0]
    matrix = (Q * rng.uniform(0.5, 2.0, size)) @ Q.T
    if which == "core" and an.polytope.ball_radius > 0:  # the polytope's size: (m/s^2)^-2
        matrix = matrix / an.polytope.ball_radius**2
    matrix = data.draw(broken(matrix))
    name = data.draw(st.sampled_from(["mine", "Bad name", "chiacchio", 3]))
    candidate = calm(lambda: pe.Candidate(name, **{which: matrix}))
    if candidate is None:
        return
    cmp = calm(
        lambda: pe.compare(an, 8, samples=256, mvie=False, outer=False, candidates=[candidate])
    )
    if cmp is not None:
        check_scores(cmp, problem["seed"])


# --- pe.Ellipsoid and pe.Polytope built by hand


@given(
    data=st.data(),
    m=st.integers(1, 3),
    magnitude=st.sampled_from(MAGNITUDES),
    seed=st.integers(0, 2**16),
)
def test_ellipsoid_and_its_methods(data, m, magnitude, seed):
    rng = np.random.default_rng(seed)
    r = data.draw(st.integers(0, m))
    axes = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :r]
    semi = rng.uniform(0.5, 2.0, r) * magnitude
    center = rng.normal(size=m) * magnitude
    which = data.draw(st.sampled_from(["center", "axes", "semi", "none"]))
    center, axes, semi = (
        data.draw(broken(v)) if which == key else v
        for key, v in (("center", center), ("axes", axes), ("semi", semi))
    )
    E = calm(lambda: pe.Ellipsoid(center, axes, semi))
    if E is None:
        return
    assert np.isfinite(E.volume) and E.volume >= 0
    T = sphere_directions(8, m)
    assert_interval(*calm(lambda: E.limits(T)))
    probe = data.draw(broken(E.center + 0.5 * T[0] * (E.semi_axes[0] if E.rank else 0.0)))
    inside = calm(lambda: E.contains(probe))
    assert inside is None or inside.dtype == bool
    support = calm(lambda: E.support(data.draw(broken(T))))
    assert support is None or np.all(np.isfinite(support))
    count = data.draw(st.sampled_from([None, 0, 1, 2, 3, 2.5, -1, 10**10, 64]))
    curve = calm(lambda: E.boundary_curve(count))
    assert curve is None or np.all(np.isfinite(curve))


@given(
    data=st.data(),
    m=st.integers(1, 3),
    n=st.integers(1, 4),
    magnitude=st.sampled_from(MAGNITUDES),
    seed=st.integers(0, 2**16),
)
def test_polytope_and_its_methods(data, m, n, magnitude, seed):
    rng = np.random.default_rng(seed)
    generators = rng.normal(size=(m, n)) * magnitude
    center = rng.normal(size=m) * magnitude * data.draw(st.sampled_from([0.0, 0.5, 3.0]))
    which = data.draw(st.sampled_from(["generators", "center", "none"]))
    if which == "generators":
        generators = data.draw(broken(generators))
    elif which == "center":
        center = data.draw(broken(center))
    P = calm(lambda: pe.Polytope(generators, center))
    if P is None:
        return
    high = 10.0 ** magnitude_limit(m)  # accepted, so within the magnitude bound
    for size in (np.abs(P.generators).max(), np.abs(P.center).max()):
        assert size == 0 or 1 / high <= size <= high
    volume = calm(lambda: P.volume)
    assert volume is None or (np.isfinite(volume) and volume >= 0)
    vertices = calm(lambda: P.vertices)
    assert vertices is None or np.all(np.isfinite(vertices))
    T = sphere_directions(8, m)
    limits = calm(lambda: P.limits(T))
    if limits is not None:
        assert_interval(*limits)
        if vertices is not None:  # every vertex inside P (or refused as too large)
            inside = calm(lambda: P.contains(vertices))
            assert inside is None or np.all(inside)


# --- pe.sweep, pe.limits_along, pe.PlanarArm


@given(data=st.data(), seed=st.integers(0, 2**16))
@settings(max_examples=15)
def test_sweep_with_any_argument_broken(data, seed):
    arm = pe.robots.load("chiacchio2000")
    rng = np.random.default_rng(seed)
    arguments: dict[str, Any] = {
        "configurations": rng.uniform(-np.pi, np.pi, (3, 3)),
        "tau_max": np.asarray(arm.tau_max, dtype=float),
        "directions": 8,
        "chunk": 2,
    }
    name = data.draw(
        st.sampled_from(["configurations", "tau_max", "scores", "rank_rtol", "chunk", "none"])
    )
    if name == "scores":
        arguments[name] = data.draw(st.sampled_from([None, 5, [], ["coverage"], ["x"], "volume"]))
    elif name == "rank_rtol":
        arguments[name] = data.draw(st.sampled_from([None, "x", -1.0, 1.0, 0.0, 1e-3, np.nan]))
    elif name != "none":
        arguments[name] = data.draw(broken(arguments[name]))
    frame = calm(lambda: pe.sweep(arm, **arguments))
    if frame is None:
        return
    for column in frame.columns:
        values = frame[column].to_numpy(dtype=float)
        if column.endswith(("_coverage", "_overreach")):
            assert np.all(np.isnan(values) | ((values >= 0) & (values <= 1))), column
        if column.endswith("_volume"):
            assert np.all(np.isnan(values) | (values >= 0)), column


@given(data=st.data(), seed=st.integers(0, 2**16))
@settings(max_examples=15)
def test_limits_along_with_any_argument_broken(data, seed):
    arm = pe.robots.load("chiacchio2000")
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (3, 3))
    T = sphere_directions(3, 2)
    name = data.draw(st.sampled_from(["q", "T", "rank_rtol", "none"]))
    rank_rtol: Any = 1e-10
    if name == "q":
        q = data.draw(broken(q))
    elif name == "T":
        T = data.draw(broken(T))
    elif name == "rank_rtol":  # None and "x": test_limits_along_refuses_a_rank_rtol_of_no_number
        rank_rtol = data.draw(st.sampled_from([-1.0, 1.0, np.nan, 0.0, 1e-3]))
    result = calm(lambda: pe.limits_along(arm, q, T, rank_rtol=rank_rtol))
    if result is not None:
        for limits in result.values():
            assert_interval(limits.lo, limits.hi)


@given(data=st.data(), seed=st.integers(0, 2**16))
def test_planar_arm_with_any_parameter_broken(data, seed):
    rng = np.random.default_rng(seed)
    n = data.draw(st.integers(1, 4))
    parameters: dict[str, Any] = {
        "lengths": rng.uniform(0.2, 1.5, n),
        "masses": rng.uniform(0.5, 10.0, n),
        "com": None,
        "inertia": None,
        "gravity": 9.81,
    }
    name = data.draw(st.sampled_from([*parameters, "none"]))
    if name != "none":
        parameters[name] = data.draw(broken(parameters[name] if name != "com" else [0.1] * n))
    arm = calm(lambda: pe.PlanarArm(**parameters))
    if arm is None:
        return
    q = data.draw(broken(rng.uniform(-np.pi, np.pi, n)))
    dyn = calm(lambda: arm.dynamics(q))
    if dyn is None:
        return
    assert all(np.all(np.isfinite(a)) for a in (dyn.J, dyn.B, dyn.g))
    an = calm(lambda: pe.analyze(dyn, np.full(n, 50.0)))
    if an is not None:
        check_analysis(an)


@given(data=st.data(), seed=st.integers(0, 2**16), magnitude=st.sampled_from(MAGNITUDES))
def test_torque_speed_with_any_argument_broken(data, seed, magnitude):
    """Torque-speed curves and their limits at a velocity: a refusal, or bounds in order."""
    rng = np.random.default_rng(seed)
    n = data.draw(st.integers(1, 4))
    stall = rng.uniform(0.5, 2.0, n) * magnitude
    rated = stall * rng.uniform(0.3, 1.0, n)
    arguments: dict[str, Any] = {
        "tau_stall": stall,
        "qd_no_load": rng.uniform(0.5, 5.0, n),
        "speeds": np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 2.0, 3))]),
        "torques": stall[:, None] * [1.0, 0.8, 0.3, data.draw(st.sampled_from([0.0, 0.1]))],
        "qd": rng.uniform(-3.0, 3.0, (data.draw(st.integers(1, 3)), n)),
        "tau_max": data.draw(st.sampled_from([None, rated])),
        "tau_min": data.draw(st.sampled_from([None, -rated])),
    }
    name = data.draw(st.sampled_from([*arguments, "none"]))
    if name != "none":
        arguments[name] = data.draw(broken(arguments[name]))
    if data.draw(st.booleans()):
        drives = calm(
            lambda: pe.TorqueSpeed.linear(arguments["tau_stall"], arguments["qd_no_load"])
        )
    else:
        drives = calm(lambda: pe.TorqueSpeed.table(arguments["speeds"], arguments["torques"]))
    if drives is None:
        return
    assert np.all(drives.tau_stall > 0) and np.all(np.isfinite(drives.tau_stall))
    qd, tau_max, tau_min = arguments["qd"], arguments["tau_max"], arguments["tau_min"]
    limits = calm(lambda: drives.limits(qd, tau_max, tau_min))
    event("limits computed" if limits is not None else "limits refused")
    if limits is None:
        return
    upper, lower = limits
    assert upper.shape == lower.shape == np.shape(qd)
    assert np.all(np.isfinite(upper)) and np.all(np.isfinite(lower)) and np.all(lower < upper)
    assert np.all(upper <= drives.tau_stall) and np.all(lower >= -drives.tau_stall)


@given(data=st.data(), m=st.integers(0, 4))
def test_direction_helpers(data, m):
    k = data.draw(st.sampled_from([1, 2, 7, 0, -1, 2.5, None, 10**9]))
    T = calm(lambda: sphere_directions(k, m))
    if T is not None:
        assert T.shape == (k if m > 1 else (2 if m == 1 else 0), m)
        if m:
            np.testing.assert_allclose(np.linalg.norm(T, axis=1), 1.0, rtol=1e-12)


def test_the_suite_covers_the_public_api():
    """Every callable of pe.__all__ is exercised above or is an exception/constant/module."""
    covered = {
        "analyze", "compare", "sweep", "limits_along", "Candidate", "PlanarArm", "Dynamics",
        "Ellipsoid", "Polytope", "Analysis", "Comparison", "Scores", "TorqueSpeed",
    }  # fmt: skip
    elsewhere = {  # exercised in their own test files (studies, robots, subspace)
        "AffineSubspace", "DirectionalLimits", "InverseSolution", "UrdfRobot", "Payload",
        "grid", "random_configurations", "local_cluster", "robots",
        "TableLayout", "limits_table",  # tests/comparison/test_print_*.py, test_limits_table.py
        "self_motion", "SelfMotion", "posture_choice", "PostureChoice",  # tests/models, studies
        "posture_choice_over_targets", "PostureChoiceOverTargets", "write_posture_tables",
        "Kinematics", "HPolytope",  # tests/capacities/test_capacity_properties.py
        "to_long", "to_wide",  # tests/comparison/test_long_form.py
        "SetComparison", "SetScores",  # tests/comparison/test_compare_sets.py
    }  # fmt: skip
    for name in pe.__all__:
        item = getattr(pe, name)
        if isinstance(item, type) and issubclass(item, BaseException | Warning):
            continue
        if not callable(item) and name not in elsewhere:
            continue  # constants, __version__
        assert name in covered | elsewhere, name


@pytest.mark.parametrize("magnitude", MAGNITUDES)
def test_every_magnitude_gives_a_result_or_a_refusal(magnitude):
    """The same arm in units from 1e-300 to 1e300: scores or a clear refusal, no warning."""
    arm = pe.robots.load("chiacchio2000")
    dyn = arm.dynamics([0.3, 0.7, -0.4])
    scaled = pe.Dynamics(dyn.J * magnitude, dyn.B, dyn.g)
    an = calm(lambda: pe.analyze(scaled, arm.tau_max))
    if 1e-100 <= magnitude <= 1e100:
        assert an is not None
    if an is not None:
        check_analysis(an)
        cmp = calm(lambda: pe.compare(an, 16, samples=256))
        assert cmp is not None
        check_scores(cmp, 0)


# --- Defects this suite found (issue 20), now refusals.


@pytest.mark.parametrize("where", ["generators", "center", "tiny"])
def test_a_huge_polytope_is_refused(where):
    generators, center = np.array([[1.0, 0.5], [0.3, -1.0]]), np.array([0.2, 0.1])
    if where == "generators":
        generators = generators * 1e283
    elif where == "center":
        center = center * 1e283
    else:
        generators = generators * 1e-300
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(pe.InputError):
            P = pe.Polytope(generators, center)
            P.limits([1.0, 0.0])
            P.volume  # noqa: B018 - the property is the call
            P.vertices  # noqa: B018


@pytest.mark.parametrize("rank_rtol", [None, "x"])
def test_limits_along_refuses_a_rank_rtol_of_no_number(rank_rtol):
    arm = pe.robots.load("chiacchio2000")
    with pytest.raises(pe.InputError, match="rank_rtol"):
        pe.limits_along(arm, [[0.1, 0.2, 0.3]], [[1.0, 0.0]], rank_rtol=rank_rtol)
