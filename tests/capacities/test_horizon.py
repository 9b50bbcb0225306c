"""The acceleration set within the joint position and velocity limits over a horizon (issue 34).

Every number is checked against an independent computation: the joint intervals against the
positions on a fine grid of instants (feasible at the bound, infeasible just beyond it), and
the directional limits of the set (its facets' closed form, :meth:`HPolytope.limits`) and of
the batched dual simplex (:func:`line_limits`) against HiGHS over the joint accelerations
themselves, with the position limits imposed at 1,000 instants of the horizon and then at
the worst instant of each joint until no instant is violated (a cutting-plane loop that
never uses the closed form).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog, minimize_scalar

import polyell as pe
from polyell.capacities.horizon import (
    acceleration_interval,
    cutting_joints,
    line_limits,
)
from polyell.errors import InputError
from tests.reference import random_spd

#: Relative agreement of the directional limits with the LP reference (issue 34's target).
RTOL_LIMITS = 1e-9
DT = (0.001, 0.01, 0.05)


def positions(q, qd, a, t):
    """``q + qd t + a t^2 / 2`` at instants ``t`` (T,) for accelerations ``a`` (n,)."""
    return q + np.outer(t, qd) + 0.5 * np.outer(t * t, a)


def reference_limits(dyn, tau_max, tau_min, state, direction, instants=1000):
    """``{s : s t achievable}`` by HiGHS over ``(qdd, s)``: the LP of the issue's target.

    The position limits hold at ``instants`` instants of ``(0, dt]``; then, for each end,
    the instant where the LP's own answer leaves each joint's limits most (on a grid of
    instants, refined by a golden-section search) is added until none leaves them by more
    than 1e-13 of the range.
    """
    J, B, g, bias = dyn.J, dyn.B, dyn.g, dyn.xdd_bias
    n = J.shape[1]
    q, qd, dt = state["q"], state["qd"], state["horizon"]
    q_min, q_max, qd_min, qd_max = state["q_min"], state["q_max"], state["qd_min"], state["qd_max"]
    grid = np.linspace(0.0, dt, 20_001)
    zero = np.zeros((n, 1))
    fixed = [np.hstack([B, zero]), np.hstack([-B, zero])]
    fixed += [np.hstack([np.eye(n) * dt, zero]), np.hstack([-np.eye(n) * dt, zero])]
    fixed_bounds = [tau_max - g, g - tau_min, qd_max - qd, qd - qd_min]
    ends = []
    for sign in (-1.0, 1.0):
        times = np.linspace(dt / instants, dt, instants)
        for _ in range(30):
            # q + qd t + qdd t^2 / 2 within [q_min, q_max] at every instant t: 2 n rows each
            square = np.kron(0.5 * times[:, None] ** 2, np.eye(n))
            rows = [*fixed, np.hstack([square, np.zeros((len(square), 1))])]
            rows.append(-rows[-1])
            bounds = [*fixed_bounds, (q_max - q - np.outer(times, qd)).ravel()]
            bounds.append((q + np.outer(times, qd) - q_min).ravel())
            A_ub, b_ub = np.vstack(rows), np.concatenate(bounds)
            scale = np.abs(A_ub).max(axis=1)
            c = np.zeros(n + 1)
            c[-1] = -sign
            result = linprog(
                c,
                A_ub=A_ub / scale[:, None],
                b_ub=b_ub / scale,
                A_eq=np.hstack([J, -direction[:, None]]),
                b_eq=-bias,
                bounds=[(None, None)] * (n + 1),
                method="highs",
                options={
                    "primal_feasibility_tolerance": 1e-10,
                    "dual_feasibility_tolerance": 1e-10,
                },
            )
            if result.status == 2:  # infeasible: the line misses the set
                ends.append(np.nan)
                break
            assert result.status == 0, result.message
            a = result.x[:n]
            new = []
            for j in range(n):  # each joint's worst instant: the grid's, refined (golden section)

                def excess(t, j=j, a=a):
                    p = q[j] + qd[j] * t + 0.5 * a[j] * t * t
                    return max(p - q_max[j], q_min[j] - p) / (q_max[j] - q_min[j])

                k = int(np.argmax([excess(t) for t in grid[::100]])) * 100
                window = (grid[max(k - 100, 0)], grid[min(k + 100, len(grid) - 1)])
                best = minimize_scalar(
                    lambda t: -excess(t),
                    bounds=window,
                    method="bounded",
                    options={"xatol": 1e-15 * dt},
                )
                if -best.fun > 1e-13:
                    new.append(best.x)
            if not new:
                ends.append(result.x[-1])
                break
            times = np.concatenate([times, new])
        else:
            raise AssertionError("the cutting planes did not converge")
    return ends[0], ends[1]


def _near(rng, q, qd, q_max, qd_max, dt, B, g, tau_max):
    """Put one joint near its upper limit, so that its interval cuts the torque set inside.

    The joint moves towards the limit and must stop at a deceleration the torques can
    give: the end-point bound ``2 (D - qd dt) / dt^2`` is drawn within the joint's reach
    ``a0 +- sum |W|`` (W = B^-1 L, a0 = -B^-1 g).
    """
    W = np.linalg.solve(B, np.diag(tau_max))
    a0 = -np.linalg.solve(B, g)
    reach = np.abs(W).sum(axis=1)
    for _ in range(200):
        j = int(rng.integers(len(q)))
        qd[j] = rng.uniform(0.05, 0.5) * qd_max[j]
        target = a0[j] + rng.uniform(-0.7, 0.7) * reach[j]
        room = qd[j] * dt + 0.5 * target * dt * dt
        if room > 0 and qd[j] * dt < 2 * room and (qd[j] + target * dt) < qd_max[j]:
            q[j] = q_max[j] - room
            return
    raise AssertionError("no near state drawn")


def random_case(seed, m=3, n=7, where="near"):
    """Random dynamics, torque limits and a state far from, near or at its limits."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(m, n))
    B = random_spd(rng, n)
    tau_max = rng.uniform(5.0, 50.0, n)
    g = 0.3 * rng.normal(size=n) * tau_max
    q_max = rng.uniform(0.5, 2.0, n)
    q_min = -rng.uniform(0.5, 2.0, n)
    qd_max = rng.uniform(1.0, 3.0, n)
    qd_min = -qd_max
    q = rng.uniform(0.5 * q_min, 0.5 * q_max)
    qd = 0.3 * rng.uniform(qd_min, qd_max)
    dt = float(rng.choice(DT))
    if where == "near":
        _near(rng, q, qd, q_max, qd_max, dt, B, g, tau_max)
    elif where == "at":
        j = int(rng.integers(n))
        q[j], qd[j] = q_max[j], 0.0
    elif where == "far":
        q, qd = 0.0 * q, 0.0 * qd
    return pe.Dynamics(J, B, g), tau_max, _state(dt, q, qd, q_min, q_max, qd_min, qd_max)


def _state(horizon, q, qd, q_min, q_max, qd_min, qd_max):
    """The keyword arguments of ``pe.analyze(..., horizon=)``."""
    names = ("horizon", "q", "qd", "q_min", "q_max", "qd_min", "qd_max")
    return dict(zip(names, (horizon, q, qd, q_min, q_max, qd_min, qd_max), strict=True))


def panda_case(seed, where="near"):
    panda = pe.robots.load("panda")
    rng = np.random.default_rng(seed)
    q_min, q_max = panda.position_limits
    qd_max, qd_min = panda.velocity_limits()
    q = rng.uniform(q_min + 0.3, q_max - 0.3)
    qd = 0.2 * rng.uniform(qd_min, qd_max)
    dt = float(rng.choice(DT))
    if where == "near":
        at_rest = panda.dynamics(q)
        _near(rng, q, qd, q_max, qd_max, dt, at_rest.B, at_rest.g, panda.tau_max)
    elif where == "at":
        j = int(rng.integers(7))
        q[j], qd[j] = q_max[j], 0.0
    state = _state(dt, q, qd, q_min, q_max, qd_min, qd_max)
    return panda.dynamics(q, qd), panda.tau_max, state


def analysis_of(dyn, tau_max, state):
    return pe.analyze(dyn, tau_max, **state)


# --- the joint interval --------------------------------------------------------------


@pytest.mark.parametrize("seed", range(4))
def test_interval_is_exact_on_a_dense_grid(seed):
    """At each end every instant is within the limits; 1e-6 beyond it, some instant is not."""
    rng = np.random.default_rng(seed)
    n = 400
    q_min, q_max = -np.ones(n), np.ones(n)
    qd_max = np.full(n, 2.0)
    q = rng.uniform(-1.0, 1.0, n)
    near = rng.random(n) < 0.5
    q[near] = np.where(rng.random(near.sum()) < 0.5, 1.0, -1.0) * (
        1 - rng.uniform(0, 0.02, near.sum())
    )
    qd = rng.uniform(-2.0, 2.0, n)
    dt = float(rng.choice([0.001, 0.05, 0.5]))
    lo, hi = acceleration_interval(dt, q, qd, q_min, q_max, -qd_max, qd_max)
    t = np.linspace(0.0, dt, 20_001)
    feasible = lo <= hi
    for a, outward in ((hi, 1.0), (lo, -1.0)):
        a = np.where(feasible, a, 0.0)
        margin = 1e-9 * (1.0 + np.abs(a))
        path = q + np.outer(t, qd) + 0.5 * np.outer(t * t, a)
        end_velocity = qd + a * dt
        assert (path[:, feasible] <= 1.0 + 1e-12).all() and (
            path[:, feasible] >= -1.0 - 1e-12
        ).all()
        assert (np.abs(end_velocity[feasible]) <= 2.0 + margin[feasible]).all()
        # just beyond: the velocity at the end or some position (the exact instant of the
        # apex, -qd/a, checked too: a grid could step over it) leaves its limits
        beyond = a + outward * 1e-6 * (1.0 + np.abs(a))
        path = q + np.outer(t, qd) + 0.5 * np.outer(t * t, beyond)
        with np.errstate(divide="ignore", invalid="ignore"):
            apex = np.clip(-qd / beyond, 0.0, dt)
        peak = q + qd * apex + 0.5 * beyond * apex**2
        out = (np.abs(path) > 1.0).any(axis=0) | (np.abs(peak) > 1.0)
        out |= np.abs(qd + beyond * dt) > 2.0
        assert out[feasible].all()
    # where the interval is empty, no acceleration on a grid keeps the joint inside
    coarse = np.linspace(0.0, dt, 501)[:, None]
    a = np.linspace(-1e5, 1e5, 4001)
    for k in np.flatnonzero(~feasible)[:20]:
        path = q[k] + qd[k] * coarse + 0.5 * coarse**2 * a
        ok = (np.abs(path) <= 1.0).all(axis=0) & (np.abs(qd[k] + a * dt) <= 2.0)
        assert not ok.any()


def test_viability_lets_the_joint_stop_before_its_limit():
    """With braking b, the end state stops within the limit: q' + v'^2 / (2 b) <= q_max."""
    rng = np.random.default_rng(7)
    n = 5000
    q = rng.uniform(0.5, 1.0, n)
    qd = rng.uniform(0.0, 2.0, n)
    b = rng.uniform(1.0, 50.0, n)
    dt = 0.01
    ones = np.ones(n)
    lo, hi = acceleration_interval(dt, q, qd, -ones, ones, -2 * ones, 2 * ones, b)
    plain = acceleration_interval(dt, q, qd, -ones, ones, -2 * ones, 2 * ones)[1]
    ok = lo <= hi
    assert (hi <= plain).all()
    v = qd + hi * dt
    stop = q + qd * dt + 0.5 * hi * dt**2 + np.maximum(v, 0.0) ** 2 / (2 * b)
    assert (stop[ok] <= 1.0 + 1e-9).all()
    # just beyond the bound, the joint can no longer stop in time (or leaves otherwise)
    beyond = hi + 1e-6 * (1 + np.abs(hi))
    v = qd + beyond * dt
    stop = q + qd * dt + 0.5 * beyond * dt**2 + np.maximum(v, 0.0) ** 2 / (2 * b)
    tight = ok & (hi < plain - 1e-6 * (1 + np.abs(plain)))  # where viability is the bound
    assert tight.sum() > 100
    assert (stop[tight] > 1.0).all()


# --- the set ------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("where", ["near", "at"])
def test_limits_equal_the_lp_on_random_arms(seed, where):
    dyn, tau_max, state = random_case(seed, where=where)
    analysis = analysis_of(dyn, tau_max, state)
    _check_against_lp(analysis, dyn, tau_max, state, seed, where)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("where", ["near", "at", "far"])
def test_limits_equal_the_lp_on_the_panda(seed, where):
    dyn, tau_max, state = panda_case(seed, where=where)
    analysis = analysis_of(dyn, tau_max, state)
    _check_against_lp(analysis, dyn, tau_max, state, seed, where)


def _check_against_lp(analysis, dyn, tau_max, state, seed, where):
    """The closed form and the batch equal the LP; near and at a limit the set is cut."""
    rng = np.random.default_rng(seed)
    if where != "far":  # these cases cut a set, not empty
        assert analysis.cut.any() and not analysis.polytope.is_empty
    T = rng.normal(size=(4, analysis.m))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    P = analysis.polytope
    batch = line_limits(
        analysis.M[None].repeat(4, 0),
        analysis.xg[None].repeat(4, 0),
        analysis.W[None].repeat(4, 0),
        analysis.a0[None].repeat(4, 0),
        analysis.qdd_lo[None].repeat(4, 0),
        analysis.qdd_hi[None].repeat(4, 0),
        T,
    )
    assert not batch[2].any()
    size = float(np.abs(analysis.xg).max() + np.abs(analysis.M).sum(axis=1).max())
    for k, t in enumerate(T):
        expected = reference_limits(dyn, tau_max, -tau_max, state, t)
        closed = P.limits(t)
        for got in ((closed.lo, closed.hi), (batch[0][k], batch[1][k])):
            assert np.isnan(got[0]) == np.isnan(expected[0])
            if not np.isnan(expected[0]):
                np.testing.assert_allclose(got, expected, rtol=0, atol=RTOL_LIMITS * size)


@pytest.mark.parametrize("seed", range(6))
def test_far_from_the_limits_the_set_is_the_zonotope(seed):
    """Far from every limit (or as dt -> 0 at rest) nothing cuts: the set is eq. (15)'s."""
    dyn, tau_max, state = random_case(seed, where="far")
    state["horizon"] = 1e-4
    analysis = analysis_of(dyn, tau_max, state)
    plain = pe.analyze(dyn, tau_max)
    assert not analysis.cut.any()
    np.testing.assert_array_equal(analysis.polytope.vertices, plain.polytope.vertices)
    assert analysis.polytope.volume == plain.polytope.volume


def test_the_set_lies_in_the_zonotope_and_its_vertices_are_feasible():
    found = 0
    for seed in range(40):
        dyn, tau_max, state = random_case(seed, where="near")
        analysis = analysis_of(dyn, tau_max, state)
        P = analysis.polytope
        if not analysis.cut.any() or P.is_empty:
            continue
        found += 1
        _check_inside(analysis, dyn, tau_max)
    assert found >= 6


def _check_inside(analysis, dyn, tau_max):
    P = analysis.polytope
    zonotope = pe.analyze(dyn, tau_max).polytope
    assert zonotope.contains(P.vertices).all()
    assert P.volume < zonotope.volume
    # every vertex is reached by normalized torques u within both boxes: the smallest
    # violation e of |u| <= 1 and qdd_lo <= a0 + W u <= qdd_hi with M u = x - xg is ~0
    n = analysis.n
    column = -np.ones((n, 1))
    A_ub = np.vstack(
        [
            np.hstack([analysis.W, column]),
            np.hstack([-analysis.W, column]),
            np.hstack([np.eye(n), column]),
            np.hstack([-np.eye(n), column]),
        ]
    )
    b_ub = np.concatenate(
        [analysis.qdd_hi - analysis.a0, analysis.a0 - analysis.qdd_lo, np.ones(n), np.ones(n)]
    )
    for x in P.vertices:
        result = linprog(
            np.eye(n + 1)[-1],
            A_ub=A_ub,
            b_ub=b_ub,
            A_eq=np.hstack([analysis.M, np.zeros((analysis.m, 1))]),
            b_eq=x - analysis.xg,
            bounds=[(None, None)] * (n + 1),
            method="highs",
        )
        assert result.status == 0 and result.x[-1] <= 1e-9


def test_singular_configuration_gives_a_flat_set():
    """Rank J < m: the cut set lies in the zonotope's affine set, with its limits."""
    rng = np.random.default_rng(3)
    dyn, tau_max, state = random_case(3, where="near")
    J = dyn.J.copy()
    J[2] = J[0] + J[1]  # rank 2 in R^3
    dyn = pe.Dynamics(J, dyn.B, dyn.g)
    analysis = analysis_of(dyn, tau_max, state)
    P = analysis.polytope
    assert analysis.rank == 2 and analysis.cut.any()
    assert P.dim == 2
    t = rng.normal(size=2)
    direction = np.array([t[0], t[1], t[0] + t[1]])  # in Im(J), which holds xg (no bias)
    direction /= np.linalg.norm(direction)
    assert P.affine_set.near(np.zeros(3), 1e-9).all()
    expected = reference_limits(dyn, tau_max, -tau_max, state, direction)
    got = P.limits(direction)
    assert not np.isnan(expected[0])
    size = float(np.abs(P.vertices).max())
    np.testing.assert_allclose([got.lo, got.hi], expected, atol=RTOL_LIMITS * size, rtol=0)


@pytest.mark.parametrize("free", [(), (0,), (0, 3)])
def test_pinned_joints_give_a_point_or_flat_set_through_the_origin(free):
    """Joints whose velocity limits are 0 at rest are pinned (qdd = 0 is their only choice).

    All pinned: the set is the one point ``J 0 + Jdot 0 = 0`` (computed as ``xg + M u``,
    which cancels to rounding): its limits along any line are [0, 0], not NaN.  Some free:
    the set holds the origin (every free joint may stay at rest), and along the image of a
    free joint's column the limits are those of the LP.
    """
    panda = pe.robots.load("panda")
    q = np.array([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8])
    low, high = panda.position_limits
    qd_max = np.zeros(7)
    qd_max[list(free)] = 2.0
    dyn = panda.dynamics(q)
    state = {"horizon": 0.01, "q": q, "qd": np.zeros(7), "q_min": low, "q_max": high,
             "qd_min": -qd_max, "qd_max": qd_max}  # fmt: skip
    P = pe.analyze(dyn, panda.tau_max, **state).polytope
    assert P.dim == len(free)
    directions = np.random.default_rng(4).normal(size=(5, 3))
    if free:
        directions[0] = dyn.J[:, free[0]]
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    for direction in directions[: 1 if free else 5]:
        got = P.limits(direction)
        expected = reference_limits(dyn, panda.tau_max, -panda.tau_max, state, direction)
        assert got.lo <= 0.0 <= got.hi
        np.testing.assert_allclose([got.lo, got.hi], expected, rtol=0, atol=1e-9 * 100.0)


# --- empty sets and bad input ---------------------------------------------------------


def test_a_state_outside_its_limits_is_an_empty_set_with_its_reason():
    dyn, tau_max, state = random_case(0, where="far")
    state["q"] = state["q"].copy()
    state["q"][2] = state["q_max"][2] + 0.01
    analysis = analysis_of(dyn, tau_max, state)
    assert analysis.polytope.is_empty
    assert "joint 3" in analysis.empty_reason and "0.01 above its limits" in analysis.empty_reason
    state["q"][2] = state["q_max"][2] + 1e-9  # said with its excess, not rounded to inside
    assert "1e-09 above its limits" in analysis_of(dyn, tau_max, state).empty_reason
    comparison = pe.compare(analysis)
    for kind in ("chiacchio", "yoshikawa"):
        assert not comparison[kind].defined
        assert "joint 3" in comparison[kind].reason
    lo, hi = analysis.polytope.limits([1.0, 0.0, 0.0])
    assert np.isnan(lo) and np.isnan(hi)


def test_a_joint_that_reaches_its_limit_whatever_it_does_is_an_empty_set():
    dyn, tau_max, state = random_case(1, where="far")
    state["q"] = state["q"].copy()
    state["qd"] = state["qd"].copy()
    state["q"][0], state["qd"][0] = state["q_max"][0], 0.5  # at the limit, moving out
    analysis = analysis_of(dyn, tau_max, state)
    assert analysis.polytope.is_empty
    assert "joint 1" in analysis.empty_reason


def test_torques_too_weak_for_the_interval_give_an_empty_set():
    """The interval asks for more deceleration than the torques give: empty, with why."""
    dyn, tau_max, state = random_case(2, where="far")
    state["q"], state["qd"] = state["q"].copy(), state["qd"].copy()
    state["horizon"] = 0.001
    state["q"][0] = state["q_max"][0] - 1e-4
    state["qd"][0] = 0.5  # must stop within 1e-4: about -1250 rad/s^2
    analysis = analysis_of(dyn, tau_max, state)
    assert (analysis.qdd_lo <= analysis.qdd_hi).all()  # the joint alone could stop...
    assert (analysis.a0 - np.abs(analysis.W).sum(axis=1))[0] > analysis.qdd_hi[0]  # ...not so
    assert analysis.polytope.is_empty
    assert "torque limits" in analysis.empty_reason


@pytest.mark.parametrize(
    ("change", "argument"),
    [
        ({"horizon": 0.0}, "horizon"),
        ({"horizon": -1e-3}, "horizon"),
        ({"horizon": float("nan")}, "horizon"),
        ({"horizon": "1ms"}, "horizon"),
        ({"horizon": True}, "horizon"),
        ({"qd": None}, "qd"),
        ({"q": None}, "q"),
        ({"q_min": None}, "q_min"),
        ({"q_max": np.ones(3)}, "q_max"),
        ({"qd_max": np.ones(8)}, "qd_max"),
        # qd_min defaulting to -qd_max: what is wrong is qd_max's (qd_min was named)
        ({"qd_min": None, "qd_max": np.full(7, np.inf)}, "qd_max"),
        ({"qd_min": None, "qd_max": -np.ones(7)}, "qd_max"),
        ({"qd_min": None, "qd_max": None}, "qd_max"),
        ({"q": np.full(7, np.nan)}, "q"),
        ({"braking": -1.0}, "braking"),
    ],
)
def test_bad_input_names_the_argument(change, argument):
    dyn, tau_max, state = random_case(0)
    state.update(change)
    with pytest.raises(InputError) as error:
        analysis_of(dyn, tau_max, state)
    assert error.value.argument == argument


def test_swapped_limits_and_other_capacities_are_refused():
    dyn, tau_max, state = random_case(0)
    swapped = {**state, "q_min": state["q_max"], "q_max": state["q_min"]}
    with pytest.raises(InputError, match="q_min"):
        analysis_of(dyn, tau_max, swapped)
    with pytest.raises(InputError, match="horizon"):
        pe.analyze(dyn, tau_max, capacity="force", **state)
    with pytest.raises(InputError, match="q"):
        pe.analyze(dyn, tau_max, q=state["q"], qd=state["qd"])  # a state without a horizon


def test_cutting_joints_batch_equals_one_by_one():
    rng = np.random.default_rng(5)
    W = rng.normal(size=(50, 4, 4))
    a0 = rng.normal(size=(50, 4))
    lo, hi = a0 - rng.uniform(0, 6, (50, 4)), a0 + rng.uniform(0, 6, (50, 4))
    batch = cutting_joints(W, a0, lo, hi)
    for k in range(50):
        np.testing.assert_array_equal(batch[k], cutting_joints(W[k], a0[k], lo[k], hi[k]))
    assert batch.any() and not batch.all()


def test_robot_analyze_takes_its_own_limits():
    panda = pe.robots.load("panda")
    q_min, q_max = panda.position_limits
    qd_max, qd_min = panda.velocity_limits()
    q = np.array([0.0, -0.5, 0.0, q_max[3] - 0.004, 0.0, 1.6, 0.8])
    qd = np.array([0.0, 0.2, 0.0, 0.5, 0.0, 0.0, 0.0])
    mine = panda.analyze(q, qd, horizon=0.01, braking=20.0)
    given = pe.analyze(
        panda.dynamics(q, qd),
        panda.tau_max,
        horizon=0.01,
        q=q,
        qd=qd,
        q_min=q_min,
        q_max=q_max,
        qd_max=qd_max,
        qd_min=qd_min,
        braking=20.0,
    )
    assert mine.cut.any()
    np.testing.assert_array_equal(mine.qdd_hi, given.qdd_hi)
    np.testing.assert_allclose(mine.polytope.vertices, given.polytope.vertices, rtol=0, atol=1e-9)
    at_rest = panda.analyze(q, horizon=0.01)
    assert (at_rest.state.qd == 0).all()


# --- found by the independent check of issue 34 ---------------------------------------

#: States whose first support points (along the axes of Im M) were affinely dependent: the
#: set came back flat (dimension 2) though it is full-dimensional.
FLAT_LOOKING = [
    (
        "kinova",
        0.009511144940178712,
        [-0.7673869865745409, 1.4608849457831723, 0.3340061586581751, 3.1407998921375087,
         2.2746104395282982, -0.21979590670503857],
        [0.0510503109713431, 0.2421306934282036, -0.18720659208017212, 0.1452310166439305,
         -0.27016691545907945, 0.36566337254869646],
        [1.0, 0.0, 0.0],
    ),
    (
        "panda",
        0.022694348846815326,
        [1.2466516896313116, -1.3963301688767384, -2.157407089864799, -0.44404899580592794,
         -1.8231494918264475, 2.7278369433630907, 0.7463793482195684],
        [-0.826215119515976, -0.8886083757982964, -0.8580185087373605, 0.27019711158524506,
         -0.3710680059083361, 0.5510908119641693, -1.153547677209642],
        [-0.5202074319069807, -0.07447837530841141, -0.850786224265628],
    ),
]  # fmt: skip


@pytest.mark.parametrize(("name", "horizon", "q", "qd", "t"), FLAT_LOOKING)
def test_a_set_is_flat_only_where_its_support_says_so(name, horizon, q, qd, t):
    robot = pe.robots.load(name)
    q, qd, t = np.array(q), np.array(qd), np.array(t)
    analysis = robot.analyze(q, qd, horizon=horizon)
    assert analysis.polytope.dim == 3
    q_min, q_max = robot.position_limits
    qd_max, qd_min = robot.velocity_limits()
    state = _state(horizon, q, qd, q_min, q_max, qd_min, qd_max)
    t = t / np.linalg.norm(t)
    dyn = robot.dynamics(q, qd)
    expected = reference_limits(dyn, analysis.tau_max, analysis.tau_min, state, t)
    size = float(np.abs(analysis.xg).max() + np.abs(analysis.M).sum(axis=1).max())
    got = analysis.polytope.limits(t)
    np.testing.assert_allclose([got.lo, got.hi], expected, rtol=0, atol=RTOL_LIMITS * size)


def test_a_six_dimensional_cut_set_is_built_or_refused_by_name():
    """6-D sets whose support points are nearly degenerate: Qhull's wide merges allowed."""
    rng = np.random.default_rng(12)
    built = 0
    for _ in range(6):
        dyn, tau_max, state = random_case(int(rng.integers(1000)), m=6, where="near")
        analysis = analysis_of(dyn, tau_max, state)
        try:
            P = analysis.polytope
        except pe.PolyellError:
            continue
        built += 1
        assert P.dim == 6 and (P.is_empty or P.volume > 0)
    assert built >= 4


def test_empty_reason_is_known_before_the_set_is_built():
    dyn, tau_max, state = random_case(2, where="far")
    state["q"], state["qd"] = state["q"].copy(), state["qd"].copy()
    state["horizon"] = 0.001
    state["q"][0] = state["q_max"][0] - 1e-4
    state["qd"][0] = 0.5
    assert "torque limits" in analysis_of(dyn, tau_max, state).empty_reason


@pytest.mark.parametrize(
    "call",
    [
        lambda robot, q: robot.analyze(q, capacity="velocity", horizon=0.01),
        lambda robot, q: robot.analyze(q, braking=5.0),
        lambda robot, q: robot.analyze(q, horizon=0.01, braking=np.ones(3)),
        lambda robot, q: robot.analyze(q, horizon=1e160),
        lambda robot, q: pe.limits_along(robot, q[None], [[1.0, 0.0, 0.0]], braking=5.0),
        lambda robot, q: pe.limits_along(robot, q[None], [[1.0, 0.0, 0.0]], qd=q[None]),
        lambda robot, q: pe.sweep(robot, q[None], braking=5.0),
    ],
)
def test_arguments_of_a_horizon_are_refused_by_name(call):
    panda = pe.robots.load("panda")
    q = np.array([0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8])
    with pytest.raises(InputError):
        call(panda, q)


def test_a_robot_in_place_of_its_dynamics_is_refused_as_dyn():
    """``pe.analyze(robot, horizon=...)`` names ``dyn`` (it said q had to have shape (0,))."""
    robot = pe.robots.load("panda")
    q = np.mean(robot.position_limits, axis=0)
    with pytest.raises(InputError, match=r"^dyn: expected a polyell\.Dynamics, got UrdfRobot"):
        pe.analyze(robot, robot.tau_max, horizon=1e-3, q=q, qd=np.zeros(7))


def test_flat_and_empty_sets_over_a_horizon_say_their_own_cause():
    """A set pinned to a point by zero velocity limits is blamed on the joints' limits
    over the horizon, not on gravity; the report of an empty set gives its
    ``empty_reason``; the interactive view draws a point ellipsoid as a marker (it raised
    an error naming an argument it does not have)."""
    from polyell.interactive import interactive_sets
    from polyell.report import format_analysis

    arm = pe.robots.load("chiacchio2000")
    q0 = np.array([np.pi / 2, -np.pi / 2, -np.pi / 2])
    limits = {"q_min": [-3.0] * 3, "q_max": [3.0] * 3}
    pinned = pe.analyze(
        arm.dynamics(q0), arm.tau_max, horizon=0.01, q=q0, qd=np.zeros(3), **limits,
        qd_max=[0.0, 0.0, 0.0],
    )  # fmt: skip
    cmp = pe.compare(pinned, 16)
    reasons = [cmp[kind].reason for kind in ("chiacchio", "yoshikawa")]
    assert all("pinned by their limits over the horizon" in r for r in reasons), reasons
    assert not any("gravity" in r for r in reasons)
    interactive_sets(cmp)  # a figure: the point ellipsoids as markers
    outside = np.array([np.pi / 2, -np.pi / 2, 3.2])  # beyond q_max
    empty = pe.analyze(
        arm.dynamics(outside), arm.tau_max, horizon=0.01, q=outside, qd=np.zeros(3),
        **limits, qd_max=[1.0, 1.0, 1.0],
    )  # fmt: skip
    assert empty.polytope.is_empty
    text = format_analysis(empty, np.array([1.0, 0.0]), "x")
    assert f"empty: {empty.empty_reason}" in text and "gravity" not in text


def test_an_infinite_interval_end_prints_beside_the_finite_ones():
    """A joint at its limit moving into it: its interval's upper end is -inf, which the
    report printed as a row of zeros (the largest entry, inf, scaled the others away);
    the empty set reads "empty", not "dimension -1", and its tables have no unit^-1."""
    from polyell.report import format_analysis

    panda = pe.robots.load("panda")
    q = np.array([0.0, -0.5, 0.0, -0.0698, 0.0, 1.6, 0.8])
    qd = np.array([0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0])
    analysis = panda.analyze(q, qd, horizon=0.01)
    assert analysis.qdd_hi[3] == -np.inf and analysis.polytope.is_empty
    text = format_analysis(analysis, np.array([1.0, 0.0, 0.0]), "x")
    block = text[text.index("qdd_hi:") :].splitlines()[1]
    assert "-inf" in block and "217.5" in block, block
    assert "Exact set: empty," in text and "dimension -1" not in text
    assert "^-1" not in pe.compare(analysis).to_markdown()
