"""Property suite of the loaders and writers (issue 33): a PolyellError or a valid result.

Files are drawn by hypothesis and written in a temporary folder (never the checkout):
trajectories (:func:`polyell.studies.trajectory.load_trajectory`) in every format with
columns in any order, extra columns and one cell or header broken; the storage helpers of
:mod:`polyell.storage` on fuzzed metadata, part files and names; meshes of
:mod:`polyell.export` checked against the sets they come from (vertices on the set, the
enclosed volume) and read back from OBJ and PLY; the posture tables of
:mod:`polyell.studies.posture_tables` with broken cells, titles and labels.  Seeded
(derandomized).
"""

from __future__ import annotations

import contextlib
import json
import re
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import polyell as pe
from polyell import storage
from polyell.export import Mesh, mesh, write_obj, write_ply
from polyell.studies.posture_tables import format_posture_table, write_posture_tables
from polyell.studies.trajectory import Trajectory, load_trajectory

JUNK = [None, "x", b"x", [], [[1.0, 2.0], [3.0]], {}, 1 + 2j, True, object(), 2.5, -3, np.nan]


def outcome(call: Callable[[], Any], argument: str | None = None) -> Any:
    """The call's result, or None for a PolyellError (naming ``argument`` when given)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return call()
        except pe.PolyellError as exn:
            if argument is not None and isinstance(exn, pe.InputError):
                assert argument in str(exn), (argument, str(exn))
            return None


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Callable[[], Path]:
    """A fresh temporary folder per example (hypothesis runs a test many times)."""
    return lambda: tmp_path_factory.mktemp("example")


# --- load_trajectory


@st.composite
def trajectories(draw: st.DrawFn) -> dict[str, Any]:
    K, n = draw(st.integers(1, 6)), draw(st.integers(1, 4))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    scale = draw(st.sampled_from([1e-300, 1e-8, 1.0, 1e3, 1e7]))
    columns: dict[str, np.ndarray] = {}
    for i in range(n):
        columns[f"q{i + 1}"] = rng.uniform(-3, 3, K) * scale
    if draw(st.booleans()):
        for i in range(n):
            columns[f"qd{i + 1}"] = rng.uniform(-3, 3, K) * scale
    if draw(st.booleans()):
        columns["t"] = np.cumsum(rng.uniform(0.01, 1.0, K))
    if draw(st.booleans()):
        columns["note"] = rng.uniform(0, 1, K)  # ignored
    order = draw(st.permutations(sorted(columns)))
    return {"K": K, "n": n, "columns": {name: columns[name] for name in order}}


def write(path: Path, columns: dict[str, Any], suffix: str) -> Path:
    file = path / f"path{suffix}"
    if suffix == ".csv":
        names = list(columns)
        lines = [",".join(names)]
        for k in range(len(next(iter(columns.values())))):
            lines.append(",".join(repr(float(columns[c][k])) for c in names))
        file.write_text("\n".join(lines) + "\n")
    elif suffix in (".npy", ".npz"):  # arrays: the joints in their order
        joints = sorted((c for c in columns if re.fullmatch(r"q\d+", c)), key=lambda c: int(c[1:]))
        q = np.column_stack([columns[c] for c in joints])
        if suffix == ".npy":
            np.save(file, q)
            return file
        arrays = {"q": q}
        rates = sorted((c for c in columns if re.fullmatch(r"qd\d+", c)), key=lambda c: int(c[2:]))
        qd = [columns[c] for c in rates]
        if qd:
            arrays["qd"] = np.column_stack(qd)
        if "t" in columns:
            arrays["t"] = np.asarray(columns["t"])
        np.savez(file, **arrays)
    else:
        pd.DataFrame(columns).to_parquet(file)
    return file


@settings(max_examples=40)
@given(case=trajectories(), suffix=st.sampled_from([".csv", ".npy", ".npz", ".parquet"]))
def test_a_written_trajectory_reads_back_exactly(folder, case, suffix):
    columns, n = case["columns"], case["n"]
    trajectory = load_trajectory(write(folder(), columns, suffix), n)
    q = np.column_stack([columns[f"q{i + 1}"] for i in range(n)])
    np.testing.assert_array_equal(trajectory.q, q)
    assert len(trajectory) == case["K"] and trajectory.n == n
    if suffix != ".npy" and "qd1" in columns:
        qd = np.column_stack([columns[f"qd{i + 1}"] for i in range(n)])
        np.testing.assert_array_equal(trajectory.qd, qd)
    else:
        assert trajectory.qd is None or suffix != ".npy"
    if suffix != ".npy" and "t" in columns:
        np.testing.assert_allclose(trajectory.t, columns["t"], rtol=1e-15)


@settings(max_examples=60)
@given(
    case=trajectories(),
    suffix=st.sampled_from([".csv", ".npz", ".parquet"]),
    data=st.data(),
)
def test_a_broken_trajectory_is_read_validly_or_refused_by_name(folder, case, suffix, data):
    columns = {name: np.asarray(values, dtype=object) for name, values in case["columns"].items()}
    n = case["n"]
    how = data.draw(
        st.sampled_from(["cell", "missing", "time", "n", "extra joint", "huge", "empty"])
    )
    if how == "cell":
        name = data.draw(st.sampled_from(sorted(columns)))
        k = data.draw(st.integers(0, case["K"] - 1))
        columns[name][k] = data.draw(st.sampled_from([np.nan, np.inf, -np.inf, 1e300, -0.0]))
    elif how == "missing":
        columns.pop(f"q{data.draw(st.integers(1, n))}")
    elif how == "time" and case["K"] > 1:
        columns["t"] = np.zeros(case["K"])
    elif how == "extra joint":
        n += 1
    elif how == "huge":
        columns["q1"] = columns["q1"] * 0 + 1e9  # beyond MAX_JOINT_VALUE
    elif how == "empty":
        columns = {name: values[:0] for name, values in columns.items()}
    columns = {name: np.asarray(values, dtype=float) for name, values in columns.items()}
    if not any(re.fullmatch(r"q\d+", c) for c in columns):
        return  # (no joint column left to write)
    path = folder()
    if how == "empty" and suffix == ".csv":
        (path / "path.csv").write_text(",".join(columns) + "\n")
        file = path / "path.csv"
    else:
        file = write(path, columns, suffix)
    wanted = data.draw(st.sampled_from([n, n, 0, -1, 2.5, "3", None, True]))
    trajectory = outcome(lambda: load_trajectory(file, wanted))
    if trajectory is None:
        return
    assert isinstance(wanted, int) and not isinstance(wanted, bool) and wanted >= 1
    for values in (trajectory.q, trajectory.qd, trajectory.t):
        assert values is None or np.all(np.isfinite(values))
    assert trajectory.q.shape[1] == wanted and len(trajectory.q) >= 1
    assert np.abs(trajectory.q).max() <= 1e8
    if trajectory.t is not None:
        assert np.all(np.diff(trajectory.t) > 0)


@given(data=st.data())
def test_trajectory_objects_refuse_wrong_arrays(data):
    q = np.zeros((3, 2))
    name = data.draw(st.sampled_from(["q", "qd", "t", "source"]))
    value = data.draw(
        st.sampled_from([*JUNK, np.zeros(3), np.zeros((3, 0)), np.zeros((2, 2)), q, q[:, 0]])
    )
    arguments: dict[str, Any] = {"q": q, name: value}
    made = outcome(lambda: Trajectory(**arguments), name)
    if made is not None:
        assert made.q.ndim == 2 and made.n == made.q.shape[1] >= 1
        if made.qd is not None:
            assert made.qd.shape == made.q.shape
        if made.t is not None:
            assert made.t.shape == (len(made.q),)
    arm = pe.robots.load("chiacchio2000")
    junk = data.draw(st.sampled_from(JUNK))
    limits = pe.studies.trajectory.tangent_limits
    assert outcome(lambda: limits(junk, Trajectory(q, q)), "source") is None
    assert outcome(lambda: limits(arm, junk), "trajectory") is None
    assert outcome(lambda: limits(arm, Trajectory(q, q)), "trajectory") is None  # 2 of 3 joints


# --- polyell.storage


@settings(max_examples=30)
@given(
    text=st.text(max_size=200),
    name=st.from_regex(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,40}", fullmatch=True),
)
def test_text_written_atomically_reads_back_and_leaves_no_temporary(folder, text, name):
    path = folder()
    target = path / name
    assert storage.write_text_atomically(target, text) == target
    assert target.read_text(encoding="utf-8") == text
    assert sorted(p.name for p in path.iterdir()) == [name]
    assert storage.write_text_atomically(str(target), text + "2") == target  # a str path too
    assert target.read_text(encoding="utf-8") == text + "2"


@settings(max_examples=40)
@given(
    content=st.one_of(
        st.binary(max_size=64),
        st.just(b'{"fingerprint": "a", "chunks": 3}'),
        st.just(b"[1, 2]"),
        st.just(b"[" * 5000 + b"]" * 5000),
        st.builds(
            lambda d: json.dumps(d).encode(), st.dictionaries(st.text(max_size=12), st.integers())
        ),
    ),
    name=st.sampled_from(["_sweep.json", "missing.json", "folder"]),
)
def test_metadata_reads_or_says_how_to_recover(folder, content, name):
    path = folder()
    if name == "_sweep.json":
        (path / name).write_bytes(content)
    elif name == "folder":
        (path / name).mkdir()
    data = outcome(lambda: storage.read_metadata(path / name), "out")
    if data is not None:
        assert isinstance(data, dict) and {"fingerprint", "chunks"} <= set(data)
        assert data == json.loads(content)


@settings(max_examples=30)
@given(
    names=st.lists(
        st.one_of(
            st.integers(0, 999_999).map(lambda i: f"part-{i:06d}.parquet"),
            st.sampled_from(["part-1.parquet", "part-0000001.parquet", "part-x.parquet"]),
            st.from_regex(r"\.part-\d{6}\.parquet\.[a-z0-9_]{8}\.tmp", fullmatch=True),
            st.sampled_from(["_sweep.json", "other.txt", "._sweep.json.abcdefgh.tmp"]),
        ),
        max_size=6,
        unique=True,
    ),
    rows=st.integers(0, 5),
)
def test_parts_are_found_checked_and_stale_temporaries_removed(folder, names, rows):
    path = folder()
    for name in names:
        (path / name).write_bytes(b"not parquet")
    parts = outcome(lambda: storage.existing_parts(path), "out")
    stray = [
        n for n in names if n.startswith("part-") and not re.fullmatch(r"part-\d{6}\.parquet", n)
    ]
    assert (parts is None) == bool(stray)
    if parts is not None:
        assert sorted(parts) == sorted(int(n[5:11]) for n in names if n.startswith("part-"))
        for index, file in parts.items():
            assert file == storage.part_path(path, index)
            assert storage.part_is_complete(file, rows) is False  # not a Parquet file
    good = storage.part_path(path, 7)
    pd.DataFrame({"a": np.arange(rows)}).to_parquet(good)
    assert storage.part_is_complete(good, rows) and not storage.part_is_complete(good, rows + 1)
    removed = storage.remove_stale_temporaries(path, storage.DATASET_FILES)
    temporary = re.compile(r"\.(part-\d{6}\.parquet|_sweep\.json)\.[a-z0-9_]{8}\.tmp")
    assert sorted(p.name for p in removed) == sorted(n for n in names if temporary.fullmatch(n))
    assert not any(temporary.fullmatch(p.name) for p in path.iterdir())


@given(
    function=st.sampled_from(
        [
            "part_path",
            "existing_parts",
            "part_is_complete",
            "read_metadata",
            "write_text",
            "remove_stale",
            "write_atomically",
            "folder_lock",
            "write_csv",
        ]
    ),
    value=st.sampled_from([*JUNK, "", -1, 10**7, 3.0]),
)
def test_storage_helpers_refuse_wrong_arguments(folder, function, value):
    path = folder()
    if (
        isinstance(value, str)
        and value
        and function in ("existing_parts", "read_metadata", "write_atomically")
    ):
        return  # a relative path is a path (test_text_written_atomically_... and the others)
    calls: dict[str, tuple[str, Callable[[], Any]]] = {
        "part_path": ("index", lambda: storage.part_path(path, value)),
        "existing_parts": ("folder", lambda: storage.existing_parts(value)),
        "part_is_complete": ("rows", lambda: [storage.part_is_complete(path / "p", value)]),
        "read_metadata": ("path", lambda: storage.read_metadata(value)),
        "write_text": ("text", lambda: storage.write_text_atomically(path / "a.txt", value)),
        "remove_stale": ("names", lambda: storage.remove_stale_temporaries(path, value)),
        "write_atomically": ("path", lambda: storage.write_atomically(value, print)),
        "folder_lock": ("name", lambda: locked(path, value)),
        "write_csv": ("frame", lambda: storage.write_csv(value, handle)),
    }
    argument, call = calls[function]
    with open(path / "f.csv", "wb") as handle, contextlib.chdir(path):  # nothing in the checkout
        result = outcome(call, argument)
    integer = isinstance(value, int) and not isinstance(value, bool)
    valid = {
        "part_path": integer and 0 <= value <= 999_999,
        "part_is_complete": integer and value >= 0,
        "write_text": isinstance(value, str),
        "folder_lock": isinstance(value, str) and value not in ("",) and "/" not in value,
    }.get(function, False)
    assert (result is not None) == valid, (function, value, result)
    if function == "part_path" and valid:
        assert result.name == f"part-{value:06d}.parquet"
    for name in ("a.txt", "x"):  # what a valid call wrote
        (path / name).unlink(missing_ok=True)
    assert sorted(p.name for p in path.iterdir()) == ["f.csv"]


def locked(path: Path, name: Any) -> bool:
    with storage.folder_lock(path, name, "sweep"):
        return True


# --- polyell.export


@st.composite
def drawable_sets(draw: st.DrawFn) -> Any:
    m = draw(st.sampled_from([2, 3]))
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    scale = draw(st.sampled_from([1e-6, 1.0, 1e6]))
    kind = draw(st.sampled_from(["zonotope", "hull", "ellipsoid"]))
    if kind == "zonotope":
        return pe.Polytope(
            rng.normal(size=(m, draw(st.integers(1, 5)))) * scale, rng.normal(size=m) * scale
        )
    if kind == "hull":
        return pe.HPolytope.from_vertices(rng.normal(size=(m + 4, m)) * scale)
    r = draw(st.integers(0, m))
    axes = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :r]
    return pe.Ellipsoid(rng.normal(size=m) * scale, axes, rng.uniform(0.5, 2.0, r) * scale)


def enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


@settings(max_examples=40)
@given(S=drawable_sets(), resolution=st.sampled_from([2, 8, 24]))
def test_meshes_lie_on_their_sets_and_enclose_their_volume(folder, S, resolution):
    item = mesh(S, resolution)
    V, F, L = item
    assert V.shape[1] == 3 and np.all(np.isfinite(V))
    assert F.size == 0 or (F.min() >= 0 and F.max() < len(V))
    assert L.size == 0 or (L.min() >= 0 and L.max() < len(V))
    m = S.ambient_dim
    assert np.all(S.contains(V[:, :m])) and (m == 3 or np.all(V[:, 2] == 0))
    dim = S.rank if isinstance(S, pe.Ellipsoid) else S.dim
    if dim == 3:  # closed and outward: the enclosed volume is the set's (a polytope exactly)
        volume = enclosed_volume(V, F)
        rtol = 1e-9 if not isinstance(S, pe.Ellipsoid) else 0.2 / resolution
        assert volume == pytest.approx(S.volume, rel=max(rtol, 1e-9))
        assert volume <= S.volume * (1 + 1e-9)
    # read back: the OBJ and PLY files hold the same vertices and faces
    path = folder()
    obj = write_obj(path / "s.obj", {"set": item})
    vertices = [
        list(map(float, line.split()[1:]))
        for line in obj.read_text().splitlines()
        if line.startswith("v ")
    ]
    np.testing.assert_array_equal(np.array(vertices).reshape(-1, 3), V)
    ply = write_ply(path / "s.ply", item).read_text().splitlines()
    assert f"element vertex {len(V)}" in ply and f"element face {len(F)}" in ply
    body = ply[ply.index("end_header") + 1 :]
    np.testing.assert_array_equal(
        np.array([list(map(float, row.split())) for row in body[: len(V)]]).reshape(-1, 3), V
    )


@given(data=st.data())
def test_mesh_writers_refuse_broken_meshes_and_paths(folder, data):
    good = Mesh(np.eye(3), np.array([[0, 1, 2]]), np.zeros((0, 2), dtype=int))
    field = data.draw(st.sampled_from(["vertices", "faces", "lines", "path", "name", "item"]))
    bad: Any = data.draw(
        st.sampled_from(
            [
                *JUNK,
                np.full((3, 3), np.nan),
                np.zeros((3, 2)),
                np.array([[0, 1, 5]]),
                np.array([[0.5, 1, 2]]),
                np.array([[-1, 0]]),
                np.array([[0, 1]]),
            ]
        )
    )
    path = folder()
    target: Any = path / "m.obj"
    item: Any = good
    name: Any = "set"
    if field in ("vertices", "faces", "lines"):
        item = good._replace(**{field: bad})
    elif field == "path":
        target = bad
    elif field == "name":
        name = bad
    else:
        item = bad
    argument = {"path": "path", "name": "name", "item": "item"}.get(field, field)
    try:
        hash(name)
    except TypeError:
        written = None  # (not a key of a mapping: write_obj takes names by its keys)
    else:
        with contextlib.chdir(path):
            written = outcome(lambda: write_obj(target, {name: item}), None)
    with contextlib.chdir(path):
        ply = outcome(
            lambda: write_ply(target if field == "path" else path / "m.ply", item, name=name),
            argument,
        )
    for result in (written, ply):
        if result is not None:
            assert result.exists()
            assert "nan" not in result.read_text().lower()
    if written is None and ply is None:
        assert sorted(p.name for p in path.iterdir()) == []


# --- polyell.studies.posture_tables


def choice_table(rng: np.random.Generator) -> pd.DataFrame:
    kinds = ["polytope", "chiacchio", "yoshikawa", "mvie", "outer"]
    index = pd.MultiIndex.from_product(
        [kinds, ["limit", "radius", "volume"]], names=["kind", "criterion"]
    )
    table = pd.DataFrame(
        {
            "picked": pd.array(rng.integers(0, 12, len(index)), dtype="Int64"),
            "true_at_pick": rng.uniform(1, 100, len(index)),
            "true_best": rng.uniform(100, 200, len(index)),
            "regret": rng.uniform(0, 0.5, len(index)),
            "spearman": rng.uniform(-1, 1, len(index)),
            "kendall": rng.uniform(-1, 1, len(index)),
        },
        index=index,
    )
    table.attrs["capacity"] = "acceleration"
    return table


@settings(max_examples=40)
@given(data=st.data(), seed=st.integers(0, 2**16))
def test_posture_tables_format_or_refuse_by_name(folder, data, seed):
    table = choice_table(np.random.default_rng(seed))
    how = data.draw(
        st.sampled_from(["cell", "index", "title", "label", "style", "layout", "frame", "none"])
    )
    style = data.draw(st.sampled_from(["latex", "markdown", "csv"]))
    title, label, layout = "Posture choice", None, None
    argument = {"cell": "table", "index": "table", "frame": "table"}.get(how, how)
    if how == "cell":
        column = data.draw(st.sampled_from(list(table.columns)))
        row = data.draw(st.integers(0, len(table) - 1))
        table[column] = table[column].astype(object)
        table.iloc[row, table.columns.get_loc(column)] = data.draw(
            st.sampled_from([np.nan, None, pd.NA, "abc", 1e300, -1e300, [1], np.inf])
        )
    elif how == "index":
        table = table.reset_index(drop=data.draw(st.booleans()))
    elif how == "title":
        title = data.draw(
            st.sampled_from(
                [
                    "<script>x</script>",
                    "a & b % c # d",
                    "$x^2$",
                    "\\end{table}",
                    "",
                    5,
                    None,
                    "two\nlines",
                ]
            )
        )
    elif how == "label":
        label = data.draw(st.sampled_from(["tab:ok", "bad label", "}", 5, ""]))
    elif how == "style":
        style = data.draw(st.sampled_from([*JUNK, "html", "LATEX"]))
    elif how == "layout":
        layout = data.draw(
            st.sampled_from(
                [*JUNK, pe.TableLayout(sets=["nothing"]), pe.TableLayout(sets=["mvie"], digits=2)]
            )
        )
    elif how == "frame":
        table = data.draw(st.sampled_from([*JUNK, table.to_numpy(), table.to_dict()]))
    text = outcome(
        lambda: format_posture_table(table, style, title, label, layout),
        None if how == "none" else argument,
    )
    if text is not None:
        assert isinstance(text, str) and text
        if style == "markdown" and isinstance(title, str):
            assert "<script>" not in text  # no live HTML from a title
        if style == "latex" and isinstance(title, str) and title:
            assert "\\end{table}" in text and text.count("\\end{table}") == 1
    written = outcome(
        lambda: write_posture_tables(
            table,
            folder(),
            title if isinstance(title, str) else "t",
            label=label if isinstance(label, str) else None,
            layout=layout,
        )
    )
    if written is not None:
        assert set(written) == {"latex", "markdown", "csv"}
        back = pd.read_csv(written["csv"], index_col=[0, 1])
        assert back.shape == table.shape


@given(
    value=st.sampled_from([*JUNK, "", "a/b", ".hidden", "ok"]),
    which=st.sampled_from(["folder", "stem"]),
)
def test_posture_table_files_refuse_wrong_places(folder, value, which):
    table = choice_table(np.random.default_rng(0))
    path = folder()
    arguments: dict[str, Any] = {"folder": path, "stem": "choice", which: value}
    with contextlib.chdir(path):  # a relative folder is refused or is the temporary one
        result = outcome(
            lambda: write_posture_tables(table, arguments["folder"], stem=arguments["stem"]), which
        )
    if result is not None:
        assert all(p.parent == path for p in result.values())
