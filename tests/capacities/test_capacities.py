"""One battery over every registered capacity, against the raw definitions.

Each check recomputes from the robot's own matrices and limits (J, B, g, the joint
boxes), never from the analysis's polytope: directional limits by a linear program over the
joint quantities, membership of ellipsoid points by the same program, the inverse by the
forward map.  Tolerances: ``RTOL_LP`` (HiGHS against a closed form) and ``RTOL_EXACT``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog

import polyell as pe
from polyell.capacities import capacity_class
from reference import RTOL_EXACT, RTOL_LP, random_directions, random_problem

SHAPES = [(2, 3), (3, 7), (6, 7)]
#: Definitions that lie inside the exact set by construction (their witness is at most 1).
INSIDE = {
    "acceleration": ("chiacchio", "yoshikawa"),
    "velocity": ("yoshikawa",),
    "force": ("chiacchio",),
}
#: Definitions whose own inverse keeps the normalized joint quantity in the unit ball.
WITNESS_BALL = {"acceleration": ("chiacchio",), "velocity": ("yoshikawa",), "force": ("chiacchio",)}


def line_program(an: pe.Analysis, start: np.ndarray, offset: np.ndarray) -> tuple[float, float]:
    """``[lo, hi]`` of ``{s : start + s offset achievable}`` by HiGHS over joint quantities.

    Variables ``(s, z)`` with z the joint accelerations or velocities, or ``s`` alone for
    forces (whose torque is fixed by the force).  NaN where the line misses the set, an
    infinite end where the set is unbounded along it.
    """
    J = an.dynamics.J
    n = J.shape[1]
    A_eq = b_eq = A_ub = b_ub = None
    if an.capacity == "force":  # tau_min <= J^T (start + s offset) + g <= tau_max
        base, step = J.T @ start + an.dynamics.g, J.T @ offset
        A_ub = np.concatenate([step, -step])[:, None]
        b_ub = np.concatenate([an.tau_max - base, base - an.tau_min])
        bounds = [(None, None)]
    elif an.capacity == "velocity":  # J qd = start + s offset, qd in its box
        A_eq, b_eq = np.hstack([-offset[:, None], J]), start
        bounds = [(None, None), *zip(an.qd_min, an.qd_max, strict=True)]
    else:  # J qdd + bias = start + s offset, tau = B qdd + g within the limits
        B, g = an.dynamics.B, an.dynamics.g
        A_ub = np.vstack([np.hstack([np.zeros((n, 1)), B]), np.hstack([np.zeros((n, 1)), -B])])
        b_ub = np.concatenate([an.tau_max - g, g - an.tau_min])
        A_eq, b_eq = np.hstack([-offset[:, None], J]), start - an.dynamics.xdd_bias
        bounds = [(None, None)] * (n + 1)
    ends = []
    for sign in (1.0, -1.0):
        cost = np.zeros(len(bounds))
        cost[0] = sign
        result = linprog(cost, A_ub, b_ub, A_eq, b_eq, bounds=bounds, method="highs")
        if result.status == 2:  # infeasible: the line misses the set
            return np.nan, np.nan
        if result.status == 3:  # unbounded along the line
            ends.append(-sign * np.inf)
            continue
        assert result.status == 0, result.message
        ends.append(result.x[0])
    return ends[0], ends[1]


def boundary_points(E: pe.Ellipsoid, count: int, seed: int) -> np.ndarray:
    u = random_directions(seed, count, E.rank)
    return E.center + (u * E.semi_axes) @ E.axes.T


def forward(an: pe.Analysis, joint: np.ndarray) -> np.ndarray:
    """The task quantity a joint quantity produces (the definition of each capacity)."""
    J = an.dynamics.J
    if an.capacity == "acceleration":
        return joint @ J.T + an.dynamics.xdd_bias
    if an.capacity == "velocity":
        return joint @ J.T
    # force: tau = J^T h + g has a solution h iff tau - g is in Im(J^T)
    return np.linalg.lstsq(J.T, (joint - an.dynamics.g).T, rcond=None)[0].T


@pytest.mark.parametrize("capacity", pe.CAPACITIES)
@pytest.mark.parametrize(("m", "n"), SHAPES)
def test_limits_equal_the_joint_program(capacity, m, n):
    # random_problem's asymmetric torque ranges may exclude 0: then most lines through the
    # origin miss the force polytope, so forces take symmetric limits here (asymmetric ones
    # are tested through the centre below)
    asymmetric = capacity != "force"
    an = random_problem(11 * m + n, m, n, asymmetric=asymmetric, gravity=0.3, capacity=capacity)
    assert an.capacity == capacity and isinstance(an, capacity_class(capacity))
    T = random_directions(5, 12, m)
    limits = an.polytope.limits(T)
    assert np.isfinite(limits.hi).sum() >= 3  # not a vacuous comparison of NaN with NaN
    for t, lo, hi in zip(T, limits.lo, limits.hi, strict=True):
        ref_lo, ref_hi = line_program(an, np.zeros(m), t)
        scale = max(1.0, abs(ref_lo), abs(ref_hi))
        assert lo == pytest.approx(ref_lo, abs=RTOL_LP * scale, nan_ok=True)
        assert hi == pytest.approx(ref_hi, abs=RTOL_LP * scale, nan_ok=True)


@pytest.mark.parametrize("capacity", pe.CAPACITIES)
@pytest.mark.parametrize(("m", "n"), SHAPES)
def test_inside_definitions_are_inside_and_their_witness_is_at_most_one(capacity, m, n):
    gravity = 0.05 if capacity == "force" else 0.3  # an arm that can hold itself
    an = random_problem(7 * m + n, m, n, asymmetric=True, gravity=gravity, capacity=capacity)
    for kind in INSIDE[capacity]:
        E = an.ellipsoid(kind)
        points = boundary_points(E, 8, seed=m + n)
        for point in points:
            assert line_program(an, E.center, point - E.center)[1] >= 1.0 - RTOL_LP
        if kind in WITNESS_BALL[capacity]:
            witness = an.witness_map(kind)(points)
            np.testing.assert_allclose(np.linalg.norm(witness, axis=1), 1.0, rtol=RTOL_EXACT)
            assert np.abs(witness).max() <= 1.0 + RTOL_EXACT
        assert pe.compare(an, 64)[kind].inscribed_scale >= 1.0 - RTOL_EXACT


@pytest.mark.parametrize("capacity", pe.CAPACITIES)
def test_inverse_reproduces_the_point_and_its_normalized_value(capacity):
    an = random_problem(3, 3, 7, asymmetric=True, gravity=0.05, capacity=capacity)
    for kind in an.ellipsoid_kinds:
        points = boundary_points(an.ellipsoid(kind), 5, seed=1)
        joint, normalized = an.inverse(points, kind)
        np.testing.assert_allclose(forward(an, joint), points, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(normalized, an.witness_map(kind)(points), atol=1e-10)
        low = an.qd_min if capacity == "velocity" else an.tau_min
        high = an.qd_max if capacity == "velocity" else an.tau_max
        np.testing.assert_allclose(
            joint if capacity != "acceleration" else joint @ an.dynamics.B.T + an.dynamics.g,
            0.5 * (high + low) + normalized * 0.5 * (high - low),
            rtol=1e-10,
            atol=1e-10,
        )


@pytest.mark.parametrize("capacity", pe.CAPACITIES)
def test_scores_are_invariant_under_scaling_the_limits(capacity):
    """Limits (and gravity) times s scale every set by s: scores do not move."""
    rng = np.random.default_rng(4)
    J, B = rng.normal(size=(3, 7)), np.diag(rng.uniform(0.5, 2.0, 7))
    g, high = 0.2 * rng.normal(size=7), rng.uniform(1.0, 3.0, 7)
    low = -rng.uniform(0.5, 1.5, 7) * high
    rows = []
    for s in (1e-3, 1.0, 1e3):
        if capacity == "velocity":
            an = pe.analyze(pe.Kinematics(J), capacity=capacity, qd_max=s * high, qd_min=s * low)
        else:
            an = pe.analyze(pe.Dynamics(J, B, s * g), s * high, s * low, capacity=capacity)
        cmp = pe.compare(an, 64, samples=256)
        rows.append((s, cmp))
    for s, cmp in rows:
        for kind in cmp.kinds:
            # closed forms to rounding; an H-polytope's MVIE to its solver's accuracy (Clarabel)
            rtol = 1e-4 if (capacity, kind) == ("force", "mvie") else 1e-6
            for name in ("inscribed_scale", "direction_error_mean", "coverage"):
                value, reference = getattr(cmp[kind], name), getattr(rows[1][1][kind], name)
                assert value == pytest.approx(reference, rel=rtol, abs=1e-9), (kind, name, s)
            volume = rows[1][1][kind].volume
            assert cmp[kind].volume == pytest.approx(s**3 * volume, rel=3 * rtol**1.5)


def test_velocity_polytope_is_the_image_of_the_joint_box():
    an = random_problem(8, 3, 5, asymmetric=True, capacity="velocity")
    J = an.dynamics.J
    corners = np.array(np.meshgrid(*zip(an.qd_min, an.qd_max, strict=True))).reshape(5, -1).T
    from scipy.spatial import ConvexHull

    images = corners @ J.T
    hull = ConvexHull(images)
    assert an.polytope.volume == pytest.approx(hull.volume, rel=RTOL_EXACT)
    np.testing.assert_allclose(an.xg, J @ (an.qd_max + an.qd_min) / 2, atol=1e-12)
    extreme = images[hull.vertices]
    found = an.polytope.vertices
    assert len(found) == len(extreme)
    distance = np.linalg.norm(found[:, None] - extreme[None], axis=2).min(axis=1)
    assert distance.max() <= 1e-12 * np.abs(images).max()


def test_velocity_ellipsoid_is_the_weighted_yoshikawa_core():
    """{J qd : qd^T L^-2 qd <= 1} has core (J L^2 J^T)^-1 (symmetric limits)."""
    an = random_problem(9, 3, 7, capacity="velocity")
    J, L = an.dynamics.J, np.diag(an.qd_max)
    np.testing.assert_allclose(
        an.ellipsoid("yoshikawa").core, np.linalg.inv(J @ L @ L @ J.T), rtol=1e-10
    )


# --- force: the derivations of the theory page --------------------------------------------


def force_problem(seed: int, m: int = 3, n: int = 7, gravity: float = 0.05) -> pe.Analysis:
    return random_problem(seed, m, n, asymmetric=True, gravity=gravity, capacity="force")


def test_force_residual_splits_into_the_ellipsoid_and_the_unbalanced_part():
    """|A h + c|^2 = |A (h - h0)|^2 + |c_perp|^2 for every h (the theory page's identity)."""
    an = force_problem(1)
    h = np.random.default_rng(2).normal(size=(20, 3))
    left = np.sum((h @ an.A.T + an.c) ** 2, axis=1)
    right = np.sum(((h - an.center) @ an.A.T) ** 2, axis=1) + an.c_perp @ an.c_perp
    np.testing.assert_allclose(left, right, rtol=1e-12)
    assert np.abs(an.A.T @ an.c_perp).max() <= 1e-12 * np.abs(an.c).max()  # c_perp in Ker A^T


def test_force_ellipsoids_match_their_definitions():
    an = force_problem(2)
    J, g = an.dynamics.J, an.dynamics.g
    L_inv = 1.0 / an.half_range
    chiacchio = boundary_points(an.ellipsoid("chiacchio"), 10, 3)
    np.testing.assert_allclose(
        np.linalg.norm((chiacchio @ J + g - an.tau_center) * L_inv, axis=1), 1.0, rtol=1e-10
    )
    static = boundary_points(an.ellipsoid("static"), 10, 4)
    assert np.abs(an.ellipsoid("static").center).max() == 0.0
    np.testing.assert_allclose(np.linalg.norm((static @ J) * L_inv, axis=1), 1.0, rtol=1e-10)
    # yoshikawa: h = pinv(J^T) (tau_c + L u - g), |u| <= 1, independently by lstsq: unit u
    # in the row space of F = pinv(J^T) L reach the boundary, the others fall inside.
    E = an.ellipsoid("yoshikawa")
    np.testing.assert_allclose(E.center, np.linalg.lstsq(J.T, an.tau_center - g, rcond=None)[0])
    F = np.linalg.lstsq(J.T, np.diag(an.half_range), rcond=None)[0]
    u = random_directions(5, 10, 7)
    row_space = u @ np.linalg.pinv(F) @ F
    row_space /= np.linalg.norm(row_space, axis=1, keepdims=True)
    for directions, level in ((row_space, 1.0), (u, None)):
        offsets = directions @ F.T
        form = np.einsum("ki,ij,kj->k", offsets, E.core, offsets)
        if level is None:
            assert np.all(form <= 1.0 + 1e-10) and np.all(form < 1.0 - 1e-6)
        else:
            np.testing.assert_allclose(form, level, rtol=1e-10)


def test_gravity_consistent_force_ellipsoid_is_inscribed():
    """The issue's number: inscribed scale >= 1 - 1e-9 and witness <= 1 + 1e-9, every try."""
    defined = 0
    for seed in range(60):
        m, n = ((2, 3), (3, 7), (6, 7), (3, 4))[seed % 4]
        an = force_problem(100 + seed, m, n, gravity=(0.05, 0.2, 0.5)[seed % 3])
        cmp = pe.compare(an, 64, samples=256, mvie=False, outer=False)
        record = cmp["chiacchio"]
        if not record.defined:  # gravity alone beyond a unit ball of torques: said
            assert np.linalg.norm(an.c_perp) >= 1.0, record.reason
            continue
        defined += 1
        assert record.inscribed_scale >= 1.0 - 1e-9
        assert record.witness_torque_max <= 1.0 + 1e-9
        for kind in ("yoshikawa", "static"):  # reported with their true overreach
            assert 0.0 <= cmp[kind].overreach <= 1.0
    assert defined >= 40  # the claim was tested, not skipped


def test_singular_force_polytope_is_unbounded_and_said_so():
    an = random_problem(6, 3, 7, rank=2, gravity=0.02, capacity="force")
    P = an.polytope
    assert an.is_singular and not P.is_bounded
    kernel = np.linalg.svd(an.dynamics.J)[0][:, 2]  # Ker J^T
    assert np.linalg.matrix_rank(np.vstack([P.rays, kernel])) == np.linalg.matrix_rank(P.rays)
    lo, hi = P.limits(kernel)
    assert lo == -np.inf and hi == np.inf
    assert P.volume == np.inf
    cmp = pe.compare(an, 32)
    for kind in cmp.kinds:
        assert not cmp[kind].defined and cmp[kind].reason
    assert "singular" in cmp["chiacchio"].reason
    with pytest.raises(pe.UndefinedEllipsoidError, match="Ker"):
        an.ellipsoid("static")
    assert cmp.to_row()["polytope_volume"] == np.inf


def test_force_polytope_of_an_arm_that_cannot_hold_itself_is_empty():
    rng = np.random.default_rng(7)
    J = rng.normal(size=(2, 4))
    tau_max = np.ones(4)
    # c in Ker(J) with |c| = 3 > sqrt(4): |A h + c|_inf >= |c| / 2 > 1 for every h
    c = np.linalg.svd(J)[2][-1] * 3.0
    an = pe.analyze(pe.Dynamics(J, np.eye(4), c * tau_max), tau_max, capacity="force")
    assert an.polytope.is_empty
    assert np.all(np.isnan(an.polytope.limits(random_directions(1, 5, 2)).hi))
    cmp = pe.compare(an, 16)
    assert all(not cmp[kind].defined for kind in cmp.kinds)


# --- refusals -----------------------------------------------------------------------------


def test_unknown_capacity_is_refused_with_a_suggestion():
    dyn = pe.Dynamics(np.eye(2), np.eye(2), np.zeros(2))
    with pytest.raises(pe.InputError, match=r"capacity: expected one of .*did you mean 'force'"):
        pe.analyze(dyn, [1.0, 1.0], capacity="forces")
    with pytest.raises(pe.InputError, match="capacity"):
        pe.analyze(dyn, [1.0, 1.0], capacity=3)


def test_velocity_limits_missing_misplaced_or_non_positive_are_refused():
    kin = pe.Kinematics(np.eye(2))
    with pytest.raises(pe.InputError, match="qd_max: expected joint velocity limits"):
        pe.analyze(kin, capacity="velocity")
    with pytest.raises(pe.InputError, match="qd_max: expected strictly positive"):
        pe.analyze(kin, capacity="velocity", qd_max=[1.0, 0.0])
    with pytest.raises(pe.InputError, match="qd_min: expected qd_min < qd_max"):
        pe.analyze(kin, capacity="velocity", qd_max=[1.0, 1.0], qd_min=[0.0, 2.0])
    with pytest.raises(pe.InputError, match="tau_max: expected no torque limits"):
        pe.analyze(kin, [1.0, 1.0], capacity="velocity", qd_max=[1.0, 1.0])
    dyn = pe.Dynamics(np.eye(2), np.eye(2), np.zeros(2))
    with pytest.raises(pe.InputError, match="qd_max: expected no joint velocity limits"):
        pe.analyze(dyn, [1.0, 1.0], qd_max=[1.0, 1.0])


def test_limits_too_small_for_floating_point_are_named_with_their_fix():
    J = np.random.default_rng(0).normal(size=(3, 7))
    tiny = np.full(7, 1e-200)
    with pytest.raises(pe.InputError, match=r"dyn or qd_max: .*joint velocity limits qd_max"):
        pe.analyze(pe.Kinematics(J), capacity="velocity", qd_max=tiny)
    with pytest.raises(pe.InputError, match=r"dyn or qd_max: .*joint velocity limits qd_max"):
        pe.sweep(
            pe.Dynamics(J[None], np.eye(7)[None], np.zeros((1, 7))),
            capacity="velocity",
            qd_max=tiny,
        )
    with pytest.raises(pe.InputError, match="qd_max: expected a joint velocity box wider"):
        pe.analyze(
            pe.Kinematics(J), capacity="velocity", qd_max=np.full(7, 1.0 + 1e-15), qd_min=np.ones(7)
        )
    dyn = pe.Dynamics(J, np.eye(7), np.zeros(7))
    for capacity in ("acceleration", "force"):
        with pytest.raises(pe.InputError, match=r"dyn or tau_max: .*the torque limits together"):
            pe.analyze(dyn, tiny, capacity=capacity)


def test_force_needs_gravity_torques():
    with pytest.raises(pe.InputError, match="dyn: expected dynamics with gravity torques"):
        pe.analyze(pe.Kinematics(np.eye(2)), [1.0, 1.0], capacity="force")
    with pytest.raises(pe.InputError, match="tau_max: expected torque limits"):
        pe.analyze(pe.Dynamics(np.eye(2), np.eye(2), np.zeros(2)), capacity="force")


def test_kinds_of_another_capacity_are_refused():
    an = random_problem(1, 2, 3, capacity="velocity")
    with pytest.raises(pe.InputError, match="the velocity capacity's ellipsoids"):
        an.ellipsoid("chiacchio")
    force = random_problem(1, 2, 3, capacity="force")
    with pytest.raises(pe.InputError, match="'static'"):
        force.inverse([0.0, 0.0], kind="mvie")


def test_every_force_ellipsoid_is_undefined_where_the_set_is_empty():
    arm = pe.robots.load("chiacchio2000")
    an = pe.analyze(arm.dynamics([0.3, 0.7, -1.1]), [1.0, 1.0, 1.0], capacity="force")
    assert an.polytope.is_empty
    for kind in an.ellipsoid_kinds:
        with pytest.raises(pe.UndefinedEllipsoidError, match="the force set is empty"):
            an.ellipsoid(kind)
