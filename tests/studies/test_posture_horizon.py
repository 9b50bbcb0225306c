"""``posture_choice(..., horizon=)``: the truth is the set within the joint limits over dt."""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.errors import InputError


def test_values_equal_the_analysis_of_each_posture():
    panda = pe.robots.load("panda")
    q_max = panda.position_limits[1]
    q0 = np.array([0.0, -0.5, 0.0, q_max[3] - 0.02, 0.0, 1.6, 0.8])
    motion = pe.self_motion(panda, q0, count=12)
    choice = pe.posture_choice(panda, motion, direction="z", mvie=False, outer=False, horizon=0.02)
    cut = 0
    for k, q in enumerate(motion.configurations):
        analysis = panda.analyze(q, horizon=0.02)
        cut += bool(analysis.cut.any())
        P = analysis.polytope
        np.testing.assert_allclose(choice.values[("polytope", "volume")][k], P.volume, rtol=1e-12)
        lo, hi = P.limits([0.0, 0.0, 1.0])
        np.testing.assert_allclose(
            [choice.values[("polytope", "lo")][k], choice.values[("polytope", "hi")][k]],
            [lo, hi],
            rtol=1e-9,
        )
        E = analysis.ellipsoid("chiacchio")
        np.testing.assert_allclose(choice.values[("chiacchio", "volume")][k], E.volume, rtol=1e-12)
    assert cut >= 3


def test_a_planar_arm_turns_freely_within_its_velocity_limits():
    """No position limits (a planar arm's joints turn freely): only qd_max over dt binds."""
    arm = pe.robots.load("chiacchio2000")
    motion = pe.self_motion(arm, [np.pi / 2, -np.pi / 2, -np.pi / 2], count=10)
    options = {"direction": "x", "mvie": False, "outer": False, "horizon": 0.01}
    free = pe.posture_choice(arm, motion, **options)
    wide = pe.posture_choice(arm, motion, **options, q_min=[-1e3] * 3, q_max=[1e3] * 3)
    np.testing.assert_allclose(free.values.to_numpy(), wide.values.to_numpy(), rtol=1e-12)
    tight = pe.posture_choice(arm, motion, **options, qd_max=[0.01] * 3)
    assert (tight.values[("polytope", "volume")] < free.values[("polytope", "volume")]).all()
    with pytest.raises(InputError) as error:
        pe.posture_choice(arm, motion, **options, q_min=[1.0] * 3, q_max=[-1.0] * 3)
    assert error.value.argument == "q_min"
