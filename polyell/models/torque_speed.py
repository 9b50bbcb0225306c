r"""Velocity-dependent joint torque limits: the torque-speed curve of each joint's drive.

The paper assumes the arm still: "bounds for joint torques are usually velocity dependent.
Since the manipulator is supposed still, constant bounds are considered here" (Chiacchio
2000, section 2).  A :class:`TorqueSpeed` gives the bounds of a joint moving at
:math:`\dot q`, from the linear derating of a DC drive or from a tabulated curve.

Sign convention: a joint torque :math:`\tau` is positive about (or along) the same axis as
the joint's position :math:`q` and velocity :math:`\dot q`, so :math:`\tau \dot q > 0` is a
drive giving power to the motion (*motoring*: the torque acts in the direction of motion)
and :math:`\tau \dot q < 0` a drive taking power from it (*braking*: the torque opposes
the motion).

A robot with a torque-speed model (``torque_speed=``) gives its limits at :math:`\dot q`
with ``robot.torque_limits(qd)``; ``robot.analyze(q, qd)`` (a URDF robot) analyses it in
motion with them, and an analysis of ``robot.dynamics(q, qd)`` given the rated limits
instead warns with a :class:`~polyell.DeratingWarning`.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.validation import (
    MAX_SPEED,
    MAX_TORQUE,
    array_ndim,
    check_array,
    check_torque_limits,
)

__all__ = ["TorqueSpeed"]


def _positive_sizes(name: str, values: NDArray[np.float64], limit: float, unit: str) -> None:
    """Refuse entries that are not strictly positive or beyond ``limit``."""
    bad = np.flatnonzero(~(values > 0))
    if bad.size:
        index = np.unravel_index(bad[0], values.shape)
        where = ", ".join(str(int(i)) for i in index)
        raise InputError(
            name,
            f"strictly positive values [{unit}]",
            f"{name}[{where}] = {values[index]:g}",
            "a drive's stall torque and no-load speed are positive; give magnitudes.",
        )
    _refuse_oversized(name, values, values, limit, unit, "values")


def _refuse_oversized(
    name: str,
    values: NDArray[np.float64],
    sizes: NDArray[np.float64],
    limit: float,
    unit: str,
    what: str,
) -> None:
    """Refuse ``values`` whose largest size (the entries of ``sizes``) is beyond ``limit``."""
    if values.size and np.max(sizes) > limit:
        index = np.unravel_index(int(np.argmax(sizes)), values.shape)
        where = ", ".join(str(int(i)) for i in index)
        raise InputError(
            name,
            f"{what} of size at most {limit:g} {unit}",
            f"{name}[{where}] = {values[index]:.3g}",
            f"give the drive's real {what} (in SI units).",
        )


class TorqueSpeed:
    r"""The torque-speed curves of a robot's joint drives (one curve per joint), immutable.

    Build it with :meth:`linear` (the linear derating of a DC drive) or :meth:`table` (a
    tabulated curve); :meth:`limits` gives the torque bounds of the joints moving at
    :math:`\dot q`.

    Each joint's curve :math:`c(s)`, :math:`s = |\dot q| \ge 0`, is the largest torque
    its drive can give **in the direction of motion** at speed :math:`s`: :math:`c(0)`
    is the stall torque, and :math:`c` does not increase with :math:`s`.  The bounds at
    :math:`\dot q` (sign convention: the module's docstring) are, with rated limits
    :math:`[\tau_{\min}, \tau_{\max}]` (default :math:`\pm c(0)`):

    ============================  ===============================  ===============================
    joint velocity                upper bound                      lower bound
    ============================  ===============================  ===============================
    :math:`\dot q > 0`            :math:`\min(\tau_{\max}, c(s))`  :math:`\tau_{\min}` (braking)
    :math:`\dot q < 0`            :math:`\tau_{\max}` (braking)    :math:`\max(\tau_{\min}, -c(s))`
    :math:`\dot q = 0`            :math:`\tau_{\max}`              :math:`\tau_{\min}`
    ============================  ===============================  ===============================

    So the side of the torque in the direction of motion is derated (it falls to 0 at the
    no-load speed) and the braking side, the torque opposing the motion, keeps its rated
    value.  The rated limits may not exceed the stall torque (:math:`\tau_{\max} \le c(0)`,
    :math:`\tau_{\min} \ge -c(0)`): a drive gives at most its stall torque at standstill,
    and with this the bounds are continuous in :math:`\dot q`.

    Why the motoring side (a DC drive, torque and speed referred to the joint): the torque
    is :math:`\tau = k_t i` and the armature voltage :math:`u = R i + k_e \dot q` must
    stay within :math:`|u| \le U`; the back-EMF :math:`k_e \dot q` opposes the motion and
    eats the voltage left to drive current in its direction, so

    .. math::

        -\tau_s \left(1 + \frac{\dot q}{\dot q_0}\right) \le \tau \le
        \tau_s \left(1 - \frac{\dot q}{\dot q_0}\right), \qquad
        \tau_s = \frac{k_t U}{R}, \quad \dot q_0 = \frac{U}{k_e},

    with :math:`\tau_s` the stall torque and :math:`\dot q_0` the no-load speed.  For
    :math:`\dot q > 0` the upper (motoring) bound :math:`\tau_s (1 - \dot q / \dot q_0)`
    falls, while the lower (braking) bound :math:`-\tau_s (1 + \dot q / \dot q_0)` grows
    beyond the stall torque, where the current limit of the drive -- the rated torque,
    at most :math:`\tau_s` -- is what bounds it: hence the rated value on the braking
    side.  (It is the back-EMF that opposes the motion; the torque bound it derates is
    the one along the motion.)

    Past the no-load speed (:math:`s \ge \dot q_0`) the derated bound is 0, not
    negative: the drive is taken to coast there, an optimistic simplification (a
    voltage-limited drive past its no-load speed can only brake).

    Examples
    --------
    >>> import polyell as pe
    >>> drives = pe.TorqueSpeed.linear(tau_stall=[100.0, 30.0], qd_no_load=[4.0, 6.0])
    >>> upper, lower = drives.limits([2.0, -3.0])
    >>> upper.tolist(), lower.tolist()
    ([50.0, 30.0], [-100.0, -15.0])
    """

    __slots__ = ("_arguments", "_kind", "_speeds", "_torques")

    _kind: Literal["linear", "table"]
    _speeds: NDArray[np.float64]
    _torques: NDArray[np.float64]
    _arguments: tuple[NDArray[np.float64], NDArray[np.float64]]

    def __init__(self, *args: object, **kwargs: object) -> None:
        raise InputError(
            "TorqueSpeed",
            "one of its constructors, TorqueSpeed.linear(tau_stall, qd_no_load) or "
            "TorqueSpeed.table(speeds, torques)",
            "a direct call TorqueSpeed(...)",
            "e.g. pe.TorqueSpeed.linear(tau_stall=[100, 30, 4], qd_no_load=[3, 4, 6]).",
        )

    @classmethod
    def _make(
        cls,
        kind: Literal["linear", "table"],
        speeds: NDArray[np.float64],
        torques: NDArray[np.float64],
        arguments: tuple[NDArray[np.float64], NDArray[np.float64]],
    ) -> TorqueSpeed:
        self = object.__new__(cls)
        for array in (speeds, torques, *arguments):
            array.flags.writeable = False
        object.__setattr__(self, "_kind", kind)
        object.__setattr__(self, "_speeds", speeds)
        object.__setattr__(self, "_torques", torques)
        object.__setattr__(self, "_arguments", arguments)
        return self

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"TorqueSpeed is immutable: cannot set {name!r}")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"TorqueSpeed is immutable: cannot delete {name!r}")

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle by the constructor and its arguments."""
        constructor = TorqueSpeed.linear if self._kind == "linear" else TorqueSpeed.table
        return (constructor, tuple(np.array(a) for a in self._arguments))

    # -- constructors ------------------------------------------------------------------

    @classmethod
    def linear(cls, tau_stall: ArrayLike, qd_no_load: ArrayLike) -> TorqueSpeed:
        r"""The linear derating of DC drives: :math:`c(s) = \tau_s (1 - s / \dot q_0)`.

        The torque a joint's drive gives in the direction of motion at speed
        :math:`s = |\dot q|` falls linearly from the stall torque :math:`\tau_s` at rest
        to 0 at the no-load speed :math:`\dot q_0`, and stays 0 beyond (the class
        docstring gives the physics and the braking side).

        Parameters
        ----------
        tau_stall : array-like, shape (n,)
            Stall torque of each joint [N m, or N for a prismatic joint], positive.
        qd_no_load : array-like, shape (n,)
            No-load speed of each joint [rad/s, or m/s], positive.

        Returns
        -------
        TorqueSpeed

        Raises
        ------
        InputError
            On a wrong shape, an empty list, a non-finite, non-positive or oversized value.
        """
        stall = check_array("tau_stall", tau_stall, (None,), what="stall torques [N m]")
        if stall.size == 0:
            raise InputError(
                "tau_stall",
                "one stall torque per joint",
                "an empty list",
                "give each joint's stall torque [N m], e.g. "
                "pe.TorqueSpeed.linear([87.0, 87.0], [2.6, 2.6])",
            )
        _positive_sizes("tau_stall", stall, MAX_TORQUE, "N m")
        n = stall.size
        speed = check_array("qd_no_load", qd_no_load, (None,), what="no-load speeds [rad/s]")
        if speed.size != n:  # either may be the wrong one: name both
            raise InputError(
                "tau_stall, qd_no_load",
                "one stall torque and one no-load speed per joint (lists of one length)",
                f"{n} stall torques and {speed.size} no-load speeds",
                "give both for every joint of the robot, in joint order.",
            )
        _positive_sizes("qd_no_load", speed, MAX_SPEED, "rad/s")
        speeds = np.stack([np.zeros(n), speed], axis=1)
        torques = np.stack([stall, np.zeros(n)], axis=1)
        return cls._make("linear", speeds, torques, (stall, speed))

    @classmethod
    def table(cls, speeds: ArrayLike, torques: ArrayLike) -> TorqueSpeed:
        r"""Tabulated torque-speed curves, linearly interpolated.

        Row ``i`` of ``torques`` is the torque joint ``i`` gives in the direction of
        motion at the speeds ``speeds`` (or ``speeds[i]``).  Between two speeds the
        torque is interpolated linearly.  Past the last speed: where the curve ends at a
        torque of 0, that speed is its no-load speed and the torque stays 0 beyond;
        where it ends above 0, the curve is unknown beyond and :meth:`limits` refuses
        such a speed (no extrapolation).

        Parameters
        ----------
        speeds : array-like, shape (k,) or (n, k)
            Speeds [rad/s or m/s]: shared by all joints, or one row per joint; each row
            starts at 0 (the stall torque) and increases strictly.
        torques : array-like, shape (n, k)
            Torques [N m or N], one row per joint: non-negative, non-increasing along
            the row, with a positive first entry (the stall torque).

        Returns
        -------
        TorqueSpeed

        Raises
        ------
        InputError
            On wrong shapes, fewer than 2 speeds, non-finite or oversized values, a row
            of speeds that does not start at 0 or does not increase, negative torques,
            torques that increase with speed, or a stall torque of 0.
        """
        table = check_array("torques", torques, ("n", "k"), what="torques [N m], one row per joint")
        n, k = table.shape
        if n == 0 or k < 2:
            raise InputError(
                "torques",
                "one row per joint (at least one), each with at least 2 speeds",
                f"shape {table.shape}",
                "tabulate each curve from speed 0 (the stall torque) onwards.",
            )
        if array_ndim(speeds) == 1:
            given = check_array("speeds", speeds, (k,), what="speeds [rad/s]")
            grid = np.broadcast_to(given, (n, k)).copy()
        else:
            given = grid = check_array(
                "speeds", speeds, (n, k), what="speeds [rad/s], one row per joint"
            )
        _refuse_oversized("speeds", grid, np.abs(grid), MAX_SPEED, "rad/s", "speeds")
        start = np.flatnonzero(grid[:, 0] != 0)
        if start.size:
            i = int(start[0])
            raise InputError(
                "speeds",
                "each curve starting at speed 0 (its stall torque)",
                f"a first speed of {grid[i, 0]:g} for joint {i}",
                "add the stall torque at speed 0: the curve must cover standstill.",
            )
        steps = np.argwhere(~(np.diff(grid, axis=1) > 0))
        if steps.size:
            i, j = (int(v) for v in steps[0])
            raise InputError(
                "speeds",
                "strictly increasing speeds along each curve",
                f"{grid[i, j]:g} then {grid[i, j + 1]:g} (joint {i}, entries {j} and {j + 1})",
                "sort the table by speed and drop repeated speeds.",
            )
        _refuse_oversized("torques", table, table, MAX_TORQUE, "N m", "torques")
        negative = np.argwhere(table < 0)
        if negative.size:
            i, j = (int(v) for v in negative[0])
            raise InputError(
                "torques",
                "non-negative torques (the torque a drive gives in the direction of motion)",
                f"torques[{i}, {j}] = {table[i, j]:g}",
                "tabulate magnitudes; past its no-load speed a curve is 0.",
            )
        stall = np.flatnonzero(~(table[:, 0] > 0))
        if stall.size:
            i = int(stall[0])
            raise InputError(
                "torques",
                "a positive stall torque (the first entry of each row)",
                f"torques[{i}, 0] = {table[i, 0]:g}",
                "a joint whose drive gives no torque at rest cannot move.",
            )
        rises = np.argwhere(np.diff(table, axis=1) > 0)
        if rises.size:
            i, j = (int(v) for v in rises[0])
            raise InputError(
                "torques",
                "torques that do not increase with speed along each row",
                f"{table[i, j]:g} then {table[i, j + 1]:g} N m (joint {i}, entries {j} and "
                f"{j + 1})",
                "a drive's torque-speed curve falls (or stays level) as the speed grows.",
            )
        return cls._make("table", grid, table, (given, table))

    # -- what it is ----------------------------------------------------------------------

    @property
    def kind(self) -> Literal["linear", "table"]:
        """``"linear"`` or ``"table"``: the constructor that made it."""
        return self._kind

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self._torques.shape[0])

    @property
    def speeds(self) -> NDArray[np.float64]:
        """The curves' speeds [rad/s], shape (n, k), read-only (``[0, qd_no_load]`` if linear)."""
        return self._speeds

    @property
    def torques(self) -> NDArray[np.float64]:
        """The curves' torques [N m], shape (n, k), read-only (``[tau_stall, 0]`` if linear)."""
        return self._torques

    @property
    def tau_stall(self) -> NDArray[np.float64]:
        """Stall torque of each joint [N m], shape (n,): the curve at speed 0."""
        return self._torques[:, 0]

    @property
    def qd_no_load(self) -> NDArray[np.float64]:
        """No-load speed of each joint [rad/s], shape (n,): the first speed of torque 0.

        ``inf`` for a tabulated curve that ends above 0 (:attr:`max_speed` is then its
        last speed).
        """
        zero = self._torques == 0
        first = np.argmax(zero, axis=1)
        speeds = self._speeds[np.arange(self.n), first]
        return np.where(zero.any(axis=1), speeds, np.inf)

    @property
    def max_speed(self) -> NDArray[np.float64]:
        """Largest ``|qd|`` [rad/s] that :meth:`limits` takes, shape (n,).

        ``inf`` where the curve reaches torque 0 (beyond, the torque in the direction of
        motion stays 0); the last tabulated speed where it ends above 0.
        """
        return np.where(self._torques[:, -1] == 0, np.inf, self._speeds[:, -1])

    def __repr__(self) -> str:
        first, second = (a.tolist() for a in self._arguments)
        if self._kind == "linear":
            return f"TorqueSpeed.linear(tau_stall={first}, qd_no_load={second})"
        return f"TorqueSpeed.table(speeds={first}, torques={second})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TorqueSpeed):
            return NotImplemented
        return (
            self._kind == other._kind
            and self._speeds.shape == other._speeds.shape
            and bool(np.array_equal(self._speeds, other._speeds))
            and bool(np.array_equal(self._torques, other._torques))
        )

    def __hash__(self) -> int:
        return hash((self._kind, self._speeds.tobytes(), self._torques.tobytes()))

    # -- the limits -------------------------------------------------------------------------

    def motoring(self, speed: ArrayLike) -> NDArray[np.float64]:
        r"""The curves :math:`c(s)`: the torque each joint gives in the direction of motion.

        Parameters
        ----------
        speed : array-like, shape (n,) or (K, n)
            Joint speeds :math:`s = |\dot q|` [rad/s] (the sign is ignored).

        Returns
        -------
        ndarray, shape (n,) or (K, n)
            Torques [N m], between 0 and the stall torque.

        Raises
        ------
        InputError
            On a wrong shape, a non-finite value, or a speed past the last entry of a
            table that ends above torque 0.
        """
        return self._curve(np.abs(self._check_qd(speed, "speed")), "speed")

    def limits(
        self,
        qd: ArrayLike,
        tau_max: ArrayLike | None = None,
        tau_min: ArrayLike | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        r"""Torque limits of the joints moving at ``qd``.

        The torque bound in the direction of each joint's motion is derated by its curve
        (never above the rated limit, never below 0); the bound opposing the motion, and
        both bounds of a joint at rest, are the rated ones.  See the class docstring.

        Parameters
        ----------
        qd : array-like, shape (n,) or (K, n)
            Joint velocities [rad/s or m/s]; a 2-D array is a batch of K of them.
        tau_max, tau_min : array-like, shape (n,), optional
            Rated torque limits [N m], within the stall torques (``tau_max <= tau_stall``,
            ``tau_min >= -tau_stall``); ``tau_min`` defaults to ``-tau_max``, both to
            ``+-tau_stall``.

        Returns
        -------
        tau_max_at_qd, tau_min_at_qd : ndarray, shape (n,) or (K, n)
            Upper and lower torque limits [N m] at ``qd``, with
            ``tau_min_at_qd < tau_max_at_qd``.

        Raises
        ------
        InputError
            On a wrong shape or a non-finite ``qd``; rated limits that are invalid
            (:func:`~polyell.validation.check_torque_limits`), given as ``tau_min``
            alone, or beyond the stall torque; a speed past the end of a table that ends
            above torque 0; or a velocity at which a joint is left no torque range of
            positive width (rated limits that exclude 0, e.g. ``[10, 100]`` N m, with the
            joint's curve below 10 N m in the direction of motion).
        """
        velocity = self._check_qd(qd, "qd")
        upper_rated, lower_rated = self._rated(tau_max, tau_min)
        curve = self._curve(np.abs(velocity), "qd")
        upper = np.where(velocity > 0, np.minimum(upper_rated, curve), upper_rated)
        lower = np.where(velocity < 0, np.maximum(lower_rated, -curve), lower_rated)
        empty = np.argwhere(~(lower < upper))
        if empty.size:
            index = tuple(int(i) for i in empty[0])
            joint = index[-1]
            where = f"qd[{', '.join(map(str, index))}]"
            raise InputError(
                "qd",
                "joint velocities at which every joint keeps a torque range of positive width",
                f"{where} = {velocity[index]:g}, where joint {joint} gives at most "
                f"{curve[index]:g} N m in the direction of motion, against rated limits "
                f"[{lower_rated[joint]:g}, {upper_rated[joint]:g}] N m",
                "rated limits that exclude 0 torque need a curve that reaches them; check "
                "tau_min and tau_max, or the joint's speed.",
            )
        return upper + 0.0, lower + 0.0  # + 0.0: fresh arrays, no negative zero

    def _check_qd(self, qd: ArrayLike, name: str) -> NDArray[np.float64]:
        shape = ("K", self.n) if array_ndim(qd) == 2 else (self.n,)
        return check_array(name, qd, shape, what="joint velocities [rad/s or m/s]")

    def _rated(
        self, tau_max: ArrayLike | None, tau_min: ArrayLike | None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The rated limits, checked against the stall torques."""
        stall = self.tau_stall
        if tau_max is None:
            if tau_min is not None:
                raise InputError(
                    "tau_min",
                    "tau_min only together with tau_max",
                    "tau_min alone",
                    "give both, or neither (the stall torques are then the rated limits).",
                )
            return stall.copy(), -stall
        upper, lower = check_torque_limits(tau_max, tau_min, self.n)
        for name, excess in (("tau_max", upper - stall), ("tau_min", -stall - lower)):
            bad = np.flatnonzero(excess > 0)
            if bad.size:
                i = int(bad[0])
                value = upper[i] if name == "tau_max" else lower[i]
                raise InputError(
                    name,
                    "rated torque limits within the stall torques (-tau_stall <= tau_min, "
                    "tau_max <= tau_stall): a drive gives at most its stall torque at rest",
                    f"{name}[{i}] = {value:g} N m against a stall torque of {stall[i]:g} N m",
                    "lower the rated limit to the stall torque, or correct the torque-speed curve.",
                )
        return upper, lower

    def _curve(self, speed: NDArray[np.float64], name: str) -> NDArray[np.float64]:
        """:math:`c(s)` at checked speeds ``s >= 0`` of shape (n,) or (K, n)."""
        beyond = np.argwhere(speed > self.max_speed)
        if beyond.size:
            index = tuple(int(i) for i in beyond[0])
            joint = index[-1]
            raise InputError(
                name,
                f"speeds within the tabulated curve of each joint (|{name}[{joint}]| <= "
                f"{self._speeds[joint, -1]:g} rad/s for joint {joint}, where its table "
                f"ends at {self._torques[joint, -1]:g} N m)",
                f"|{name}[{', '.join(map(str, index))}]| = {speed[index]:g}",
                "extend the table up to the no-load speed (a last torque of 0); polyell "
                "does not extrapolate a curve.",
            )
        curve = np.empty_like(speed)
        for i in range(self.n):
            # Past the last speed only curves ending at 0 remain: np.interp holds it.
            curve[..., i] = np.interp(speed[..., i], self._speeds[i], self._torques[i])
        return curve
