r"""The largest ball about the origin inside an ellipsoid, batched and exact.

For a full-dimensional ellipsoid :math:`E = \{c + U \operatorname{diag}(s) u : \|u\| \le 1\}`
that contains the origin, the radius is the distance from the origin to the boundary of
E.  In E's frame the origin is :math:`z = -U^T c`; the nearest boundary point is
:math:`y_i = z_i s_i^2 / (s_i^2 + \mu)` with :math:`\mu` the root in
:math:`(-s_{min}^2, 0]` of the secular equation

.. math::

    \sum_i \left(\frac{s_i z_i}{s_i^2 + \mu}\right)^2 = 1,

whose left side decreases monotonically there (Eberly, "Distance from a point to an
ellipse, an ellipsoid, or a hyperellipsoid", 2013).  The root is found by bisection in
:math:`t = s_{min}^2 + \mu \in [0, s_{min}^2]`, with the denominators written as
:math:`(s_i - s_{min})(s_i + s_{min}) + t` (no cancellation), and the distance is
evaluated through the constraint for the shortest axis, so the "hard case" (the origin on
the shortest axis' hyperplane, the root at :math:`t = 0`) needs no special branch.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.validation import as_floats

__all__ = ["BISECTION_STEPS", "ellipsoid_origin_radius"]

Array = NDArray[np.float64]

#: Bisection steps: the bracket [0, s_min^2] shrinks below one unit in the last place.
BISECTION_STEPS = 80


def _checked(center: object, axes: object, semi_axes: object) -> tuple[Array, Array, Array]:
    """The three arrays as floats of shapes (K, m), (K, m, m), (K, m), finite or NaN."""
    arrays = []
    for name, value, ndim, shape in (
        ("center", center, 2, "(K, m)"),
        ("axes", axes, 3, "(K, m, m)"),
        ("semi_axes", semi_axes, 2, "(K, m)"),
    ):
        array = as_floats(name, value)
        if array.ndim != ndim:
            raise InputError(
                name,
                f"an array of shape {shape}",
                f"shape {array.shape}",
                f"stack one row per ellipsoid, e.g. {name}[None] for a single ellipsoid",
            )
        if np.isinf(array).any():
            raise InputError(
                name,
                "finite values (NaN marks an unknown ellipsoid)",
                "inf",
                f"set the inf entries of {name} to NaN to mark those ellipsoids unknown",
            )
        arrays.append(array)
    c, U, s = arrays
    K, m = c.shape
    if U.shape != (K, m, m) or s.shape != (K, m):
        raise InputError(
            "axes" if U.shape != (K, m, m) else "semi_axes",
            f"axes of shape {(K, m, m)} and semi-axes of shape {(K, m)} for centres {c.shape}",
            f"axes {U.shape} and semi-axes {s.shape}",
            "give full-dimensional ellipsoids, one per centre.",
        )
    if (s <= 0).any():
        raise InputError(
            "semi_axes",
            "strictly positive lengths",
            f"{s[s <= 0][0]:.3g}",
            "pass full-dimensional ellipsoids only, or set the rows with a semi-axis <= 0 to NaN",
        )
    return c, U, s


def ellipsoid_origin_radius(center: Array, axes: Array, semi_axes: Array) -> Array:
    """Radius of the largest ball about the origin inside each ellipsoid.

    Parameters
    ----------
    center : ndarray, shape (K, m)
        Centres c [task units].
    axes : ndarray, shape (K, m, m)
        Orthonormal principal axes (columns); full-dimensional ellipsoids only.
    semi_axes : ndarray, shape (K, m)
        Strictly positive semi-axes [task units].

    Returns
    -------
    ndarray, shape (K,)
        The distance from the origin to each ellipsoid's boundary [task units]; 0 where
        the origin is outside (or on the boundary); NaN where an entry of the ellipsoid is
        NaN (an unknown one).

    Raises
    ------
    InputError
        For arrays of other shapes, infinite entries or semi-axes that are not positive.

    Examples
    --------
    >>> import numpy as np
    >>> r = ellipsoid_origin_radius(np.array([[1.0, 0.0]]), np.eye(2)[None], np.array([[3.0, 2.0]]))
    >>> round(float(r[0]), 9)  # 4/sqrt(5): the nearest boundary point is off the axes
    1.788854382
    """
    center, axes, semi_axes = _checked(center, axes, semi_axes)
    unknown = np.asarray(
        np.isnan(center).any(axis=-1) | np.isnan(axes).any(axis=(-2, -1)), dtype=bool
    )
    center = np.where(unknown[:, None], 0.0, center)
    axes = np.where(unknown[:, None, None], np.eye(axes.shape[-1]), axes)
    semi_axes = np.where(unknown[:, None], np.nan, semi_axes)
    z = -np.einsum("kmr,km->kr", axes, center)  # the origin in each ellipsoid's frame
    s = semi_axes
    inside = ((z / s) ** 2).sum(axis=-1) <= 1.0
    shortest = np.argmin(np.where(np.isnan(s), np.inf, s), axis=-1)
    s_min = np.take_along_axis(s, shortest[:, None], axis=-1)  # (K, 1)
    gap = (s - s_min) * (s + s_min)  # s_i^2 - s_min^2 >= 0, exact zero on the shortest axis
    others = np.ones(s.shape, dtype=bool)
    np.put_along_axis(others, shortest[:, None], False, axis=-1)
    weighted = z * s  # s_i z_i

    def secular(t: Array, mask: NDArray[np.bool_] | None = None) -> Array:
        with np.errstate(divide="ignore", invalid="ignore"):
            terms = np.where(weighted == 0, 0.0, (weighted / (gap + t)) ** 2)
        if mask is not None:
            terms = np.where(mask, terms, 0.0)
        result: Array = terms.sum(axis=-1, keepdims=True)
        return result

    low = np.zeros_like(s_min)
    high = s_min * s_min
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        above = secular(middle) > 1.0  # the root lies above middle (the sum decreases)
        low, high = np.where(above, middle, low), np.where(above, high, middle)
    t = high
    mu = t - s_min * s_min  # <= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        across = np.where(others & (z != 0), (z / (gap + t)) ** 2, 0.0).sum(axis=-1)
    rest = np.clip(1.0 - secular(t, others)[:, 0], 0.0, 1.0)  # (s_min y_min / s_min^2)^2
    mu, s_min = mu[:, 0], s_min[:, 0]
    distance = np.abs(mu) * np.sqrt(across + rest / (s_min * s_min))
    radius: Array = np.where(inside, distance, 0.0)
    return np.where(np.isnan(s).any(axis=-1), np.nan, radius)
