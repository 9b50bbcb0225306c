"""Writers at their edges: a clear PolyellError or a valid file, never a raw exception.

Tables, figures, meshes and reports written into missing folders or under names too long
for the file system; mesh resolutions out of range; figure texts whose mathtext does not
parse; and a seeded fuzz of the static figures and mesh writers over wrong types, NaN,
infinity and extreme magnitudes.
"""

from __future__ import annotations

import errno
import os

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st
from matplotlib.figure import Figure

import polyell as pe
from polyell.errors import InputError, PolyellError, StorageError
from polyell.export import (
    MAX_RESOLUTION,
    Mesh,
    check_resolution,
    export_comparison,
    mesh,
    write_obj,
    write_ply,
)
from polyell.figures import (
    check_title,
    plot_score_histogram,
    plot_score_map,
    plot_score_series,
    plot_sets,
    save_figure,
)
from reference import PAPER_Q_REDUNDANT, paper_analysis

LONG = "x" * 300  # one name longer than NAME_MAX (255 bytes on Linux file systems)


@pytest.fixture(scope="module")
def paper() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 16, mvie=False)


def writers(paper):
    """Each writer as a function of its target path (without or with the suffix it needs)."""
    figure = Figure()
    figure.add_subplot().plot([0, 1])
    return {
        "csv": lambda path: paper.to_csv(path.with_suffix(".csv")),
        "obj": lambda path: export_comparison(paper, path.with_suffix(".obj"), 2),
        "ply": lambda path: export_comparison(paper, path.with_suffix(".ply"), 2),
        "figure": lambda path: save_figure(figure, path, ("png",), 20),
        "report": lambda path: (
            pe.interactive.write_report(path.with_suffix(".html"), "t", [("s", "text")])
            if hasattr(pe, "interactive")
            else __import__("polyell.interactive").interactive.write_report(
                path.with_suffix(".html"), "t", [("s", "text")]
            )
        ),
    }


@pytest.mark.parametrize("writer", ["csv", "obj", "ply", "figure", "report"])
def test_a_missing_folder_is_a_storage_error_with_the_fix(paper, tmp_path, writer):
    with pytest.raises(StorageError, match="create the folder") as caught:
        writers(paper)[writer](tmp_path / "missing" / "out")
    assert "missing" in str(caught.value)


@pytest.mark.parametrize("writer", ["csv", "obj", "ply", "figure", "report"])
def test_a_name_too_long_is_a_storage_error_with_the_fix(paper, tmp_path, writer):
    with pytest.raises(StorageError, match="shorter file name"):
        writers(paper)[writer](tmp_path / LONG)
    assert os.listdir(tmp_path) == []  # nothing partial left


def test_to_csv_is_atomic_a_failed_write_keeps_the_old_file(paper, tmp_path, monkeypatch):
    path = tmp_path / "scores.csv"
    path.write_text("old,file\n", encoding="utf-8")

    def full_disk(source, target):  # the rename of a finished temporary file fails
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr("polyell.storage.os.replace", full_disk)
    with pytest.raises(StorageError, match="free disk space"):
        paper.to_csv(path)
    assert path.read_text(encoding="utf-8") == "old,file\n"
    assert sorted(os.listdir(tmp_path)) == ["scores.csv"]  # no temporary file left


def test_to_csv_refuses_a_path_of_a_wrong_type(paper):
    with pytest.raises(InputError, match="path"):
        paper.to_csv(5)  # type: ignore[arg-type]


@pytest.mark.parametrize("resolution", [0, 1, -1, 2.5, 10**6, True, "24", None, np.float64(24)])
def test_a_mesh_resolution_out_of_range_is_refused(paper, tmp_path, resolution):
    for call in (
        lambda: mesh(paper.ellipsoid("chiacchio"), resolution),
        lambda: export_comparison(paper, tmp_path / "sets.obj", resolution),
    ):
        with pytest.raises(InputError, match=rf"resolution.*\[2, {MAX_RESOLUTION}\]"):
            call()
    assert os.listdir(tmp_path) == []


def test_mesh_resolution_limits_are_accepted(paper):
    assert check_resolution(2) == 2 and check_resolution(np.int64(MAX_RESOLUTION)) == 512
    E = paper.ellipsoid("chiacchio")  # 2-D: a fan of 8 k boundary points
    assert len(mesh(E, 2).vertices) == 16


def test_mesh_names_and_headers_stay_on_their_lines(tmp_path):
    item = Mesh(np.zeros((1, 3)), np.zeros((0, 3), dtype=int), np.zeros((0, 2), dtype=int))
    with pytest.raises(InputError, match="name"):
        write_obj(tmp_path / "a.obj", {"a\nv 1 2 3": item})
    with pytest.raises(InputError, match="name"):
        write_ply(tmp_path / "a.ply", item, name="a\nend_header")
    with pytest.raises(InputError, match="meshes"):
        write_obj(tmp_path / "a.obj", {"a": "not a mesh"})  # type: ignore[dict-item]
    assert os.listdir(tmp_path) == []
    # A line break in the unit is a space: the header stays one comment line.
    text = write_obj(tmp_path / "a.obj", {"a": item}, unit="m\nv 0 0 0").read_text()
    assert sum(line.startswith("v ") for line in text.splitlines()) == 1


@pytest.mark.parametrize("title", [r"$\frac{$", r"$\alpha_$", r"cost $5 and $6 $\sqrt{$"])
def test_titles_whose_mathtext_does_not_parse_are_refused_before_drawing(title):
    with pytest.raises(InputError, match=r"title.*\\\$") as caught:
        check_title(title)
    assert title in str(caught.value) or repr(title) in str(caught.value)
    with pytest.raises(InputError, match="title"):
        plot_sets(paper_analysis(PAPER_Q_REDUNDANT), title=title)


@pytest.mark.parametrize("title", ["cost \\$5 and \\$6", "plain", r"$\ddot x$ [m/s$^2$]", "$"])
def test_titles_that_parse_are_drawn(title, tmp_path):
    assert check_title(title) == title
    figure = plot_sets(paper_analysis(PAPER_Q_REDUNDANT), title=title)
    assert [p.name for p in save_figure(figure, tmp_path / "f", ("png",), 20)] == ["f.png"]


def test_save_figure_refuses_unknown_formats_and_dpi(tmp_path):
    figure = Figure()
    for formats, dpi in ((("bmp2",), 50), ("png", 50), (("png",), 0), (("png",), 10**6)):
        with pytest.raises(InputError, match=r"formats|dpi"):
            save_figure(figure, tmp_path / "f", formats, dpi)
    assert os.listdir(tmp_path) == []


VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e-300, 1e300, -1e-300, -1e300, 0.0]),
)


@given(
    values=st.lists(VALUES, min_size=6, max_size=6),
    title=st.one_of(st.none(), st.text(max_size=12), st.integers()),
)
def test_static_score_figures_are_a_figure_or_a_polyell_error(values, title):
    results = pd.DataFrame(
        {
            "configuration": np.arange(6),
            "chiacchio_coverage": values,
            "yoshikawa_coverage": values[::-1],
        }
    )
    for draw in (
        lambda: plot_score_histogram(results, "coverage", title=title),
        lambda: plot_score_series(results, "coverage", title=title),
        lambda: plot_score_map(
            np.array(values).reshape(2, 3),
            np.arange(3.0),
            np.arange(2.0),
            xlabel="x",
            ylabel="y",
            label="c",
            title=title,
        ),
    ):
        try:
            figure = draw()
        except PolyellError:
            continue
        figure.canvas.draw()  # renders every text: a bad mathtext would raise here


@given(
    scale=st.sampled_from([1e-300, 1e-150, 1e-12, 1.0, 1e12, 1e150, 1e300]),
    resolution=st.one_of(st.integers(-3, 6), st.floats(), st.none()),
)
def test_mesh_export_is_a_file_or_a_polyell_error(tmp_path_factory, scale, resolution):
    folder = tmp_path_factory.mktemp("mesh")
    try:  # semi-axes beyond the magnitude bound are refused by the Ellipsoid itself
        E = pe.Ellipsoid(np.zeros(3), np.eye(3), scale * np.array([1.0, 2.0, 3.0]))
        item = mesh(E, resolution)
    except PolyellError:
        return
    path = write_obj(folder / "e.obj", {"e": item})
    lines = path.read_text(encoding="utf-8").splitlines()
    vertices = np.array([line.split()[1:] for line in lines if line.startswith("v ")], float)
    assert np.isfinite(vertices).all() and len(vertices) == len(item.vertices)
    assert sum(line.startswith("f ") for line in lines) == len(item.faces)
