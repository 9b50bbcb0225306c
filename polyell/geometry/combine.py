r"""Two arms on one object: the sum and the intersection of two sets of the same task space.

Two arms holding one object in the same task frame exert the sum of their forces, so the
forces they can exert together form the Minkowski sum
:math:`P_1 \oplus P_2 = \{h_1 + h_2\}` (its vertices are among the sums of vertices);
the forces each of them can exert alone form the intersection :math:`P_1 \cap P_2` (the
two sets of half-spaces together).  Both are :class:`~polyell.HPolytope` objects that
:func:`~polyell.comparison.metrics.inscribed_scale` and the other metrics score like any
set.
"""

from __future__ import annotations

import numpy as np

from polyell.errors import InputError
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.polytope import Polytope

__all__ = ["intersection", "minkowski_sum"]

Set = Polytope | HPolytope


def _check_pair(P1: object, P2: object) -> tuple[Set, Set]:
    for name, P in (("P1", P1), ("P2", P2)):
        if not isinstance(P, Polytope | HPolytope):
            raise InputError(name, "a pe.Polytope or a pe.HPolytope", type(P).__name__)
    assert isinstance(P1, Polytope | HPolytope) and isinstance(P2, Polytope | HPolytope)
    if P1.ambient_dim != P2.ambient_dim:
        raise InputError(
            "P2",
            f"a set of the same {P1.ambient_dim}-dimensional task space as P1",
            f"a set of a {P2.ambient_dim}-dimensional one",
            "two polytopes of different task spaces cannot be added or intersected: "
            "express both in the same task frame and rows.",
        )
    return P1, P2


def _halfspaces(P: Set) -> tuple[np.ndarray, np.ndarray]:
    """All of P's constraints as half-spaces (an equality as two)."""
    if isinstance(P, HPolytope) and P.is_empty:
        m = P.ambient_dim
        return np.zeros((1, m)), np.array([-1.0])  # 0 <= -1: nothing satisfies it
    A_eq, b_eq = P.A_eq, P.b_eq
    return np.vstack([P.A, A_eq, -A_eq]), np.concatenate([P.b, b_eq, -b_eq])


def minkowski_sum(P1: Set, P2: Set) -> HPolytope:
    """The set ``{x1 + x2 : x1 in P1, x2 in P2}`` (forces of two arms add).

    Parameters
    ----------
    P1, P2 : Polytope or HPolytope
        Bounded sets of the same task space.

    Returns
    -------
    HPolytope
        Empty if either is empty.

    Raises
    ------
    InputError
        For sets of different task spaces, or an unbounded or lower-dimensional sum (give
        nonsingular postures).
    """
    P1, P2 = _check_pair(P1, P2)
    for name, P in (("P1", P1), ("P2", P2)):
        if isinstance(P, HPolytope) and not P.is_empty and not P.is_bounded:
            raise InputError(
                name,
                "a bounded set",
                f"a set unbounded along {len(P.rays)} ray(s)",
                "the sum is then unbounded too: add the force polytopes of nonsingular postures.",
            )
    if any(isinstance(P, HPolytope) and P.is_empty for P in (P1, P2)):
        return HPolytope(*_halfspaces(P1 if isinstance(P1, HPolytope) and P1.is_empty else P2))
    sums = (P1.vertices[:, None, :] + P2.vertices[None, :, :]).reshape(-1, P1.ambient_dim)
    centered = sums - sums.mean(axis=0)
    rank = int(np.linalg.matrix_rank(centered, tol=1e-12 * max(1.0, np.abs(centered).max())))
    if rank < P1.ambient_dim:
        raise InputError(
            "P1",
            f"sets whose sum spans the {P1.ambient_dim}-dimensional task space",
            f"a sum of dimension {rank}",
            "add full-dimensional sets (nonsingular postures).",
        )
    total = HPolytope.from_vertices(sums)
    return HPolytope(total.A, total.b, center=P1.center + P2.center)


def intersection(P1: Set, P2: Set) -> HPolytope:
    """The set of points in both (forces that each of two arms can exert).

    Parameters
    ----------
    P1, P2 : Polytope or HPolytope
        Sets of the same task space (unbounded ones too).

    Returns
    -------
    HPolytope
        Possibly empty (``is_empty``) or lower-dimensional.
    """
    P1, P2 = _check_pair(P1, P2)
    A1, b1 = _halfspaces(P1)
    A2, b2 = _halfspaces(P2)
    return HPolytope(np.vstack([A1, A2]), np.concatenate([b1, b2]))
