r"""The static force capacity: end-effector forces within the torque limits, with gravity.

At rest, an end-effector force (or moment) :math:`h` needs the joint torques
:math:`\tau = J^T h + g`.  With :math:`\tau = \tau_c + L \tilde\tau`,
:math:`\|\tilde\tau\|_\infty \le 1`, write :math:`A = L^{-1} J^T` (n, m) and
:math:`c = L^{-1} (g - \tau_c)`; the forces the arm can exert form the H-polytope

.. math::

    P_f = \{ h : \|A h + c\|_\infty \le 1 \}
        = \{ h : A h \le 1 - c,\ -A h \le 1 + c \}

(2n half-spaces in :math:`R^m`).  At a singular posture it is unbounded along
:math:`\operatorname{Ker} J^T`; it is empty when gravity alone needs more torque than the
joints have along a direction no end-effector force can help.

Its ellipsoids, from the SVD :math:`J L^{-1} = U_1 S V_1^T` (so :math:`A = V_1 S U_1^T`):

* ``"chiacchio"``, the static-consistent one with gravity, :math:`\{h : \|A h + c\| \le
  1\}`.  With :math:`h_0 = -A^+ c` and :math:`c_\perp = (I - A A^+) c` (the part of the
  gravity load no end-effector force can balance),
  :math:`\|A h + c\|^2 = \|A (h - h_0)\|^2 + \|c_\perp\|^2`, so it is the ellipsoid of
  centre :math:`h_0`, axes :math:`U_1` and semi-axes :math:`\rho / S` with
  :math:`\rho = \sqrt{1 - \|c_\perp\|^2}`.  It lies inside :math:`P_f` because
  :math:`\|\cdot\|_\infty \le \|\cdot\|_2`.
* ``"yoshikawa"``, the classic one: the unit ball of normalized torques through the
  unweighted pseudo-inverse, :math:`\{(J^T)^+ (\tau_c + L u - g) : \|u\| \le 1\}`, centred
  at :math:`-(J^T)^+ (g - \tau_c)`.
* ``"static"``, what capacity libraries compute today: :math:`\{h : \|L^{-1} J^T h\| \le
  1\}`, centred at 0, gravity ignored (axes :math:`U_1`, semi-axes :math:`1 / S`).

The torque a force needs is unique, so every ellipsoid has the same witness,
:math:`\tilde\tau = A h + c`: more than 1 in the infinity norm means the ellipsoid promises
a force the arm cannot exert.

The set of a batch of configurations (:func:`force_vertices`: every m rows and bounds
solved, the vertices certified complete by their edges) is the force sweep's
(:mod:`polyell.studies.force_batch`), and an analysis' polytope is its batch of one;
cddlib (:class:`~polyell.HPolytope`) decides where the batch cannot certify the set
(singular, empty, not in general position).
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import ClassVar, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from polyell.cached import cached_property
from polyell.capacities.acceleration import check_dynamics
from polyell.capacities.base import (
    Analysis,
    InverseSolution,
    centre_and_half_range,
    label_rows,
)
from polyell.errors import InputError, SolverError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL, rank_revealing_svd, scaled_norm
from polyell.geometry.zonotope import order_polygon, subsets
from polyell.inverse import AffineMap
from polyell.models.dynamics import Dynamics
from polyell.models.kinematics import Kinematics
from polyell.validation import (
    check_fraction,
    check_magnitudes,
    check_torque_limits,
    magnitude_limit,
)

__all__ = [
    "DEPENDENT",
    "GENERAL_POSITION",
    "MAX_CANDIDATES",
    "ForceAnalysis",
    "ForceVertices",
    "force_terms",
    "force_vertices",
]


#: The smallest largest entry of a Jacobian the force set is computed from: below, its
#: pseudo-inverse (the classic force ellipsoid) overflows.  The set itself depends on J, g
#: and the limits together, so it is refused, not rescaled.
SMALLEST_JACOBIAN = 1e-290


def force_terms(
    J: NDArray[np.float64],
    g: NDArray[np.float64],
    tau_center: NDArray[np.float64],
    half_range: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``A^T = J L^-1`` (..., m, n) and ``c = L^-1 (g - tau_c)`` (..., n), checked.

    One configuration or a batch (the sweep's).  Raises :class:`InputError` where the
    forces or gravity's share of the limits are not representable.
    """
    size = _MAX(np.abs(J), (-2, -1)) if J.size else np.zeros(J.shape[:-2])
    if _ANY((size > 0) & (size < SMALLEST_JACOBIAN), None):  # its pseudo-inverse overflows
        raise InputError(
            "dyn.J",
            f"a Jacobian with entries of at least {SMALLEST_JACOBIAN:.0e} (or zero)",
            f"largest entries down to {np.min(np.where(size > 0, size, np.inf)):.3g}",
            "give J, g and the torque limits in units of moderate size (m, N m).",
        )
    with np.errstate(over="ignore", invalid="ignore", under="ignore"):
        M = J / half_range  # J L^-1 = A^T
        c = (g - tau_center) / half_range
    # forces are about 1 / |J L^-1| and gravity's share c is a number: no relative test
    check_magnitudes(M, np.zeros(M.shape[:-1]), quantity=("forces", "J L^-1", "(none)"))
    if not _MAX(np.abs(c), None, initial=0.0) <= 10.0 ** magnitude_limit(1):  # NaN: refused
        raise InputError(
            "dyn.g",
            "gravity torques of the size of the torque limits (within 1e140 of them)",
            f"L^-1 (g - tau_c) up to {np.abs(c).max():.3g}",
            "give g and the torque limits in the same units (N m).",
        )
    return M, c


class ForceAnalysis(Analysis):
    """The end-effector forces a robot at rest can exert at one configuration.

    Build it with ``pe.analyze(dyn, tau_max, tau_min, capacity="force")``.

    Attributes
    ----------
    dynamics : Dynamics
        ``J`` (m, n) and the gravity torques ``g`` (n,) (``B`` is not used).
    tau_max, tau_min, tau_center, half_range : ndarray, shape (n,)
        Torque limits, their midpoint and ``diag(L)`` [N m].
    A : ndarray, shape (n, m)
        ``L^-1 J^T`` [per N]: normalized torque per unit force.
    c : ndarray, shape (n,)
        ``L^-1 (g - tau_c)``: the normalized torques gravity needs.
    center : ndarray, shape (m,)
        ``h0 = -A^+ c`` [N]: the force of least normalized torque residual, the centre of
        the ``"chiacchio"`` ellipsoid.
    """

    capacity = "force"
    ellipsoid_kinds = ("chiacchio", "yoshikawa", "static")
    kind_notes: ClassVar[dict[str, str]] = {
        "chiacchio": "the static-consistent one with gravity, |L^-1 (J^T h + g - tau_c)| <= 1",
        "yoshikawa": "the unit torque ball through the unweighted pseudo-inverse of J^T",
        "static": "|L^-1 J^T h| <= 1, centred at 0, gravity ignored",
    }
    quantity = "forces"
    inverse_names = ("tau", "tau_n")
    output_suffix = "_force"
    rank_matrix = "J"
    unique_inverse = True  # the torque a force needs is unique
    dynamics: Dynamics

    def __init__(
        self,
        dynamics: object,
        tau_max: ArrayLike,
        tau_min: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        if isinstance(dynamics, Kinematics):
            raise InputError(
                "dyn",
                "dynamics with gravity torques g for the force capacity",
                "a Kinematics (a Jacobian alone)",
                "pass pe.Dynamics(J, B, g) or arm.dynamics(q); use g = 0 to ignore gravity.",
            )
        dynamics = check_dynamics(dynamics, "force")
        self.dynamics = dynamics
        self.tau_max, self.tau_min = check_torque_limits(tau_max, tau_min, dynamics.n)
        self.tau_center, self.half_range = centre_and_half_range(self.tau_max, self.tau_min)
        M, self.c = force_terms(dynamics.J, dynamics.g, self.tau_center, self.half_range)
        self.A: NDArray[np.float64] = M.T
        # The rank is J's: the set is unbounded only along Ker J^T.  M = J L^-1 is
        # ill-conditioned where the torque ranges differ by orders of magnitude, but that
        # makes the set thin across the narrow range's rows, not infinite along the others.
        _, kinematic, _, info = lapack.dgesdd(dynamics.J, compute_uv=0)
        if info != 0:  # pragma: no cover - Dynamics has checked J (finite)
            raise SolverError(f"The SVD of J did not converge: LAPACK dgesdd info={info}.")
        rank_rtol = check_fraction("rank_rtol", rank_rtol)
        values = kinematic.tolist()  # a few numbers: counted in Python
        rank = sum(value > rank_rtol * values[0] for value in values) if values[0] else 0
        self.svd = rank_revealing_svd(M, rank_rtol, rank=rank)
        self.affine_rtol = check_fraction("affine_rtol", affine_rtol)
        svd = self.svd
        along = svd.V1.T @ self.c  # the part of c that forces can balance, in V_1
        self._center: NDArray[np.float64] = -svd.U1 @ (along / svd.sigma)
        self.c_perp: NDArray[np.float64] = self.c - svd.V1 @ along

    def __repr__(self) -> str:
        return (
            f"ForceAnalysis(m={self.m}, n={self.n}, rank={self.rank}, "
            f"center={np.round(self.center, 6).tolist()})"
        )

    @property
    def center(self) -> NDArray[np.float64]:
        """``h0 = -A^+ c`` [N]: the force of least normalized torque residual."""
        return self._center

    @property
    def rank(self) -> int:
        """Numerical rank of ``J`` (decided on ``J``, the rank of ``J L^-1`` as well)."""
        return self.svd.rank

    @cached_property
    def polytope(self) -> HPolytope:
        """The exact force polytope ``{h : |A h + c|_inf <= 1}`` (unbounded or empty, said).

        Enumerated as a batch of one (:func:`force_vertices`) where that certifies it
        (bounded, full-dimensional, in general position), else by cddlib
        (:class:`~polyell.HPolytope`).
        """
        # In torques, tau_min <= J^T h + g <= tau_max: a row is negligible when its joint's
        # column of J is (no force loads it), not when its torque range is wide.
        J, g = self.dynamics.J, self.dynamics.g
        A = np.concatenate([J.T, -J.T])
        b = np.concatenate([self.tau_max - g, g - self.tau_min])
        polytope = self._enumerated(A, b)
        if polytope is None:
            polytope = HPolytope(A, b, center=self.center, rank=self.rank)  # lines: Ker J^T
        polytope.affine_rtol = self.affine_rtol
        label_rows(polytope, self.task)
        return polytope

    def _enumerated(self, A: NDArray[np.float64], b: NDArray[np.float64]) -> HPolytope | None:
        """The set ``{h : A h <= b}`` (the 2n rows) from :func:`force_vertices`, or None.

        None where the batch does not certify it, and where :class:`~polyell.HPolytope`
        would refuse its offsets (it says why).
        """
        m, n = self.m, self.n
        if not (2 <= m <= n and self.rank == m and math.comb(n, m) * 2**m <= MAX_CANDIDATES):
            return None
        J = self.dynamics.J
        norms = np.sqrt(_ADD(J * J, 0))  # |J_i|, as HPolytope normalizes its rows
        largest = _MAX(norms)
        if not 1e-140 < largest < 1e140:  # squares that may underflow or overflow
            norms = scaled_norm(J, axis=0)
            largest = _MAX(norms)
        used = norms > RANK_RTOL * largest
        svd = self.svd
        found = force_vertices(svd.V1.T[None], self.c_perp[None], used[None])
        if not found.general[0]:
            return None
        norms = np.concatenate((norms, norms))
        offsets = b / np.where(np.concatenate((used, used)), norms, np.inf)  # unused: 0
        limit = 10.0 ** magnitude_limit(m)
        if not 1.0 / limit <= _MAX(np.abs(offsets)) <= limit:
            return None  # HPolytope refuses them
        z = found.z[0].compress(found.vertex[0], axis=0)
        vertices = self.center + (z / svd.sigma) @ svd.U1.T
        if m == 2:  # counter-clockwise, as a zonotope's
            vertices = order_polygon(vertices)
        facet = found.facet[0]  # (rows tight at a vertex: used ones)
        norms = norms.compress(facet)
        return HPolytope._from_enumeration(
            A.compress(facet, axis=0) / norms[:, None],
            offsets.compress(facet),
            vertices,
            self.center,
            (z, svd.U1, 1.0 / svd.sigma),
        )

    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """``A = L^-1 J^T``, ``c = L^-1 (g - tau_c)``, the centre ``h0`` and ``c_perp``."""
        return {"A": self.A, "c": self.c, "center": self.center, "c_perp": self.c_perp}

    def joint_limits(self) -> dict[str, NDArray[np.float64]]:
        """``tau_max`` and ``tau_min`` [N m]."""
        return {"tau_max": self.tau_max, "tau_min": self.tau_min}

    def _require_bounded(self, kind: str) -> None:
        if self.is_singular:
            raise UndefinedEllipsoidError(
                f"The force ellipsoid {kind!r} is undefined at this singular posture: rank J "
                f"= {self.rank} < m = {self.m}, so forces along Ker(J^T) need no torque and "
                "the force polytope is unbounded along them (see polytope.rays); there the "
                "gravity-consistent and static ellipsoids would be infinite cylinders and "
                "the classic one flat."
            )
        if self.polytope.is_empty:
            raise UndefinedEllipsoidError(
                f"The force ellipsoid {kind!r} is undefined here: the force set is empty (the "
                "arm cannot hold itself against gravity within its torque limits), so no "
                "ellipsoid describes it."
            )

    def _build_ellipsoid(self, kind: str) -> Ellipsoid:
        self._require_bounded(kind)
        svd = self.svd
        if kind == "static":
            return Ellipsoid(np.zeros(self.m), svd.U1, 1.0 / svd.sigma, kind=kind)
        if kind == "chiacchio":
            margin = 1.0 - float(self.c_perp @ self.c_perp)
            if not margin > 0.0:
                raise UndefinedEllipsoidError(
                    "The force ellipsoid 'chiacchio' is empty at this posture: the part of "
                    "the gravity torques that no end-effector force can balance has "
                    f"normalized norm |c_perp| = {np.sqrt(1.0 - margin):.4g} >= 1, so no "
                    "ball of normalized torques about it fits the limits."
                )
            return Ellipsoid(self.center, svd.U1, np.sqrt(margin) / svd.sigma, kind=kind)
        # yoshikawa: h = (J^T)^+ (tau_c + L u - g), |u| <= 1.
        pseudo_inverse = np.linalg.pinv(self.dynamics.J.T)
        center = -pseudo_inverse @ (self.dynamics.g - self.tau_center)
        U, s, _ = np.linalg.svd(pseudo_inverse * self.half_range, full_matrices=False)
        return Ellipsoid(center, U, s, kind=kind)

    def _witness_map(self, kind: str) -> AffineMap:
        """``h -> tau_n = A h + c`` (the torque a force needs is unique), about ``h0``."""
        return AffineMap(self.A, self.center, self.c_perp)

    def inverse(self, x: ArrayLike, kind: str | None = None) -> InverseSolution:
        """The joint torques that exert end-effector forces at rest.

        Parameters
        ----------
        x : array-like, shape (m,) or (k, m)
            End-effector forces [N] (moments [N m] for an angular task).
        kind : str, optional
            Any of :attr:`ellipsoid_kinds`: the torque ``J^T h + g`` is unique, so every
            definition has the same inverse.

        Returns
        -------
        InverseSolution
            ``(tau, tau_n)``: ``tau = J^T h + g`` [N m] and ``tau_n = L^-1 (tau - tau_c)``.
        """
        if kind is not None:
            self.check_kind(kind)
        h = self._points(x, "h")
        tau_n = self.witness_map("chiacchio")(h)
        return InverseSolution(self.tau_center + tau_n * self.half_range, tau_n)


# --- The force sets of a batch of configurations ------------------------------------------
# Leading axis K: a sweep's block (polyell.studies.force_batch), or a batch of one
# (ForceAnalysis.polytope).

#: Vertex candidates ``C(n, m) 2^m`` of a configuration above which cddlib enumerates
#: instead (:class:`~polyell.HPolytope`).
MAX_CANDIDATES = 4096
#: A row counts as tight at a vertex within this of its bound (whitened rows have norm at
#: most 1 and the bounds are 1): a vertex with more than m rows that close is left to
#: cddlib.
GENERAL_POSITION = 1e-9
#: m unit normals spanning less than this volume (``|det|``) are taken as dependent: their
#: candidate is skipped, and the edges of the vertices found certify that it was no vertex.
DEPENDENT = 1e-6
#: Reductions without the array methods' Python wrappers (several microseconds apiece on
#: the small arrays of one set).
_ADD, _MAX, _ANY, _ALL = (
    np.add.reduce,
    np.maximum.reduce,
    np.logical_or.reduce,
    np.logical_and.reduce,
)


class ForceVertices(NamedTuple):
    """The vertex candidates of a batch of force sets in whitened coordinates, and facets.

    The sets are ``{z : |V z + c_perp|_inf <= 1}`` (:func:`force_vertices`); the
    candidates are every m rows S and bounds sigma, in the order of :func:`_layout`
    (candidate ``p``: the rows ``chosen[p // 2^m]``, the bounds ``signs[p % 2^m]``).

    Attributes
    ----------
    z : ndarray, shape (K, P, m)
        Each candidate's point (NaN where its rows are nearly dependent).
    vertex : ndarray of bool, shape (K, P)
        The candidates that are vertices.
    facet : ndarray of bool, shape (K, 2n)
        The one-sided rows (``+row`` then ``-row``) tight at some vertex: the facets.
    general : ndarray of bool, shape (K,)
        Vertices certainly all of them, in general position (the others: cddlib).
    adjugate : ndarray, shape (K, C, m, m)
        The transposed adjugates of the m rows S, ``det(V_S) V_S^-T`` (row t: the
        cofactors of column t).
    det : ndarray, shape (K, C)
        ``det V_S``.
    """

    z: NDArray[np.float64]
    vertex: NDArray[np.bool_]
    facet: NDArray[np.bool_]
    general: NDArray[np.bool_]
    adjugate: NDArray[np.float64]
    det: NDArray[np.float64]


def force_vertices(
    Vt: NDArray[np.float64], c_perp: NDArray[np.float64], used: NDArray[np.bool_]
) -> ForceVertices:
    r"""Vertices of ``{z : |V z + c_perp|_inf <= 1}`` for a batch, by every m rows and signs.

    In the whitened coordinates ``z = S U^T (h - h0)`` of :class:`ForceAnalysis` (``A =
    V S U^T``), rows not ``used`` (negligible, as :class:`~polyell.HPolytope` decides)
    constrain nothing.  Rows ``S`` and bounds ``sigma`` give ``V_S z = sigma - c_perp,S``;
    the point is a vertex when every row holds.  A row is certified (``general``) where no
    vertex has more than m rows within :data:`GENERAL_POSITION` of tight, every edge of a
    vertex found ends at another one (:func:`_closed`: the candidates of nearly dependent
    rows, skipped, hid no vertex) and there are more than m vertices (bounded and
    full-dimensional).

    Parameters
    ----------
    Vt : ndarray, shape (K, m, n)
        The rows of the sets, transposed (``V^T``, orthonormal rows).
    c_perp : ndarray, shape (K, n)
        The part of the gravity torques no force balances, normalized.
    used : ndarray of bool, shape (K, n)
        The rows that constrain forces.

    Returns
    -------
    ForceVertices
    """
    K, m, n = Vt.shape
    chosen, signs, incidence, edges = _layout(n, m)
    others = _other_rows(n, m)
    V = Vt.swapaxes(1, 2)  # (K, n, m)
    every_row = bool(_ALL(used, None))
    if not every_row:
        V = np.where(used[..., None], V, 0.0)
    adjugate, det = _adjugates(V, chosen)
    # m rows spanning less than DEPENDENT (as unit normals) are skipped: a NaN point
    lengths = np.sqrt(_ADD(V * V, -1)).take(chosen, axis=1)  # (K, C, m)
    solvable = np.abs(det) > DEPENDENT * np.multiply.reduce(lengths, -1)
    scale = np.reciprocal(np.where(solvable, det, np.nan))
    # z = V_S^-1 (sigma - c_S) for every sigma: (K, C, m, 2^m), then (K, m, P)
    z = adjugate.swapaxes(-1, -2) @ (signs.T - c_perp.take(chosen, axis=1)[..., None])
    z *= scale[..., None, None]
    z = z.swapaxes(1, 2).reshape(K, m, -1)
    magnitude = V @ z
    magnitude += c_perp[..., None]
    magnitude = np.abs(magnitude, out=magnitude)  # (K, n, P)
    # The candidate's own rows are tight (to rounding); the largest of the others decides:
    # below 1 - GENERAL_POSITION a vertex, up to 1 + GENERAL_POSITION one with more than
    # m rows tight (not in general position), above it no point of the set (NaN: skipped).
    magnitude *= others
    other = _MAX(magnitude, 1)
    vertex = other < 1.0 - GENERAL_POSITION
    crowded = (other <= 1.0 + GENERAL_POSITION) ^ vertex
    general = _ANY(vertex, 1) & ~_ANY(crowded, 1)
    # m nearly dependent rows (skipped above) could hide a vertex: the edges certify that
    # none is missing (and closed, a vertex has m neighbours: there are more than m).
    # Where no m used rows were skipped, every vertex was solved for: a bounded set
    # (V has rank m) in general position, whose edges close (m rows of an unused row, 0,
    # are no vertex's).
    skipped = ~solvable if every_row else ~solvable & _ALL(used.take(chosen, axis=1), -1)
    if _ANY(skipped, None):
        general &= _closed(vertex, edges)
    facet = (vertex @ incidence) > 0  # no other row is tight: those would be crowded
    return ForceVertices(z.swapaxes(1, 2), vertex, facet, general, adjugate, det)


@lru_cache(maxsize=16)
def _other_rows(n: int, m: int) -> NDArray[np.float64]:
    """(n, C 2^m): 0 at each candidate's own m rows (:func:`_layout`), 1 at the others."""
    others = np.ones((n, math.comb(n, m) << m))
    chosen = np.repeat(subsets(n, m), 1 << m, axis=0)  # (P, m): each candidate's rows
    others[chosen.T, np.arange(len(chosen))] = 0.0
    others.flags.writeable = False
    return others


@lru_cache(maxsize=16)
def _layout(
    n: int, m: int
) -> tuple[NDArray[np.int_], NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """The candidates of :func:`force_vertices`: rows, signs, tight one-sided rows, edges.

    Returns
    -------
    chosen : ndarray of int, shape (C, m)
        Every m of the n rows.
    signs : ndarray, shape (2^m, m)
        Every choice of bounds (+1: ``1 - c``, -1: ``-1 - c``).
    incidence : ndarray, shape (C 2^m, 2n)
        1 where candidate ``(S, sigma)`` (in that order) is tight at the one-sided row
        (``+row i``: column i, ``-row i``: column n + i).
    edges : ndarray of int64, shape (C 2^m, m)
        The m edges of each candidate as a vertex: its tight one-sided rows but one, as
        bits (bit i: ``+row i``, bit n + i: ``-row i``).
    """
    chosen = subsets(n, m)
    signs = np.array(np.meshgrid(*[[1.0, -1.0]] * m, indexing="ij")).reshape(m, -1).T
    tight = (chosen[:, None, :] + n * (signs[None] < 0)).reshape(-1, m)  # (C 2^m, m)
    incidence = np.zeros((len(tight), 2 * n))
    np.put_along_axis(incidence, tight, 1.0, axis=1)
    bits = np.int64(1) << tight.astype(np.int64)
    edges = bits.sum(axis=1, keepdims=True) - bits
    for array in (signs, incidence, edges):
        array.flags.writeable = False
    return chosen, signs, incidence, edges


def _closed(candidates: NDArray[np.bool_], edges: NDArray[np.int64]) -> NDArray[np.bool_]:
    """Rows whose vertices are all found: every edge of a vertex ends at another one.

    The vertices of a simple bounded polytope and their edges (m - 1 tight rows) form a
    connected graph in which every edge joins exactly two vertices; vertices of which each
    edge is shared by exactly one other found vertex are therefore all of them.  This
    certifies the enumeration where candidates of nearly dependent rows were skipped (a
    spherical shoulder, parallel joint axes: rows with coplanar normals).

    Parameters
    ----------
    candidates : ndarray of bool, shape (K, P)
        The vertices found among the candidates of :func:`_layout`.
    edges : ndarray of int64, shape (P, m)
        Each candidate's edges, :func:`_layout`.

    Returns
    -------
    ndarray of bool, shape (K,)
    """
    K = len(candidates)
    width = int(_MAX(edges, None, initial=1)).bit_length() if K > 1 else 0
    if width + int(K).bit_length() > 62:  # the keys would not fit one int64
        return np.zeros(K, dtype=bool)
    row, candidate = np.nonzero(candidates)
    if not row.size:  # no vertex in any row: nothing to close (the callers refuse them)
        return np.ones(K, dtype=bool)
    keys = edges.take(candidate, axis=0)  # (a new array)
    if K > 1:  # each row's keys apart
        keys += (row.astype(np.int64) << width)[:, None]
    keys = keys.ravel()
    keys.sort()
    # every key exactly twice (the usual case): equal in pairs, pairs distinct
    if len(keys) % 2 == 0 and bool(
        _ALL(keys[0::2] == keys[1::2], None) and _ALL(keys[1:-1:2] != keys[2::2], None)
    ):
        return np.ones(K, dtype=bool)
    new = np.ones(len(keys) + 1, dtype=bool)
    new[1:-1] = keys[1:] != keys[:-1]
    starts = np.flatnonzero(new)
    twice = np.diff(starts) == 2
    closed = np.ones(K, dtype=bool)
    closed[keys[starts[:-1][~twice]] >> width if K > 1 else 0] = False
    return closed


def _adjugates(
    V: NDArray[np.float64], chosen: NDArray[np.int_]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Transposed adjugates and determinants of the m x m matrices of rows ``V[:, S]``.

    ``V`` (K, n, m), ``chosen`` (C, m): returns (K, C, m, m) (row t: the cofactors of
    column t, so that ``V_S^-1 = adj^T / det``) and (K, C).  For m = 3 the rows of the
    rows a, b, c are ``b x c``, ``c x a``, ``a x b`` and the determinant ``a . (b x c)``,
    gathered at once from the flattened rows; for m = 2 ``[[b1, -b0], [-a1, a0]]``;
    above, from LAPACK's inverses.
    """
    K, n, m = V.shape
    if m == 3:
        factors, first = _adjugate_indices(n)
        flat = V.reshape(K, 3 * n)
        t = flat.take(factors, axis=-1)  # (K, 4, 9 C)
        adjugate = (t[:, 0] * t[:, 1] - t[:, 2] * t[:, 3]).reshape(K, -1, 3, 3)
        det = _ADD(flat.take(first, axis=-1).reshape(K, -1, 3) * adjugate[:, :, 0], -1)
        return adjugate, det
    blocks = V[:, chosen]  # (K, C, m, m)
    if m == 2:
        det = blocks[..., 0, 0] * blocks[..., 1, 1] - blocks[..., 0, 1] * blocks[..., 1, 0]
        return blocks[..., ::-1, ::-1] * np.array([[1.0, -1.0], [-1.0, 1.0]]), det
    det = np.linalg.det(blocks)
    regular = (det != 0)[..., None, None]
    inverse = np.linalg.inv(np.where(regular, blocks, np.eye(m)))
    return np.where(regular, np.swapaxes(inverse, -1, -2) * det[..., None, None], 0.0), det


@lru_cache(maxsize=16)
def _adjugate_indices(n: int) -> tuple[NDArray[np.int_], NDArray[np.int_]]:
    """Flat indices into rows (n, 3) for the adjugates of every 3 rows.

    Returns ``factors`` (4, 9 C): ``adj[S, t, k] = f0 f1 - f2 f3``, row t the cofactors of
    column t of the rows S = (a, b, c), the cross products ``b x c``, ``c x a``, ``a x b``;
    and ``first`` (3 C), the entries of each a: the determinant is ``a . (b x c)``.
    """
    S = subsets(n, 3)
    p = S[:, [1, 2, 0]][:, :, None] * 3  # (C, t, 1): the rows of each cross product
    q = S[:, [2, 0, 1]][:, :, None] * 3
    k1, k2 = (np.arange(3) + 1) % 3, (np.arange(3) + 2) % 3  # (b x c)_k = b_k1 c_k2 - b_k2 c_k1
    factors = np.stack([p + k1, q + k2, p + k2, q + k1]).reshape(4, -1)
    first = (S[:, :1] * 3 + np.arange(3)).ravel()
    factors.flags.writeable = first.flags.writeable = False
    return factors, first
