r"""The capacity interface: an exact set of task quantities, its ellipsoids, their witness.

A *capacity* (DESIGN.md section 7) answers "what can the arm do at this configuration" for
one task quantity -- accelerations, velocities or static forces -- with three things:

* the exact convex set of achievable task quantities (:attr:`Analysis.polytope`),
* its named ellipsoids (:attr:`Analysis.ellipsoid_kinds`, :meth:`Analysis.ellipsoid`),
* the witness map from a task point back to the normalized joint quantity that realizes it
  (:meth:`Analysis.witness_map`; more than 1 in the infinity norm means the point needs
  more than the joints can give).

The comparator, the tables, the figures, the studies and the command line speak to this
interface only; :mod:`polyell.capacities.acceleration`, :mod:`~polyell.capacities.velocity`
and :mod:`~polyell.capacities.force` implement it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from functools import lru_cache
from typing import Any, ClassVar, NamedTuple, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.cached import cached_property
from polyell.errors import InputError
from polyell.geometry.convex_set import ConvexSet
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import HPolytope
from polyell.geometry.polytope import Polytope
from polyell.geometry.subspace import AFFINE_RTOL, RANK_RTOL
from polyell.inverse import AffineMap
from polyell.models.dynamics import Dynamics
from polyell.models.kinematics import Kinematics
from polyell.models.task import check_task, task_unit
from polyell.validation import check_instance, check_points, source_torque_limits

__all__ = ["Analysis", "InverseSolution", "JointLimited", "centre_and_half_range", "label_rows"]


class JointLimited(Protocol):
    """A robot with joint limits of its own (:class:`polyell.UrdfRobot`, a study's robot)."""

    def torque_limits(
        self, qd: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(tau_max, tau_min)`` [N m], at rest or derated at the joint velocities ``qd``."""
        ...

    def velocity_limits(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(qd_max, qd_min)`` [rad/s]."""
        ...


@lru_cache(maxsize=64)
def _checked_rows(rows: tuple[str, ...], m: int) -> tuple[str, ...]:
    """:func:`~polyell.models.task.check_task` of hashable row names, remembered."""
    return check_task(rows, m)


def label_rows(convex_set: ConvexSet, rows: tuple[str, ...]) -> None:
    """Set a set's task rows (``convex_set.task = rows``), checking rows seen before once.

    An analysis labels every set it builds with the same few tuples of row names: their
    check (:func:`~polyell.models.task.check_task`, a few microseconds) is remembered.
    Names that are not hashable (a robot's rows edited by hand) go through the setter.
    """
    try:
        convex_set._task = _checked_rows(rows, convex_set.ambient_dim)
    except TypeError:  # unhashable names: the setter's own check and message
        convex_set.task = rows


def centre_and_half_range(
    upper: NDArray[np.float64], lower: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``((upper + lower) / 2, (upper - lower) / 2)``: a joint box as ``c + L u``, ``|u| <= 1``.

    The paper's "suitable transformation" after eq. 9; symmetric limits give exactly
    ``(0, upper)`` (limits are at most 1e150: no overflow).
    """
    return 0.5 * (upper + lower), 0.5 * (upper - lower)


class InverseSolution(NamedTuple):
    """Joint quantities and their normalized values that realize task points.

    Unpacks as ``joint, normalized = solution``; for accelerations also read as
    ``qdd, tau_n`` (:attr:`qdd`, :attr:`tau_n`).

    Attributes
    ----------
    joint : ndarray, shape (..., n)
        The joint quantity: joint accelerations [rad/s^2] (acceleration capacity), joint
        velocities [rad/s] (velocity) or joint torques [N m] (force).
    normalized : ndarray, shape (..., n)
        Its normalized value (torques for accelerations and forces, joint velocities for
        velocities): the limits hold iff ``|normalized|_inf <= 1``.
    """

    joint: NDArray[np.float64]
    normalized: NDArray[np.float64]

    @property
    def qdd(self) -> NDArray[np.float64]:
        """The joint accelerations of an acceleration analysis (:attr:`joint`)."""
        return self.joint

    @property
    def tau_n(self) -> NDArray[np.float64]:
        """The normalized torques of an acceleration analysis (:attr:`normalized`)."""
        return self.normalized

    @property
    def torque_norm(self) -> NDArray[np.float64]:
        """Euclidean norm of :attr:`normalized`; at most 1 on the ellipsoid of the same kind."""
        return np.linalg.norm(self.normalized, axis=-1)

    @property
    def within_limits(self) -> NDArray[np.bool_]:
        """Whether every joint respects its limits (``|normalized|_inf <= 1``, to 1e-9)."""
        return np.max(np.abs(self.normalized), axis=-1) <= 1.0 + 1e-9


class Analysis(ABC):
    """One capacity of one robot at one configuration.

    Build it with :func:`polyell.analyze`; ``analysis.capacity`` says which.

    Attributes
    ----------
    capacity : str
        ``"acceleration"``, ``"velocity"`` or ``"force"``.
    ellipsoid_kinds : tuple of str
        The ellipsoid definitions of this capacity (:meth:`ellipsoid`).
    dynamics : Dynamics or Kinematics
        The robot's matrices at the configuration (a velocity analysis needs only J).
    affine_rtol : float
        The tolerance of "on the affine set" shared by the set, the ellipsoids and
        :meth:`inverse`.
    """

    capacity: ClassVar[str]
    ellipsoid_kinds: ClassVar[tuple[str, ...]]
    #: What the definitions are, for error messages: ``{kind: one-line description}``.
    kind_notes: ClassVar[dict[str, str]]
    #: The task quantity in words ("accelerations", "velocities", "forces").
    quantity: ClassVar[str]
    #: Names of :class:`InverseSolution`'s two fields in reports: ``("qdd", "tau_n")``, ...
    inverse_names: ClassVar[tuple[str, str]]

    # What callers ask of a capacity instead of comparing its name (issue 31).
    #: The keyword arguments of :func:`polyell.analyze` (and of the sweeps and studies) for
    #: the joint limits, ``(upper, lower)``: ``("tau_max", "tau_min")`` for torques,
    #: ``("qd_max", "qd_min")`` for joint velocities.
    limit_keywords: ClassVar[tuple[str, str]] = ("tau_max", "tau_min")
    #: Those limits in words, with their unit, for messages: ``"torque limits [N m]"``.
    limit_description: ClassVar[str] = "torque limits [N m]"
    #: How to give the limits when they are missing (the hint of the InputError).
    limit_hint: ClassVar[str] = "pass tau_max=[...] (and tau_min=), e.g. robot.tau_max."
    #: Whether the set depends on the joint velocities ``qd`` of an arm in motion (torque
    #: limits derated at ``qd``, Coriolis and centrifugal torques); the velocity set does
    #: not (it is every joint velocity within the limits).
    in_motion: ClassVar[bool] = True
    #: True for the paper's capacity (accelerations, the default): its reports keep the
    #: paper's names and equation numbers (``xdd_g (eq. 8)``, ``Polytope (eq. 15)``) and
    #: name no capacity.
    paper: ClassVar[bool] = False
    #: What a study's output names of this capacity end with (before the extension):
    #: ``""`` for the paper's (``summary.tex``), else ``"_<capacity>"`` (``summary_force.tex``).
    output_suffix: ClassVar[str]
    #: The legend of the exact set in figures: ``"polytope (15)"`` for the paper's.
    polytope_label: ClassVar[str] = "polytope"
    #: The symbol of a task point in reports: ``"xdd"`` (accelerations) or ``"x"``.
    point_symbol: ClassVar[str] = "x"
    #: The legend of the centre marker (plain text): ``"centre xg"`` for accelerations.
    centre_label: ClassVar[str] = "centre"
    #: The same in matplotlib's TeX: ``r"centre $\ddot x_g$"`` for accelerations.
    centre_label_tex: ClassVar[str] = "centre"
    #: The matrix whose rank reports state: ``"M"`` (a zonotope's generators) or ``"J"``.
    rank_matrix: ClassVar[str] = "M"
    #: True where every ellipsoid's inverse is the same (a force needs one torque): reports
    #: show one.
    unique_inverse: ClassVar[bool] = False

    @abstractmethod
    def __init__(
        self,
        dynamics: Dynamics | Kinematics,
        upper: ArrayLike,
        lower: ArrayLike | None = None,
        *,
        rank_rtol: float = RANK_RTOL,
        affine_rtol: float = AFFINE_RTOL,
    ) -> None:
        """The analysis at one configuration within the joint limits ``upper``, ``lower``.

        The limits are those named by :attr:`limit_keywords`; ``lower`` defaults to
        ``-upper``.
        """

    @classmethod
    def limit_arguments(cls, upper: Any, lower: Any) -> dict[str, Any]:
        """``{limit_keywords[0]: upper, limit_keywords[1]: lower}``: keyword arguments."""
        return dict(zip(cls.limit_keywords, (upper, lower), strict=True))

    @classmethod
    def _robot_limits(
        cls, robot: JointLimited, qd: ArrayLike | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """A robot's own joint limits of this capacity, ``(upper, lower)``.

        Its torque limits, at rest or at the joint velocities ``qd`` (the velocity
        capacity: its joint velocity limits, ``qd`` unused).
        """
        return robot.torque_limits(qd)

    @classmethod
    def _source_limits(
        cls, source: object, upper: ArrayLike | None, lower: ArrayLike | None, n: int
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The joint limits given, checked, or else those of ``source`` (a robot).

        Raises an InputError naming the limit keyword when neither is there.
        """
        return source_torque_limits(source, upper, lower, n)

    @abstractmethod
    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """The matrices that define the set, by name and in report order (``xg``, ``M``)."""

    @abstractmethod
    def joint_limits(self) -> dict[str, NDArray[np.float64]]:
        """The joint limits of the analysis by name (``tau_max``, ``tau_min`` or ``qd_...``)."""

    dynamics: Dynamics | Kinematics
    affine_rtol: float = AFFINE_RTOL

    @property
    def m(self) -> int:
        """Task-space dimension."""
        return int(self.dynamics.J.shape[0])

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.dynamics.J.shape[1])

    @property
    def task(self) -> tuple[str, ...]:
        """Names of the task rows (``x``, ``y``, ``z``, ``wx``, ...)."""
        return tuple(self.dynamics.task)

    @property
    @abstractmethod
    def center(self) -> NDArray[np.float64]:
        """The reference point of the set and its ellipsoids, shape (m,) [task unit]."""

    def unit(self, tex: bool = False) -> str:
        """The unit of the task quantity: ``m/s^2``, ``m/s``, ``N``, ``N m``, ..."""
        return task_unit(self.task, tex, capacity=self.capacity)

    @property
    @abstractmethod
    def polytope(self) -> Polytope | HPolytope:
        """The exact set of achievable task quantities."""

    @property
    @abstractmethod
    def rank(self) -> int:
        """Numerical rank of the task map (that of J)."""

    @property
    def is_singular(self) -> bool:
        """True at a singular configuration (``rank J < m``)."""
        return self.rank < self.m

    def _points(self, x: ArrayLike, name: str) -> NDArray[np.float64]:
        """Task points ``x`` (m,) or (k, m), checked (finite, representable)."""
        return check_points(name, x, self.m)

    def check_kind(self, kind: object) -> str:
        """Return ``kind`` if it names an ellipsoid of this capacity, else raise InputError."""
        if not isinstance(kind, str) or kind not in self.ellipsoid_kinds:
            notes = "; ".join(f"{k!r}: {note}" for k, note in self.kind_notes.items())
            raise InputError(
                "kind",
                "one of "
                + ", ".join(repr(k) for k in self.ellipsoid_kinds)
                + f" (the {self.capacity} capacity's ellipsoids)",
                repr(kind),
                notes + ".",
            )
        return kind

    def ellipsoid(self, kind: str | None = None) -> Ellipsoid:
        """An ellipsoid of this capacity (built once; default the first of its kinds).

        Raises
        ------
        InputError
            For a kind this capacity does not define.
        UndefinedEllipsoidError
            Where the definition does not exist at this configuration (the message says
            why).
        """
        kind = self.check_kind(self.ellipsoid_kinds[0] if kind is None else kind)
        if kind not in self._ellipsoids:
            try:
                ellipsoid = self._build_ellipsoid(kind)
            except InputError as error:  # an axis beyond floating point: the limits' doing
                if error.argument not in ("semi_axes", "center"):
                    raise
                upper = next(iter(self.joint_limits()))
                raise InputError(
                    f"dyn or {upper}",
                    f"limits whose {kind} ellipsoid has {error.expected}",
                    f"{error.argument} {error.got}",
                    f"check {upper} for a limit near zero or limits many orders of magnitude "
                    "apart, or express the task in other units.",
                ) from None
            ellipsoid.affine_rtol = self.affine_rtol
            label_rows(ellipsoid, self.task)
            self._ellipsoids[kind] = ellipsoid
        return self._ellipsoids[kind]

    @cached_property
    def _ellipsoids(self) -> dict[str, Ellipsoid]:
        return {}

    @abstractmethod
    def _build_ellipsoid(self, kind: str) -> Ellipsoid:
        """The ellipsoid of a checked kind."""

    def witness_map(self, kind: str) -> AffineMap:
        """The affine map from task points to normalized joint quantities of a kind's inverse.

        ``kind`` is one of :attr:`ellipsoid_kinds`, or any other scored set (the MVIE, the
        outer ellipsoid, a candidate), which takes the capacity's own minimum-norm inverse.
        """
        check_instance("kind", kind, str, "pass a kind's name, e.g. 'chiacchio' or 'mvie'.")
        return self._witness_map(kind)

    @abstractmethod
    def _witness_map(self, kind: str) -> AffineMap:
        """:meth:`witness_map` of a kind given as a str."""

    @abstractmethod
    def inverse(self, x: ArrayLike, kind: str | None = None) -> InverseSolution:
        """The joint quantities (and their normalized values) that realize task points."""
