"""Plain-text reports of an analysis (what the command line prints)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from polyell.analysis import ELLIPSOID_KINDS, Analysis
from polyell.errors import UndefinedEllipsoidError

__all__ = ["format_analysis"]


def _matrix(a: NDArray[np.float64], indent: str = "    ") -> str:
    text = np.array2string(
        np.atleast_2d(a), max_line_width=100, formatter={"float_kind": lambda v: f"{v:11.5g}"}
    )
    return "\n".join(indent + line for line in text.splitlines())


def _interval(lo: float, hi: float) -> str:
    return "empty" if np.isnan(lo) else f"[{lo:.5g}, {hi:.5g}]"


def format_analysis(analysis: Analysis, direction: NDArray[np.float64], label: str) -> str:
    """Describe the polytope, both ellipsoids and the limits along one direction.

    Parameters
    ----------
    analysis : Analysis
    direction : ndarray, shape (m,)
        Unit direction for the directional limits.
    label : str
        Name of the direction (e.g. ``"x"``).

    Returns
    -------
    str
    """
    P = analysis.polytope
    lines = [
        f"rank M = {analysis.rank} of m = {analysis.dynamics.m}"
        + (" (singular configuration)" if analysis.is_singular else ""),
        "xdd_g (eq. 8) [m/s^2]:",
        _matrix(analysis.xg),
        "M (eq. 14):",
        _matrix(analysis.M),
        "",
        f"Polytope (eq. 15): dimension {P.dim}, {len(P.vertices)} vertices, "
        f"{len(P.A)} facets, volume {P.volume:.6g}",
        "  vertices [m/s^2]:",
        _matrix(P.vertices),
    ]
    if P.A_eq.size:
        lines += ["  equalities A_eq x = b_eq:", _matrix(np.hstack([P.A_eq, P.b_eq[:, None]]))]
    limits = {"polytope": P.limits(direction)}
    for kind in ELLIPSOID_KINDS:
        lines.append("")
        try:
            E = analysis.ellipsoid(kind)
        except UndefinedEllipsoidError as exn:
            lines += [f"Ellipsoid {kind!r}: undefined here.", f"  {exn}"]
            continue
        limits[kind] = E.limits(direction)
        lines += [
            f"Ellipsoid {kind!r}: rank {E.rank}, volume {E.volume:.6g}",
            "  core N:",
            _matrix(E.core),
            "  semi-axes [m/s^2]: " + ", ".join(f"{s:.5g}" for s in E.semi_axes),
            "  axes (columns):",
            _matrix(E.axes),
        ]
    lines += ["", f"Achievable accelerations along {label} = {np.round(direction, 6).tolist()}:"]
    lines += [
        f"  {name:<10} {_interval(float(lo), float(hi))}" for name, (lo, hi) in limits.items()
    ]
    return "\n".join(lines)
