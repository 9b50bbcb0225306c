"""``limits_along(..., horizon=)``: the batch equals ``analyze(..., horizon=)`` row by row."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.errors import InputError
from tests.reference import random_arm

RTOL = 1e-9


def _panda_path(seed, K=120):
    """Panda states: random ones, and a joint driven towards its upper limit along a path."""
    panda = pe.robots.load("panda")
    rng = np.random.default_rng(seed)
    q_min, q_max = panda.position_limits
    qd_max, qd_min = panda.velocity_limits()
    q = rng.uniform(q_min + 0.2, q_max - 0.2, (K, 7))
    qd = 0.5 * rng.uniform(qd_min, qd_max, (K, 7))
    j = 3
    q[: K // 2, j] = q_max[j] - np.geomspace(0.2, 1e-5, K // 2)  # nearer and nearer
    qd[: K // 2, j] = np.linspace(1.0, 0.05, K // 2)
    q[-3:, j] = q_max[j] + [0.0, 1e-3, 0.0]  # at the limit, beyond it
    qd[-3:, j] = [0.0, 0.0, 0.3]
    T = rng.normal(size=(K, 3))
    return panda, q, qd, T / np.linalg.norm(T, axis=1, keepdims=True)


@pytest.mark.parametrize("horizon", [0.001, 0.01, 0.05])
def test_rows_equal_the_analysis_on_the_panda(horizon):
    panda, q, qd, T = _panda_path(int(horizon * 1000))
    out = pe.limits_along(panda, q, T, horizon=horizon, qd=qd)
    q_min, q_max = panda.position_limits
    qd_max, qd_min = panda.velocity_limits()
    cut = empty = 0
    for k in range(len(q)):
        analysis = pe.analyze(
            panda.dynamics(q[k], qd[k], check_limits=False),
            panda.tau_max,
            horizon=horizon,
            q=q[k],
            qd=qd[k],
            q_min=q_min,
            q_max=q_max,
            qd_max=qd_max,
            qd_min=qd_min,
        )
        cut += bool(analysis.cut.any())
        empty += analysis.empty_reason is not None
        P = analysis.polytope
        size = float(np.abs(analysis.xg).max() + np.abs(analysis.M).sum(axis=1).max())
        expected = P.limits(T[k])
        got = out["polytope"].lo[k], out["polytope"].hi[k]
        np.testing.assert_allclose(got, expected, rtol=0, atol=RTOL * size, equal_nan=True)
        for kind in ("chiacchio", "yoshikawa"):
            E = analysis.ellipsoid(kind).limits(T[k])
            got = out[kind].lo[k], out[kind].hi[k]
            np.testing.assert_allclose(got, E, rtol=RTOL, atol=RTOL * size)
    assert cut >= 10 and empty >= 1  # the path covers cut and empty sets


def test_planar_arm_at_rest_with_given_limits_and_viability():
    arm, q0, rng = random_arm(4, 3)
    K = 60
    tau_max = rng.uniform(5.0, 40.0, 3)
    q = q0 + 0.05 * rng.normal(size=(K, 3))
    limits = {"q_min": q0 - 0.06, "q_max": q0 + 0.06, "qd_max": np.full(3, 1.5)}
    T = rng.normal(size=(K, 2))
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    out = pe.limits_along(arm, q, T, tau_max, horizon=0.05, braking=30.0, **limits)
    cut = 0
    for k in range(K):
        analysis = pe.analyze(
            arm.dynamics(q[k]),
            tau_max,
            horizon=0.05,
            q=q[k],
            qd=np.zeros(3),
            braking=30.0,
            **limits,
        )
        cut += bool(analysis.cut.any())
        size = float(np.abs(analysis.xg).max() + np.abs(analysis.M).sum(axis=1).max())
        expected = analysis.polytope.limits(T[k])
        got = out["polytope"].lo[k], out["polytope"].hi[k]
        np.testing.assert_allclose(got, expected, rtol=0, atol=RTOL * size, equal_nan=True)
    assert cut >= 5
    with pytest.raises(InputError) as error:  # a planar arm has no velocity terms
        pe.limits_along(arm, q, T, tau_max, horizon=0.05, qd=np.ones((K, 3)), **limits)
    assert error.value.argument == "qd"


def test_bad_input():
    panda, q, qd, T = _panda_path(0, K=4)
    dyn = panda.dynamics(q)
    with pytest.raises(InputError) as error:
        pe.limits_along(dyn, None, T, panda.tau_max, horizon=0.01)
    assert error.value.argument == "source"
    with pytest.raises(InputError) as error:
        pe.limits_along(panda, q, T, horizon=0.01, qd=qd, capacity="force")
    assert error.value.argument == "horizon"
    with pytest.raises(InputError) as error:
        pe.limits_along(panda, q, T, horizon=-1.0, qd=qd)
    assert error.value.argument == "horizon"
    with pytest.raises(InputError) as error:
        pe.limits_along(panda, q, T, horizon=0.01, qd=qd[:, :3])
    assert error.value.argument == "qd"
