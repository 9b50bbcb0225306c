"""Interactive views (issue 14): plotly figures of the sets, maps and histograms, and a
self-contained HTML report checked in a real headless browser (no network request, no
console error, the sets drawn)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from browser import coloured_share, load
from polyell.interactive import (
    HISTOGRAM_BINS,
    interactive_histogram,
    interactive_map,
    interactive_sets,
    write_report,
)
from reference import PAPER_ARM, PAPER_TAU_MAX, paper_analysis

REDUNDANT = np.array([np.pi / 2, -np.pi / 2, -np.pi / 2])


def test_2d_sets_trace_the_exact_polytope_and_every_ellipsoid():
    cmp = pe.compare(
        paper_analysis(REDUNDANT), 64, candidates=[pe.Candidate("w", weighting=np.eye(3) * 2)]
    )
    figure = interactive_sets(cmp)
    names = [trace.name for trace in figure.data]
    assert names[0].startswith("polytope")
    assert len(figure.data) == 1 + 5 + 1  # polytope, 4 built-ins and the candidate, centre
    polygon = np.column_stack([figure.data[0].x, figure.data[0].y])
    np.testing.assert_allclose(polygon[:-1], cmp.analysis.polytope.vertices)
    for trace, kind in zip(figure.data[1:6], cmp.kinds, strict=True):  # on each boundary
        E = cmp.ellipsoid(kind)
        points = np.column_stack([trace.x, trace.y])
        norms = np.linalg.norm(((points - E.center) @ E.axes) / E.semi_axes, axis=1)
        np.testing.assert_allclose(norms, 1.0, rtol=1e-9)
        assert f"{100 * cmp[kind].coverage:.4g}" in trace.text


def test_3d_sets_are_meshes_on_the_boundaries():
    robot = pe.robots.load("panda")
    cmp = pe.compare(pe.analyze(robot.dynamics([0, -0.5, 0, -2, 0, 1.6, 0.8]), robot.tau_max), 64)
    figure = interactive_sets(cmp)
    P = cmp.analysis.polytope
    hull = figure.data[0]
    vertices = np.column_stack([hull.x, hull.y, hull.z])
    assert np.all(vertices @ P.A.T <= P.b + 1e-9)  # the hull's points are P's vertices
    for trace in [t for t in figure.data if t.type == "mesh3d" and t.legendgroup != "polytope"]:
        kind = next(k for k in cmp.kinds if pe.comparison.tables.ellipsoid_label(k) == trace.name)
        E = cmp.ellipsoid(kind)
        points = np.column_stack([trace.x, trace.y, trace.z])
        norms = np.linalg.norm(((points - E.center) @ E.axes) / E.semi_axes, axis=1)
        np.testing.assert_allclose(norms, 1.0, rtol=1e-9)


def test_singular_sets_are_segments():
    cmp = pe.compare(pe.analyze(PAPER_ARM.dynamics([np.pi / 6, 0, 0]), PAPER_TAU_MAX), 16)
    figure = interactive_sets(cmp)
    assert all(len(trace.x) == 2 for trace in figure.data[:-1])  # the classic one is absent
    assert "Yoshikawa" not in " ".join(trace.name for trace in figure.data)


def test_map_and_histogram_hover_every_score():
    grid = pe.grid(np.pi / 2, (-np.pi, np.pi, 5), (-np.pi, np.pi, 4))
    results = pe.sweep(PAPER_ARM, grid, PAPER_TAU_MAX, directions=16)
    figure = interactive_map(results, "chiacchio_coverage", "q3", "q2")
    heat = figure.data[0]
    assert np.asarray(heat.z).shape == (5, 4)
    assert "chiacchio_inscribed_scale" in heat.hovertemplate
    row = results.sort_values(["q2", "q3"]).iloc[6]
    assert heat.z[1][2] == pytest.approx(100 * row["chiacchio_coverage"], nan_ok=True)
    both = interactive_map(results, ["chiacchio_coverage", "yoshikawa_coverage"], "q3", "q2")
    menu = both.layout.updatemenus[0].buttons
    assert [b.label for b in menu] == [
        "Chiacchio: coverage [%]",
        "Yoshikawa: coverage [%]",
    ]
    assert "yoshikawa_inscribed_scale" in menu[1].args[0]["hovertemplate"][0]
    assert "chiacchio_inscribed_scale" not in menu[1].args[0]["hovertemplate"][0]
    shared = np.nanmax(100 * results[["chiacchio_coverage", "yoshikawa_coverage"]].to_numpy())
    assert menu[0].args[0]["zmax"][0] == menu[1].args[0]["zmax"][0] == pytest.approx(shared)
    histogram = interactive_histogram(results, "coverage")
    assert [t.name for t in histogram.data][:2] == ["Chiacchio", "Yoshikawa"]
    with pytest.raises(pe.InputError, match="full grid"):
        interactive_map(results.iloc[:-1], "chiacchio_coverage", "q3", "q2")


def test_report_loads_offline_without_errors_and_draws_the_sets(tmp_path):
    cmp = pe.compare(paper_analysis(REDUNDANT), 64)
    robot = pe.robots.load("panda")
    cmp3 = pe.compare(pe.analyze(robot.dynamics([0, -0.5, 0, -2, 0, 1.6, 0.8]), robot.tau_max), 64)
    page = write_report(
        tmp_path / "report.html",
        "polyell report",
        [
            ("redundant configuration", interactive_sets(cmp)),
            ("Panda", interactive_sets(cmp3)),
            ("scores", cmp.to_frame()),
        ],
    )
    visit = load(
        page,
        tmp_path / "report.png",
        {
            "plots": "document.querySelectorAll('.js-plotly-plot').length",
            "traces": "[...document.querySelectorAll('.js-plotly-plot')].map(p => p.data.length)",
            "paths": "document.querySelectorAll('.js-plotly-plot path.js-line').length",
        },
        wait_for=".js-plotly-plot .main-svg",
    )
    assert visit.requests == []  # nothing fetched: plotly is inlined
    assert visit.errors == []
    assert visit.values["plots"] == 2 and visit.values["traces"] == [6, 8]
    assert visit.values["paths"] >= 5  # the 2-D polygon and four ellipses, drawn
    assert coloured_share(visit.screenshot) > 0.002  # coloured curves on the page


GRID_STUDY = """
title = "grid"
[robot]
library = "chiacchio2000"
[grid]
q1 = "pi/2"
q2 = { start = "-pi", stop = "pi", num = 7 }
q3 = { start = "-pi", stop = "pi", num = 6 }
[compare]
directions = 16
[[candidates]]
name = "heavy_wrist"
weighting = [1, 1, 4]
[output]
formats = ["html"]
maps = ["chiacchio_coverage", "heavy_wrist_mvie_ratio"]
histograms = ["coverage"]
"""


def test_study_html_report_works_offline_in_a_browser(tmp_path):
    from polyell.studies import load_study, run_study

    path = tmp_path / "grid.toml"
    path.write_text(GRID_STUDY)
    written = run_study(load_study(path), tmp_path / "out")
    names = {p.name for p in written}
    assert "report.html" in names and not any(n.endswith((".png", ".pdf")) for n in names)
    visit = load(
        tmp_path / "out" / "report.html",
        tmp_path / "shot.png",
        {
            "plots": "document.querySelectorAll('.js-plotly-plot').length",
            "heatmaps": "[...document.querySelectorAll('.js-plotly-plot')]"
            ".filter(p => p.data[0].type === 'heatmap').length",
            "tables": "document.querySelectorAll('table').length",
        },
        wait_for=".js-plotly-plot .main-svg",
    )
    assert visit.requests == [] and visit.errors == []
    assert visit.values == {"plots": 2, "heatmaps": 1, "tables": 1}  # maps share a menu
    assert coloured_share(visit.screenshot) > 0.02  # the heat map's colours on screen


# --- long series, decimated (issue 20) ---------------------------------------------------


def long_series(samples: int, seed: int = 20):
    import pandas as pd

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, samples))
    frame = pd.DataFrame(
        {
            "configuration": np.arange(samples),
            "t": t,
            "chiacchio_coverage": rng.uniform(0.2, 0.9, samples),
            "yoshikawa_coverage": np.sin(t / 50.0),
        }
    )
    frame.loc[rng.choice(samples, 5, replace=False), "yoshikawa_coverage"] = np.nan
    return frame


def test_decimation_keeps_every_bucket_extreme_and_gap():
    from polyell.interactive import decimate_series

    frame = long_series(123_457)
    traces = ["chiacchio_coverage", "yoshikawa_coverage"]
    kept = decimate_series(frame, traces, buckets=500)
    assert len(kept) <= 3 * len(traces) * 500
    assert kept["configuration"].is_monotonic_increasing
    bucket = -(-len(frame) // 500)
    for name in traces:
        values = frame[name].to_numpy()
        groups = np.arange(len(values)) // bucket
        shown = kept.set_index("configuration")[name]
        for g in np.unique(groups)[::37]:  # every bucket's min and max are drawn
            inside = values[groups == g]
            rows = kept["configuration"].to_numpy() // bucket == g
            assert np.nanmin(inside) == np.nanmin(kept[name].to_numpy()[rows])
            assert np.nanmax(inside) == np.nanmax(kept[name].to_numpy()[rows])
        gaps = np.flatnonzero(np.isnan(values))  # each NaN's bucket shows a gap
        assert all(np.isnan(shown[shown.index // bucket == k // bucket]).any() for k in gaps)
    # a series in parts decimates exactly as a whole one (the runner reads parts)
    from polyell.interactive import SeriesDecimator

    decimator = SeriesDecimator(len(frame), traces, buckets=500)
    for start in range(0, len(frame), 7_919):
        decimator.add(frame.iloc[start : start + 7_919].reset_index(drop=True))
    parts = decimator.result()
    np.testing.assert_array_equal(parts["configuration"], kept["configuration"])


def test_short_series_are_drawn_whole():
    from polyell.interactive import DECIMATION_BUCKETS, decimate_series

    frame = long_series(2 * DECIMATION_BUCKETS)
    kept = decimate_series(frame, ["chiacchio_coverage"])
    assert len(kept) == len(frame)


def test_long_series_figures_are_bounded_and_say_so():
    from polyell.interactive import DECIMATION_BUCKETS, interactive_series

    sizes = []
    for samples in (20_000, 200_000):
        figure = interactive_series(long_series(samples), "coverage")
        for trace in figure.data:
            assert len(trace.x) <= 3 * 2 * DECIMATION_BUCKETS
        notes = [a.text for a in figure.layout.annotations]
        assert notes and notes[0].startswith(f"{samples:,} samples, shown decimated to")
        sizes.append(len(figure.to_json()))
    # the same number of points at most; each differs in at most two 25-character numbers
    assert abs(sizes[1] - sizes[0]) <= 3 * 2 * DECIMATION_BUCKETS * 2 * 2 * 25


@pytest.mark.parametrize("count", [50, 200_000])
def test_histogram_counts_every_finite_value_on_shared_bins_in_bounded_size(count):
    rng = np.random.default_rng(3)
    results = pd.DataFrame(
        {
            "chiacchio_coverage": rng.uniform(0.2, 0.9, count),
            "yoshikawa_coverage": np.where(rng.uniform(size=count) < 0.1, np.nan, 0.5),
        }
    )
    figure = interactive_histogram(results, "coverage")
    new, classic = figure.data
    assert np.array_equal(new.x, classic.x) and np.array_equal(new.width, classic.width)
    assert len(new.x) <= HISTOGRAM_BINS
    assert sum(new.y) == count  # every value in a bin, once
    assert sum(classic.y) == np.isfinite(results["yoshikawa_coverage"]).sum()
    edges = np.append(new.x - new.width / 2, new.x[-1] + new.width[-1] / 2)
    expected, _ = np.histogram(100 * results["chiacchio_coverage"], bins=edges)
    assert np.array_equal(new.y, expected)
    assert len(figure.to_json()) < 40_000  # bins, not values: the same size for any count


# --- issue 24: reports that fit the page, 3-D scenes that stay legible -------------------

PANDA_POSTURES = {
    "ready": [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785],
    "folded": [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8],
}
#: The start of plotly's bundle, once per copy inlined.
PLOTLY_BUNDLE = "* plotly.js v"


def panda_comparisons():
    robot = pe.robots.load("panda")
    return {
        name: pe.compare(pe.analyze(robot.dynamics(q), robot.tau_max), 64)
        for name, q in PANDA_POSTURES.items()
    }


def wide_table(columns: int = 24) -> pd.DataFrame:
    rng = np.random.default_rng(24)
    names = [f"direction_error_{i}_of_every_ellipsoid" for i in range(columns)]
    return pd.DataFrame(
        rng.uniform(-1e6, 1e6, (4, columns)),
        columns=names,
        index=[f"posture {i}: Chiacchio" for i in range(4)],
    )


@pytest.mark.parametrize("width", [1100, 720])
def test_report_tables_fit_the_page_and_plotly_is_inlined_once(tmp_path, width):
    comparisons = panda_comparisons()
    sections = [(name, interactive_sets(cmp)) for name, cmp in comparisons.items()]
    sections += [("a wide table", wide_table()), ("scores", comparisons["ready"].to_frame())]
    sections += [
        ("histogram", interactive_histogram(pd.DataFrame({"a_coverage": [0.1, 0.5]}), "coverage"))
    ]
    page = write_report(tmp_path / "report.html", "fit", sections)
    text = page.read_text()
    assert text.count(PLOTLY_BUNDLE) == 1  # three figures, one copy of plotly
    visit = load(
        page,
        tmp_path / "fit.png",
        {
            "page": "[document.documentElement.scrollWidth, document.documentElement.clientWidth]",
            "boxes": "[...document.querySelectorAll('.table-box')].map(b => {"
            " const r = b.getBoundingClientRect(), body = document.body.getBoundingClientRect();"
            " return [r.left >= body.left - 0.5, r.right <= body.right + 0.5,"
            " b.clientWidth, b.scrollWidth]})",
            "plots": "[...document.querySelectorAll('.js-plotly-plot')].map(p => "
            "p.getBoundingClientRect().right <= document.documentElement.clientWidth)",
            "header_lines": "[...document.querySelectorAll('thead th')].map(th => "
            "Math.round(th.getBoundingClientRect().height))",
        },
        wait_for=".js-plotly-plot .main-svg",
        viewport=(width, 900),
    )
    assert visit.requests == [] and visit.errors == []
    scroll_width, client_width = visit.values["page"]
    assert scroll_width <= client_width  # the page never scrolls sideways
    boxes = visit.values["boxes"]
    assert len(boxes) == 2 and all(left and right for left, right, *_ in boxes)
    wide_box = boxes[0]
    assert wide_box[3] > wide_box[2]  # the wide table scrolls inside its own box
    assert all(visit.values["plots"])
    assert max(visit.values["header_lines"]) > min(visit.values["header_lines"])  # wrapped


def scene_pixels(page, index: int, path):
    """A screenshot of the 3-D scene of plot ``index``, as an (h, w, 3) float array."""
    import matplotlib.image

    box = page.evaluate(
        f"(() => {{ const gd = document.querySelectorAll('.js-plotly-plot')[{index}];"
        " const r = gd._fullLayout.scene._scene.container.getBoundingClientRect();"
        " return {x: r.left + window.scrollX, y: r.top + window.scrollY,"
        " width: r.width, height: r.height}; })()"
    )
    page.screenshot(path=str(path), clip=box, full_page=True)
    return matplotlib.image.imread(path)[..., :3]


def dark(image) -> float:
    """Share of dark, grey pixels: the polytope's edges (#222) through the ellipsoids."""
    luminance = image.mean(axis=-1)
    return float(((luminance < 0.3) & (image.max(axis=-1) - image.min(axis=-1) < 0.2)).mean())


def test_3d_scenes_show_the_polytope_through_the_ellipsoids_with_whole_axis_titles(tmp_path):
    from browser import session

    comparisons = panda_comparisons()
    page_path = write_report(
        tmp_path / "scenes.html",
        "scenes",
        [(name, interactive_sets(cmp)) for name, cmp in comparisons.items()],
    )
    with session(page_path, ".js-plotly-plot .main-svg") as (page, visit):
        for index in range(len(comparisons)):
            shown = scene_pixels(page, index, tmp_path / f"scene{index}.png")
            # nothing is cut at the scene's edges: its outer frame is background only
            ring = np.concatenate(
                [
                    shown[:4].reshape(-1, 3),
                    shown[-4:].reshape(-1, 3),
                    shown[:, :4].reshape(-1, 3),
                    shown[:, -4:].reshape(-1, 3),
                ]
            )
            assert ring.mean(axis=-1).min() > 0.8, f"scene {index}: drawn up to its edge"
            # the axis titles are drawn whole inside the scene (the camera sees them all)
            titles = page.evaluate(
                f"(() => {{ const s = document.querySelectorAll('.js-plotly-plot')[{index}]"
                "._fullLayout.scene; return [s.xaxis.title.text, s.yaxis.title.text,"
                " s.zaxis.title.text]; })()"
            )
            assert all(t.endswith("[m/s^2]") for t in titles)
            # the polytope is visible through every ellipsoid: hiding its group takes its
            # dark edges away
            page.evaluate(
                f"(() => {{ const gd = document.querySelectorAll('.js-plotly-plot')[{index}];"
                " const group = gd.data.map((t, i) => t.legendgroup === 'polytope' ? i : -1)"
                ".filter(i => i >= 0); return Plotly.restyle(gd, {visible: 'legendonly'}, group);"
                " })()"
            )
            page.wait_for_timeout(300)
            hidden = scene_pixels(page, index, tmp_path / f"scene{index}_hidden.png")
            assert dark(shown) > dark(hidden) + 0.002, (dark(shown), dark(hidden))
        # each ellipsoid is toggled by its legend entry
        plot = page.locator(".js-plotly-plot").nth(0)
        names = page.evaluate(
            "document.querySelectorAll('.js-plotly-plot')[0].data.map(t => t.name)"
        )
        outer = names.index("outer (min. volume)")
        plot.locator(".legendtext", has_text="outer (min. volume)").click(force=True)
        page.wait_for_timeout(700)  # plotly waits to tell a click from a double click
        state = f"document.querySelectorAll('.js-plotly-plot')[0].data[{outer}].visible"
        assert page.evaluate(state) == "legendonly"
        plot.locator(".legendtext", has_text="outer (min. volume)").click(force=True)
        page.wait_for_timeout(700)
        assert page.evaluate(state) is True
    assert visit.requests == [] and visit.errors == []


def test_3d_ellipsoids_are_translucent_and_the_polytope_is_one_legend_group():
    cmp = panda_comparisons()["ready"]
    figure = interactive_sets(cmp)
    polytope = [t for t in figure.data if t.legendgroup == "polytope"]
    assert [t.type for t in polytope] == ["mesh3d", "scatter3d", "scatter3d"]
    assert sum(bool(t.showlegend) for t in polytope) == 1  # one entry toggles all three
    edges = polytope[1]
    P = cmp.analysis.polytope
    path = np.column_stack([edges.x, edges.y, edges.z]).astype(float)
    segments = path.reshape(-1, 3, 3)  # two ends and a break per edge
    assert np.all(np.isnan(segments[:, 2]))
    ends = segments[:, :2].reshape(-1, 3)
    assert np.all(ends @ P.A.T <= P.b + 1e-9 * np.abs(P.b).max())  # on P, at its vertices
    meshes = [t for t in figure.data if t.type == "mesh3d" and t.legendgroup != "polytope"]
    assert len(meshes) == 4
    assert all(t.opacity < polytope[0].opacity < 1 for t in meshes)
    assert len({t.legendgroup for t in meshes}) == 4  # each its own legend entry


PANDA_STUDY = """
title = "Panda, three postures"
[robot]
library = "panda"
[[points]]
name = "ready"
q = [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
direction = [1, 0, 0]
[[points]]
name = "stretched"
q = [0, 0.3, 0, -1.2, 0, 1.5, 0.8]
direction = [0, 0, 1]
[[points]]
name = "folded"
q = [0, -0.5, 0, -2.0, 0, 1.6, 0.8]
direction = [0, 1, 0]
[compare]
directions = 64
[output]
formats = ["html"]
"""


def test_panda_study_report_fits_the_page(tmp_path):
    from polyell.studies import load_study, run_study

    path = tmp_path / "panda.toml"
    path.write_text(PANDA_STUDY)
    run_study(load_study(path), tmp_path / "out")
    page = tmp_path / "out" / "report.html"
    assert page.read_text().count(PLOTLY_BUNDLE) == 1
    visit = load(
        page,
        tmp_path / "panda.png",
        {
            "page": "[document.documentElement.scrollWidth, document.documentElement.clientWidth]",
            "scenes": "[...document.querySelectorAll('.js-plotly-plot')]"
            ".filter(p => p._fullLayout.scene).length",
        },
        wait_for=".js-plotly-plot .main-svg",
    )
    assert visit.requests == [] and visit.errors == []
    assert visit.values["scenes"] == 3
    scroll_width, client_width = visit.values["page"]
    assert scroll_width <= client_width


@pytest.mark.parametrize(
    ("q", "scale", "got"),
    [([0.3, 0.6, 0.9], 1e-3, "an empty set"), ([0.0, 0.0, 0.0], 1.0, "unbounded")],
)
def test_a_set_with_nothing_to_draw_is_refused_in_2d_as_in_3d(q, scale, got):
    """An empty force set (torques too weak to hold the arm) and an unbounded one (the
    stretched arm) have no drawing: refused by name, as plot_sets and 3-D sets are (an
    empty 2-D set drew its ellipsoids alone)."""
    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics(q), scale * np.asarray(arm.tau_max), capacity="force")
    comparison = pe.compare(analysis, mvie=False, outer=False)
    with pytest.raises(pe.InputError, match=f"comparison: .*{got}"):
        interactive_sets(comparison)
