"""Vertex-to-halfspace conversion with pycddlib (cdd >= 3), the independent reference.

The conversion runs in the coordinates of the polytope's affine set, where the
polytope is full-dimensional, so that floating-point cdd never has to discover an
implicit equality from rounded data.
"""

from __future__ import annotations

import cdd
import numpy as np
from numpy.typing import NDArray

__all__ = ["halfspaces_from_vertices"]


def halfspaces_from_vertices(
    vertices: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Irredundant H-representation ``{y : A y <= b}`` of the convex hull of points.

    Parameters
    ----------
    vertices : ndarray, shape (V, r)
        Points spanning R^r (the hull must be full-dimensional).

    Returns
    -------
    A : ndarray, shape (F, r)
        Facet normals, scaled to unit length.
    b : ndarray, shape (F,)
        Offsets.
    """
    generators = np.hstack([np.ones((vertices.shape[0], 1)), vertices])
    matrix = cdd.matrix_from_array(generators.tolist(), rep_type=cdd.RepType.GENERATOR)
    inequalities = cdd.copy_inequalities(cdd.polyhedron_from_matrix(matrix))
    rows = np.array(inequalities.array, dtype=float).reshape(-1, vertices.shape[1] + 1)
    # cdd writes b - A y >= 0 as the row [b, -A].
    A, b = -rows[:, 1:], rows[:, 0]
    scale = np.linalg.norm(A, axis=1)
    return A / scale[:, None], b / scale
