"""Shared reference problems with known answers, and seeded random problems.

Tolerances used across the suite:

* ``PRINTED``: a paper value printed with d decimals must match to half a unit in the
  last printed place.
* ``RTOL_EXACT = 1e-9``: two closed forms of the same quantity.
* ``RTOL_LP = 1e-8``: closed form against an interior-point LP (Clarabel at 1e-12).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

import polyell as pe
from polyell.comparison.scores import ROUNDING_FACTOR, ellipsoid_of, fit, set_of

RTOL_EXACT = 1e-9
RTOL_LP = 1e-8

#: The planar arm of Chiacchio (2000), section 6.
PAPER_ARM = pe.PlanarArm(lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6], com=[0.5, 0.4, 0.25])
PAPER_TAU_MAX = np.array([100.0, 30.0, 4.0])
PAPER_Q_REDUNDANT = np.array([np.pi / 2, -np.pi / 2, -np.pi / 2])
PAPER_Q_SINGULAR = np.array([np.pi / 6, 0.0, 0.0])


def paper_analysis(q: np.ndarray) -> pe.Analysis:
    return pe.analyze(PAPER_ARM.dynamics(q), tau_max=PAPER_TAU_MAX)


def assert_printed(actual, printed: str, scale: float = 1.0) -> None:
    """Assert ``actual / scale`` matches the whitespace-separated numbers in ``printed``.

    Each printed number with d decimals must agree to 0.5e-d (rounding of the last digit).
    """
    values = np.ravel(np.asarray(actual, dtype=float)) / scale
    tokens = printed.split()
    assert len(tokens) == values.size, f"{len(tokens)} printed numbers, {values.size} computed"
    for token, value in zip(tokens, values, strict=True):
        decimals = len(token.split(".")[1]) if "." in token else 0
        tolerance = 0.5 * 10.0**-decimals + 1e-12
        assert abs(value - float(token)) <= tolerance, f"computed {value!r}, printed {token}"


def random_spd(rng: np.random.Generator, n: int, condition: float = 100.0) -> np.ndarray:
    """A random symmetric positive-definite matrix with a given condition number."""
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    eigenvalues = np.geomspace(1.0, condition, n) * rng.uniform(0.1, 2.0)
    return (Q * eigenvalues) @ Q.T


def random_problem(
    seed: int,
    m: int,
    n: int,
    rank: int | None = None,
    asymmetric: bool = False,
    gravity: float = 1.0,
    capacity: str = "acceleration",
) -> pe.Analysis:
    """A random analysis: Jacobian of the given rank, SPD inertia, gravity, limits.

    ``gravity`` scales the gravity torques relative to the torque limits; above about 1
    the origin tends to leave the polytope, so that some lines miss it.  The velocity
    capacity takes the same numbers as joint velocity limits [rad/s].
    """
    rng = np.random.default_rng(seed)
    rank = min(m, n) if rank is None else rank
    # Singular values in [0.3, 3]: generic directions, a condition number of at most 10, so
    # that exactness tests compare formulas rather than rounding (issue: ill-conditioning).
    U = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :rank]
    V = np.linalg.qr(rng.normal(size=(n, n)))[0][:, :rank]
    J = (U * rng.uniform(0.3, 3.0, rank)) @ V.T
    B = random_spd(rng, n)
    tau_max = rng.uniform(1.0, 10.0, n)
    tau_min = tau_max - rng.uniform(0.5, 2.0, n) * tau_max if asymmetric else None
    if asymmetric and capacity == "force":  # mild asymmetry about 0, as real drives have
        spread = (tau_max - tau_min) / tau_max  # the same draw, in [0.5, 2]
        tau_min = -tau_max * (0.6 + 0.4 * (spread - 0.5) / 1.5)
    g = gravity * rng.normal(size=n) * tau_max
    if capacity == "velocity":
        return pe.analyze(pe.Kinematics(J), capacity=capacity, qd_max=tau_max, qd_min=tau_min)
    return pe.analyze(pe.Dynamics(J, B, g), tau_max, tau_min, capacity=capacity)


def random_arm(seed: int, n: int) -> tuple[pe.PlanarArm, np.ndarray, np.random.Generator]:
    """A random planar arm (real, positive inertias), a random posture, and the generator."""
    rng = np.random.default_rng(seed)
    lengths = rng.uniform(0.2, 1.5, n)
    arm = pe.PlanarArm(
        lengths=lengths,
        masses=rng.uniform(0.5, 10.0, n),
        com=lengths * rng.uniform(0.1, 0.9, n),
        inertia=rng.uniform(0.01, 1.0, n),
    )
    return arm, rng.uniform(-np.pi, np.pi, n), rng


def random_arm_analysis(seed: int, n: int, singular: bool = False) -> pe.Analysis:
    """A random planar arm at a random, or a stretched singular, posture."""
    arm, q, rng = random_arm(seed, n)
    if singular:
        q[1:] = rng.choice([0.0, np.pi], size=n - 1)
    return pe.analyze(arm.dynamics(q), tau_max=rng.uniform(1.0, 100.0, n))


def random_directions(seed: int, k: int, m: int) -> np.ndarray:
    T = np.random.default_rng(seed).normal(size=(k, m))
    return T / np.linalg.norm(T, axis=1, keepdims=True)


def planar_urdf(arm: pe.PlanarArm, joint_type: str = "revolute") -> str:
    """A URDF of a planar arm: links along x, joints about z, a 'tip' frame at the end."""
    parts = ['<robot name="planar">', '<link name="base"/>']
    parent = "base"
    offset = 0.0
    for i, (length, mass, com, inertia) in enumerate(
        zip(arm.lengths, arm.masses, arm.com, arm.inertia, strict=True)
    ):
        parts += [
            f'<link name="link{i}"><inertial><origin xyz="{com} 0 0"/><mass value="{mass}"/>'
            f'<inertia ixx="1e-3" iyy="1e-3" izz="{inertia}" ixy="0" ixz="0" iyz="0"/>'
            "</inertial></link>",
            f'<joint name="joint{i}" type="{joint_type}"><parent link="{parent}"/>'
            f'<child link="link{i}"/><origin xyz="{offset} 0 0"/><axis xyz="0 0 1"/>'
            '<limit effort="50" velocity="1" lower="-10" upper="10"/></joint>',
        ]
        parent, offset = f"link{i}", length
    parts += [
        '<link name="tip"/>',
        f'<joint name="tip_joint" type="fixed"><parent link="{parent}"/><child link="tip"/>'
        f'<origin xyz="{offset} 0 0"/></joint>',
        "</robot>",
    ]
    return "\n".join(parts)


# ---------------------------------------------------------------------------------------
# The uniform quasi-Monte-Carlo estimate of a share of E inside P that cap_union_share
# replaced (8 replicates of 2^13 scrambled Sobol' points mapped into E): a reference.


def uniform_in_ball(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Map points of (0, 1)^(r+1) to uniform points of the unit r-ball."""
    from scipy.stats import norm  # here: scipy.stats takes half a second to import

    r = points.shape[1] - 1
    gaussian = norm.ppf(np.clip(points[:, :r], 1e-12, 1 - 1e-12))
    directions = gaussian / np.linalg.norm(gaussian, axis=1, keepdims=True)
    return directions * points[:, r:] ** (1.0 / r)


def ball_points(
    r: int, samples: int, replicates: int, seed: int
) -> tuple[NDArray[np.float64], ...]:
    """The quasi-Monte-Carlo points of :func:`overlap`: uniform in the unit r-ball.

    ``replicates`` independently scrambled Sobol' sets of ``samples`` points, the first
    ``samples`` of a power-of-two draw (the size at which scipy's generator keeps its
    balance and issues no warning), from ``seed``.  They depend on nothing else: a sweep
    of many configurations draws them once (:func:`sorted_ball_points` keeps them).
    """
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    exponent = max(0, int(samples - 1).bit_length())
    sets = []
    for _ in range(replicates):
        sobol = qmc.Sobol(d=r + 1, scramble=True, seed=rng)
        ball = uniform_in_ball(sobol.random_base2(exponent)[:samples])
        ball.flags.writeable = False
        sets.append(ball)
    return tuple(sets)


@lru_cache(maxsize=8)
def sorted_ball_points(
    r: int, samples: int, replicates: int, seed: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Every replicate's points of :func:`ball_points` together, sorted by radius.

    Only how many points of each replicate fall inside P enters an estimate, not their
    order: sorted, the points of the ball of radius t (all inside P when ``t E`` is) are a
    prefix, and one product tests the rest of every replicate at once.

    Returns
    -------
    points : ndarray, shape (replicates * samples, r)
    radii : ndarray, shape (replicates * samples,)
        Their norms, ascending.
    replicate : ndarray of int, shape (replicates * samples,)
        The replicate each point belongs to.
    """
    sets = ball_points(r, samples, replicates, seed)
    points = np.concatenate(sets)
    radii = np.linalg.norm(points, axis=1)
    order = np.argsort(radii, kind="stable")
    replicate = np.repeat(np.arange(replicates), samples)[order]
    points, radii = points[order], radii[order]
    for array in (points, radii, replicate):
        array.flags.writeable = False
    return points, radii, replicate


def qmc_count_inside(
    axes: NDArray[np.float64],
    semi_axes: NDArray[np.float64],
    A: NDArray[np.float64],
    slack: NDArray[np.float64],
    samples: int,
    replicates: int,
    seed: int,
) -> NDArray[np.int64]:
    """How many quasi-Monte-Carlo points of each replicate, mapped into E, satisfy A x <= slack.

    ``E`` is ``{c + U diag(s) u : |u| <= 1}`` with ``axes`` U (m, r) and ``semi_axes`` s
    (r,); ``slack`` (F,) holds the facets' offsets about its centre c.

    The same counts as testing every point against every facet (``x = U diag(s) u``,
    ``all(x @ A.T <= slack)``), with the work only where the answer can be no: a facet
    whose reach over E (``|diag(s) U^T a_i|``) stays below its slack by more than the
    rounding of ``a_i . x`` (``ROUNDING_FACTOR (m + r + 2) eps s_max`` for unit normals)
    holds for every point of E, and a point of radius at most ``t`` with ``t reach_i <=
    slack_i`` minus that rounding for every facet (the scaled copy ``t E`` inside P) holds
    for all.  The rest are tested as before.
    """
    rank = len(semi_axes)
    reach = np.linalg.norm((A @ axes) * semi_axes, axis=1)
    terms = A.shape[1] + rank + 2
    rounding = ROUNDING_FACTOR * terms * float(np.finfo(float).eps) * float(np.max(semi_axes))
    rounding *= max(1.0, float(np.linalg.norm(A, axis=1).max(initial=0.0)))
    margin = slack - rounding
    crossing = ~(reach < margin)  # NaN-safe: test a facet unless it surely holds
    with np.errstate(divide="ignore", invalid="ignore"):
        scales = np.where(reach > 0, margin / reach, np.where(margin >= 0, np.inf, -np.inf))
    radius = float(np.min(scales, initial=np.inf)) * (1.0 - 1e-12)
    points, radii, replicate = sorted_ball_points(rank, samples, replicates, seed)
    start = int(np.searchsorted(radii, radius, side="right")) if radius > 0 else 0
    offsets = (points[start:] * semi_axes) @ axes.T  # about E's centre
    # each facet only on the points beyond its own radius (the copy of E it holds)
    holds = np.where(scales > 0.0, scales, 0.0) * (1.0 - 1e-12)  # NaN: test every point
    firsts = np.searchsorted(radii, holds, side="right")
    outside = np.zeros(len(offsets), dtype=bool)
    for i in np.flatnonzero(crossing):
        tail = outside[firsts[i] - start :]
        tail |= offsets[firsts[i] - start :] @ A[i] > slack[i]
    missed = np.bincount(replicate[start:][outside], minlength=replicates)
    return samples - missed


def slacks(E, P):
    """``b_i - a_i . c`` of P's facets about E's centre (the scorer's own)."""
    return fit(set_of(P), ellipsoid_of(E)).slacks[0]
