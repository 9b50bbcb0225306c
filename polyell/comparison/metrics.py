"""The comparison metrics of one ellipsoid against one exact set (DESIGN.md section 2).

Each function takes an ellipsoid ``E`` lying in the affine set of the polytope ``P`` (as
both ellipsoid definitions and the MVIE do) and returns plain numbers: the batch of one of
the array scorer (:mod:`polyell.comparison.scores`), which ``compare`` and every sweep use.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.directional import STATISTICS, statistics
from polyell.comparison.scores import Fit, ellipsoid_of, fit, set_of, shares
from polyell.errors import InputError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.limits import DirectionalLimits
from polyell.geometry.polytope import Polytope
from polyell.inverse import AffineMap
from polyell.validation import as_floats, check_instance, check_integer

__all__ = [
    "DirectionErrors",
    "Overlap",
    "check_same_affine_set",
    "direction_errors",
    "enclosing_scale",
    "inscribed_scale",
    "inside_rtol",
    "overlap",
    "relative_error",
    "witness_torque_max",
]


#: How to mend a wrong DirectionalLimits argument.
_LIMITS = "pass the limits of an ellipsoid and of the polytope (E.limits(T), P.limits(T))."


def _check_sets(E: object, P: object) -> None:
    """Refuse an ellipsoid or a set of the wrong type, naming the argument."""
    check_instance("E", E, Ellipsoid, "pass an ellipsoid, e.g. analysis.ellipsoid('chiacchio').")
    check_instance("P", P, (Polytope, HPolytope), "pass the exact set, analysis.polytope.")


def _fit(E: Ellipsoid, P: Polytope | HPolytope) -> Fit:
    """:func:`~polyell.comparison.scores.fit` of one ellipsoid and one set, checked."""
    _check_sets(E, P)
    return fit(set_of(P), ellipsoid_of(E))


def inside_rtol(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Tolerance of "E inside P" and "E around P" (:attr:`~polyell.comparison.scores.Fit.rtol`).

    An ellipsoid with ``inscribed_scale >= 1 - inside_rtol`` is inside P, one with
    ``enclosing_scale <= 1 + inside_rtol`` around it.
    """
    return float(_fit(E, P).rtol[0])


def inscribed_scale(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Largest ``k`` with ``c + k (E - c)`` inside ``P`` (:func:`~polyell.comparison.scores.fit`).

    ``min_i (b_i - a_i . c) / |diag(s) U^T a_i|`` over the facets; at least 1 iff ``E`` is
    inside ``P``, negative if even its centre is outside.  A point ellipsoid gives
    ``inf`` (if its centre is in P) or ``-inf``.
    """
    return float(_fit(E, P).inscribed[0])


def enclosing_scale(E: Ellipsoid, P: Polytope | HPolytope) -> float:
    """Smallest ``k`` with ``P`` inside ``c + k (E - c)`` (:func:`~polyell.comparison.scores.fit`).

    The largest ``|diag(s)^-1 U^T (v - c)|`` over the vertices v of ``P``: at most 1 iff
    ``E`` contains ``P`` (the outer ellipsoid touches: exactly 1); ``inf`` for an unbounded
    ``P``.
    """
    return float(_fit(E, P).enclosing[0])


def check_same_affine_set(E: Ellipsoid, P: Polytope | HPolytope) -> None:
    """Raise unless ``E`` spans exactly the affine set of ``P``."""
    _check_sets(E, P)
    off = P.affine_set.distance(E.center + (E.axes * E.semi_axes).T)
    if E.rank != P.dim or P.affine_set.distance(E.center) > P.atol or np.any(off > P.atol):
        raise InputError(
            "ellipsoid",
            f"an ellipsoid spanning the polytope's {P.dim}-dimensional affine set",
            f"one of rank {E.rank} at distance {P.affine_set.distance(E.center):.3g}",
            "compare ellipsoids built from the same analysis as the polytope.",
        )


class Overlap(NamedTuple):
    r"""Volume shares of ``E`` and ``P``, exact or estimated.

    Attributes
    ----------
    coverage : float
        ``vol(E & P) / vol(P)``.
    overreach : float
        ``vol(E \ P) / vol(E)``.
    coverage_stderr, overreach_stderr : float
        Standard errors of the quasi-Monte-Carlo estimates; 0 when exact.
    """

    coverage: float
    overreach: float
    coverage_stderr: float
    overreach_stderr: float


def overlap(
    E: Ellipsoid,
    P: Polytope | HPolytope,
    *,
    samples: int = 2**13,
    replicates: int = 8,
    seed: int = 0,
) -> Overlap:
    r"""Coverage and overreach of ``E`` with respect to ``P`` (the scorer's ``shares``).

    Exact when ``E`` is inside ``P`` (coverage ``vol(E) / vol(P)``, overreach 0), when it
    contains ``P`` (coverage 1, overreach ``1 - vol(P) / vol(E)``) or when no two of its
    caps beyond P's facets meet; otherwise the union of the caps is estimated
    (:func:`~polyell.comparison.caps.cap_union_share`: Karp-Luby-Madras, randomized
    quasi-Monte Carlo) with the standard error of ``replicates`` independent replicates.

    Parameters
    ----------
    E : Ellipsoid
    P : Polytope or HPolytope
    samples : int, optional
        Sampling budget: every pair of caps that meet gets ``samples //``
        :data:`~polyell.comparison.caps.CAP_SAMPLES_RATIO` heights per replicate (16 at the
        default 2^13), and where three caps meet ``samples`` directions per replicate.
    replicates : int, optional
        Independent scramblings (at least 2, for the standard error).
    seed : int, optional
        Seed of the scramblings: the estimate is reproducible, and a row of the batched
        sweep gets the same numbers.
    """
    _check_sets(E, P)
    samples = check_integer("samples", samples, 1, 2**22)
    replicates = check_integer("replicates", replicates, 2, 2**10)
    seed = check_integer("seed", seed, 0, 2**63 - 1)
    sets, ellipsoid = set_of(P), ellipsoid_of(E)
    result = shares(
        sets, ellipsoid, fit(sets, ellipsoid), samples=samples, seed=seed, replicates=replicates
    )
    return Overlap(*(float(values[0]) for values in result))


class DirectionErrors(NamedTuple):
    """Relative errors ``(hi_E - hi_P) / |hi_P|`` of an ellipsoid's directional limits.

    Over directions where both intervals are non-empty and ``hi_P != 0``.

    Attributes
    ----------
    mean, max, rms : float
        Mean, maximum and root-mean-square of the absolute relative error.
    bias : float
        Mean signed relative error (> 0: the ellipsoid promises too much).
    mismatch : int
        Directions where exactly one of the two intervals is empty.
    used : int
        Directions that entered the statistics.
    """

    mean: float
    max: float
    rms: float
    bias: float
    mismatch: int
    used: int


def relative_error(
    ellipsoid: NDArray[np.float64], polytope: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``(e - p) / |p|`` of directional limits, elementwise; NaN where either is NaN or p = 0.

    Where the polytope's limit is infinite (an unbounded set, along a ray) and the
    ellipsoid's finite, the limit of that ratio, ``-sign(p)``: -1 for an upper limit (the
    ellipsoid states none of it).

    Parameters
    ----------
    ellipsoid, polytope : ndarray, shape (k,)
        The same end (``hi`` or ``lo``) of the intervals of an ellipsoid and of the polytope
        [m/s^2 or rad/s^2]; NaN where the interval is empty.

    Returns
    -------
    ndarray, shape (k,)
        Dimensionless.  For upper limits > 0 means the ellipsoid promises too much; for
        lower limits < 0 does (it reaches further down).
    """
    e, p = as_floats("ellipsoid", ellipsoid), as_floats("polytope", polytope)
    used = ~np.isnan(e) & ~np.isnan(p) & (p != 0)
    error = np.full(np.broadcast_shapes(e.shape, p.shape), np.nan)
    infinite = used & np.isinf(p) & np.isfinite(e)
    finite = used & np.isfinite(p)
    error[finite] = (e[finite] - p[finite]) / np.abs(p[finite])
    error[infinite] = -np.sign(p[infinite])
    return error


def direction_errors(ellipsoid: DirectionalLimits, polytope: DirectionalLimits) -> DirectionErrors:
    """Statistics of the upper directional limits of an ellipsoid against the polytope's.

    :func:`~polyell.comparison.directional.statistics` of one configuration.
    """
    check_instance("ellipsoid", ellipsoid, DirectionalLimits, _LIMITS)
    check_instance("polytope", polytope, DirectionalLimits, _LIMITS)
    hi_e, hi_p = (np.atleast_1d(limits.hi).reshape(1, -1) for limits in (ellipsoid, polytope))
    if hi_e.shape != hi_p.shape:
        raise InputError(
            "ellipsoid",
            f"limits on the polytope's {hi_p.size} directions",
            f"{hi_e.size}",
            "compute both on the same directions T, e.g. E.limits(T) and P.limits(T)",
        )
    feasible_e, feasible_p = (
        np.atleast_1d(limits.feasible).reshape(1, -1) for limits in (ellipsoid, polytope)
    )
    stats = statistics(hi_e, feasible_e, hi_p, feasible_p)
    mean, largest, rms, bias = (float(stats[name][0]) for name in STATISTICS[:4])
    mismatch, used = (int(stats[name][0]) for name in STATISTICS[4:])
    return DirectionErrors(mean, largest, rms, bias, mismatch, used)


def witness_torque_max(E: Ellipsoid, torques: AffineMap) -> float:
    """Largest ``|tau_n|_inf`` over ``E`` under an affine inverse map, exactly.

    :func:`~polyell.comparison.scores.witness` of one ellipsoid.
    """
    check_instance("E", E, Ellipsoid, "pass an ellipsoid.")
    return float(ellipsoid_of(E, torques.matrix, torques(E.center)).witness[0])
