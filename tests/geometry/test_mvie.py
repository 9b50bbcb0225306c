"""The maximum-volume inscribed ellipsoid: the dedicated solver against cvxpy + Clarabel,
closed forms, 6-D tasks and configurations next to singular ones (issues 11 and 15)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import polyell as pe
from polyell.errors import SolverError
from polyell.geometry import logdet
from polyell.geometry.logdet import centred_mvee
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from reference import PAPER_ARM, PAPER_TAU_MAX, random_problem

#: The solver certifies 1e-8 in log det; Clarabel stops at its own tolerances.
RTOL_SOLVERS = 1e-6


def assert_touches_and_is_maximal(E: pe.Ellipsoid, P: pe.Polytope, atol: float = 1e-9) -> None:
    scale = pe.comparison.metrics.inscribed_scale(E, P)
    assert scale == pytest.approx(1.0, abs=atol)
    for i in range(E.rank):  # no enlargement along any axis fits
        bigger = E.semi_axes.copy()
        bigger[i] *= 1 + 1e-5
        assert pe.comparison.metrics.inscribed_scale(pe.Ellipsoid(E.center, E.axes, bigger), P) < 1


@pytest.mark.parametrize(("m", "n"), [(2, 3), (3, 5), (3, 7), (6, 8), (6, 12)])
@pytest.mark.parametrize("seed", range(3))
def test_logdet_solver_agrees_with_cvxpy(m, n, seed):
    P = random_problem(seed, m, n).polytope
    E = max_volume_inscribed_ellipsoid(P)
    reference = max_volume_inscribed_ellipsoid(P, method="cvxpy")
    assert E.volume == pytest.approx(reference.volume, rel=RTOL_SOLVERS)
    np.testing.assert_allclose(E.core, reference.core, rtol=1e-4, atol=1e-6 * np.abs(E.core).max())
    assert_touches_and_is_maximal(E, P)


@pytest.mark.parametrize("n", [12, 16])
def test_every_six_dimensional_case_scores_without_warnings(n):
    """Issue 11: 4 of 16 (n = 12) and 7 of 16 (n = 16) of these raised SolverError."""
    for seed in range(16):
        analysis = random_problem(seed, 6, n)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            cmp = pe.compare(analysis, 32)
        assert cmp["mvie"].defined, cmp["mvie"].reason
        assert 0 < cmp["chiacchio"].mvie_ratio < 1
        assert cmp.mvie.volume >= analysis.ellipsoid("chiacchio").volume


@pytest.mark.parametrize("seed", range(4))
def test_square_case_is_exactly_the_new_ellipsoid(seed):
    """n = m: P is a parallelotope and its MVIE is the new ellipsoid (ratio exactly 1)."""
    analysis = random_problem(seed, 6, 6)
    cmp = pe.compare(analysis, 16)
    assert cmp["chiacchio"].mvie_ratio == 1.0
    # and the general solver agrees once the parallelotope is seen as a zonotope of 7
    # generators, one of them zero-length
    padded = pe.Polytope(np.column_stack([analysis.M, np.zeros(6)]), analysis.xg)
    general = max_volume_inscribed_ellipsoid(padded)
    assert general.volume == pytest.approx(cmp.mvie.volume, rel=1e-7)


@pytest.mark.parametrize("d", [10.0**-e for e in range(3, 10)])
def test_mvie_next_to_a_singular_configuration(d):
    """Issue 15: the log-det program failed for q = (0.4, 1e-7, 1e-7)."""
    analysis = pe.analyze(PAPER_ARM.dynamics([0.4, d, d]), tau_max=PAPER_TAU_MAX)
    assert analysis.rank == 2
    P = analysis.polytope
    E = max_volume_inscribed_ellipsoid(P)
    s = analysis.svd.singular_values
    # P's facets in task coordinates carry the data's error, eps * kappa (test_near_singular)
    assert_touches_and_is_maximal(E, P, atol=max(1e-9, 100 * np.finfo(float).eps * s[0] / s[-1]))
    assert E.volume >= analysis.ellipsoid("chiacchio").volume
    reference = max_volume_inscribed_ellipsoid(P, method="cvxpy")
    assert E.volume == pytest.approx(reference.volume, rel=RTOL_SOLVERS)


@pytest.mark.parametrize(("m", "n"), [(3, 7), (6, 10)])
def test_the_batch_solves_each_problem_as_alone(m, n):
    """centred_mvee_batch on K problems equals centred_mvee on each one."""
    problems = []
    for seed in range(6):
        svd = random_problem(seed, m, n).svd
        facets = pe.geometry.zonotope.zonotope_facets(svd.V1.T)
        half = len(facets.normals) // 2
        problems.append(facets.normals[:half] / facets.offsets[:half, None])
    count = min(len(p) for p in problems)
    points = np.stack([p[:count] for p in problems])  # the same count for a batch
    shapes, gaps, _ = logdet.centred_mvee_batch(points)
    for k in range(len(points)):
        alone = centred_mvee(points[k])
        np.testing.assert_allclose(shapes[k], alone.shape, rtol=1e-12, atol=1e-12)
        assert gaps[k] == pytest.approx(alone.gap, abs=1e-12) and gaps[k] <= 1e-8


def test_certificate_bounds_the_optimum_of_a_known_problem():
    """Points +-e_i / h_i: the MVEE is the axis-aligned ellipsoid with X = diag(h^-2)... of
    the box's polar, X_ii = h_i^2 (D-optimal design on the axes)."""
    h = np.array([0.5, 2.0, 3.0])
    result = centred_mvee(np.diag(1.0 / h))
    np.testing.assert_allclose(result.shape, np.diag(h**2), rtol=1e-8, atol=1e-12)
    assert 0 <= result.gap <= 1e-8


def test_a_failed_mvie_is_a_record_not_an_exception(monkeypatch):
    """A score that cannot be computed is reported, not raised (sweeps: test_sweep.py)."""

    def fail(points, **_):
        raise SolverError("injected")

    monkeypatch.setattr(logdet, "centred_mvee", fail)
    monkeypatch.setattr(pe.geometry.mvie, "centred_mvee", fail)
    arm = pe.robots.load("chiacchio2000")
    cmp = pe.compare(pe.analyze(arm.dynamics([0.1, 0.2, 0.3]), arm.tau_max), 8)
    assert not cmp["mvie"].defined and "injected" in cmp["mvie"].reason


def test_kinova_six_dimensional_task_scores_everywhere():
    """Issue 11: the Kinova 6-D task failed in 1 of 10 configurations (n = m = 6: exact)."""
    robot = pe.robots.load("kinova", task=["x", "y", "z", "wx", "wy", "wz"], weights=[1] * 6)
    low, high = robot.position_limits
    for q in pe.random_configurations(10, low, high, seed=1).rows(0, 10):
        cmp = pe.compare(pe.analyze(robot.dynamics(q), robot.tau_max), 16)
        assert cmp["mvie"].defined and cmp["chiacchio"].mvie_ratio == 1.0
