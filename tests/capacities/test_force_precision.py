"""Precision sweep of the force capacity against mpmath at 50 digits.

Along a path of Jacobians whose condition number kappa runs from 1e2 to near the rank
threshold, in 2-D, 3-D and 6-D, the gravity-consistent ellipsoid's centre h0 = -A^+ c, its
semi-axes sqrt(1 - |c_perp|^2) / s_i and the force polytope's directional limits are
recomputed in 50-digit arithmetic from the same double-precision J, g and limits.  A
backward-stable double computation (SVD, solves of m + n terms) errs by at most about
(m + n) eps kappa relative to the largest entry of each quantity: the tolerance is 16 times
that bound; anything that squares kappa (normal equations, J J^T) fails it.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import polyell as pe

DIGITS = 50
EPS = float(np.finfo(float).eps)


def jacobian(m: int, n: int, kappa: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    U = np.linalg.qr(rng.normal(size=(m, m)))[0]
    V = np.linalg.qr(rng.normal(size=(n, n)))[0][:, :m]
    return (U * np.geomspace(1.0, 1.0 / kappa, m)) @ V.T


def reference(J: np.ndarray, g: np.ndarray, tau_max: np.ndarray, tau_min: np.ndarray):
    """h0, the semi-axes (descending) and the limits along e1, in 50 digits."""
    with mp.workdps(DIGITS):
        L = [
            (mp.mpf(float(a)) - mp.mpf(float(b))) / 2 for a, b in zip(tau_max, tau_min, strict=True)
        ]
        tc = [
            (mp.mpf(float(a)) + mp.mpf(float(b))) / 2 for a, b in zip(tau_max, tau_min, strict=True)
        ]
        m, n = J.shape
        A = mp.matrix([[mp.mpf(float(J[j, i])) / L[i] for j in range(m)] for i in range(n)])
        c = mp.matrix([(mp.mpf(float(g[i])) - tc[i]) / L[i] for i in range(n)])
        AtA = A.T * A
        h0 = -(mp.inverse(AtA) * (A.T * c))
        residual = A * h0 + c
        rho2 = 1 - sum(residual[i] ** 2 for i in range(n))
        eigenvalues = sorted(mp.eigsy(AtA)[0], reverse=False)  # s_i^2 ascending
        semi = [mp.sqrt(rho2) / mp.sqrt(e) for e in eigenvalues]  # descending
        # limits along e1: t a_i1 <= 1 - c_i and -t a_i1 <= 1 + c_i
        upper = min((1 - c[i]) / A[i, 0] for i in range(n) if A[i, 0] > 0)
        upper = min(upper, *((1 + c[i]) / -A[i, 0] for i in range(n) if A[i, 0] < 0))
        lower = max((1 - c[i]) / A[i, 0] for i in range(n) if A[i, 0] < 0)
        lower = max(lower, *((1 + c[i]) / -A[i, 0] for i in range(n) if A[i, 0] > 0))
        return (
            np.array([float(x) for x in h0]),
            np.array([float(x) for x in semi]),
            (float(lower), float(upper)),
        )


@pytest.mark.parametrize(("m", "n"), [(2, 3), (3, 7), (6, 7)])
@pytest.mark.parametrize("kappa", [1e2, 1e4, 1e6, 1e8])
def test_force_ellipsoid_and_limits_against_fifty_digits(m, n, kappa):
    rng = np.random.default_rng(int(np.log10(kappa)) + 10 * m)
    J = jacobian(m, n, kappa, seed=m + n)
    tau_max = rng.uniform(1.0, 5.0, n)
    tau_min = -tau_max * rng.uniform(0.7, 1.0, n)
    # gravity mostly balanced by forces (c in Im A), so the set is non-empty and bounded
    g = J.T @ rng.normal(size=m) * 0.05 + 0.01 * rng.normal(size=n)
    an = pe.analyze(pe.Dynamics(J, np.eye(n), g), tau_max, tau_min, capacity="force")
    h0, semi, (lower, upper) = reference(J, g, tau_max, tau_min)
    bound = 16 * (m + n) * EPS * kappa
    assert np.abs(an.center - h0).max() <= bound * np.abs(h0).max()
    E = an.ellipsoid("chiacchio")
    np.testing.assert_allclose(E.semi_axes, semi, rtol=bound, atol=0)
    lo, hi = an.polytope.limits(np.eye(m)[0])
    scale = max(abs(lower), abs(upper))
    assert abs(lo - lower) <= bound * scale and abs(hi - upper) <= bound * scale


def test_force_volume_where_qhull_finds_a_dupridge():
    """A regular 6x7 arm (cond J = 33) whose 91 whitened vertices make Qhull fail
    (QH6271 dupridge; found by the independent check): the volume by cones over the faces,
    checked against Lawrence's formula of the force sweep (another algorithm, its two
    evaluations agreeing to VOLUME_RTOL: ten times that here; Qhull in task coordinates
    fails on these vertices as well), and on regular cases."""
    from polyell.geometry.directions import sphere_directions
    from polyell.geometry.hpolytope import _face_volume
    from polyell.studies.batch import BatchOptions
    from polyell.studies.force_batch import VOLUME_RTOL, force_rows

    r = np.random.default_rng(173)
    n, m = 7, 6
    J = r.normal(size=(m, n))
    X = r.normal(size=(n, n))
    B, g = X @ X.T + n * np.eye(n), 0.1 * r.normal(size=n)
    tmax, tmin = r.uniform(1, 5, n), -r.uniform(0.5, 3, n)
    an = pe.analyze(pe.Dynamics(J, B, g), tmax, tmin, capacity="force")
    P = an.polytope
    batch = pe.Dynamics(J[None], B[None], g[None])
    columns, scalar = force_rows(batch, tmax, tmin, sphere_directions(8, m), BatchOptions())
    assert not scalar[0]
    assert P.volume == pytest.approx(columns["polytope_volume"][0], rel=10 * VOLUME_RTOL)
    assert 0 <= pe.compare(an, 64, samples=256, mvie=False, outer=False)["chiacchio"].coverage <= 1
    for seed in range(2):
        other = pe.analyze(
            pe.Dynamics(np.random.default_rng(seed).normal(size=(m, n)), B, g),
            tmax,
            tmin,
            capacity="force",
        ).polytope
        tight = other.facet_slacks(other.vertices) <= 1e-9 * other.extent
        assert _face_volume(other.vertices, tight, m) == pytest.approx(other.volume, rel=1e-12)
