"""Reports of one analysis: plain text (what the command line prints) and JSON."""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import Analysis, InverseSolution
from polyell.comparison import Comparison
from polyell.comparison.labels import Labels, check_labels, set_label
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.hpolytope import HPolytope

__all__ = ["analysis_to_json", "format_analysis"]


def _matrix(a: NDArray[np.float64], indent: str = "    ") -> str:
    """Five significant digits; entries below 1e-12 of the largest finite one print as 0."""
    a = np.atleast_2d(a)
    finite = np.abs(a[np.isfinite(a)])  # an inf end (an empty interval) scales nothing
    scale = float(finite.max()) if finite.size else 0.0
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

    Returns the point (None where the interval is empty) and the solutions of the
    definitions defined here (the capacity's first kind is its "new" one).  The direction
    is the one the limits used: projected onto the affine set when it was typed rounded (a
    singular configuration).
    """
    P = analysis.polytope
    try:
        first = analysis.ellipsoid(analysis.ellipsoid_kinds[0])
    except UndefinedEllipsoidError:
        return None, {}
    end = float(getattr(first.limits(direction), inverse_at))
    if math.isnan(end):
        return None, {}
    xdd = end * P.affine_set._meet_lines(direction[None], P.affine_rtol).projected[0]
    solutions: dict[str, InverseSolution] = {}
    for kind in analysis.ellipsoid_kinds:
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
    *,
    equations: bool | None = None,
    labels: Labels = None,
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
    equations : bool, optional
        Whether the labels carry the paper's names and equation numbers (``xdd_g (eq. 8)``,
        ``Polytope (eq. 15)``): for the paper's own study (a table layout's
        ``labels="chiacchio2000"``).  False: the names that fit any robot.  None (the
        default): the capacity's (``analysis.paper``: accelerations), as before.
    labels : str or mapping, optional
        How the sets are named, as a table layout's ``labels``
        (:class:`polyell.TableLayout`): a preset's name (``"chiacchio2000"``) or a mapping
        of set names to labels -- an empty one for the default labels that every table
        and figure uses (``"Chiacchio"``, ``"Yoshikawa"``).  A study passes its own, so
        that its numbers name each set as its tables and figures do.  None (the default):
        the kinds' names of the API (``'chiacchio'``, as ``analysis.ellipsoid`` takes
        them).

    Returns
    -------
    str

    Raises
    ------
    InputError
        If ``equations`` is not a bool or None, or ``labels`` is not a preset's name or a
        mapping of labels (naming ``labels``).
    """
    P, svd = analysis.polytope, analysis.svd  # type: ignore[attr-defined]
    unit = analysis.unit()
    if equations is not None and not isinstance(equations, bool):
        raise InputError(
            "equations",
            "True, False or None",
            repr(equations)[:60],
            "pass equations=True or equations=False, or leave it None to follow the analysis",
        )
    labels = check_labels(labels)

    def called(kind: str) -> str:
        """A set's name: the API's kind (``labels`` None), else its label."""
        return kind if labels is None else set_label(kind, analysis.capacity, labels)

    # the paper's names and equation numbers (an acceleration analysis has the matrices)
    paper = analysis.paper and (equations is None or equations)
    lines = [
        f"{analysis.capacity} capacity: task rows {', '.join(analysis.task)} [{unit}]"
        if not paper
        else f"task rows {', '.join(analysis.task)} [{unit}]",
        f"rank {analysis.rank_matrix} = {analysis.rank} of m = {analysis.m}"
        + (" (singular configuration)" if analysis.is_singular else ""),
    ]
    if paper:
        matrices = analysis.matrices()
        lines += [f"xdd_g (eq. 8) [{unit}]:", _matrix(matrices["xg"]), "M (eq. 14):"]
        lines += [_matrix(matrices["M"]), "SVD of M (eq. 35): singular values "]
    else:
        for name, value in analysis.matrices().items():
            lines += [f"{name}:", _matrix(value)]
        for name, value in analysis.joint_limits().items():
            lines.append(f"{name}: " + ", ".join(f"{v:.5g}" for v in value))
        lines.append("SVD: singular values ")
    lines[-1] += ", ".join(f"{s:.5g}" for s in svd.singular_values)
    if labels is not None:
        exact = called("polytope")
        exact = exact[:1].upper() + exact[1:]
    else:
        exact = "Polytope (eq. 15)" if paper else "Exact set"
    lines += [
        "  U = [U1 U2]:",
        _matrix(np.hstack([svd.U1, svd.U2])),
        "  V1^T:",
        _matrix(svd.V1.T),
        "",
        f"{exact}: {'empty' if P.dim < 0 else f'dimension {P.dim}'}, "
        f"{len(P.vertices)} vertices, {len(P.A)} facets, volume {P.volume:.6g}",
        f"  vertices [{unit}]:",
        _matrix(P.vertices),
    ]
    if isinstance(P, HPolytope) and P.is_empty:
        why = getattr(analysis, "empty_reason", None)
        lines.append(
            f"  empty: {why or 'the arm cannot hold itself against gravity within its limits'}"
        )
    if isinstance(P, HPolytope) and not P.is_bounded:
        lines += ["  unbounded along the rays:", _matrix(P.rays)]
    if P.A_eq.size:
        lines += ["  equalities A_eq x = b_eq:", _matrix(np.hstack([P.A_eq, P.b_eq[:, None]]))]
    limits = {"polytope": P.limits(direction)}

    def heading(kind: str) -> str:
        return repr(kind) if labels is None else called(kind)

    for kind in analysis.ellipsoid_kinds:
        lines.append("")
        try:
            E = analysis.ellipsoid(kind)
        except UndefinedEllipsoidError as exn:
            lines += [f"Ellipsoid {heading(kind)}: undefined here.", f"  {exn}"]
            continue
        limits[kind] = E.limits(direction)
        lines += [
            f"Ellipsoid {heading(kind)}: rank {E.rank}, volume {E.volume:.6g}",
            "  core N:",
            _matrix(E.core),
            f"  semi-axes [{unit}]: " + ", ".join(f"{s:.5g}" for s in E.semi_axes),
            "  axes (columns):",
            _matrix(E.axes),
        ]
    lines += [
        "",
        f"Achievable {analysis.quantity} along {label} = {np.round(direction, 6).tolist()}:",
    ]
    width = max(10, *(len(called(kind)) for kind in limits))
    lines += [
        f"  {called(kind):<{width}} {_interval(float(lo), float(hi))}"
        for kind, (lo, hi) in limits.items()
    ]
    xdd, solutions = inverse_at_end(analysis, direction, inverse_at)
    if xdd is None:
        return "\n".join(lines)
    first = "new" if paper and labels is None else called(analysis.ellipsoid_kinds[0])
    lines += [
        "",
        f"Inverse maps at {analysis.point_symbol} = {np.round(xdd, 5).tolist()} "
        f"({inverse_at} end, {first}):",
    ]
    # the inverse maps' equations (a label of the paper's preset holds the set's own)
    numbers = {"chiacchio": "eq. 33/40", "yoshikawa": "eq. 26"} if paper else {}
    numbers = {
        kind: f" ({number})" if labels is None else f", {number}"
        for kind, number in numbers.items()
    }
    joint, normalized = analysis.inverse_names
    if analysis.unique_inverse:  # a force needs one torque, whatever the definition
        solutions = dict(list(solutions.items())[:1])
    for kind, solution in solutions.items():
        lines += [
            f"  {called(kind)}{numbers.get(kind, '')}: {joint} = "
            f"{np.round(solution.joint, 5).tolist()}",
            f"    {normalized} = {np.round(solution.normalized, 5).tolist()}, "
            f"|{normalized}| = {float(solution.torque_norm):.5g}, "
            f"max |{normalized}_i| = {float(np.max(np.abs(solution.normalized))):.5g}",
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
    for kind in analysis.ellipsoid_kinds:
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
        "capacity": analysis.capacity,
        "task": list(analysis.task),
        "unit": analysis.unit(),
        **analysis.matrices(),
        "rank": analysis.rank,
        "singular_values": analysis.svd.singular_values,  # type: ignore[attr-defined]
        "direction": direction,
        **analysis.joint_limits(),
        "polytope": {
            "dim": P.dim,
            "volume": P.volume,
            "vertices": P.vertices,
            "A": P.A,
            "b": P.b,
            "A_eq": P.A_eq,
            "b_eq": P.b_eq,
            "rays": getattr(P, "rays", np.zeros((0, analysis.m))),
            "empty": bool(getattr(P, "is_empty", False)),
            "limits": [lo, hi],
        },
        "ellipsoids": ellipsoids,
    }
    xdd, solutions = inverse_at_end(analysis, direction, inverse_at)
    joint, normalized = analysis.inverse_names
    result["inverse"] = {"at": inverse_at, analysis.point_symbol: xdd} | {
        kind: {joint: solution.joint, normalized: solution.normalized}
        for kind, solution in solutions.items()
    }
    if comparison is not None:
        result["scores"] = {kind: r.as_dict() for kind, r in comparison.records.items()}
    return _plain(result)
