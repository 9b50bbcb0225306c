"""Study data that is never lost or mixed: atomic files, a lock per dataset, verified parts.

A sweep's Parquet dataset is a folder of ``part-NNNNNN.parquet`` files (one per chunk) and
``_sweep.json`` (what produced them and how many there are).  Every file is written to a
temporary name (``.<name>.<8 random characters>.tmp`` beside it) and renamed, so a reader
sees a whole file or none; a running sweep holds an exclusive lock (``_sweep.lock``) so that
no second sweep writes into the same folder; and a part counts as done only when its
Parquet footer reads and holds the expected rows.  A writer killed outright (SIGKILL, a
power cut) cannot remove its temporary file: whoever takes the folder's lock next removes
those of the files it owns (:func:`remove_stale_temporaries`).
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
from typing import IO, Any

from polyell.errors import InputError, StorageError
from polyell.validation import check_frame, check_integer

__all__ = [
    "DATASET_FILES",
    "as_path",
    "dataset_lock",
    "existing_parts",
    "folder_lock",
    "part_is_complete",
    "part_path",
    "read_metadata",
    "remove_stale_temporaries",
    "write_atomically",
    "write_csv",
    "write_text_atomically",
]

_PART = re.compile(r"part-(\d{6})\.parquet")
#: The files a sweep writes into its dataset folder.
DATASET_FILES = re.compile(r"part-\d{6}\.parquet|_sweep\.json")
#: The temporary name :func:`write_atomically` gives ``<name>`` (``tempfile.mkstemp``'s
#: random part is 8 characters among lower-case letters, digits and ``_``).
#: The longest file name of common file systems (ext4, XFS, APFS, NTFS) [bytes].
_NAME_MAX = 255
_TEMPORARY = re.compile(r"\.(?P<name>.+)\.[a-z0-9_]{8}\.tmp")


def as_path(name: str, value: object) -> Path:
    """``value`` (a str or an os.PathLike) as a Path, or an InputError naming ``name``."""
    if isinstance(value, bytes) or not isinstance(value, str | os.PathLike) or not str(value):
        raise InputError(
            name,
            "a path (a str or a pathlib.Path)",
            f"{type(value).__name__} {value!r:.80}",
            f"pass a non-empty str or pathlib.Path, e.g. {name}=Path('results')",
        )
    if "\x00" in str(value):
        raise InputError(
            name,
            "a path without NUL characters",
            repr(str(value))[:80],
            "remove the NUL characters ('\\x00') from the path",
        )
    return Path(value)


def part_path(folder: Path, index: int) -> Path:
    """The file of chunk ``index`` (from 0 to 999,999)."""
    index = check_integer("index", index, 0, 999_999)
    return as_path("folder", folder) / f"part-{index:06d}.parquet"


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
    path = as_path("path", path)
    if not callable(write):
        raise InputError(
            "write",
            "a function of the temporary file name",
            repr(write)[:80],
            "pass a callable that writes the file it is given, "
            "e.g. lambda name: Path(name).write_text(text)",
        )
    name = path.name
    if not name or name in (".", ".."):
        raise InputError("path", "the path of a file", repr(str(path)), "name the file.")
    while len(os.fsencode(f".{name}.XXXXXXXX.tmp")) > _NAME_MAX and len(name) > 1:
        name = name[:-1]  # a name near the limit: the temporary name gets a shorter prefix
    temporary = ""
    try:
        handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{name}.", suffix=".tmp")
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
    if not isinstance(text, str):
        raise InputError(
            "text",
            "a str",
            f"{type(text).__name__} {text!r:.80}",
            "pass the text as a str, e.g. decode bytes with data.decode('utf-8')",
        )
    return write_atomically(path, lambda name: Path(name).write_text(text, encoding="utf-8"))


def write_csv(frame: Any, handle: Any, header: bool = True) -> None:
    """Append a DataFrame to an open binary file as CSV (comma, quotes only where needed).

    By pyarrow's writer: every float in its shortest repr that reads back to the same
    double (whole numbers without ``.0``), NaN as an empty field; about ten times faster
    than ``DataFrame.to_csv`` (half a second for 5,000 rows of 80 scores).
    """
    import pyarrow as pa
    import pyarrow.csv as pa_csv

    check_frame("frame", frame, "pass a pandas DataFrame, e.g. pd.DataFrame(rows)")
    if not callable(getattr(handle, "write", None)):
        raise InputError(
            "handle",
            "a file open for binary writing",
            repr(handle)[:80],
            "pass a file opened in binary mode, e.g. open(path, 'wb')",
        )
    if not isinstance(header, bool):
        raise InputError(
            "header",
            "True or False",
            repr(header)[:80],
            "pass header=True to write the column names, header=False to leave them out",
        )
    table = pa.Table.from_pandas(frame, preserve_index=False)
    options = pa_csv.WriteOptions(include_header=header, quoting_style="needed")
    pa_csv.write_csv(table, handle, options)


def read_metadata(path: Path) -> dict[str, Any]:
    """Read ``_sweep.json``; a torn or foreign file is an error that says how to recover."""
    path = as_path("path", path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(data, dict) or not {"fingerprint", "chunks"} <= set(data):
            raise ValueError("missing keys")
    except (ValueError, UnicodeDecodeError, OSError, RecursionError) as exn:
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
    for path in as_path("folder", folder).glob("part-*.parquet"):
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

    path = as_path("path", path)
    rows = check_integer("rows", rows, 0, 2**62)
    try:
        return bool(pq.read_metadata(path).num_rows == rows)
    except (OSError, ValueError):  # pyarrow's ArrowInvalid is a ValueError
        return False


def remove_stale_temporaries(folder: Path, names: re.Pattern[str]) -> list[Path]:
    """Remove the temporary files that killed writers left for the files ``names`` matches.

    Call it only while holding the folder's lock (:func:`folder_lock`): then no live
    writer of those files exists, and every such temporary file is a dead one's.  Other
    files, and temporary files of other names, are left alone.

    Parameters
    ----------
    folder : Path
        The folder (not searched recursively).
    names : re.Pattern
        The names of the files the lock holder writes (matched whole).

    Returns
    -------
    list of Path
        The files removed.

    Raises
    ------
    StorageError
        If one of them cannot be removed.
    """
    folder = as_path("folder", folder)
    if not isinstance(names, re.Pattern):
        raise InputError(
            "names",
            "a compiled regular expression (re.compile)",
            repr(names)[:80],
            "compile the pattern of the file names first, e.g. re.compile(r'_sweep\\.json')",
        )
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError as exn:
        raise StorageError(f"Could not list {folder}: {exn.strerror or exn}.") from exn
    for entry in entries:
        match = _TEMPORARY.fullmatch(entry.name)
        if match is None or not names.fullmatch(match.group("name")):
            continue
        try:
            os.unlink(entry.path)
        except FileNotFoundError:
            continue
        except OSError as exn:
            raise StorageError(
                f"Could not remove the stale temporary file {entry.path}: "
                f"{exn.strerror or exn}. Fix: remove it by hand."
            ) from exn
        removed.append(Path(entry.path))
    return removed


@contextlib.contextmanager
def folder_lock(folder: Path, name: str, what: str) -> Iterator[None]:
    """Hold an exclusive lock on a folder, or refuse at once if another process holds it.

    The lock is ``fcntl.flock`` on the file ``folder / name``: the operating system
    releases it when its process ends, however it ends (a killed run leaves no stale lock,
    only the file).  The holder removes the file before it lets go, and a process that
    locked a file no longer under that name opens the current one again.

    Parameters
    ----------
    folder : Path
    name : str
        The lock file's name.
    what : str
        What holds such a lock ("sweep", "study"), for the message.

    Raises
    ------
    InputError
        If another process holds the lock.
    StorageError
        If the lock file cannot be opened.
    """
    import fcntl

    folder = as_path("folder", folder)
    for label, text in (("name", name), ("what", what)):
        if not isinstance(text, str) or not text:
            example = "name='_sweep.lock'" if label == "name" else "what='sweep'"
            raise InputError(
                label, "a non-empty str", repr(text)[:80], f"pass a non-empty str, e.g. {example}"
            )
    if Path(name).name != name:
        raise InputError(
            "name",
            "a file name without folders",
            repr(name)[:80],
            "pass the lock file's bare name, e.g. '_sweep.lock', and its folder as folder",
        )
    path = folder / name
    refusal = InputError(
        "out",
        f"a folder no other {what} is writing",
        f"{folder} is locked by a running {what}",
        "wait for it to finish, or choose another folder.",
    )
    for _ in range(3):  # a holder that just finished may have removed the file we opened
        try:
            handle = open(path, "a+")
        except OSError as exn:
            raise StorageError(f"Could not open {path}: {exn.strerror or exn}.") from exn
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.close()
            raise refusal from None
        if _names_this_file(path, handle):
            break
        handle.close()  # locked a file no longer in the folder: open the current one
    else:
        raise refusal
    try:
        yield
    finally:
        path.unlink(missing_ok=True)  # still holding the lock: no one else holds this file
        handle.close()  # releases the lock


def _names_this_file(path: Path, handle: IO[str]) -> bool:
    """Whether ``path`` still names the open file ``handle`` (not removed or replaced)."""
    try:
        on_disk = os.stat(path)
    except FileNotFoundError:
        return False
    held = os.fstat(handle.fileno())
    return (on_disk.st_dev, on_disk.st_ino) == (held.st_dev, held.st_ino)


@contextlib.contextmanager
def dataset_lock(folder: Path) -> Iterator[None]:
    """Hold the exclusive lock of a dataset folder, or refuse at once if another holds it.

    The lock is ``_sweep.lock`` (:func:`folder_lock`).  Once it is held, the temporary
    files of parts and metadata that a killed sweep left are removed.
    """
    with folder_lock(folder, "_sweep.lock", "sweep"):
        remove_stale_temporaries(folder, DATASET_FILES)
        yield
