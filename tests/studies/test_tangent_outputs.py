"""A trajectory study's tangent limits are in its Parquet dataset, and the CSV is the dataset.

The columns ``tangent_<set>_lo``, ``_hi`` (what a capacity allows along the path's
tangent) were added to ``results.csv`` only: with ``[output] csv = false`` (or "auto"
above 100,000 samples) they were written nowhere.  Every column a study reports is in the
dataset ``results/``, and the CSV streamed from its parts equals it column for column.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.studies import load_study, run_study
from polyell.studies.trajectory import Trajectory, tangent_limits

ARM = pe.robots.load("chiacchio2000")
T = np.linspace(0.0, 2.0, 41)
TANGENTS = [
    f"tangent_{name}_{end}"
    for name in ("polytope", "chiacchio", "yoshikawa")
    for end in ("lo", "hi")
]


def path(velocities: bool = True) -> pd.DataFrame:
    """q(t) = q0 + A sin(w t) with its exact derivative (still at t = 1: qd = 0)."""
    q0, A, w = np.array([1.2, -1.0, -0.8]), np.array([0.5, 0.4, 0.6]), np.pi / 2
    q = q0 + A * np.sin(w * T)[:, None]
    qd = A * w * np.cos(w * T)[:, None]
    table = {"t": T} | {f"q{i + 1}": q[:, i] for i in range(3)}
    if velocities:
        table |= {f"qd{i + 1}": qd[:, i] for i in range(3)}
    return pd.DataFrame(table)


def study(
    folder: Path, *, csv: str = "true", capacities: str = '["acceleration"]', **more: str
) -> Path:
    """A trajectory study of the path in ``folder``, in chunks of 10 samples (5 parts)."""
    extra = "".join(f"{key} = {value}\n" for key, value in more.items())
    spec = folder / "study.toml"
    spec.write_text(
        'title = "path"\n[robot]\nlibrary = "chiacchio2000"\n'
        '[trajectory]\nfile = "path.csv"\n'
        f"[compare]\ndirections = 16\nseed = 0\nchunk = 10\ncapacities = {capacities}\n{extra}"
        f'[output]\nformats = ["png"]\ndpi = 30\ncsv = {csv}\n'
    )
    return spec


def run(folder: Path, velocities: bool = True, **options: str) -> Path:
    path(velocities).to_csv(folder / "path.csv", index=False)
    out = folder / "out"
    run_study(load_study(study(folder, **options)), out)
    return out


def assert_same_frames(dataset: pd.DataFrame, csv: pd.DataFrame) -> None:
    """The same columns in the same order, every value equal (NaN where NaN)."""
    assert list(dataset.columns) == list(csv.columns)
    assert len(dataset) == len(csv)
    for name in dataset.columns:
        ours, theirs = dataset[name].to_numpy(), csv[name].to_numpy()
        if ours.dtype.kind == "f":
            np.testing.assert_array_equal(ours, theirs.astype(float), err_msg=name)
        else:
            assert (ours == theirs).all(), name


def test_the_tangent_limits_are_in_the_dataset_and_the_csv_is_the_dataset(tmp_path):
    out = run(tmp_path)
    dataset = pd.read_parquet(out / "results")
    csv = pd.read_csv(out / "results.csv")
    assert set(TANGENTS) <= set(dataset.columns)
    for name in TANGENTS:  # exactly: the CSV writes each double's shortest repr
        np.testing.assert_array_equal(dataset[name].to_numpy(), csv[name].to_numpy())
    assert_same_frames(dataset, csv)
    # The limits of the whole path at once, as the library computes them.
    frame = path()
    trajectory = Trajectory(
        frame[["q1", "q2", "q3"]].to_numpy(), frame[["qd1", "qd2", "qd3"]].to_numpy()
    )
    expected = tangent_limits(ARM, trajectory)
    for name in TANGENTS:
        np.testing.assert_allclose(dataset[name], expected[name], rtol=1e-12, atol=0.0)
    assert np.isnan(dataset.loc[20, "tangent_polytope_hi"])  # t = 1: still, no tangent
    assert np.isfinite(dataset.drop(index=20)[TANGENTS].to_numpy()).all()
    # Each part holds its own samples' columns (the dataset is read part by part).
    parts = sorted((out / "results").glob("part-*.parquet"))
    assert len(parts) == 5
    for part in parts:
        assert set(TANGENTS) <= set(pd.read_parquet(part).columns)
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest.get("complete", True) is True  # (an unfinished run: false)
    assert {"results.csv", "summary.csv", "tangent_limits.png"} <= set(manifest["files"])
    assert "results/" in manifest["datasets"]
    summary = pd.read_csv(out / "summary.csv")
    assert len(summary) > 0 and not any("tangent" in str(c) for c in summary.columns)


def test_without_a_csv_the_tangent_limits_are_still_in_the_dataset(tmp_path):
    out = run(tmp_path, csv="false")
    assert not (out / "results.csv").exists()
    dataset = pd.read_parquet(out / "results")
    assert set(TANGENTS) <= set(dataset.columns) and len(dataset) == len(T)
    assert np.isfinite(dataset[TANGENTS].drop(index=20).to_numpy()).all()
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest.get("complete", True) is True  # (an unfinished run: false)
    notes = " ".join(manifest.get("notes", []))
    assert "results.csv not written" in notes and "only in the CSV" not in notes
    assert "tangent_limits.png" in manifest["files"]


def test_each_capacity_dataset_holds_its_own_tangent_limits(tmp_path):
    out = run(tmp_path, capacities='["acceleration", "force"]')
    force = pd.read_parquet(out / "results_force")
    assert {"tangent_polytope_lo", "tangent_static_hi"} <= set(force.columns)
    assert_same_frames(force, pd.read_csv(out / "results_force.csv"))
    acceleration = pd.read_parquet(out / "results")
    assert "tangent_static_hi" not in acceleration
    assert_same_frames(acceleration, pd.read_csv(out / "results.csv"))


def test_a_resumed_run_leaves_the_parts_as_they_are(tmp_path):
    out = run(tmp_path)
    parts = sorted((out / "results").glob("part-*.parquet"))
    before = {part: (part.stat().st_mtime_ns, part.read_bytes()) for part in parts}
    run_study(load_study(tmp_path / "study.toml"), out)  # the same study: resumed
    assert sorted((out / "results").glob("part-*.parquet")) == parts
    for part, (stamp, data) in before.items():
        assert part.stat().st_mtime_ns == stamp and part.read_bytes() == data
    assert_same_frames(pd.read_parquet(out / "results"), pd.read_csv(out / "results.csv"))


def test_a_path_without_velocities_has_no_tangent_columns(tmp_path):
    out = run(tmp_path, velocities=False)
    dataset = pd.read_parquet(out / "results")
    assert not [name for name in dataset.columns if str(name).startswith("tangent_")]
    assert_same_frames(dataset, pd.read_csv(out / "results.csv"))
    assert not (out / "tangent_limits.png").exists()


def test_the_tangent_figure_refuses_results_without_tangent_columns():
    """A plain sweep's frame has no tangent limits: an InputError naming results."""
    from polyell.figures import plot_tangent_limits

    frame = pe.sweep(ARM, pe.grid(np.pi / 2, (-np.pi, np.pi, 3), (-np.pi, np.pi, 3)))
    with pytest.raises(pe.InputError) as error:
        plot_tangent_limits(frame)
    assert error.value.argument == "results"
    assert "tangent_" in str(error.value) and "[trajectory]" in error.value.fix
    assert "tangent_limits" in error.value.fix


def test_the_tangent_figure_refuses_half_an_interval_and_names_the_capacity():
    from polyell.figures import plot_tangent_limits

    base = {"t": [0.0, 1.0]}
    half = pd.DataFrame(base | {"tangent_polytope_lo": [-1.0, -2.0]})
    with pytest.raises(pe.InputError) as error:
        plot_tangent_limits(half)
    assert error.value.argument == "results" and "tangent_polytope_hi" in str(error.value)
    force = pd.DataFrame(base | {"tangent_static_lo": [-1.0, -2.0], "tangent_static_hi": [1, 2]})
    with pytest.raises(pe.InputError) as error:
        plot_tangent_limits(force)
    assert error.value.argument == "results" and "capacity='force'" in error.value.fix
    figure = plot_tangent_limits(force, capacity="force", unit="N")
    assert len(figure.axes[0].lines) == 2 + 1  # both ends, and the zero line
