"""Study data that is never lost or mixed: atomic files, a lock per dataset, verified parts.

A sweep's Parquet dataset is a folder of ``part-NNNNNN.parquet`` files (one per chunk) and
``_sweep.json`` (what produced them and how many there are).  Every file is written to a
temporary name and renamed, so a reader sees a whole file or none; a running sweep holds
an exclusive lock (``_sweep.lock``) so that no second sweep writes into the same folder; and
a part counts as done only when its Parquet footer reads and holds the expected rows.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from polyell.errors import InputError, StorageError

__all__ = [
    "dataset_lock",
    "existing_parts",
    "part_is_complete",
    "part_path",
    "read_metadata",
    "write_atomically",
    "write_text_atomically",
]

_PART = re.compile(r"part-(\d{6})\.parquet")


def part_path(folder: Path, index: int) -> Path:
    """The file of chunk ``index``."""
    return folder / f"part-{index:06d}.parquet"


def write_atomically(path: Path, write: Callable[[str], Any]) -> Path:
    """Write ``path`` through ``write(temporary_name)``, then rename it into place.

    The file gets the permissions of a file created normally (``0o666`` less the umask):
    a temporary file alone would be private (``0o600``).

    Raises
    ------
    StorageError
        If the file cannot be written (a full disk, a file size limit, permissions); no
        partial file is left behind.
    """
    temporary = ""
    try:
        handle, temporary = tempfile.mkstemp(
            dir=path.parent, prefix=f".{path.name}.", suffix=".tmp"
        )
        os.close(handle)
        write(temporary)
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, path)
    except OSError as exn:
        raise StorageError(
            f"Could not write {path}: {exn.strerror or exn}. Fix: {_fix(exn)}"
        ) from exn
    finally:
        if temporary and os.path.exists(temporary):
            os.unlink(temporary)
    return path


def _fix(exn: OSError) -> str:
    """What to do about a failed write, by its cause."""
    if exn.errno == errno.ENOENT:
        return "create the folder first, or choose an existing one."
    if exn.errno == errno.ENAMETOOLONG:
        return "choose a shorter file name (the limit is usually 255 bytes per name)."
    if exn.errno in (errno.ENOTDIR, errno.EISDIR):
        return "a part of the path is a file, or the name is a folder: choose another path."
    if exn.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        return "choose a folder you can write to."
    return (
        "free disk space (or raise the limit) and run again; finished parts are kept and a "
        "sweep resumes."
    )


def _umask() -> int:
    """The process's umask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_text_atomically(path: Path, text: str) -> Path:
    """:func:`write_atomically` for UTF-8 text."""
    return write_atomically(path, lambda name: Path(name).write_text(text, encoding="utf-8"))


def read_metadata(path: Path) -> dict[str, Any]:
    """Read ``_sweep.json``; a torn or foreign file is an error that says how to recover."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(data, dict) or not {"fingerprint", "chunks"} <= set(data):
            raise ValueError("missing keys")
    except (ValueError, UnicodeDecodeError) as exn:
        raise InputError(
            "out",
            "a sweep dataset with a readable _sweep.json",
            f"{path} is torn or not a sweep's ({exn.__class__.__name__})",
            f"delete {path.parent} (or its part files and {path.name}) to start over.",
        ) from None
    return data


def existing_parts(folder: Path) -> dict[int, Path]:
    """The part files of a dataset folder, by chunk index."""
    parts = {}
    for path in folder.glob("part-*.parquet"):
        match = _PART.fullmatch(path.name)
        if match is None:
            raise InputError(
                "out",
                "a folder whose part files are a sweep's (part-NNNNNN.parquet)",
                f"a stray file {path.name}",
                "move it away, or use another folder.",
            )
        parts[int(match.group(1))] = path
    return parts


def part_is_complete(path: Path, rows: int) -> bool:
    """Whether a part's Parquet footer reads and holds ``rows`` rows."""
    import pyarrow.parquet as pq

    try:
        return bool(pq.read_metadata(path).num_rows == rows)
    except (OSError, ValueError):  # pyarrow's ArrowInvalid is a ValueError
        return False


@contextlib.contextmanager
def dataset_lock(folder: Path) -> Iterator[None]:
    """Hold the exclusive lock of a dataset folder, or refuse at once if another holds it.

    The lock is ``fcntl.flock`` on ``_sweep.lock``: the operating system releases it when
    its process ends, however it ends (a killed sweep leaves no stale lock).
    """
    import fcntl

    path = folder / "_sweep.lock"
    try:
        handle = open(path, "a+")
    except OSError as exn:
        raise StorageError(f"Could not open {path}: {exn.strerror or exn}.") from exn
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InputError(
                "out",
                "a dataset folder no other sweep is writing",
                f"{folder} is locked by a running sweep",
                "wait for it to finish, or choose another folder.",
            ) from None
        yield
    finally:
        handle.close()  # releases the lock
