"""pe.limits_along: one direction per configuration, equal row by row to the per-row API."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from reference import random_directions, random_spd

ARM = pe.robots.load("chiacchio2000")


def assert_equals_per_row(out, dynamics, tau_max, tau_min, T, rtol=1e-9):
    for k, t in enumerate(T):
        analysis = pe.analyze(dynamics(k), tau_max, tau_min)
        expected = {"polytope": analysis.polytope.limits(t)}
        for kind in ("chiacchio", "yoshikawa"):
            try:
                expected[kind] = analysis.ellipsoid(kind).limits(t)
            except pe.UndefinedEllipsoidError:
                expected[kind] = (np.nan, np.nan)
        for name, (lo, hi) in expected.items():
            scale = max(1.0, np.nanmax(np.abs([lo, hi, 1.0])))
            np.testing.assert_allclose(
                [out[name].lo[k], out[name].hi[k]],
                [lo, hi],
                rtol=rtol,
                atol=rtol * scale,
                err_msg=f"{name} at {k}",
            )


def test_panda_path_equals_the_per_row_api():
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    q = pe.random_configurations(60, low, high, seed=4).rows(0, 60)
    T = random_directions(5, 60, 3)
    out = pe.limits_along(panda, q, T)
    assert_equals_per_row(out, lambda k: panda.dynamics(q[k]), panda.tau_max, None, T)
    assert np.isfinite(out["polytope"].hi).all()


def test_planar_arm_with_singular_rows_and_lines_that_miss():
    """A grid through the stretched postures (singular: the exact path), strong gravity."""
    q = pe.grid(0.4, (-np.pi, np.pi, 7), (-np.pi, np.pi, 7)).rows(0, 49)
    T = random_directions(6, 49, 2)
    tau_max = np.array([8.0, 3.0, 1.0])  # weak joints: gravity pulls P off the origin
    out = pe.limits_along(ARM, q, T, tau_max)
    assert_equals_per_row(out, lambda k: ARM.dynamics(q[k]), tau_max, None, T)
    assert np.isnan(out["polytope"].lo).any() and np.isnan(out["yoshikawa"].lo).any()


def test_six_dimensional_batched_dynamics_with_asymmetric_limits_and_bias():
    rng = np.random.default_rng(7)
    K, m, n = 30, 6, 8
    J = rng.normal(size=(K, m, n))
    B = np.stack([random_spd(rng, n) for _ in range(K)])
    dyn = pe.Dynamics(J, B, rng.normal(size=(K, n)), xdd_bias=rng.normal(size=(K, m)))
    tau_max, tau_min = np.full(n, 5.0), np.full(n, -3.0)
    T = random_directions(8, K, m)
    out = pe.limits_along(dyn, None, T, tau_max, tau_min)
    assert_equals_per_row(out, lambda k: dyn[k], tau_max, tau_min, T)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"directions": [[1.0, 0.0]]}, "one unit direction per configuration"),
        ({"directions": [[1.0, 1.0], [1.0, 0.0]]}, "unit direction vectors"),
        ({"configurations": None}, "configurations: expected"),
    ],
)
def test_bad_calls(kwargs, fragment):
    arguments = {
        "configurations": [[0.1, 0.2, 0.3], [0.2, 0.3, 0.4]],
        "directions": [[1.0, 0.0], [0.0, 1.0]],
    } | kwargs
    with pytest.raises(pe.InputError, match=fragment):
        pe.limits_along(ARM, arguments["configurations"], arguments["directions"])


def test_more_task_rows_than_joints_equal_the_per_row_api():
    """m > n: P is at most n-dimensional in R^m (the exact path), no ZeroDivisionError."""
    rng = np.random.default_rng(12)
    K, m, n = 5, 4, 2
    dyn = pe.Dynamics(
        rng.normal(size=(K, m, n)),
        np.stack([random_spd(rng, n) for _ in range(K)]),
        rng.normal(size=(K, n)),
    )
    T = random_directions(13, K, m)
    out = pe.limits_along(dyn, None, T, np.full(n, 10.0))
    assert_equals_per_row(out, lambda k: dyn[k], np.full(n, 10.0), None, T)


@pytest.mark.parametrize("rank_rtol", [-1e-10, 1.0, "1e-10", None, True, np.nan])
def test_a_rank_tolerance_of_a_wrong_type_or_sign_is_refused(rank_rtol):
    q = [[0.3, 0.2, 0.1]]
    with pytest.raises(pe.InputError) as error:
        pe.limits_along(ARM, q, [[1.0, 0.0]], rank_rtol=rank_rtol)
    assert error.value.argument == "rank_rtol"


def _quadratic_interval(Q: np.ndarray, center: np.ndarray, t: np.ndarray) -> tuple[float, float]:
    """[lo, hi] of {s : (s t - c)^T Q^-1 (s t - c) <= 1} for a full-rank shape matrix Q."""
    Qi = np.linalg.inv(Q)
    a, b, c = t @ Qi @ t, -2.0 * t @ Qi @ center, center @ Qi @ center - 1.0
    disc = b * b - 4.0 * a * c
    if disc < 0:
        return np.nan, np.nan
    root = np.sqrt(disc)
    return (-b - root) / (2.0 * a), (-b + root) / (2.0 * a)


def _lp_interval(A_ub, b_ub, t, A_eq=None, n_free=0):
    """[lo, hi] of s over {(s, x) : A_ub [s; x] <= b_ub, A_eq [s; x] = 0} (HiGHS)."""
    from scipy.optimize import linprog

    size = A_ub.shape[1]
    ends = []
    for sign in (1.0, -1.0):
        cost = np.zeros(size)
        cost[0] = sign
        result = linprog(
            cost,
            A_ub=A_ub,
            b_ub=b_ub,
            A_eq=A_eq,
            b_eq=None if A_eq is None else np.zeros(len(A_eq)),
            bounds=[(None, None)] * size,
            method="highs",
        )
        ends.append(
            result.x[0]
            if result.status == 0
            else (-sign * np.inf if result.status == 3 else np.nan)
        )
    return ends[0], ends[1]


def test_velocity_and_force_limits_against_linear_programs_and_quadratics():
    """Independent of the package's paths: an LP for each set, eq. (24)'s quadratic for each
    ellipsoid from its shape matrix (velocities: J L^2 J^T about J qd_c; forces: the three
    definitions of the theory page)."""
    rng = np.random.default_rng(21)
    K, m, n = 12, 3, 6
    J = rng.normal(size=(K, m, n))
    g = 0.3 * rng.normal(size=(K, n))
    dyn = pe.Dynamics(J, np.broadcast_to(np.eye(n), (K, n, n)).copy(), g)
    upper = rng.uniform(1.0, 3.0, n)
    lower = -upper * rng.uniform(0.6, 1.0, n)
    T = random_directions(22, K, m)
    centre, half = (upper + lower) / 2, (upper - lower) / 2
    L2 = np.diag(half**2)
    velocity = pe.limits_along(dyn, None, T, capacity="velocity", qd_max=upper, qd_min=lower)
    force = pe.limits_along(dyn, None, T, upper, lower, capacity="force")
    assert set(velocity) == {"polytope", "yoshikawa"}
    assert set(force) == {"polytope", "chiacchio", "yoshikawa", "static"}
    for k in range(K):
        Jk, gk, t = J[k], g[k], T[k]
        # velocities: s t = J qd, lower <= qd <= upper; variables (s, qd)
        A_eq = np.hstack([-t[:, None], Jk])
        box = np.vstack(
            [np.hstack([np.zeros((n, 1)), np.eye(n)]), np.hstack([np.zeros((n, 1)), -np.eye(n)])]
        )
        expected = _lp_interval(box, np.concatenate([upper, -lower]), t, A_eq)
        np.testing.assert_allclose(
            [velocity["polytope"].lo[k], velocity["polytope"].hi[k]], expected, rtol=1e-7, atol=1e-9
        )
        shape = Jk @ L2 @ Jk.T
        expected = _quadratic_interval(shape, Jk @ centre, t)
        np.testing.assert_allclose(
            [velocity["yoshikawa"].lo[k], velocity["yoshikawa"].hi[k]], expected, rtol=1e-9
        )
        # forces: lower <= J^T (s t) + g <= upper; variable s alone
        a = (Jk.T @ t)[:, None]
        expected = _lp_interval(np.vstack([a, -a]), np.concatenate([upper - gk, gk - lower]), t)
        np.testing.assert_allclose(
            [force["polytope"].lo[k], force["polytope"].hi[k]], expected, rtol=1e-7, atol=1e-9
        )
        Li = np.diag(1.0 / half)
        P = Li @ Jk.T  # |P h + q| <= 1 for the gravity-consistent one, q = L^-1 (g - tau_c)
        q = Li @ (gk - centre)
        coefficients = (P @ t) @ (P @ t), 2.0 * (P @ t) @ q, q @ q - 1.0
        roots = np.sort(np.roots(coefficients).real)
        np.testing.assert_allclose(
            [force["chiacchio"].lo[k], force["chiacchio"].hi[k]], roots, rtol=1e-9
        )
        pinv = np.linalg.pinv(Jk.T)  # classic: (J^T)^+ (L u - (g - tau_c)), |u| <= 1
        expected = _quadratic_interval(pinv @ L2 @ pinv.T, -pinv @ (gk - centre), t)
        np.testing.assert_allclose(
            [force["yoshikawa"].lo[k], force["yoshikawa"].hi[k]], expected, rtol=1e-9
        )
        expected = _quadratic_interval(
            np.linalg.inv(Jk @ np.diag(1 / half**2) @ Jk.T), np.zeros(m), t
        )
        np.testing.assert_allclose(
            [force["static"].lo[k], force["static"].hi[k]], expected, rtol=1e-9
        )


def test_capacities_on_a_robot_with_its_own_velocity_limits_and_a_singular_posture():
    along_arm = [np.cos(0.4), np.sin(0.4)]
    q = [[0.3, 0.5, 0.7], [0.4, 0.0, 0.0]]  # the second is stretched along along_arm: singular
    T = [[1.0, 0.0], along_arm]
    velocity = pe.limits_along(ARM, q, T, capacity="velocity")  # the robot's qd limits
    force = pe.limits_along(ARM, q, T, capacity="force")  # its torque limits
    for k in range(2):
        dyn = ARM.dynamics(q[k])
        v = pe.analyze(dyn, capacity="velocity", qd_max=ARM.qd_max, qd_min=ARM.qd_min)
        f = pe.analyze(dyn, ARM.tau_max, capacity="force")
        got = [velocity["polytope"].lo[k], velocity["polytope"].hi[k]]
        np.testing.assert_allclose(got, np.array(v.polytope.limits(T[k]), dtype=float))
        got = [force["polytope"].lo[k], force["polytope"].hi[k]]
        np.testing.assert_allclose(got, np.array(f.polytope.limits(T[k]), dtype=float))
    # stretched, the arm holds any force along itself and moves its tip only across
    assert force["polytope"].lo[1] == -np.inf and force["polytope"].hi[1] == np.inf
    assert velocity["polytope"].lo[1] == pytest.approx(0.0, abs=1e-12)
    assert velocity["polytope"].hi[1] == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(pe.InputError, match="tau_max"):
        pe.limits_along(ARM, q, T, ARM.tau_max, capacity="velocity")
    with pytest.raises(pe.InputError, match="capacity"):
        pe.limits_along(ARM, q, T, capacity="torque")


def test_a_lower_limit_alone_goes_with_the_robots_upper_one():
    q0, d = [[np.pi / 2, -np.pi / 2, -np.pi / 2]], [[0.6, 0.8]]
    low = [-50.0, -10.0, -2.0]
    for capacity in ("acceleration", "force"):
        alone = pe.limits_along(ARM, q0, d, tau_min=low, capacity=capacity)["polytope"]
        both = pe.limits_along(ARM, q0, d, ARM.tau_max, low, capacity=capacity)["polytope"]
        assert (alone.lo[0], alone.hi[0]) == (both.lo[0], both.hi[0])
        assert alone.lo[0] != pe.limits_along(ARM, q0, d, capacity=capacity)["polytope"].lo[0]
    # the limits of another capacity are refused naming the one given
    with pytest.raises(pe.InputError, match=r"^tau_min"):
        pe.limits_along(ARM, q0, d, tau_min=low, capacity="velocity")
    with pytest.raises(pe.InputError, match=r"^qd_min"):
        pe.limits_along(ARM, q0, d, qd_min=[-1.0, -1.0, -1.0])
