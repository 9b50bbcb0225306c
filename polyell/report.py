"""Reports of one analysis: plain text (what the command line prints) and JSON."""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import ELLIPSOID_KINDS, Analysis, InverseSolution
from polyell.comparison import Comparison
from polyell.errors import UndefinedEllipsoidError

__all__ = ["analysis_to_json", "format_analysis"]


def _matrix(a: NDArray[np.float64], indent: str = "    ") -> str:
    """Five significant digits; entries below 1e-12 of the largest print as 0 (rounding)."""
    a = np.atleast_2d(a)
    scale = np.max(np.abs(a)) if a.size else 0.0
    shown = np.where(np.abs(a) <= 1e-12 * scale, 0.0, a)
    text = np.array2string(
        shown, max_line_width=100, formatter={"float_kind": lambda v: f"{v:11.5g}"}
    )
    return "\n".join(indent + line for line in text.splitlines())


def _interval(lo: float, hi: float) -> str:
    return "empty" if np.isnan(lo) else f"[{lo:.5g}, {hi:.5g}]"


def inverse_at_end(
    analysis: Analysis, direction: NDArray[np.float64], inverse_at: Literal["lo", "hi"]
) -> tuple[NDArray[np.float64] | None, dict[str, InverseSolution]]:
    """Both inverse maps at one end of the new ellipsoid's interval along ``direction``.

    Returns the acceleration (None where the interval is empty) and the solutions of the
    definitions defined here.  The direction is the one the limits used: projected onto
    the affine set when it was typed rounded (a singular configuration).
    """
    P = analysis.polytope
    end = float(getattr(analysis.ellipsoid("chiacchio").limits(direction), inverse_at))
    if math.isnan(end):
        return None, {}
    xdd = end * P.affine_set.meet_lines(direction[None], P.affine_rtol).projected[0]
    solutions: dict[str, InverseSolution] = {}
    for kind in ELLIPSOID_KINDS:
        try:
            solutions[kind] = analysis.inverse(xdd, kind=kind)
        except UndefinedEllipsoidError:
            continue
    return xdd, solutions


def format_analysis(
    analysis: Analysis,
    direction: NDArray[np.float64],
    label: str,
    inverse_at: Literal["lo", "hi"] = "hi",
) -> str:
    """Every quantity of the paper's section 6 at one configuration, as text.

    ``xdd_g``, ``M`` and its SVD (eq. 35), the polytope, both ellipsoids (core, semi-axes,
    axes), the limits along ``direction``, and both inverse maps (eq. 26 and 33/40) at the
    ``inverse_at`` end of the new ellipsoid's interval.

    Parameters
    ----------
    analysis : Analysis
    direction : ndarray, shape (m,)
        Unit direction for the directional limits.
    label : str
        Name of the direction (e.g. ``"x"``).
    inverse_at : {"lo", "hi"}
        Which end of the new ellipsoid's interval the inverse maps are applied to.

    Returns
    -------
    str
    """
    P, svd = analysis.polytope, analysis.svd
    unit = analysis.unit()
    lines = [
        f"task rows {', '.join(analysis.dynamics.task)} [{unit}]",
        f"rank M = {analysis.rank} of m = {analysis.dynamics.m}"
        + (" (singular configuration)" if analysis.is_singular else ""),
        f"xdd_g (eq. 8) [{unit}]:",
        _matrix(analysis.xg),
        "M (eq. 14):",
        _matrix(analysis.M),
        "SVD of M (eq. 35): singular values " + ", ".join(f"{s:.5g}" for s in svd.singular_values),
        "  U = [U1 U2]:",
        _matrix(np.hstack([svd.U1, svd.U2])),
        "  V1^T:",
        _matrix(svd.V1.T),
        "",
        f"Polytope (eq. 15): dimension {P.dim}, {len(P.vertices)} vertices, "
        f"{len(P.A)} facets, volume {P.volume:.6g}",
        f"  vertices [{unit}]:",
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
            f"  semi-axes [{unit}]: " + ", ".join(f"{s:.5g}" for s in E.semi_axes),
            "  axes (columns):",
            _matrix(E.axes),
        ]
    lines += ["", f"Achievable accelerations along {label} = {np.round(direction, 6).tolist()}:"]
    lines += [
        f"  {name:<10} {_interval(float(lo), float(hi))}" for name, (lo, hi) in limits.items()
    ]
    xdd, solutions = inverse_at_end(analysis, direction, inverse_at)
    if xdd is None:
        return "\n".join(lines)
    lines += ["", f"Inverse maps at xdd = {np.round(xdd, 5).tolist()} ({inverse_at} end, new):"]
    equations = {"chiacchio": "33/40", "yoshikawa": "26"}
    for name, solution in solutions.items():
        lines += [
            f"  {name} (eq. {equations[name]}): qdd = {np.round(solution.qdd, 5).tolist()}",
            f"    tau_n = {np.round(solution.tau_n, 5).tolist()}, "
            f"|tau_n| = {float(solution.torque_norm):.5g}, "
            f"max |tau_n_i| = {float(np.max(np.abs(solution.tau_n))):.5g}",
        ]
    return "\n".join(lines)


def _plain(value: Any) -> Any:
    """Numpy to JSON-ready Python, with NaN and infinity as None."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def analysis_to_json(
    analysis: Analysis,
    direction: NDArray[np.float64],
    comparison: Comparison | None = None,
    inverse_at: Literal["lo", "hi"] = "hi",
) -> dict[str, Any]:
    """Everything :func:`format_analysis` shows (and the scores, if given), JSON-ready."""
    P = analysis.polytope
    ellipsoids: dict[str, Any] = {}
    for kind in ELLIPSOID_KINDS:
        try:
            E = analysis.ellipsoid(kind)
        except UndefinedEllipsoidError as exn:
            ellipsoids[kind] = {"defined": False, "reason": str(exn)}
            continue
        lo, hi = E.limits(direction)
        ellipsoids[kind] = {
            "defined": True,
            "center": E.center,
            "core": E.core,
            "semi_axes": E.semi_axes,
            "axes": E.axes,
            "rank": E.rank,
            "volume": E.volume,
            "limits": [lo, hi],
        }
    lo, hi = P.limits(direction)
    result: dict[str, Any] = {
        "task": list(analysis.dynamics.task),
        "unit": analysis.unit(),
        "xg": analysis.xg,
        "M": analysis.M,
        "rank": analysis.rank,
        "singular_values": analysis.svd.singular_values,
        "direction": direction,
        "tau_max": analysis.tau_max,
        "tau_min": analysis.tau_min,
        "polytope": {
            "dim": P.dim,
            "volume": P.volume,
            "vertices": P.vertices,
            "A": P.A,
            "b": P.b,
            "A_eq": P.A_eq,
            "b_eq": P.b_eq,
            "limits": [lo, hi],
        },
        "ellipsoids": ellipsoids,
    }
    xdd, solutions = inverse_at_end(analysis, direction, inverse_at)
    result["inverse"] = {"at": inverse_at, "xdd": xdd} | {
        kind: {"qdd": solution.qdd, "tau_n": solution.tau_n} for kind, solution in solutions.items()
    }
    if comparison is not None:
        result["scores"] = {kind: r.as_dict() for kind, r in comparison.records.items()}
    return _plain(result)
