"""Grid, random and trajectory studies read their results one part at a time (issue 33: a
10^6-configuration grid study held every row, 1.6 GB, and wrote a 965 MB results.csv).

The summary's statistics are those of ``summarize`` over every row (exact, or to rounding
for the mean and the standard deviation), results.csv is the dataset's rows written part
by part, and what a figure shows of a large study (a sub-grid, a sample) is said."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
import polyell.studies.models as models
import polyell.studies.runner as runner
from polyell.comparison.summary import summarize
from polyell.storage import write_csv
from polyell.studies import load_study, run_study
from polyell.studies.configurations import Grid, uniform_rows
from polyell.studies.spec import GridAxis, SeededRows

GRID = """
    title = "grid"
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = {{ start = "-pi", stop = "pi", num = {rows} }}
    q3 = {{ start = "-pi", stop = "pi", num = 9 }}
    [compare]
    directions = 12
    mvie = false
    samples = 64
    chunk = {chunk}
    [[candidates]]
    name = "heavy_wrist"
    weighting = [1, 1, 4]
    [output]
    formats = ["png", "html"]
    dpi = 20
    maps = ["chiacchio_coverage", "heavy_wrist_inscribed_scale"]
    histograms = ["coverage"]
    {output}
"""


def grid_study(tmp_path: Path, rows: int = 7, chunk: int = 10, output: str = "") -> Path:
    path = tmp_path / "grid.toml"
    path.write_text(textwrap.dedent(GRID).format(rows=rows, chunk=chunk, output=output))
    return path


def whole(dataset: Path) -> pd.DataFrame:
    """Every row of a dataset at once: what the runner held before issue 33."""
    return pd.read_parquet(dataset).sort_values("configuration").reset_index(drop=True)


# --- the summary's statistics ------------------------------------------------------------


def parts_of(tmp_path: Path, frame: pd.DataFrame, rows: int) -> list[Path]:
    paths = []
    for index, start in enumerate(range(0, len(frame), rows)):
        path = tmp_path / f"part-{index:06d}.parquet"
        frame.iloc[start : start + rows].to_parquet(path, index=False)
        paths.append(path)
    return paths


def streamed(columns: dict, parts: list[Path]) -> pd.DataFrame:
    statistics = runner.StreamedSummary(columns)
    for part in parts:
        statistics.add(pd.read_parquet(part))
    return statistics.summary(parts)


def random_scores(seed: int, count: int) -> pd.DataFrame:
    """Scores with what a sweep holds: NaN and inf rows, ties, -0.0, signs, magnitudes."""
    rng = np.random.default_rng(seed)
    a = rng.normal(0.5, 0.1, count)
    a[rng.random(count) < 0.1] = np.nan
    a[rng.random(count) < 0.01] = np.inf
    b = np.round(rng.normal(0.0, 3.0, count), 1)  # many ties, both signs
    b[rng.random(count) < 0.05] = -0.0
    c = np.exp(rng.normal(0.0, 20.0, count)) * rng.choice([-1.0, 1.0], count)
    d = np.full(count, 1.0)  # one value
    e = np.full(count, np.nan)  # undefined everywhere: no row
    return pd.DataFrame(
        {
            "chiacchio_coverage": a,
            "chiacchio_inscribed_scale": b,
            "yoshikawa_coverage": c,
            "mvie_coverage": d,
            "yoshikawa_inscribed_scale": e,
        }
    )


COLUMNS = {
    ("chiacchio", "inscribed_scale"): "chiacchio_inscribed_scale",
    ("chiacchio", "coverage"): "chiacchio_coverage",
    ("yoshikawa", "inscribed_scale"): "yoshikawa_inscribed_scale",
    ("yoshikawa", "coverage"): "yoshikawa_coverage",
    ("mvie", "coverage"): "mvie_coverage",
}


def assert_summaries_agree(got: pd.DataFrame, expected: pd.DataFrame) -> None:
    assert list(got.index) == list(expected.index)
    assert list(got.columns) == list(expected.columns)
    assert list(got.dtypes) == list(expected.dtypes)
    for name in ("defined", "min", "median", "max"):  # exact
        np.testing.assert_array_equal(got[name].to_numpy(), expected[name].to_numpy(), name)
    for name in ("mean", "std"):  # the same sums, added in another order
        np.testing.assert_allclose(got[name], expected[name], rtol=1e-13, atol=0, err_msg=name)


@pytest.mark.parametrize(
    ("count", "rows", "keep", "digits"),
    [
        (1001, 97, 16, 12),  # odd counts, ranges kept once they hold 16 values
        (2000, 300, 8, 3),  # even counts: the two middle values, 3 bits a pass
        (2000, 2000, 2, 1),  # one part, one bit a pass: down to single keys
        (40_001, 5000, runner._KEEP, runner._DIGIT_BITS),  # the defaults, past _KEEP
    ],
)
def test_streamed_summary_equals_summarize(tmp_path, monkeypatch, count, rows, keep, digits):
    monkeypatch.setattr(runner, "_KEEP", keep)
    monkeypatch.setattr(runner, "_DIGIT_BITS", digits)
    frame = random_scores(count, count)
    expected = summarize(frame, kinds=["chiacchio", "yoshikawa", "mvie"])
    got = streamed(COLUMNS, parts_of(tmp_path, frame, rows))
    assert_summaries_agree(got, expected)
    assert ("yoshikawa", "inscribed_scale") not in got.index  # no finite value: no row


def test_a_short_column_is_summarised_by_summarize_itself(tmp_path):
    """At most _KEEP values: kept whole, every statistic summarize's to the last bit."""
    frame = random_scores(5, 3000)
    expected = summarize(frame, kinds=["chiacchio", "yoshikawa", "mvie"])
    got = streamed(COLUMNS, parts_of(tmp_path, frame, 700))
    pd.testing.assert_frame_equal(got, expected)


# --- results.csv, the summary and the figures of a study ---------------------------------


def test_a_grid_study_in_many_parts_writes_what_it_held_whole(tmp_path, monkeypatch):
    """results.csv, summary.csv: the bytes the runner wrote from every row at once.

    With the summary's selection forced (ranges of at most 4 values kept), the median,
    min, max and counts are still those of summarize over the whole dataset.
    """
    monkeypatch.setattr(runner, "_KEEP", 4)
    out = tmp_path / "out"
    run_study(load_study(grid_study(tmp_path, rows=7, chunk=10)), out)
    results = whole(out / "results")
    assert len(results) == 63 and len(list((out / "results").glob("part-*.parquet"))) == 7
    expected = tmp_path / "expected.csv"
    with open(expected, "wb") as handle:
        write_csv(results, handle)
    assert (out / "results.csv").read_bytes() == expected.read_bytes()
    got = pd.read_csv(out / "summary.csv", index_col=[0, 1])
    reference = pd.read_csv(pd.io.common.StringIO(summarize(results).to_csv()), index_col=[0, 1])
    assert_summaries_agree(got, reference)
    for name in ("map_chiacchio_coverage.png", "map_heavy_wrist_inscribed_scale.png"):
        assert (out / name).stat().st_size > 0
    assert "notes" not in json.loads((out / "manifest.json").read_text())  # nothing left out


ROBOTS = {
    "a": 'library = "chiacchio2000"\n',
    "b": 'library = "chiacchio2000"\ntau_max = [80, 20, 3]\n',
    "c": "planar = { lengths = [1, 0.5], masses = [2, 1] }\ntau_max = [40, 10]\n",
}


@pytest.mark.parametrize("names", ["ab", "ac", "ca"])
def test_several_robots_stream_into_one_csv_with_their_names(tmp_path, names):
    """The rows of every robot under one header: a robot of fewer joints has empty q3."""
    path = tmp_path / "two.toml"
    path.write_text(
        "".join(f'[[robots]]\nname = "{name}"\n{ROBOTS[name]}' for name in names)
        + "[random]\ncount = 25\nseed = 2\n"
        "[compare]\ndirections = 12\nmvie = false\nouter = false\nsamples = 64\nchunk = 7\n"
        '[output]\nformats = []\nhistograms = ["coverage"]\n'
    )
    out = tmp_path / "out"
    run_study(load_study(path), out)
    # what the runner wrote before issue 33: the robots' rows joined by pandas.concat
    frames = [whole(out / "results" / f"robot={name}").assign(robot=name) for name in names]
    table = pd.concat(frames, ignore_index=True)
    table = table[["robot", *[c for c in table.columns if c != "robot"]]]
    assert ("q3" in table) and table["q3"].isna().any() == ("c" in names)
    expected = tmp_path / "expected.csv"
    with open(expected, "wb") as handle:
        write_csv(table, handle)
    assert (out / "results.csv").read_bytes() == expected.read_bytes()
    summary = pd.read_csv(out / "summary.csv", index_col=[0, 1, 2])
    for name, frame in zip(names, frames, strict=True):
        assert summary.loc[(name, "chiacchio", "coverage"), "median"] == pytest.approx(
            frame["chiacchio_coverage"].median(), rel=0, abs=0
        )


@pytest.mark.parametrize(
    ("csv", "limit", "written"),
    [("", 63, True), ("", 62, False), ("csv = true", 1, True), ("csv = false", 10**6, False)],
)
def test_results_csv_is_written_as_the_csv_key_says(tmp_path, monkeypatch, csv, limit, written):
    monkeypatch.setattr(models, "CSV_AUTO_ROWS", limit)
    out = tmp_path / "out"
    files = run_study(load_study(grid_study(tmp_path, output=csv)), out)
    manifest = json.loads((out / "manifest.json").read_text())
    assert (out / "results.csv").exists() == written == ("results.csv" in manifest["files"])
    assert (out / "results.csv" in files) == written
    assert len(whole(out / "results")) == 63  # the Parquet dataset holds every row
    if written:
        assert "notes" not in manifest
        return
    why = (
        "[output] csv = false"
        if csv
        else '63 configurations, more than [output] csv = "auto" writes'
    )
    assert manifest["notes"] == [
        f"results.csv not written ({why}): every row is in the Parquet dataset results/ "
        "(pandas.read_parquet); csv = true writes it, streamed"
    ]


def test_a_rerun_without_the_csv_removes_the_old_one(tmp_path):
    out = tmp_path / "out"
    run_study(load_study(grid_study(tmp_path)), out)
    assert (out / "results.csv").exists()
    run_study(load_study(grid_study(tmp_path, output="csv = false")), out)
    assert not (out / "results.csv").exists()
    assert "results.csv" in json.loads((out / "manifest.json").read_text())["removed"]


def test_large_maps_draw_a_sub_grid_and_large_histograms_a_sample(tmp_path, monkeypatch):
    monkeypatch.setattr(runner, "MAP_AXIS_VALUES", 3)
    monkeypatch.setattr(runner, "REPORT_MAP_AXIS_VALUES", 2)
    monkeypatch.setattr(runner, "HISTOGRAM_ROWS", 20)
    out = tmp_path / "out"
    run_study(load_study(grid_study(tmp_path)), out)
    notes = json.loads((out / "manifest.json").read_text())["notes"]
    assert notes[0] == (
        "maps map_*: 3 x 3 of 7 x 9 grid points: every 3rd value of q2, every 3rd value of q3"
    )
    assert notes[1].startswith("histograms histogram_*: a seeded random sample of ")
    assert notes[1].endswith(" of 63 configurations")
    page = (out / "report.html").read_text()
    assert "2 x 2 of 7 x 9 grid points" in page and "a seeded random sample of" in page
    assert (out / "map_chiacchio_coverage.png").exists()
    assert (out / "histogram_coverage.png").exists()


def test_a_sub_grid_keeps_every_k_th_value_of_the_whole_grid():
    y = GridAxis("q2", np.linspace(-1, 1, 7))
    x = GridAxis("q3", np.linspace(0, 1, 10))
    values = np.arange(70.0).reshape(7, 10)
    frame = pd.DataFrame({"configuration": np.arange(70), "s": values.ravel()})
    for rows in (1, 3, 70):  # any chunking
        grid = runner._SubGrid(y, x, 4, ["s"])
        for start in range(0, 70, rows):
            grid.add(frame.iloc[start : start + rows])
        np.testing.assert_array_equal(grid.values("s"), values[::2, ::3])
        np.testing.assert_array_equal(grid.axes[0], y.values[::2])
        np.testing.assert_array_equal(grid.axes[1], x.values[::3])
    assert grid.decimated and grid.shape_note() == "4 x 4 of 7 x 10 grid points"


def test_the_histogram_sample_does_not_depend_on_the_chunks():
    frame = pd.DataFrame({"configuration": np.arange(10_000), "s": np.arange(10_000.0)})
    samples = []
    for rows in (1000, 333, 10_000):
        sample = runner._RowSample(10_000, ["s"], limit=1000)
        for start in range(0, 10_000, rows):
            sample.add(frame.iloc[start : start + rows])
        samples.append(sample.frame()["s"].to_numpy())
    assert all(np.array_equal(samples[0], other) for other in samples[1:])
    assert 900 < samples[0].size < 1100 and sample.sampled
    # spread over the rows, not their first thousand
    assert samples[0].min() < 100 and samples[0].max() > 9900
    every = runner._RowSample(500, ["s"], limit=1000)
    every.add(frame.iloc[:500])
    assert not every.sampled and len(every.frame()) == 500


def test_a_trajectory_study_streams_its_summary_and_can_leave_out_its_csv(tmp_path, monkeypatch):
    monkeypatch.setattr(runner, "_KEEP", 4)
    source = Path(__file__).resolve().parents[2] / "studies" / "planar3r_path.csv"
    (tmp_path / "path.csv").write_text("".join(source.read_text().splitlines(True)[:41]))
    path = tmp_path / "path.toml"
    text = (
        '[robot]\nlibrary = "chiacchio2000"\n[trajectory]\nfile = "path.csv"\n'
        "[compare]\ndirections = 12\nmvie = false\nouter = false\nsamples = 64\nchunk = 9\n"
        '[output]\nformats = []\nhistograms = ["coverage"]\n'
    )
    path.write_text(text)
    out = tmp_path / "out"
    run_study(load_study(path), out)
    results = whole(out / "results")
    got = pd.read_csv(out / "summary.csv", index_col=[0, 1])
    reference = pd.read_csv(pd.io.common.StringIO(summarize(results).to_csv()), index_col=[0, 1])
    assert_summaries_agree(got, reference)
    assert len(pd.read_csv(out / "results.csv")) == 40
    path.write_text(text + "csv = false\n")
    run_study(load_study(path), tmp_path / "out2")
    assert not (tmp_path / "out2" / "results.csv").exists()
    notes = json.loads((tmp_path / "out2" / "manifest.json").read_text())["notes"]
    assert notes[0].startswith("results.csv not written ([output] csv = false)")


# --- the configurations are made a chunk at a time ---------------------------------------


def test_grid_and_random_studies_sweep_lazy_configurations(tmp_path, monkeypatch):
    """A 10^7-configuration grid was one (K, n) array (and its meshgrid copies), pickled
    whole into the sweep's fingerprint; now the sweep makes each chunk's rows."""
    seen = []
    real = runner.sweep

    def spy(model, configurations, *args, **kwargs):
        seen.append(configurations)
        return real(model, configurations, *args, **kwargs)

    monkeypatch.setattr(runner, "sweep", spy)
    spec = load_study(grid_study(tmp_path))
    run_study(spec, tmp_path / "grid")
    assert isinstance(seen[-1], Grid)
    np.testing.assert_array_equal(np.asarray(seen[-1]), spec.configurations())
    mesh = np.meshgrid(*[axis.values for axis in spec.grid], indexing="ij")
    np.testing.assert_array_equal(spec.configurations(), np.stack([m.ravel() for m in mesh], 1))
    path = tmp_path / "random.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 30\nseed = 5\n'
        "[compare]\ndirections = 12\nmvie = false\nouter = false\nsamples = 64\nchunk = 7\n"
        "[output]\nformats = []\n"
    )
    spec = load_study(path)
    run_study(spec, tmp_path / "random")
    assert isinstance(seen[-1], SeededRows)
    results = whole(tmp_path / "random" / "results")
    rows = uniform_rows(np.random.default_rng(5), np.full(3, -np.pi), np.full(3, np.pi), 30)
    np.testing.assert_array_equal(results[["q1", "q2", "q3"]].to_numpy(), rows)  # as before


def test_seeded_rows_are_the_rows_the_seed_always_gave():
    for low, high in (
        (np.array([-1.0, -2.0, 0.0]), np.array([1.0, 2.0, 0.0])),
        (np.full(2, -1e308), np.full(2, 1e308)),  # a box wider than the largest float
    ):
        expected = uniform_rows(np.random.default_rng(11), low, high, 500)
        rows = SeededRows(500, low, high, 11)
        assert len(rows) == 500 and rows.n == low.size
        np.testing.assert_array_equal(np.asarray(rows), expected)
        for start, stop in ((0, 1), (123, 457), (499, 600), (7, 7)):
            np.testing.assert_array_equal(rows.rows(start, stop), expected[start:stop])
    assert pe.studies.spec.SeededRows is SeededRows


def test_the_reference_page_gives_the_runners_caps():
    text = " ".join((models.OutputTable.__doc__ or "").split())
    assert f"more than {runner.MAP_AXIS_VALUES:,} values along an axis" in text
    assert f"more than {runner.HISTOGRAM_ROWS:,} configurations" in text
    assert f"about {runner.HISTOGRAM_ROWS:,} of them" in text
    assert (
        f"{models.CSV_AUTO_ROWS:,} configurations"
        in models.OutputTable.model_fields["csv"].description
    )


@pytest.mark.parametrize(
    ("arguments", "start"),
    [
        ((0, [0.0], [1.0], 0), "count: expected an integer"),
        ((3, [1.0], [0.0], 0), "low: expected low <= high for every joint"),
        ((3, [0.0, 0.0], [1.0], 0), "high: expected"),
        ((3, [0.0], [1.0], -1), "seed: expected an integer"),
    ],
)
def test_bad_seeded_rows_are_refused_naming_the_argument(arguments, start):
    with pytest.raises(pe.InputError) as info:
        SeededRows(*arguments)
    assert str(info.value).startswith(start), str(info.value)
