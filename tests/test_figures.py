from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

import polyell as pe
from polyell.comparison.summary import format_summary_table, summarize
from polyell.figures import (
    plot_directional_limits,
    plot_score_histogram,
    plot_score_map,
    plot_score_series,
    plot_sets,
    plot_sets_3d,
    save_figure,
)
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis, random_problem


def drawn_lines(figure: Figure) -> dict[str, np.ndarray]:
    return {line.get_label(): line.get_xydata() for line in figure.axes[0].get_lines()}


def test_sets_figure_draws_the_polytope_and_both_ellipsoids():
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    lines = drawn_lines(plot_sets(analysis))
    polygon = lines["polytope"]
    np.testing.assert_allclose(polygon[:-1], analysis.polytope.vertices)
    new = lines["Chiacchio"]
    assert np.all(analysis.ellipsoid("chiacchio").contains(new))
    np.testing.assert_allclose(lines[r"centre $\ddot x_g$"][0], analysis.xg)


def test_singular_sets_are_segments_and_skip_the_undefined_classic():
    analysis = paper_analysis(PAPER_Q_SINGULAR)
    lines = drawn_lines(plot_sets(analysis))
    assert "Yoshikawa" not in lines
    assert lines["polytope"].shape == (2, 2) == lines["Chiacchio"].shape


def test_other_figures_and_saving(tmp_path):
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    figure = plot_directional_limits(analysis, directions=90)
    paths = save_figure(figure, tmp_path / "polar", dpi=50)
    assert [p.suffix for p in paths] == [".pdf", ".png"] and all(p.stat().st_size for p in paths)
    grid = np.arange(12.0).reshape(3, 4)
    grid[0, 0] = np.nan
    plot_score_map(grid, np.arange(4.0), np.arange(3.0), xlabel="x", ylabel="y", label="v")
    with pytest.raises(pe.InputError, match=r"^limits: .*Fix: swap them"):  # not silently
        plot_score_map(
            grid, np.arange(4.0), np.arange(3.0), xlabel="x", ylabel="y", label="v", limits=(1, 0)
        )
    spatial = random_problem(0, 3, 5)
    assert isinstance(plot_sets_3d(spatial), Figure)


def test_dimension_checks():
    with pytest.raises(pe.InputError, match="a 2-D task space"):
        plot_sets(random_problem(0, 3, 5))
    with pytest.raises(pe.InputError, match="a 3-D task space"):
        plot_sets_3d(paper_analysis(PAPER_Q_REDUNDANT))


def test_singular_figure_legend_shows_each_stroke_as_drawn():
    """Issue 13: polytope, new ellipsoid and MVIE lie on one segment; each stays legible."""
    analysis = paper_analysis(PAPER_Q_SINGULAR)
    mvie = pe.compare(analysis, 8).mvie
    ax = plot_sets(analysis, kinds=("chiacchio", "mvie"), mvie=mvie).axes[0]
    drawn = {line.get_label(): line for line in ax.get_lines()}
    legend = ax.get_legend()
    handles = dict(
        zip([t.get_text() for t in legend.get_texts()], legend.legend_handles, strict=True)
    )
    for label in ("polytope", "Chiacchio", "MVIE"):
        line, handle = drawn[label], handles[label]
        assert handle.get_linestyle() == line.get_linestyle(), label
        assert handle.get_linewidth() == line.get_linewidth(), label
        assert handle.get_color() == line.get_color(), label
    widths = [drawn[label].get_linewidth() for label in ("polytope", "Chiacchio", "MVIE")]
    assert widths == sorted(widths, reverse=True)  # layered: each visible above the one below
    assert drawn["polytope"].get_linestyle() == "-"  # a solid band, not long dashes


def test_percent_scores_are_percent_in_every_display():
    results = pd.DataFrame(
        {
            "configuration": range(4),
            "chiacchio_coverage": [0.2, 0.4, 0.5, 0.6],
            "yoshikawa_coverage": [0.1, 0.2, 0.3, 0.35],
        }
    )
    figure = plot_score_histogram(results, "coverage")
    assert figure.axes[0].get_xlabel() == "coverage [%]"
    patches = figure.axes[0].patches
    assert max(p.get_path().vertices[:, 0].max() for p in patches) == pytest.approx(60.0)
    series = plot_score_series(results, "coverage").axes[0]
    assert series.get_ylabel() == "coverage [%]"
    assert series.get_lines()[0].get_ydata().max() == pytest.approx(60.0)
    table = format_summary_table(summarize(results), "markdown")
    row = next(
        line for line in table.splitlines() if "Chiacchio" in line and "coverage [%]" in line
    )
    assert [cell.strip() for cell in row.split("|")][4] == "42.5"  # the mean 0.425, in percent


def test_maps_of_one_score_share_a_colour_scale(tmp_path, monkeypatch):
    import polyell.figures as figures

    scales = {}
    original = figures.plot_score_map

    def record(values, x, y, **options):
        scales[options["title"]] = options["limits"]
        return original(values, x, y, **options)

    monkeypatch.setattr(figures, "plot_score_map", record)
    spec = tmp_path / "grid.toml"
    spec.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[grid]\nq1 = 0.3\n'
        "q2 = { start = -1, stop = 1, num = 4 }\nq3 = { start = -1, stop = 1, num = 5 }\n"
        '[compare]\ndirections = 16\nmvie = false\n[output]\nformats = ["png"]\ndpi = 20\n'
        'maps = ["chiacchio_coverage", "yoshikawa_coverage", "chiacchio_inscribed_scale"]\n'
    )
    pe.studies.run_study(pe.studies.load_study(spec), tmp_path / "out")
    coverage = [limits for title, limits in scales.items() if "coverage" in title]
    assert len(coverage) == 2 and coverage[0] == coverage[1]
    results = pd.read_csv(tmp_path / "out" / "results.csv")
    both = 100 * results[["chiacchio_coverage", "yoshikawa_coverage"]].to_numpy()
    assert coverage[0] == pytest.approx((np.nanmin(both), np.nanmax(both)))


# --- issue 24: a given suffix is honoured -------------------------------------------------


def file_format(path) -> str:
    """The format of a file by its magic bytes (independent of its name)."""
    head = path.read_bytes()[:8]
    if head.startswith(b"%PDF"):
        return "pdf"
    if head.startswith(b"\x89PNG"):
        return "png"
    if head.startswith((b"<?xml", b"<svg")):
        return "svg"
    return "unknown"


def small_figure() -> Figure:
    figure = Figure(figsize=(1, 1))
    figure.add_subplot().plot([0, 1])
    return figure


@pytest.mark.parametrize(
    ("name", "formats", "written"),
    [
        ("x.png", None, {"x.png": "png"}),
        ("x.PDF", None, {"x.PDF": "pdf"}),
        ("x.svg", ("svg",), {"x.svg": "svg"}),
        ("x", None, {"x.pdf": "pdf", "x.png": "png"}),
        ("x", ("svg",), {"x.svg": "svg"}),
        ("x.png", (), {}),  # no format asked for: nothing written
        ("run.v2", None, {"run.v2.pdf": "pdf", "run.v2.png": "png"}),  # not a figure suffix
    ],
)
def test_save_figure_honours_a_given_suffix(tmp_path, name, formats, written):
    paths = save_figure(small_figure(), tmp_path / name, formats, dpi=20)
    assert [p.name for p in paths] == list(written)
    assert {p.name: file_format(p) for p in tmp_path.iterdir()} == written  # nothing else


def test_a_suffix_with_other_formats_is_ambiguous(tmp_path):
    with pytest.raises(pe.InputError, match=r"stem: expected a name without a figure suffix"):
        save_figure(small_figure(), tmp_path / "x.png", ("pdf", "png"), dpi=20)
    assert list(tmp_path.iterdir()) == []


# --- issue 24: the static 3-D figure, legible and whole ----------------------------------

PANDA_POSTURES = {
    "ready": [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785],
    "folded": [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8],
}


def four_ellipsoid_figure(analysis, title="a posture", view=(25.0, -60.0)):
    cmp = pe.compare(analysis, 64)
    extra = {"outer": cmp.ellipsoid("outer")} if cmp["outer"].defined else {}
    kinds = ("chiacchio", "yoshikawa", "mvie") if cmp["mvie"].defined else ("chiacchio",)
    mvie = cmp.mvie if cmp["mvie"].defined else None
    figure = plot_sets_3d(analysis, kinds=kinds, mvie=mvie, extra=extra, title=title, view=view)
    return figure, cmp


def spatial_cases():
    panda = pe.robots.load("panda")
    for name, q in PANDA_POSTURES.items():
        yield name, pe.analyze(panda.dynamics(q), panda.tau_max)
    yield "random", random_problem(0, 3, 5)
    yield "flat", random_problem(1, 3, 5, rank=2)


@pytest.mark.parametrize("case", ["ready", "folded", "random", "flat"])
def test_3d_figure_keeps_every_label_inside_the_canvas(case, tmp_path):
    import matplotlib.image
    from matplotlib.text import Text

    analysis = dict(spatial_cases())[case]
    figure, _ = four_ellipsoid_figure(analysis, title=f"Panda, {case} posture")
    (png,) = save_figure(figure, tmp_path / "sets.png", dpi=100)  # the code's own settings
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas_agg = FigureCanvasAgg(figure)  # the layout as saved, at the figure's dpi
    canvas_agg.draw()
    renderer = canvas_agg.get_renderer()
    canvas = figure.bbox
    ax = figure.axes[0]
    axes = (ax.xaxis, ax.yaxis, ax.zaxis)
    ticks = {id(t.label1) for axis in axes for t in axis.get_major_ticks() + axis.get_minor_ticks()}
    texts = [  # the title, the axis labels, the legend: every text but the tick labels
        t
        for t in figure.findobj(Text)
        if t.get_visible() and t.get_text().strip() and id(t) not in ticks
    ]
    labels = {t.get_text() for t in texts}
    assert {"Panda, " + case + " posture", "polytope"} <= labels
    assert any("ddot z" in label for label in labels)  # the z label is drawn
    boxes = {t.get_text(): t.get_window_extent(renderer) for t in texts}
    # each axis with the tick labels it draws (those within its limits) and its label
    boxes |= {f"{axis.axis_name} axis": axis.get_tightbbox(renderer) for axis in axes}
    for name, box in boxes.items():
        inside = box.x0 >= canvas.x0 and box.y0 >= canvas.y0
        assert inside and box.x1 <= canvas.x1 and box.y1 <= canvas.y1, (name, box, canvas)
    # independently, in the saved pixels: nothing drawn on the canvas's outer frame
    image = matplotlib.image.imread(png)[..., :3]
    frame = np.concatenate(
        [image[:3].ravel(), image[-3:].ravel(), image[:, :3].ravel(), image[:, -3:].ravel()]
    )
    assert frame.min() > 0.95


def test_3d_figure_names_every_set_in_the_legend_with_distinct_strokes():
    analysis = dict(spatial_cases())["ready"]
    figure, _ = four_ellipsoid_figure(analysis)
    legend = figure.legends[0]
    texts = [t.get_text() for t in legend.get_texts()]
    assert texts[:5] == [
        "polytope",
        "Chiacchio",
        "Yoshikawa",
        "MVIE",
        "outer (min. volume)",
    ]
    handles = dict(zip(texts, legend.legend_handles, strict=True))
    assert handles["polytope"].get_facecolor()[3] > 0  # a filled patch: the faces
    ax = figure.axes[0]
    outlines = {line.get_label(): line for line in ax.get_lines() if line.get_label() in texts}
    strokes = {
        (str(o.get_color()), str(o.get_linestyle()), str(o.get_marker())) for o in outlines.values()
    }
    assert len(strokes) == len(outlines) == 6  # four ellipsoids, the centre, the origin
    for label in texts[1:5]:  # each legend entry is drawn as its outline is
        assert handles[label].get_linestyle() == outlines[label].get_linestyle()
        assert handles[label].get_color() == outlines[label].get_color()
    # few lines: an outline and three principal sections per ellipsoid, nothing else
    assert len(ax.get_lines()) == 4 * 4 + 2


@pytest.mark.parametrize("view", [(25.0, -60.0), (10.0, 30.0), (70.0, 200.0)])
def test_3d_outline_is_the_silhouette_of_the_ellipsoid(view):
    from polyell.figures import ellipsoid_outline

    analysis = dict(spatial_cases())["folded"]
    for kind in ("chiacchio", "yoshikawa"):
        E = analysis.ellipsoid(kind)
        outline, sections = ellipsoid_outline(E, view)
        y = outline - E.center
        N = E.core  # (x - c)^T N (x - c) = 1 on the surface
        np.testing.assert_allclose(np.einsum("ij,jk,ik->i", y, N, y), 1.0, rtol=1e-9)
        e, a = np.radians(view)
        d = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
        normals = y @ N  # the surface's normals there are perpendicular to the line of sight
        cosines = normals @ d / np.linalg.norm(normals, axis=1)
        np.testing.assert_allclose(cosines, 0.0, atol=1e-9)
        # seen along d, the outline is the ellipsoid's contour: the same support in every
        # direction u of the picture plane, h(u) = u.c + sqrt(u^T N^-1 u)
        plane = np.linalg.svd(d[None])[2][1:]
        angles = np.linspace(0, 2 * np.pi, 50)
        u = np.outer(np.cos(angles), plane[0]) + np.outer(np.sin(angles), plane[1])
        support = u @ E.center + np.sqrt(np.einsum("ij,jk,ik->i", u, np.linalg.inv(N), u))
        drawn = (outline @ u.T).max(axis=0)  # 180 chords: at most 1.6e-4 of the size inside
        size = E.semi_axes.max()
        assert np.all(drawn <= support + 1e-9 * size)
        assert np.all(drawn >= support - 2e-4 * size)
        assert len(sections) == 3
        for section in sections:
            s = section - E.center
            np.testing.assert_allclose(np.einsum("ij,jk,ik->i", s, N, s), 1.0, rtol=1e-9)


def test_every_force_ellipsoid_has_its_own_line():
    from polyell.figures import _style

    kinds = ("polytope", "chiacchio", "yoshikawa", "static")
    drawn = [
        (_style(k, kinds, "force")["color"], str(_style(k, kinds, "force")["linestyle"]))
        for k in kinds
    ]
    assert len(set(drawn)) == len(kinds)
    assert _style("static", kinds, "force")["label"] == "static (no gravity)"


def test_series_without_an_abscissa_are_refused_by_name():
    """A frame with neither 't' nor 'configuration': an InputError naming results."""
    import pandas as pd

    from polyell.figures import plot_score_series, plot_tangent_limits

    frame = pd.DataFrame({"chiacchio_coverage": [0.5, 0.6], "tangent_polytope_lo": [-1.0, -2.0]})
    for call in (
        lambda: plot_score_series(frame, "coverage"),
        lambda: plot_tangent_limits(frame),
    ):
        with pytest.raises(pe.InputError) as error:
            call()
        assert error.value.argument == "results"


@pytest.mark.parametrize("projection", ["polar", "3d"])
def test_plot_sets_refuses_axes_that_cannot_hold_a_2d_drawing(projection):
    """A polar or 3-D ax is refused by name (polar raised matplotlib's ValueError, 3-D drew
    silently; found by the independent check of issue 31)."""
    from matplotlib.figure import Figure

    from polyell.figures import plot_sets

    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), arm.tau_max)
    ax = Figure().add_subplot(projection=projection)
    with pytest.raises(pe.InputError, match=f"ax: .*projection '{projection}'"):
        plot_sets(analysis, ax=ax)
