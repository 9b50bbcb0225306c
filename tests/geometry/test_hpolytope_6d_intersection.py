"""A 6-D intersection of two zonotopes of very different sizes, far apart (issue 33's attack).

``intersection(P1, P2)`` of a zonotope of 9 generators (size ~3) and one of 8 (size ~4000,
its centre ~3500 away) is a bounded 6-D set of 364 rows whose vertices lie on up to 30 of
them.  The edge walk gives up there (tangent cones of 26 rows), cddlib's vertices are all
of them, but Qhull cannot build their hull exactly (a "dupridge") and its joggled hull
splits every facet into slivers on no row: the check rejected a complete answer, the
fallback (Qhull's half-space intersection) hit the same dupridge, and a ``SolverError``
was raised.  Reference: scipy's half-space intersection and hull in task coordinates, and
HiGHS.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection

import polyell as pe
import polyell.geometry.hpolytope as hp
from polyell.geometry.combine import intersection


def _saved_case() -> tuple[pe.Polytope, pe.Polytope]:
    """The tester's case ``inter_fail_6_2``: its seeded draws replayed (m = 6, trial 2)."""
    rng = np.random.default_rng(7)
    for m in range(2, 7):
        for trial in range(6):
            n1, n2 = rng.integers(m, m + 4, size=2)
            G1 = rng.normal(size=(m, n1))
            c1 = rng.normal(size=m)
            s2 = 10.0 ** rng.uniform(-4, 4)
            G2 = rng.normal(size=(m, n2)) * s2
            c2 = rng.normal(size=m) * s2
            if (m, trial) == (6, 2):
                return pe.Polytope(G1, c1), pe.Polytope(G2, c2)
            for _ in range(5):
                rng.normal(size=m)
            if m in (2, 3):
                for _ in range(3):
                    rng.normal(size=m)
    raise AssertionError("unreachable")


@pytest.fixture(scope="module")
def case() -> dict[str, object]:
    P1, P2 = _saved_case()
    A, b = np.vstack([P1.A, P2.A]), np.concatenate([P1.b, P2.b])
    m = A.shape[1]
    ball = linprog(
        np.r_[np.zeros(m), -1.0],
        A_ub=np.hstack([A, np.linalg.norm(A, axis=1)[:, None]]),
        b_ub=b,
        bounds=[(None, None)] * m + [(0, None)],
        method="highs",
    )
    assert ball.status == 0 and ball.x[-1] > 1.0  # well posed: radius 1.44
    reference = ConvexHull(
        HalfspaceIntersection(np.hstack([A, -b[:, None]]), ball.x[:-1]).intersections
    )
    return {"P1": P1, "P2": P2, "A": A, "b": b, "reference": reference}


@pytest.fixture(scope="module")
def polytope(case: dict[str, object]) -> pe.HPolytope:
    return pe.HPolytope(case["A"], case["b"])


def _agrees(H: pe.HPolytope, case: dict[str, object]) -> None:
    A, b = case["A"], case["b"]
    reference = case["reference"]
    assert isinstance(A, np.ndarray) and isinstance(b, np.ndarray)
    assert isinstance(reference, ConvexHull)
    assert H.dim == 6 and not H.is_empty and H.is_bounded
    assert len(H.vertices) == len(reference.vertices) == 438
    assert H.volume == pytest.approx(reference.volume, rel=1e-9)
    # the vertices are on the rows (exact to rounding), every one inside
    scale = float(np.abs(b).max())
    assert float((A @ H.vertices.T - b[:, None]).max()) <= 1e-12 * scale
    rng = np.random.default_rng(2033)
    directions = rng.normal(size=(12, 6))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    size = float(np.abs(H.vertices).max())
    for t in directions:
        # the support along t: the vertices' against HiGHS over the rows
        top = linprog(-t, A_ub=A, b_ub=b, bounds=[(None, None)] * 6, method="highs")
        assert top.status == 0
        assert float((H.vertices @ t).max()) == pytest.approx(-top.fun, rel=1e-9, abs=1e-9 * size)
        # the limits of the line {a t}: against HiGHS in the one variable a
        limits = H.limits(t)
        slopes = (A @ t)[:, None]
        hi = linprog([-1.0], A_ub=slopes, b_ub=b, bounds=[(None, None)], method="highs")
        lo = linprog([1.0], A_ub=slopes, b_ub=b, bounds=[(None, None)], method="highs")
        if hi.status == 2:  # the line misses the set
            assert np.isnan(limits.hi) and np.isnan(limits.lo)
            continue
        assert hi.status == 0 and lo.status == 0
        assert float(limits.hi) == pytest.approx(-hi.fun, rel=1e-9, abs=1e-9 * size)
        assert float(limits.lo) == pytest.approx(lo.fun, rel=1e-9, abs=1e-9 * size)


def test_intersection_of_far_apart_zonotopes_of_very_different_sizes(case):
    _agrees(intersection(case["P1"], case["P2"]), case)


def test_the_same_rows_as_one_hpolytope(case, polytope):
    _agrees(polytope, case)


def test_qhull_fallback_through_a_dupridge(case, monkeypatch):
    """Where cddlib's answer is rejected and every r rows are too many: Qhull's, joggled."""
    monkeypatch.setattr(hp, "_checked", lambda description, normals, offsets: (False, None, None))
    monkeypatch.setattr(hp, "MAX_SUBSETS", 0)
    _agrees(pe.HPolytope(case["A"], case["b"]), case)


def test_edge_graph_certificate_refuses_a_missing_vertex(polytope):
    """The certificate that stands in for the failing hull check is no rubber stamp."""
    y, _ = polytope._whitened
    rows = polytope._rows_y
    normals, offsets = -rows[:, 1:], rows[:, 0]
    assert hp._edge_closed(y, normals, offsets) is not None
    for dropped in (0, len(y) - 1):
        assert hp._edge_closed(np.delete(y, dropped, axis=0), normals, offsets) is None
    assert hp._certified(np.delete(y, 217, axis=0), normals, offsets)[0] is None
