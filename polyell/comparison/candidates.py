r"""User-defined candidate ellipsoids, scored exactly like the built-in ones.

A researcher proposing a capability measure adds it to :func:`polyell.compare` and
:func:`polyell.sweep` (and to study files) as a :class:`Candidate`:

* from a **torque weighting** ``W`` (n x n, symmetric positive definite, in normalized
  torques): the accelerations reachable with :math:`\tilde\tau^T W \tilde\tau \le 1`,
  :math:`\{\ddot x_g + M W^{-1/2} u : \|u\| \le 1\}` (as in Azad, Babič and Mistry,
  Autonomous Robots 2019).  ``W = I`` is the new ellipsoid (eq. 32); a weighting in torques
  :math:`\tau^T W_\tau \tau` about the centre torque is :math:`W = L W_\tau L` in normalized
  ones (:math:`L` = ``Analysis.half_range`` on the diagonal).
* from a **core** ``N`` (m x m, symmetric positive definite) and an optional centre ``c``
  (default :math:`\ddot x_g`): :math:`\{\ddot x : (\ddot x - c)^T N (\ddot x - c) \le 1\}`,
  taken, like every set here, in the polytope's affine set (its section there: at a singular
  configuration a full-dimensional ellipsoid is cut to the reachable plane or line).

Its torque witness uses the minimum-norm inverse of the new ellipsoid (eq. 33/40), as the
MVIE's does.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import ELLIPSOID_KINDS, Analysis
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.polytope import Polytope
from polyell.models.task import MAX_TASK_ROWS
from polyell.validation import check_instance, check_integer, check_points, check_spd

__all__ = ["BUILT_IN_KINDS", "CANDIDATE_NAME", "Candidate", "check_candidates"]

#: The ellipsoids every comparison knows: both definitions, the maximum-volume inscribed
#: ellipsoid and the minimum-volume enclosing (outer) one.
BUILT_IN_KINDS = (*ELLIPSOID_KINDS, "mvie", "outer")

#: A candidate's name: a lower-case identifier, the prefix of its result columns.
CANDIDATE_NAME = re.compile(r"[a-z][a-z0-9_]{0,31}")

_RESERVED = (*BUILT_IN_KINDS, "static", "polytope", "configuration")  # static: a force kind


@dataclass(frozen=True, eq=False)
class Candidate:
    """A user-defined ellipsoid: a torque weighting, or a core and an optional centre.

    Parameters
    ----------
    name : str
        Lower-case identifier (``[a-z][a-z0-9_]{0,31}``), not a built-in kind; results name
        its scores ``<name>_<score>``.
    weighting : array-like, shape (n, n), optional
        Symmetric positive-definite weighting ``W`` of normalized torques.
    core : array-like, shape (m, m), optional
        Symmetric positive-definite core ``N`` [(m/s^2)^-2].
    center : array-like, shape (m,), optional
        Centre of a core-defined candidate [m/s^2]; default ``xg``.

    Give exactly one of ``weighting`` and ``core``.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> an = pe.analyze(arm.dynamics([0.1, 0.2, 0.3]), arm.tau_max)
    >>> heavy_wrist = pe.Candidate("heavy_wrist", weighting=np.diag([1.0, 1.0, 4.0]))
    >>> cmp = pe.compare(an, candidates=[heavy_wrist])
    >>> cmp["heavy_wrist"].inscribed_scale >= 1.0
    True
    """

    name: str
    weighting: NDArray[np.float64] | None = None
    core: NDArray[np.float64] | None = None
    center: NDArray[np.float64] | None = None
    _root_inverse: NDArray[np.float64] | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not CANDIDATE_NAME.fullmatch(self.name):
            raise InputError(
                "name",
                "a lower-case identifier: a letter, then up to 31 letters, digits or '_'",
                repr(self.name),
                "name it with a lower-case identifier, e.g. pe.Candidate('heavy_wrist', ...)",
            )
        if self.name in _RESERVED:
            raise InputError(
                "name",
                f"a name other than {', '.join(map(repr, _RESERVED))}",
                repr(self.name),
                f"rename it, e.g. {'my_' + self.name!r}",
            )
        if (self.weighting is None) == (self.core is None):
            raise InputError(
                f"candidate {self.name!r}",
                "exactly one of weighting= (n x n) and core= (m x m)",
                "both" if self.weighting is not None else "neither",
                "drop one: keep weighting= (joint space) or core= (task space)"
                if self.weighting is not None
                else "pass one, e.g. weighting=np.diag([1.0, 1.0, 4.0]) or core=np.eye(m)",
            )
        fix = "a weighting or core must be symmetric positive definite."
        if self.weighting is not None:
            if self.center is not None:
                raise InputError(
                    f"candidate {self.name!r}",
                    "no center with a weighting (the weighted set is centred at xg)",
                    "center=...",
                    "give a core instead, or drop center.",
                )
            W = check_spd(f"{self.name}.weighting", self.weighting, "n", fix=fix)
            eigenvalues, eigenvectors = np.linalg.eigh(W)
            object.__setattr__(self, "weighting", W)
            object.__setattr__(
                self, "_root_inverse", (eigenvectors / np.sqrt(eigenvalues)) @ eigenvectors.T
            )
        else:
            assert self.core is not None
            N = check_spd(f"{self.name}.core", self.core, "m", fix=fix)
            object.__setattr__(self, "core", N)
            if self.center is not None:
                c = check_points(f"{self.name}.center", self.center, N.shape[0])
                if c.shape != (N.shape[0],):
                    raise InputError(
                        f"{self.name}.center",
                        f"shape ({N.shape[0]},)",
                        f"shape {c.shape}",
                        f"pass one point of {N.shape[0]} coordinates, e.g. np.zeros({N.shape[0]})",
                    )
                object.__setattr__(self, "center", c)

    def __repr__(self) -> str:
        what = "weighting" if self.weighting is not None else "core"
        matrix = self.weighting if self.weighting is not None else self.core
        assert matrix is not None
        return f"Candidate({self.name!r}, {what}={np.round(matrix, 6).tolist()})"

    @property
    def root_inverse(self) -> NDArray[np.float64]:
        """``W^(-1/2)`` of a weighted candidate (n, n)."""
        if self._root_inverse is None:
            raise InputError(
                f"candidate {self.name!r}",
                "a weighted candidate",
                "a core",
                f"build it with weighting=, e.g. pe.Candidate({self.name!r}, weighting=np.eye(n))",
            )
        return self._root_inverse

    def check_sizes(self, m: int, n: int) -> None:
        """Raise unless the candidate fits a task of dimension m and an n-joint arm."""
        m, n = check_integer("m", m, 1, MAX_TASK_ROWS), check_integer("n", n, 0, 10**4)
        if self.weighting is not None and self.weighting.shape[0] != n:
            raise InputError(
                f"{self.name}.weighting",
                f"a ({n}, {n}) weighting for this {n}-joint arm",
                f"shape {self.weighting.shape}",
                f"pass one weight per joint, e.g. weighting=np.eye({n})",
            )
        if self.core is not None and self.core.shape[0] != m:
            raise InputError(
                f"{self.name}.core",
                f"a ({m}, {m}) core for this {m}-D task",
                f"shape {self.core.shape}",
                f"pass one row and column per task coordinate, e.g. core=np.eye({m})",
            )

    def ellipsoid(self, analysis: Analysis) -> Ellipsoid:
        """The candidate at one configuration, in the polytope's affine set.

        Raises
        ------
        InputError
            If its matrix does not fit the arm or the task.
        UndefinedEllipsoidError
            If a core-defined ellipsoid misses the polytope's affine set.
        """
        check_instance("analysis", analysis, Analysis, "pass pe.analyze(...) of the arm.")
        self.check_sizes(analysis.m, analysis.n)
        try:
            return self._ellipsoid(analysis)
        except InputError as exn:  # its size, refused by Ellipsoid: name the candidate
            raise InputError(
                f"candidate {self.name!r}",
                "an ellipsoid of representable size at this configuration",
                f"{exn.argument} {exn.got}",
                "scale its weighting or core (a core is in (m/s^2)^-2).",
            ) from None

    def _ellipsoid(self, analysis: Analysis) -> Ellipsoid:
        P = analysis.polytope
        if self.weighting is not None:
            r, xg = P.dim, P.center
            if not isinstance(analysis, ZonotopeAnalysis):
                raise UndefinedEllipsoidError(
                    f"candidate {self.name!r}: a weighting of normalized joint quantities "
                    f"defines an ellipsoid of a zonotope capacity, not of the "
                    f"{analysis.capacity} capacity; give a core (and a centre) instead."
                )
            U, s, _ = np.linalg.svd(analysis.M @ self.root_inverse, full_matrices=False)
            E = Ellipsoid(xg, U[:, :r], s[:r], kind=self.name)
            E.task = analysis.task
            return E
        E = self.section(P)
        E.task = analysis.task
        return E

    def section(self, P: Polytope | HPolytope) -> Ellipsoid:
        """A core-defined candidate in the affine set of a set ``P`` (its section there).

        The centre defaults to ``P.center`` (``xg`` for an analysis's polytope).  Used by
        :meth:`ellipsoid` and by :func:`polyell.compare` of a bare set, which has no arm
        and so no weighting.

        Raises
        ------
        InputError
            For a weighted candidate, a core that does not fit ``P``'s task space or is
            not positive definite on its affine set in double precision.
        UndefinedEllipsoidError
            If the ellipsoid misses ``P``'s affine set.
        """
        if self.core is None:
            raise InputError(
                f"candidate {self.name!r}",
                "a core-defined candidate (a bare set has no arm to weight torques of)",
                "a weighting",
                "give core= (m x m) and center=, or compare the analysis itself.",
            )
        self.check_sizes(P.ambient_dim, 0)
        r, xg, U1 = P.dim, P.center, P.affine_set.basis
        # The section with {xg + U1 y}: (y - y0)^T A (y - y0) <= rho^2.
        center = xg if self.center is None else self.center
        A = U1.T @ self.core @ U1
        eigenvalues, eigenvectors = np.linalg.eigh(A)
        if r and not eigenvalues[0] > np.finfo(float).eps * eigenvalues[-1]:
            raise InputError(
                f"{self.name}.core",
                "a core positive definite, in double precision, on the polytope's affine set",
                f"eigenvalues from {eigenvalues[0]:.3g} to {eigenvalues[-1]:.3g} there",
                "give a core whose condition number is well below 1e16 (scale the task "
                "units so that its entries have similar sizes).",
            )
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below
            b = U1.T @ self.core @ (xg - center)
            y0 = -np.linalg.solve(A, b) if r else np.zeros(0)
            offset = xg - center
            rho2 = 1.0 - offset @ self.core @ offset - b @ y0
        if not rho2 > 0:
            raise UndefinedEllipsoidError(
                f"candidate {self.name!r} misses the polytope's {r}-dimensional affine set "
                "at this (singular) configuration."
            )
        E = Ellipsoid(xg + U1 @ y0, U1 @ eigenvectors, np.sqrt(rho2 / eigenvalues), kind=self.name)
        E.affine_rtol, E.task = P.affine_rtol, P.task
        return E


def check_candidates(candidates: Any) -> tuple[Candidate, ...]:
    """Validate a sequence of :class:`Candidate` with distinct names."""
    if isinstance(candidates, Candidate):
        candidates = (candidates,)
    if isinstance(candidates, str | bytes) or not hasattr(candidates, "__iter__"):
        raise InputError(
            "candidates",
            "a sequence of pe.Candidate",
            type(candidates).__name__,
            "pass a list, e.g. candidates=[pe.Candidate('heavy_wrist', weighting=W)]",
        )
    found = tuple(candidates)
    for item in found:
        if not isinstance(item, Candidate):
            raise InputError(
                "candidates",
                "a sequence of pe.Candidate",
                f"an item {type(item).__name__}",
                "wrap each item, e.g. pe.Candidate('heavy_wrist', weighting=W)",
            )
    names = [c.name for c in found]
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise InputError(
            "candidates",
            "distinct names",
            f"{repeated} more than once",
            f"give each candidate its own name, e.g. rename one {repeated[0]!r} to "
            f"{repeated[0][:29] + '_2'!r}",
        )
    return found
