"""PlanarArm against independent computations: finite differences and energies."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import polyell as pe
from reference import random_arm


def arm_and_posture(seed: int, n: int) -> tuple[pe.PlanarArm, np.ndarray]:
    arm, q, _ = random_arm(seed, n)
    return arm, q


def com_positions(arm: pe.PlanarArm, q: np.ndarray) -> np.ndarray:
    """Centres of mass, shape (n, 2), by walking the chain link by link."""
    joint = np.zeros(2)
    angle = 0.0
    points = []
    for length, com, qi in zip(arm.lengths, arm.com, q, strict=True):
        angle += qi
        u = np.array([np.cos(angle), np.sin(angle)])
        points.append(joint + com * u)
        joint = joint + length * u
    return np.array(points)


def potential_energy(arm: pe.PlanarArm, q: np.ndarray) -> float:
    return float(arm.gravity * arm.masses @ com_positions(arm, q)[:, 1])


def kinetic_energy(arm: pe.PlanarArm, q: np.ndarray, qd: np.ndarray, h: float = 1e-6) -> float:
    """1/2 sum m |v|^2 + 1/2 sum I w^2, velocities by central differences."""
    v = (com_positions(arm, q + h * qd) - com_positions(arm, q - h * qd)) / (2 * h)
    w = np.cumsum(qd)
    return 0.5 * float(arm.masses @ np.sum(v**2, axis=1) + arm.inertia @ w**2)


def numerical_gradient(f, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    return np.array([(f(q + h * e) - f(q - h * e)) / (2 * h) for e in np.eye(q.size)])


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6))
def test_jacobian_is_the_derivative_of_forward_kinematics(seed, n):
    arm, q = arm_and_posture(seed, n)
    numerical = numerical_gradient(arm.forward_kinematics, q).T
    np.testing.assert_allclose(arm.jacobian(q), numerical, atol=1e-7)
    np.testing.assert_array_equal(arm.dynamics(q).J, arm.jacobian(q))


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6))
def test_gravity_torques_are_the_gradient_of_potential_energy(seed, n):
    arm, q = arm_and_posture(seed, n)
    expected = numerical_gradient(lambda x: potential_energy(arm, x), q)
    np.testing.assert_allclose(arm.dynamics(q).g, expected, atol=1e-6)


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6))
def test_inertia_matrix_gives_the_kinetic_energy(seed, n):
    arm, q = arm_and_posture(seed, n)
    qd = np.random.default_rng(seed + 1).normal(size=n)
    B = arm.dynamics(q).B
    assert 0.5 * qd @ B @ qd == pytest.approx(kinetic_energy(arm, q, qd), rel=1e-7)


def test_single_link_pendulum_closed_form():
    arm = pe.PlanarArm(lengths=[2.0], masses=[3.0], com=[0.5], inertia=[0.7], gravity=9.81)
    q = 0.3
    dyn = arm.dynamics([q])
    np.testing.assert_allclose(dyn.B, [[0.7 + 3.0 * 0.5**2]])
    np.testing.assert_allclose(dyn.g, [3.0 * 9.81 * 0.5 * np.cos(q)])
    np.testing.assert_allclose(dyn.J, [[-2.0 * np.sin(q)], [2.0 * np.cos(q)]])


def test_default_centre_of_mass_and_inertia_are_a_uniform_rod():
    arm = pe.PlanarArm(lengths=[1.0, 0.8], masses=[4.0, 2.0])
    np.testing.assert_allclose(arm.com, [0.5, 0.4])
    np.testing.assert_allclose(arm.inertia, [4.0 / 12, 2.0 * 0.64 / 12])
    # m l^2 / 12 about the centre of mass is m l^2 / 3 about the joint axis.
    np.testing.assert_allclose(
        arm.inertia + arm.masses * arm.com**2, arm.masses * arm.lengths**2 / 3
    )
