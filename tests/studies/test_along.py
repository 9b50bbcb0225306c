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
