"""Interactive views (plotly): the sets in 2-D and 3-D, score maps and histograms, reports.

Every function returns a ``plotly.graph_objects.Figure`` (shown inline in a notebook);
:func:`write_report` puts several into one self-contained HTML file that works offline
(plotly's JavaScript is embedded once, nothing is fetched).  plotly is imported here only,
when a figure is made (start-up time).

Traces are grouped per set, so clicking a legend entry toggles that set; hovering shows its
values (coordinates, volume and scores, or a configuration and every score of a map).
"""

from __future__ import annotations

import html
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import check_capacity
from polyell.comparison.comparison import SCORE_NAMES, Comparison
from polyell.comparison.labels import Labels, check_labels, label_text
from polyell.comparison.latex_text import unit_power
from polyell.comparison.layout import TableLayout
from polyell.comparison.summary import result_kinds, split_column
from polyell.comparison.tables import score_display
from polyell.errors import InputError
from polyell.export import mesh, polytope_edges
from polyell.geometry.hpolytope import require_drawable
from polyell.storage import as_path, write_text_atomically
from polyell.validation import _describe, check_frame, check_instance, check_integer

if TYPE_CHECKING:  # plotly and pandas are imported where they are used (start-up time)
    import pandas as pd
    import plotly.graph_objects as go

__all__ = [
    "COLORS",
    "DECIMATION_BUCKETS",
    "ELLIPSOID_OPACITY",
    "HISTOGRAM_BINS",
    "POLYTOPE_OPACITY",
    "HtmlTable",
    "SeriesDecimator",
    "decimate_series",
    "decimation_note",
    "interactive_histogram",
    "interactive_map",
    "interactive_series",
    "interactive_sets",
    "write_report",
]

#: How to mend a wrong results argument (the message of check_instance).
_FIX_RESULTS = "pass the results frame of pe.sweep or of a study (pd.read_csv(results.csv))."

#: One colour per set (the static figures are greyscale; here colour separates the sets).
COLORS = {
    "polytope": "#555555",
    "chiacchio": "#1f77b4",
    "yoshikawa": "#d62728",
    "mvie": "#2ca02c",
    "outer": "#9467bd",
}
_CANDIDATE_COLORS = ("#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#bcbd22")
#: Opacity of the polytope's faces and of each ellipsoid's surface in 3-D: the ellipsoids
#: are the more transparent, and the polytope's edges are lines, seen through all of them.
POLYTOPE_OPACITY = 0.3
ELLIPSOID_OPACITY = 0.18
POLYTOPE_EDGE_COLOR = "#222222"
#: Buckets a long series is cut into for plotting; each keeps, per trace, its smallest and
#: largest value (and its first NaN, so that gaps stay visible): a series of any length is
#: drawn with at most ``3 * traces`` points per bucket.
DECIMATION_BUCKETS = 1000
#: Scores shown when hovering over an ellipsoid.
_HOVER_SCORES = ("inscribed_scale", "enclosing_scale", "coverage", "mvie_ratio", "outer_ratio")


def _close(name: str, valid: Sequence[str]) -> str:
    """A fix naming the valid column closest to ``name`` (difflib), if any."""
    from difflib import get_close_matches

    close = get_close_matches(str(name), valid, n=1, cutoff=0.6)
    return f"did you mean {close[0]!r}?" if close else ""


def _plain_label(row: str) -> str:
    """A plain-text axis label (plotly shows no TeX offline): ẍ for x, ω̇x for wx."""
    if row.startswith("w"):
        return "\u03c9\u0307" + row[1:]
    return row[0] + "\u0308" + row[1:]


def _plot_title(title: object) -> str | None:
    """A figure's title as plotly shows it: text, not markup (``<``, ``&`` escaped).

    Plotly reads a subset of HTML in titles (``<b>``, ``<a href=...>``); a title is plain
    text here, its line breaks kept (as ``<br>``).
    """
    if title is None:
        return None
    if not isinstance(title, str):
        raise InputError(
            "title",
            "a str or None",
            f"{type(title).__name__} {title!r:.60}",
            "pass the title as text, e.g. title='Panda at q0', or leave it out.",
        )
    return "<br>".join(html.escape(line) for line in title.splitlines()) if title else None


def _labels(labels: object) -> Labels:
    """The names of sets and scores a figure shows: as a table layout's ``labels``.

    A :class:`~polyell.comparison.layout.TableLayout` (its ``labels``), a preset's name, a
    mapping of set and score names to labels (plain text, or ``(plain, latex)``: a figure
    shows the plain text) or None (the defaults); checked as the layout checks them, every
    message naming ``labels``.
    """
    if isinstance(labels, TableLayout):
        return labels.labels
    if labels is not None and not isinstance(labels, str | Mapping):
        raise InputError(
            "labels",
            "a pe.TableLayout, a mapping of set or score names to labels, or a preset's name",
            _describe(labels),
            'e.g. labels={"chiacchio": "DME", "coverage": "share covered"}, or the '
            "layout of your tables.",
        )
    return check_labels(labels, "labels")


def _name(kind: str, capacity: str, labels: Labels) -> str:
    """A set's label as plotly shows it (a legend entry, a title): its text, not markup."""
    return html.escape(label_text(kind, capacity, labels).plain, quote=False)


def _score(score: str, capacity: str, labels: Labels) -> tuple[str, float]:
    """A score's label as plotly shows it (:func:`score_display`), and its factor."""
    name, factor = score_display(score, capacity, labels)
    return html.escape(name, quote=False), factor


def _plotly() -> Any:
    """Plotly's graph objects, imported on first use."""
    import plotly.graph_objects as go

    return go


def _results_figure(
    results: object, title: object, capacity: str, labels: object
) -> tuple[str, Labels, str | None, Any]:
    """The checked capacity, labels and title of a figure of ``results``, and plotly."""
    check_frame("results", results, _FIX_RESULTS)
    return check_capacity(capacity), _labels(labels), _plot_title(title), _plotly()


def _xyz(
    points: NDArray[np.float64], faces: NDArray[np.int64] | None = None
) -> dict[str, NDArray[Any]]:
    """A trace's coordinates: the columns of ``points`` (k, 2 or 3), the faces' vertices."""
    columns = dict(zip("xyz", points.T, strict=False))
    return columns if faces is None else columns | dict(zip("ijk", faces.T, strict=True))


def _color(kind: str, kinds: Sequence[str]) -> str:
    if kind in COLORS:
        return COLORS[kind]
    others = [k for k in kinds if k not in COLORS]
    index = others.index(kind) if kind in others else 0
    return _CANDIDATE_COLORS[index % len(_CANDIDATE_COLORS)]


def _hover_text(kind: str, comparison: Comparison, unit: str, labels: Labels) -> str:
    record = comparison[kind]
    capacity = comparison.analysis.capacity
    lines = [f"<b>{_name(kind, capacity, labels)}</b>"]
    lines.append(f"volume {record.volume:.4g} {unit_power(unit, int(record.dimension))}")
    for score in _HOVER_SCORES:
        value = getattr(record, score)
        if np.isfinite(value):
            name, factor = _score(score, capacity, labels)
            lines.append(f"{name} {factor * value:.4g}")
    return "<br>".join(lines)


def interactive_sets(
    comparison: Comparison,
    kinds: Sequence[str] | None = None,
    *,
    title: str | None = None,
    labels: Labels | TableLayout = None,
) -> go.Figure:
    """The polytope and the ellipsoids of a comparison, rotatable (3-D) or zoomable (2-D).

    Parameters
    ----------
    comparison : Comparison
        From :func:`polyell.compare`; its sets are drawn in its task frame.
    kinds : sequence of str, optional
        Which ellipsoids; default every defined one (both definitions, the MVIE, the outer
        ellipsoid, candidates).
    title : str, optional
    labels : str, mapping or TableLayout, optional
        The names of the sets (legend, hover) and of the scores (hover), as a table
        layout's ``labels`` (:class:`polyell.TableLayout`: a mapping of set and score
        names to labels, plain text or ``(plain, latex)``, or a preset's name), or a
        layout whose labels these are; default one name per set.

    Returns
    -------
    plotly.graph_objects.Figure
        One legend entry per set (click to hide or show it); hover for the values.

    Raises
    ------
    InputError
        For a task space other than 2-D or 3-D, an empty or unbounded set (naming
        ``comparison``), or labels that are not labels (naming ``labels``).
    """
    check_instance("comparison", comparison, Comparison, "pass pe.compare(analysis).")
    labels = _labels(labels)
    title = _plot_title(title)
    go = _plotly()
    analysis = comparison.analysis
    m = analysis.m
    if m not in (2, 3):
        raise InputError(
            "comparison",
            "a 2-D or 3-D task space",
            f"m = {m}",
            "analyze a task of 2 or 3 rows (task='planar' or 'linear'), or read the "
            "comparison's scores (comparison.to_markdown()).",
        )
    if kinds is not None and (
        isinstance(kinds, str)
        or not isinstance(kinds, Sequence)
        or not all(isinstance(kind, str) and kind in comparison.kinds for kind in kinds)
    ):
        raise InputError(
            "kinds", f"a list of the comparison's kinds, among {list(comparison.kinds)}",
            repr(kinds)[:80], "pass a list such as kinds=['chiacchio'], or leave kinds out.",
        )  # fmt: skip
    chosen = [k for k in (kinds or comparison.kinds) if comparison[k].defined]
    unit = analysis.unit()
    rows = [_plain_label(row) for row in analysis.task]
    P = analysis.polytope
    require_drawable(P, "comparison")  # empty or unbounded: nothing to draw, in 2-D as in 3-D
    figure = go.Figure()
    vertex_text = [
        "<br>".join(f"{label} {value:.4g} {unit}" for label, value in zip(rows, v, strict=True))
        for v in P.vertices
    ]
    polytope = _name("polytope", analysis.capacity, labels)
    polytope_name = f"{polytope}, volume {P.volume:.4g} {unit_power(unit, P.dim)}"
    if m == 2:
        outline = P.vertices if P.dim < 2 else np.vstack([P.vertices, P.vertices[:1]])
        figure.add_trace(
            go.Scatter(
                **_xyz(outline),
                mode="lines+markers",
                name=polytope_name,
                line={"color": COLORS["polytope"], "dash": "dash", "width": 3},
                text=vertex_text + vertex_text[:1],
                hoverinfo="text",
            )
        )
    else:
        vertices, faces, _ = mesh(P)
        if len(faces):
            figure.add_trace(
                go.Mesh3d(
                    **_xyz(vertices, faces),
                    color=COLORS["polytope"],
                    opacity=POLYTOPE_OPACITY,
                    flatshading=True,
                    name=polytope_name,
                    legendgroup="polytope",
                    showlegend=True,
                    hoverinfo="skip",
                )
            )
        # its edges, drawn as lines: seen through every translucent ellipsoid
        edges = polytope_edges(P)
        ends = P.vertices[edges]  # (E, 2, 3)
        gaps = np.full((len(edges), 1, 3), np.nan)  # one trace, a break after each edge
        path = np.concatenate([ends, gaps], axis=1).reshape(-1, 3)
        figure.add_trace(
            go.Scatter3d(
                **_xyz(path),
                mode="lines",
                line={"color": POLYTOPE_EDGE_COLOR, "width": 4},
                name=polytope_name,
                legendgroup="polytope",
                showlegend=not len(faces),
                hoverinfo="skip",
            )
        )
        figure.add_trace(
            go.Scatter3d(
                **_xyz(P.vertices),
                mode="markers",
                marker={"size": 3, "color": POLYTOPE_EDGE_COLOR},
                name=f"{polytope} vertices",
                legendgroup="polytope",
                showlegend=False,
                text=vertex_text,
                hoverinfo="text",
            )
        )
    for kind in chosen:
        E = comparison.ellipsoid(kind)
        color, text = _color(kind, chosen), _hover_text(kind, comparison, unit, labels)
        name = _name(kind, analysis.capacity, labels)
        if m == 2 or E.rank < 3:
            # a point (rank 0: a set pinned to one point) as a marker, else its outline
            curve = E.boundary_curve(240, closed=True) if E.rank else E.center[None]
            mode = "lines" if E.rank else "markers"
            trace = (go.Scatter if m == 2 else go.Scatter3d)(**_xyz(curve), mode=mode)
            trace.update(name=name, line={"color": color, "width": 3}, text=text, hoverinfo="text")
            figure.add_trace(trace)
            continue
        vertices, faces, _ = mesh(E)
        figure.add_trace(
            go.Mesh3d(
                **_xyz(vertices, faces),
                color=color,
                opacity=ELLIPSOID_OPACITY,
                name=name,
                legendgroup=kind,
                showlegend=True,
                hovertext=text,
                hoverinfo="text",
            )
        )
    centre = {axis: [value] for axis, value in zip("xyz", analysis.center, strict=False)}
    figure.add_trace(
        (go.Scatter if m == 2 else go.Scatter3d)(
            **centre,
            mode="markers",
            marker={"symbol": "cross", "color": "black", "size": 6},
            name=analysis.centre_label,
        )
    )
    if m == 2:
        figure.update_yaxes(scaleanchor="x", scaleratio=1)
        figure.update_layout(xaxis_title=f"{rows[0]} [{unit}]", yaxis_title=f"{rows[1]} [{unit}]")
    else:
        figure.update_layout(
            scene={
                "aspectmode": "data",
                "xaxis_title": f"{rows[0]} [{unit}]",
                "yaxis_title": f"{rows[1]} [{unit}]",
                "zaxis_title": f"{rows[2]} [{unit}]",
                # farther than plotly's default (1.25, 1.25, 1.25): the axis titles whole
                "camera": {"eye": {"x": 1.6, "y": 1.6, "z": 1.2}},
            },
            height=640,
            margin={"l": 10, "r": 10, "t": 50, "b": 10},
            # the legend below the scene: the scene keeps the page's whole width
            legend={"orientation": "h", "yanchor": "top", "y": -0.02, "x": 0.0},
        )
    figure.update_layout(title=title, template="plotly_white", legend={"itemclick": "toggle"})
    return figure


def interactive_map(
    results: pd.DataFrame,
    columns: str | Sequence[str],
    x: str,
    y: str,
    *,
    title: str | None = None,
    capacity: str = "acceleration",
    labels: Labels | TableLayout = None,
    units: tuple[str, str] = ("rad", "rad"),
) -> go.Figure:
    """Heat maps of scores over a grid of two joints, the configuration and scores on hover.

    Parameters
    ----------
    results : DataFrame
        One row per configuration of a grid (``pe.sweep``), with the joint columns.
    columns : str or sequence of str
        The score columns mapped, e.g. ``"chiacchio_coverage"``; with several, a menu
        switches between them (one colour scale per score, shared by the ellipsoids).
    x, y : str
        The joint columns along the horizontal and vertical axes (e.g. ``"q3"``, ``"q2"``).
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids the scores are.
    labels : str, mapping or TableLayout, optional
        The names of the sets and scores in the titles, the menu and the colour bar, as
        :func:`interactive_sets` takes them.
    units : (str, str), optional
        The units of ``x`` and ``y`` on the axes: ``"rad"``, ``"m"`` for a prismatic joint
        (:func:`~polyell.studies.posture_tables.joint_units`).

    Returns
    -------
    plotly.graph_objects.Figure
        Hovering over a cell shows its configuration, the polytope's numbers and every
        score of the mapped ellipsoid.
    """
    import pandas as pd

    capacity, labels, title, go = _results_figure(results, title, capacity, labels)
    if isinstance(columns, str):
        mapped = [columns]
    elif isinstance(columns, Sequence) and columns and all(isinstance(c, str) for c in columns):
        mapped = list(columns)
    else:
        raise InputError(
            "columns",
            "a score column or a non-empty list of them, e.g. 'chiacchio_coverage'",
            repr(columns)[:80],
            "pass a column of the results such as 'chiacchio_coverage'.",
        )
    for label, value in (("x", x), ("y", y)):
        if not isinstance(value, str):
            raise InputError(
                label,
                "the name of a joint column such as 'q2'",
                repr(value)[:80],
                f"pass {label}='q2' (a joint the grid varies).",
            )
    if x == y:
        raise InputError(
            "y",
            f"a joint column other than x = {x!r}",
            repr(y),
            "pass the grid's other varying joint as y.",
        )
    if not (
        isinstance(units, tuple | list)
        and len(units) == 2
        and all(u in ("rad", "m") for u in units)
    ):
        raise InputError(
            "units",
            'two joint units, each "rad" or "m"',
            repr(units)[:80],
            'pass units=("rad", "rad"), "m" for a prismatic joint.',
        )
    for name in (*mapped, x, y):
        if name not in results:
            raise InputError(
                "results",
                f"a column {name!r}",
                f"columns {list(results)[:8]}...",
                _close(name, [str(c) for c in results.columns])
                or "pass a results frame of pe.sweep with that column, or another name.",
            )
    table = results.sort_values([y, x])
    xs, ys = np.unique(table[x].to_numpy()), np.unique(table[y].to_numpy())
    if len(xs) * len(ys) != len(table):
        raise InputError(
            "results",
            f"a full grid over ({x}, {y})",
            f"{len(table)} rows",
            "pass the results of a grid sweep (every x with every y), or draw a histogram.",
        )
    common = [
        c
        for c in table.columns
        if c == "configuration" or re.fullmatch(r"q\d+", c) or c.startswith("polytope_")
    ]
    split = {c: parts for c in table.columns if (parts := split_column(c)) is not None}
    scores = list(split)
    shown = common + scores
    for column in (*shown, x, y):
        numbers = pd.to_numeric(table[column], errors="coerce")
        if bool((numbers.isna() & table[column].notna()).any()):
            raise InputError(
                f"results[{column!r}]",
                "numbers",
                f"{table[column][numbers.isna()].iloc[0]!r}",
                "pass the numeric results of pe.sweep (or convert the column to numbers).",
            )
    values64 = table[shown].to_numpy(dtype=float)
    finite = np.abs(values64[np.isfinite(values64)])
    # float32: the hover shows 4 digits, and the page is half the size (float64 where a
    # value is beyond float32's range, which would overflow to inf)
    small = not finite.size or float(finite.max()) <= float(np.finfo(np.float32).max)
    data = (values64.astype(np.float32) if small else values64).reshape(
        len(ys), len(xs), len(shown)
    )

    def hover(column: str) -> str:
        kind = split[column][0]
        rows = [c for c in shown if c in common or split[c][0] == kind]
        return "<br>".join(f"{c} %{{customdata[{shown.index(c)}]:.4g}}" for c in rows)

    views = []
    for column in mapped:
        if column not in split:
            raise InputError(
                "columns",
                "score columns <ellipsoid>_<score>",
                repr(column),
                "pass a column such as 'chiacchio_coverage'.",
            )
        kind, score = split[column]
        label, factor = _score(score, capacity, labels)
        same = [c for c in mapped if split[c][1] == score]
        values = factor * table[same].to_numpy(dtype=float)
        finite = values[np.isfinite(values)]
        low, high = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
        z = factor * table[column].to_numpy(dtype=float).reshape(len(ys), len(xs))
        views.append(
            (f"{_name(kind, capacity, labels)}: {label}", z, low, high, label, hover(column))
        )
    name, z, low, high, label, template = views[0]
    figure = go.Figure(
        go.Heatmap(
            x=xs,
            y=ys,
            z=z,
            zmin=low,
            zmax=high,
            customdata=data,
            hovertemplate=template + "<extra></extra>",
            colorscale="Cividis",
            colorbar={"title": {"text": label}},
        )
    )
    if len(views) > 1:
        buttons = [
            {
                "label": view[0],
                "method": "update",
                "args": [
                    {
                        "z": [view[1]],
                        "zmin": [view[2]],
                        "zmax": [view[3]],
                        "colorbar.title.text": view[4],
                        "hovertemplate": [view[5] + "<extra></extra>"],
                    },
                    {"title.text": title or view[0]},
                ],
            }
            for view in views
        ]
        figure.update_layout(updatemenus=[{"buttons": buttons, "x": 0.0, "y": 1.15}])
    figure.update_layout(
        title=title or name,
        xaxis_title=f"{x} [{units[0]}]",
        yaxis_title=f"{y} [{units[1]}]",
        template="plotly_white",
    )
    return figure


def _kinds_with(results: pd.DataFrame, score: str, kinds: Sequence[str] | None) -> list[str]:
    """The ellipsoids (``kinds``, default all) with a ``<kind>_<score>`` column."""
    if not isinstance(score, str):
        raise InputError(
            "score",
            f"a score name, one of {list(SCORE_NAMES)}",
            repr(score)[:80],
            "pass a score name such as 'coverage'.",
        )
    if kinds is not None and (
        isinstance(kinds, str)
        or not isinstance(kinds, Sequence)
        or not all(isinstance(kind, str) for kind in kinds)
    ):
        raise InputError(
            "kinds",
            "a list of ellipsoid names such as ['chiacchio']",
            repr(kinds)[:80],
            "pass a list such as kinds=['chiacchio'], or leave kinds out.",
        )
    chosen = [k for k in (kinds or result_kinds(results.columns)) if f"{k}_{score}" in results]
    if not chosen:
        raise InputError(
            "score",
            "a score with columns in the results",
            repr(score),
            f"one of {list(SCORE_NAMES)}",
        )
    return chosen


#: Most bins of an interactive histogram.
HISTOGRAM_BINS = 200


def interactive_histogram(
    results: pd.DataFrame,
    score: str,
    kinds: Sequence[str] | None = None,
    *,
    title: str | None = None,
    capacity: str = "acceleration",
    labels: Labels | TableLayout = None,
) -> go.Figure:
    """Overlaid histograms of one score over a study, one per ellipsoid (toggle in the legend).

    The counts are binned here, on bins shared by every ellipsoid (numpy's ``"auto"`` rule,
    at most :data:`HISTOGRAM_BINS`), so that the figure's size does not grow with the
    number of configurations.  ``capacity`` says whose ellipsoids the scores are, as in
    :func:`interactive_map`; ``labels`` name the sets (legend) and the score (axis), as
    :func:`interactive_sets` takes them.
    """
    capacity, labels, title, go = _results_figure(results, title, capacity, labels)
    chosen = _kinds_with(results, score, kinds)
    label, factor = _score(score, capacity, labels)
    values = {}
    for kind in chosen:
        column = factor * results[f"{kind}_{score}"].to_numpy(dtype=float)
        values[kind] = column[np.isfinite(column)]
    every = np.concatenate([np.zeros(0), *values.values()])
    figure = go.Figure()
    if every.size:
        edges = np.histogram_bin_edges(every, bins="auto")
        if len(edges) > HISTOGRAM_BINS + 1:
            edges = np.linspace(edges[0], edges[-1], HISTOGRAM_BINS + 1)
        for kind in chosen:
            counts, _ = np.histogram(values[kind], bins=edges)
            figure.add_trace(
                go.Bar(
                    x=0.5 * (edges[:-1] + edges[1:]),
                    y=counts,
                    width=np.diff(edges),
                    name=_name(kind, capacity, labels),
                    opacity=0.6,
                    marker_color=_color(kind, chosen),
                )
            )
    figure.update_layout(
        barmode="overlay",
        bargap=0,
        title=title,
        xaxis_title=label,
        yaxis_title="configurations",
        template="plotly_white",
    )
    return figure


def _bucket_picks(values: NDArray[np.float64], bucket: int) -> NDArray[np.int64]:
    """Rows kept of ``values`` (k, traces): per bucket of rows and trace, min, max, first NaN."""
    k = len(values)
    if k == 0:
        return np.zeros(0, dtype=np.int64)
    whole = -(-k // bucket) * bucket
    padded = np.full((whole, values.shape[1]), np.nan)
    padded[:k] = values
    blocks = padded.reshape(-1, bucket, values.shape[1])  # (buckets, bucket, traces)
    starts = np.arange(len(blocks))[:, None] * bucket
    finite = np.isfinite(blocks)
    low = np.where(finite, blocks, np.inf).argmin(axis=1)
    high = np.where(finite, blocks, -np.inf).argmax(axis=1)
    nan = (~finite).argmax(axis=1)  # the first non-finite row (0 where there is none)
    has_nan = (~finite[:, :bucket]).any(axis=1)
    picks = [starts + low, starts + high, (starts + nan)[has_nan]]
    rows = np.unique(np.concatenate([p.ravel() for p in picks]))
    return rows[rows < k].astype(np.int64)


class SeriesDecimator:
    """Min/max-preserving decimation of a long series read in parts (constant memory).

    Rows are cut into buckets of ``bucket = ceil(total / buckets)`` consecutive samples;
    each bucket keeps, per trace, the rows of its smallest and largest value and of its
    first NaN (a gap).  The extremes of every trace are therefore all drawn, and a series
    of ``total`` samples becomes at most ``3 * traces * buckets`` rows.

    Parameters
    ----------
    total : int
        The series' length (all parts together).
    traces : sequence of str
        The columns whose extremes are kept; the other columns (e.g. ``t``) follow them.
    buckets : int, optional
        How many buckets (default :data:`DECIMATION_BUCKETS`); a series of at most
        ``2 * buckets`` samples is kept whole.
    """

    def __init__(
        self, total: int, traces: Sequence[str], buckets: int = DECIMATION_BUCKETS
    ) -> None:
        self.total = check_integer("total", total, 0, 2**62)
        if isinstance(traces, str) or not isinstance(traces, Sequence):
            raise InputError(
                "traces", "a list of column names", repr(traces)[:80], "pass e.g. ['coverage']."
            )
        self.traces = list(traces)
        if not all(isinstance(trace, str) for trace in self.traces):
            raise InputError(
                "traces", "column names (str)", repr(self.traces)[:80], "pass each name as a str."
            )
        buckets = check_integer("buckets", buckets, 1, 2**62)
        self.bucket = 1 if self.total <= 2 * buckets else -(-self.total // buckets)
        self._carry: pd.DataFrame | None = None
        self._kept: list[pd.DataFrame] = []
        self._columns: pd.DataFrame | None = None  # an empty frame of the series' columns

    def _keep(self, frame: pd.DataFrame) -> None:
        if self.bucket == 1:
            self._kept.append(frame)
            return
        values = frame[self.traces].to_numpy(dtype=float)
        self._kept.append(frame.iloc[_bucket_picks(values, self.bucket)])

    def add(self, frame: pd.DataFrame) -> None:
        """The next rows of the series, in order."""
        import pandas as pd

        check_instance("frame", frame, pd.DataFrame, "pass the next rows of the series.")
        missing = [trace for trace in self.traces if trace not in frame]
        if missing:
            raise InputError(
                "frame",
                f"the columns {self.traces}",
                f"none named {missing}",
                "add those columns to every frame, or leave them out of traces.",
            )
        if self._columns is None:
            self._columns = frame.iloc[:0]
        if self._carry is not None:
            frame = pd.concat([self._carry, frame], ignore_index=True)
        whole = len(frame) // self.bucket * self.bucket
        self._keep(frame.iloc[:whole])
        self._carry = frame.iloc[whole:].reset_index(drop=True)

    def result(self) -> pd.DataFrame:
        """The kept rows, in order."""
        import pandas as pd

        if self._carry is not None and len(self._carry):
            self._keep(self._carry)
        self._carry = None
        frames = [frame for frame in self._kept if len(frame)]
        if frames:
            return pd.concat(frames, ignore_index=True)
        # nothing kept: no rows, but the series' columns
        return pd.DataFrame() if self._columns is None else self._columns.reset_index(drop=True)


def decimate_series(
    frame: pd.DataFrame, traces: Sequence[str], buckets: int = DECIMATION_BUCKETS
) -> pd.DataFrame:
    """The rows of ``frame`` a plot of the columns ``traces`` needs (:class:`SeriesDecimator`)."""
    check_frame("frame", frame, _FIX_RESULTS)
    decimator = SeriesDecimator(len(frame), traces, buckets)
    decimator.add(frame.reset_index(drop=True))
    return decimator.result()


def decimation_note(total: int, shown: int) -> str:
    """The sentence a page shows under a decimated series."""
    total = check_integer("total", total, 0, 2**62)
    shown = check_integer("shown", shown, 0, 2**62)
    if shown >= total:
        return f"{total:,} samples, all shown."
    return (
        f"{total:,} samples, shown decimated to {shown:,} (per bucket of "
        f"{-(-total // DECIMATION_BUCKETS):,} consecutive samples, each curve's smallest and "
        "largest value)."
    )


def interactive_series(
    results: pd.DataFrame,
    score: str,
    kinds: Sequence[str] | None = None,
    *,
    title: str | None = None,
    capacity: str = "acceleration",
    total: int | None = None,
    labels: Labels | TableLayout = None,
) -> go.Figure:
    """One score of each ellipsoid along a trajectory (against ``t``, or the sample index).

    Parameters
    ----------
    results : DataFrame
        One row per sample (``pe.sweep`` of a trajectory), or already decimated
        (:func:`decimate_series`) with ``total`` its original length.
    score : str
    kinds : sequence of str, optional
        The ellipsoids drawn; default every one with a ``<kind>_<score>`` column.
    title : str, optional
    capacity : {"acceleration", "velocity", "force"}, optional
        Whose ellipsoids the scores are: their names (a force ``"chiacchio"`` is "with
        gravity").
    total : int, optional
        The number of samples ``results`` was decimated from.
    labels : str, mapping or TableLayout, optional
        The names of the sets (legend) and of the score (axis), as
        :func:`interactive_sets` takes them.

    Returns
    -------
    plotly.graph_objects.Figure
        A series longer than ``2 * DECIMATION_BUCKETS`` samples is drawn decimated
        (:class:`SeriesDecimator`: every bucket's extremes kept), and the figure says so
        under its title: "N samples, shown decimated to K".
    """
    capacity, labels, title, go = _results_figure(results, title, capacity, labels)
    chosen = _kinds_with(results, score, kinds)
    label, factor = _score(score, capacity, labels)
    total = len(results) if total is None else check_integer("total", total, 0, 2**62)
    results = decimate_series(results, [f"{kind}_{score}" for kind in chosen])
    x = results["t"] if "t" in results else results["configuration"]
    figure = go.Figure()
    for kind in chosen:
        figure.add_trace(
            go.Scatter(
                x=x,
                y=factor * results[f"{kind}_{score}"],
                mode="lines",
                name=_name(kind, capacity, labels),
                line={"color": _color(kind, chosen)},
            )
        )
    figure.update_layout(
        title=title,
        xaxis_title="t [s]" if "t" in results else "sample",
        yaxis_title=label,
        template="plotly_white",
        hovermode="x unified",
    )
    if total > len(results):
        figure.add_annotation(
            text=html.escape(decimation_note(total, len(results))),
            xref="paper",
            yref="paper",
            x=0.0,
            y=1.0,
            yanchor="bottom",
            showarrow=False,
            font={"size": 11, "color": "#555555"},
        )
    return figure


def _breakable_headers(table: str) -> str:
    """Let long column names (``direction_error_mean``) wrap after each underscore.

    The HTML is pandas' (its text escaped), so the ``<wbr>`` tags added are the only markup.
    """
    head, separator, body = table.partition("</thead>")
    return re.sub(r"_(?=[^<>]*</th>)", "_<wbr>", head) + separator + body


class HtmlTable(str):
    """A table already written as HTML by polyell's own writers (escaped, in its box).

    ``format_comparison_table(..., "html")`` and ``format_limits_table(..., "html")`` give
    the same labels, units and percentages as the LaTeX and Markdown tables; wrapped in this
    class, :func:`write_report` places them as they are (any other string is plain text).
    """


def write_report(path: str | Path, title: str, sections: Sequence[tuple[str, Any]]) -> Path:
    """One self-contained HTML file: a title and sections of figures, tables or text.

    Parameters
    ----------
    path : str or Path
    title : str
    sections : sequence of (heading, content)
        ``content`` is a plotly figure, a pandas DataFrame (a table), an
        :class:`HtmlTable` (a table of polyell's writers) or a string (a paragraph of plain
        text).

    Returns
    -------
    Path
        The file, written atomically.  plotly's JavaScript is inlined once: the page makes
        no network request.  Tables wrap their long column names and, still wider than
        the page, scroll inside their own box: the page never scrolls sideways.
    """
    import pandas as pd

    if not isinstance(title, str):
        raise InputError(
            "title",
            "a str (the page's heading)",
            f"{type(title).__name__}",
            "pass the heading as text, e.g. 'Study 1'.",
        )
    if (
        isinstance(sections, str | bytes)
        or not isinstance(sections, Sequence)
        or not all(
            isinstance(item, tuple | list) and len(item) == 2 and isinstance(item[0], str)
            for item in sections
        )
    ):
        raise InputError(
            "sections",
            "a sequence of (heading, content) pairs, the heading a str",
            repr(sections)[:120],
            'e.g. [("sets", interactive_sets(comparison))].',
        )
    go = _plotly()
    for heading, content in sections:
        if not isinstance(content, go.Figure | pd.DataFrame | HtmlTable | str):
            raise InputError(
                f"sections[{heading!r}]",
                "a plotly figure, a pandas DataFrame, an HtmlTable or a str",
                type(content).__name__,
                "pass str(value) for a number, or leave the section out.",
            )
    parts: list[str] = []
    first = True
    for heading, content in sections:
        parts.append(f"<h2>{html.escape(heading)}</h2>")
        if isinstance(content, go.Figure):
            parts.append(
                content.to_html(
                    full_html=False,
                    include_plotlyjs=first,
                    include_mathjax=False,
                    config={"displaylogo": False},
                )
            )
            first = False
        elif isinstance(content, pd.DataFrame):
            table = content.to_html(float_format=lambda v: f"{v:.4g}", border=0)
            parts.append(f"<div class='table-box'>{_breakable_headers(table)}</div>")
        elif isinstance(content, HtmlTable):
            parts.append(f"<div class='table-box'>{content}</div>")
        else:
            parts.append(f"<p>{html.escape(str(content))}</p>")
    style = (
        "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;"
        "color:#222;box-sizing:border-box}"
        # a table wider than the page scrolls inside its own box, never the page
        ".table-box{max-width:100%;overflow-x:auto;margin-bottom:1em}"
        "table{border-collapse:collapse;font-size:0.85em}"
        "td,th{padding:0.2em 0.5em;text-align:right;border-bottom:1px solid #ddd}"
        "th{vertical-align:bottom}"
        "tbody th{text-align:left;min-width:8em}"
        ".js-plotly-plot,.plotly-graph-div{max-width:100%}"
    )
    page = (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{style}</style></head><body>"
        f"<h1>{html.escape(title)}</h1>{''.join(parts)}</body></html>\n"
    )
    return write_text_atomically(as_path("path", path), page)
