"""Closed-form directional limits: a line through the origin against a set of halfspaces."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "ATOL_RELATIVE",
    "PARALLEL_SLOPE",
    "DirectionalLimits",
    "facet_slack",
    "line_interval_in_ellipsoids",
    "line_interval_in_halfspaces",
    "parallel_slopes",
    "rounding_floor",
    "snap_to_zero",
    "unit_ball_interval",
]


#: Membership tolerance, relative to the set itself: a point of a polytope counts as inside
#: when it lies in the set grown by ``1 + ATOL_RELATIVE`` about its centre (each facet moved
#: out by that share of the set's own half-width along its normal, see :func:`facet_slack`).
#: Relative to the width
#: along every normal, not to the set's diameter: a thin set with a sharp tip is not
#: widened beyond itself (an absolute slack of ``1e-9 * size`` per facet would let the
#: half-spaces at a tip of angle 1e-8 overlap a tenth of the set's size beyond it).
ATOL_RELATIVE = 1e-9

#: A unit row and a unit direction whose product ``|a_i . t|`` is at most this are parallel
#: to rounding (64 eps: the rounding of a product of up to 60-odd terms): the line runs in
#: the row's plane, bounded there by the other rows.  Without it a line along a facet
#: through the origin (a force set whose torque limit equals the gravity torque, a velocity
#: set with ``qd_min = 0``) was cut at ``0 / 1e-17 = 0``, half its interval lost.
PARALLEL_SLOPE = 64.0 * float(np.finfo(float).eps)


def facet_slack(
    half_widths: NDArray[np.float64], reach: NDArray[np.float64] | float, terms: int
) -> NDArray[np.float64]:
    """How far beyond each facet ``a_i . (x - c) <= h_i`` a point still counts as inside.

    ``ATOL_RELATIVE * h_i + terms * eps * reach``: the first term grows the set by the
    factor ``1 + ATOL_RELATIVE`` about its centre ``c``; the second is the rounding floor
    of evaluating ``a_i . (x - c)`` and of the points themselves.  With ``reach`` at least
    ``|x| + |c| + sum_i |g_i|``, forming ``x - c`` and a dot product of m terms errs by at most
    about ``(m + 1) eps reach``, and a vertex summed from n generators by ``n eps reach``
    (first-order bounds ``gamma_k = k eps``, Higham, Accuracy and Stability, section 3.1), so
    ``terms = m + n + 2`` covers both.  Below that floor facets evaluated in double precision
    cannot decide membership (an extended-precision evaluation could; none is done): at a
    tip of angle theta it is ``terms * eps * reach / theta`` along the tip's axis, and
    relative to a thin set's width about ``terms * eps`` times its condition number.

    Parameters
    ----------
    half_widths : ndarray, shape (..., F)
        ``h_i``: the set's support about its centre along each unit normal.
    reach : float or ndarray, shape (...) or (..., 1)
        The size of the points and of the set, broadcast against ``half_widths``.
    terms : int
        ``m + n + 2`` for a zonotope of n generators in m dimensions.

    Returns
    -------
    ndarray, the shape of ``half_widths`` broadcast with ``reach``
    """
    return ATOL_RELATIVE * half_widths + rounding_floor(reach, terms)


def rounding_floor(reach: NDArray[np.float64] | float, terms: int) -> NDArray[np.float64]:
    """``terms * eps * reach``: the rounding of a facet's offset from the origin.

    The second term of :func:`facet_slack`.  An offset ``b_i`` (the facet's signed distance
    from the origin along its unit normal) below it in magnitude cannot be told from 0: the
    origin is on that facet, and every line through it leaving P across the facet has its
    far end at exactly 0 (:func:`snap_to_zero`), not at a rounding error of either sign.
    """
    return np.asarray(terms * np.finfo(float).eps * reach)


def snap_to_zero(
    offsets: NDArray[np.float64], floor: NDArray[np.float64] | float
) -> NDArray[np.float64]:
    """``offsets`` with the entries within ``floor`` (:func:`rounding_floor`) of 0 set to 0."""
    return np.where(np.abs(offsets) <= floor, 0.0, offsets)


def parallel_slopes(
    slack: NDArray[np.float64] | float, reach: NDArray[np.float64] | float | None
) -> NDArray[np.float64]:
    """Slopes ``|a_i . t|`` up to which a line runs along row i within its slack.

    ``slack_i / reach``: over the points that matter (``|a| <= reach``) the row's value
    along the line moves by at most its :func:`facet_slack`, the tolerance of membership,
    so the line lies in the row's plane as far as membership can tell: a line along a
    facet through the origin then keeps its whole interval in the facet, whatever the
    rounding of the facet's normal.  At least :data:`PARALLEL_SLOPE`; that alone without
    ``reach``.
    """
    if reach is None:
        return np.asarray(PARALLEL_SLOPE)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(slack) / np.asarray(reach)
    return np.maximum(PARALLEL_SLOPE, np.nan_to_num(ratio, nan=0.0, posinf=0.0))


def line_interval_in_halfspaces(
    A: NDArray[np.float64],
    b: NDArray[np.float64],
    directions: NDArray[np.float64],
    slack: NDArray[np.float64] | float,
    floor: NDArray[np.float64] | float = 0.0,
    slope_floor: float = PARALLEL_SLOPE,
    reach: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The interval ``{a : A (a t) <= b}`` for each direction ``t``.

    Each facet ``A_i x <= b_i`` cuts the line at ``a = b_i / (A_i . t)``: from above when
    ``A_i . t > 0``, from below when ``< 0``; when ``A_i . t = 0`` it keeps the whole
    line if ``b_i >= 0`` and empties it otherwise.

    Parameters
    ----------
    A : ndarray, shape (F, m)
        Facet normals.
    b : ndarray, shape (F,)
        Offsets.
    directions : ndarray, shape (k, m)
        Unit directions.
    slack : float or ndarray, shape (F,)
        How far beyond each facet a point still counts as inside (:func:`facet_slack`): a
        line that misses ``{A x <= b}`` (``lo > hi``, a line grazing a vertex or an edge,
        to rounding) but meets ``{A x <= b + slack}`` touches the set in the single point
        ``(lo + hi) / 2``.
    floor : float or ndarray, shape (F,)
        :func:`rounding_floor`: offsets ``b_i`` within it of 0 are taken as 0 (the origin on
        that facet), so that a line leaving P across it ends at exactly 0.
    slope_floor : float, optional
        Slopes ``|A_i . t|`` at or below it are taken as 0 (a line parallel to the facet
        to rounding; at least :data:`PARALLEL_SLOPE`): a line in the plane of a facet
        through the origin keeps its whole interval in that facet, not ``0 / 1e-17 = 0``
        at one end, and an unbounded set has infinite limits along its rays (a larger
        floor, its rank decision), not ``b_i / 1e-17``.
    reach : float, optional
        A bound on ``|a|`` over the points that matter (the set's distance from the origin
        plus its size): a row whose slope moves it by at most its ``slack`` over that
        reach (:func:`parallel_slopes`) is parallel too, as a point within the slack counts
        as inside (a facet normal known to the rounding of an ill-conditioned M).

    Returns
    -------
    lo, hi : ndarray, shape (k,)
        Interval ends, NaN where the line misses the set.
    """
    slopes = directions @ A.T  # (k, F)
    threshold = np.maximum(max(slope_floor, PARALLEL_SLOPE), parallel_slopes(slack, reach))
    slopes = np.where(np.abs(slopes) <= threshold, 0.0, slopes)
    loose = b + slack
    b = snap_to_zero(b, floor)
    lower, upper = _cut(b, slopes)
    blocked = ((slopes == 0) & (loose < 0)).any(axis=1)
    grazing = lower > upper
    if grazing.any():  # does the line meet the set grown by the slack?
        lower_loose, upper_loose = _cut(np.broadcast_to(loose, b.shape), slopes[grazing])
        grazing[grazing] = lower_loose <= upper_loose
    with np.errstate(invalid="ignore"):  # -inf + inf on unbounded lines, never grazing
        middle = 0.5 * (lower + upper)
    lower = np.where(grazing, middle, lower)
    upper = np.where(grazing, middle, upper)
    empty = blocked | (lower > upper)
    return np.where(empty, np.nan, lower), np.where(empty, np.nan, upper)


def _cut(
    b: NDArray[np.float64], slopes: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Largest lower and smallest upper cut ``b_i / slope_i`` of each line (rows of slopes)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        cuts = b / slopes
    upper = np.where(slopes > 0, cuts, np.inf).min(axis=1, initial=np.inf)
    lower = np.where(slopes < 0, cuts, -np.inf).max(axis=1, initial=-np.inf)
    return lower, upper


def line_interval_in_ellipsoids(
    center: NDArray[np.float64],
    axes: NDArray[np.float64],
    semi_axes: NDArray[np.float64],
    directions: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""Eq. (23)-(24) from the factors: the interval ``{a : a t in E}`` for lines in E's span.

    With :math:`E = \{c + U \operatorname{diag}(s) u : \|u\| \le 1\}`, ``a t`` is in E
    when :math:`\|a p - w\| \le 1` with :math:`p = \operatorname{diag}(s)^{-1} U^T t` and
    :math:`w = \operatorname{diag}(s)^{-1} U^T c`, so

    .. math::

        a = \frac{\hat p \cdot w \pm \sqrt{1 - \|w_\perp\|^2}}{\|p\|},
        \qquad w_\perp = w - (\hat p \cdot w) \hat p .

    This is eq. (24) with :math:`\alpha = \|p\|^2 = t^T N t`, :math:`\beta = -p \cdot w`,
    :math:`\gamma = \|w\|^2 - 1`, evaluated without the core
    :math:`N = U \operatorname{diag}(s)^{-2} U^T`, whose condition number is the square of
    the ellipsoid's: near a singular configuration (``s_min / s_max`` of 1e-8) eq. (24)
    through N loses every digit, this form only those the data do not have.

    Parameters
    ----------
    center : ndarray, shape (K, m)
        Centres ``c`` of K ellipsoids.
    axes : ndarray, shape (K, m, r)
        Orthonormal axes ``U``.
    semi_axes : ndarray, shape (K, r)
        Strictly positive semi-axes ``s``.
    directions : ndarray, shape (k, m)
        Unit directions ``t`` whose lines lie in the ellipsoids' affine sets.

    Returns
    -------
    lo, hi : ndarray, shape (K, k)
        Interval ends, NaN where the line misses the ellipsoid.
    """
    # Laid out (K, r, k): the sums run over the short axis r, on contiguous rows of k.
    p = np.matmul(np.swapaxes(axes, 1, 2), directions.T) / semi_axes[:, :, None]
    w = np.matmul(center[:, None, :], axes)[:, 0, :, None] / semi_axes[:, :, None]
    return unit_ball_interval(p, w)


def unit_ball_interval(
    p: NDArray[np.float64], w: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``{a : |a p - w| <= 1}``: eq. (24) in the frame where the ellipsoid is the unit ball.

    The vector components run along axis 1 of ``p`` and ``w`` (``w`` broadcasts against
    ``p``); the roots are taken as ``(p̂ . w ± sqrt(1 - |w_⊥|²)) / |p|``, without cancellation.

    Returns
    -------
    lo, hi : ndarray
        The shape of ``p`` without axis 1; NaN where the line misses the ball.
    """
    length = np.sqrt((p * p).sum(axis=1))
    p_hat = p / np.expand_dims(length, 1)
    along = (p_hat * w).sum(axis=1)
    across = w - np.expand_dims(along, 1) * p_hat
    discriminant = 1.0 - (across * across).sum(axis=1)
    root = np.sqrt(np.where(discriminant >= 0, discriminant, np.nan))
    return (along - root) / length, (along + root) / length


class DirectionalLimits(NamedTuple):
    """Achievable accelerations ``a`` along directions ``t``: the intervals ``[lo, hi]``.

    Unpacks as ``lo, hi = limits``.  Both ends are NaN where the line ``{a t}`` meets no
    achievable acceleration; an interval need not contain 0 (gravity can push it away).

    Attributes
    ----------
    lo, hi : ndarray, shape (k,) or ()
        Interval ends [m/s^2 for a linear task, rad/s^2 for an angular one].
    """

    lo: NDArray[np.float64]
    hi: NDArray[np.float64]

    @property
    def feasible(self) -> NDArray[np.bool_]:
        """True where the interval is non-empty."""
        return ~np.isnan(self.lo)
