"""High-precision references (mpmath, 80 digits) for the planar arm, independent of polyell.

The dynamics are written again from first principles (link centres of mass, rod inertias
``m l^2 / 12``, gravity along -y), and every quantity is evaluated in 80-digit arithmetic
from the same double-precision joint angles.  Near a singular configuration a double
computation can only be as good as its data: a relative error of order
``eps * sigma_max / sigma_min`` (the condition number of M), which the tests allow with a
stated factor; anything that squares the condition number fails them.
"""

from __future__ import annotations

from collections.abc import Sequence

import mpmath as mp

import polyell as pe

DIGITS = 80


def _point_jacobian(weights: Sequence, du: Sequence) -> mp.matrix:
    """Jacobian (2, n) of the point ``sum_j w_j u(theta_j)`` with ``u' = du``."""
    n = len(du)
    return mp.matrix(
        [[sum(weights[j] * du[j][a] for j in range(k, n)) for k in range(n)] for a in range(2)]
    )


def planar_model(arm: pe.PlanarArm, q: Sequence[float], tau_max: Sequence[float]):
    """``M`` (eq. 14), ``xg`` (eq. 8), ``J``, ``B`` of a planar arm in 80-digit arithmetic."""
    with mp.workdps(DIGITS):
        n = arm.n
        angles = [mp.mpf(float(x)) for x in q]
        theta = [sum(angles[: i + 1]) for i in range(n)]
        du = [(-mp.sin(t), mp.cos(t)) for t in theta]
        lengths = [mp.mpf(float(x)) for x in arm.lengths]
        J = _point_jacobian(lengths, du)
        B = mp.zeros(n, n)
        g = mp.zeros(n, 1)
        for i in range(n):
            weights = [lengths[j] if j < i else 0 for j in range(n)]
            weights[i] = mp.mpf(float(arm.com[i]))
            Jc = _point_jacobian(weights, du)
            mass = mp.mpf(float(arm.masses[i]))
            rotation = mp.matrix([[1 if k <= i else 0 for k in range(n)]])
            B += mass * Jc.T * Jc + mp.mpf(float(arm.inertia[i])) * rotation.T * rotation
            g += mp.mpf(float(arm.gravity)) * mass * Jc[1, :].T
        J_Binv = J * B**-1
        M = J_Binv * mp.diag([mp.mpf(float(t)) for t in tau_max])
        return M, -(J_Binv * g), J, B


def ellipsoid_limits(core: mp.matrix, center: mp.matrix, t: Sequence[float]):
    """Eq. (23)-(24) in 80 digits: the roots of ``(a t - c)^T N (a t - c) = 1``."""
    with mp.workdps(DIGITS):
        t = mp.matrix([mp.mpf(float(x)) for x in t])
        alpha = (t.T * core * t)[0]
        beta = -(t.T * core * center)[0]
        gamma = (center.T * core * center)[0] - 1
        root = mp.sqrt(beta**2 - alpha * gamma)
        return (-beta - root) / alpha, (-beta + root) / alpha


def chiacchio_core(M: mp.matrix) -> mp.matrix:
    """``(M M^T)^-1`` (eq. 32 at full rank)."""
    with mp.workdps(DIGITS):
        return (M * M.T) ** -1


def yoshikawa_core(J: mp.matrix, B: mp.matrix, tau_max: Sequence[float]) -> mp.matrix:
    """``J^+T B L^-2 B J^+`` (eq. 27) with ``J^+ = J^T (J J^T)^-1``."""
    with mp.workdps(DIGITS):
        J_pinv = J.T * (J * J.T) ** -1
        L_inv = mp.diag([1 / mp.mpf(float(t)) for t in tau_max])
        F = L_inv * B * J_pinv
        return F.T * F


def planar_polytope_limits(M: mp.matrix, center: mp.matrix, t: Sequence[float]):
    """The polytope's interval along t in 80 digits, from the zonotope's facets in 2-D.

    Each generator ``g_j`` gives the facet pair with normals ``+-perp(g_j)`` and offsets
    ``+-a . c + sum_k |a . g_k|``.
    """
    with mp.workdps(DIGITS):
        t = mp.matrix([mp.mpf(float(x)) for x in t])
        lo, hi = -mp.inf, mp.inf
        for j in range(M.cols):
            normal = mp.matrix([-M[1, j], M[0, j]])
            normal /= mp.norm(normal)
            for a in (normal, -normal):
                offset = sum(abs((a.T * M[:, k])[0]) for k in range(M.cols)) + (a.T * center)[0]
                slope = (a.T * t)[0]
                if slope > 0:
                    hi = min(hi, offset / slope)
                elif slope < 0:
                    lo = max(lo, offset / slope)
        return lo, hi


def zonotope_facets(M, digits: int = 50) -> list[tuple[mp.matrix, mp.mpf]]:
    """Every facet pair ``(a, h)`` of ``{M u : |u|_inf <= 1}`` (M of full row rank r), one of
    each ``+-a``, in ``digits``-digit arithmetic from the double entries of ``M``.

    The zonotope formula on the data itself, no whitening: each (r - 1)-subset of columns
    gives the normal ``a`` orthogonal to them (the cofactors of the r x (r - 1) block by
    Laplace expansion), kept when non-zero, unit length, offset ``h = sum_i |a . g_i|``.
    For data in general position (seeded random matrices) no two subsets share a plane.
    """
    from itertools import combinations

    r, n = len(M), len(M[0])
    with mp.workdps(digits):
        G = mp.matrix([[mp.mpf(float(x)) for x in row] for row in M])
        scale = max(mp.norm(G[:, j]) for j in range(n)) ** (r - 1)
        facets = []
        for subset in combinations(range(n), r - 1):
            a = mp.matrix(r, 1)
            for k in range(r):
                rows = [i for i in range(r) if i != k]
                minor = mp.matrix([[G[i, j] for j in subset] for i in rows]) if rows else None
                a[k] = (-1) ** k * (mp.det(minor) if r > 1 else 1)
            length = mp.norm(a)
            if length <= mp.mpf(10) ** (-digits // 2) * scale:
                continue  # dependent columns (not met by data in general position)
            a /= length
            h = sum(abs(sum(a[i] * G[i, j] for i in range(r))) for j in range(n))
            facets.append((a, h))
        return facets


def support(M, a, digits: int = 50) -> mp.mpf:
    """``sum_i |a . g_i|`` in ``digits`` digits for a double vector ``a`` (r,)."""
    with mp.workdps(digits):
        return sum(
            abs(sum(mp.mpf(float(a[i])) * mp.mpf(float(M[i][j])) for i in range(len(M))))
            for j in range(len(M[0]))
        )


def halfspace_limits(facets, center, t, digits: int = 50):
    """``{x : |a . (x - c)| <= h}`` for every pair, along the line ``{s t}``: ``(lo, hi)``."""
    with mp.workdps(digits):
        c = [mp.mpf(float(x)) for x in center]
        t = [mp.mpf(float(x)) for x in t]
        lo, hi = -mp.inf, mp.inf
        for a, h in facets:
            slope = sum(a[i] * t[i] for i in range(len(t)))
            mid = sum(a[i] * c[i] for i in range(len(t)))
            if slope == 0:
                if abs(mid) > h:
                    return None
                continue
            ends = sorted([(mid - h) / slope, (mid + h) / slope])
            lo, hi = max(lo, ends[0]), min(hi, ends[1])
        return (lo, hi) if lo <= hi else None
