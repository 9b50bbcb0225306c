"""Seeded fuzz of trajectory files (issue 20): damaged CSV bytes, mutated Parquet, NumPy
files with mutated headers, truncated files.  Every one is either read as a valid
trajectory or refused with a PolyellError — never another exception, and never a warning."""

from __future__ import annotations

import io
import warnings

import numpy as np
import pandas as pd
import pytest

from polyell.errors import PolyellError
from polyell.studies.trajectory import MAX_JOINT_VALUE, Trajectory, load_trajectory

N = 3
ROWS = 12
CASES = 300  # per format: well under a second each


def base_files() -> dict[str, bytes]:
    rng = np.random.default_rng(2020)
    q = rng.uniform(-3.0, 3.0, (ROWS, N))
    qd = rng.normal(size=(ROWS, N))
    t = np.cumsum(rng.uniform(0.01, 0.1, ROWS))
    table = pd.DataFrame(
        {"t": t}
        | {f"q{i + 1}": q[:, i] for i in range(N)}
        | {f"qd{i + 1}": qd[:, i] for i in range(N)}
    )
    files = {".csv": table.to_csv(index=False).encode()}
    buffer = io.BytesIO()
    table.assign(t=pd.to_timedelta(t, unit="s")).to_parquet(buffer)
    files[".parquet"] = buffer.getvalue()
    buffer = io.BytesIO()
    np.save(buffer, q)
    files[".npy"] = buffer.getvalue()
    buffer = io.BytesIO()
    np.savez(buffer, q=q, qd=qd, t=t)
    files[".npz"] = buffer.getvalue()
    return files


def mutate(data: bytes, rng: np.random.Generator, suffix: str) -> bytes:
    """One of: flip bytes, truncate, insert, delete, or (text and headers) edit a token."""
    data = bytearray(data)
    kind = rng.integers(6)
    if kind == 0:  # flip 1-4 bytes
        for _ in range(rng.integers(1, 5)):
            data[rng.integers(len(data))] = rng.integers(256)
    elif kind == 1:  # truncate
        del data[rng.integers(len(data)) :]
    elif kind == 2:  # insert random or structural bytes
        at = rng.integers(len(data) + 1)
        pieces = [b",", b"\n", b"-", b"e999", b"nan", b"\x00", b"9" * 30, bytes(rng.bytes(4))]
        data[at:at] = pieces[rng.integers(len(pieces))]
    elif kind == 3:  # delete a span
        at = rng.integers(len(data))
        del data[at : at + rng.integers(1, 16)]
    elif kind == 4 and suffix in (".npy", ".npz"):  # edit the .npy header's text
        text = bytes(data)
        start = text.find(b"{'descr'")
        if start >= 0:
            end = text.find(b"}", start) + 1
            header = text[start:end]
            edits = [
                (b"<f8", b"|O"),
                (b"<f8", b"<c16"),
                (b"<f8", b">f8"),
                (b"<f8", b"<f4"),
                (b"False", b"True"),
                (f"({ROWS}, {N})".encode(), b"(1000000000000, 3)"),
                (f"({ROWS}, {N})".encode(), f"({ROWS + 1}, {N})".encode()),
                (f"({ROWS}, {N})".encode(), b"(-1, 3)"),
                (b"'shape'", b"'shapes'"),
            ]
            old, new = edits[rng.integers(len(edits))]
            new_header = header.replace(old, new).ljust(len(header))[: len(header)]
            data[start:end] = new_header
    else:  # duplicate a span (a repeated row, a repeated header name)
        at = rng.integers(len(data))
        data[at:at] = data[at : at + rng.integers(1, 40)]
    return bytes(data)


def check_valid(trajectory: Trajectory) -> None:
    """The invariants of a trajectory that was accepted."""
    assert trajectory.q.ndim == 2 and trajectory.q.shape[1] == N and len(trajectory.q) >= 1
    assert trajectory.q.dtype == np.float64
    assert np.isfinite(trajectory.q).all() and (np.abs(trajectory.q) <= MAX_JOINT_VALUE).all()
    if trajectory.qd is not None:
        assert trajectory.qd.shape == trajectory.q.shape and np.isfinite(trajectory.qd).all()
    if trajectory.t is not None:
        assert trajectory.t.shape == (len(trajectory.q),) and np.isfinite(trajectory.t).all()
        assert (trajectory.t[1:] > trajectory.t[:-1]).all()


@pytest.mark.parametrize("suffix", [".csv", ".parquet", ".npy", ".npz"])
def test_mutated_trajectory_files_are_read_or_refused(tmp_path, suffix):
    original = base_files()[suffix]
    rng = np.random.default_rng([20, len(suffix)])
    outcomes = {"read": 0, "refused": 0}
    for case in range(CASES):
        data = mutate(original, rng, suffix)
        file = tmp_path / f"case{case}{suffix}"
        file.write_bytes(data)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            try:
                trajectory = load_trajectory(file, N)
            except PolyellError as exn:
                assert file.name in str(exn)
                outcomes["refused"] += 1
                continue
        check_valid(trajectory)
        outcomes["read"] += 1
    assert outcomes["refused"] > 0  # the mutations do reach the checks
