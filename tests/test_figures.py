from __future__ import annotations

import numpy as np
import pytest
from matplotlib.figure import Figure

import polyell as pe
from polyell.figures import (
    plot_directional_limits,
    plot_score_map,
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
    polygon = lines["polytope (15)"]
    np.testing.assert_allclose(polygon[:-1], analysis.polytope.vertices)
    new = lines["new (eq. 32/38)"]
    assert np.all(analysis.ellipsoid("chiacchio").contains(new))
    np.testing.assert_allclose(lines[r"centre $\ddot x_g$"][0], analysis.xg)


def test_singular_sets_are_segments_and_skip_the_undefined_classic():
    analysis = paper_analysis(PAPER_Q_SINGULAR)
    lines = drawn_lines(plot_sets(analysis))
    assert "classic (eq. 27)" not in lines
    assert lines["polytope (15)"].shape == (2, 2) == lines["new (eq. 32/38)"].shape


def test_other_figures_and_saving(tmp_path):
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    figure = plot_directional_limits(analysis, directions=90)
    paths = save_figure(figure, tmp_path / "polar", dpi=50)
    assert [p.suffix for p in paths] == [".pdf", ".png"] and all(p.stat().st_size for p in paths)
    grid = np.arange(12.0).reshape(3, 4)
    grid[0, 0] = np.nan
    plot_score_map(grid, np.arange(4.0), np.arange(3.0), xlabel="x", ylabel="y", label="v")
    spatial = random_problem(0, 3, 5)
    assert isinstance(plot_sets_3d(spatial), Figure)


def test_dimension_checks():
    with pytest.raises(pe.InputError, match="a 2-D task space"):
        plot_sets(random_problem(0, 3, 5))
    with pytest.raises(pe.InputError, match="a 3-D task space"):
        plot_sets_3d(paper_analysis(PAPER_Q_REDUNDANT))
