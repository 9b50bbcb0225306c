r"""The sets of a block of full-rank configurations, batched.

Facets, vertices, the MVIE, the outer ellipsoid and user-defined candidates.

Every function takes arrays with a leading batch axis K (configurations of one block) and
computes what :class:`~polyell.geometry.polytope.Polytope`,
:func:`~polyell.geometry.mvie.max_volume_inscribed_ellipsoid`,
:func:`~polyell.geometry.outer.min_volume_enclosing_ellipsoid` and
:meth:`~polyell.comparison.candidates.Candidate.ellipsoid` compute for one.  An ellipsoid
is returned as ``(axes (K, m, m), semi_axes (K, m), witness (K,))``, centred at ``xg``
unless said otherwise; NaN semi-axes mark rows whose solver did not certify an optimum.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from polyell.comparison.candidates import Candidate
from polyell.comparison.scores import witness
from polyell.geometry.ellipsoid import canonical_axes
from polyell.geometry.logdet import centred_mvee_batch
from polyell.geometry.mvie import MVIE_GAP
from polyell.geometry.zonotope import (  # the batched zonotopes (a Polytope's: a batch of one)
    BlockFacets,
    facets,
    vertex_count,
    vertex_signs,
)

__all__ = [
    "BlockFacets",
    "candidate_ellipsoid",
    "facets",
    "log_det_ellipsoid",
    "vertex_count",
    "vertex_signs",
]

Array = NDArray[np.float64]
Ellipsoids = tuple[Array, Array, Array]


def log_det_ellipsoid(
    U: Array, s: Array, V1t: Array, points: Array | None, *, enclosing: bool
) -> Ellipsoids:
    """The MVIE (``enclosing=False``) or the outer ellipsoid of full-rank blocks, batched.

    In whitened coordinates (P the zonotope of the rows of V1^T) the shape X of
    :func:`~polyell.geometry.logdet.centred_mvee_batch` of ``points`` (K, N, m) -- the
    scaled facet normals for the MVIE, the vertices for the outer ellipsoid -- gives
    ``E = {xg + U Sigma X^(+-1/2) u}``.  n = m: X = I (the MVIE is the new ellipsoid, the
    outer one that scaled by sqrt(m)).

    Returns
    -------
    axes, semi_axes, witness
        The witness is the largest row norm of ``V1 X^(+-1/2)``: the torque witness under
        the minimum-torque map (eq. 33).
    """
    K, m = s.shape
    if points is None:  # a parallelotope
        root = np.broadcast_to(np.eye(m) * (np.sqrt(m) if enclosing else 1.0), (K, m, m))
        certified = np.ones(K, dtype=bool)
    else:
        shapes, gaps, _ = centred_mvee_batch(points, gap=MVIE_GAP)
        certified = gaps <= MVIE_GAP
        shapes = np.where(certified[:, None, None], shapes, np.eye(m))
        eigenvalues, eigenvectors = np.linalg.eigh(shapes)
        power = -0.5 if enclosing else 0.5
        root = (eigenvectors * eigenvalues[:, None, :] ** power) @ np.swapaxes(eigenvectors, 1, 2)
    W, semi, _ = np.linalg.svd(s[:, :, None] * root)
    witness = np.max(np.linalg.norm(np.swapaxes(V1t, -1, -2) @ root, axis=-1), axis=-1)
    semi = np.where(certified[:, None], semi, np.nan)
    return U[:, :, :m] @ W, semi, np.where(certified, witness, np.nan)


def candidate_ellipsoid(
    candidate: Candidate, M: Array, xg: Array, U: Array, s: Array, V1t: Array
) -> tuple[Array, Array, Array, Array]:
    """A candidate at every (full-rank) configuration of a block.

    Returns
    -------
    axes, semi_axes, witness, center
        ``center`` (K, m): ``xg``, or a core-defined candidate's own centre.  The witness
        uses the minimum-torque map ``tau_n = M^+ (x - xg)``.
    """
    K, m = s.shape
    if candidate.weighting is not None:
        axes, semi, _ = np.linalg.svd(M @ candidate.root_inverse, full_matrices=False)
        center = xg
    else:
        assert candidate.core is not None
        eigenvalues, eigenvectors = np.linalg.eigh(candidate.core)
        axes = np.broadcast_to(eigenvectors, (K, m, m))
        semi = np.broadcast_to(1.0 / np.sqrt(eigenvalues), (K, m))
        center = xg if candidate.center is None else np.broadcast_to(candidate.center, (K, m))
    axes, semi = canonical_axes(np.array(axes), np.array(semi))  # as Ellipsoid: the same points
    # M^+ = V1 Sigma^-1 U^T: at the centre, and the reach along the axes.
    pinv_t = np.swapaxes(V1t, 1, 2) / s[:, None, :] @ np.swapaxes(U, 1, 2)  # (K, n, m)
    at_center = np.einsum("knm,km->kn", pinv_t, center - xg)
    return np.array(axes), np.array(semi), witness(pinv_t, at_center, axes, semi), np.array(center)
