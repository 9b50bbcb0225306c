"""Property suite of the views (issue 33): a PolyellError or a valid figure, page or file.

:mod:`polyell.interactive` (plotly figures, the decimation of long series, the offline
report) and :mod:`polyell.figures` (matplotlib, Agg; called only: the figures are not
looked at) given results frames with NaN, infinite, constant or missing columns, wrong
types for every argument, and titles with markup.  A decimated series must keep each
curve's smallest and largest value; a figure's drawn data must be finite.  Every file goes
to a temporary folder.  Seeded (derandomized).
"""

from __future__ import annotations

import contextlib
import re
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell import figures, interactive

matplotlib.use("Agg")  # no window: the figures are only made

JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3, np.nan]
ARM = pe.robots.load("chiacchio2000")
ANALYSIS = pe.analyze(ARM.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), ARM.tau_max)
SINGULAR = pe.analyze(ARM.dynamics([np.pi / 6, 0.0, 0.0]), ARM.tau_max)
_rng = np.random.default_rng(3)
_Q = np.linalg.qr(_rng.normal(size=(4, 4)))[0]
SPATIAL = pe.analyze(
    pe.Dynamics(_rng.normal(size=(3, 4)), (_Q * [1.0, 2.0, 3.0, 4.0]) @ _Q.T, np.zeros(4)),
    np.full(4, 5.0),
)
COMPARISONS = {
    "planar": pe.compare(ANALYSIS, 16, samples=256),
    "singular": pe.compare(SINGULAR, 16, samples=256),
    "spatial": pe.compare(SPATIAL, 16, samples=256, outer=False),
}
RESULTS = pe.sweep(ARM, pe.grid((-1.0, 1.0, 4), (-1.0, 1.0, 3), (0.5, 0.5, 1)), directions=8)
SCORES = ["chiacchio_coverage", "yoshikawa_inscribed_scale", "chiacchio_volume"]


def outcome(call: Callable[[], Any], argument: str | None = None) -> Any:
    """The call's result, or None for a PolyellError (naming ``argument`` when given)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", pe.ProjectedInputWarning)
        try:
            return call()
        except pe.PolyellError as exn:
            if argument is not None and isinstance(exn, pe.InputError):
                assert argument in str(exn), (argument, str(exn))
            return None
        finally:
            plt.close("all")


@st.composite
def results_frames(draw: st.DrawFn) -> pd.DataFrame:
    """The sweep's frame with a score column broken: NaN, inf, constant, negative, text."""
    frame = RESULTS.copy()
    column = draw(st.sampled_from(SCORES))
    how = draw(
        st.sampled_from(["same", "nan", "all nan", "inf", "constant", "huge", "text", "drop"])
    )
    values = frame[column].to_numpy(dtype=float, copy=True)
    if how == "nan":
        values[draw(st.integers(0, len(values) - 1))] = np.nan
    elif how == "all nan":
        values[:] = np.nan
    elif how == "inf":
        values[draw(st.integers(0, len(values) - 1))] = np.inf
    elif how == "constant":
        values[:] = 0.5
    elif how == "huge":
        values *= 1e300
    if how == "text":
        frame[column] = frame[column].astype(object)
        frame.loc[0, column] = "abc"
    elif how == "drop":
        frame = frame.drop(columns=[column])
    else:
        frame[column] = values
    frame.attrs.update(RESULTS.attrs)
    return frame


def finite_plotly(figure: Any) -> None:
    """The figure serialises (what a page embeds): no number plotly cannot write.

    Plotly writes NaN and infinity as null, a gap in the drawing; drawn coordinates of
    scatter traces (the sets' outlines) are finite.
    """
    import json

    json.loads(figure.to_json())
    for trace in figure.data:
        if trace.type in ("scatter", "scatter3d"):
            for name in ("x", "y", "z"):
                values = getattr(trace, name, None)
                if values is not None and trace.name and not trace.name.startswith("centre"):
                    numbers = np.asarray([v for v in values if v is not None], dtype=float)
                    assert not np.isinf(numbers).any(), (trace.name, name)


# --- polyell.interactive


@settings(max_examples=20)
@given(
    which=st.sampled_from(sorted(COMPARISONS)),
    kinds=st.sampled_from(
        [None, ["chiacchio"], ["mvie", "yoshikawa"], ["nothing"], "chiacchio", []]
    ),
    title=st.sampled_from([None, "sets <b>bold</b> & $x$", "", 5, "two\nlines"]),
)
def test_interactive_sets(which, kinds, title):
    figure = outcome(
        lambda: interactive.interactive_sets(COMPARISONS[which], kinds, title=title), None
    )
    if figure is None:
        return
    assert len(figure.data) >= 2  # the polytope and at least one ellipsoid (and the centre)
    finite_plotly(figure)
    if isinstance(title, str) and "<b>" in title:
        assert "<b>bold</b>" not in str(figure.layout.title.text)  # no live markup


@settings(max_examples=30)
@given(
    frame=results_frames(),
    columns=st.sampled_from([SCORES[0], SCORES[:2], [], "q1", "nothing", 5]),
    axes=st.sampled_from([("q1", "q2"), ("q2", "q1"), ("q1", "q1"), ("q3", "q1"), ("x", "q2")]),
    capacity=st.sampled_from(["acceleration", "force", "speed", None]),
)
def test_interactive_map(frame, columns, axes, capacity):
    figure = outcome(
        lambda: interactive.interactive_map(frame, columns, *axes, capacity=capacity), None
    )
    if figure is not None:
        assert len(figure.data) >= 1
        finite_plotly(figure)


@settings(max_examples=30)
@given(
    frame=results_frames(),
    score=st.sampled_from(["coverage", "inscribed_scale", "volume", "nothing", 5]),
    kinds=st.sampled_from(
        [None, ["chiacchio"], ["chiacchio", "yoshikawa"], ["nothing"], "chiacchio"]
    ),
    function=st.sampled_from(["histogram", "series"]),
)
def test_interactive_histogram_and_series(frame, score, kinds, function):
    call = {
        "histogram": lambda: interactive.interactive_histogram(frame, score, kinds),
        "series": lambda: interactive.interactive_series(frame, score, kinds),
    }[function]
    figure = outcome(call, None)
    if figure is not None:
        finite_plotly(figure)


@settings(max_examples=40)
@given(
    length=st.integers(0, 400),
    buckets=st.sampled_from([1, 2, 7, 50, 1000, 0, -1, 2.5, None]),
    seed=st.integers(0, 2**16),
    holes=st.booleans(),
)
def test_decimated_series_keep_every_curves_extremes(length, buckets, seed, holes):
    rng = np.random.default_rng(seed)
    frame = pd.DataFrame({"a": rng.normal(size=length), "b": np.cumsum(rng.normal(size=length))})
    if holes and length:
        frame.loc[rng.integers(0, length, 3), "a"] = np.nan
    shown = outcome(lambda: interactive.decimate_series(frame, ["a", "b"], buckets), "buckets")
    if shown is None:
        assert not (isinstance(buckets, int) and buckets >= 1 and not isinstance(buckets, bool))
        return
    assert len(shown) <= len(frame)
    for column in ("a", "b"):  # the rows shown are rows of the frame, the extremes among them
        values = frame[column].dropna()
        if len(values):
            assert shown[column].max() == values.max() and shown[column].min() == values.min()
        assert set(shown[column].dropna()) <= set(values)
    note = interactive.decimation_note(len(frame), len(shown))
    assert f"{len(frame):,} samples" in note


@given(
    total=st.sampled_from([0, 5, 10**6, -1, 2.5, None, "x", True]),
    shown=st.sampled_from([0, 5, -1, 2.5, None]),
)
def test_decimation_note_refuses_what_is_no_count(total, shown):
    note = outcome(lambda: interactive.decimation_note(total, shown), None)
    counts = [v for v in (total, shown) if isinstance(v, int) and not isinstance(v, bool)]
    assert (note is not None) == (len(counts) == 2 and min(counts) >= 0)


@settings(max_examples=25)
@given(
    title=st.sampled_from(["Report", "<script>alert(1)</script>", "a & b", "", None, 5]),
    sections=st.sampled_from(["figure", "table", "empty", "junk", "text", "bad pair"]),
    name=st.sampled_from(["r.html", "sub/r.html", "", None]),
)
def test_write_report_writes_a_page_or_refuses(tmp_path_factory, title, sections, name):
    path = tmp_path_factory.mktemp("report")
    figure = interactive.interactive_sets(COMPARISONS["planar"], ["chiacchio"])
    content: Any = {
        "figure": [("sets", figure)],
        "table": [("table", interactive.HtmlTable("<table><tr><td>1</td></tr></table>"))],
        "empty": [],
        "junk": 5,
        "text": [("text", "<b>not markup</b>")],
        "bad pair": [("a",)],
    }[sections]
    target = None if name is None else (path / name if name else "")
    with contextlib.chdir(path):
        page = outcome(lambda: interactive.write_report(target, title, content), None)
    if page is None:
        return
    text = Path(page).read_text(encoding="utf-8")
    assert text.lstrip().lower().startswith("<!doctype html")
    assert "<script>alert(1)</script>" not in text  # a title is text, not markup
    assert "<b>not markup</b>" not in text
    assert Path(page).resolve().is_relative_to(path.resolve())


# --- polyell.figures (called only: the figures are not looked at)


@settings(max_examples=25)
@given(
    which=st.sampled_from(sorted(COMPARISONS)),
    function=st.sampled_from(["plot_sets", "plot_sets_3d", "plot_directional_limits"]),
    kinds=st.sampled_from([None, ["chiacchio"], ["nothing"], "chiacchio", []]),
    title=st.sampled_from([None, "a $x$ & b", 5, ""]),
    labels=st.sampled_from([None, "chiacchio2000", {"chiacchio": "new"}, "nothing", 5]),
)
def test_set_figures(which, function, kinds, title, labels):
    analysis = COMPARISONS[which].analysis
    figure = outcome(
        lambda: getattr(figures, function)(analysis, kinds=kinds, title=title, labels=labels),
        None,
    )
    if figure is not None:
        assert len(figure.axes) >= 1
        assert not isinstance(title, int)  # a title of no text is refused
        dim = analysis.polytope.ambient_dim
        assert function != "plot_sets_3d" or dim == 3
        assert function == "plot_sets_3d" or dim == 2


@settings(max_examples=25)
@given(
    shape=st.sampled_from(["grid", "flat", "wrong", "nan", "inf", "constant"]),
    limits=st.sampled_from([None, (0.0, 1.0), (1.0, 0.0), (np.nan, 1.0)]),
)
def test_score_map(shape, limits):
    x, y = np.linspace(0, 1, 4), np.linspace(-1, 1, 3)
    values = np.random.default_rng(0).uniform(0, 1, (3, 4))
    if shape == "flat":
        values = values.ravel()
    elif shape == "wrong":
        values = values.T
    elif shape == "nan":
        values[1, 1] = np.nan
    elif shape == "inf":
        values[0, 0] = np.inf
    elif shape == "constant":
        values[:] = 1.0
    figure = outcome(
        lambda: figures.plot_score_map(
            values, x, y, xlabel="q3", ylabel="q2", label="coverage", limits=limits
        ),
        None,
    )
    if figure is not None:
        assert shape != "wrong" and len(figure.axes) >= 1


@settings(max_examples=30)
@given(
    frame=results_frames(),
    function=st.sampled_from(["plot_score_histogram", "plot_score_series"]),
    score=st.sampled_from(["coverage", "inscribed_scale", "volume", "nothing"]),
    kinds=st.sampled_from([("chiacchio", "yoshikawa"), ("chiacchio",), ("nothing",), ()]),
    bins=st.sampled_from([30, 1, 0]),
)
def test_score_histogram_and_series(frame, function, score, kinds, bins):
    arguments: dict[str, Any] = {"kinds": kinds}
    if function == "plot_score_histogram":
        arguments["bins"] = bins
    figure = outcome(lambda: getattr(figures, function)(frame, score, **arguments), None)
    if figure is not None:
        assert len(figure.axes) >= 1 and score != "nothing"


@settings(max_examples=20)
@given(
    formats=st.sampled_from([None, ["png"], ["pdf", "svg"], ["bmp"], "png", [], [5]]),
    dpi=st.sampled_from([300, 20, 0, -1, 10**6]),
    stem=st.sampled_from(["figure", "sub/figure", None]),
)
def test_save_figure(tmp_path_factory, formats, dpi, stem):
    path = tmp_path_factory.mktemp("figure")
    figure = figures.plot_sets(ANALYSIS)
    target = None if stem is None else str(path / stem)
    with contextlib.chdir(path):
        written = outcome(lambda: figures.save_figure(figure, target, formats, dpi), None)
    if written is not None:
        assert written and all(Path(p).is_file() and Path(p).stat().st_size > 0 for p in written)
        assert all(Path(p).resolve().is_relative_to(path.resolve()) for p in written)


@given(value=st.sampled_from([None, "x", b"x", {}, True, object(), -3, np.nan]))
def test_figure_functions_refuse_junk(value):
    """Each of these figure arguments replaced by junk: a refusal."""
    calls = {
        "plot_sets_3d view": lambda v: figures.plot_sets_3d(SPATIAL, view=v),
        "plot_directional_limits": lambda v: figures.plot_directional_limits(
            ANALYSIS, directions=v
        ),
        "plot_tangent_limits": lambda v: figures.plot_tangent_limits(v),
        "plot_posture_indices": lambda v: figures.plot_posture_indices(v, v),
        "ellipsoid_outline": lambda v: figures.ellipsoid_outline(v),
        "save_figure": lambda v: figures.save_figure(v, "never"),
        "plot_sets unit": lambda v: figures.plot_sets(ANALYSIS, unit=v),
        "plot_sets ax": lambda v: figures.plot_sets(ANALYSIS, v),
        "plot_sets mvie": lambda v: figures.plot_sets(ANALYSIS, mvie=v),
        "ellipsoid_outline view": lambda v: figures.ellipsoid_outline(
            SPATIAL.ellipsoid("chiacchio"), v
        ),
        "plot_score_map limits": lambda v: figures.plot_score_map(
            np.ones((2, 2)), [0, 1], [0, 1], xlabel="a", ylabel="b", label="c", limits=v
        ),
        "plot_score_histogram bins": lambda v: figures.plot_score_histogram(
            RESULTS, "coverage", bins=v
        ),
        "save_figure dpi": lambda v: _in_a_temporary_folder(
            lambda: figures.save_figure(figures.plot_sets(ANALYSIS), "f", ["png"], v)
        ),
    }
    for name, call in calls.items():
        result = outcome(lambda c=call: c(value), None)
        if result is not None:  # only "no value" or text is an accepted value
            assert value is None or (isinstance(value, str) and name.endswith("unit")), name


def _frame_with(column: str, value: Any) -> pd.DataFrame:
    frame = RESULTS.copy()
    frame[column] = frame[column].astype(object)
    frame.loc[0, column] = value
    return frame


def _in_a_temporary_folder(call: Callable[[], Any]) -> Any:
    with tempfile.TemporaryDirectory() as folder, contextlib.chdir(folder):
        return call()


def _all_nan(column: str) -> pd.DataFrame:
    frame = RESULTS.copy()
    frame[column] = np.nan
    return frame


#: Defects of polyell/figures.py this suite found, fixed: each was a raw exception (or a
#: numpy warning, or an argument silently ignored) where an InputError naming the argument
#: is due.  Case: (the argument the message names, the call).
FIGURE_DEFECTS: dict[str, tuple[str, Callable[[], Any]]] = {
    "plot_sets kinds=5": ("kinds", lambda: figures.plot_sets(ANALYSIS, kinds=5)),
    "plot_sets ax='x'": ("ax", lambda: figures.plot_sets(ANALYSIS, "x")),
    "plot_sets extra='x'": ("extra", lambda: figures.plot_sets(ANALYSIS, extra="x")),
    "plot_sets extra=1+2j": ("extra", lambda: figures.plot_sets(ANALYSIS, extra=1 + 2j)),
    "plot_score_map limits='x'": (
        "limits",
        lambda: figures.plot_score_map(
            np.ones((2, 2)), [0, 1], [0, 1], xlabel="a", ylabel="b", label="c", limits="x"
        ),
    ),
    "plot_score_map empty": (
        "values",
        lambda: figures.plot_score_map(np.zeros((0, 0)), [], [], xlabel="a", ylabel="b", label="c"),
    ),
    "plot_score_histogram bins=-1": (
        "bins",
        lambda: figures.plot_score_histogram(RESULTS, "coverage", bins=-1),
    ),
    "plot_score_histogram bins=2.5": (
        "bins",
        lambda: figures.plot_score_histogram(RESULTS, "coverage", bins=2.5),
    ),
    "plot_score_histogram text cell": (
        "results['chiacchio_coverage']",
        lambda: figures.plot_score_histogram(_frame_with("chiacchio_coverage", "abc"), "coverage"),
    ),
    "plot_score_series text cell": (
        "results['chiacchio_coverage']",
        lambda: figures.plot_score_series(_frame_with("chiacchio_coverage", "abc"), "coverage"),
    ),
    "ellipsoid_outline view=None": (
        "view",
        lambda: figures.ellipsoid_outline(SPATIAL.ellipsoid("chiacchio"), None),
    ),
    "ellipsoid_outline view=[]": (
        "view",
        lambda: figures.ellipsoid_outline(SPATIAL.ellipsoid("chiacchio"), []),
    ),
    "save_figure dpi=2.5": (  # was a FreeType error: no text at 2.5 dots per inch
        "dpi",
        lambda: figures.save_figure(figures.plot_sets(ANALYSIS), "f", ["png"], 2.5),
    ),
    "save_figure stem=''": (  # wrote hidden files .pdf and .png into the current folder
        "stem",
        lambda: figures.save_figure(figures.plot_sets(ANALYSIS), ""),
    ),
    "plot_sets mvie='x' (ignored, not refused)": (
        "mvie",
        lambda: figures.plot_sets(ANALYSIS, mvie="x"),
    ),
}


@pytest.mark.parametrize("case", sorted(FIGURE_DEFECTS))
def test_figure_defects(case):
    """Called in a temporary folder: a refusal naming the argument, and no file written."""
    argument, call = FIGURE_DEFECTS[case]
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as folder:
        warnings.simplefilter("error")
        try:
            with contextlib.chdir(folder), pytest.raises(pe.InputError) as refusal:
                call()
            assert refusal.value.argument == argument
            assert re.search(r"expected .+, got .+", str(refusal.value))
            assert not list(Path(folder).iterdir())  # nothing written, hidden or not
        finally:
            plt.close("all")


def test_histogram_of_a_score_undefined_everywhere_says_so():
    """An all-NaN column (a set undefined at every configuration): a figure, no numpy warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            figure = figures.plot_score_histogram(_all_nan("chiacchio_coverage"), "coverage")
            legend = [text.get_text() for text in figure.axes[0].get_legend().get_texts()]
        finally:
            plt.close("all")
    assert legend[0] == "Chiacchio (no finite value)"
    assert legend[1].startswith("Yoshikawa (median ")
