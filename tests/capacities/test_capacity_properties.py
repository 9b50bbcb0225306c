"""Property suite over the velocity and force capacities (the acceleration one: test_properties).

The same invariant as tests/test_properties.py: a PolyellError, or a valid result --
intervals with ``lo <= hi`` (infinite ends only where the set is unbounded), scores in
[0, 1] where they are fractions, the inscribed definitions inside the exact set -- with
hypothesis-drawn problems at magnitudes from 1e-300 to 1e300 and one argument broken.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from hypothesis import event, given
from hypothesis import strategies as st
from test_properties import JUNK, assert_inside, broken, calm, problems

import polyell as pe
from polyell.comparison.metrics import inside_rtol
from polyell.geometry.directions import sphere_directions

CAPACITY_NAMES = st.sampled_from(["velocity", "force"])


def build(problem: dict[str, Any], capacity: str) -> pe.Analysis | None:
    def make() -> pe.Analysis:
        if capacity == "velocity":
            kin = pe.Kinematics(problem["J"])
            return pe.analyze(
                kin, capacity=capacity, qd_max=problem["tau_max"], qd_min=problem["tau_min"]
            )
        dyn = pe.Dynamics(problem["J"], problem["B"], problem["g"])
        return pe.analyze(dyn, problem["tau_max"], problem["tau_min"], capacity=capacity)

    result: pe.Analysis | None = calm(make)
    event(f"{capacity} built" if result is not None else f"{capacity} refused")
    return result


def check_set(an: pe.Analysis) -> None:
    P = an.polytope
    T = sphere_directions(12, an.m)
    limits = calm(lambda: P.limits(T))
    assert limits is not None
    lo, hi = np.asarray(limits.lo), np.asarray(limits.hi)
    assert np.array_equal(np.isnan(lo), np.isnan(hi))
    ok = ~np.isnan(lo)
    assert np.all(lo[ok] <= hi[ok] + 4 * np.finfo(float).eps * np.abs(hi[ok]))
    bounded = getattr(P, "is_bounded", True)
    if bounded:
        assert np.all(np.isfinite(lo[ok])) and np.isfinite(P.volume)
    assert P.volume >= 0


@given(problem=problems(), capacity=CAPACITY_NAMES, data=st.data())
def test_analyze_any_capacity_with_any_argument_broken(problem, capacity, data):
    name = data.draw(st.sampled_from(["J", "B", "g", "tau_max", "tau_min", "capacity", "none"]))
    if name == "capacity":
        capacity = data.draw(st.sampled_from([*JUNK, "Force", "velocities", ""]))
    elif name != "none":
        problem[name] = data.draw(broken(problem[name]))
    an = build(problem, capacity)
    if an is not None:
        check_set(an)


@given(problem=problems(), capacity=CAPACITY_NAMES)
def test_scores_of_every_capacity_are_valid(problem, capacity):
    an = build(problem, capacity)
    if an is None:
        return
    cmp = calm(lambda: pe.compare(an, 16, samples=256))
    if cmp is None:
        return
    inside = {"velocity": ("yoshikawa",), "force": ("chiacchio",)}[capacity]
    for kind in cmp.kinds:
        s = cmp[kind]
        if not s.defined:
            assert s.reason
            continue
        for name in ("coverage", "overreach"):
            assert 0.0 <= getattr(s, name) <= 1.0, (kind, name)
        assert s.volume >= 0
        if kind in inside:
            E, P = cmp.ellipsoid(kind), an.polytope
            assert s.inscribed_scale >= 1.0 - inside_rtol(E, P)
            assert_inside(E, P, problem["seed"])
            assert s.witness_torque_max <= 1.0 + 1e-9


@given(J=st.one_of(st.sampled_from(JUNK), st.just(np.eye(2)), st.just(np.zeros((0, 2)))))
def test_kinematics_with_any_jacobian(J):
    kin = calm(lambda: pe.Kinematics(J))
    if kin is not None:
        assert kin.J.shape == (kin.m, kin.n) and len(kin.task) == kin.m


@st.composite
def halfspaces(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray]:
    """Random half-spaces of R^m at a random magnitude: a box, a simplex-like set, a slab."""
    m = draw(st.integers(1, 3))
    k = draw(st.integers(0, 8))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    scale = draw(st.sampled_from([1e-150, 1e-3, 1.0, 1e3, 1e150]))
    A = rng.normal(size=(k, m))
    b = rng.uniform(-0.2, 1.0, k) * scale
    return A, b


@given(sets=halfspaces(), data=st.data())
def test_hpolytope_with_any_halfspaces(sets, data):
    A, b = sets
    name = data.draw(st.sampled_from(["A", "b", "none"]))
    arguments = {"A": A, "b": b}
    if name != "none":
        arguments[name] = data.draw(broken(arguments[name]))
    P = calm(lambda: pe.HPolytope(**arguments))
    if P is None:
        return
    event("empty" if P.is_empty else "bounded" if P.is_bounded else "unbounded")
    assert P.volume >= 0
    assert (P.volume == np.inf) == (not P.is_bounded and not P.is_empty)
    T = sphere_directions(6, A.shape[1])
    limits = calm(lambda: P.limits(T))
    lo, hi = np.asarray(limits.lo), np.asarray(limits.hi)
    if P.is_empty:
        assert np.all(np.isnan(lo))
        return
    ok = ~np.isnan(lo)
    assert np.all(lo[ok] <= hi[ok] + 1e-9 * np.abs(hi[ok]))
    if len(P.vertices) and P.is_bounded:  # every vertex satisfies every facet
        slack = P.facet_slacks(P.vertices)
        assert np.all(slack >= -1e-7 * max(1.0, float(np.abs(P.b).max(initial=1.0))))
