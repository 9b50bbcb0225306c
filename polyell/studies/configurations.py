"""Lazy sets of configurations: grids and seeded random samples of any size.

Both produce any range of their rows on demand, so a sweep over millions of
configurations never holds them all in memory, and the rows do not depend on how the
sweep is chunked.
"""

from __future__ import annotations

import inspect
from collections.abc import Sequence
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.validation import MAX_AXIS_VALUES, array_ndim, check_array, check_integer

__all__ = [
    "MAX_IN_MEMORY",
    "ConfigurationSet",
    "Grid",
    "RandomConfigurations",
    "grid",
    "joint_bounds",
    "random_configurations",
    "uniform_rows",
]

#: Most numbers (rows times joints) a configuration set gives as one array
#: (``np.asarray``): 100 million, 0.8 GB.  Larger sets are read with ``rows`` in parts.
MAX_IN_MEMORY = 100_000_000


def uniform_rows(
    rng: np.random.Generator,
    low: NDArray[np.float64],
    high: NDArray[np.float64],
    count: int,
) -> NDArray[np.float64]:
    """``count`` rows uniform in the box ``[low, high]``, shape (count, n).

    The same numbers as ``rng.uniform(low, high, (count, n))``; where a box is wider than
    the largest float (``high - low`` overflows, bounds near +-1e308) the draws are made in
    the box halved and doubled, which is exact (scaling by 2 is exact in binary floating
    point) instead of numpy's ``OverflowError``.

    Parameters
    ----------
    rng : numpy.random.Generator
    low, high : ndarray, shape (n,)
        Finite bounds with ``low <= high``.
    count : int
        Rows.
    """
    if not isinstance(rng, np.random.Generator):
        raise InputError(
            "rng",
            "a numpy.random.Generator",
            type(rng).__name__,
            "pass np.random.default_rng(seed).",
        )
    low = check_array("low", low, (None,))
    if not low.size:
        raise InputError(
            "low",
            "a bound for at least one joint",
            "an empty array",
            "pass one lower bound per joint, e.g. low=np.full(n, -np.pi).",
        )
    high = check_array("high", high, (low.size,))
    count = check_integer("count", count, 0, MAX_AXIS_VALUES)
    if np.any(low > high):
        raise InputError(
            "high",
            "bounds with low <= high",
            f"high {high} below low {low}",
            "swap the bounds where they are reversed, e.g. low=np.minimum(low, high), "
            "high=np.maximum(low, high).",
        )
    with np.errstate(over="ignore"):
        wide = not np.all(np.isfinite(high - low))
    if not wide:
        return rng.uniform(low, high, (count, low.size))
    return 2.0 * rng.uniform(0.5 * low, 0.5 * high, (count, low.size))


class ConfigurationSet:
    """A sequence of joint configurations, produced by ranges of rows.

    ``np.asarray(configurations)`` gives every row, shape (len, n), in radians (metres for
    prismatic joints); a set of more than :data:`MAX_IN_MEMORY` numbers is read in parts
    with :meth:`rows` instead (``pe.sweep`` does).
    """

    n: int

    def __len__(self) -> int:
        raise NotImplementedError

    def rows(self, start: int, stop: int) -> NDArray[np.float64]:
        """Configurations ``start`` to ``stop - 1``, shape (stop - start, n)."""
        raise NotImplementedError

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> NDArray[Any]:
        """Every configuration, shape (len, n): the array protocol of numpy."""
        if copy is False:
            raise ValueError(
                "a configuration set makes its rows on demand: it cannot be viewed without "
                "a copy (use np.asarray, or copy=None)"
            )
        total = len(self)
        if total * self.n > MAX_IN_MEMORY:
            raise InputError(
                "configurations",
                f"at most {MAX_IN_MEMORY:,} numbers (rows times joints) as one array",
                f"{total:,} rows of {self.n} joints",
                "read them in parts with .rows(start, stop), or pass the set itself to "
                "pe.sweep (it reads it lazily).",
            )
        rows = self.rows(0, total)
        return rows if dtype is None else rows.astype(dtype, copy=False)


class Grid(ConfigurationSet):
    """The Cartesian product of per-joint values, the last joint varying fastest.

    Parameters
    ----------
    axes : sequence of array-like
        The values of each joint (a single value for a fixed joint).
    """

    def __init__(self, axes: Sequence[ArrayLike]) -> None:
        self.axes = [
            np.atleast_1d(
                check_array(f"q{i + 1}", a, (None,)) if np.ndim(a) else np.array([a], float)
            )
            for i, a in enumerate(axes)
        ]
        self.n = len(self.axes)
        self.shape = tuple(a.size for a in self.axes)

    def __len__(self) -> int:
        return int(np.prod(self.shape))

    def rows(self, start: int, stop: int) -> NDArray[np.float64]:
        """Configurations ``start`` to ``stop - 1`` of the grid."""
        index = np.unravel_index(np.arange(start, min(stop, len(self))), self.shape)
        return np.stack([axis[i] for axis, i in zip(self.axes, index, strict=True)], axis=1)

    def __repr__(self) -> str:
        return f"Grid(shape={self.shape})"


def grid(*axes: float | tuple[float, float, int] | ArrayLike) -> Grid:
    """A grid of configurations, one argument per joint.

    Each argument is a fixed value, a ``(start, stop, num)`` tuple (a range, inclusive,
    like ``numpy.linspace``; ``num`` an integer) or explicit values as a list or array.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> g = pe.grid(np.pi / 2, (-np.pi, np.pi, 3), (0.0, 1.0, 2))
    >>> len(g), g.rows(0, 2).tolist()[1]
    (6, [1.5707963267948966, -3.141592653589793, 1.0])
    """
    if not axes:
        raise InputError(
            "axes",
            "one value, range or array per joint",
            "none",
            "give one argument per joint, e.g. pe.grid(np.pi / 2, (-np.pi, np.pi, 5), 0.0).",
        )
    values = []
    for i, axis in enumerate(axes):
        if isinstance(axis, tuple):  # always a range: explicit values go as a list or array
            if len(axis) != 3:
                raise InputError(
                    f"q{i + 1}",
                    "a (start, stop, num) range; explicit values as a list or an array",
                    repr(axis),
                    f"give a range of three numbers, e.g. q{i + 1}=(-np.pi, np.pi, 5), or explicit "
                    f"values as a list, e.g. {list(axis)!r}.",
                )
            start, stop = check_array(f"q{i + 1}", axis[:2], (2,))
            num = check_integer(f"q{i + 1} num", axis[2], 1, MAX_AXIS_VALUES)
            values.append(np.linspace(start, stop, num))
        else:
            shape: tuple[None, ...] = () if array_ndim(axis) == 0 else (None,)
            values.append(np.atleast_1d(check_array(f"q{i + 1}", axis, shape)))
            if values[-1].size == 0:
                raise InputError(
                    f"q{i + 1}",
                    "at least one value",
                    "an empty array",
                    f"give at least one angle, e.g. q{i + 1}=[0.0], or a range such as "
                    "(-np.pi, np.pi, 5).",
                )
    return Grid(values)


class RandomConfigurations(ConfigurationSet):
    """Seeded uniform samples in a box, generated in fixed blocks of rows.

    Row ``i`` is the same whatever range it is asked in: rows are drawn in blocks of
    ``BLOCK`` from a generator seeded with ``(seed, block)``.
    """

    BLOCK = 4096

    def __init__(self, count: int, low: ArrayLike, high: ArrayLike, seed: int = 0) -> None:
        self.low = check_array("low", low, (None,))
        self.high = check_array("high", high, (self.low.size,))
        if np.any(self.low > self.high):
            raise InputError(
                "low",
                "low <= high for every joint",
                f"low={self.low}, high={self.high}",
                "swap the bounds where they are reversed, e.g. low=np.minimum(low, high), "
                "high=np.maximum(low, high).",
            )
        self.count = check_integer("count", count, 1, 2**62)
        self.seed = check_integer("seed", seed, 0, 2**63 - 1)
        self.n = self.low.size

    def __len__(self) -> int:
        return self.count

    def rows(self, start: int, stop: int) -> NDArray[np.float64]:
        """Configurations ``start`` to ``stop - 1``."""
        stop = min(stop, self.count)
        first, last = start // self.BLOCK, (stop - 1) // self.BLOCK
        blocks = [
            uniform_rows(np.random.default_rng([self.seed, b]), self.low, self.high, self.BLOCK)
            for b in range(first, last + 1)
        ]
        rows = np.concatenate(blocks)
        return rows[start - first * self.BLOCK : stop - first * self.BLOCK]

    def __repr__(self) -> str:
        return f"RandomConfigurations(count={self.count}, seed={self.seed})"


def joint_bounds(robot: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A robot's joint limits: lower and upper positions, shape (n,) each.

    A URDF robot's (:attr:`~polyell.UrdfRobot.position_limits`, ``[-pi, pi]`` for a
    continuous joint); ``[-pi, pi]`` for every joint of a robot without limits (the
    planar arm's revolute joints).

    Parameters
    ----------
    robot : PlanarArm or UrdfRobot
        Anything with ``n`` joints and ``dynamics(q)``.

    Raises
    ------
    InputError
        For an object that is not a robot.
    """
    if not _is_robot(robot):
        raise InputError(
            "robot",
            "a robot (pe.PlanarArm, pe.UrdfRobot, pe.robots.load(...))",
            type(robot).__name__,
            "pass a robot, e.g. pe.robots.load('chiacchio2000'); for a box without a robot, "
            "call random_configurations(count, low, high).",
        )
    limits = getattr(robot, "position_limits", None)
    if limits is None:
        return np.full(robot.n, -np.pi), np.full(robot.n, np.pi)
    low, high = limits
    return np.array(low, dtype=float), np.array(high, dtype=float)


def _is_robot(value: object) -> bool:
    return hasattr(value, "dynamics") and hasattr(value, "n") and not isinstance(value, type)


def _in_box(count: int, low: ArrayLike, high: ArrayLike, seed: int = 0) -> RandomConfigurations:
    return RandomConfigurations(count, low, high, seed)


def _for_robot(
    robot: Any,
    count: int,
    seed: int = 0,
    *,
    low: ArrayLike | None = None,
    high: ArrayLike | None = None,
) -> RandomConfigurations:
    lower, upper = joint_bounds(robot)
    for name, given in (("low", low), ("high", high)):
        if given is not None:
            bound = check_array(name, given, (robot.n,))
            lower, upper = (bound, upper) if name == "low" else (lower, bound)
    return RandomConfigurations(count, lower, upper, seed)


@overload
def random_configurations(
    count: int, low: ArrayLike, high: ArrayLike, seed: int = 0
) -> RandomConfigurations: ...


@overload
def random_configurations(
    robot: Any,
    count: int,
    seed: int = 0,
    *,
    low: ArrayLike | None = None,
    high: ArrayLike | None = None,
) -> RandomConfigurations: ...


def random_configurations(*args: Any, **kwargs: Any) -> RandomConfigurations:
    """Seeded uniform configurations (lazy): in a robot's joint limits, or in a box.

    Two forms:

    * ``random_configurations(robot, count, seed=0, *, low=None, high=None)``: in the
      robot's joint limits (:func:`joint_bounds`; ``low`` or ``high`` replace them);
    * ``random_configurations(count, low, high, seed=0)``: in the box ``[low, high]``.

    Parameters
    ----------
    robot : PlanarArm or UrdfRobot
    count : int
        Configurations, at least 1.
    low, high : array-like, shape (n,)
        Bounds of each joint [rad, or m for a prismatic joint].
    seed : int, optional
        Row ``i`` depends on ``seed`` and ``i`` only (not on how the rows are read).

    Returns
    -------
    RandomConfigurations
        ``np.asarray`` of it is the (count, n) array of rows.

    Examples
    --------
    >>> import numpy as np, polyell as pe
    >>> arm = pe.robots.load("chiacchio2000")
    >>> q = np.asarray(pe.random_configurations(arm, 4, seed=1))
    >>> q.shape, bool(np.all(np.abs(q) <= np.pi))
    ((4, 3), True)
    """
    robot_form = (bool(args) and _is_robot(args[0])) or "robot" in kwargs
    form = _for_robot if robot_form else _in_box
    try:
        inspect.signature(form).bind(*args, **kwargs)
    except TypeError as exn:
        raise InputError(
            "arguments",
            "random_configurations(robot, count, seed=0) or "
            "random_configurations(count, low, high, seed=0)",
            str(exn),
            "pass a robot and a count, or a count and the bounds of every joint.",
        ) from None
    return form(*args, **kwargs)
