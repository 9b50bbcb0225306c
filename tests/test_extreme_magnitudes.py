"""Extreme magnitudes: exact scaling inside the representable range, a clear error outside
(issue 15: M above ~1e154 or below ~1e-154 raised raw numpy errors or gave volume 0)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import polyell as pe
from reference import random_directions


def scaled(scale: float, m: int = 3, n: int = 5, batch: int | None = None) -> pe.Dynamics:
    """Accelerations (M and xg alike) multiplied by ``scale``: B = I, unit limits."""
    rng = np.random.default_rng(4)
    J, g = rng.normal(size=(m, n)), rng.normal(size=n)
    if batch is None:
        return pe.Dynamics(J * scale, np.eye(n), g)
    return pe.Dynamics(
        np.broadcast_to(J * scale, (batch, m, n)),
        np.broadcast_to(np.eye(n), (batch, n, n)),
        np.broadcast_to(g, (batch, n)),
    )


@pytest.fixture(scope="module")
def unit_scores():
    analysis = pe.analyze(scaled(1.0), np.ones(5))
    return analysis, pe.compare(analysis, 32)


@pytest.mark.parametrize("exponent", [-90, -45, -20, 20, 45, 90])
def test_results_scale_exactly_inside_the_range(unit_scores, exponent):
    reference, reference_scores = unit_scores
    scale = 10.0**exponent
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow or underflow anywhere
        analysis = pe.analyze(scaled(scale), np.ones(5))
        scores = pe.compare(analysis, 32)
    T = random_directions(1, 20, 3)
    np.testing.assert_allclose(
        np.array(analysis.polytope.limits(T)) / scale, reference.polytope.limits(T), rtol=1e-9
    )
    assert analysis.polytope.volume / scale**3 == pytest.approx(reference.polytope.volume, rel=1e-9)
    for kind in ("chiacchio", "yoshikawa", "mvie"):
        for score in ("coverage", "inscribed_scale", "mvie_ratio", "direction_error_mean"):
            assert getattr(scores[kind], score) == pytest.approx(
                getattr(reference_scores[kind], score), rel=1e-7
            ), (kind, score)


@pytest.mark.parametrize("exponent", [-300, -200, -160, -100, 100, 160, 200, 300])
def test_outside_the_range_is_a_clear_error(exponent):
    with pytest.raises(pe.InputError, match=r"1e-96\.\.1e96 in a 3-dimensional task"):
        pe.analyze(scaled(10.0**exponent), np.ones(5))
    with pytest.raises(pe.InputError, match="configuration 0 of the batch"):
        pe.sweep(scaled(10.0**exponent, batch=3), tau_max=np.ones(5), directions=8)


def test_the_range_narrows_with_the_task_dimension():
    pe.compare(pe.analyze(scaled(1e45, m=6, n=8), np.ones(8)), 16)  # 6-D: within 1e+-48
    with pytest.raises(pe.InputError, match=r"1e-48\.\.1e48 in a 6-dimensional task"):
        pe.analyze(scaled(1e50, m=6, n=8), np.ones(8))


@pytest.mark.parametrize("scale", [1e-160, 1e-200, 1e-280])
def test_a_force_set_in_tiny_units_is_the_same_set(scale):
    # Found by the independent check: J, g and the torque limits scaled together leave the
    # force set unchanged; numpy's norms of rows of 1e-200 underflowed to 0 (every row
    # dropped: an unbounded set, then a raw ValueError).
    J = np.array([[1.0, 0.5, 0.2], [0.0, 1.0, 0.3]])
    g, limit = np.array([0.1, 0.2, 0.0]), np.array([1.0, 2.0, 3.0])
    unit = pe.compare(pe.analyze(pe.Dynamics(J, np.eye(3), g), limit, capacity="force"), 16)
    analysis = pe.analyze(pe.Dynamics(J * scale, np.eye(3), g * scale), limit * scale,
                          capacity="force")  # fmt: skip
    assert analysis.polytope.volume == pytest.approx(8.0, rel=1e-12)
    scaled = pe.compare(analysis, 16)
    assert scaled["static"].coverage == pytest.approx(unit["static"].coverage, rel=1e-12)
    frame = pe.sweep(pe.Dynamics(J[None] * scale, np.eye(3)[None], g[None] * scale),
                     tau_max=limit * scale, capacity="force", directions=16)  # fmt: skip
    assert frame["polytope_volume"][0] == pytest.approx(8.0, rel=1e-12)


def test_subnormal_jacobians_and_underflowing_accelerations_are_refused():
    J = np.array([[1.0, 0.5, 0.2], [0.0, 1.0, 0.3]])
    g, limit = np.array([0.1, 0.2, 0.0]), np.array([1.0, 2.0, 3.0])
    with pytest.raises(pe.InputError, match=r"dyn\.J"):
        pe.analyze(pe.Dynamics(J * 1e-305, np.eye(3), g * 1e-305), limit * 1e-305,
                   capacity="force")  # fmt: skip
    # J B^-1 L of 1e-200 * 1e-200 is 0: not a point, an underflow
    with pytest.raises(pe.InputError, match="underflow"):
        pe.analyze(pe.Dynamics(J * 1e-200, np.eye(3), g * 1e-200), limit * 1e-200)
