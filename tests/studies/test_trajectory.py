"""Trajectories from files: reading, malformed files, sweeps, tangent limits, studies."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.studies import load_study, run_study
from polyell.studies.trajectory import Trajectory, load_trajectory, tangent_limits

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
        (
            lambda f: f.assign(q2=f["q2"].where(f.index != 5)),
            "empty cell at row 5 (line 7), column q2",
        ),
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


# --- columns by name, with units (issue 20) ---------------------------------------------

Q = np.random.default_rng(20).uniform(-2.0, 2.0, (6, 3))
TIME_S = np.array([0.0, 0.25, 0.5, 1.0, 2.0, 4.0])
COUNTS = np.array([0, 1, 3, 4, 8, 9], dtype=np.int64) * 250  # time in ticks of a unit


def q_columns(q=Q) -> dict[str, np.ndarray]:
    return {f"q{i + 1}": q[:, i] for i in range(3)}


@pytest.mark.parametrize("unit", ["s", "ms", "us", "ns"])
def test_parquet_durations_are_seconds_by_their_unit(tmp_path, unit):
    import pyarrow as pa
    import pyarrow.parquet as pq

    ticks = {"s": 1, "ms": 10**3, "us": 10**6, "ns": 10**9}[unit]
    file = tmp_path / "d.parquet"
    pq.write_table(pa.table({"t": pa.array(COUNTS, pa.duration(unit))} | q_columns()), file)
    trajectory = load_trajectory(file, 3)
    # counts / ticks of exact integers is correctly rounded however it is computed
    np.testing.assert_array_equal(trajectory.t, COUNTS / ticks)
    np.testing.assert_array_equal(trajectory.q, Q)


def test_timestamps_are_seconds_after_the_first_sample(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    start = np.datetime64("2026-11-23T12:00:00", "ms")
    stamps = start + (TIME_S * 1000).astype("timedelta64[ms]")
    file = tmp_path / "ts.parquet"
    table = {"t": pa.array(stamps, pa.timestamp("ms", tz="Europe/Rome"))} | q_columns()
    pq.write_table(pa.table(table), file)
    np.testing.assert_array_equal(load_trajectory(file, 3).t, TIME_S)
    np.savez(tmp_path / "ts.npz", q=Q, t=stamps)
    np.testing.assert_array_equal(load_trajectory(tmp_path / "ts.npz", 3).t, TIME_S)


@pytest.mark.parametrize("unit", ["s", "ms", "us"])
def test_npz_timedelta_time_is_seconds_by_its_unit(tmp_path, unit):
    ticks = {"s": 1, "ms": 10**3, "us": 10**6}[unit]
    np.savez(tmp_path / "p.npz", q=Q, t=COUNTS.astype(f"timedelta64[{unit}]"))
    np.testing.assert_array_equal(load_trajectory(tmp_path / "p.npz", 3).t, COUNTS / ticks)


def test_time_without_a_unit_is_refused(tmp_path):
    np.savez(tmp_path / "p.npz", q=Q, t=np.arange(6).astype("timedelta64"))
    with pytest.raises(pe.InputError, match=r"p\.npz.*no unit"):
        load_trajectory(tmp_path / "p.npz", 3)


def csv_text(header: str, rows: list[str]) -> str:
    return "\n".join([header, *rows]) + "\n"


@pytest.mark.parametrize(
    ("header", "rows", "fragment"),
    [
        # one more field than the header: pandas took the first column as the index
        ("t,q1,q2,q3", ["0,0,1,2,3", "1,0,1,2,3"], "4 fields in every row, as in the header"),
        ("t,q1,q2,q3", ["0,1,2,3", "1,1,2"], "got 3 fields at line 3"),
        ("t,q1,q2,q2,q3", ["0,1,2,2,3"], "'q2' as columns 3 and 4"),
        (",t,q1,q2,q3", ["0,0,1,2,3"], "an empty name in column 1"),
        ("t,q1,q2,q3", ["0,1,2,3", "1,1,x,3"], "'x' at row 1 (line 3)"),
        ("t,q1,q2,q3", ["0,1,2,3", "1,1,2_0,3"], "'2_0' at row 1 (line 3)"),
        ("t,q1,q2,q3", ["0,1,2,3", "1,1,2,"], "empty cell at row 1 (line 3), column q3"),
        ("t,q1,q2,q3", ["0,1,2,3", "1,1,inf,3"], "inf at row 1 (line 3), column q2"),
        ("t,q1,q2,q3", ["0,1,2,3", "0,1,2,3"], "t = 0.0 at row 1 (line 3) after 0.0"),
        ("t,q1,q2,q3", ["0,1e308,2,3"], "within +-1e+08 in column q1"),
        ("t,q1,q2,q3", ['0,"1,5",2,3'], "4 fields in every row"),
    ],
)
def test_ambiguous_csv_is_refused_naming_the_line(tmp_path, header, rows, fragment):
    file = tmp_path / "p.csv"
    file.write_text(csv_text(header, rows))
    with pytest.raises(pe.InputError, match=r"p\.csv") as info:
        load_trajectory(file, 3)
    assert fragment in str(info.value)


def test_csv_columns_are_read_by_name_in_any_order(tmp_path):
    _, qd = path()
    order = ["qd2", "q3", "note", "t", "q1", "qd1", "qd3", "q2"]
    table = frame().assign(note=7.0)[order]
    table.to_csv(tmp_path / "p.csv", index=False)
    trajectory = load_trajectory(tmp_path / "p.csv", 3)
    np.testing.assert_array_equal(trajectory.q, pd.read_csv(tmp_path / "p.csv")[["q1", "q2", "q3"]])
    np.testing.assert_array_equal(trajectory.qd, qd)  # to_csv writes the shortest round-trip
    (tmp_path / "blank.csv").write_text('\ufeffq1, q2 ,"q3"\r\n\r\n1,2,3\r\n\r\n')
    np.testing.assert_array_equal(load_trajectory(tmp_path / "blank.csv", 3).q, [[1, 2, 3]])


def write_npy_header(file, shape, descr="<f8", data=b""):
    with open(file, "wb") as handle:
        header = {"descr": descr, "fortran_order": False, "shape": shape}
        np.lib.format.write_array_header_1_0(handle, header)
        handle.write(data)


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda f: write_npy_header(f, (10**12, 3), data=b"\0" * 48), "1,000,000,000,000 samples"),
        (
            lambda f: write_npy_header(f, (4, 3), data=b"\0" * 40),
            "224 bytes for its header's shape (4, 3) of float64, got 168",
        ),
        (lambda f: write_npy_header(f, (4, 3), data=b"\0" * 200), "shape (4, 3) of float64"),
        (lambda f: write_npy_header(f, (0, 3)), "got 0 samples"),
        (lambda f: f.write_bytes(b""), "damaged or mislabelled"),
        (lambda f: f.write_bytes(b"q1,q2,q3\n1,2,3\n"), "damaged or mislabelled"),
        (lambda f: np.save(f, np.array([[1, 2, None]], object), allow_pickle=True), "pickle"),
        (lambda f: np.save(f, np.zeros((2, 3), complex)), "dtype complex128"),
        (lambda f: np.save(f, np.zeros((2, 3), "U2")), "dtype <U2"),
        (lambda f: np.save(f, np.zeros(3)), "shape (3,)"),
    ],
)
def test_damaged_npy_files_are_refused_from_the_header(tmp_path, make, fragment):
    file = tmp_path / "p.npy"
    make(file)
    with pytest.raises(pe.InputError, match=r"p\.npy") as info:
        load_trajectory(file, 3)
    assert fragment in str(info.value)


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda f: f.write_bytes(b"q1,q2,q3\n1,2,3\n"), "not a zip file"),
        (lambda f: f.write_bytes(b""), "damaged or mislabelled"),
        (lambda f: np.savez(f, x=Q), "an array 'q'"),
        (lambda f: np.savez(f, q=np.array([[1, 2, None]], object)), "pickle"),
        (lambda f: np.savez(f, q=Q, qd=Q[:3]), "qd of shape (6, 3)"),
        (lambda f: np.savez(f, q=Q, t=TIME_S[:2]), "t of shape (6,)"),
        (lambda f: np.savez(f, q=Q.astype("datetime64[s]")), "dtype datetime64[s]"),
        (lambda f: f.write_bytes(_npz_bytes()[:-30]), "damaged or mislabelled"),
    ],
)
def test_damaged_npz_files_are_refused(tmp_path, make, fragment):
    file = tmp_path / "p.npz"
    make(file)
    with pytest.raises(pe.InputError, match=r"p\.npz") as info:
        load_trajectory(file, 3)
    assert fragment in str(info.value)


def _npz_bytes() -> bytes:
    import io

    buffer = io.BytesIO()
    np.savez(buffer, q=Q, t=TIME_S)
    return buffer.getvalue()


def test_fortran_ordered_and_compressed_arrays_read_the_same(tmp_path):
    q, qd = path()
    np.save(tmp_path / "f.npy", np.asfortranarray(q))
    np.testing.assert_array_equal(load_trajectory(tmp_path / "f.npy", 3).q, q)
    np.savez_compressed(tmp_path / "c.npz", q=np.asfortranarray(q), qd=qd, t=T)
    trajectory = load_trajectory(tmp_path / "c.npz", 3)
    np.testing.assert_array_equal(trajectory.q, q)
    np.testing.assert_array_equal(trajectory.qd, qd)
    np.testing.assert_array_equal(trajectory.t, T)


@pytest.mark.parametrize(
    ("make", "fragment"),
    [
        (lambda f: f.write_bytes(_parquet_bytes()[:-100]), "damaged or mislabelled"),
        (lambda f: f.write_bytes(b"PAR1" + b"\0" * 64 + b"PAR1"), "damaged or mislabelled"),
        (lambda f: pd.DataFrame({"q1": ["a"], "q2": [1.0], "q3": [1.0]}).to_parquet(f), "string"),
        (
            lambda f: pd.DataFrame({"t": ["x"]} | q_columns(Q[:1])).to_parquet(f),
            "column t, got type",
        ),
        (lambda f: pd.DataFrame({"q1": [1, None], "q2": 1.0, "q3": 1.0}).to_parquet(f), "nan"),
    ],
)
def test_damaged_parquet_files_are_refused(tmp_path, make, fragment):
    file = tmp_path / "p.parquet"
    make(file)
    with pytest.raises(pe.InputError, match=r"p\.parquet") as info:
        load_trajectory(file, 3)
    assert fragment in str(info.value)


def _parquet_bytes() -> bytes:
    import io

    buffer = io.BytesIO()
    pd.DataFrame({"t": TIME_S} | q_columns()).to_parquet(buffer)
    return buffer.getvalue()


def test_duplicate_parquet_names_are_refused(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_arrays([Q[:, 0], Q[:, 1], Q[:, 1], Q[:, 2]], ["q1", "q2", "q2", "q3"])
    pq.write_table(table, tmp_path / "p.parquet")
    with pytest.raises(pe.InputError, match="'q2' as columns 2 and 3"):
        load_trajectory(tmp_path / "p.parquet", 3)


# --- 1e308 (issue 20) --------------------------------------------------------------------


def test_huge_values_give_the_right_answer_or_a_refusal(tmp_path, recwarn):
    """q beyond MAX_JOINT_VALUE is refused; huge velocities and times are exact."""
    q, qd = path()
    np.savez(tmp_path / "q.npz", q=np.where(np.arange(41)[:, None] == 3, 1e308, q))
    with pytest.raises(pe.InputError, match=r"1e\+308 at row 3"):
        load_trajectory(tmp_path / "q.npz", 3)
    # The tangent is the direction of J qd: scaling qd by 2^1000 changes nothing (exact
    # in binary), and must not overflow to inf or NaN.
    big = qd * 2.0**1000
    times = T * 2.0**1000  # t up to 2^1001 ~ 2e301, strictly increasing
    np.savez(tmp_path / "big.npz", q=q, qd=big, t=times)
    trajectory = load_trajectory(tmp_path / "big.npz", 3)
    np.testing.assert_array_equal(trajectory.t, times)
    np.savez(tmp_path / "plain.npz", q=q, qd=qd, t=T)
    plain = tangent_limits(ARM, load_trajectory(tmp_path / "plain.npz", 3))
    for name, values in tangent_limits(ARM, trajectory).items():
        np.testing.assert_array_equal(values, plain[name])
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


def test_one_fast_sample_leaves_the_others_tangents_alone(tmp_path):
    """Each sample's tangent is J qd / |J qd| of its own velocities: a sample at 1e300 rad/s
    (the path's largest) no longer flushes the others' J qd to 0 (their limits were NaN)."""
    q, qd = path()
    fast = qd.copy()
    fast[0] = 1e300 * np.sign(qd[0] + 0.5)
    np.savez(tmp_path / "fast.npz", q=q, qd=fast)
    mixed = tangent_limits(ARM, load_trajectory(tmp_path / "fast.npz", 3))
    plain = tangent_limits(ARM, Trajectory(q, qd))
    for name, values in mixed.items():
        np.testing.assert_allclose(values[1:], plain[name][1:], rtol=1e-13, atol=0)
        assert np.isfinite(values[1:]).any()
    # the fast sample's own tangent: the direction of J sign(qd_0), by its own polytope
    dyn = ARM.dynamics(q[0])
    t = dyn.J @ np.sign(qd[0] + 0.5)
    expected = pe.analyze(dyn, ARM.tau_max).polytope.limits(t / np.linalg.norm(t))
    np.testing.assert_allclose(
        [mixed["tangent_polytope_lo"][0], mixed["tangent_polytope_hi"][0]],
        [expected.lo, expected.hi], rtol=1e-12,
    )  # fmt: skip
