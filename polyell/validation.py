"""Validators that convert, check and return clean float64 arrays.

Each ``check_*`` function takes the argument's name (as the caller wrote it) so that
the :class:`~polyell.errors.InputError` it raises can point at the right place.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError

__all__ = [
    "DIRECTION_NORM_RTOL",
    "MAX_SPEED",
    "MAX_TORQUE",
    "MIN_RELATIVE_EXTENT",
    "ROUNDED_INPUT_RTOL",
    "array_ndim",
    "as_floats",
    "check_array",
    "check_directions",
    "check_fraction",
    "check_frame",
    "check_instance",
    "check_integer",
    "check_magnitudes",
    "check_points",
    "check_spd",
    "check_torque_limits",
    "check_velocity_limits",
    "source_torque_limits",
    "source_velocity_limits",
]

#: The one rule for rounded input: numbers typed or printed to 5 significant digits or
#: more carry a relative rounding error of at most ``0.5e-4`` each (half a unit in the
#: fifth digit of a leading 1), so a unit direction typed that way has a norm within
#: ``0.5e-4`` of 1 and a component off any set it lies in of at most ``0.5e-4``; a point
#: printed that way is within ``0.5e-4 |x|`` of where it belongs.  ``ROUNDED_INPUT_RTOL``
#: (twice that) bounds both: it is the tolerance on a direction's unit norm
#: (:func:`check_directions`) and, as :data:`polyell.AFFINE_RTOL`, on "on the affine set".
ROUNDED_INPUT_RTOL = 1e-4
#: Tolerance on the unit norm of a direction: the rounded-input rule.
DIRECTION_NORM_RTOL = ROUNDED_INPUT_RTOL
#: Relative tolerance on the symmetry of an inertia matrix.
SYMMETRY_RTOL = 1e-9
#: Most directions a direction set may hold (a million 6-D directions take 48 MB).
MAX_DIRECTIONS = 1_000_000
#: Most values along one axis of a grid.
MAX_AXIS_VALUES = 100_000_000


def _describe(value: object) -> str:
    """Say briefly what arrived (a value that is not an array of numbers)."""
    text = f"{type(value).__name__} {value!r}"
    return text if len(text) <= 120 else text[:117] + "..."


def _as_finite_float(
    name: str, value: ArrayLike, expected: Callable[[], str]
) -> NDArray[np.float64]:
    """Convert to a float64 array and reject NaN and infinity (``expected()``: for messages)."""
    if value is None:  # np.array(None, dtype=float) would be a silent NaN
        raise InputError(
            name,
            expected(),
            "None",
            "pass numbers instead of None, as a list or an array, e.g. [0.0, 1.0]",
        )
    try:
        raw = np.asarray(value)
        complex_values = np.iscomplexobj(raw)
        array = np.array(raw.real if complex_values else raw, dtype=np.float64)
    except (TypeError, ValueError):  # a ragged list: "inhomogeneous shape"
        raise InputError(
            name,
            expected(),
            _describe(value),
            "pass numbers only, in rows of one length, e.g. [[1.0, 0.0], [0.0, 1.0]] "
            "(np.asarray(value, dtype=float) must accept it)",
        ) from None
    if complex_values:  # a float conversion would silently drop the imaginary part
        raise InputError(
            name,
            expected(),
            f"complex values ({_describe(value)})",
            "pass real numbers, e.g. np.real(value) where the imaginary parts are rounding noise",
        )
    if not np.isfinite(array).all():
        bad = np.argwhere(~np.isfinite(array))[0]
        raise InputError(
            name,
            "finite values",
            f"{array[tuple(bad)]} at index {tuple(int(i) for i in bad)}",
            "remove NaN and infinite entries.",
        )
    return array


def check_array(
    name: str, value: ArrayLike, shape: Sequence[int | str | None], *, what: str = "real numbers"
) -> NDArray[np.float64]:
    """Convert ``value`` to a finite float64 array of the given shape.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : array-like
        The value to check.
    shape : sequence of int, str or None
        Expected shape; a str (a label such as ``"m"``, shown in messages) or ``None``
        (shown as ``k``) matches any length along that axis.
    what : str, optional
        Description of the entries, used in error messages.

    Returns
    -------
    array : ndarray of float64, shape ``shape``
        A fresh, contiguous copy.

    Raises
    ------
    InputError
        If ``value`` is not numeric, has the wrong shape or holds NaN or infinity.
    """
    if (  # a float64 array of the right shape and finite: the copy, no more to check
        type(value) is np.ndarray
        and value.dtype == np.float64
        and value.ndim == len(shape)
        and all(not isinstance(s, int) or s == a for s, a in zip(shape, value.shape, strict=True))
    ):
        array = np.array(value)
        if np.isfinite(array).all():
            return array

    def expected() -> str:
        dims = ", ".join("k" if s is None else str(s) for s in shape)
        return f"an array of {what} with shape ({dims}{',' if len(shape) == 1 else ''})"

    array = _as_finite_float(name, value, expected)
    if array.ndim != len(shape) or any(
        isinstance(s, int) and s != a for s, a in zip(shape, array.shape, strict=True)
    ):
        raise InputError(
            name, expected(), f"shape {array.shape}", "check the number of joints and task rows."
        )
    return array


def check_spd(
    name: str,
    value: ArrayLike,
    n: int | str,
    batch: tuple[int, ...] = (),
    *,
    fix: str = "an inertia matrix has strictly positive eigenvalues; check masses and inertias.",
) -> NDArray[np.float64]:
    """Check symmetric positive-definite (n, n) matrices, such as inertia matrices.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : array-like, shape batch + (n, n)
        The matrix, or a stack of them.
    n : int or str
        Expected size, or a label (any square size).
    batch : tuple of int, optional
        Leading (batch) shape.
    fix : str, optional
        How to repair a matrix that is not positive definite.

    Returns
    -------
    matrix : ndarray of float64, shape batch + (n, n)
        The matrices, symmetrised exactly (``(B + B^T) / 2``) after the check.

    Raises
    ------
    InputError
        If a matrix is not square of size ``n``, not symmetric to a relative tolerance of
        ``SYMMETRY_RTOL``, or not positive definite.
    """
    matrix = check_array(name, value, (*batch, n, n))
    if matrix.shape[-1] != matrix.shape[-2]:
        raise InputError(
            name,
            f"a square ({n}, {n}) matrix",
            f"shape {matrix.shape}",
            "pass a square matrix: as many rows as columns",
        )
    transposed = np.swapaxes(matrix, -1, -2)
    scale = float(np.max(np.abs(matrix))) if matrix.size else 0.0
    # Differences of entries above 1 scaled to at most 1: no overflow near 1e308 (and no
    # 1 / scale for subnormal entries, which would overflow instead).
    unit = 1.0 / scale if scale > 1.0 else 1.0
    asymmetry = np.max(np.abs(matrix * unit - transposed * unit)) / unit if matrix.size else 0.0
    if asymmetry > SYMMETRY_RTOL * scale:
        raise InputError(
            name,
            "a symmetric matrix",
            f"max |B - B^T| = {asymmetry:.3g} (max |B| = {scale:.3g})",
            "pass a symmetric matrix (the inertia matrix is one).",
        )
    matrix = 0.5 * matrix + 0.5 * transposed
    try:
        np.linalg.cholesky(matrix)
    except np.linalg.LinAlgError:
        smallest = np.linalg.eigvalsh(matrix)[..., 0]
        where = np.unravel_index(np.argmin(smallest), smallest.shape) if batch else ()
        at = f" (matrix {tuple(int(i) for i in where)})" if batch else ""
        raise InputError(
            name,
            "a positive-definite matrix",
            f"smallest eigenvalue {np.min(smallest):.6g}{at}",
            fix,
        ) from None
    return matrix


#: Reductions without the array methods' Python wrappers (the fast paths of one set).
_ALL, _MAX, _MIN = np.logical_and.reduce, np.maximum.reduce, np.minimum.reduce

#: Largest torque limit accepted [N m]: ``tau_max - tau_min`` and its products with the
#: inverse inertia stay finite; a limit beyond it is no limit (the sets would be unbounded).
MAX_TORQUE = 1e150


def _check_torque_size(name: str, value: NDArray[np.float64]) -> None:
    if value.size and np.max(np.abs(value)) > MAX_TORQUE:
        i = int(np.argmax(np.abs(value)))
        raise InputError(
            name,
            f"limits of size at most {MAX_TORQUE:g} (N m, rad/s)",
            f"{name}[{i}] = {value[i]:.3g}",
            "give the real limits (with the gravity torques in the same units); polyell's "
            "sets are bounded.",
        )


def _plain(value: object, n: int) -> bool:
    """Whether ``value`` is a float64 array of shape (n,)."""
    return type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (n,)


def check_torque_limits(
    tau_max: ArrayLike,
    tau_min: ArrayLike | None,
    n: int,
    names: tuple[str, str] = ("tau_max", "tau_min"),
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Check joint torque limits and return ``(tau_max, tau_min)`` as float64 arrays.

    Parameters
    ----------
    tau_max : array-like, shape (n,)
        Upper torque bounds [N m].
    tau_min : array-like, shape (n,), optional
        Lower torque bounds [N m]; default ``-tau_max`` (then ``tau_max`` must be
        positive).
    n : int
        Number of joints.
    names : (str, str), optional
        The arguments' names in messages (``("qd_max", "qd_min")`` for velocity limits).

    Raises
    ------
    InputError
        If a shape is wrong, a value is not finite, or ``tau_min >= tau_max`` anywhere.
    """
    hi, lo = names
    if _plain(tau_max, n) and (tau_min is None or _plain(tau_min, n)):
        # float64 arrays of the right shape: finite, within MAX_TORQUE and ordered in a
        # few operations (the checks below say what is wrong otherwise)
        upper = np.array(tau_max)
        lower = -upper if tau_min is None else np.array(tau_min)
        # ordered (NaN is not) and within MAX_TORQUE: lower >= -MAX_TORQUE and upper <=
        # MAX_TORQUE bound both, as lower < upper
        if (
            _ALL(lower < upper, None)
            and -MAX_TORQUE <= _MIN(lower, None, initial=0.0)
            and (_MAX(upper, None, initial=0.0) <= MAX_TORQUE)
        ):
            return upper, lower
    upper = check_array(hi, tau_max, (n,))
    _check_torque_size(hi, upper)
    if tau_min is None:
        if (upper <= 0).any():
            bad = np.flatnonzero(upper <= 0)
            raise InputError(
                hi,
                f"strictly positive symmetric bounds when {lo} is not given",
                f"{hi}[{bad[0]}] = {upper[bad[0]]:g}",
                f"give positive bounds, or pass {lo} explicitly for asymmetric limits.",
            )
        return upper, -upper
    lower = check_array(lo, tau_min, (n,))
    _check_torque_size(lo, lower)
    if (lower >= upper).any():
        i = np.flatnonzero(lower >= upper)[0]
        raise InputError(
            lo,
            f"{lo} < {hi} for every joint",
            f"{lo}[{i}] = {lower[i]:g} >= {hi}[{i}] = {upper[i]:g}",
            "each joint needs a range of positive width.",
        )
    return upper, lower


#: Largest joint speed accepted [rad/s or m/s]: a velocity limit beyond it is no limit.
MAX_SPEED = 1e150


def check_velocity_limits(
    qd_max: ArrayLike, qd_min: ArrayLike | None, n: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Check joint velocity limits and return ``(qd_max, qd_min)`` as float64 arrays.

    The limits are a box of joint velocities, ``qd_min < qd_max`` for every joint: the
    rule of ``pe.analyze(..., capacity="velocity", qd_max=, qd_min=)``, so that a robot (a
    robot or study file) takes every box the analysis takes.  Joint limits usually
    bracket rest (``qd_min <= 0 < qd_max``; ``qd_min = 0``: a joint that only turns one
    way); a ``qd_min`` above 0 is a joint that must move forward, and its velocity set lies
    away from rest.

    Parameters
    ----------
    qd_max : array-like, shape (n,)
        Upper joint velocities [rad/s or m/s]; strictly positive without ``qd_min``.
    qd_min : array-like, shape (n,), optional
        Lower joint velocities [rad/s or m/s], below ``qd_max``; default ``-qd_max``.
    n : int
        Number of joints.

    Raises
    ------
    InputError
        If a shape is wrong, a value is not finite or beyond :data:`MAX_SPEED`, a
        ``qd_max`` is not positive without ``qd_min``, or ``qd_min >= qd_max`` for a joint.
    """
    upper = check_array("qd_max", qd_max, (n,), what="joint velocities [rad/s or m/s]")
    lower = (
        -upper
        if qd_min is None
        else check_array("qd_min", qd_min, (n,), what="joint velocities [rad/s or m/s]")
    )
    for name, values in (("qd_max", upper), ("qd_min", lower)):
        if values.size and np.max(np.abs(values)) > MAX_SPEED:
            i = int(np.argmax(np.abs(values)))
            raise InputError(
                name,
                f"joint velocity limits of size at most {MAX_SPEED:g} rad/s (or m/s)",
                f"{name}[{i}] = {values[i]:.3g}",
                "give the joints' real velocity limits; a limit beyond it is no limit.",
            )
    if qd_min is None:
        bad = np.flatnonzero(~(upper > 0))
        if bad.size:
            raise InputError(
                "qd_max",
                "strictly positive upper joint velocities [rad/s or m/s]",
                f"qd_max[{bad[0]}] = {upper[bad[0]]:g}",
                "without qd_min (it defaults to -qd_max) the limits bracket rest: give "
                "positive limits, or qd_min explicitly for a box that does not hold rest.",
            )
    bad = np.flatnonzero(~(lower < upper))
    if bad.size:
        i = bad[0]
        raise InputError(
            "qd_min",
            "qd_min < qd_max for every joint [rad/s or m/s]",
            f"qd_min[{i}] = {lower[i]:g} >= qd_max[{i}] = {upper[i]:g}",
            "each joint needs a range of positive width; a lower limit is usually at most 0 "
            "(a negative qd_min is a speed backwards).",
        )
    return upper, lower + 0.0  # + 0.0: no negative zero from -qd_max


def array_ndim(value: ArrayLike) -> int:
    """``np.ndim(value)``, or -1 for a ragged nested list (check_array then says what is wrong)."""
    try:
        return int(np.ndim(value))
    except ValueError:
        return -1


def check_instance(name: str, value: object, kind: type | tuple[type, ...], fix: str = "") -> None:
    """Refuse a value that is not an instance of ``kind``, naming the argument and the fix."""
    if not isinstance(value, kind):
        kinds = kind if isinstance(kind, tuple) else (kind,)
        expected = " or ".join(k.__name__ for k in kinds)
        raise InputError(
            name,
            f"a {expected}",
            _describe(value)[:120],
            fix or f"pass a {expected} as {name}, not a {type(value).__name__}",
        )


def check_frame(name: str, value: object, fix: str = "") -> None:
    """Refuse a value that is not a pandas DataFrame (pandas imported only here, lazily)."""
    import pandas as pd

    check_instance(name, value, pd.DataFrame, fix)


def as_floats(name: str, value: object) -> NDArray[np.float64]:
    """``value`` as an array of floats (NaN and inf allowed), or an InputError naming it."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(
            name,
            "an array of real numbers",
            repr(value)[:80],
            "pass numbers only, in rows of one length, e.g. [[0.0, 1.0], [1.0, 0.0]]",
        ) from None


def check_integer(name: str, value: object, low: int, high: int) -> int:
    """Check an integer in ``[low, high]`` (a Python or numpy integer, not a bool or float)."""
    if (
        isinstance(value, bool)
        or not isinstance(value, int | np.integer)
        or not (low <= int(value) <= high)
    ):
        raise InputError(
            name,
            f"an integer from {low:,} to {high:,}",
            _describe(value),
            f"pass an int in that range, e.g. {_integer_example(value, low, high)}",
        )
    return int(value)


def _integer_example(value: object, low: int, high: int) -> int:
    """An integer of ``[low, high]`` near ``value`` (a real number), else ``low``."""
    if isinstance(value, int | np.integer) and not isinstance(value, bool):
        return min(max(int(value), low), high)
    if isinstance(value, float | np.floating) and not np.isnan(value):
        return high if value >= high else low if value <= low else round(float(value))
    return low


def check_fraction(name: str, value: object) -> float:
    """Check a relative tolerance: a real number in ``[0, 1)``, returned as a float."""
    if type(value) is float and 0.0 <= value < 1.0:  # the usual case: as it is
        return value
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float | np.integer | np.floating)
        or not 0.0 <= float(value) < 1.0
    ):
        raise InputError(
            name,
            "a relative tolerance in [0, 1)",
            repr(value),
            f"pass a float from 0 up to (not including) 1, e.g. {name}=1e-9, or leave it out",
        )
    return float(value)


def magnitude_limit(m: int) -> int:
    """Largest ``log10`` of an acceleration magnitude accepted in an m-dimensional task.

    Volumes are in (m/s^2)^r with r up to m, and squares of accelerations are formed, so
    sizes within ``10^(+-min(140, 290 // m))`` keep every quantity representable.
    """
    return min(140, 290 // m)


#: Smallest extent of the polytope relative to its distance from the origin: below
#: ``sqrt(eps)`` its points (``xg + M t``) keep fewer than half of their digits.
MIN_RELATIVE_EXTENT = float(np.sqrt(np.finfo(float).eps))


def check_magnitudes(
    M: NDArray[np.float64],
    xg: NDArray[np.float64],
    argument: str | None = None,
    quantity: tuple[str, str, str] = ("accelerations", "the generators M (eq. 14)", "xg (eq. 8)"),
    limits: str = "tau_max",
) -> None:
    """Refuse accelerations too large or too small for floating point (issue 15).

    Parameters
    ----------
    M : ndarray, shape (..., m, n)
        Generators (eq. 14), one matrix or a batch.
    xg : ndarray, shape (..., m)
        Centres (eq. 8).
    argument : str, optional
        The argument the errors name when ``M`` and ``xg`` were given directly (a
        :class:`~polyell.Polytope`'s ``"generators"``); by default they come from a robot's
        dynamics and torque limits.
    quantity : (str, str, str)
        What the sets hold and what ``M`` and ``xg`` are, for the messages (the velocity
        and force capacities name theirs).
    limits : {"tau_max", "qd_max"}
        The joint limits the sets come from (torques, or the velocity capacity's joint
        velocities): the messages name them with ``dyn`` and say how to rescale them.

    Raises
    ------
    InputError
        If the largest entry of M or of xg (when non-zero) is outside
        ``10^(+-magnitude_limit(m))``, or if M (when non-zero) is below
        :data:`MIN_RELATIVE_EXTENT` times xg: a set that small against its distance from
        rest (torques far too weak to hold the arm against gravity, or torque limits in
        other units than the gravity torques) is below the resolution of its own points.
    """
    m = M.shape[-2]
    limit = magnitude_limit(m)
    high = 10.0**limit
    if M.ndim == 2 and M.size and xg.size:  # one set: the same tests on two numbers
        one_m, one_x = float(_MAX(np.abs(M), None)), float(_MAX(np.abs(xg), None))
        if (
            one_m <= high
            and one_x <= high
            and not 0.0 < one_m < 1.0 / high
            and not 0.0 < one_x < 1.0 / high
            and not 0.0 < one_m < MIN_RELATIVE_EXTENT * one_x
        ):
            return
    size_m = np.max(np.abs(M), axis=(-2, -1)) if M.size else np.zeros(M.shape[:-2])
    size_x = np.max(np.abs(xg), axis=-1) if xg.size else np.zeros(xg.shape[:-1])
    what_sets, what_m, what_x = quantity
    sizes = {  # largest entries: no squares, which would overflow first
        what_m: size_m,
        f"the centre {what_x}": size_x,
    }
    for what, size in sizes.items():
        # not (size <= high): an overflow to inf or NaN is too large as well
        bad = np.atleast_1d(~(size <= high) | ((size > 0) & (size < 1.0 / high)))
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            where = f" (configuration {k} of the batch)" if np.ndim(size) else ""
            if argument:
                fix = "scale the generators and the centre together."
            elif limits == "qd_max":
                fix = "scale the rows of J, or the joint velocity limits qd_max and qd_min."
            else:
                fix = (
                    "scale the rows of J (and Jdot qdot), or the torque limits together "
                    "with the gravity torques."
                )
            raise InputError(
                argument or f"dyn or {limits}",
                f"{what_sets} of size within 1e-{limit}..1e{limit} in a "
                f"{m}-dimensional task, so that volumes in (unit)^{m} stay representable",
                f"{what} of size {float(np.atleast_1d(size)[k]):.3g}{where}"
                + ("" if np.isfinite(np.atleast_1d(size)[k]) else " (an overflow)"),
                "express the task in other units: " + fix,
            )
    tiny = np.atleast_1d((size_m > 0) & (size_m < MIN_RELATIVE_EXTENT * size_x))
    if tiny.any():
        k = int(np.flatnonzero(tiny)[0])
        where = f" (configuration {k} of the batch)" if np.ndim(size_m) else ""
        if argument:
            raise InputError(
                argument,
                f"generators of at least {MIN_RELATIVE_EXTENT:.1e} of the centre's size, so "
                "that the polytope's points are resolved in floating point",
                f"generators of size {float(np.atleast_1d(size_m)[k]):.3g} against a centre "
                f"of size {float(np.atleast_1d(size_x)[k]):.3g}",
                "shift the set so that its centre is near the origin (limits are taken "
                "along lines through it).",
            )
        if limits == "qd_max":
            raise InputError(
                "qd_max",
                f"a joint velocity box wider than {MIN_RELATIVE_EXTENT:.1e} of its centre's "
                "image, so that the polytope's points are resolved in floating point",
                f"{what_m} of size {float(np.atleast_1d(size_m)[k]):.3g} against the centre "
                f"{what_x} of size {float(np.atleast_1d(size_x)[k]):.3g}{where}",
                "give qd_max and qd_min that differ by more than their rounding.",
            )
        raise InputError(
            "tau_max",
            f"torque limits that move the arm by more than {MIN_RELATIVE_EXTENT:.1e} of its "
            "free-fall acceleration, so that the polytope's points are resolved in floating "
            "point",
            f"{what_m} of size {float(np.atleast_1d(size_m)[k]):.3g} against the centre "
            f"{what_x} of size {float(np.atleast_1d(size_x)[k]):.3g}{where}",
            "give the torque limits and the gravity torques in the same units (N m).",
        )


def source_torque_limits(
    source: object, tau_max: ArrayLike | None, tau_min: ArrayLike | None, n: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Torque limits given, or else the source's own (a robot's ``tau_max``, ``tau_min``).

    A ``tau_min`` given without ``tau_max`` goes with the robot's ``tau_max`` (as a
    ``qd_min`` does with its ``qd_max``).
    """
    if tau_max is None:
        tau_max, default_min = getattr(source, "tau_max", None), getattr(source, "tau_min", None)
        if tau_max is None:
            raise InputError(
                "tau_max",
                "torque limits (the source has none of its own)",
                "tau_min alone" if tau_min is not None else "None",
                "pass tau_max=[...] (and tau_min=).",
            )
        tau_min = default_min if tau_min is None else tau_min
    return check_torque_limits(tau_max, tau_min, n)


def source_velocity_limits(
    source: object, qd_max: ArrayLike | None, qd_min: ArrayLike | None, n: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Velocity limits given, or else the robot's own (``robot.velocity_limits()``)."""
    if qd_max is None:
        if not hasattr(source, "velocity_limits"):
            raise InputError(
                "qd_max",
                "joint velocity limits [rad/s] for the velocity capacity",
                ("qd_min alone" if qd_min is not None else "none")
                + " (a batched Dynamics has no limits of its own)",
                "pass qd_max=[...] (and qd_min=).",
            )
        qd_max, default_min = source.velocity_limits()
        qd_min = default_min if qd_min is None else qd_min
    return check_torque_limits(qd_max, qd_min, n, names=("qd_max", "qd_min"))


#: Joint speeds above this [rad/s] are refused: beyond any drive, and the Coriolis and
#: centrifugal torques (quadratic in qd) would leave floating point before the limits do.
MAX_JOINT_SPEED = 1e6


def check_joint_velocities(name: str, value: ArrayLike, n: int) -> NDArray[np.float64]:
    """Joint velocities ``qd`` (n,) [rad/s or m/s] of a robot in motion, finite and bounded."""
    qd = check_array(name, value, (n,), what="joint velocities [rad/s]")
    if np.abs(qd).max(initial=0.0) > MAX_JOINT_SPEED:
        raise InputError(
            name,
            f"joint velocities of at most {MAX_JOINT_SPEED:.0e} rad/s",
            f"{np.abs(qd).max():.3g} rad/s",
            "give the joint velocities in rad/s (m/s for prismatic joints).",
        )
    return qd


def check_points(name: str, value: ArrayLike, m: int) -> NDArray[np.float64]:
    """Check finite task-space points of shape ``(m,)`` or ``(..., m)``.

    Coordinates beyond ``10^magnitude_limit(m)`` (the bound :func:`check_magnitudes` puts
    on the sets themselves) are refused: their squares and their products with the sets'
    facets would overflow.

    Returns
    -------
    points : ndarray of float64, shape ``(..., m)``
    """
    expected = f"points with {m} coordinates in the last axis, shape (m,) or (k, m)"
    array = _as_finite_float(name, value, lambda: expected)
    if array.ndim == 0 or array.shape[-1] != m:
        raise InputError(
            name, expected, f"shape {array.shape}", "give one entry per task-space row of J."
        )
    limit = magnitude_limit(m)
    if array.size and np.max(np.abs(array)) > 10.0**limit:
        raise InputError(
            name,
            f"coordinates of size at most 1e{limit} in a {m}-dimensional task",
            f"an entry of size {np.max(np.abs(array)):.3g}",
            "express the task in other units.",
        )
    return array


def check_directions(name: str, value: ArrayLike, m: int) -> NDArray[np.float64]:
    """Check unit direction vectors of shape ``(m,)`` or ``(k, m)``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : array-like, shape (m,) or (k, m)
        Directions; each must have unit Euclidean norm to a relative tolerance of
        ``DIRECTION_NORM_RTOL`` (:data:`ROUNDED_INPUT_RTOL`: a unit vector typed to 5
        significant digits or more passes).
    m : int
        Task-space dimension.

    Returns
    -------
    directions : ndarray of float64, shape (m,) or (k, m)
        The directions, renormalised exactly to unit length.

    Raises
    ------
    InputError
        On a wrong shape, a non-finite entry, a zero-length or a non-unit direction.
    """
    directions = check_points(name, value, m)
    if directions.ndim > 2:
        raise InputError(
            name,
            "shape (m,) or (k, m)",
            f"shape {directions.shape}",
            f"stack the directions in rows, e.g. np.reshape({name}, (-1, {m}))",
        )
    # The norm of the rows scaled by their largest entry: no overflow for entries of 1e308
    # and no underflow for 1e-300 (either is then refused as far from unit length).
    largest = np.max(np.abs(directions), axis=-1)
    if np.any(largest == 0):
        i = int(np.flatnonzero(np.atleast_1d(largest) == 0)[0])
        raise InputError(
            name,
            "non-zero unit direction vectors",
            f"a zero-length direction at row {i}",
            "every direction needs a non-zero length.",
        )
    scaled = directions / largest[..., None]
    norms = np.linalg.norm(scaled, axis=-1) * largest
    off = ~(np.abs(norms - 1.0) <= DIRECTION_NORM_RTOL)
    if np.any(off):
        i = int(np.flatnonzero(np.atleast_1d(off))[0])
        norm = float(np.atleast_1d(norms)[i])
        raise InputError(
            name,
            f"unit direction vectors, to {DIRECTION_NORM_RTOL:g} (the limits are the values a "
            "with a * t in the set, in the task's unit)",
            f"a direction of norm {norm!r}"
            + (  # how far from 1, where that is what the rounding of the input decides
                f" (1 {'+' if norm >= 1 else '-'} {abs(norm - 1.0):.3g})"
                if abs(norm - 1.0) < 0.5
                else ""
            )
            + f" at row {i}",
            "normalise with T / np.linalg.norm(T, axis=-1, keepdims=True).",
        )
    unit: NDArray[np.float64] = scaled / np.linalg.norm(scaled, axis=-1)[..., None]
    return unit
