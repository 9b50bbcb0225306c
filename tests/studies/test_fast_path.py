"""The sweep's fast path equals the scalar compare() to 1e-12 on random arms, at its defaults.

The batched path (polyell.studies.batch and .directional) computes every default score of
many configurations at once, the directional limits from the polytope's gauge and from a
rearranged closed form of the ellipsoids' eq. 24; compare() computes them one configuration
at a time through Polytope.limits and Ellipsoid.limits.  Both are closed forms of the same
quantities, so they agree to rounding: the tolerance 1e-12 is a few hundred units of
rounding of scores of order one (relative for the dimensional columns, the volumes and the
radii).  A far end of an ellipsoid along a line that nearly touches it (the origin outside
the ellipsoid: strong gravity or asymmetric limits) is ill-conditioned, and both paths then
round differently within its condition number: the direction statistics are held to
``TOL + 32 eps kappa`` there, with kappa the first-order bound of :func:`far_end_condition`.
Arms are drawn with gravity weak and strong against the torques, so that both the
gauge (origin inside P) and the facet cuts (origin outside P, lines that miss it) are used,
and with symmetric and asymmetric torque limits.
"""

from __future__ import annotations

import numpy as np
import pytest

import polyell as pe
from polyell.comparison.directional import polytope_far_ends
from polyell.geometry.directions import default_direction_count, sphere_directions
from reference import random_spd

TOL = 1e-12
EPS = np.finfo(float).eps
DIMENSIONAL = ("volume", "radius", "witness_torque_max")
STATISTICS = ("direction_error", "direction_bias")


def far_end_condition(E, T: np.ndarray, hi_p: np.ndarray) -> float:
    """First-order bound on how the direction errors move per unit relative error of the data.

    The far end is ``hi = r + sqrt(r^2 + q)`` with ``r = p.w / |p|^2`` and
    ``q = (1 - |w|^2) / |p|^2`` (``p = S^-1 U^T t``, ``w = S^-1 U^T c``).  Relative errors
    ``e`` in p and w move r by about ``e |r|`` and q by ``e (|q| + 2 |w|^2 / |p|^2)``, so hi
    by ``e [(1 + |r| / root) |r| + (|q| + 2 |w|^2 / |p|^2) / (2 root)]``; the error
    ``(hi_E - hi_P) / |hi_P|`` by that over ``|hi_P|``.  The largest over the lines that meet
    both sets.
    """
    p = (T @ E.axes) / E.semi_axes
    w = (E.axes.T @ E.center) / E.semi_axes
    length2 = (p * p).sum(axis=1)
    r = p @ w / length2
    q = (1.0 - w @ w) / length2
    with np.errstate(invalid="ignore"):
        root = np.sqrt(r * r + q)
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = (
            (1.0 + np.abs(r) / root) * np.abs(r)
            + (np.abs(q) + 2.0 * (w @ w) / length2) / (2.0 * root)
        ) / np.abs(hi_p)
    return float(np.nanmax(np.where(np.isfinite(kappa), kappa, np.nan), initial=1.0))


def random_batch(seed: int, K: int, m: int, n: int, gravity: float, asymmetric: bool):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(K, m, n))
    B = np.stack([random_spd(rng, n) for _ in range(K)])
    tau_max = rng.uniform(1.0, 10.0, n)
    tau_min = tau_max - rng.uniform(0.5, 2.0, n) * tau_max if asymmetric else -tau_max
    g = gravity * rng.normal(size=(K, n)) * tau_max
    return pe.Dynamics(J, B, g), tau_max, tau_min


CASES = [
    # (m, n, gravity, asymmetric)
    (2, 4, 0.3, False),
    (3, 7, 0.3, False),
    (3, 7, 1.5, True),
    (6, 7, 0.3, True),
]


@pytest.mark.parametrize(("m", "n", "gravity", "asymmetric"), CASES)
def test_default_sweep_equals_compare(m, n, gravity, asymmetric):
    dyn, tau_max, tau_min = random_batch(100 * m + n, 24, m, n, gravity, asymmetric)
    frame = pe.sweep(dyn, tau_max=tau_max, tau_min=tau_min)
    T = sphere_directions(default_direction_count(m), m)
    origin_outside = 0
    for k in range(len(dyn)):
        analysis = pe.analyze(dyn[k], tau_max, tau_min)
        origin_outside += not analysis.polytope.contains(np.zeros(m))
        expected = pe.compare(analysis).to_row()
        hi_p = analysis.polytope.limits(T).hi
        for name in frame.columns.intersection(list(expected)):
            got, want = frame.loc[k, name], expected[name]
            if np.isnan(want):
                assert np.isnan(got), f"{name} at {k}"
                continue
            tol = TOL * (abs(want) if any(s in name for s in DIMENSIONAL) else 1.0)
            kind = name.split("_")[0]
            if any(s in name for s in STATISTICS):
                kappa = far_end_condition(analysis.ellipsoid(kind), T, hi_p)
                tol += 32.0 * EPS * kappa
            assert abs(got - want) <= tol, f"{name} at {k}: {got!r} vs {want!r}"
    if gravity > 1.0:  # the facet-cut path was taken, not only the gauge
        assert origin_outside > 0


def test_gauge_and_facet_cuts_agree():
    """Both ways of computing the far ends, on the same polytopes (origin inside)."""
    rng = np.random.default_rng(7)
    K, C, m, k = 30, 21, 3, 200
    normals = rng.normal(size=(K, C, m))
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    h = rng.uniform(1.0, 3.0, (K, C))
    center = rng.normal(size=(K, m)) * 0.2
    T = sphere_directions(k, m)
    Tt = np.ascontiguousarray(T.T)
    offsets = np.einsum("kcm,km->kc", normals, center)
    hi, meets = polytope_far_ends(normals, h, offsets, Tt, np.zeros((K, C)), np.zeros((K, 1)))
    assert meets.all() and (hi > 0).all()
    # The same far ends by cutting each line with every facet pair, one row at a time.
    slopes = np.einsum("kcm,dm->kcd", normals, T)
    with np.errstate(divide="ignore"):
        cuts = np.where(
            slopes > 0, (offsets + h)[..., None] / slopes, (offsets - h)[..., None] / slopes
        )
    np.testing.assert_allclose(hi, cuts.min(axis=1), rtol=TOL)


@pytest.mark.filterwarnings("error")  # no raw numpy warning either
@pytest.mark.parametrize("angle", [0.0, 0.3, 1e-9])
def test_origin_on_a_facet_leaves_the_outward_half_out_of_the_statistics(angle):
    """Found by the independent check: the origin on a facet, to rounding.

    J a rotation, B = I, g = (1, 0), |tau| <= 1: x_g = -R e_1, so the origin lies on the
    facet of tau_1 = -1.  Every line leaving P across it has its far end at exactly 0 (not a
    rounding error used as a denominator): those directions are not used, and the other
    half give the same statistics in the sweep, in compare() and by hand.
    """
    R = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    T = sphere_directions(358, 2)  # none along the facet (358 is not a multiple of 4)
    dyn = pe.Dynamics(R[None], np.eye(2)[None], np.array([[1.0, 0.0]]))
    row = pe.sweep(dyn, tau_max=[1.0, 1.0], directions=T).iloc[0]
    analysis = pe.analyze(dyn[0], [1.0, 1.0])
    expected = pe.compare(analysis, T, mvie=False, outer=False).to_row()
    inward = T @ R[:, 0] < -1e-12  # into P across the facet (its outward normal is -R e_1)
    hi_p = analysis.polytope.limits(T).hi
    assert (hi_p[T @ R[:, 0] > 1e-12] == 0).all()
    for kind in ("chiacchio", "yoshikawa"):
        E = analysis.ellipsoid(kind)
        hi_e = E.limits(T).hi
        used = inward & ~np.isnan(hi_e)
        error = (hi_e[used] - hi_p[used]) / np.abs(hi_p[used])
        # The origin is on the ellipsoids' boundary too: lines near their tangents.
        tol = TOL + 32.0 * EPS * far_end_condition(E, T, np.where(used, hi_p, np.nan))
        assert row[f"{kind}_directions_used"] == expected[f"{kind}_directions_used"] == used.sum()
        for name, value in (
            ("direction_error_mean", np.abs(error).mean()),
            ("direction_error_max", np.abs(error).max()),
            ("direction_bias", error.mean()),
        ):
            assert row[f"{kind}_{name}"] == pytest.approx(value, abs=tol)
            assert expected[f"{kind}_{name}"] == pytest.approx(value, abs=tol)


def test_a_singular_configuration_uses_the_default_count_of_its_rank():
    """Found by the independent check: rank 2 in 3-D took the 3-D count in the sweep."""
    J = np.random.default_rng(0).normal(size=(1, 3, 2))
    dyn = pe.Dynamics(J, np.eye(2)[None], np.zeros((1, 2)))
    row = pe.sweep(dyn, tau_max=[1.0, 1.0]).iloc[0]
    expected = pe.compare(pe.analyze(dyn[0], [1.0, 1.0]), mvie=False, outer=False).to_row()
    assert expected["chiacchio_directions_used"] == default_direction_count(2)
    for name, value in expected.items():
        if name in row.index:
            np.testing.assert_allclose(row[name], value, rtol=1e-12, atol=1e-12, err_msg=name)


@pytest.mark.filterwarnings("error")
def test_an_empty_direction_set_gives_no_statistics():
    dyn, tau_max, tau_min = random_batch(1, 3, 3, 7, 0.3, False)
    row = pe.sweep(dyn, tau_max=tau_max, tau_min=tau_min, directions=np.zeros((0, 3))).iloc[0]
    assert row["chiacchio_directions_used"] == 0
    assert np.isnan(row["chiacchio_direction_error_max"])
    assert np.isnan(row["yoshikawa_direction_error_mean"])


@pytest.mark.parametrize("directions", [True, 10.0, np.float64(3.0)])
def test_a_direction_count_must_be_an_integer(directions):
    dyn, tau_max, _ = random_batch(1, 2, 3, 7, 0.3, False)
    with pytest.raises(pe.InputError, match="a count"):
        pe.sweep(dyn, tau_max=tau_max, directions=directions)


def test_a_negligible_generator_gives_the_sweep_the_scalar_facets():
    # Found by an independent check: a Jacobian column of 1e-16 (a tip on a joint's axis,
    # as Pinocchio returns it) gave the batch facets of no direction, and an overreaching
    # candidate a different coverage estimate (2.5e-3 apart, 12x the stderr) than compare.
    m, n = 3, 6
    qd = np.full(n, 3.0)
    grown = pe.Candidate("grown", weighting=np.eye(n) / 1.8**2)
    rng = np.random.default_rng(4)
    for _ in range(4):
        J = rng.standard_normal((m, n))
        J[:, -1] = 1e-16 * rng.standard_normal(m)
        dyn = pe.Dynamics(J=J, B=np.eye(n), g=np.zeros(n))
        row = pe.sweep(
            pe.Dynamics(J=J[None], B=np.eye(n)[None], g=np.zeros((1, n))),
            capacity="velocity",
            qd_max=qd,
            candidates=[grown],
            outer=True,
            seed=2,
        ).iloc[0]
        scores = pe.compare(
            pe.analyze(dyn, capacity="velocity", qd_max=qd), seed=2, candidates=[grown], mvie=False
        )["grown"]
        assert not row["per_row"]
        assert row["grown_coverage"] == pytest.approx(scores.coverage, abs=1e-12)
        assert row["grown_coverage_stderr"] == pytest.approx(scores.coverage_stderr, rel=1e-9)
