"""Ellipsoids: limits (eq. 23-24) against a second-order cone program, volume, membership."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import polyell as pe
from reference import RTOL_EXACT, RTOL_LP, random_directions, random_spd


def random_ellipsoid(seed: int, m: int, rank: int, offset: float = 1.0) -> pe.Ellipsoid:
    rng = np.random.default_rng(seed)
    axes = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :rank]
    semi_axes = rng.uniform(0.5, 5.0, rank)
    center = offset * axes @ rng.normal(size=rank) * 3.0  # centre inside its own affine set
    return pe.Ellipsoid(center, axes, semi_axes)


def limits_by_socp(E: pe.Ellipsoid, t: np.ndarray) -> tuple[float, float]:
    """min and max a with a t = c + U diag(s) u, |u| <= 1 (NaN if infeasible)."""
    a, u = cp.Variable(), cp.Variable(E.rank)
    constraints = [a * t == E.center + (E.axes * E.semi_axes) @ u, cp.norm(u) <= 1]
    ends = []
    for sense in (cp.Minimize, cp.Maximize):
        problem = cp.Problem(sense(a), constraints)
        problem.solve(solver=cp.CLARABEL)
        assert problem.status in (cp.OPTIMAL, cp.INFEASIBLE), problem.status
        ends.append(a.value if problem.status == cp.OPTIMAL else np.nan)
    return ends[0], ends[1]


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize(("m", "rank"), [(2, 2), (3, 3), (2, 1), (3, 2), (3, 1)])
def test_limits_equal_a_cone_program(seed, m, rank):
    E = random_ellipsoid(seed, m, rank)
    T = np.vstack([E.axes.T, random_directions(seed + 99, 4, m)])
    lo, hi = E.limits(T)
    for k, t in enumerate(T):
        expected = limits_by_socp(E, t)
        if np.isnan(expected[0]):
            assert np.isnan(lo[k]) and np.isnan(hi[k])
        else:
            np.testing.assert_allclose(
                [lo[k], hi[k]], expected, rtol=1e-6, atol=1e-6 * E.semi_axes[0]
            )


def test_far_centre_leaves_lines_that_miss():
    E = pe.Ellipsoid([10.0, 0.0], np.eye(2), [1.0, 1.0])
    lo, hi = E.limits([[0.0, 1.0], [1.0, 0.0]])
    assert np.isnan(lo[0]) and np.isnan(hi[0])
    np.testing.assert_allclose([lo[1], hi[1]], [9.0, 11.0])


def test_eq23_alone_is_wrong_for_a_degenerate_ellipsoid():
    # A segment along y through (1, 0): the x axis meets it only at (1, 0).
    E = pe.Ellipsoid([1.0, 0.0], [[0.0], [1.0]], [2.0])
    lo, hi = E.limits([[1.0, 0.0], [0.0, 1.0]])
    np.testing.assert_allclose([lo[0], hi[0]], [1.0, 1.0])
    assert np.isnan(lo[1]) and np.isnan(hi[1])  # the y axis is parallel to it and misses it


@given(seed=st.integers(0, 2**32 - 1), m=st.integers(1, 4))
def test_volume_from_core_determinant(seed, m):
    N = random_spd(np.random.default_rng(seed), m)
    E = pe.Ellipsoid.from_core(np.zeros(m), N)
    unit_ball = {1: 2.0, 2: np.pi, 3: 4.0 / 3.0 * np.pi, 4: np.pi**2 / 2.0}[m]
    assert E.volume == pytest.approx(unit_ball / np.sqrt(np.linalg.det(N)), rel=RTOL_EXACT)
    np.testing.assert_allclose(E.core, N, rtol=RTOL_EXACT, atol=RTOL_EXACT * np.abs(N).max())


@given(seed=st.integers(0, 2**32 - 1))
def test_contains_boundary_and_rejects_points_just_outside(seed):
    E = random_ellipsoid(seed, 3, 2)
    u = random_directions(seed, 20, 2)
    boundary = E.center + (u * E.semi_axes) @ E.axes.T
    assert np.all(E.contains(boundary))
    assert not np.any(E.contains(E.center + 1.001 * (boundary - E.center)))
    normal = np.cross(E.axes[:, 0], E.axes[:, 1])
    scale = np.linalg.norm(E.center)  # off the plane: within AFFINE_RTOL of |x| (rounding)
    assert not E.contains(E.center + 10 * pe.AFFINE_RTOL * (scale + 1.0) * normal)
    assert E.contains(E.center + 0.1 * pe.AFFINE_RTOL * scale * normal)


def test_support_function_is_attained_on_the_boundary():
    E = random_ellipsoid(4, 3, 3)
    a = random_directions(5, 10, 3)
    u = random_directions(6, 20000, 3)
    boundary = E.center + (u * E.semi_axes) @ E.axes.T
    assert np.all(E.support(a) >= (boundary @ a.T).max(axis=0) - 1e-12)
    assert np.all(E.support(a) <= (boundary @ a.T).max(axis=0) + 0.05 * E.semi_axes[0])


def test_axes_are_sorted_and_sign_canonical():
    E = pe.Ellipsoid([0.0, 0.0], [[0.0, -1.0], [1.0, 0.0]], [1.0, 3.0])
    np.testing.assert_array_equal(E.semi_axes, [3.0, 1.0])
    np.testing.assert_array_equal(E.axes, [[1.0, 0.0], [0.0, 1.0]])


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"semi_axes": [1.0, 0.0]}, "semi_axes: expected strictly positive"),
        ({"axes": [[1.0, 1.0], [0.0, 1.0]]}, "axes: expected orthonormal columns"),
        ({"center": [0.0, np.nan]}, "center: expected finite values"),
        ({"axes": np.eye(3)}, "axes: expected an array of real numbers with shape (2, k)"),
    ],
)
def test_bad_ellipsoids(kwargs, fragment):
    args = {"center": [0.0, 0.0], "axes": np.eye(2), "semi_axes": [2.0, 1.0]} | kwargs
    with pytest.raises(pe.InputError) as info:
        pe.Ellipsoid(**args)
    assert fragment in str(info.value)


def test_rtol_lp_constant_is_what_the_polytope_tests_use():
    assert RTOL_LP == 1e-8


@given(
    ratio_exponent=st.integers(3, 9),
    scale_exponent=st.integers(-16, 16),
    m=st.integers(2, 4),
    seed=st.integers(0, 2**16),
)
def test_membership_of_thin_ellipsoids_is_relative_and_scale_free(
    ratio_exponent, scale_exponent, m, seed
):
    """Semi-axes (1, ..., 10^-ratio): points at (1 +- 1e-6) x the thin semi-axis.

    The tolerance of contains is 1 + ATOL_RELATIVE (1e-9) plus a rounding floor of
    (m + r + 3) eps (|x| + |c|) / s_min; with the centre within 3 s_min of the origin the
    floor is below 14 * 2.2e-16 * 5 < 2e-14, so 1e-6 is decided on either side at every
    condition number and, scaled by 10^k (which rounds the data by eps relative only), at
    every scale.
    """
    rng = np.random.default_rng(seed)
    axes = np.linalg.qr(rng.normal(size=(m, m)))[0]
    semi = np.concatenate([rng.uniform(0.5, 2.0, m - 1), [10.0**-ratio_exponent]])
    thin = axes[:, -1] * semi[-1]
    center = axes @ rng.uniform(-1.0, 1.0, m) * semi[-1]  # near the origin against s_min
    factor = 10.0**scale_exponent
    E = pe.Ellipsoid(center * factor, axes, semi * factor)
    points = center + np.outer([1.0 + 1e-6, 1.0 - 1e-6, -(1.0 + 1e-6), -(1.0 - 1e-6)], thin)
    np.testing.assert_array_equal(E.contains(points * factor), [False, True, False, True])
    # along a long axis too: 1 +- 1e-6 of it
    long = center + np.outer([1.0 + 1e-6, 1.0 - 1e-6], axes[:, 0] * semi[0])
    np.testing.assert_array_equal(E.contains(long * factor), [False, True])


def test_a_thin_ellipsoid_refuses_a_point_at_twice_its_thin_semi_axis():
    """The old slack atol / s_min (~1e-9 s_max / s_min = 1 here) accepted 1.9 s_min."""
    E = pe.Ellipsoid([0.0, 0.0], np.eye(2), [1.0, 1e-9])
    assert not E.contains([0.0, 1.9e-9])
    assert E.contains([0.0, 1e-9])


def test_a_flat_ellipsoid_offset_by_rounding_holds_the_origin():
    """A segment's ellipsoid whose centre is off its axis by the rounding of a solver
    (1e-15 of a 40-long set) holds the lines through the origin along it and the origin
    (the limits were NaN and ``contains`` False: the MVIE and the outer ellipsoid of a
    segment reported two feasibility mismatches); an offset beyond that rounding
    (OFFSET_RTOL of the size) is a set that misses the origin."""
    for offset in (1e-15, 1e-13):
        E = pe.Ellipsoid([0.0, offset], [[1.0], [0.0]], [40.0])
        np.testing.assert_allclose(E.limits([1.0, 0.0]), [-40.0, 40.0], rtol=1e-15)
        np.testing.assert_array_equal(E.limits([0.6, 0.8]), [0.0, 0.0])
        assert E.contains([0.0, 0.0])
    apart = pe.Ellipsoid([0.0, 1e-9], [[1.0], [0.0]], [40.0])
    assert np.isnan(apart.limits([1.0, 0.0]).lo) and not apart.contains([0.0, 0.0])
    for offset in (0.0, 1e-15, 1.78e-15):
        segment = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [40, 40, offset, -offset])
        cmp = pe.compare(segment)
        assert cmp["mvie"].feasibility_mismatch == cmp["outer"].feasibility_mismatch == 0
