"""Figures with matplotlib: sets, directional limits, and score maps, readable in greyscale.

The style follows Figures 1 and 2 of the paper: the polytope dashed, Chiacchio's ellipsoid
solid, Yoshikawa's dotted; the centre ``xdd_g`` and the origin are marked.  Every
function draws on a :class:`matplotlib.figure.Figure` built without pyplot, so it works on
machines without a display.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from numpy.typing import NDArray
from scipy.spatial import ConvexHull

from polyell.capacities import CAPACITIES, Analysis, capacity_class, check_capacity
from polyell.comparison.labels import Labels, ellipsoid_label, resolve_labels
from polyell.comparison.tables import score_display
from polyell.errors import InputError, UndefinedEllipsoidError
from polyell.geometry.directions import sphere_directions
from polyell.geometry.ellipsoid import Ellipsoid
from polyell.geometry.hpolytope import require_drawable
from polyell.models.task import row_label
from polyell.storage import write_atomically
from polyell.validation import as_floats, check_array, check_instance, check_integer

__all__ = [
    "STYLES",
    "check_title",
    "ellipsoid_outline",
    "plot_directional_limits",
    "plot_posture_indices",
    "plot_score_histogram",
    "plot_score_map",
    "plot_score_series",
    "plot_sets",
    "plot_sets_3d",
    "plot_tangent_limits",
    "save_figure",
]

#: How to mend a wrong first argument (the messages of check_instance).
_FIX_ANALYSIS = "pass an analysis (pe.analyze(...)); of a comparison, its .analysis."
_FIX_RESULTS = "pass the results frame of pe.sweep or of a study (pd.read_csv(results.csv))."
_FIX_FIGURE = "pass a matplotlib Figure (the plot_* functions return one)."
_FIX_ELLIPSOID = "pass an ellipsoid: analysis.ellipsoid('chiacchio'), comparison.mvie, ..."

#: Line styles per set: distinct in greyscale (dash pattern, width and grey level).
STYLES = {
    "polytope": {"color": "0.35", "linestyle": "--", "linewidth": 2.2},
    "chiacchio": {"color": "black", "linestyle": "-", "linewidth": 1.4},
    "yoshikawa": {"color": "black", "linestyle": ":", "linewidth": 1.6},
    "mvie": {"color": "0.55", "linestyle": "-.", "linewidth": 1.2},
    "outer": {"color": "0.3", "linestyle": (0, (7, 2)), "linewidth": 1.0},
    "static": {"color": "0.5", "linestyle": (0, (4, 1.5, 1, 1.5)), "linewidth": 1.6},
}
#: Largest resolution of a saved figure: a 6-inch figure at 2400 dpi is 14400 pixels wide
#: (about 0.6 GB of RGBA pixels for a square one), beyond any journal's requirement.
MAX_DPI = 2400
#: Smallest resolution of a saved figure (a study's too): below it FreeType cannot render
#: the figures' smallest text (legends, subscripts) in a raster format.
MIN_DPI = 10
#: Most bins of a histogram (a figure 5 inches wide shows far fewer).
MAX_BINS = 10_000
#: Styles of user-defined candidates, in the order they are drawn.
CANDIDATE_STYLES = (
    {"color": "0.15", "linestyle": (0, (1, 1)), "linewidth": 1.8},
    {"color": "0.45", "linestyle": (0, (5, 1, 1, 1, 1, 1)), "linewidth": 1.2},
    {"color": "0.65", "linestyle": "-", "linewidth": 2.4},
    {"color": "0.25", "linestyle": (0, (3, 3)), "linewidth": 1.4},
)


def check_title(title: object, argument: str = "title") -> str:
    r"""Check text that a figure draws (a title, an axis label, a set's name).

    matplotlib reads text between pairs of ``$`` as mathtext (a subset of TeX); text
    whose mathtext does not parse would fail only when the figure is drawn, deep inside
    matplotlib.  Call this before any work (a study checks its title when it is loaded).

    Parameters
    ----------
    title : str
        The text.
    argument : str, optional
        Its name in the error message.

    Returns
    -------
    str
        ``title``, unchanged.

    Raises
    ------
    InputError
        If ``title`` is not a string, or its mathtext does not parse; the fix is to write
        a literal dollar sign as ``\$`` (or to correct the formula).
    """
    if not isinstance(title, str):
        raise InputError(
            argument,
            "a string",
            type(title).__name__,
            "pass the text as a str, e.g. 'Chiacchio arm' (str(value) converts a number)",
        )
    from matplotlib import cbook
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import MathTextParser

    if cbook.is_math_text(title):
        try:
            MathTextParser("path").parse(title, 72, FontProperties())
        except ValueError as exn:
            detail = " ".join(str(exn).split())
            raise InputError(
                argument,
                "text whose $...$ parts are valid matplotlib mathtext",
                f"{title!r} ({detail[:120]})",
                r"write a literal dollar sign as \$ (e.g. 'cost \$5'), or correct the formula "
                "between the dollar signs.",
            ) from None
    return title


def _check_texts(**texts: object) -> None:
    """:func:`check_title` for every text given that is not None."""
    for argument, text in texts.items():
        if text is not None:
            check_title(text, argument)


def _check_kinds(kinds: object) -> list[str]:
    """Names of the sets to draw: a sequence of str (one str's letters are no names)."""
    if isinstance(kinds, Iterable) and not isinstance(kinds, str | bytes):
        names = list(kinds)
        if all(isinstance(name, str) for name in names):
            return names
    raise InputError(
        "kinds",
        "a sequence of set names such as ('chiacchio', 'yoshikawa')",
        f"{type(kinds).__name__} {kinds!r:.80}",
        "pass a list or tuple of names, e.g. kinds=['chiacchio'].",
    )


def _check_ellipsoid(argument: str, E: Ellipsoid, m: int) -> None:
    """Refuse what is not an ellipsoid of the m-D task space (``mvie=``, ``extra=``)."""
    check_instance(argument, E, Ellipsoid, _FIX_ELLIPSOID)
    if E.center.size != m:
        raise InputError(
            argument,
            f"an ellipsoid of the {m}-D task space",
            f"one of {E.center.size}-D",
            "pass an ellipsoid of the same analysis, e.g. analysis.ellipsoid('chiacchio') "
            "or pe.compare(analysis).mvie",
        )


def _check_pair(
    argument: str, value: object, expected: str, *, finite: bool = True
) -> tuple[float, float]:
    """Two real numbers (a tuple, list or array of two; finite if ``finite``), as floats."""
    items = value.tolist() if isinstance(value, np.ndarray) else value
    if (
        isinstance(items, tuple | list)
        and len(items) == 2
        and all(
            isinstance(v, int | float | np.integer | np.floating) and not isinstance(v, bool)
            for v in items
        )
        and (not finite or bool(np.all(np.isfinite(items))))
    ):
        return float(items[0]), float(items[1])
    example = "(30.0, -60.0)" if argument == "view" else "(0.0, 1.0)"
    raise InputError(
        argument,
        expected,
        f"{type(value).__name__} {value!r:.80}",
        f"pass two real numbers as a tuple, e.g. {argument}={example}",
    )


def _check_view(view: object) -> tuple[float, float]:
    """The ``(elevation, azimuth)`` of a 3-D view, as floats."""
    return _check_pair("view", view, "(elevation, azimuth) in degrees, two finite numbers")


def _style(
    kind: str, kinds: Sequence[str] = (), capacity: str = "acceleration", labels: Labels = None
) -> dict[str, object]:
    """The line style of a set; a candidate's by its place among the others in ``kinds``.

    Its legend is the set's label (:func:`~polyell.comparison.labels.set_label`: one name
    per kind, or ``labels``), as in the tables.
    """
    if kind in STYLES:
        style = dict(STYLES[kind])
    else:
        others = [k for k in kinds if k not in STYLES]
        index = others.index(kind) if kind in others else 0
        style = dict(CANDIDATE_STYLES[index % len(CANDIDATE_STYLES)])
    style["label"] = ellipsoid_label(kind, capacity, labels)
    return style


def _check_labels(labels: object) -> Labels:
    """The labels of sets and scores a figure draws (a layout's), checked as drawn text."""
    for name, text in resolve_labels(labels).items():  # type: ignore[arg-type]
        check_title(text.plain, f"labels[{name!r}]")
    return labels  # type: ignore[return-value]


def _check_analysis(
    analysis: Analysis, m: int, fix: str, labels: object, **texts: object
) -> Labels:
    """Refuse what is not an analysis of an m-D task space (``fix``), check texts and labels."""
    check_instance("analysis", analysis, Analysis, _FIX_ANALYSIS)
    if analysis.m != m:
        raise InputError("analysis", f"a {m}-D task space", f"m = {analysis.m}", fix)
    _check_texts(**texts)
    return _check_labels(labels)


def _check_results(
    results: object, capacity: object, labels: object, **texts: object
) -> tuple[str, Labels]:
    """Refuse what is not a results frame, check texts; the checked capacity and labels."""
    check_instance("results", results, pd.DataFrame, _FIX_RESULTS)
    capacity = check_capacity(capacity)
    _check_texts(**texts)
    return capacity, _check_labels(labels)


def _mark_centre(ax: Axes, analysis: Analysis) -> list[Line2D]:
    """Mark the centre (its legend the paper's symbol for accelerations) and the origin."""
    (centre,) = ax.plot(
        *analysis.center,
        marker="+",
        color="black",
        markersize=9,
        linestyle="none",
        label=analysis.centre_label_tex,
    )
    (origin,) = ax.plot(
        *np.zeros(analysis.m),
        marker="o",
        color="black",
        markerfacecolor="white",
        linestyle="none",
        label="origin",
    )
    return [centre, origin]


def _ellipsoids(
    analysis: Analysis,
    kinds: Sequence[str] | None,
    mvie: Ellipsoid | None,
    extra: Mapping[str, Ellipsoid] | None,
) -> dict[str, Ellipsoid]:
    """The ellipsoids to draw: ``kinds`` (default the capacity's own), then ``extra``."""
    require_drawable(analysis.polytope, "analysis")
    if mvie is not None:  # checked even when kinds leave it out: never silently ignored
        _check_ellipsoid("mvie", mvie, analysis.m)
    if extra is not None and not isinstance(extra, Mapping):
        got = f"{type(extra).__name__} {extra!r:.80}"
        fix = "e.g. extra={'outer': comparison.outer}."
        raise InputError("extra", "a mapping of set names to ellipsoids", got, fix)
    for name, E in (extra or {}).items():
        check_title(name, "extra")  # drawn as a legend entry
        _check_ellipsoid(f"extra[{name!r}]", E, analysis.m)
    found: dict[str, Ellipsoid] = {}
    for kind in analysis.ellipsoid_kinds if kinds is None else _check_kinds(kinds):
        if kind == "mvie":
            if mvie is None:
                raise InputError(
                    "kinds",
                    "an 'mvie' ellipsoid passed as mvie=",
                    "None",
                    "pass mvie=comparison.mvie (comparison = pe.compare(analysis)), or drop "
                    "'mvie' from kinds",
                )
            found[kind] = mvie
            continue
        try:
            found[kind] = analysis.ellipsoid(kind)
        except UndefinedEllipsoidError:
            continue  # undefined here (singular configuration): nothing to draw
    return found | dict(extra or {})


def _label_axes(ax: Axes, analysis: Analysis, unit: str | None) -> None:
    """Label each axis with its task row (x, z, wx, ...) and the task's unit."""
    unit = unit or analysis.unit(tex=True)
    setters = (ax.set_xlabel, ax.set_ylabel, getattr(ax, "set_zlabel", None))
    for setter, row in zip(setters, analysis.task, strict=False):
        assert setter is not None
        setter(f"{row_label(row, analysis.capacity)} [{unit}]")


def plot_sets(
    analysis: Analysis,
    ax: Axes | None = None,
    *,
    kinds: Sequence[str] | None = None,
    mvie: Ellipsoid | None = None,
    extra: Mapping[str, Ellipsoid] | None = None,
    unit: str | None = None,
    title: str | None = None,
    labels: Labels = None,
) -> Figure:
    """The polytope and the ellipsoids of a 2-D task space (paper Figures 1 and 2).

    Degenerate sets (a singular configuration) are drawn as the segments they are.

    Parameters
    ----------
    analysis : Analysis
        With a 2-D task space.
    ax : Axes, optional
        Where to draw; a new figure otherwise.
    kinds : sequence of str, optional
        Ellipsoids to draw, among the capacity's kinds (``analysis.ellipsoid_kinds``, the
        default) and ``"mvie"``; an undefined one is skipped.
    mvie : Ellipsoid, optional
        The maximum-volume inscribed ellipsoid, when ``"mvie"`` is in ``kinds``.
    extra : mapping of str to Ellipsoid, optional
        More sets by name: the outer ellipsoid (``Comparison.outer``) or candidates
        (``Comparison.ellipsoid(name)``).
    unit : str, optional
        Axis unit; default the task's (m/s^2 for linear rows, rad/s^2 for angular ones).
    title : str, optional
    labels : str or mapping, optional
        The sets' names in the legend, as a table layout's ``labels``
        (:class:`polyell.TableLayout`): a mapping of set names to labels (their plain
        text), or a preset (``"chiacchio2000"``, the paper's equation numbers).  Default:
        one name per set (``"polytope"``, ``"Chiacchio"``, ``"Yoshikawa"``, ``"MVIE"``).

    Returns
    -------
    Figure
    """
    labels = _check_analysis(analysis, 2, "use plot_sets_3d.", labels, unit=unit, title=title)
    drawn = _ellipsoids(analysis, kinds, mvie, extra)  # checked before drawing on ax
    if ax is None:
        ax = Figure(figsize=(4.8, 5.2), layout="constrained").add_subplot()
    check_instance("ax", ax, Axes, "pass a matplotlib Axes (figure.add_subplot()), or no ax.")
    if ax.name != "rectilinear":  # polar or 3-D axes cannot hold an equal-aspect 2-D drawing
        raise InputError(
            "ax",
            "a 2-D (rectilinear) matplotlib Axes",
            f"an Axes of projection {ax.name!r}",
            "pass figure.add_subplot() without a projection, or no ax (plot_sets_3d draws "
            "3-D sets).",
        )
    P = analysis.polytope
    vertices = P.vertices if P.dim < 2 else np.vstack([P.vertices, P.vertices[:1]])
    # Segments (a singular configuration) share one line: layered solid strokes of
    # decreasing width, each with its own end marks, so every set stays readable and the
    # legend shows each stroke as drawn.
    segment: dict[str, object] = {}
    if P.dim < 2:
        segment = {"color": "0.8", "linewidth": 9.0, "linestyle": "-"}
        segment |= {"solid_capstyle": "butt", "marker": "s", "markersize": 9}
    polytope = _style("polytope", (), analysis.capacity, labels)
    ax.plot(*vertices.T, **(polytope | segment))  # type: ignore[arg-type]
    widths = {"chiacchio": 3.2, "yoshikawa": 2.0, "mvie": 1.3}
    for kind, E in drawn.items():
        ends: dict[str, object] = {}
        if E.rank < 2:
            ends = {"marker": "|", "markersize": 16, "markeredgewidth": 1.6}
            ends |= {"linewidth": widths.get(kind, 1.3), "solid_capstyle": "butt"}
        style = _style(kind, list(drawn), analysis.capacity, labels)
        ax.plot(*E.boundary_curve(720, closed=True).T, **(style | ends))  # type: ignore[arg-type]
    _mark_centre(ax, analysis)
    ax.set_aspect("equal", adjustable="datalim")
    _label_axes(ax, analysis, unit)
    ax.grid(True, color="0.9", linewidth=0.6)
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    if title:
        ax.set_title(title)
    figure = ax.get_figure()
    assert isinstance(figure, Figure)
    return figure


def _view_direction(view: tuple[float, float]) -> NDArray[np.float64]:
    """The unit vector from the scene towards the viewer, for ``(elevation, azimuth)``."""
    elevation, azimuth = np.radians(view)
    return np.array(
        [
            np.cos(elevation) * np.cos(azimuth),
            np.cos(elevation) * np.sin(azimuth),
            np.sin(elevation),
        ]
    )


def _ellipse(E: Ellipsoid, plane: NDArray[np.float64], count: int = 181) -> NDArray[np.float64]:
    """The ellipse ``{c + U S u : |u| = 1, u in span(plane)}`` of ``E``, (count, 3), closed.

    ``plane`` holds two orthonormal columns in the ellipsoid's own coordinates ``u``.
    """
    angles = np.linspace(0.0, 2.0 * np.pi, count)
    circle = np.outer(np.cos(angles), plane[:, 0]) + np.outer(np.sin(angles), plane[:, 1])
    return E.center + (circle * E.semi_axes) @ E.axes.T


def ellipsoid_outline(
    E: Ellipsoid, view: tuple[float, float] = (25.0, -60.0)
) -> tuple[NDArray[np.float64], list[NDArray[np.float64]]]:
    """Curves that draw a 3-D ellipsoid legibly: its outline seen from ``view``, its sections.

    Parameters
    ----------
    E : Ellipsoid
        Of a 3-D task space.
    view : (float, float)
        ``(elevation, azimuth)`` in degrees, as :func:`plot_sets_3d`.

    Returns
    -------
    outline : ndarray, shape (k, 3)
        For a full-rank ellipsoid, its silhouette in an orthographic view along ``view``
        (the points whose normal is perpendicular to the line of sight: the contour an
        eye sees); a flat one's boundary ellipse; a segment's two ends.
    sections : list of ndarray, shape (k, 3)
        The principal sections of a full-rank ellipsoid (the ellipses through two of its
        axes), none otherwise.
    """
    check_instance("E", E, Ellipsoid, "pass an ellipsoid, e.g. analysis.ellipsoid('chiacchio').")
    view = _check_view(view)
    if E.rank < 3:
        curve = E.boundary_curve(180, closed=True) if E.rank > 0 else E.center[None]
        return curve, []
    # silhouette: points y = U S u with y^T N d = 0, i.e. u orthogonal to S^-1 U^T d
    normal = (E.axes.T @ _view_direction(view)) / E.semi_axes
    plane = np.linalg.svd(normal[None, :])[2][1:].T  # an orthonormal basis of normal's plane
    sections = [_ellipse(E, np.eye(3)[:, [i, j]]) for i, j in ((0, 1), (0, 2), (1, 2))]
    return _ellipse(E, plane), sections


def plot_sets_3d(
    analysis: Analysis,
    *,
    kinds: Sequence[str] | None = None,
    mvie: Ellipsoid | None = None,
    extra: Mapping[str, Ellipsoid] | None = None,
    unit: str | None = None,
    title: str | None = None,
    view: tuple[float, float] = (25.0, -60.0),
    labels: Labels = None,
) -> Figure:
    """The polytope and the ellipsoids of a 3-D task space, legible in print.

    The polytope is drawn with translucent faces and its edges; each ellipsoid by its
    outline as seen from ``view`` (in its line style, :data:`STYLES`) and, thinner and
    lighter, its three principal sections, so that four ellipsoids stay apart.  The view is
    orthographic; the legend, below the axes, names every set (the polytope included).
    Every label stays inside the figure.

    Arguments as for :func:`plot_sets`; the view is ``(elevation, azimuth)`` in degrees.
    """
    from matplotlib.patches import Patch
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    from polyell.export import polytope_edges

    labels = _check_analysis(analysis, 3, "use plot_sets.", labels, unit=unit, title=title)
    view = _check_view(view)
    figure = Figure(figsize=(5.5, 5.0), layout="constrained")
    ax = figure.add_subplot(projection="3d", proj_type="ortho")
    P = analysis.polytope
    polytope_style = _style("polytope", (), analysis.capacity, labels)
    edge_color = "0.25"
    handles: list[object] = []
    if P.dim == 3:
        hull = ConvexHull(P.vertices)
        faces = Poly3DCollection(
            P.vertices[hull.simplices], facecolor="0.82", alpha=0.3, linewidth=0.0
        )
        ax.add_collection3d(faces)
    edges = polytope_edges(P)
    if len(edges):
        ax.add_collection3d(Line3DCollection(P.vertices[edges], colors=edge_color, linewidths=0.8))
    else:
        ax.plot(*P.vertices.T, "s", color=edge_color)
    handles.append(
        Patch(
            facecolor=(0.82, 0.82, 0.82, 0.6) if P.dim == 3 else "none",
            edgecolor=edge_color,
            linewidth=0.8,
            label=str(polytope_style["label"]),
        )
    )
    drawn = _ellipsoids(analysis, kinds, mvie, extra)
    for kind, E in drawn.items():
        style = _style(kind, list(drawn), analysis.capacity, labels)
        outline, sections = ellipsoid_outline(E, view)
        line_style = {"color": style["color"], "linestyle": style["linestyle"]}
        (line,) = ax.plot(*outline.T, linewidth=1.5, label=str(style["label"]), **line_style)
        if len(outline) == 2:
            line.set_marker("|")
        for section in sections:
            ax.plot(*section.T, linewidth=0.6, alpha=0.55, **line_style)
        handles.append(line)
    handles += _mark_centre(ax, analysis)
    reach = [np.linalg.norm(E.axes * E.semi_axes, axis=1) for E in drawn.values()]
    boxes = [
        np.vstack([E.center - r, E.center + r]) for E, r in zip(drawn.values(), reach, strict=True)
    ]
    bounds = np.vstack([P.vertices, np.zeros((1, 3)), analysis.center[None], *boxes])
    low, high = bounds.min(axis=0), bounds.max(axis=0)
    span = high - low
    floor = 1e-3 * max(float(span.max()), 1e-300)  # a flat set keeps a visible thickness
    pad = np.maximum(span, floor) * 0.02 + np.where(span < floor, floor, 0.0)
    ax.set(xlim=(low[0] - pad[0], high[0] + pad[0]), ylim=(low[1] - pad[1], high[1] + pad[1]))
    ax.set_zlim(low[2] - pad[2], high[2] + pad[2])
    # equal scales on the three axes (the outline is the silhouette of that view)
    ax.set_box_aspect(span + 2 * pad, zoom=0.9)
    ax.view_init(*view)
    _label_axes(ax, analysis, unit)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.labelpad = 6
    ax.tick_params(labelsize="small", pad=1)
    figure.legend(
        handles=handles,
        fontsize="small",
        loc="outside lower center",
        ncol=3,
        frameon=False,
    )
    if title:
        ax.set_title(title)
    return figure


def plot_directional_limits(
    analysis: Analysis,
    *,
    kinds: Sequence[str] | None = None,
    mvie: Ellipsoid | None = None,
    extra: Mapping[str, Ellipsoid] | None = None,
    directions: int = 720,
    unit: str | None = None,
    title: str | None = None,
    labels: Labels = None,
) -> Figure:
    """Polar plot of the upper directional limit ``hi(t)`` of P and of each ellipsoid (2-D).

    Only directions with a positive upper limit are drawn (the radius of a polar plot
    cannot be negative); the others are gaps.  Arguments as for :func:`plot_sets`.
    """
    fix = "analyze a task of 2 rows (task='planar'), or draw a 3-D task's sets with plot_sets_3d"
    labels = _check_analysis(analysis, 2, fix, labels, unit=unit, title=title)
    T = sphere_directions(directions, 2)
    angles = np.arctan2(T[:, 1], T[:, 0])
    order = np.argsort(angles)
    figure = Figure(figsize=(4.5, 4.5), layout="constrained")
    ax = figure.add_subplot(projection="polar")
    sets = {"polytope": analysis.polytope, **_ellipsoids(analysis, kinds, mvie, extra)}
    for name, S in sets.items():
        hi = S.limits(T).hi[order]
        style = _style(name, list(sets), analysis.capacity, labels)
        ax.plot(angles[order], np.where(hi > 0, hi, np.nan), **style)  # type: ignore[arg-type]
    unit = unit or analysis.unit(tex=True)
    ax.set_title(title or f"upper limit along each direction [{unit}]", fontsize="medium")
    ax.legend(fontsize="small", loc="lower left", bbox_to_anchor=(-0.1, -0.12))
    return figure


def plot_score_map(
    values: NDArray[np.float64],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    *,
    xlabel: str,
    ylabel: str,
    label: str,
    title: str | None = None,
    limits: tuple[float, float] | None = None,
) -> Figure:
    """Heat map of a score over a 2-D grid of configurations.

    Parameters
    ----------
    values : ndarray, shape (len(y), len(x))
        The score; NaN (undefined, e.g. the classic ellipsoid at a singularity) is drawn
        white.
    x, y : ndarray
        Grid coordinates.
    xlabel, ylabel, label : str
        Axis and colour-bar labels.
    limits : (float, float), optional
        The colour scale's range; give maps of one score the same one, so that their
        colours compare.
    """
    _check_texts(xlabel=xlabel, ylabel=ylabel, label=label, title=title)
    x, y = check_array("x", x, ("nx",)), check_array("y", y, ("ny",))
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(
            "values",
            "an array of numbers (NaN: undefined)",
            type(values).__name__,
            "pass a 2-D float array, with np.nan where the score is undefined, e.g. "
            "results[column].to_numpy(dtype=float).reshape(len(y), len(x))",
        ) from None
    if values.shape != (len(y), len(x)):
        raise InputError(
            "values",
            f"shape (len(y), len(x)) = {(len(y), len(x))}",
            f"shape {values.shape}",
            f"give one row per y value and one column per x value, e.g. "
            f"values.reshape({len(y)}, {len(x)}) (values.T if x and y are swapped)",
        )
    if not values.size:
        raise InputError(
            "values", "a grid of one value or more", f"shape {values.shape}", "give x and y values."
        )
    vmin, vmax = (None, None)
    if limits is not None:  # NaN or infinite limits are accepted, as before
        vmin, vmax = _check_pair("limits", limits, "(low, high), two numbers", finite=False)
        if vmin > vmax:  # (NaN compares False: an unknown end, as before)
            raise InputError(
                "limits",
                "(low, high) with low <= high",
                f"({vmin:g}, {vmax:g})",
                f"swap them: limits=({vmax:g}, {vmin:g})",
            )
    figure = Figure(figsize=(5.0, 4.0), layout="constrained")
    ax = figure.add_subplot()
    mesh = ax.pcolormesh(
        x, y, np.ma.masked_invalid(values), cmap="cividis", shading="nearest", vmin=vmin, vmax=vmax
    )
    figure.colorbar(mesh, ax=ax, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_aspect("equal")
    if title:
        ax.set_title(title, fontsize="medium")
    return figure


def _score_columns(
    results: pd.DataFrame, score: str, kinds: object
) -> dict[str, NDArray[np.float64]]:
    """The ``<kind>_<score>`` columns of ``results`` there are, of ``kinds``, as floats."""
    present = [kind for kind in _check_kinds(kinds) if f"{kind}_{score}" in results]
    if not present:
        raise InputError(
            "score",
            f"a score with columns in the results, e.g. {list(results)[:4]}",
            repr(score),
            _score_fix(results, score, kinds),
        )
    columns = {}
    for kind in present:
        column = results[f"{kind}_{score}"]
        try:
            columns[kind] = column.to_numpy(dtype=float)
        except (TypeError, ValueError):
            bad = column[pd.to_numeric(column, errors="coerce").isna() & column.notna()]
            raise InputError(
                f"results[{column.name!r}]",
                "numbers (NaN where undefined)",
                f"{bad.iloc[0]!r} in row {bad.index[0]!r}" if len(bad) else str(column.dtype),
                f"make the column numeric: pd.to_numeric(results[{column.name!r}], "
                "errors='coerce') (text becomes NaN).",
            ) from None
    return columns


def _score_fix(results: pd.DataFrame, score: object, kinds: object) -> str:
    """How to name a score that ``results`` has columns ``<kind>_<score>`` of."""
    columns = [str(column) for column in results.columns]
    names = _check_kinds(kinds)
    scores = sorted({c[len(k) + 1 :] for c in columns for k in names if c.startswith(f"{k}_")})
    if scores:
        return f"use a score these kinds have columns of, e.g. score={scores[0]!r}"
    owners = [c[: -len(f"_{score}")] for c in columns if c.endswith(f"_{score}")]
    if owners:
        return f"pass kinds that have this score, e.g. kinds={owners[:3]}"
    return (
        "pass the results of pe.sweep or of a study, whose columns are '<kind>_<score>' "
        "such as 'chiacchio_coverage'"
    )


def _bin_edges(data: NDArray[np.float64], bins: int) -> list[float]:
    """Equal bins over the finite data, at any magnitude (1e-300 to 1e300).

    Computed on the data scaled to [-1, 1] (no overflow of the range), and one value
    (or values within 1e-9 of the largest) gets bins 1e-3 of it wide around it.
    """
    if not data.size:
        return np.linspace(0.0, 1.0, bins + 1).tolist()
    scale = float(np.max(np.abs(data))) or 1.0
    lo, hi = float(np.min(data / scale)), float(np.max(data / scale))
    if hi - lo < 1e-9:
        lo, hi = lo - 5e-4, hi + 5e-4
    return (np.linspace(lo, hi, bins + 1) * scale).tolist()


def plot_score_histogram(
    results: pd.DataFrame,
    score: str,
    *,
    kinds: Sequence[str] = ("chiacchio", "yoshikawa"),
    bins: int = 30,
    title: str | None = None,
    capacity: str = "acceleration",
    labels: Labels = None,
) -> Figure:
    """Histograms of one score over the configurations of a study, one per ellipsoid.

    Parameters
    ----------
    results : DataFrame
        One row per configuration with ``<kind>_<score>`` columns.
    score : str
        A score name, e.g. ``"coverage"``.
    kinds : sequence of str
        Ellipsoids to overlay (step outlines in the line styles of :data:`STYLES`);
        configurations where one is undefined are left out of its histogram.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids they are (the witness's label: a torque or a joint velocity).
    labels : str or mapping, optional
        Names of the sets and of the score, as a table layout's ``labels``.
    """
    capacity, labels = _check_results(results, capacity, labels, title=title)
    bins = check_integer("bins", bins, 1, MAX_BINS)
    columns = _score_columns(results, score, kinds)
    present = list(columns)
    name, factor = score_display(score, capacity, labels)
    values = [factor * column for column in columns.values()]
    finite = [v[np.isfinite(v)] for v in values]
    edges = _bin_edges(np.concatenate(finite), bins)
    figure = Figure(figsize=(5.0, 3.6), layout="constrained")
    ax = figure.add_subplot()
    for kind, data in zip(present, finite, strict=True):
        style = _style(kind, present, capacity, labels)
        # an all-NaN column (undefined everywhere) is named, without bars or median
        median = f"median {np.median(data):.3g}" if data.size else "no finite value"
        ax.hist(
            data,
            bins=edges,
            histtype="step",
            color=str(style["color"]),
            linestyle=style["linestyle"],
            linewidth=1.6,
            label=f"{style['label']} ({median})",
        )
    ax.set_xlabel(name)
    ax.set_ylabel("configurations")
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title, fontsize="medium")
    return figure


def _abscissa(results: pd.DataFrame) -> pd.Series:
    """A path's time ``t`` [s], or else its ``configuration`` index; an InputError without."""
    for name in ("t", "configuration"):
        if name in results:
            return results[name]
    raise InputError(
        "results",
        "a results frame with a column 't' (time) or 'configuration' (the sample index)",
        f"columns {list(results.columns)[:8]}",
        "pass the frame of pe.sweep or of a trajectory study (pd.read_csv(results.csv)).",
    )


def plot_score_series(
    results: pd.DataFrame,
    score: str,
    *,
    kinds: Sequence[str] = ("chiacchio", "yoshikawa", "mvie"),
    title: str | None = None,
    capacity: str = "acceleration",
    labels: Labels = None,
) -> Figure:
    """One score of each candidate along a trajectory (against ``t``, or the sample index).

    Parameters
    ----------
    results : DataFrame
        One row per sample with ``<kind>_<score>`` columns (and ``t`` if the trajectory
        has time).
    score : str
        A score name, e.g. ``"coverage"``.
    kinds : sequence of str
        Candidates to draw, those with columns in ``results``.
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids they are (the witness's label: a torque or a joint velocity).
    labels : str or mapping, optional
        Names of the sets and of the score, as a table layout's ``labels``.
    """
    capacity, labels = _check_results(results, capacity, labels, title=title)
    columns = _score_columns(results, score, kinds)
    present = list(columns)
    x = _abscissa(results)
    name, factor = score_display(score, capacity, labels)
    figure = Figure(figsize=(6.0, 3.2), layout="constrained")
    ax = figure.add_subplot()
    for kind in present:
        style = _style(kind, present, capacity, labels)
        ax.plot(
            x,
            factor * columns[kind],
            color=str(style["color"]),
            linestyle=style["linestyle"],
            label=style["label"],
        )
    ax.set_xlabel("t [s]" if "t" in results else "sample")
    ax.set_ylabel(name)
    ax.grid(True, color="0.9", linewidth=0.6)
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title, fontsize="medium")
    return figure


def plot_tangent_limits(
    results: pd.DataFrame,
    *,
    unit: str = "m/s$^2$",
    capacity: str = "acceleration",
    labels: Labels = None,
) -> Figure:
    """What each set allows along the path's tangent: its interval over time.

    ``capacity`` chooses the sets (accelerations by default; velocities, forces), ``unit``
    is its task unit and ``labels`` (a table layout's) name the sets.

    Raises
    ------
    InputError
        Naming ``results`` if it has no pair of columns ``tangent_<set>_lo`` and
        ``tangent_<set>_hi`` of the capacity's sets (the results of a ``[trajectory]``
        study with velocities, or :func:`polyell.studies.trajectory.tangent_limits`), or
        only one column of a pair, or neither ``t`` nor ``configuration``.
    """
    capacity, labels = _check_results(results, capacity, labels, unit=unit)
    drawn = _tangent_sets(results, capacity)
    x = _abscissa(results)
    figure = Figure(figsize=(6.0, 3.4), layout="constrained")
    ax = figure.add_subplot()
    for name in drawn:
        style = _style(name, (), capacity, labels)
        for end in ("lo", "hi"):
            ax.plot(
                x,
                results[f"tangent_{name}_{end}"],
                color=str(style["color"]),
                linestyle=style["linestyle"],
                label=style["label"] if end == "hi" else None,
            )
    ax.axhline(0.0, color="0.6", linewidth=0.6)
    ax.set_xlabel("t [s]" if "t" in results else "sample")
    ax.set_ylabel(f"along the tangent [{unit}]")
    ax.legend(fontsize="small")
    return figure


def _tangent_sets(results: pd.DataFrame, capacity: str) -> list[str]:
    """The sets of ``capacity`` with both ``tangent_<set>_lo`` and ``_hi`` in ``results``.

    An InputError naming ``results`` if there is none, or a set has one of the two only.
    """
    names = ("polytope", *capacity_class(capacity).ellipsoid_kinds)
    ends = {name: [f"tangent_{name}_{end}" in results for end in ("lo", "hi")] for name in names}
    half = [name for name, found in ends.items() if any(found) and not all(found)]
    if half:
        name = half[0]
        missing = "hi" if ends[name][0] else "lo"
        raise InputError(
            "results",
            f"both columns tangent_{name}_lo and tangent_{name}_hi",
            f"no column tangent_{name}_{missing}",
            "pass both ends of each interval, as pe.studies.trajectory.tangent_limits(...) "
            "returns them (or drop the other column).",
        )
    drawn = [name for name, found in ends.items() if all(found)]
    if not drawn:
        tangents = [str(c) for c in results.columns if str(c).startswith("tangent_")]
        got = (
            f"tangent columns of other sets {tangents[:4]}"
            if tangents
            else f"no tangent_* columns (columns {[str(c) for c in results.columns][:6]})"
        )
        fix = (
            "pass the results of a [trajectory] study whose path has velocities qd1..qdn "
            "(pd.read_parquet(out / 'results')), or a frame with the columns of "
            "pe.studies.tangent_limits(robot, trajectory): "
            "frame.assign(**pe.studies.tangent_limits(robot, trajectory))"
        )
        owners = [
            other
            for other in CAPACITIES
            if any(f"tangent_{k}_hi" in results for k in capacity_class(other).ellipsoid_kinds)
        ]
        if owners:
            fix = f"pass the capacity the columns are of, capacity={owners[0]!r}; or {fix}"
        raise InputError(
            "results",
            f"columns tangent_<set>_lo and tangent_<set>_hi of the {capacity} sets {list(names)}",
            got,
            fix,
        )
    return drawn


#: The criteria of a posture choice and how a figure names them.
_POSTURE_CRITERIA = {
    "limit": "limit along d",
    "radius": "ball about the origin",
    "volume": "volume",
}


def plot_posture_indices(
    values: pd.DataFrame,
    table: pd.DataFrame,
    *,
    position: Sequence[float] | NDArray[np.float64] | None = None,
    xlabel: str | None = None,
    title: str | None = None,
    labels: Labels = None,
) -> Figure:
    """Each index of a posture choice along the postures, normalised to its own best.

    One panel per criterion (limit along d, ball about the origin, volume); on each, the
    truth (the polytope) and every ellipsoid, each divided by its largest value over the
    postures, so that the curves share one axis from 0 to 1; the posture each index picks
    is marked on its curve.

    Parameters
    ----------
    values : DataFrame
        :attr:`polyell.PostureChoice.values`: one row per posture, columns (kind, criterion).
    table : DataFrame
        :attr:`polyell.PostureChoice.table`: its ``picked`` column marks the picks.
    position : array-like, shape (k,), optional
        The postures' positions along the manifold (:attr:`polyell.SelfMotion.position`,
        rad); default the posture number.  The curves are drawn in its order.
    xlabel : str, optional
        Default ``"position along the self-motion [rad]"`` with ``position``, else
        ``"posture"``.
    title : str, optional
    labels : str or mapping, optional
        Names of the sets, as a table layout's ``labels``.

    Returns
    -------
    Figure
    """
    check_instance("values", values, pd.DataFrame, "pass choice.values of pe.posture_choice.")
    _check_texts(xlabel=xlabel, title=title)
    labels = _check_labels(labels)
    if not isinstance(values, pd.DataFrame) or values.columns.nlevels != 2:
        raise InputError(
            "values",
            "PostureChoice.values (columns (kind, quantity))",
            f"a DataFrame of {values.columns.nlevels} column level(s)",
            "pass choice.values of pe.posture_choice, unchanged (two column levels)",
        )
    if not isinstance(table, pd.DataFrame) or "picked" not in table.columns:
        raise InputError(
            "table",
            "PostureChoice.table (a 'picked' column)",
            f"columns {list(table.columns)[:6]}"
            if isinstance(table, pd.DataFrame)
            else type(table).__name__,
            "pass choice.table of the same pe.posture_choice as values",
        )
    count = len(values)
    if position is None:
        x = np.arange(count, dtype=float)
        xlabel = "posture" if xlabel is None else xlabel
    else:
        x = as_floats("position", position)
        if x.shape != (count,) or not np.all(np.isfinite(x)):
            raise InputError(
                "position",
                f"{count} finite positions, one per posture",
                f"shape {x.shape}" + ("" if np.all(np.isfinite(x)) else " with NaN or inf"),
                f"pass {count} finite values, one per row of values (e.g. SelfMotion.position), "
                "or leave position out",
            )
        xlabel = "position along the self-motion [rad]" if xlabel is None else xlabel
    order = np.argsort(x, kind="stable")
    kinds = list(dict.fromkeys(values.columns.get_level_values(0)))
    criteria = [c for c in _POSTURE_CRITERIA if ("polytope", c) in values.columns]
    figure = Figure(figsize=(6.0, 2.0 + 1.6 * len(criteria)), layout="constrained")
    axes = figure.subplots(len(criteria), 1, sharex=True, squeeze=False)[:, 0]
    for ax, criterion in zip(axes, criteria, strict=True):
        for kind in kinds:
            index = values[(kind, criterion)].to_numpy(dtype=float)
            best = np.nanmax(index) if np.any(index > 0) else np.nan
            if not best > 0:
                continue  # undefined or zero everywhere: nothing to normalise
            style = _style(kind, kinds, values.attrs.get("capacity", "acceleration"), labels)
            label = f"{style['label']} (truth)" if kind == "polytope" else str(style["label"])
            ax.plot(
                x[order],
                index[order] / best,
                color=str(style["color"]),
                linestyle=style["linestyle"],
                linewidth=float(style["linewidth"]),  # type: ignore[arg-type]
                label=label,
            )
            picked = table.loc[(kind, criterion), "picked"]
            if not pd.isna(picked):
                k = int(picked)
                ax.plot(
                    [x[k]],
                    [index[k] / best],
                    marker="o" if kind == "polytope" else "v",
                    markersize=7 if kind == "polytope" else 5,
                    markerfacecolor="white" if kind == "polytope" else str(style["color"]),
                    markeredgecolor=str(style["color"]),
                    linestyle="none",
                )
        ax.set_ylim(-0.05, 1.12)
        ax.set_ylabel(f"{_POSTURE_CRITERIA[criterion]}\n/ own best")
        ax.grid(True, color="0.9", linewidth=0.6)
    axes[0].legend(fontsize="x-small", loc="lower left", ncol=2, framealpha=0.85)
    axes[-1].set_xlabel(xlabel)
    if title:
        axes[0].set_title(title, fontsize="medium")
    return figure


def save_figure(
    figure: Figure,
    stem: str | Path,
    formats: Sequence[str] | None = None,
    dpi: int = 300,
) -> list[Path]:
    """Save ``figure`` at print resolution: ``stem.pdf`` and ``stem.png``, or one named file.

    * ``save_figure(fig, "sets")`` writes ``sets.pdf`` and ``sets.png``;
      ``formats=("svg",)`` writes ``sets.svg``.
    * A name that ends in a figure format (``"sets.png"``, ``"sets.PDF"``, any format of
      ``figure.canvas.get_supported_filetypes()``) writes that file only, in that format.

    Each file is written under a temporary name and renamed (never half a file).

    Parameters
    ----------
    figure : Figure
    stem : str or Path
        A file name without a suffix, or with a figure format's suffix.
    formats : sequence of str, optional
        Formats, each written as ``stem.<format>``; default ``("pdf", "png")``, or the
        suffix of ``stem`` when it is a figure format.  Empty: nothing is written.
    dpi : int, optional
        Dots per inch of the raster formats (:data:`MIN_DPI` to :data:`MAX_DPI`).

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    InputError
        For a name with a figure suffix together with ``formats`` that are not exactly
        that format (ambiguous: ``"x.png"`` with ``("pdf", "png")``), a name without a
        file's name (``""``, ``"out/"``: hidden files ``.pdf``), unknown formats, or a
        ``dpi`` out of range.
    StorageError
        If a file cannot be written.
    """
    check_instance("figure", figure, Figure, _FIX_FIGURE)
    if not isinstance(stem, str | Path):
        raise InputError(
            "stem",
            "a file name without extension (str or Path)",
            repr(stem),
            "pass a str or pathlib.Path, e.g. stem='figures/sets'",
        )
    if str(stem).replace(os.sep, "/").rsplit("/", 1)[-1] in ("", ".", ".."):
        raise InputError(
            "stem",
            "a file name, e.g. 'sets' or 'out/sets'",
            repr(stem),
            "name the file: a folder alone would write hidden files such as '.pdf'.",
        )
    supported = sorted(figure.canvas.get_supported_filetypes())
    if formats is not None and (
        isinstance(formats, str)
        or not isinstance(formats, Sequence)
        or not all(fmt in supported for fmt in formats)
    ):
        raise InputError(
            "formats",
            f"a sequence of formats among {supported}",
            repr(formats),
            "pass a list of formats listed, e.g. formats=['pdf', 'png'] (one format: ['png'])",
        )
    suffix = Path(stem).suffix[1:].lower()
    targets: list[tuple[Path, str]]
    if formats is not None and not len(formats):
        targets = []  # no format asked for (a study writing its report only)
    elif suffix in supported:
        if formats is not None and list(formats) != [suffix]:
            raise InputError(
                "stem",
                "a name without a figure suffix when formats are given",
                f"{str(stem)!r} with formats {list(formats)}",
                f"drop the suffix to write each format, or leave formats out to write "
                f"{Path(stem).name} only.",
            )
        targets = [(Path(stem), suffix)]
    else:
        chosen = ("pdf", "png") if formats is None else formats
        targets = [(Path(f"{stem}.{fmt}"), fmt) for fmt in chosen]
    if (
        isinstance(dpi, bool)
        or not isinstance(dpi, int | float | np.integer | np.floating)
        or not MIN_DPI <= dpi <= MAX_DPI
    ):
        raise InputError(
            "dpi",
            f"dots per inch from {MIN_DPI} to {MAX_DPI}",
            repr(dpi),
            "pass a number in that range, e.g. dpi=300",
        )
    paths = []
    for path, fmt in targets:
        metadata = {"CreationDate": None} if fmt == "pdf" else None

        def save(name: str, fmt: str = fmt, metadata: dict[str, None] | None = metadata) -> None:
            figure.savefig(name, format=fmt, dpi=dpi, metadata=metadata)

        paths.append(write_atomically(path, save))
    return paths
