"""Trajectories from files: configurations (and velocities, time) a user already has.

A trajectory file holds one row per sample.  Columns are read **by name**, never by
position:

* ``q1 .. qn``: joint angles [rad] (or [m] for a prismatic joint), required;
* ``qd1 .. qdn``: joint velocities [rad/s], optional (all of them or none);
* ``t``: time, optional, strictly increasing.  A plain number is seconds.  A *duration*
  (Parquet ``duration[s|ms|us|ns]``, NumPy ``timedelta64``) is converted by its own unit
  to seconds.  A *timestamp* (Parquet ``timestamp``, NumPy ``datetime64``) is converted to
  seconds after the first sample (so the first sample has ``t = 0``).

Other columns are ignored.  Formats:

* CSV: a header row of distinct names, then one line per sample with exactly as many
  fields as the header (blank lines are skipped); every cell of a used column a decimal
  number.  Errors name the file's line.
* Parquet: named columns of integer, floating-point, decimal, duration or timestamp type.
* ``.npy``: one plain numeric array (K, n) of joint angles.
* ``.npz``: arrays ``q`` (K, n), optionally ``qd`` (K, n) and ``t`` (K,).  Arrays are read
  without pickle (object arrays are refused); sizes are checked from each array's header
  against the file before anything is loaded.

Anything ambiguous is refused with an :class:`~polyell.errors.InputError` naming the file,
the column or row and the fix: rows with more or fewer fields than the header, repeated
names, cells that are not numbers, NaN or infinity, time that does not increase, joint
values beyond :data:`MAX_JOINT_VALUE`, more than :data:`MAX_SAMPLES` samples or
:data:`MAX_VALUES` values, damaged, truncated or mislabelled files.

A :class:`Trajectory` is a configuration set: :func:`polyell.sweep` takes it like a grid.
"""

from __future__ import annotations

import os
import re
import struct
import warnings
import zipfile
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path
from tokenize import TokenError
from typing import IO, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.capacities import capacity_class, joint_limits_of
from polyell.errors import InputError
from polyell.studies.along import limits_along
from polyell.studies.configurations import ConfigurationSet
from polyell.validation import check_array, check_integer

__all__ = [
    "MAX_JOINT_VALUE",
    "MAX_SAMPLES",
    "MAX_VALUES",
    "Trajectory",
    "load_trajectory",
    "tangent_limits",
]

#: Most samples of a trajectory file.
MAX_SAMPLES = 10_000_000
#: Most float64 values a trajectory holds in memory (q, qd and t together: 2 GiB).
MAX_VALUES = 2**28
#: Largest |q| accepted [rad or m].  The spacing of float64 numbers at 1e8 is 1.5e-8, so
#: beyond it the stored angle itself is uncertain by more than 1e-8 rad (and at 1e308 its
#: sine is meaningless); no physical joint travels 1e8 rad or m within one path.
MAX_JOINT_VALUE = 1e8
#: Rows converted at a time while reading (bounds the temporary memory of a reader).
_READ_BLOCK = 1 << 16
#: A CSV cell: a decimal number (also nan/inf, refused afterwards with its row).
_NUMBER = re.compile(rb"[+-]?(?:\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?|nan|inf)", re.I)


def _float_rows(name: str, value: object, shape: tuple[int, ...] | None) -> NDArray[np.float64]:
    """A float64 array (kept as is when it is one: no copy of a long path) of ``shape``.

    ``shape`` None: any (K, n) with n >= 1.  Values are checked by :func:`load_trajectory`;
    other arrays are checked here (finite).
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        array: NDArray[np.float64] = value
    else:
        array = check_array(
            name, cast(ArrayLike, value), (None,) * (2 if shape is None else len(shape))
        )
    wrong = array.ndim != 2 or array.shape[1] == 0 if shape is None else array.shape != shape
    if wrong:
        expected = "shape (K, n)" if shape is None else f"shape {shape}"
        raise InputError(
            name,
            f"an array of {expected}",
            f"shape {array.shape}",
            "pass one row per sample and one column per joint, e.g. q of shape (K, robot.n)"
            if shape is None
            else f"pass {name} with one entry per sample of q, shape {shape}",
        )
    return array


class Trajectory(ConfigurationSet):
    """Samples of a path: joint angles, and optionally velocities and time.

    Use :func:`load_trajectory` to read one from a file (it checks every value).

    Attributes
    ----------
    q : ndarray, shape (K, n)
        Joint angles [rad].
    qd : ndarray, shape (K, n), or None
        Joint velocities [rad/s].
    t : ndarray, shape (K,), or None
        Time [s], strictly increasing.
    source : str
        The file it came from (for messages).
    """

    def __init__(
        self,
        q: NDArray[np.float64],
        qd: NDArray[np.float64] | None = None,
        t: NDArray[np.float64] | None = None,
        source: str = "trajectory",
    ) -> None:
        if not isinstance(source, str):
            raise InputError(
                "source",
                "the name of the file (str)",
                repr(source)[:80],
                "pass the file's name as a string, e.g. source='path.csv'.",
            )
        q = _float_rows("q", q, None)
        qd = None if qd is None else _float_rows("qd", qd, q.shape)
        t = None if t is None else _float_rows("t", t, q.shape[:1])
        self.q, self.qd, self.t, self.source = q, qd, t, source
        self.n = q.shape[1]

    def __len__(self) -> int:
        return len(self.q)

    def rows(self, start: int, stop: int) -> NDArray[np.float64]:
        """Joint angles of samples ``start`` to ``stop - 1``."""
        return self.q[start:stop]

    def __repr__(self) -> str:
        extras = [name for name in ("qd", "t") if getattr(self, name) is not None]
        return f"Trajectory({self.source!r}, samples={len(self)}, n={self.n}, with={extras})"


# ----------------------------------------------------------------------------- columns


def _bad(source: str, expected: str, got: str, fix: str) -> InputError:
    return InputError(source, expected, got, fix)


def _wanted(source: str, names: list[str], n: int) -> list[str]:
    """The columns to read among a file's ``names``: q1..qn, then qd1..qdn and t if present."""
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            raise _bad(
                source,
                "distinct column names",
                f"{name!r} as columns {seen[name] + 1} and {i + 1}",
                "rename or drop one of them (which one holds the values is ambiguous).",
            )
        seen[name] = i
    q_names = [f"q{i + 1}" for i in range(n)]
    missing = [name for name in q_names if name not in seen]
    if missing:
        raise _bad(
            source,
            f"columns {q_names[0]}..{q_names[-1]} (joint angles) for the robot's {n} joints",
            f"columns {names[:12]}{'...' if len(names) > 12 else ''}, without {missing}",
            "name the columns q1..qn (and qd1..qdn, t if you have them).",
        )
    joint = re.compile(r"qd?([1-9]\d*)")
    extra = sorted(
        {name for name in names if (match := joint.fullmatch(name)) and int(match.group(1)) > n}
    )
    if extra:
        raise _bad(source, f"{n} joint columns for this robot", f"also {extra}", "check the robot.")
    qd_names = [f"qd{i + 1}" for i in range(n)]
    has_qd = [name in seen for name in qd_names]
    if any(has_qd) and not all(has_qd):
        raise _bad(
            source,
            f"all of {qd_names[0]}..{qd_names[-1]} or none",
            f"only {[name for name, h in zip(qd_names, has_qd, strict=True) if h]}",
            "add the missing velocity columns, or drop the others.",
        )
    return q_names + (qd_names if all(has_qd) else []) + (["t"] if "t" in seen else [])


def _check_count(source: str, samples: int, columns: int) -> None:
    """Refuse an empty trajectory, or one too large to hold, before it is read."""
    if not 1 <= samples <= MAX_SAMPLES or samples * columns > MAX_VALUES:
        most = min(MAX_SAMPLES, MAX_VALUES // max(columns, 1))
        raise _bad(
            source,
            f"1 to {most:,} samples ({columns} columns of float64 held in memory)",
            f"{samples:,} samples",
            "give at least one sample; split a longer path into several files (studies).",
        )


def _seconds(source: str, values: NDArray[Any], origin: Any) -> NDArray[np.float64]:
    """Time in seconds: numbers as they are, durations by their unit, timestamps from the first.

    ``origin`` is the first timestamp of the file (for ``datetime64`` values).
    """
    if values.dtype.kind in "mM" and np.datetime_data(values.dtype)[0] == "generic":
        raise _bad(
            source,
            "time t as seconds, or a duration or timestamp with a unit (s, ms, us, ns...)",
            f"dtype {values.dtype} (no unit)",
            "store t as float seconds, or give the unit: np.array(t, 'timedelta64[ms]').",
        )
    try:
        if values.dtype.kind == "m":
            return values / np.timedelta64(1, "s")  # NaT -> NaN (refused with its row)
        if values.dtype.kind == "M":
            return (values - origin) / np.timedelta64(1, "s")
    except (TypeError, ValueError, OverflowError):  # a generic unit has no length
        raise _bad(
            source,
            "time t as seconds, a duration or a timestamp with a unit (s, ms, us, ns...)",
            f"dtype {values.dtype}",
            "store t as float seconds.",
        ) from None
    return values.astype(np.float64)


def _finite(
    source: str, name: str, values: NDArray[np.float64], label: Callable[[int], str]
) -> None:
    """Refuse NaN, infinity and joint values beyond MAX_JOINT_VALUE in one block."""
    bad = ~np.isfinite(values)
    joint = name.startswith("q") and not name.startswith("qd")
    if joint:
        bad |= np.abs(np.where(bad, 0.0, values)) > MAX_JOINT_VALUE
    if not bad.any():
        return
    k = int(np.flatnonzero(bad)[0])
    value = values[k]
    if np.isfinite(value):
        raise _bad(
            source,
            f"joint values within +-{MAX_JOINT_VALUE:g} in column {name}",
            f"{value:g} at {label(k)}",
            "joint angles are in rad (metres for prismatic joints): check the unit and the column.",
        )
    raise _bad(
        source,
        "finite numbers in every row",
        f"{value} at {label(k)}, column {name}",
        "remove or fill the row.",
    )


class _Columns:
    """Blocks of checked float64 columns, gathered into a :class:`Trajectory`."""

    def __init__(self, source: str, names: list[str]) -> None:
        self.source, self.names = source, names
        self.blocks: dict[str, list[NDArray[np.float64]]] = {name: [] for name in names}
        self.samples = 0
        self.last_t: float | None = None

    def add(
        self, block: dict[str, NDArray[np.float64]], lines: NDArray[np.int64] | None = None
    ) -> None:
        """Append a block of rows (``lines``: their lines in a text file, for messages)."""
        count = len(next(iter(block.values())))
        first = self.samples

        def label(k: int) -> str:
            return f"row {first + k}" + ("" if lines is None else f" (line {int(lines[k])})")

        for name in self.names:
            _finite(self.source, name, block[name], label)
            self.blocks[name].append(block[name])
        if "t" in block and count:
            t = block["t"]
            offset = 0 if self.last_t is None else 1
            full = t if self.last_t is None else np.concatenate([[self.last_t], t])
            steps = np.flatnonzero(full[1:] <= full[:-1])
            if steps.size:
                k = int(steps[0]) + 1  # index in full
                raise _bad(
                    self.source,
                    "strictly increasing time in column t",
                    f"t = {full[k]} at {label(k - offset)} after {full[k - 1]}",
                    "sort the samples by time and drop duplicates.",
                )
            self.last_t = float(t[-1])
        self.samples += count
        _check_count(self.source, max(self.samples, 1), len(self.names))

    def trajectory(self, n: int) -> Trajectory:
        _check_count(self.source, self.samples, len(self.names))

        def stacked(names: list[str]) -> NDArray[np.float64]:
            out = np.empty((self.samples, len(names)))
            for j, name in enumerate(names):
                out[:, j] = np.concatenate(self.blocks.pop(name))
            return out

        q = stacked([f"q{i + 1}" for i in range(n)])
        qd = stacked([f"qd{i + 1}" for i in range(n)]) if f"qd{n}" in self.names else None
        t = stacked(["t"])[:, 0] if "t" in self.names else None
        return Trajectory(q, qd, t, self.source)


# ----------------------------------------------------------------------------- CSV


def _csv_cells(line: bytes) -> list[bytes]:
    return [cell.strip().strip(b'"').strip() for cell in line.split(b",")]


def _read_csv(file: Path, source: str, n: int) -> Trajectory:
    with open(file, "rb") as handle:
        header_line = b""
        line_number = 0
        for raw in handle:
            line_number += 1
            if raw.strip():
                header_line = raw
                break
        try:
            header = header_line.decode("utf-8-sig")
        except UnicodeDecodeError:
            raise _bad(
                source,
                "a UTF-8 header row of column names",
                "bytes that are not UTF-8 text",
                "save the file as UTF-8 CSV.",
            ) from None
        names = [cell.strip().strip('"').strip() for cell in header.split(",")]
        if not header.strip():
            raise _bad(
                source,
                "a header row of column names (q1, q2, ...)",
                "an empty file",
                "start the file with a header row, e.g. q1,q2,q3, then one sample per line.",
            )
        if any(not name for name in names):
            raise _bad(
                source,
                "a name in every field of the header row",
                f"an empty name in column {names.index('') + 1} of line {line_number}",
                "name every column; the first line must be the header (no index column).",
            )
        chosen = _wanted(source, names, n)
        index = [names.index(name) for name in chosen]
        width = len(names)
        columns = _Columns(source, chosen)
        while True:
            lines = handle.readlines(1 << 22)
            if not lines:
                break
            cells: list[list[bytes]] = []
            labels: list[int] = []
            for raw in lines:
                line_number += 1
                if not raw.strip():
                    continue
                fields = _csv_cells(raw)
                if len(fields) != width:
                    raise _bad(
                        source,
                        f"{width} fields in every row, as in the header",
                        f"{len(fields)} fields at line {line_number}",
                        "remove the extra (or add the missing) fields: an unnamed first "
                        "column (an index) needs a name in the header.",
                    )
                cells.append([fields[i] for i in index])
                labels.append(line_number)
            if cells:
                block = _parse_cells(source, chosen, cells, labels, columns.samples)
                columns.add(block, np.asarray(labels))
    return columns.trajectory(n)


def _parse_cells(
    source: str, names: list[str], cells: list[list[bytes]], labels: list[int], first: int
) -> dict[str, NDArray[np.float64]]:
    """Decimal numbers of a block of CSV rows, by column; a cell that is not one is refused."""
    block: dict[str, NDArray[np.float64]] = {}
    for j, name in enumerate(names):
        column = [row[j] for row in cells]
        for k, cell in enumerate(column):
            if not cell:
                raise _bad(
                    source,
                    "a number in every cell",
                    f"an empty cell at row {first + k} (line {labels[k]}), column {name}",
                    "remove or fill the row.",
                )
            if _NUMBER.fullmatch(cell) is None:
                shown = cell.decode("utf-8", "replace")[:40]
                raise _bad(
                    source,
                    f"a decimal number in every cell of column {name}",
                    f"{shown!r} at row {first + k} (line {labels[k]})",
                    "fix or remove the cell (seconds for t, rad for q, rad/s for qd).",
                )
        block[name] = np.array(column, dtype=np.bytes_).astype(np.float64)
    return block


# ----------------------------------------------------------------------------- Parquet


def _read_parquet(file: Path, source: str, n: int) -> Trajectory:
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        parquet = pq.ParquetFile(file)
        schema = parquet.schema_arrow
        names = [str(name) for name in schema.names]
        chosen = _wanted(source, names, n)
        for name in chosen:
            kind = schema.field(name).type
            numeric = (
                pa.types.is_integer(kind) or pa.types.is_floating(kind) or pa.types.is_decimal(kind)
            )
            timing = name == "t" and (pa.types.is_duration(kind) or pa.types.is_timestamp(kind))
            if not (numeric or timing):
                allowed = "numbers, a duration or a timestamp" if name == "t" else "real numbers"
                raise _bad(
                    source,
                    f"{allowed} in column {name}",
                    f"type {kind}",
                    "store the column as float64 (t: float seconds or a duration).",
                )
        _check_count(source, parquet.metadata.num_rows, len(chosen))
        columns = _Columns(source, chosen)
        first = 0
        origin = None
        for batch in parquet.iter_batches(batch_size=_READ_BLOCK, columns=chosen):
            block = {}
            for name in chosen:
                values = batch.column(name).to_numpy(zero_copy_only=False)
                if values.dtype.kind == "M" and origin is None and len(values):
                    origin = values[0]
                if values.dtype.kind == "O":  # decimals arrive as Python objects
                    values = np.array(values, dtype=np.float64)
                block[name] = _seconds(source, values, origin)
            columns.add(block)
            first += batch.num_rows
        if first != parquet.metadata.num_rows:
            raise _bad(
                source,
                f"{parquet.metadata.num_rows} rows",
                f"{first} read",
                "the file is truncated or damaged: write it again.",
            )
        return columns.trajectory(n)
    except (pa.ArrowException, OSError, ValueError, TypeError, OverflowError) as exn:
        if isinstance(exn, InputError):
            raise
        raise _unreadable(source, "a Parquet file", exn) from None


def _unreadable(source: str, what: str, exn: BaseException) -> InputError:
    text = " ".join(str(exn).split())[:160] or type(exn).__name__
    return _bad(
        source,
        f"a readable trajectory file ({what})",
        f"a damaged or mislabelled file: {text}",
        "write the file again (a truncated copy or a wrong suffix cannot be read).",
    )


# ----------------------------------------------------------------------------- NumPy


def _npy_header(handle: IO[bytes], source: str, label: str) -> tuple[tuple[int, ...], bool, Any]:
    """Shape, Fortran order and dtype from a .npy header (nothing else is read)."""
    fmt = np.lib.format
    try:
        with warnings.catch_warnings():
            # numpy warns when it falls back to parsing a header written by Python 2
            warnings.simplefilter("ignore", UserWarning)
            version = fmt.read_magic(handle)
            if version == (1, 0):
                shape, fortran, dtype = fmt.read_array_header_1_0(handle)
            elif version == (2, 0):
                shape, fortran, dtype = fmt.read_array_header_2_0(handle)
            else:
                raise _bad(
                    source,
                    f"{label}: a .npy array of format version 1 or 2",
                    f"version {version}",
                    "save it again with np.save, which writes version 1 (2 for large headers).",
                )
    except (ValueError, TypeError, KeyError, SyntaxError, TokenError, RecursionError) as exn:
        if isinstance(exn, InputError):
            raise
        # numpy parses the header's text as a Python literal: a damaged one fails anywhere
        raise _unreadable(source, f"a .npy array ({label})", exn) from None
    if dtype.hasobject or dtype.names is not None or dtype.subdtype is not None:
        raise _bad(
            source,
            f"{label}: a plain numeric array (read without pickle)",
            f"dtype {dtype}",
            "save a float64 array: np.save(file, np.asarray(q, dtype=float)).",
        )
    return tuple(int(s) for s in shape), bool(fortran), dtype


def _check_dtype(source: str, label: str, dtype: Any, time: bool) -> None:
    kinds = "fiumM" if time else "fiu"
    if dtype.kind not in kinds:
        allowed = "real numbers, durations or datetimes" if time else "real numbers"
        raise _bad(source, f"{label}: {allowed}", f"dtype {dtype}", "save a float64 array.")


def _read_array(
    handle: IO[bytes],
    size: int,
    source: str,
    label: str,
    wanted: tuple[int | None, ...],
    time: bool = False,
) -> NDArray[Any]:
    """One .npy stream of ``size`` bytes: header checked against the size, then read.

    ``wanted`` is the expected shape, None for any length along that axis.
    """
    shape, fortran, dtype = _npy_header(handle, source, label)
    _check_dtype(source, label, dtype, time)
    if len(shape) != len(wanted) or any(
        w not in (None, s) for w, s in zip(wanted, shape, strict=False)
    ):
        text = ", ".join("K" if w is None else str(w) for w in wanted)
        meaning = ": joint angles" if label in ("q", "the array") else ""
        raise _bad(
            source,
            f"{label} of shape ({text}{',' if len(wanted) == 1 else ''}){meaning}",
            f"shape {shape}",
            "one row per sample, one column per joint of the robot.",
        )
    count = int(np.prod(shape, dtype=object))
    _check_count(source, shape[0], count // shape[0] if shape[0] else 1)
    offset = handle.tell()
    if size != offset + count * dtype.itemsize:
        raise _bad(
            source,
            f"{label}: {offset + count * dtype.itemsize:,} bytes for its header's "
            f"shape {shape} of {dtype}",
            f"{size:,} bytes",
            "the file is truncated or damaged: write it again.",
        )
    data = handle.read(count * dtype.itemsize)
    if len(data) != count * dtype.itemsize:
        raise _bad(
            source,
            f"{label}: {count * dtype.itemsize:,} bytes of data",
            f"{len(data):,}",
            "the file is truncated or damaged: write it again.",
        )
    array = np.frombuffer(data, dtype=dtype, count=count)
    return array.reshape(shape, order="F" if fortran else "C")


def _array_blocks(
    source: str,
    n: int,
    q: NDArray[Any],
    qd: NDArray[Any] | None,
    t: NDArray[Any] | None,
) -> Trajectory:
    chosen = [f"q{i + 1}" for i in range(n)]
    chosen += [f"qd{i + 1}" for i in range(n)] if qd is not None else []
    chosen += ["t"] if t is not None else []
    columns = _Columns(source, chosen)
    origin = t[0] if t is not None and t.dtype.kind == "M" else None
    for start in range(0, len(q), _READ_BLOCK):
        stop = min(start + _READ_BLOCK, len(q))
        block = {f"q{i + 1}": q[start:stop, i].astype(np.float64) for i in range(n)}
        if qd is not None:
            block |= {f"qd{i + 1}": qd[start:stop, i].astype(np.float64) for i in range(n)}
        if t is not None:
            block["t"] = _seconds(source, t[start:stop], origin)
        columns.add(block)
    return columns.trajectory(n)


def _read_npy(file: Path, source: str, n: int) -> Trajectory:
    with open(file, "rb") as handle:
        try:
            q = _read_array(
                handle,
                file.stat().st_size,
                source,
                "the array",
                (None, n),
            )
        except ValueError as exn:
            if isinstance(exn, InputError):
                raise
            raise _unreadable(source, "a .npy array", exn) from None
    return _array_blocks(source, n, q, None, None)


def _read_npz(file: Path, source: str, n: int) -> Trajectory:
    try:
        with zipfile.ZipFile(file) as archive:
            members = archive.infolist()
            names = [info.filename for info in members]
            arrays = [name[:-4] for name in names if name.endswith(".npy")]
            repeated = sorted({name for name in arrays if arrays.count(name) > 1})
            if repeated:
                raise _bad(
                    source,
                    "distinct array names",
                    f"{repeated} more than once",
                    "write the archive again with one array per name, e.g. "
                    "np.savez(file, q=q, qd=qd, t=t).",
                )
            if "q" not in arrays:
                raise _bad(
                    source,
                    "an array 'q' (K, n)",
                    f"arrays {sorted(arrays)[:12]}",
                    "name the joint angles q when saving, e.g. np.savez(file, q=q, qd=qd, t=t).",
                )
            info = {name[:-4]: item for name, item in zip(names, members, strict=True)}
            read: dict[str, NDArray[Any]] = {}
            for name in ("q", "qd", "t"):
                if name not in info:
                    continue
                k = len(read["q"]) if name != "q" else None
                shape = {"q": (None, n), "qd": (k, n), "t": (k,)}[name]
                with archive.open(info[name]) as handle:
                    read[name] = _read_array(
                        handle,
                        info[name].file_size,
                        source,
                        name,
                        shape,
                        time=name == "t",
                    )
    except (
        zipfile.BadZipFile,  # also a CRC that does not match
        zipfile.LargeZipFile,
        zlib.error,  # a damaged deflate stream
        struct.error,
        NotImplementedError,  # a compression method zipfile lacks
        RuntimeError,  # an encrypted member
        OSError,
        ValueError,
        EOFError,
    ) as exn:
        if isinstance(exn, InputError):
            raise
        raise _unreadable(source, "a .npz archive of .npy arrays", exn) from None
    return _array_blocks(source, n, read["q"], read.get("qd"), read.get("t"))


# ----------------------------------------------------------------------------- entry


_READERS: dict[str, Callable[[Path, str, int], Trajectory]] = {
    ".csv": _read_csv,
    ".parquet": _read_parquet,
    ".npy": _read_npy,
    ".npz": _read_npz,
}


def load_trajectory(path: str | Path, n: int) -> Trajectory:
    """Read a trajectory file for a robot of ``n`` joints.

    Parameters
    ----------
    path : str or Path
        A ``.csv``, ``.parquet``, ``.npy`` or ``.npz`` file (see the module's text for the
        columns and their units).
    n : int
        The robot's number of joints.

    Returns
    -------
    Trajectory
        ``q`` (K, n) [rad], ``qd`` (K, n) [rad/s] or None, ``t`` (K,) [s] or None.

    Raises
    ------
    InputError
        For a missing, unreadable, damaged or mislabelled file; missing, repeated or extra
        columns; rows with more or fewer fields than the header; a cell that is not a
        number, NaN or infinity, a joint value beyond ``MAX_JOINT_VALUE``; time that does
        not increase; more samples than fit (each naming the file, the row or line, and
        the column).
    """
    n = check_integer("n", n, 1, 10_000)  # the robot's joint count
    if not isinstance(path, str | os.PathLike):
        raise InputError(
            "trajectory", "a file path (str or pathlib.Path)", type(path).__name__,
            "pass the file's name, e.g. load_trajectory('path.csv', robot.n).",
        )  # fmt: skip
    file = Path(path)
    source = file.name
    try:
        if not file.is_file():
            raise InputError(
                "trajectory",
                "an existing file",
                repr(str(path)),
                "check the path's spelling; a relative path is read from the current "
                "working folder.",
            )
    except OSError:  # a name too long, a loop of links
        raise InputError(
            "trajectory",
            "an existing file",
            repr(str(path)),
            "check the path: it is too long or loops through links.",
        ) from None
    reader = _READERS.get(file.suffix.lower())
    if reader is None:
        raise InputError(
            "trajectory",
            "a .csv, .parquet, .npy or .npz file",
            repr(file.name),
            "save the trajectory in one of these formats, e.g. as CSV with columns q1..qn, "
            "or with np.save as a (K, n) .npy array.",
        )
    try:
        return reader(file, source, n)
    except MemoryError:
        raise _bad(
            source, "a trajectory that fits in memory", "too many samples", "split the file."
        ) from None
    except OSError as exn:
        if isinstance(exn, InputError):
            raise
        raise _unreadable(source, "a file polyell can read", exn) from None


def _blocks(count: int, size: int) -> Iterator[tuple[int, int]]:
    for start in range(0, count, size):
        yield start, min(start + size, count)


#: Samples of a trajectory whose dynamics are computed at a time (tangent limits).
TANGENT_BLOCK = 4096
#: A task velocity counts as zero (no tangent) when ``|J qd| <= TANGENT_RTOL |J| |qd|_max``,
#: ``|qd|_max`` the largest joint speed of the whole path: rounding in ``J qd`` is a few eps
#: of that, and a still sample (qd = 0 to rounding, e.g. ``cos(pi/2) = 6e-17``) is far below.
TANGENT_RTOL = 1e-12


def tangent_limits(
    source: Any,
    trajectory: Trajectory,
    tau_max: Any = None,
    tau_min: Any = None,
    *,
    capacity: str = "acceleration",
    qd_max: Any = None,
    qd_min: Any = None,
    horizon: float | None = None,
    braking: Any = None,
) -> dict[str, NDArray[np.float64]]:
    """What a capacity allows along the path's tangent ``J q̇ / |J q̇|``, per sample.

    Accelerations by default: the velocity capacity gives the end-effector speeds along
    the path the joint velocity limits allow, the force capacity the forces along it.

    Computed in blocks of :data:`TANGENT_BLOCK` samples (memory independent of the
    path's length, besides the returned columns).

    Parameters
    ----------
    source : robot
        Its dynamics give J at each sample.
    trajectory : Trajectory
        With velocities ``qd``.
    tau_max, tau_min : array-like, optional
        Torque limits (of accelerations and forces); default the robot's own.
    capacity : {"acceleration", "velocity", "force"}, optional
        As in :func:`polyell.limits_along`.
    qd_max, qd_min : array-like, optional
        Joint velocity limits [rad/s] of the velocity capacity; default the robot's own.
    horizon, braking : optional
        A control period [s] and viability's braking decelerations: the polytope's limits
        within the robot's joint position and velocity limits over the period, from each
        sample's state ``(q, qd)`` (the dynamics then in motion), as
        ``limits_along(..., horizon=)``.

    Returns
    -------
    dict of str to ndarray (K,)
        ``tangent_<set>_lo`` and ``tangent_<set>_hi`` for the polytope and the capacity's
        ellipsoids (:func:`polyell.limits_along`); NaN where the task velocity is zero
        (``|J qd| <= TANGENT_RTOL |J|`` times the path's typical speed, the median over its
        samples of ``max_i |qd_i|``: no tangent) or the line misses the set.
    """
    if not (hasattr(source, "dynamics") and hasattr(source, "n")) or isinstance(source, type):
        raise InputError(
            "source",
            "a robot (pe.PlanarArm, pe.UrdfRobot, pe.robots.load(...))",
            type(source).__name__,
            "pass the robot the trajectory is for, e.g. pe.robots.load('chiacchio2000').",
        )
    if not isinstance(trajectory, Trajectory):
        raise InputError(
            "trajectory",
            "a Trajectory (polyell.studies.load_trajectory)",
            type(trajectory).__name__,
            "read it with load_trajectory(path, robot.n), or build Trajectory(q, qd) from "
            "arrays of shape (K, n).",
        )
    if trajectory.qd is None:
        raise InputError(
            "trajectory",
            "joint velocities qd1..qdn for the tangent",
            f"{trajectory!r}",
            "add the columns qd1..qdn to the file (an array qd to a .npz), or pass "
            "Trajectory(q, qd) with qd of shape (K, n).",
        )
    if trajectory.q.shape[1] != source.n:
        raise InputError(
            "trajectory",
            f"{source.n} joint positions per sample (the robot's joints)",
            f"{trajectory.q.shape[1]}",
            "load the trajectory with the robot's number of joints.",
        )
    K = len(trajectory)
    # A sample moves when |J qd| exceeds TANGENT_RTOL |J| times the path's typical speed
    # (the median of its samples' largest |qd_i|): a stop's rounding noise has no tangent,
    # and one sample a thousand orders of magnitude faster does not stop all the others.
    fastest = np.max(np.abs(trajectory.qd), axis=1, initial=0.0)
    typical = float(np.median(fastest[fastest > 0])) if (fastest > 0).any() else 0.0
    columns: dict[str, NDArray[np.float64]] = {}
    cls = capacity_class(capacity)
    given = joint_limits_of(cls.capacity, tau_max, tau_min, qd_max, qd_min)
    upper = lower = None
    for start, stop in _blocks(K, TANGENT_BLOCK):
        dyn = source.dynamics(trajectory.q[start:stop])
        if upper is None:
            upper, lower = cls._source_limits(source, *given, dyn.n)
        # The direction does not depend on the speed's scale: each sample's velocities
        # divided by their largest first, so that up to 1e308 nothing overflows in J qd
        # (and one fast sample does not flush the others' to 0, as the path's largest did).
        scale = fastest[start:stop]
        qd = trajectory.qd[start:stop] / np.where(scale > 0, scale, 1.0)[:, None]
        velocity = np.einsum("kmn,kn->km", dyn.J, qd)
        speed = np.linalg.norm(velocity, axis=1)
        size = np.linalg.norm(dyn.J, axis=(1, 2))  # Frobenius: >= the spectral norm
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            relative = np.where(scale > 0, scale / typical, 0.0)  # (inf: far faster)
            moving = speed * relative > TANGENT_RTOL * size
        T = np.where(moving[:, None], velocity / np.where(moving, speed, 1.0)[:, None], 0.0)
        T[~moving, 0] = 1.0  # a placeholder direction; its rows are NaN below
        arguments = cls.limit_arguments(upper, lower)
        if horizon is None:
            limits = limits_along(dyn, None, T, capacity=capacity, **arguments)
        else:  # the state's limits over the horizon: the robot's, at the samples' velocities
            states = (trajectory.q[start:stop], trajectory.qd[start:stop])
            limits = limits_along(
                source, states[0], T, **arguments, horizon=horizon, qd=states[1], braking=braking
            )
        for name, (lo, hi) in limits.items():
            for end, values in ((f"tangent_{name}_lo", lo), (f"tangent_{name}_hi", hi)):
                if end not in columns:
                    columns[end] = np.empty(K)
                columns[end][start:stop] = np.where(moving, values, np.nan)
    return columns
