r"""A polyhedron given by half-spaces, :math:`\{x : A x \le b\}`: the force capacity's set.

Unlike the zonotopes of accelerations and velocities it need not be bounded (a force
polytope at a singular posture is unbounded along :math:`\operatorname{Ker} J^T`) nor
non-empty (an arm that cannot hold itself against gravity), and it has no centre of
symmetry.  Its vertices, rays and irredundant facets are computed about an interior point,
in coordinates where the set is well scaled: by walking its edge graph from one vertex
(every edge followed until no vertex is new: exact, at the speed of the vertex count), or
for a few rows by cddlib (pycddlib) where its answer is certainly complete, and by cddlib's
double description where the set has no interior point or a decision of the walk is too
close to call.
"""

from __future__ import annotations

import math
import warnings
from functools import lru_cache
from typing import NamedTuple

import cdd
import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.cached import cached_property
from polyell.errors import InputError, ProjectedInputWarning, SolverError
from polyell.geometry.convex_set import PROJECTION_NOTICE, ConvexSet
from polyell.geometry.limits import facet_slack, line_interval_in_halfspaces, rounding_floor
from polyell.geometry.subspace import (
    RANK_RTOL,
    AffineSubspace,
    _whole_space,
    rank_revealing_svd,
    scaled_norm,
)
from polyell.geometry.zonotope import order_polygon
from polyell.validation import check_array, check_integer, check_points, magnitude_limit

__all__ = ["HPolytope", "require_drawable"]


class HPolytope(ConvexSet):
    r"""The polyhedron :math:`\{x \in R^m : A x \le b\}`, possibly unbounded or empty.

    The irredundant facets are :attr:`A`, :attr:`b` (unit normals); :attr:`vertices` and
    :attr:`rays` generate the set (``conv(vertices) + cone(rays)``; a line of the set as a
    pair of rays ``+-d``): the extreme points and the recession cone when it holds no line.

    Parameters
    ----------
    A : array-like, shape (k, m)
        Half-space normals (any scale; zero rows are allowed and kept only if they make
        the set empty).
    b : array-like, shape (k,)
        Offsets.
    center : array-like, shape (m,), optional
        A reference point of the set (the force capacity passes the force of least
        torque residual); default its Chebyshev centre (the centre of the largest ball
        inside, by a linear program).
    rank : int, optional
        The rank of the normals as the caller decided it (the force capacity passes the
        rank of ``J``): the set is unbounded along the rest (its lines); by default the
        rank of the unit normals by ``RANK_RTOL``.

    Examples
    --------
    >>> import polyell as pe
    >>> box = pe.HPolytope([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 2, 1])
    >>> round(box.volume, 12), box.limits([0.0, 1.0])
    (6.0, DirectionalLimits(lo=array(-1.), hi=array(2.)))
    """

    def __init__(
        self,
        A: ArrayLike,
        b: ArrayLike,
        *,
        center: ArrayLike | None = None,
        rank: int | None = None,
    ) -> None:
        A = check_array("A", A, ("k", "m"))
        if A.shape[1] == 0:
            raise InputError(
                "A",
                "at least one column (the task dimension m)",
                "shape (k, 0)",
                "give A one column per task coordinate, e.g. shape (2 * m, m) for a box in R^m",
            )
        b = check_array("b", b, (A.shape[0],))
        norms = scaled_norm(A, axis=1)  # rows of 1e-200 (units of forces) are no zero rows
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            kept = norms > RANK_RTOL * norms.max(initial=0.0)
            offsets = np.abs(b[kept] / norms[kept])
        limit = 10.0 ** magnitude_limit(A.shape[1])
        size = float(offsets.max(initial=0.0))
        if not np.all(np.isfinite(offsets)) or size > limit or 0 < size < 1 / limit:
            raise InputError(
                "b",
                f"offsets b_i / |a_i| of size between 1e-{magnitude_limit(A.shape[1])} and "
                f"1e{magnitude_limit(A.shape[1])} (the set's volume and limits representable)",
                f"offsets up to {size:.3g}",
                "express the half-spaces in units where the set is of moderate size.",
            )
        # A normal negligible against the others (rank decision, RANK_RTOL) is a zero row: it
        # keeps every point (b >= 0) or none, as a joint that no task force loads.
        zero = norms <= RANK_RTOL * norms.max(initial=0.0)
        self._infeasible_row = bool(np.any(zero & (b < 0)))
        keep = ~zero
        self._A_in, self._b_in = A[keep] / norms[keep, None], b[keep] / norms[keep]
        self._A_in, self._b_in = _close_rounded_slabs(self._A_in, self._b_in)
        m = A.shape[1]
        self._rank = None if rank is None else check_integer("rank", rank, 0, A.shape[1])
        if self._rank == 0 and len(self._A_in):
            raise InputError(
                "rank",
                f"the rank of the normals, from 1 to {m} (rows that are not all zero)",
                "0",
                "leave rank=None to have it decided by RANK_RTOL.",
            )
        self._volume_y: float | None = None
        if center is None:
            self.center = self._chebyshev_center()
        else:
            self.center = check_array("center", center, (m,))
        self._generators()  # vertices, rays, facets and the affine set, at once
        if center is None and not self._empty and self.affine_set.dim < m:
            # a flat set: the largest ball of its affine hull (the full-space linear
            # program's ball has radius 0 there, and lands on any point, a vertex)
            self.center = self._relative_chebyshev_center()

    # --- the double description ------------------------------------------------------

    def _chebyshev_center(self) -> NDArray[np.float64]:
        """The centre of the largest ball inside (radius capped: unbounded sets have one).

        Solved in units of the median offset, so that HiGHS's absolute tolerances are
        relative to the set; the origin for an empty set (never used).  The cap, twice the
        largest offset, never binds on a bounded set (its inradius is at most a convex
        combination of offsets: the normals of its rows positively span R^m).  Where the
        radius found is below :data:`CENTER_RESOLVED` of those units (the median is no
        size of the set: redundant rows far beyond it, or a thin set), solved again about
        that centre in units of that radius (where it is 0, of the distance to the
        (m + 1)-th nearest row), up to :data:`CENTER_PASSES` times; a centre replaces the
        one before only where its ball (its least slack) is larger.
        """
        from scipy.optimize import linprog

        m = self._A_in.shape[1]
        if self._infeasible_row or not len(self._A_in):
            return np.zeros(m)
        scale = float(np.median(np.abs(self._b_in))) or 1.0
        cost = np.zeros(m + 1)
        cost[-1] = -1.0
        A_ub = np.hstack([self._A_in, np.ones((len(self._A_in), 1))])
        point, center, radius = np.zeros(m), np.zeros(m), -np.inf
        for _ in range(CENTER_PASSES):
            offsets = self._b_in - self._A_in @ point
            cap = 2.0 * float(np.abs(offsets).max()) / scale
            bounds = [(None, None)] * m + [(0.0, max(cap, 1.0))]
            result = linprog(cost, A_ub, offsets / scale, bounds=bounds, method="highs")
            if result.status != 0:  # infeasible: an empty set (or no better centre)
                break
            point = point + scale * result.x[:m]
            reach = float((self._b_in - self._A_in @ point).min())
            if reach > radius + CENTER_RESOLVED * abs(radius) or not math.isfinite(radius):
                center, radius = point, reach
            found = float(result.x[m])
            if not found < CENTER_RESOLVED:
                break
            # in units of the radius found, or where it is 0 to the tolerances (the set
            # thinner than they are), of the distance to the (m + 1)-th nearest row
            distances = np.sort(np.abs(self._b_in - self._A_in @ point))
            nearest = float(distances[min(m, len(distances) - 1)])
            smaller = scale * found if found > 0 else nearest
            if not 0.0 < smaller < CENTER_RESOLVED * scale:
                break
            scale = smaller
        return center

    def _relative_chebyshev_center(self) -> NDArray[np.float64]:
        """The Chebyshev centre of a flat set within its affine hull (the relative one).

        In coordinates z of the hull, x = p + B z (p a point of the set, B its orthonormal
        basis), a facet a . x <= b is (B^T a) . z <= b - a . p, a distance in the hull of
        that over |B^T a|; the linear program maximises the least such distance, in units
        of the set's size about p (HiGHS's tolerances are absolute).  Radius capped at
        twice that size (an unbounded set has no largest ball).  A point (dim 0): itself.
        """
        from scipy.optimize import linprog

        basis = self.affine_set.basis
        q = basis.shape[1]
        anchor = self.vertices[0] if len(self.vertices) else self.affine_set.point
        anchor = self.affine_set.project(anchor)
        if q == 0:
            return anchor
        normals = self.A @ basis  # (F, q)
        lengths = np.sqrt((normals * normals).sum(axis=1))
        kept = lengths > RANK_RTOL * max(1.0, float(lengths.max(initial=0.0)))
        if not kept.any():  # no facet across the hull: the whole affine set
            return anchor
        normals = normals[kept] / lengths[kept, None]
        offsets = (self.b[kept] - self.A[kept] @ anchor) / lengths[kept]
        spread = float(np.abs(self.vertices - anchor).max(initial=0.0))
        scale = max(spread, float(np.abs(offsets).max())) or 1.0
        cost = np.zeros(q + 1)
        cost[-1] = -1.0
        A_ub = np.hstack([normals, np.ones((len(normals), 1))])
        bounds = [(None, None)] * q + [(0.0, 2.0)]
        result = linprog(cost, A_ub, offsets / scale, bounds=bounds, method="highs")
        if result.status != 0:
            return self.center
        found = anchor + scale * (basis @ result.x[:q])
        slack = (self.b[kept] - self.A[kept] @ found) / lengths[kept]
        before = (self.b[kept] - self.A[kept] @ self.affine_set.project(self.center)) / lengths[
            kept
        ]
        return found if float(slack.min()) >= float(before.min()) else self.center

    def _interior_point(self) -> NDArray[np.float64]:
        """:attr:`center` if it is strictly inside every half-space, else the Chebyshev centre.

        cddlib works about this point, in units of its farthest row, or, where some row
        is much closer, with every row scaled to distance 1 from it (the polar whitening
        of :meth:`_generators`): a thin set about a point strictly inside it, as a force
        set about its centre h0, is then as well scaled as a round one.
        """
        offsets = self._b_in - self._A_in @ self.center
        if len(offsets) and offsets.min() > 0:
            return self.center
        return self._chebyshev_center()

    def _generators(self) -> None:
        m = self.ambient_dim
        empty = np.zeros((0, m))
        self._line_slope = 0.0  # the largest singular value of the rows counted as zero
        self._rays, self._lines = empty, empty
        self._vertices = empty
        self._facet_A, self._facet_b = empty, np.zeros(0)
        self._rows_y = np.zeros((0, m + 1))
        self._whitened = (empty, np.ones(m))
        self._edges: NDArray[np.int_] | None = None  # vertex pairs, where the walk found them
        self.affine_set = AffineSubspace(self.center, *_whole_space(m))
        self._empty = self._infeasible_row
        if self._empty:
            return
        if not len(self._A_in):  # no constraint: the whole space (cddlib has no rows)
            self._vertices = self.center[None, :].copy()
            self._rays = np.vstack([np.eye(m), -np.eye(m)])
            return
        # About an interior point and in units of the largest offset from it: cdd then
        # works on numbers of order 1 whatever the set's size and distance from 0.
        origin = self._interior_point()
        shifted = self._b_in - self._A_in @ origin
        if 0 < float(shifted.min()) < POLAR_RATIO * float(shifted.max()):
            # far closer to one row than to another: from the analytic centre instead,
            # where a thin set's rows are as close as its width allows, in every direction
            origin = _analytic_center(self._A_in, self._b_in, origin)
            shifted = self._b_in - self._A_in @ origin
        unit = float(np.abs(shifted).max()) or 1.0
        # Whitened coordinates (DESIGN.md section 7, "Thin zonotopes", for half-spaces): with
        # A = V1 S U1^T (rank by RANK_RTOL), y = S U1^T (x - origin) / unit turns the rows into
        # the well-scaled V1: cdd meets no nearly parallel facets however thin the set is.
        # The lines of the set (normals spanning less than R^m, a force polytope at a singular
        # posture) are U2, by the rank decision and not by cddlib's epsilon.
        svd = rank_revealing_svd(self._A_in.T, rank=self._rank)
        U1, S, V1, lines = svd.U1, svd.sigma, svd.V1, svd.U2
        self._lines = lines.T  # (l, m): the directions along which the set is a line
        if svd.rank < len(svd.singular_values):  # a unit line meets rows at slopes below it
            self._line_slope = float(svd.singular_values[svd.rank])
        if svd.rank and 0 < float(shifted.min()) < POLAR_RATIO * unit:
            # Polar whitening within the row space: rows a_i / shifted_i (each at distance
            # 1 from the origin) = V S U^T, y = S U^T U1^T (x - origin) gives the rows V
            # with offsets 1, so that a thin slab (a force set with one tiny torque range)
            # is as wide as any other and not taken for an equality by cddlib's epsilon.
            # (Only then: cddlib is slower on rows all at distance 1.)
            polar = rank_revealing_svd(((self._A_in @ U1) / shifted[:, None]).T, rank=svd.rank)
            U1, S, V1, shifted, unit = (
                U1 @ polar.U1,
                polar.sigma,
                polar.V1,
                np.ones_like(shifted),
                1.0,
            )
        array = np.empty((len(shifted), svd.rank + 1))  # cdd's rows [b | -a]
        array[:, 0], array[:, 1:] = shifted / unit, -V1
        known = self.__dict__.pop("_known", None)  # vertices and edges a caller computed
        if float(shifted.min()) > 0:  # the origin strictly inside (in the row space)
            # Its vertices, rays and facets by walking the edge graph (exact; at the speed
            # of the vertex count), or read from the caller's vertices where they fit.
            walk = None if known is None else _known_walk(known, array, S, U1, unit, origin)
            if walk is None and svd.rank == m and len(array) <= 52:
                # a few rows: cddlib's vertices where they are certainly all (a simple
                # polytope whose every vertex has its m neighbours among them), faster
                bounded = _bounded_description(array)
                if bounded is not None and bounded[2]:
                    self._vertices_and_facets(bounded[0], bounded[1][:, 1:], S, U1, unit, origin)
                    return
            if walk is None:
                walk = _walk_polyhedron(V1, array[:, 0])
            if walk is not None:
                self._from_walk(walk, array, S, U1, unit, origin, lines)
                return
        # Where a decision of the walk is too close to call, or the set has no interior
        # point: cddlib, in floating point.  Where the set is full-dimensional with the
        # origin strictly inside, its answer is checked (no vertex missed, not empty) and
        # replaced by an enumeration of every r rows where it fails (_complete).
        description = _double_description(array)
        if svd.rank == m and float(shifted.min()) > 0:  # solid: the walk's decision was close
            complete, self._volume_y, description = _checked(description, V1, array[:, 0])
            if not complete:
                rows, points, self._volume_y = _complete(array[:, 0], V1)
                self._vertices_and_facets(rows, points, S, U1, unit, origin)
                return
        if description is None:
            self._empty = True
            return
        rows, linear, points, paired_rows = description
        is_vertex = _is_point(points)
        if not is_vertex.any() and not float(np.abs(array[:, 0]).max()) > 0:
            # every row through the interior point (a flat cone: a ray, a half-plane in
            # R^3): cddlib lists only the directions of the homogeneous system, whose
            # point, the apex, is that point (y = 0)
            points = np.vstack([np.eye(1, len(points[0])), points])
            is_vertex = np.r_[True, is_vertex]
            paired_rows = [i + 1 for i in paired_rows]
        # Facets: the inequality rows of the canonical form, a_y . y <= b_y, that is
        # (U1 S a_y) . (x - origin) <= unit b_y; equalities: its linearity.
        inequality = np.ones(len(rows), dtype=bool)
        inequality[linear] = False
        y = points[is_vertex, 1:] / points[is_vertex, :1]
        self._vertices_and_facets(rows[inequality], y, S, U1, unit, origin)
        directions = (points[~is_vertex, 1:] / S) @ U1.T
        norms = np.linalg.norm(directions, axis=1)
        directions = directions / np.where(norms > 0, norms, 1.0)[:, None]
        paired = np.zeros(len(points), dtype=bool)
        paired[paired_rows] = True
        pairs = np.vstack([directions[paired[~is_vertex]], lines.T])
        self._rays = np.vstack([directions, pairs, -pairs])
        if linear:
            normals = rank_revealing_svd(U1 @ (-rows[linear, 1:] * S).T).U1  # (m, e)
            e = normals.shape[1]  # the complement's rank is m - e exactly (not its noise's)
            complement = rank_revealing_svd(np.eye(m) - normals @ normals.T, rank=m - e).U1
            self.affine_set = AffineSubspace(origin, complement, normals)

    def _vertices_and_facets(
        self,
        rows: NDArray[np.float64],
        y: NDArray[np.float64],
        S: NDArray[np.float64],
        U1: NDArray[np.float64],
        unit: float,
        origin: NDArray[np.float64],
    ) -> None:
        """The vertices from whitened points ``y`` and the facets from ``rows``."""
        self._whitened = (y, unit / S)
        self._vertices = origin + unit * (y / S) @ U1.T
        if self.ambient_dim == 2 and len(self._vertices) > 2:  # counter-clockwise, as a zonotope's
            self._vertices = order_polygon(self._vertices)
        self._facets_from_rows(rows, S, U1, unit, origin)

    def _from_walk(
        self,
        walk: _Walk,
        array: NDArray[np.float64],
        S: NDArray[np.float64],
        U1: NDArray[np.float64],
        unit: float,
        origin: NDArray[np.float64],
        lines: NDArray[np.float64],
    ) -> None:
        """Vertices, rays, edges and facets from a walk of the whitened rows ``array``.

        The rays are the walk's extreme rays and the lines (columns of ``lines``) both
        ways; a facet is a row whose face has dimension r - 1 (:func:`_facet_rows`).
        """
        y, edges = walk.points, walk.edges
        vertices = origin + unit * (y / S) @ U1.T
        if self.ambient_dim == 2 and len(vertices) > 2:  # counter-clockwise, as a zonotope's
            centre = vertices.mean(axis=0)
            order = np.argsort(np.arctan2(*(vertices - centre).T[::-1]))
            y, vertices = y[order], vertices[order]
            edges = None if edges is None else np.argsort(order)[edges]
        self._whitened, self._vertices, self._edges = (y, unit / S), vertices, edges
        directions = (walk.rays / S) @ U1.T
        directions /= np.sqrt((directions * directions).sum(axis=1))[:, None]
        self._rays = np.vstack([directions, lines.T, -lines.T])
        self._facets_from_rows(array[_facet_rows(walk)], S, U1, unit, origin)

    @classmethod
    def _with_vertices(
        cls,
        A: NDArray[np.float64],
        b: NDArray[np.float64],
        vertices: NDArray[np.float64],
        edges: NDArray[np.int_] | None,
        center: NDArray[np.float64],
        volume: float | None = None,
    ) -> HPolytope:
        """``HPolytope(A, b, center=center)`` whose vertices (V, m) and edges are known.

        For :func:`~polyell.geometry.combine.minkowski_sum`, which finds them exactly (edges:
        None where unknown; ``volume`` where a closed form gives it, a zonotope's): they
        are used where every vertex satisfies every row and lies on m rows or more (to
        :data:`WALK_ON_PLANE`), and the set is then not enumerated again; the facets are
        the rows whose faces have dimension m - 1.  Otherwise the usual walk.
        """
        polytope = cls.__new__(cls)
        polytope.__dict__["_known"] = (vertices, edges)  # read once by _generators
        polytope.__init__(A, b, center=center)  # type: ignore[misc]
        if volume is not None:
            polytope.__dict__["volume"] = float(volume)  # the cached property's value
        return polytope

    def _vertex_edges(self) -> NDArray[np.int_]:
        """The edges of a bounded set, pairs of indices into :attr:`vertices` (E, 2).

        The walk's, or where another path computed the vertices, the pairs whose common
        facets have rank ``dim - 1`` (a face of dimension 1 holds exactly two vertices).
        """
        edges = getattr(self, "_edges", None)
        if edges is None:
            edges = vertex_edges(self.vertices, self.A, self.b, self.affine_set.basis)
            self._edges = edges
        return edges

    def _facets_from_rows(
        self,
        rows: NDArray[np.float64],
        S: NDArray[np.float64],
        U1: NDArray[np.float64],
        unit: float,
        origin: NDArray[np.float64],
    ) -> None:
        """Facets from cdd's inequality rows ``[b_y | -a_y]``: unit normals, offsets."""
        self._rows_y = rows  # in the whitened coordinates (a volume's fallback)
        A_rows, b_rows = (-rows[:, 1:] * S) @ U1.T, unit * rows[:, 0]
        scale = np.sqrt((A_rows * A_rows).sum(axis=1))
        self._facet_A = A_rows / scale[:, None]
        self._facet_b = b_rows / scale + self._facet_A @ origin
        self._facets_as_given(origin)

    def _facets_as_given(self, origin: NDArray[np.float64]) -> None:
        """Each facet as the input row it is, where it is one to rounding (exact offsets).

        A facet mapped back from the whitened coordinates carries their rounding (a box's
        ``b = 1`` as 1.0000000000000004, which makes two boxes sharing an edge meet in a
        slab 4e-16 wide); the input row it came from is the same plane, exactly as given.
        Matched when the unit normals agree to ``m eps`` and the offsets to the rounding of
        the shift by the interior point (skipped beyond 4e6 facet-row pairs).
        """
        F, k = len(self._facet_b), len(self._b_in)
        if not F or not k or F * k > 4_000_000:
            return
        m = self.ambient_dim
        eps = float(np.finfo(float).eps)
        dots = self._facet_A @ self._A_in.T  # (F, k)
        best = np.argmax(dots, axis=1)
        rows = np.arange(F)
        reach = np.abs(self._facet_b) + float(np.abs(origin).sum()) + np.abs(self._b_in[best])
        same = (dots[rows, best] >= 1.0 - 4 * m * eps) & (
            np.abs(self._b_in[best] - self._facet_b) <= 4 * (m + 2) * eps * reach
        )
        self._facet_A = np.where(same[:, None], self._A_in[best], self._facet_A)
        self._facet_b = np.where(same, self._b_in[best], self._facet_b)

    # --- what the set is ---------------------------------------------------------------

    def __repr__(self) -> str:
        if self.is_empty:
            return f"HPolytope(m={self.ambient_dim}, empty)"
        return (
            f"HPolytope(m={self.ambient_dim}, dim={self.dim}, facets={len(self.b)}, "
            f"vertices={len(self.vertices)}, bounded={self.is_bounded}, volume={self.volume:.6g})"
        )

    @property
    def is_empty(self) -> bool:
        """True when no point satisfies every half-space."""
        return self._empty

    @property
    def is_bounded(self) -> bool:
        """True for a polytope (no rays); an empty set counts as bounded."""
        return not len(self._rays)

    @property
    def dim(self) -> int:
        """Dimension of the set's affine hull; -1 for an empty set."""
        return -1 if self.is_empty else self.affine_set.dim

    @property
    def A(self) -> NDArray[np.float64]:
        """Unit outward normals of the irredundant facets, shape (F, m)."""
        return self._facet_A

    @property
    def b(self) -> NDArray[np.float64]:
        """Facet offsets, shape (F,): the set is ``{x : A x <= b, A_eq x = b_eq}``."""
        return self._facet_b

    @property
    def vertices(self) -> NDArray[np.float64]:
        """Extreme points, shape (V, m); none for an empty set.

        When the set holds a line: points of the set that generate it with :attr:`rays`.
        """
        return self._vertices

    @property
    def rays(self) -> NDArray[np.float64]:
        """Unit directions of unboundedness, shape (R, m); empty for a bounded set."""
        return self._rays

    @cached_property
    def half_widths(self) -> NDArray[np.float64]:
        """``b_i - a_i . center`` (F,): each facet's distance from the reference point."""
        return self.b - self.A @ self.center

    @cached_property
    def volume(self) -> float:
        """Volume in the affine hull (r-dimensional); ``inf`` if unbounded, 0 if empty."""
        if self.is_empty:
            return 0.0
        if not self.is_bounded:
            return float("inf")
        r = self.dim
        if r == 0:
            return 1.0
        # In the whitened coordinates (well scaled however thin the set), times the Jacobian
        # of x = origin + U1 diag(unit / S) y; a lower-dimensional set in its hull's basis.
        y, stretch = self._whitened
        flat = r < len(stretch)
        if flat:
            y, stretch = self.affine_set.coordinates(self.vertices), np.ones(r)
        elif self._volume_y is not None:  # the hull that certified the vertices
            return float(self._volume_y * np.prod(stretch))
        if r == 1:
            return float((y.max() - y.min()) * stretch[0])
        from scipy.spatial import ConvexHull, QhullError

        if flat or len(self._rows_y) == 0:  # (the rows are the whitened, unflattened ones)
            try:
                return float(ConvexHull(y).volume * np.prod(stretch))
            except QhullError:  # a dupridge in 6-D: sum cones over the faces instead
                tight = self.facet_slacks(self.vertices) <= 1e-9 * max(1.0, self.extent)
                return _face_volume(y, tight, r)
        # In the whitened coordinates, with the facets there (a thin set is well shaped in
        # them; in task coordinates its extent would swamp the tolerance).  From 5-D on,
        # and where Qhull's merging fails on many coplanar vertices (a "dupridge"), as a
        # sum of cones over the facets, each facet's volume one dimension down.
        cones = _facet_cone_volume(y, self._rows_y) if r > 4 else None
        if cones is None:
            try:
                return float(ConvexHull(y).volume * np.prod(stretch))
            except QhullError:
                cones = _facet_cone_volume(y, self._rows_y)
        if cones is None:  # rows and vertices that disagree: the faces' incidence as is
            normals, offsets = -self._rows_y[:, 1:], self._rows_y[:, 0]
            lengths = np.sqrt((normals * normals).sum(axis=1))
            slack = (offsets - y @ normals.T) / lengths
            tight = slack <= 1e-9 * max(1.0, float(np.abs(y).max()))  # (V, F)
            cones = _face_volume(y, tight, r)
        return cones * float(np.prod(stretch))

    @cached_property
    def ball_radius(self) -> float:
        """Radius of the largest ball about :attr:`center` inside the set, in its hull.

        NaN if the centre is outside (the force capacity's centre ``h0`` is outside when
        gravity needs more than the limits along a direction no force balances), as
        :attr:`origin_radius` is for the origin.
        """
        if self.is_empty or not self.contains(self.center):
            return float("nan")
        if not len(self.b):
            return float("inf")
        widths = self.half_widths
        if self.dim < self.ambient_dim:  # distances within the hull, not across it
            along = np.linalg.norm(self.A @ self.affine_set.basis, axis=1)
            with np.errstate(divide="ignore", invalid="ignore"):
                widths = np.where(along > RANK_RTOL, widths / along, np.inf)
        return float(max(0.0, np.min(widths)))

    @cached_property
    def origin_radius(self) -> float:
        """Radius of the largest ball about the origin inside the set; NaN if outside."""
        if self.is_empty or not self.contains(np.zeros(self.ambient_dim)):
            return float("nan")
        if not len(self.b):
            return float("inf")
        return float(max(0.0, np.min(self.b)))

    @cached_property
    def extent(self) -> float:
        """Largest distance of a vertex from :attr:`center` (``inf`` if unbounded)."""
        if not self.is_bounded:
            return float("inf")
        if not len(self.vertices):
            return 0.0
        return float(np.linalg.norm(self.vertices - self.center, axis=1).max())

    def facet_slacks(self, x: ArrayLike) -> NDArray[np.float64]:
        """``b - A x`` for points x (m,) or (k, m): non-negative inside.

        The points are checked as by :meth:`contains` (real, finite, m coordinates).
        """
        points = check_points("x", x, self.ambient_dim)
        return self.half_widths - (points - self.center) @ self.A.T

    def halfspaces(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The irredundant facets ``(A, b)`` (unit normals)."""
        return self.A, self.b

    @classmethod
    def _from_enumeration(
        cls,
        A: NDArray[np.float64],
        b: NDArray[np.float64],
        vertices: NDArray[np.float64],
        center: NDArray[np.float64],
        whitened: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    ) -> HPolytope:
        """A bounded, full-dimensional polytope whose facets and vertices are known: no cddlib.

        For a caller that enumerated them exactly and certified them complete (the force
        capacity's batch of one, :func:`polyell.capacities.force.force_vertices`); nothing
        is checked here.

        Parameters
        ----------
        A : ndarray, shape (F, m)
            Unit outward normals of the irredundant facets.
        b : ndarray, shape (F,)
            Their offsets.
        vertices : ndarray, shape (V, m)
            The extreme points (counter-clockwise when m = 2).
        center : ndarray, shape (m,)
            A point strictly inside.
        whitened : (ndarray (V, m), ndarray (m, m), ndarray (m,))
            The vertices ``y`` in coordinates where the set is well scaled, the orthonormal
            frame ``U`` and the stretch ``t`` of ``x = center + U diag(t) y``: the volume
            is that of the hull of ``y`` times ``prod(t)``.
        """
        polytope = cls.__new__(cls)
        m = A.shape[1]
        y, frame, stretch = whitened
        polytope._A_in, polytope._b_in = A, b
        polytope._infeasible_row = polytope._empty = False
        polytope._rank, polytope._volume_y, polytope._line_slope = m, None, 0.0
        polytope.center = center
        polytope._rays = polytope._lines = np.zeros((0, m))
        polytope._vertices, polytope._facet_A, polytope._facet_b = vertices, A, b
        polytope._whitened, polytope._edges = (y, stretch), None
        # the facets in the whitened coordinates, [b_y | -a_y] (a volume's fallback)
        polytope._rows_y = np.concatenate(((b - A @ center)[:, None], -(A @ frame) * stretch), 1)
        polytope.affine_set = AffineSubspace(center, *_whole_space(m))
        return polytope

    @classmethod
    def from_vertices(cls, vertices: ArrayLike) -> HPolytope:
        """The convex hull of points (V, m), with its facets and vertices.

        The hull must be full-dimensional in R^m (points of rank m about their mean, by
        ``RANK_RTOL``); interior, repeated and coplanar points are allowed.  The vertices
        are the points the hull needs (repeats within rounding once); the facets are
        Qhull's (its triangulated boundary grouped by plane; cddlib's where Qhull's fail),
        each with the offset of the farthest point, and certified
        (:func:`_hull_of_points`): every facet holds m affinely independent points, and
        the boundary closes up (every ridge on two facets), so that none is missing.  All
        in coordinates where the points are round (their principal axes, scaled).  The
        vertices are not enumerated again from the facets: in 5-D and 6-D a hull of a few
        dozen points has vertices on dozens of facets each, which no floating-point
        enumeration of half-spaces decides reliably (14 random points in 6-D raised
        SolverError so).

        Raises
        ------
        InputError
            If the points do not span R^m.
        SolverError
            If neither Qhull's nor cddlib's facets pass the certificate.
        """
        V = check_array("vertices", vertices, ("V", "m"))
        m = V.shape[1]
        if m == 0:
            raise InputError(
                "vertices",
                "at least one column (the task dimension m)",
                "shape (V, 0)",
                "give each point its m task coordinates, e.g. vertices of shape (8, 3) in 3-D",
            )
        limit = magnitude_limit(m)
        if len(V) and float(np.abs(V).max()) > 10.0**limit:  # (squares overflow below)
            raise InputError(
                "vertices",
                f"coordinates of size at most 1e{limit} (the set's volume and limits "
                "representable)",
                f"an entry of size {float(np.abs(V).max()):.3g}",
                "express the points in units where the set is of moderate size.",
            )
        center = V.mean(axis=0) if len(V) else np.zeros(m)
        svd = rank_revealing_svd((V - center).T) if len(V) else None
        rank = 0 if svd is None else svd.rank
        if rank < m:
            raise InputError(
                "vertices",
                f"points spanning R^{m} (a full-dimensional hull)",
                f"{len(V)} points of rank {rank} about their mean",
                "give the points of a full-dimensional set.",
            )
        assert svd is not None
        # Whitened coordinates: x = center + U diag(t) y with the points' principal axes U
        # and spreads t, scaled so that the farthest point is at distance 1: the hull of a
        # thin or far-off cloud is as well shaped as a round one's.
        frame = svd.U1
        stretch = svd.sigma.copy()
        y = ((V - center) @ frame) / stretch
        reach = float(np.sqrt((y * y).sum(axis=1)).max())
        y, stretch = y / reach, stretch * reach
        kept = _distinct_points(y)
        hull = _hull_of_points(y[kept])
        normals, offsets, vertex = hull.normals, hull.offsets, kept[hull.vertices]
        y_vertices = y[vertex]
        # the facets in task coordinates: n . y <= o is (n / t) . U^T (x - center) <= o,
        # scaled by max(t) first (1 / t of a set of size 1e-160 overflows, of 1e200 underflows)
        widest = float(stretch.max())
        A = (normals / (stretch / widest)) @ frame.T
        scale = np.sqrt((A * A).sum(axis=1))
        A = A / scale[:, None]
        b = offsets * (widest / scale) + A @ center
        size = float(np.abs(b).max())
        if not math.isfinite(size) or size > 10.0**limit or 0 < size < 10.0**-limit:
            raise InputError(
                "vertices",
                f"points whose facets lie at distances between 1e-{limit} and 1e{limit} from "
                "the origin (the set's volume and limits representable)",
                f"facets up to {size:.3g} away",
                "express the points in units where the set is of moderate size.",
            )
        points = V[vertex]
        if m == 2:  # counter-clockwise, as a zonotope's (y is x turned by U: a reflection?)
            turn = float(np.linalg.det(frame))
            angle = np.arctan2(*(y_vertices - y_vertices.mean(axis=0)).T[::-1])
            order = np.argsort(angle if turn > 0 else -angle)
            points, y_vertices = points[order], y_vertices[order]
        polytope = cls._from_enumeration(A, b, points, center, (y_vertices, frame, stretch))
        polytope._volume_y = hull.volume
        return polytope

    # --- ConvexSet -------------------------------------------------------------------------

    def _size(self) -> float:
        if self.is_bounded:
            return max(self.extent, float(np.abs(self.half_widths).max(initial=0.0)))
        return float(np.abs(self.half_widths).max(initial=1.0))

    @property
    def _terms(self) -> int:
        return self.ambient_dim + 2

    def _inside_hull(self, x: NDArray[np.float64]) -> NDArray[np.bool_]:
        if self.is_empty:
            return np.zeros(x.shape[:-1], dtype=bool)
        h = self.half_widths
        reach = np.linalg.norm(x, axis=-1)[..., None] + float(np.linalg.norm(self.center))
        reach = reach + self._size()
        inside = (x - self.center) @ self.A.T <= h + facet_slack(h, reach, self._terms)
        return np.all(inside, axis=-1)

    def _interval_on_lines(
        self, lines: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if self.is_empty:
            return np.full(len(lines), np.nan), np.full(len(lines), np.nan)
        lines = self._rounded_to_lines(lines)
        reach = 2.0 * (float(np.linalg.norm(self.center)) + self._size())
        slack = facet_slack(self.half_widths, reach, self._terms)
        floor = rounding_floor(reach, self._terms)
        # Unbounded: a line within the rank decision of a ray (its slopes against the rows
        # at most the largest singular value counted as zero, or rounding) is parallel to it.
        eps = float(np.finfo(float).eps)
        slope_floor = 0.0 if self.is_bounded else max(self._terms * eps, 2.0 * self._line_slope)
        return line_interval_in_halfspaces(
            self.A, self.b, lines, slack, floor, slope_floor, reach=reach
        )

    def _rounded_to_lines(self, directions: NDArray[np.float64]) -> NDArray[np.float64]:
        """Directions within :attr:`affine_rtol` of the set's lines, taken as along them.

        A direction typed to a few digits along a line of the set (a force polytope at a
        singular posture, unbounded along Ker J^T) is the line itself, as rounded input
        is for a singular configuration's affine set: it is projected onto the lines' span,
        with a :class:`~polyell.ProjectedInputWarning`, and has infinite limits there,
        not those of a line 1e-5 off it (1e6 times the set's size).
        """
        if not len(self._lines):
            return directions
        along = directions @ self._lines.T @ self._lines
        off = np.linalg.norm(directions - along, axis=1)
        rounded = (off <= self.affine_rtol) & (off > 0.0)
        if not rounded.any():
            return directions
        if off[rounded].max() > PROJECTION_NOTICE:  # (not for the line's own rounding)
            warnings.warn(
                f"directions: {np.count_nonzero(rounded)} direction(s) up to "
                f"{off[rounded].max():.2g} off the line(s) of this unbounded set were taken as "
                f"rounded and projected onto them (affine_rtol = {self.affine_rtol:g}).",
                ProjectedInputWarning,
                stacklevel=5,
            )
        snapped = directions.copy()
        snapped[rounded] = along[rounded] / np.linalg.norm(along[rounded], axis=1, keepdims=True)
        return snapped


def _close_rounded_slabs(
    A: NDArray[np.float64], b: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unit rows with opposite pairs closer than their offsets' rounding made one plane.

    Two rows ``a . x <= b1`` and ``-a . x <= b2`` (normals opposite to ``m eps``) bound a
    slab of width ``b1 + b2``; where that is within the rounding of the offsets,
    ``(m + 2) eps (|b1| + |b2|)`` (:func:`~polyell.geometry.limits.rounding_floor`, the
    offsets' size is the set's distance from the origin), the slab cannot be told from
    the plane between them, and is that plane (an exact equality): two boxes sharing the
    edge x = 1, one offset stored as 1.0000000000000004, meet in a segment, not in a
    2-D slab of width 4e-16.  Pairs found by normals rounded to 9 digits.
    """
    k, m = A.shape
    if k < 2:
        return A, b
    eps = float(np.finfo(float).eps)
    keys: dict[bytes, int] = {}
    for index, row in enumerate(np.round(A, 9) + 0.0):
        keys.setdefault(row.tobytes(), index)
    A, b = A.copy(), b.copy()
    for j, row in enumerate(np.round(-A, 9) + 0.0):
        i = keys.get(row.tobytes())
        if i is None or i >= j or float(np.abs(A[i] + A[j]).max()) > m * eps:
            continue
        width = b[i] + b[j]
        if width != 0.0 and abs(width) <= (m + 2) * eps * (abs(b[i]) + abs(b[j])):
            middle = 0.5 * (b[i] - b[j])
            A[j], b[i], b[j] = -A[i], middle, -middle
    return A, b


def require_drawable(S: object, argument: str) -> None:
    """Refuse an H-polytope that is unbounded or empty (it has no finite drawing or mesh)."""
    if isinstance(S, HPolytope) and (S.is_empty or not S.is_bounded):
        raise InputError(
            argument,
            "a bounded, non-empty set",
            "an empty set" if S.is_empty else f"a set unbounded along {len(S.rays)} ray(s)",
            (
                "an empty set has nothing to draw: take another posture or state (a force "
                "set is empty where the arm cannot hold itself, a set over a horizon where "
                "a joint reaches its limit whatever it does: analysis.empty_reason says), "
                "or check the half-spaces."
                if S.is_empty
                else "bound it first, e.g. HPolytope(np.vstack([S.A, C]), np.r_[S.b, d]) "
                "with a box C x <= d around the part to draw (a force polytope is "
                "unbounded at a singular posture: or take another posture)."
            ),
        )


Description = tuple[NDArray[np.float64], list[int], NDArray[np.float64], list[int]]


def _analytic_center(
    A: NDArray[np.float64], b: NDArray[np.float64], start: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The minimiser of ``-sum log(b - A x)`` by damped Newton steps from an interior point.

    Steps of length ``1 / (1 + lambda)`` (``lambda`` the Newton decrement) stay inside
    (the barrier is self-concordant), in the span of the rows (least squares: lines are
    left alone).  ``start`` is returned where the set has no centre to converge to (a
    recession direction: the slacks grow past 1e3 times their start) or the iterations
    run out before the decrement is small.
    """
    x = start.copy()
    slack = b - A @ x
    limit = 1e3 * float(slack.max())
    for _ in range(MAX_CENTERING_STEPS):
        weights = 1.0 / slack
        gradient = A.T @ weights
        hessian = (A * weights[:, None] ** 2).T @ A
        # scaled to a unit diagonal first: slacks of very different sizes (a far row, or
        # a recession direction) must not leave a direction below lstsq's cut-off, which
        # would stop the steps along it (a false convergence, far out along a ray)
        diagonal = np.sqrt(np.diag(hessian))
        diagonal = np.where(diagonal > 0, diagonal, 1.0)
        scaled = hessian / diagonal[:, None] / diagonal[None, :]
        step = -np.linalg.lstsq(scaled, gradient / diagonal, rcond=None)[0] / diagonal
        decrement = float(np.sqrt(max(0.0, -gradient @ step)))
        if decrement < 1e-10:
            return x
        x = x + step / (1.0 + decrement)
        slack = b - A @ x
        if not (float(slack.min()) > 0 and float(slack.max()) < limit):
            return start
    return x if decrement < 0.25 else start


def _double_description(array: NDArray[np.float64]) -> Description | None:
    """The double description of ``{y : normals y <= offsets}``; None if it is empty.

    Irredundant rows ``[b | -a]``, the indices of its equalities, generators ``[1 | v]``
    (points) and ``[0 | d]`` (rays), and the indices of the rays that are lines.
    cddlib in floating point; where it reports a numerical inconsistency (a thin set in
    6-D), Qhull's half-space intersection about the interior point y = 0 (offsets > 0).
    """
    matrix = cdd.matrix_from_array(array.tolist(), rep_type=cdd.RepType.INEQUALITY)
    offsets, normals = array[:, 0], -array[:, 1:]
    r = normals.shape[1]
    try:
        cdd.matrix_canonicalize(matrix)
        generators = cdd.copy_generators(cdd.polyhedron_from_matrix(matrix))
    except RuntimeError as exn:
        return _by_qhull(offsets, normals, exn)
    rows = np.array(matrix.array, dtype=float).reshape(-1, r + 1)
    points = np.array(generators.array, dtype=float).reshape(-1, r + 1)
    if not len(points):
        return None
    return rows, sorted(matrix.lin_set), points, sorted(generators.lin_set)


#: A Chebyshev radius below this in the units of its linear program (the median offset)
#: is solved again in units of that radius, up to :data:`CENTER_PASSES` linear programs:
#: HiGHS's absolute tolerances (1e-7) then resolve a set far smaller than its far rows.
CENTER_RESOLVED = 1e-3
CENTER_PASSES = 6

#: Rows closer to the interior point than this times the farthest one are whitened by
#: their distances (a thin set, :meth:`HPolytope._generators`).
POLAR_RATIO = 1e-3
#: Newton steps of :func:`_analytic_center` at most (quadratic convergence after the
#: damped phase, whose length grows as the log of how far off centre the start is).
MAX_CENTERING_STEPS = 200
#: A vertex is on a row's plane when its slack is at most this (whitened units, offsets
#: at most 1), and off it when its slack is at least :data:`_OFF_PLANE`; a slack between
#: the two leaves the decision to cddlib's canonical form.
_ON_PLANE = 1e-9
_OFF_PLANE = 1e-6


def _bounded_description(
    array: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], bool] | None:
    """The facet rows and the points ``[1 | y]`` of a clearly full-dimensional polytope.

    cddlib enumerates the vertices of the rows ``array = [offsets | -normals]`` as given;
    the irredundant rows are then read from the incidence instead of cddlib's canonical
    form (one LP per row).  For a bounded full-dimensional polytope a row is a facet
    exactly when the vertices on its plane are not a proper subset of those on another
    row (a lower face lies in a facet with more vertices) and not all of them (an
    implicit equality); of rows with the same vertices (one plane) the canonical form
    keeps the last.  Taken only when every decision is clear: no rays or lines, every
    slack at most :data:`_ON_PLANE` or at least :data:`_OFF_PLANE`, no row on every vertex
    and no two vertices on the same rows (a vertex is where its rows meet).  None otherwise
    (an unbounded, empty, flat or borderline set: the caller canonicalises).  The third
    item says whether the vertices are certainly all of them (:func:`_closed`).
    """
    k, r = array.shape[0], array.shape[1] - 1
    if k > 52:  # the vertices' rows as exact sums of powers of 2 below
        return None
    try:
        generators = cdd.copy_generators(
            cdd.polyhedron_from_matrix(
                cdd.matrix_from_array(array.tolist(), rep_type=cdd.RepType.INEQUALITY)
            )
        )
    except RuntimeError:
        return None
    rows = generators.array
    if len(rows) <= r or generators.lin_set or any(row[0] != 1.0 for row in rows):
        return None  # empty, flat, unbounded or scaled: the canonical path decides
    points = np.array(rows, dtype=float)
    slack = array @ points.T  # (k, V): b_i - a_i . y for the points [1 | y]
    if slack.min() < -_ON_PLANE:
        return None  # a point outside a row: rows cddlib merged (nearly parallel)
    on = slack <= _ON_PLANE
    if np.count_nonzero(on) != np.count_nonzero(slack < _OFF_PLANE):
        return None  # a slack between the two: borderline
    incidence = on.astype(float)
    count = incidence.sum(axis=1)
    keys = np.sort(_POWERS[:k] @ incidence)  # each vertex's rows as one number
    if count.max() >= len(rows) or not bool((keys[1:] > keys[:-1]).all()):
        return None  # an implicit equality, or two vertices on the same rows
    # Row i's vertices all on row j, with j later in the order (count, index): row i is
    # a lower face (fewer vertices) or the same plane again (kept once, the last).
    within = incidence @ incidence.T == count[:, None]
    order = count * k + _INDICES[:k]
    facet = ~(within & (order[None, :] > order[:, None])).any(axis=1)
    return array[facet], points, _closed(incidence, r)


def _closed(incidence: NDArray[np.float64], r: int) -> bool:
    """Whether the vertices found are all of a simple polytope's (rows x vertices incidence).

    In a simple r-polytope every vertex is on r rows and has r edges, each to the vertex
    that shares all but one of its rows; the edges connect every vertex.  So the vertices
    found (each a true vertex: feasible, on r rows) are all of them when each has its r
    neighbours among them: a missed vertex would leave an edge of a found one unmatched.
    False when the polytope is not simple (another check decides then).
    """
    per_vertex = incidence.sum(axis=0)
    if not bool((per_vertex == r).all()):
        return False
    shared = incidence.T @ incidence  # rows two vertices share
    neighbours = np.count_nonzero(shared == r - 1, axis=1)
    return bool((neighbours == r).all())


_POWERS = 2.0 ** np.arange(52)
_INDICES = np.arange(52, dtype=float)


def _by_qhull(
    offsets: NDArray[np.float64], normals: NDArray[np.float64], cause: Exception
) -> Description:
    """The double description of a bounded set with the interior point 0, by Qhull."""
    from scipy.optimize import linprog
    from scipy.spatial import HalfspaceIntersection, QhullError

    r = normals.shape[1]
    for sign in (1.0, -1.0):  # bounded? (each coordinate bounded both ways)
        for i in range(r):
            cost = np.zeros(r)
            cost[i] = sign
            if linprog(cost, normals, offsets, bounds=[(None, None)] * r).status == 3:
                raise SolverError(
                    f"half-spaces to vertices: cddlib failed ({cause}) on an unbounded set, "
                    "where Qhull cannot stand in."
                ) from cause
    if not offsets.min() > 0:
        raise SolverError(f"half-spaces to vertices: cddlib failed ({cause}).") from cause
    halfspaces = np.hstack([normals, -offsets[:, None]])
    try:
        hull = HalfspaceIntersection(halfspaces, np.zeros(r))
        vertices = np.unique(np.round(hull.intersections, 12), axis=0)
    except (QhullError, ValueError) as exn:
        # A "dupridge" where many rows meet at a vertex (6-D): joggled input, each point
        # then solved again on the rows within JOGGLE_REACH times the joggle's reach (the
        # largest r-th smallest slack) and kept once per set of rows; the caller checks.
        try:
            hull = HalfspaceIntersection(halfspaces, np.zeros(r), qhull_options="QJ")
        except (QhullError, ValueError):
            raise SolverError(
                f"half-spaces to vertices: cddlib ({cause}) and Qhull failed."
            ) from exn
        vertices = _snapped(normals, offsets, hull.intersections)
    # A row is a facet when it holds at least r affinely independent vertices.
    return _description_of(vertices, normals, offsets)


def _snapped(
    normals: NDArray[np.float64], offsets: NDArray[np.float64], points: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Vertices of ``{y : normals y <= offsets}`` near joggled ones (V, r), each once.

    A point is solved again (least squares) on the rows within :data:`JOGGLE_REACH` times
    the joggle's reach (the largest r-th smallest slack of a point) where they have rank
    r, and kept where it then satisfies every row, once per set of rows through it; the
    others are dropped (the caller checks that none is missing).
    """
    r = normals.shape[1]
    n, o = _unit_rows(normals, offsets)
    slack = o[None, :] - points @ n.T
    reach = JOGGLE_REACH * float(np.abs(np.sort(slack, axis=1)[:, :r]).max(initial=0.0))
    close = slack <= reach
    found: dict[bytes, NDArray[np.float64]] = {}
    for j in np.sort(np.unique(_keys(close), return_index=True)[1]):  # each set of rows once
        near = close[j]
        if int(near.sum()) < r or _rank(n[near]) < r:
            continue
        y = np.linalg.lstsq(n[near], o[near], rcond=None)[0]
        after = o - n @ y
        on = _on_plane(o, y[None, :])[0]
        if bool((after < -on).any()):
            continue
        found.setdefault(np.packbits(after <= on).tobytes(), y)
    return np.array(list(found.values())).reshape(-1, r)


def _description_of(
    vertices: NDArray[np.float64], normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> Description:
    """The description of a bounded set from its vertices (V, r) and rows.

    A row is a facet when it holds r affinely independent vertices (to 1e-9 of the
    offsets' scale).
    """
    r = normals.shape[1]
    tight = np.abs(vertices @ normals.T - offsets) <= 1e-9 * max(1.0, float(offsets.max()))
    facets = [
        i
        for i in range(len(offsets))
        if tight[:, i].sum() >= r  # (first: no mean of an empty selection)
        and np.linalg.matrix_rank(vertices[tight[:, i]] - vertices[tight[:, i]].mean(0)) >= r - 1
    ]
    rows = np.hstack([offsets[facets, None], -normals[facets]])
    return rows, [], np.hstack([np.ones((len(vertices), 1)), vertices]), []


def _facet_cone_volume(points: NDArray[np.float64], rows: NDArray[np.float64]) -> float | None:
    """Volume of a full-dimensional polytope from its vertices (V, r) and facet rows (F, r + 1).

    ``sum_F h_F vol_(r-1)(F) / r``: cones from the vertices' mean ``c`` over the facets
    (rows ``[b | -a]``, ``h_F`` the distance of ``c`` to the facet's plane), each facet's
    volume by Qhull in its own plane (r - 1 coordinates, its vertices only), or where Qhull
    fails there by :func:`_face_volume`; a row through fewer than r affinely independent
    vertices is no facet and adds nothing.  Positive terms: no cancellation.  None where a
    vertex is outside a row by more than the tolerance (rows from another computation).
    """
    from scipy.spatial import ConvexHull, QhullError

    r = points.shape[1]
    normals, offsets = -rows[:, 1:], rows[:, 0]
    lengths = np.sqrt((normals * normals).sum(axis=1))
    normals, offsets = normals / lengths[:, None], offsets / lengths
    centre = points.mean(axis=0)
    heights = offsets - normals @ centre
    slack = offsets[None, :] - points @ normals.T
    tol = 1e-9 * max(1.0, float(np.abs(points).max()))
    if float(slack.min()) < -tol:
        return None
    tight = slack <= tol  # (V, F)
    total = 0.0
    for i in range(len(offsets)):
        face = points[tight[:, i]]
        plane = np.linalg.svd(normals[i][None, :], full_matrices=True)[2][1:].T  # (r, r - 1)
        local = (face - face.mean(axis=0)) @ plane
        if len(face) < r or np.linalg.matrix_rank(local, tol=tol) < r - 1:
            continue  # a lower face: no facet
        if r == 2:
            area = float(local.max() - local.min())
        else:
            try:
                area = float(ConvexHull(local).volume)
            except QhullError:
                area = _face_volume(local, tight[tight[:, i]], r - 1)
        total += float(heights[i]) * area / r
    return total


def _face_volume(points: NDArray[np.float64], tight: NDArray[np.bool_], k: int) -> float:
    """k-volume of the convex hull of ``points`` (V, k) from its facet incidence ``tight``.

    The sum over the facets of cones from the centroid, ``h vol_(k-1)(facet) / k``, each
    facet's volume by the same sum one dimension down (its own facets are its intersections
    with the other facets, of dimension k - 2).  Exact to rounding where Qhull's merging
    fails (a "dupridge" among many nearly coplanar facets in 6-D).
    """
    return _cone_sum(points, tight, tuple(range(len(points))), k)


def _cone_sum(
    points: NDArray[np.float64], tight: NDArray[np.bool_], rows: tuple[int, ...], k: int
) -> float:
    face = points[list(rows)]
    centre = face.mean(axis=0)
    if k == 1:
        return float(np.linalg.norm(face - face[0], axis=1).max())
    basis = np.linalg.svd(face - centre, full_matrices=False)[2][:k]  # the face's span
    scale = max(1.0, float(np.abs(face - centre).max()))
    total, seen = 0.0, set()
    for column in tight.T:
        sub = tuple(row for row in rows if column[row])
        if len(sub) < k or sub in seen:
            continue
        local = (points[list(sub)] - centre) @ basis.T  # (S, k)
        middle = local.mean(axis=0)
        _, sigma, span = np.linalg.svd(local - middle, full_matrices=True)
        if len(sigma) < k - 1 or sigma[k - 2] <= 1e-9 * scale:
            continue  # not a facet of this face (fewer dimensions)
        seen.add(sub)
        height = abs(float(middle @ span[k - 1]))  # the centre's distance to its hull
        total += height * _cone_sum(points, tight, sub, k - 1) / k
    return total


#: A facet of the vertices' hull counts as a row's plane when its unit normal and offset
#: are within this of the row's (whitened units: offsets at most 1).  Then every point of
#: the set lies within ``(1 + R) CERTIFIED`` of the hull (R: the largest vertex norm).
CERTIFIED = 1e-8
#: A joggled half-space intersection's point is on the rows whose slack is at most this
#: times the largest r-th smallest slack of any of its points (how far the joggle moved
#: them), before it is solved again on them.
JOGGLE_REACH = 10.0
#: Row subsets the last fallback (every r rows solved) may try.
MAX_SUBSETS = 200_000


def _hull_if_complete(
    points: NDArray[np.float64],
    normals: NDArray[np.float64],
    offsets: NDArray[np.float64],
    joggle: bool = False,
) -> float | None:
    """The volume of the hull of ``points`` (V, r) if it is all of ``{y : normals y <= offsets}``.

    The points must satisfy every row (to :data:`CERTIFIED`), so that their hull lies in
    the set; the set lies in the hull when every facet of the hull is (to
    :data:`CERTIFIED`) the plane of a row, since the set is on the inner side of every
    row.  A vertex a floating-point enumeration missed leaves a facet of the hull across
    the set, on no row's plane: None then (and when the points do not span r dimensions).
    Qhull computes the hull, exactly (its merges), or with ``joggle`` by joggled input;
    :class:`~scipy.spatial.QhullError` where it fails (a "dupridge" in 6-D).  A joggled
    hull splits a facet of more than r vertices into simplices, slivers among them with
    normals on no row: only a simplicial set passes there.
    """
    from scipy.spatial import ConvexHull

    r = normals.shape[1]
    norms = np.sqrt((normals * normals).sum(axis=1))
    kept = norms > 0
    unit, reach = normals[kept] / norms[kept, None], offsets[kept] / norms[kept]
    if len(points) and float((points @ unit.T - reach).max()) > CERTIFIED:
        return None  # a point outside a row: not a vertex of this set
    if r < 2 or len(points) < r + 1:  # (an interval is always walked: never checked here)
        return None
    hull = ConvexHull(points, qhull_options="QJ") if joggle else ConvexHull(points)
    facet_normals, facet_offsets = hull.equations[:, :r], -hull.equations[:, r]
    on_row = np.zeros(len(facet_offsets), dtype=bool)
    for start in range(0, len(unit), 64):  # (facets, rows, r) differences, a few rows at a time
        rows = slice(start, start + 64)
        close = np.abs(facet_normals[:, None, :] - unit[None, rows, :]).max(axis=-1) <= CERTIFIED
        close &= np.abs(facet_offsets[:, None] - reach[None, rows]) <= CERTIFIED
        on_row |= close.any(axis=1)
    return float(hull.volume) if on_row.all() else None


def _by_enumeration(offsets: NDArray[np.float64], normals: NDArray[np.float64]) -> Description:
    """The vertices of a bounded ``{y : normals y <= offsets}`` from every r rows, and its facets.

    Every r-subset of rows is solved (in batches) and its point kept where every row holds
    to rounding; a row is a facet when it holds r affinely independent vertices.  The last
    resort of :class:`HPolytope` where the floating-point enumerations miss a vertex (rows
    at angles near cddlib's epsilon), for up to :data:`MAX_SUBSETS` subsets (the caller's
    check).
    """
    from itertools import combinations

    k, r = normals.shape
    found = []
    subsets = np.array(list(combinations(range(k), r)), dtype=int).reshape(-1, r)
    for start in range(0, len(subsets), 4096):
        chosen = subsets[start : start + 4096]
        blocks, rhs = normals[chosen], offsets[chosen]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            det = np.linalg.det(blocks)
        scale = np.prod(np.sqrt((blocks * blocks).sum(axis=-1)), axis=-1)
        solvable = np.abs(det) > 1e-12 * scale
        if not solvable.any():
            continue
        y = np.linalg.solve(blocks[solvable], rhs[solvable][..., None])[..., 0]
        slack = offsets - y @ normals.T
        found.append(y[(slack >= -1e-9 * max(1.0, float(np.abs(offsets).max()))).all(axis=1)])
    vertices = np.concatenate(found) if found else np.zeros((0, r))
    if len(vertices):
        vertices = np.unique(np.round(vertices, 12), axis=0)
    return _description_of(vertices, normals, offsets)


def _checked(
    description: Description | None, normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> tuple[bool, float | None, Description | None]:
    """Whether cddlib's description of a set with the origin strictly inside holds.

    Not empty (the origin is inside), and where bounded (no rays, no equalities) every
    vertex there (:func:`_certified`).  Returns the verdict, the whitened volume of the
    hull that certified it (None where not computed) and the description, its points
    solved again on their rows where the edge graph certified them.
    """
    if description is None:
        return False, None, None
    rows, linear, points, paired = description
    if linear or not _is_point(points).all():  # unbounded: rays (not checked here)
        return True, None, description
    y, volume = _certified(points[:, 1:] / points[:, :1], normals, offsets)
    if y is None:
        return False, None, description
    return True, volume, (rows, linear, np.hstack([np.ones((len(y), 1)), y]), paired)


def _certified(
    points: NDArray[np.float64], normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> tuple[NDArray[np.float64] | None, float | None]:
    """The vertices (V, r) of ``{y : normals y <= offsets}`` if ``points`` are all of them.

    Certified by the hull of the points (:func:`_hull_if_complete`, which also gives the
    whitened volume), or where that fails, by the edge graph (:func:`_edge_closed`, the
    points then solved again on their rows): Qhull may not build the hull exactly (a
    "dupridge" among many coplanar vertices in 6-D, where its joggled hull has sliver
    facets on no row and rejects a complete answer), or merge facets off their rows.  A
    joggled hull last, where the exact one failed.  None where none certifies them.
    """
    from scipy.spatial import QhullError

    try:
        volume = _hull_if_complete(points, normals, offsets)
        built = True
    except QhullError:
        volume, built = None, False
    if volume is not None:
        return points, volume
    y = _edge_closed(points, normals, offsets)
    if y is not None or built:
        return y, None
    try:  # (after the edge graph: a joggled hull certifies only a simplicial set)
        volume = _hull_if_complete(points, normals, offsets, joggle=True)
    except QhullError:
        volume = None
    return (None, None) if volume is None else (points, volume)


def _complete(
    offsets: NDArray[np.float64], normals: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], float | None]:
    """Facet rows and vertices where cddlib missed some: every r rows, else Qhull (checked).

    The enumeration is complete by construction; Qhull's half-space intersection stands
    in where it has too many subsets, and must pass the same check as cddlib.  The third
    item is the whitened volume of the checking hull (None after the enumeration).
    """
    k, r = normals.shape
    if math.comb(k, r) <= MAX_SUBSETS:
        rows, _, points, _ = _by_enumeration(offsets, normals)
        return rows, points[:, 1:], None
    cause = SolverError("cddlib missed vertices of a full-dimensional set")
    rows, _, points, _ = _by_qhull(offsets, normals, cause)
    y, volume = _certified(points[:, 1:], normals, offsets)
    if y is None:
        raise SolverError(
            f"half-spaces to vertices: cddlib and Qhull missed vertices of this set ({k} "
            f"half-spaces in {r} dimensions, too many to try every {r} of them); express "
            "it with fewer half-spaces or report it."
        )
    return rows, y, volume


def _rank(normals: NDArray[np.float64]) -> int:
    """The rank of unit rows (t, r), by :data:`RANK_RTOL` of the largest singular value."""
    sigma = np.linalg.svd(normals, compute_uv=False)
    return int(np.count_nonzero(sigma > RANK_RTOL * sigma[0])) if len(sigma) else 0


def _edge_closed(
    points: NDArray[np.float64], normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> NDArray[np.float64] | None:
    """The vertices (V, r) of a bounded ``{y : normals y <= offsets}`` if ``points`` are all.

    Each point, solved again on the rows through it (:func:`_polish`), must be a vertex
    (rows of rank r).  The points are all the vertices when, at each, the directions to the
    others it shares an edge with (rows of rank r - 1 through both) generate its whole
    tangent cone ``{d : N_T d <= 0}`` (:func:`_spans_cone`): every extreme ray of that
    cone is then the direction to a point found, which lies on the edge of the set along
    it (inside the set) and, a vertex, is the edge's other end; the vertices found are
    closed under the edges of the set, whose graph is connected.  A missed vertex leaves
    the cone of a neighbour's directions short of an edge.  Exact combinatorics, no hull
    of the points: it holds where Qhull's merging fails.  None where not certified (a
    decision too close to call, a vertex with too many neighbours to try every r - 1 of
    them, or a vertex missing).
    """
    r = normals.shape[1]
    if r < 2 or len(points) < r + 1:
        return None
    n, o = _unit_rows(normals, offsets)
    try:
        y, tight = _polish(n, o, points)
    except _Ambiguous:
        return None
    keys = _keys(tight)
    first = np.sort(np.unique(keys, return_index=True)[1])  # a point on the same rows: once
    y, tight = y[first], tight[first]
    incidence = tight.astype(np.float64)
    shared = incidence @ incidence.T  # (V, V): the rows through both
    np.fill_diagonal(shared, 0.0)
    for v in range(len(y)):
        through = n[tight[v]]
        if _rank(through) < r:
            return None  # not a vertex, to rounding
        near = [
            u
            for u in np.flatnonzero(shared[v] >= r - 1)
            if _rank(n[tight[v] & tight[u]]) == r - 1  # an edge: their common face a segment
        ]
        D = y[near] - y[v]
        lengths = np.sqrt((D * D).sum(axis=1))
        if not len(near) or lengths.min() <= 0.0:
            return None
        if not _spans_cone(D / lengths[:, None], through):
            return None
    return y


def _spans_cone(rays: NDArray[np.float64], normals: NDArray[np.float64]) -> bool:
    """Whether unit ``rays`` (p, r) generate all of ``{d : normals d <= 0}`` (unit rows).

    :func:`_cone_is` with each facet of the rays' cone on a row's plane to
    :data:`CERTIFIED` (unit normals within it of a row's, as the hull check's facets)
    rather than to an angle of sqrt(2 WALK_ON_PLANE): a vertex missed past a thin sliver
    leaves a facet that far off every row.
    """
    p, r = rays.shape
    if float((rays @ normals.T).max()) > WALK_ON_PLANE or math.comb(p, r - 1) > MAX_CONE_SUBSETS:
        return False
    facets, _ = _supporting(rays, rays)
    if not len(facets):
        return False
    gap = np.abs(facets[:, None, :] - normals[None, :, :]).max(axis=-1).min(axis=1)
    return bool((gap <= CERTIFIED).all())


# --- the hull of points (HPolytope.from_vertices) ------------------------------------------

#: Whitened units of :meth:`HPolytope.from_vertices` (the farthest point at distance 1): a
#: point is on a facet's plane when its slack is at most this; two points this close are
#: one; two planes whose unit normals and offsets are this close are one (a facet that
#: Qhull split in two).
HULL_TOL = 1e-9
#: A facet's points span r - 1 dimensions when their (r - 1)-th singular value about their
#: mean is above this (whitened units; a sliver facet of points close along a curve is
#: thinner than HULL_TOL, a lower face's points are flat to rounding, about 1e-16).
SPAN_TOL = 1e-14
#: A point's facets span R^r (it is a vertex) when the r-th singular value of their unit
#: normals is above this (those through an edge are dependent to the rounding of the
#: normals, about 1e-15).
VERTEX_TOL = 1e-11
#: The incidence of points on a hull and its facets is a boolean matrix of at most this
#: many entries (bytes); beyond, the hull is refused with an InputError.
MAX_INCIDENCE = 400_000_000
#: cddlib's V-to-H conversion stands in for Qhull for at most this many points.
MAX_CDD_POINTS = 2_000


class _Hull(NamedTuple):
    """Certified facets ``normals y <= offsets`` (unit normals) of the hull of points."""

    normals: NDArray[np.float64]
    offsets: NDArray[np.float64]
    vertices: NDArray[np.int_]  # the points that are vertices
    volume: float | None  # Qhull's volume of the hull, where its exact hull gave the facets


def _distinct_points(y: NDArray[np.float64]) -> NDArray[np.int_]:
    """Indices of the points (V, r), each once within :data:`HULL_TOL` (the first kept)."""
    from scipy.spatial import cKDTree

    first = np.sort(np.unique(y, axis=0, return_index=True)[1])
    pairs = cKDTree(y[first]).query_pairs(HULL_TOL, output_type="ndarray")
    later = np.zeros(len(first), dtype=bool)
    later[pairs.max(axis=1)] = True
    return first[~later]


def _hull_of_points(y: NDArray[np.float64]) -> _Hull:
    """The facets and vertices of the hull of points ``y`` (V, r) spanning R^r, certified.

    Qhull's hull (its exact merges, then joggled input) where :func:`_qhull_facets`
    certifies it, else cddlib's V-to-H conversion where :func:`_certified_facets` does
    (up to :data:`MAX_CDD_POINTS` points); a :class:`SolverError` otherwise.  The vertices
    are the points on facets whose normals span R^r.
    """
    from scipy.spatial import ConvexHull, QhullError

    from polyell.geometry.cddlib import halfspaces_from_vertices

    r = y.shape[1]
    if r == 1:
        lo, hi = int(np.argmin(y[:, 0])), int(np.argmax(y[:, 0]))
        normals, offsets = np.array([[1.0], [-1.0]]), np.array([y[hi, 0], -y[lo, 0]])
        return _Hull(normals, offsets, np.array([lo, hi]), float(y[hi, 0] - y[lo, 0]))
    for options in (None, "QJ"):
        try:
            hull = ConvexHull(y) if options is None else ConvexHull(y, qhull_options=options)
        except (QhullError, ValueError):
            continue
        qhull = _qhull_facets(y, hull)
        if qhull is not None:
            volume = float(hull.volume) if options is None else None
            return _Hull(*qhull, volume)
    facets = None
    if len(y) <= MAX_CDD_POINTS:  # (cddlib's time grows fast with the points)
        try:
            A, b = halfspaces_from_vertices(y)
        except RuntimeError:
            pass
        else:
            facets = _certified_facets(y, A, b)
    if facets is None:
        raise SolverError(
            f"the hull of {len(y)} points in {r} dimensions: neither Qhull's nor cddlib's "
            "facets could be certified (a facet missing or on too few points); report it."
        )
    return _Hull(*facets, None)


def _qhull_facets(
    y: NDArray[np.float64], hull: object
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int_]] | None:
    """The facets and vertices of Qhull's hull of ``y`` (V, r), or None unless certified.

    Certified: its simplices (its facets triangulated) are distinct and close up (every
    r - 1 of a simplex's points are in exactly two simplices), and every point is within
    :data:`HULL_TOL` below the plane of each (the offset is then moved to the farthest
    point), whose own points are on it: a closed surface of supporting simplices is the
    whole boundary of the hull, so no facet is missing.  The simplices of one plane
    (Qhull's merged facets) make one facet, whose points must span r - 1 dimensions.  The
    vertices: the points of the simplices whose facets' normals span R^r.
    """
    r = y.shape[1]
    simplices = np.sort(np.asarray(hull.simplices, dtype=np.int64), axis=1)  # type: ignore[attr-defined]
    equations = np.asarray(hull.equations)  # type: ignore[attr-defined]
    if not len(simplices) or len(np.unique(simplices, axis=0)) != len(simplices):
        return None
    ridges = np.concatenate([np.delete(simplices, j, axis=1) for j in range(r)])
    if not bool((np.unique(ridges, axis=0, return_counts=True)[1] == 2).all()):
        return None  # not closed: a simplex missing (or a ridge on three)
    normals = equations[:, :r]
    lengths = np.sqrt((normals * normals).sum(axis=1))
    if not bool((lengths > 0).all()):
        return None
    normals = normals / lengths[:, None]
    offsets = _support(y, normals)
    own = offsets[:, None] - np.einsum("skr,sr->sk", y[simplices], normals)  # (S, r) >= 0
    if float(own.max()) > HULL_TOL or float((offsets + equations[:, r] / lengths).max()) > HULL_TOL:
        return None  # a simplex off its plane, or a point beyond it
    # one facet per plane (Qhull's merged facets come triangulated)
    keys = np.round(np.hstack([normals, offsets[:, None]]) / HULL_TOL) * HULL_TOL
    _, first, label = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    label = label.reshape(-1)
    F, V = len(first), len(y)
    _check_incidence(V, F)
    incidence = np.zeros((V, F), dtype=bool)
    incidence[simplices, label[:, None]] = True
    spans = [np.flatnonzero(incidence[:, f]) for f in range(F)]
    for points in spans:
        local = y[points] - y[points].mean(axis=0)
        if len(points) < r or np.linalg.svd(local, compute_uv=False)[r - 2] <= SPAN_TOL:
            return None
    n, o = normals[first], offsets[first]
    return n, o, _vertex_points(n, incidence)


def _check_incidence(points: int, facets: int) -> None:
    """Refuse a hull whose incidence matrix would exceed :data:`MAX_INCIDENCE` entries."""
    if points * facets > MAX_INCIDENCE:
        raise InputError(
            "vertices",
            f"a hull of at most {MAX_INCIDENCE:.0e} pairs of a point and a facet",
            f"{points} points and {facets} facets",
            "thin the points out (e.g. keep the vertices of scipy.spatial.ConvexHull).",
        )


def _support(y: NDArray[np.float64], normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """``max_i normals . y_i`` of each normal (F, r) over the points (V, r), a block at a time."""
    out = np.full(len(normals), -np.inf)
    for start in range(0, len(y), 2048):
        out = np.maximum(out, (y[start : start + 2048] @ normals.T).max(axis=0))
    return out


def _certified_facets(
    y: NDArray[np.float64], normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int_]] | None:
    """The facets of the hull of ``y`` (V, r) from candidate planes, and its vertices; or None.

    Each plane is moved to the farthest point along its normal (so that every point
    satisfies it), planes that coincide are merged (refitted to the points on them), and
    repeats dropped.  None unless certified: every facet holds points spanning r - 1
    dimensions, and every ridge of every facet (from the facet's own points) lies on
    another facet.  A missing facet would leave the ridges around it on one facet only;
    a candidate that is no facet spans fewer dimensions.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    r = y.shape[1]
    _check_incidence(len(y), len(normals))
    lengths = np.sqrt((normals * normals).sum(axis=1))
    if not len(normals) or not bool((lengths > 0).all()):
        return None
    n = normals / lengths[:, None]
    o = (y @ n.T).max(axis=0)
    keys = np.hstack([n, o[:, None]])
    pairs = cKDTree(keys).query_pairs(HULL_TOL, p=np.inf, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(n), len(n)))
    _, label = connected_components(graph, directed=False)
    first = np.unique(label, return_index=True)[1]
    n, o = n[first], o[first]
    for group in np.flatnonzero(np.bincount(label) > 1):  # planes Qhull split: one fit
        members = label == group
        on = (o[group] - y @ n[group] <= HULL_TOL) | (
            ((keys[members, r] - y @ keys[members, :r].T) <= HULL_TOL).any(axis=1)
        )
        points = y[on]
        fitted = np.linalg.svd(points - points.mean(axis=0))[2][-1]
        n[group] = fitted if fitted @ n[group] > 0 else -fitted
        o[group] = float((y @ n[group]).max())
    tight = (o[None, :] - y @ n.T) <= HULL_TOL  # (V, F)
    unique = np.unique(np.packbits(tight, axis=0), axis=1, return_index=True)[1]
    keep = np.sort(unique)
    n, o, tight = n[keep], o[keep], tight[:, keep]
    ridges = _ridges(y, n, tight)
    if ridges is None or not _ridges_shared(ridges, tight):
        return None
    return n, o, _vertex_points(n, tight)


def _ridges(
    y: NDArray[np.float64], n: NDArray[np.float64], tight: NDArray[np.bool_]
) -> list[NDArray[np.int_]] | None:
    """Every ridge of every facet, as point indices (groups of one size stacked).

    A facet on r points: its r subsets of r - 1; on more: the facets of their hull within
    the facet's plane (the points within :data:`HULL_TOL` of each).  None where a facet's
    points span fewer than r - 1 dimensions (by :data:`SPAN_TOL`: it is no facet).
    """
    from scipy.spatial import ConvexHull, QhullError

    r = y.shape[1]
    count = tight.sum(axis=0)
    if int(count.min()) < r:
        return None
    found: dict[int, list[tuple[int, ...]]] = {}
    simple = np.flatnonzero(count == r)
    if len(simple):
        points = np.nonzero(tight[:, simple].T)[1].reshape(-1, r)  # (S, r), sorted
        span = y[points] - y[points].mean(axis=1, keepdims=True)
        sigma = np.linalg.svd(span, compute_uv=False)
        if bool((sigma[:, r - 2] <= SPAN_TOL).any()):
            return None
        for drop in range(r):
            found.setdefault(r - 1, []).extend(map(tuple, np.delete(points, drop, axis=1)))
    for f in np.flatnonzero(count > r):
        on = np.flatnonzero(tight[:, f])
        local = y[on] - y[on].mean(axis=0)
        _, sigma, vt = np.linalg.svd(local, full_matrices=True)
        if sigma[r - 2] <= SPAN_TOL:
            return None
        plane = local @ vt[: r - 1].T  # (k, r - 1): coordinates in the facet's plane
        if r == 2:
            faces = [plane[:, 0] <= plane[:, 0].min() + HULL_TOL]
            faces.append(plane[:, 0] >= plane[:, 0].max() - HULL_TOL)
        else:
            equations = None
            for options in (None, "QJ"):
                try:
                    hull = (
                        ConvexHull(plane)
                        if options is None
                        else ConvexHull(plane, qhull_options=options)
                    )
                except (QhullError, ValueError):
                    continue
                equations = hull.equations
                break
            if equations is None:
                return None
            lengths = np.sqrt((equations[:, :-1] ** 2).sum(axis=1))
            height = (-equations[:, -1] / lengths)[None, :] - plane @ (
                equations[:, :-1] / lengths[:, None]
            ).T
            height = (
                height - np.minimum(height.min(axis=0), 0.0)[None, :]
            )  # (its offset: the farthest)
            faces = list((height <= HULL_TOL).T)
        for face in faces:
            ridge = tuple(on[face])
            if len(ridge) < r - 1:
                return None
            found.setdefault(len(ridge), []).append(ridge)
    return [np.unique(np.array(group), axis=0) for group in found.values()]


def _ridges_shared(ridges: list[NDArray[np.int_]], tight: NDArray[np.bool_]) -> bool:
    """Whether every ridge (point indices) lies on two facets or more (``tight``, (V, F))."""
    bits = np.packbits(tight, axis=1)  # (V, F / 8): a point's facets, 8 to a byte
    for group in ridges:
        for start in range(0, len(group), 4096):
            block = group[start : start + 4096]
            on = bits[block[:, 0]]
            for j in range(1, block.shape[1]):
                on = on & bits[block[:, j]]
            if int(_BITS_SET[on].sum(axis=1, dtype=np.int64).min()) < 2:
                return False
    return True


#: The number of bits set in each byte (numpy before 2.0 has no bitwise_count).
_BITS_SET = np.array([bin(byte).count("1") for byte in range(256)], dtype=np.uint8)


def _vertex_points(n: NDArray[np.float64], tight: NDArray[np.bool_]) -> NDArray[np.int_]:
    """The points (rows of ``tight``, (V, F)) on facets whose unit normals span R^r."""
    r = n.shape[1]
    vertices = []
    for i in np.flatnonzero(tight.sum(axis=1) >= r):
        sigma = np.linalg.svd(n[tight[i]], compute_uv=False)
        if sigma[r - 1] > VERTEX_TOL:
            vertices.append(i)
    return np.array(vertices, dtype=int)


# --- vertex enumeration by walking the edges ---------------------------------------------
#
# A pointed polyhedron {y : N y <= o} with the origin strictly inside (o > 0) has a connected
# graph of vertices and bounded edges, and each extreme ray is the direction of an unbounded
# edge at some vertex.  From one vertex, every edge of every vertex reached is followed (a
# ratio test along it) until no new vertex appears; then all of them are found, whatever a
# floating-point double description would have rounded away.  The edges of a vertex are the
# extreme rays of its tangent cone {d : N_T d <= 0} (T: the rows through it): the columns of
# -N_T^-1 at a simple vertex (r rows), and at a degenerate one every r - 1 of its rows tried,
# or cddlib's rays checked (each facet of their cone on the plane of a row through the
# vertex); beyond that, the decision is cddlib's for the whole set.

#: A row passes through a point y when its slack is at most this times (the row's own offset
#: + |y|), the size of the terms the slack is computed from: relative to the set's size, so
#: that scaling A or b changes nothing but the scale, and to each row's, so that a redundant
#: row however far (whose offset is no scale of the set) widens no other row's plane.
WALK_ON_PLANE = 1e-9
#: A step (or a generator of cddlib) reaching farther than this times the set's scale (its
#: farthest row from the interior point, plus the point's own size) is a direction: the
#: rank rule for rays, as a line is a direction along which the rows' slopes are at most
#: ``RANK_RTOL`` of the largest.
FAR_RATIO = 1.0 / RANK_RTOL
#: Subsets of r - 1 rows (or rays) that the exact enumeration (or the check) of one
#: tangent cone may try; beyond, cddlib decides for the whole set.
MAX_CONE_SUBSETS = 20_000
#: Up to this many subsets, every r - 1 rows are tried first (cheaper than cddlib then).
FEW_CONE_SUBSETS = 64


class _Walk(NamedTuple):
    """The generators of a pointed polyhedron found by :func:`_walk_polyhedron`.

    Attributes
    ----------
    points : ndarray, shape (V, r)
        The vertices, each solved again on the rows through it.
    rays : ndarray, shape (R, r)
        The extreme rays, unit vectors.
    tight : ndarray of bool, shape (V, k)
        The rows through each vertex.
    ray_tight : ndarray of bool, shape (R, k)
        The rows whose planes hold each ray.
    edges : ndarray of int, shape (E, 2), or None
        The bounded edges, as pairs of vertex indices (None: not known).
    """

    points: NDArray[np.float64]
    rays: NDArray[np.float64]
    tight: NDArray[np.bool_]
    ray_tight: NDArray[np.bool_]
    edges: NDArray[np.int_] | None


class _Ambiguous(Exception):
    """A decision the walk's tolerances cannot make (the caller falls back to cddlib)."""


def _walk_polyhedron(normals: NDArray[np.float64], offsets: NDArray[np.float64]) -> _Walk | None:
    """Vertices, extreme rays and edges of ``{y : normals y <= offsets}`` by its edge graph.

    Parameters
    ----------
    normals : ndarray, shape (k, r)
        Rows of rank r (the set holds no line), none zero.
    offsets : ndarray, shape (k,)
        Positive offsets: the origin is strictly inside.

    Returns
    -------
    _Walk or None
        None where a decision is too close to call: a point on nearly dependent rows, a
        step of length zero, a tangent cone that is not pointed to rounding.
    """
    try:
        return _walk(normals, offsets)
    except _Ambiguous:
        return None


def _unit_rows(
    normals: NDArray[np.float64], offsets: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rows scaled to unit normals (offsets: distances from the origin)."""
    lengths = np.sqrt((normals * normals).sum(axis=1))
    return normals / lengths[:, None], offsets / lengths


def _on_plane(offsets: NDArray[np.float64], points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The slack under which each row (offsets (k,)) passes through each point (V, r): (V, k).

    Each row's own offset and not the largest: a vertex is on r rows whose offsets are at
    most its norm, so that the tolerance is about ``WALK_ON_PLANE |y|`` where it matters,
    whereas a far redundant row's offset (1e9 times the set's size) would make it the
    size of the set and put every row through every point.
    """
    size = np.abs(points).max(axis=1, initial=0.0)
    return WALK_ON_PLANE * (np.abs(offsets)[None, :] + size[:, None])


def _keys(tight: NDArray[np.bool_]) -> list[bytes]:
    """Each point's rows as a dictionary key."""
    return [row.tobytes() for row in np.packbits(tight, axis=1)]


def _walk(normals: NDArray[np.float64], offsets: NDArray[np.float64]) -> _Walk:
    n, o = _unit_rows(normals, offsets)
    r = n.shape[1]
    scale = float(o.max())
    if r == 1:
        return _walk_line(n[:, 0], o)
    first, first_tight = _polish(n, o, _some_vertex(n, o, scale)[None, :])
    points, tights = [first[0]], [first_tight[0]]
    index = {_keys(first_tight)[0]: 0}
    edges: set[tuple[int, int]] = set()
    rays: list[NDArray[np.float64]] = []
    frontier = np.zeros(1, dtype=int)
    while len(frontier):  # breadth first, one frontier of vertices at a time
        here = np.array([points[i] for i in frontier])
        through = np.array([tights[i] for i in frontier])
        owners, directions = _edges_at(n, through)
        origin = here[owners]
        rate = directions @ n.T
        blocking = (rate > 0) & ~through[owners]  # the rows through a vertex stay behind
        slack = o[None, :] - origin @ n.T
        with np.errstate(divide="ignore", invalid="ignore"):
            steps = np.where(blocking, slack / np.where(blocking, rate, 1.0), np.inf)
        step = steps.min(axis=1)
        bounded = step <= FAR_RATIO * (scale + np.abs(origin).max(axis=1))
        rays.extend(directions[~bounded])
        ends = origin[bounded] + step[bounded, None] * directions[bounded]
        ids = np.array([index.get(key, -1) for key in _keys(_slack_tight(n, o, ends))], dtype=int)
        before = len(points)
        unknown = np.flatnonzero(ids < 0)
        if len(unknown):  # solved again on their rows, known by those rows
            found, found_tight = _polish(n, o, ends[unknown])
            for j, y, row, key in zip(unknown, found, found_tight, _keys(found_tight), strict=True):
                if key not in index:
                    index[key] = len(points)
                    points.append(y)
                    tights.append(row)
                ids[j] = index[key]
        for a, b in zip(frontier[owners[bounded]], ids, strict=True):
            if a == b:
                raise _Ambiguous  # a step of length zero: a row both through and off
            edges.add((int(min(a, b)), int(max(a, b))))
        frontier = np.arange(before, len(points))
    R = _unique_directions(np.array(rays).reshape(-1, r))
    return _Walk(
        np.array(points),
        R,
        np.array(tights),
        np.abs(R @ n.T) <= WALK_ON_PLANE,
        np.array(sorted(edges), dtype=int).reshape(-1, 2),
    )


def _slack_tight(
    n: NDArray[np.float64], o: NDArray[np.float64], points: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """The rows through each point (V, r), by :data:`WALK_ON_PLANE`: (V, k)."""
    return (o[None, :] - points @ n.T) <= _on_plane(o, points)


def _walk_line(n: NDArray[np.float64], o: NDArray[np.float64]) -> _Walk:
    """The one-dimensional case: an interval, a half-line (its ray) or nothing pointed."""
    up, down = n > 0, n < 0
    ends, rays = [], []
    if up.any():
        ends.append(float(np.min(o[up] / n[up])))
    else:
        rays.append(1.0)
    if down.any():
        ends.append(float(np.max(o[down] / n[down])))
    else:
        rays.append(-1.0)
    if not ends:
        raise _Ambiguous  # a line: not pointed
    points = np.array(ends).reshape(-1, 1)
    R = np.array(rays).reshape(-1, 1)
    edges = np.array([[0, 1]]) if len(points) == 2 else np.zeros((0, 2), dtype=int)
    tight = _slack_tight(n[:, None], o, points)
    return _Walk(points, R, tight, np.zeros((len(R), len(n)), dtype=bool), edges)


def _some_vertex(
    n: NDArray[np.float64], o: NDArray[np.float64], scale: float
) -> NDArray[np.float64]:
    """A vertex, reached from the origin by steps to the nearest rows within the rows hit."""
    k, r = n.shape
    y = np.zeros(r)
    goal = np.cos(np.arange(1, r + 1) * 1.234567)  # a fixed direction in general position
    tight = np.zeros(k, dtype=bool)
    for _ in range(2 * r + 2):
        through = n[tight]
        if len(through):
            _, sigma, vt = np.linalg.svd(through, full_matrices=True)
            rank = int(np.count_nonzero(sigma > RANK_RTOL * sigma[0]))
            if rank == r:
                return y
            free = vt[rank:].T
        else:
            free = np.eye(r)
        d = free @ (free.T @ goal)
        d = d if np.linalg.norm(d) > 1e-3 else free[:, 0]
        d = d / np.linalg.norm(d)
        for sign in (1.0, -1.0):
            rate = sign * (n @ d)
            blocking = (rate > 0) & ~tight
            if blocking.any():
                step = float(np.min((o - n @ y)[blocking] / rate[blocking]))
                if step <= FAR_RATIO * (scale + float(np.abs(y).max())):
                    break
        else:
            raise _Ambiguous  # a line through the point, to rounding
        y = y + step * sign * d
        tight = _slack_tight(n, o, y[None, :])[0]
    raise _Ambiguous


def _polish(
    n: NDArray[np.float64], o: NDArray[np.float64], points: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Points (V, r) solved again on the rows through them; those rows after, (V, k)."""
    r = n.shape[1]
    tight = _slack_tight(n, o, points)
    count = tight.sum(axis=1)
    if count.min(initial=r) < r:
        raise _Ambiguous  # not a vertex
    out = np.empty_like(points)
    simple = count == r
    if simple.any():
        rows = np.nonzero(tight[simple])[1].reshape(-1, r)
        out[simple] = np.linalg.solve(n[rows], o[rows][..., None])[..., 0]
    for j in np.flatnonzero(~simple):
        out[j] = np.linalg.lstsq(n[tight[j]], o[tight[j]], rcond=None)[0]
    slack = o[None, :] - out @ n.T
    on = _on_plane(o, out)
    if (slack < -on).any():
        raise _Ambiguous  # outside a row once solved
    return out, slack <= on


def _edges_at(
    n: NDArray[np.float64], tight: NDArray[np.bool_]
) -> tuple[NDArray[np.int_], NDArray[np.float64]]:
    """The edge directions (unit) at vertices on the rows ``tight`` (V, k): owners, directions."""
    r = n.shape[1]
    count = tight.sum(axis=1)
    simple = np.flatnonzero(count == r)
    owners, directions = [], []
    if len(simple):
        blocks = n[np.nonzero(tight[simple])[1].reshape(-1, r)]
        sigma = np.linalg.svd(blocks, compute_uv=False)
        if (sigma[:, -1] <= RANK_RTOL * sigma[:, 0]).any():
            raise _Ambiguous  # a vertex on nearly dependent rows
        D = -np.swapaxes(np.linalg.inv(blocks), 1, 2).reshape(-1, r)  # -N_T^-1, by columns
        owners.append(np.repeat(simple, r))
        directions.append(D / np.sqrt((D * D).sum(axis=1))[:, None])
    for v in np.flatnonzero(count > r):
        D = _cone_rays(n[tight[v]])
        owners.append(np.full(len(D), v))
        directions.append(D)
    return np.concatenate(owners), np.vstack(directions)


def _cone_rays(normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """The extreme rays (unit) of the pointed cone ``{d : normals d <= 0}``.

    Parameters
    ----------
    normals : ndarray, shape (t, r)
        Unit rows of rank r.

    Returns
    -------
    ndarray, shape (p, r)
        Every r - 1 rows tried where they are few (exact: a ray is on r - 1 independent
        rows and inside); else cddlib's rays where they are certainly all of them
        (:func:`_simple_and_closed`, or every facet of their cone on a row's plane,
        :func:`_cone_is`); else every r - 1 rows up to :data:`MAX_CONE_SUBSETS`; beyond,
        :class:`_Ambiguous` (the caller's fallback: cddlib, or the hull of a sum's pairs).
    """
    t, r = normals.shape
    subsets = math.comb(t, r - 1)
    if subsets <= FEW_CONE_SUBSETS:
        return _cone_rays_by_subsets(normals)
    try:
        matrix = cdd.matrix_from_array(
            np.hstack([np.zeros((t, 1)), -normals]).tolist(), rep_type=cdd.RepType.INEQUALITY
        )
        found = np.array(cdd.copy_generators(cdd.polyhedron_from_matrix(matrix)).array, float)
    except RuntimeError:
        found = np.zeros((0, r + 1))
    found = found.reshape(-1, r + 1)
    found = found[~_is_point(found)]
    D = found[:, 1:] / np.sqrt((found[:, 1:] ** 2).sum(axis=1))[:, None]
    if len(D) >= r and float((D @ normals.T).max()) <= WALK_ON_PLANE:
        if _simple_and_closed(D, normals) or _cone_is(D, normals):
            return D
    if subsets <= MAX_CONE_SUBSETS:
        return _cone_rays_by_subsets(normals)
    raise _Ambiguous  # too many rows through one point to try every r - 1 of them


def _simple_and_closed(rays: NDArray[np.float64], normals: NDArray[np.float64]) -> bool:
    """Whether extreme rays found (p, r) of ``{d : normals d <= 0}`` are certainly all.

    When each is on exactly r - 1 rows, independent, the slice of the cone is a simple
    polytope of dimension r - 1 at every ray found, whose edges join rays sharing r - 2
    rows; they are all when each has its r - 1 neighbours among them (:func:`_closed`).
    """
    r = normals.shape[1]
    through = np.abs(rays @ normals.T) <= WALK_ON_PLANE  # (p, t)
    if not bool((through.sum(axis=1) == r - 1).all()):
        return False
    blocks = normals[np.nonzero(through)[1].reshape(-1, r - 1)]  # (p, r - 1, r)
    sigma = np.linalg.svd(blocks, compute_uv=False)
    if bool((sigma[:, -1] <= WALK_ON_PLANE * sigma[:, 0]).any()):
        return False
    return r == 2 or _closed(through.T.astype(float), r - 1)


def _cofactor_normals(blocks: NDArray[np.float64]) -> NDArray[np.float64]:
    """The normal of each block of r - 1 vectors (..., r - 1, r): its cofactors, (..., r)."""
    r = blocks.shape[-1]
    out = np.empty((*blocks.shape[:-2], r))
    for j in range(r):
        out[..., j] = (-1.0) ** j * np.linalg.det(blocks[..., _OTHER_COLUMNS[r][j]])
    return out


#: The columns but j, for each j, per dimension (the minors of the cofactors).
_OTHER_COLUMNS = {r: [[i for i in range(r) if i != j] for j in range(r)] for r in range(1, 16)}


def _supporting(
    vectors: NDArray[np.float64], others: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int_]]:
    """Unit normals ``a`` of every r - 1 of ``vectors`` (t, r) with ``others @ a <= 0``.

    Each is orthogonal to r - 1 independent vectors (cofactor length above
    :data:`WALK_ON_PLANE`: unit vectors at angles above it) and has every one of
    ``others`` on its side (to :data:`WALK_ON_PLANE`), its sign chosen so.  Returns the
    normals (p, r) and the subsets' indices (p, r - 1).
    """
    t, r = vectors.shape
    subsets = _subsets(t, r - 1)
    normals = _cofactor_normals(vectors[subsets])
    size = np.sqrt((normals * normals).sum(axis=1))
    independent = size > WALK_ON_PLANE
    normals, subsets = normals[independent] / size[independent, None], subsets[independent]
    dots = normals @ others.T
    below = (dots <= WALK_ON_PLANE).all(axis=1)
    above = (dots >= -WALK_ON_PLANE).all(axis=1)
    keep = below | above
    normals = normals[keep] * np.where(below[keep], 1.0, -1.0)[:, None]
    return normals, subsets[keep]


@lru_cache(maxsize=256)
def _subsets(t: int, q: int) -> NDArray[np.int_]:
    """Every q of t indices, (C(t, q), q), read-only (cached)."""
    from itertools import combinations

    table = np.array(list(combinations(range(t), q)), dtype=int).reshape(-1, q)
    table.flags.writeable = False
    return table


def _cone_rays_by_subsets(normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """Extreme rays of ``{d : normals d <= 0}``: null directions of r - 1 rows, inside."""
    rays, _ = _supporting(normals, normals)
    rays = _unique_directions(rays)  # normals d <= 0: the rays themselves
    if len(rays) < normals.shape[1]:
        raise _Ambiguous  # not a pointed full-dimensional cone, to rounding
    return rays


def _cone_is(rays: NDArray[np.float64], normals: NDArray[np.float64]) -> bool:
    """Whether ``cone(rays)`` is all of ``{d : normals d <= 0}`` (the rays found inside it).

    It is inside; it is all of it when each of its facets lies on the plane of a row, the
    cone being on the inner side of every row.  Its facets: the planes through r - 1
    independent rays with every ray on one side (tried when there are few enough).
    """
    p, r = rays.shape
    if float((rays @ normals.T).max()) > WALK_ON_PLANE or math.comb(p, r - 1) > MAX_CONE_SUBSETS:
        return False
    facets, _ = _supporting(rays, rays)
    return bool(len(facets)) and bool(((facets @ normals.T).max(axis=1) >= 1 - WALK_ON_PLANE).all())


def _unique_directions(D: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit directions (p, r), each once (within :data:`WALK_ON_PLANE`), in their order."""
    if len(D) < 2:
        return D
    from scipy.spatial import cKDTree

    D = D[np.sort(np.unique(np.round(D, 7), axis=0, return_index=True)[1])]  # most copies
    pairs = cKDTree(D).query_pairs(WALK_ON_PLANE, p=np.inf, output_type="ndarray")
    later = np.zeros(len(D), dtype=bool)
    later[pairs.max(axis=1)] = True  # within the tolerance of an earlier one
    return D[~later]


def _facet_rows(walk: _Walk) -> NDArray[np.bool_]:
    """The rows that are facets: their faces of dimension r - 1, each plane once (the last).

    The face of a row is spanned by the vertices and rays on it (a face of a pointed
    polyhedron holds a vertex); rows on the same vertices and rays are one plane.
    """
    k, r = walk.tight.shape[1], walk.points.shape[1]
    facet = np.zeros(k, dtype=bool)
    last: dict[bytes, int] = {}
    scale = max(1.0, float(np.abs(walk.points).max(initial=0.0)))
    for i in range(k):
        on, on_rays = walk.tight[:, i], walk.ray_tight[:, i]
        count = int(on.sum())
        if not count or count - 1 + int(on_rays.sum()) < r - 1:
            continue
        face = walk.points[on]
        span = np.vstack([face[1:] - face[0], walk.rays[on_rays]])
        sigma = np.linalg.svd(span, compute_uv=False)
        if int(np.count_nonzero(sigma > 1e-9 * max([scale, *sigma[:1]]))) != r - 1:
            continue
        key = np.packbits(np.concatenate([on, on_rays])).tobytes()
        if key in last:
            facet[last[key]] = False
        last[key] = i
        facet[i] = True
    return facet


def _is_point(generators: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which of cddlib's generators ``[t | y]`` (G, r + 1) are points (the rest: directions).

    A relative rule: a point farther than :data:`FAR_RATIO` whitened units (the interior
    point's farthest row at distance 1) is a direction, ``|t| <= |y| / FAR_RATIO``; a ray
    that cddlib's rounding left at ``t = 1e-15`` is no vertex at 1e16.
    """
    return np.abs(generators[:, 0]) * FAR_RATIO > np.abs(generators[:, 1:]).max(axis=1)


def _known_walk(
    known: tuple[NDArray[np.float64], NDArray[np.int_] | None],
    array: NDArray[np.float64],
    S: NDArray[np.float64],
    U1: NDArray[np.float64],
    unit: float,
    origin: NDArray[np.float64],
) -> _Walk | None:
    """A caller's vertices (V, m) and edges as a walk of the whitened rows ``array``.

    None unless the rows have full rank m, every vertex satisfies every row and lies on m
    rows or more (to :data:`WALK_ON_PLANE`).
    """
    vertices, edges = known
    r = array.shape[1] - 1
    if r != vertices.shape[1] or not len(vertices):
        return None
    y = S * ((vertices - origin) @ U1) / unit
    n, o = _unit_rows(-array[:, 1:], array[:, 0])
    slack = o[None, :] - y @ n.T
    on = _on_plane(o, y)
    if bool((slack < -on).any()):
        return None
    tight = slack <= on
    if int(tight.sum(axis=1).min()) < r:
        return None
    return _Walk(y, np.zeros((0, r)), tight, np.zeros((0, len(o)), dtype=bool), edges)


def vertex_edges(
    vertices: NDArray[np.float64],
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    basis: NDArray[np.float64],
) -> NDArray[np.int_]:
    """The edges of a polytope from its vertices (V, m) and facets ``A x <= b`` (F, m).

    Two vertices are the ends of an edge when the facets through both have rank q - 1 in
    the polytope's affine hull (``basis``, (m, q)): their common face has dimension 1 and
    holds no other vertex.  A facet passes through a vertex when its slack is at most
    1e-9 of the polytope's size about the vertices' mean.

    Returns
    -------
    ndarray of int, shape (E, 2)
        Pairs of vertex indices, the smaller first.
    """
    from scipy.sparse import csr_matrix

    V, q = len(vertices), basis.shape[1]
    if q == 0 or V < 2:
        return np.zeros((0, 2), dtype=int)
    if q == 1:
        return np.array([[0, 1]]) if V == 2 else np.zeros((0, 2), dtype=int)
    centre = vertices.mean(axis=0)
    widths = b - A @ centre
    reach = float(np.abs(vertices - centre).max()) + float(np.abs(widths).max(initial=0.0))
    tight = widths[None, :] - (vertices - centre) @ A.T <= 1e-9 * reach
    incidence = csr_matrix(tight.astype(np.int32))
    shared = (incidence @ incidence.T).tocoo()
    pick = (shared.row < shared.col) & (shared.data >= q - 1)
    rows, cols, common = shared.row[pick], shared.col[pick], shared.data[pick]
    count = tight.sum(axis=1)
    normals = A @ basis  # (F, q): the facets within the affine hull
    edges = []
    for i, j, c in zip(rows, cols, common, strict=True):
        if c == q - 1 and count[i] == q and count[j] == q:  # simple ends: rank q - 1
            edges.append((i, j))
            continue
        sigma = np.linalg.svd(normals[tight[i] & tight[j]], compute_uv=False)
        if int(np.count_nonzero(sigma > 1e-9 * sigma[0])) == q - 1:
            edges.append((i, j))
    return np.array(edges, dtype=int).reshape(-1, 2)
