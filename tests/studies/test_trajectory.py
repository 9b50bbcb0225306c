"""Trajectories from files: reading, malformed files, sweeps, tangent limits, studies."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.studies import load_study, run_study
from polyell.studies.trajectory import load_trajectory, tangent_limits

ARM = pe.robots.load("chiacchio2000")
T = np.linspace(0.0, 2.0, 41)


def path() -> tuple[np.ndarray, np.ndarray]:
    """q(t) = q0 + A sin(w t), with its exact derivative; still at t = pi/2w (qd = 0)."""
    q0, A, w = np.array([1.2, -1.0, -0.8]), np.array([0.5, 0.4, 0.6]), np.pi / 2
    q = q0 + A * np.sin(w * T)[:, None]
    qd = A * w * np.cos(w * T)[:, None]
    return q, qd


def frame() -> pd.DataFrame:
    q, qd = path()
    table = {"t": T} | {f"q{i + 1}": q[:, i] for i in range(3)}
    return pd.DataFrame(table | {f"qd{i + 1}": qd[:, i] for i in range(3)})


@pytest.mark.parametrize("suffix", [".csv", ".parquet", ".npy", ".npz"])
def test_every_format_reads_the_same_path(tmp_path, suffix):
    q, qd = path()
    file = tmp_path / f"path{suffix}"
    if suffix == ".csv":
        frame().to_csv(file, index=False)
    elif suffix == ".parquet":
        frame().to_parquet(file)
    elif suffix == ".npy":
        np.save(file, q)
    else:
        np.savez(file, q=q, qd=qd, t=T)
    trajectory = load_trajectory(file, 3)
    np.testing.assert_allclose(trajectory.q, q, rtol=1e-15)
    if suffix != ".npy":
        np.testing.assert_allclose(trajectory.qd, qd, rtol=1e-15)
        np.testing.assert_allclose(trajectory.t, T, rtol=1e-15)
    else:
        assert trajectory.qd is None and trajectory.t is None


@pytest.mark.parametrize(
    ("edit", "fragment"),
    [
        (lambda f: f.drop(columns="q3"), "without ['q3']"),
        (lambda f: f.assign(q4=0.0), "also ['q4']"),
        (lambda f: f.drop(columns="qd2"), "all of qd1..qd3 or none"),
        (lambda f: f.assign(q2=f["q2"].where(f.index != 5)), "empty cell at row 5 (line 7), column q2"),
        (lambda f: f.assign(t=f["t"].where(f.index != 7, 0.1)), "at row 7"),
        (lambda f: f.assign(t=f["t"].where(f.index != 9, f["t"][8])), "at row 9"),
        (lambda f: f.assign(q1="x"), "a decimal number in every cell of column q1"),
        (lambda f: f.iloc[:0], "1 to 10,000,000 samples"),
    ],
)
def test_malformed_files_name_the_row_and_column(tmp_path, edit, fragment):
    file = tmp_path / "bad.csv"
    edit(frame()).to_csv(file, index=False)
    with pytest.raises(pe.InputError, match=r"bad\.csv") as info:
        load_trajectory(file, 3)
    assert fragment in str(info.value)


def test_other_bad_files(tmp_path):
    with pytest.raises(pe.InputError, match="an existing file"):
        load_trajectory(tmp_path / "none.csv", 3)
    (tmp_path / "path.txt").write_text("q1\n0\n")
    with pytest.raises(pe.InputError, match=r"\.csv, \.parquet, \.npy or \.npz"):
        load_trajectory(tmp_path / "path.txt", 3)
    np.save(tmp_path / "wide.npy", np.zeros((4, 5)))
    with pytest.raises(pe.InputError, match=r"shape \(K, 3\)"):
        load_trajectory(tmp_path / "wide.npy", 3)
    (tmp_path / "torn.parquet").write_bytes(b"PAR1 not really")
    with pytest.raises(pe.InputError, match="a readable trajectory file"):
        load_trajectory(tmp_path / "torn.parquet", 3)


def test_a_trajectory_is_a_sweep_input_with_time(tmp_path):
    file = tmp_path / "path.csv"
    frame().to_csv(file, index=False)
    trajectory = load_trajectory(file, 3)
    along = pe.sweep(ARM, trajectory, directions=16)
    plain = pe.sweep(ARM, trajectory.q, directions=16)
    np.testing.assert_allclose(along["t"], T)
    pd.testing.assert_frame_equal(along.drop(columns="t"), plain)


def test_tangent_limits_follow_the_task_velocity(tmp_path):
    file = tmp_path / "path.npz"
    q, qd = path()
    np.savez(file, q=q, qd=qd, t=T)
    trajectory = load_trajectory(file, 3)
    columns = tangent_limits(ARM, trajectory)
    for k in (0, 13, 27, 40):
        J = ARM.dynamics(q[k]).J
        tangent = J @ qd[k] / np.linalg.norm(J @ qd[k])
        analysis = pe.analyze(ARM.dynamics(q[k]), ARM.tau_max)
        lo, hi = analysis.polytope.limits(tangent)
        assert columns["tangent_polytope_lo"][k] == pytest.approx(lo, rel=1e-9)
        assert columns["tangent_polytope_hi"][k] == pytest.approx(hi, rel=1e-9)
        lo, hi = analysis.ellipsoid("chiacchio").limits(tangent)
        assert columns["tangent_chiacchio_hi"][k] == pytest.approx(hi, rel=1e-9)
    still = np.flatnonzero(np.abs(np.cos(np.pi / 2 * T)) < 1e-12)  # qd = 0 at t = 1
    assert still.size == 1 and np.isnan(columns["tangent_polytope_hi"][still[0]])


def test_a_trajectory_study_writes_series_and_tangent_limits(tmp_path):
    frame().to_csv(tmp_path / "path.csv", index=False)
    spec = tmp_path / "study.toml"
    spec.write_text(
        'title = "path"\n[robot]\nlibrary = "chiacchio2000"\n[trajectory]\nfile = "path.csv"\n'
        "[compare]\ndirections = 16\nmvie = true\n"
        '[output]\nformats = ["png"]\ndpi = 30\nseries = ["coverage", "mvie_ratio"]\n'
    )
    out = tmp_path / "out"
    run_study(load_study(spec), out)
    results = pd.read_csv(out / "results.csv")
    assert len(results) == 41 and np.allclose(results["t"], T)
    assert {"tangent_polytope_lo", "tangent_yoshikawa_hi"} <= set(results)
    files = json.loads((out / "manifest.json").read_text())["files"]
    for name in ("series_coverage.png", "series_mvie_ratio.png", "tangent_limits.png"):
        assert name in files and (out / name).stat().st_size > 0


def test_trajectory_study_errors(tmp_path):
    base = '[robot]\nlibrary = "chiacchio2000"\n'
    spec = tmp_path / "s.toml"
    spec.write_text(base + '[trajectory]\nfile = "missing.csv"\n')
    with pytest.raises(pe.InputError, match="an existing file"):
        load_study(spec)
    spec.write_text(base + '[trajectory]\nfile = "p.csv"\nformat = "csv"\n')
    with pytest.raises(pe.InputError, match="unknown key"):
        load_study(spec)
    spec.write_text(base + '[random]\ncount = 3\n[output]\nseries = ["coverage"]\n')
    with pytest.raises(pe.InputError, match=r"output\.series: expected a \[trajectory\] study"):
        load_study(spec)
