"""Deterministic, near-uniform sets of unit directions."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.geometry.subspace import AffineSubspace
from polyell.validation import MAX_DIRECTIONS, check_instance, check_integer

__all__ = ["default_direction_count", "directions_in", "sphere_directions"]

#: Largest dimension of a direction set (Sobol' points beyond it are not balanced).
MAX_DIMENSION = 1000

_GOLDEN_ANGLE = np.pi * (3.0 - np.sqrt(5.0))


def default_direction_count(r: int) -> int:
    """Default size of a direction set on the unit sphere of R^r: 2, 360, 256, then 2,000.

    Chosen from the convergence of the direction statistics (``docs/performance.md``,
    section (i)): on random 3x7 arms and on the Panda, the mean, RMS and bias of the
    direction errors at 256 Fibonacci directions differ from their values at 16,384 by about
    1e-4 (median), 5e-4 (95th percentile) and 2e-3 at worst, at about a third of the time of
    1,000.  The maximum is a sampled supremum: it converges slowly at any
    count (a few per cent below at 256, about one per cent at 1,000): pass more directions
    when it matters.
    """
    r = check_integer("r", r, 0, MAX_DIMENSION)
    return {0: 0, 1: 2, 2: 360, 3: 256}.get(r, 2000)


def sphere_directions(k: int, r: int) -> NDArray[np.float64]:
    """``k`` unit vectors spread near-uniformly on the unit sphere of R^r.

    Evenly spaced angles in 2-D (starting at +x), a Fibonacci lattice in 3-D, a
    fixed-seed scrambled Sobol' set pushed to the sphere in higher dimensions.  In 1-D the
    only directions are +1 and -1, whatever ``k``.

    Parameters
    ----------
    k : int
        Number of directions (at least 1).
    r : int
        Dimension.

    Returns
    -------
    ndarray, shape (k, r)
        Identical on every call.
    """
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or not 1 <= k <= MAX_DIRECTIONS:
        raise InputError(
            "directions",
            f"a positive number of directions, at most {MAX_DIRECTIONS:,}",
            repr(k),
            f"pass an int from 1 to {MAX_DIRECTIONS:,}, e.g. 360",
        )
    r = check_integer("r", r, 0, MAX_DIMENSION)
    if r == 0:
        return np.zeros((0, 0))
    if r == 1:
        return np.array([[1.0], [-1.0]])
    if r == 2:
        angles = 2.0 * np.pi * np.arange(k) / k
        return np.column_stack([np.cos(angles), np.sin(angles)])
    if r == 3:
        i = np.arange(k)
        z = 1.0 - (2.0 * i + 1.0) / k
        radius = np.sqrt(1.0 - z**2)
        return np.column_stack(
            [radius * np.cos(i * _GOLDEN_ANGLE), radius * np.sin(i * _GOLDEN_ANGLE), z]
        )
    from scipy.stats import norm, qmc  # here: scipy.stats takes half a second to import

    # The first k points of the sequence, drawn as a power of two (the size at which
    # scipy's Sobol' generator keeps its balance and issues no warning).
    exponent = max(0, int(k - 1).bit_length())
    points = qmc.Sobol(d=r, scramble=True, seed=0).random_base2(exponent)[:k]
    gaussian = norm.ppf(np.clip(points, 1e-12, 1 - 1e-12))
    return gaussian / np.linalg.norm(gaussian, axis=1, keepdims=True)


def directions_in(affine_set: AffineSubspace, k: int | None = None) -> NDArray[np.float64]:
    """Near-uniform unit directions of the task space that lie in an affine set.

    At a singular configuration only these directions see a non-trivial interval; any
    other line crosses the set in one point.

    Parameters
    ----------
    affine_set : AffineSubspace
        The set (its dimension r decides the sphere).
    k : int, optional
        Number of directions; default :func:`default_direction_count` of r.

    Returns
    -------
    ndarray, shape (k, m)
    """
    check_instance("affine_set", affine_set, AffineSubspace, "pass a set's affine_set.")
    r = affine_set.dim
    count = default_direction_count(r) if k is None else k
    if r == 0:  # a point has no directions: k checked all the same (0 allowed)
        check_integer("directions", count, 0, MAX_DIRECTIONS)
        return np.zeros((0, affine_set.ambient_dim))
    return sphere_directions(count, r) @ affine_set.basis.T
