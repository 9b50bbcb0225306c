"""Results in long form (issue 31, item 5): ``pe.to_long`` and ``pe.to_wide``.

Round trips on real sweeps of the paper's arm -- every capacity, with and without candidates
whose names hold underscores (and begin like a built-in kind's), with and without the MVIE
and the outer ellipsoid, several capacities together, several robots, ``to_row`` records --
give back the wide frame exactly (values, dtypes, column order, attrs, index).  Every value
of the long frame is checked against the wide frame's column by a plain loop over rows and
kinds (not the vectorised interleave), at exact equality; the kinds come from the frame's
recorded structure, and what cannot be resolved is refused naming the argument.  The
summaries (``polyell.comparison.summary``) use the same structure.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.comparison.comparison import SCORE_NAMES, compared_kinds
from polyell.comparison.long_form import (
    BUILT_IN_SCORED_KINDS,
    score_columns,
    to_long,
    to_wide,
    wide_attrs,
)
from polyell.comparison.summary import SUMMARY_SCORES, result_kinds, split_column, summarize

ARM = pe.robots.load("chiacchio2000")
#: Seeded random configurations and the paper's singular one (a per-row configuration).
Q = np.vstack([np.random.default_rng(31).uniform(-np.pi, np.pi, (11, 3)), [np.pi / 6, 0, 0]])
#: Candidates whose names hold underscores, one beginning like a built-in kind's columns
#: (``chiacchio_w2_coverage``) and one holding a score name (``volume_like``).
CANDIDATES = (
    pe.Candidate("heavy_wrist", weighting=np.diag([1.0, 1.0, 4.0])),
    pe.Candidate("chiacchio_w2", weighting=np.diag([2.0, 1.0, 1.0])),
    pe.Candidate("volume_like", weighting=np.diag([1.0, 3.0, 1.0])),
)
NAMES = [candidate.name for candidate in CANDIDATES]
CAPACITIES = ("acceleration", "velocity", "force")
#: (candidates, mvie and outer)
OPTIONS = [(False, False), (True, True), (True, False), (False, True)]

_frames: dict[tuple[str, bool, bool], pd.DataFrame] = {}


def sweep(capacity: str, candidates: bool = True, optima: bool = False) -> pd.DataFrame:
    """A sweep of the paper's arm at Q (computed once per arguments); a copy."""
    key = (capacity, candidates, optima)
    if key not in _frames:
        _frames[key] = pe.sweep(
            ARM,
            Q,
            capacity=capacity,
            candidates=CANDIDATES if candidates else (),
            mvie=optima,
            outer=optima,
            directions=24,
        )
    frame = _frames[key].copy()
    frame.attrs = {k: list(v) if isinstance(v, list) else v for k, v in frame.attrs.items()}
    return frame


def assert_same_wide(got: pd.DataFrame, expected: pd.DataFrame) -> None:
    """Equal values (NaN where NaN), dtypes, column order, index and attrs."""
    assert list(got.columns) == list(expected.columns)
    assert list(got.dtypes) == list(expected.dtypes)
    pd.testing.assert_frame_equal(got, expected, check_exact=True)
    assert got.equals(expected)
    assert got.index.equals(expected.index) and type(got.index) is type(expected.index)
    assert got.attrs == expected.attrs


def assert_long_matches(long: pd.DataFrame, wide: pd.DataFrame, capacity: str) -> None:
    """Every cell of ``long`` against the wide frame, by a plain loop over rows and kinds."""
    kinds, scores = wide.attrs["kinds"], wide.attrs["scores"]
    per = [c for c in wide.columns if c != "configuration" and c not in _score_names(wide)]
    expected_index = [(c, capacity, k) for c in wide["configuration"] for k in kinds]
    assert list(long.xs(capacity, level="capacity", drop_level=False).index) == expected_index
    assert list(long.columns[: len(scores)]) == [s for s in SCORE_NAMES if s in scores]
    for row in range(len(wide)):
        configuration = int(wide["configuration"].iloc[row])
        for kind in kinds:
            record = long.loc[(configuration, capacity, kind)]
            for score in scores:
                value, wanted = record[score], wide[f"{kind}_{score}"].iloc[row]
                assert value == wanted or (np.isnan(value) and np.isnan(wanted)), (kind, score)
            for column in per:
                value, wanted = record[column], wide[column].iloc[row]
                assert value == wanted or (pd.isna(value) and pd.isna(wanted)), column


def _score_names(wide: pd.DataFrame) -> set[str]:
    return {f"{k}_{s}" for k in wide.attrs["kinds"] for s in wide.attrs["scores"]}


# -- the structure a sweep records ---------------------------------------------------------


@pytest.mark.parametrize("capacity", CAPACITIES)
@pytest.mark.parametrize(("candidates", "optima"), OPTIONS)
def test_a_sweep_records_its_kinds_capacity_and_scores(capacity, candidates, optima):
    frame = sweep(capacity, candidates, optima)
    kinds = [k for k in compared_kinds(capacity) if optima or k not in ("mvie", "outer")]
    kinds += NAMES if candidates else []
    assert frame.attrs["capacity"] == capacity and frame.attrs["kinds"] == kinds
    scores = frame.attrs["scores"]
    assert set(scores) <= set(SCORE_NAMES) and ("mvie_ratio" in scores) == optima
    score_columns_ = [c for c in frame.columns if c in _score_names(frame)]
    assert score_columns_ == [f"{k}_{s}" for k in kinds for s in scores]  # the full product


def test_scores_in_the_order_asked_and_several_robots_record_the_same(tmp_path):
    frame = pe.sweep(ARM, Q[:3], scores=["coverage", "volume"], directions=16)
    assert frame.attrs["scores"] == ["coverage", "volume"]
    long = to_long(frame)
    assert list(long.columns[:2]) == ["volume", "coverage"]  # SCORE_NAMES order
    assert_same_wide(to_wide(long), frame)  # the wide order back
    robots = pe.sweep({"a": ARM, "b_2": ARM}, Q[:4], directions=16, candidates=CANDIDATES[:1])
    assert robots.attrs["kinds"] == ["chiacchio", "yoshikawa", "heavy_wrist"]
    long = to_long(robots)
    assert list(long.index.names) == ["robot", "configuration", "capacity", "kind"]
    assert (
        long.loc[("b_2", 3, "acceleration", "heavy_wrist"), "coverage"]
        == (robots.loc[7, "heavy_wrist_coverage"])
    )
    assert_same_wide(to_wide(long), robots)


def test_a_parquet_dataset_keeps_the_attrs(tmp_path):
    out = pe.sweep(ARM, Q, candidates=CANDIDATES, out=tmp_path / "d", chunk=5, directions=24)
    stored = pd.read_parquet(out).sort_values("configuration").reset_index(drop=True)
    frame = sweep("acceleration")
    assert stored.attrs == frame.attrs
    assert_same_wide(to_wide(to_long(stored)), stored)
    pd.testing.assert_frame_equal(stored, frame, check_exact=True)


def test_the_velocity_sweep_keeps_candidates_named_like_built_in_kinds():
    # Found by this item: the velocity path renamed "chiacchio_*" to "yoshikawa_*" and
    # dropped "yoshikawa_*" by prefix, so a candidate "chiacchio_w2" raised a KeyError.
    odd = (*CANDIDATES, pe.Candidate("yoshikawa_x", weighting=np.diag([1.0, 1.0, 2.0])))
    frame = pe.sweep(ARM, Q, capacity="velocity", candidates=odd, directions=24)
    assert frame.attrs["kinds"] == ["yoshikawa", *NAMES, "yoshikawa_x"]
    for k, q in enumerate(Q):
        an = pe.analyze(ARM.dynamics(q), capacity="velocity", qd_max=ARM.qd_max)  # the default
        row = pe.compare(an, 24, mvie=False, outer=False, candidates=odd).to_row()
        for kind in frame.attrs["kinds"]:
            for score in frame.attrs["scores"]:
                value, wanted = frame.loc[k, f"{kind}_{score}"], row[f"{kind}_{score}"]
                if np.isnan(wanted):
                    assert np.isnan(value), (k, kind, score)
                else:
                    assert abs(value - wanted) <= 1e-9 * max(1.0, abs(wanted)), (k, kind, score)


# -- round trips ---------------------------------------------------------------------------


@pytest.mark.parametrize("capacity", CAPACITIES)
@pytest.mark.parametrize(("candidates", "optima"), OPTIONS)
def test_round_trip_of_a_sweep_is_exact(capacity, candidates, optima):
    frame = sweep(capacity, candidates, optima)
    long = to_long(frame)
    assert list(long.index.names) == ["configuration", "capacity", "kind"]
    assert len(long) == len(frame) * len(frame.attrs["kinds"])
    assert_long_matches(long, frame, capacity)
    assert_same_wide(to_wide(long), frame)
    # what a pandas user does with it: one kind is one row per configuration again
    chiacchio = long.xs(frame.attrs["kinds"][0], level="kind")
    kind = frame.attrs["kinds"][0]
    assert np.array_equal(
        chiacchio["coverage"].to_numpy(), frame[f"{kind}_coverage"].to_numpy(), equal_nan=True
    )
    assert np.array_equal(chiacchio["q2"].to_numpy(), frame["q2"].to_numpy())
    assert long["per_row"].dtype == bool and long["per_row"].any() == frame["per_row"].any()


def test_several_capacities_concatenated():
    frames = {capacity: sweep(capacity, True, True) for capacity in CAPACITIES}
    long = to_long(frames)
    assert list(long.index.unique("capacity")) == list(CAPACITIES)
    assert to_long(list(frames.values())).equals(long)
    for capacity, frame in frames.items():
        assert_long_matches(long, frame, capacity)
        assert_same_wide(to_wide(long, capacity=capacity), frame)
    kinds = long.index.unique("kind")
    assert list(kinds) == ["chiacchio", "yoshikawa", "mvie", "outer", *NAMES, "static"]
    # groupby over the tidy frame: one mean per capacity and kind, the wide columns' means
    means = long.groupby(level=["capacity", "kind"], sort=False)["coverage"].mean()
    for (capacity, kind), mean in means.items():
        assert mean == pytest.approx(frames[capacity][f"{kind}_coverage"].mean(), nan_ok=True)
    with pytest.raises(pe.InputError, match="capacity: expected one of") as info:
        to_wide(long)
    assert "Fix: pass capacity='acceleration'" in str(info.value)


def test_round_trip_through_files(tmp_path):
    frames = {capacity: sweep(capacity, True, False) for capacity in CAPACITIES}
    long = to_long(frames)
    long.to_parquet(tmp_path / "long.parquet")
    back = pd.read_parquet(tmp_path / "long.parquet")
    assert back.equals(long)
    for capacity, frame in frames.items():
        assert_same_wide(to_wide(back, capacity=capacity), frame)
    # without attrs (the columns of the other capacities are all NaN here: left out)
    bare = long.copy()
    bare.attrs = {}
    for capacity, frame in frames.items():
        rebuilt = to_wide(bare, capacity=capacity)
        assert list(rebuilt.columns) == list(frame.columns)  # the canonical order is a sweep's
        pd.testing.assert_frame_equal(rebuilt, frame, check_exact=True)
        assert rebuilt.attrs == frame.attrs  # wide_attrs: what the sweep recorded
    # CSV keeps no attrs: the columns and the names passed say what the frame is
    frame = frames["force"]
    frame.to_csv(tmp_path / "wide.csv", index=False)
    read = pd.read_csv(tmp_path / "wide.csv")
    with pytest.raises(pe.InputError, match="heavy_wrist_dimension") as info:
        to_long(read)
    assert "Fix: pass kinds=[...]" in str(info.value)
    long = to_long(read, kinds=NAMES)
    assert list(long.index.unique("capacity")) == ["force"]  # told by 'static_*'
    assert long.index.unique("kind").tolist() == frame.attrs["kinds"]
    assert_same_wide(to_wide(long), read)
    # a long frame read back from CSV: its levels are columns, its attrs gone
    long.reset_index().to_csv(tmp_path / "long.csv", index=False)
    rebuilt = to_wide(pd.read_csv(tmp_path / "long.csv"))
    expected = read[[*rebuilt.columns]]  # the canonical order: keys, per configuration, kinds
    assert rebuilt.attrs == wide_attrs("force", frame.attrs["kinds"], frame.attrs["scores"])
    expected.attrs = rebuilt.attrs
    pd.testing.assert_frame_equal(rebuilt, expected, check_exact=True)
    assert set(rebuilt.columns) == set(read.columns)


def test_rows_keep_their_order_and_empty_frames_round_trip():
    frame = sweep("acceleration")
    shuffled = frame.sample(frac=1.0, random_state=3)
    back = to_wide(to_long(shuffled))
    assert list(back["configuration"]) == list(shuffled["configuration"])
    assert_same_wide(back, shuffled.reset_index(drop=True))  # the index: a RangeIndex
    empty = frame.iloc[:0]
    long = to_long(empty)
    assert len(long) == 0 and list(long.columns) == list(to_long(frame).columns)
    assert_same_wide(to_wide(long), empty)
    bare = empty.copy()
    bare.attrs = {}
    assert_same_wide(to_wide(to_long(bare, kinds=NAMES)), bare)


def test_to_row_records_and_frames():
    analyses = [pe.analyze(ARM.dynamics(q), ARM.tau_max) for q in Q[:3]]
    comparisons = [pe.compare(an, 16, candidates=CANDIDATES) for an in analyses]
    row = comparisons[0].to_row()
    long = to_long(row, kinds=NAMES)  # capacity told by the kinds: accelerations
    assert list(long.index) == [(0, "acceleration", kind) for kind in comparisons[0].kinds]
    for kind in comparisons[0].kinds:
        record = comparisons[0][kind]
        for score in SCORE_NAMES:
            value, wanted = long.loc[(0, "acceleration", kind), score], getattr(record, score)
            assert value == wanted or (np.isnan(value) and np.isnan(wanted))
    assert_same_wide(to_wide(long), pd.DataFrame([row]))
    frame = pd.DataFrame([c.to_row() for c in comparisons], index=pd.Index([5, 7, 9], name="q"))
    long = to_long(frame, kinds=NAMES, capacity="acceleration")
    assert list(long.index.unique("configuration")) == [5, 7, 9]
    assert_same_wide(to_wide(long), frame)  # the index was the configuration: kept
    plain = pd.DataFrame([c.to_row() for c in comparisons])
    assert_same_wide(to_wide(to_long(plain, kinds=NAMES)), plain)
    # what Comparison.to_long() is to be: the record with its capacity and kinds
    for comparison in comparisons:
        long = to_long(comparison.to_row(), capacity="acceleration", kinds=comparison.kinds)
        assert list(long.index.get_level_values("kind")) == list(comparison.kinds)
    # a force record's capacity is told by its 'static' kind, a velocity one by 'yoshikawa'
    for capacity, limits in (
        ("force", {"tau_max": ARM.tau_max}),
        ("velocity", {"qd_max": [1.0] * 3}),
    ):
        an = pe.analyze(ARM.dynamics(Q[0]), capacity=capacity, **limits)
        row = pe.compare(an, 16, mvie=False, outer=False).to_row()
        assert to_long(row).index.unique("capacity").tolist() == [capacity]


def test_candidate_names_are_matched_exactly_never_split():
    columns = [
        "configuration",
        "q1",
        "polytope_volume",
        "chiacchio_coverage",
        "chiacchio_w2_coverage",
        "chiacchio_w2_coverage_stderr",
        "volume_like_volume",
        "mvie_ratio_coverage",  # a candidate named 'mvie_ratio', not the MVIE's 'ratio_...'
    ]
    found = score_columns(columns, kinds=["chiacchio_w2", "volume_like", "mvie_ratio"])
    assert found.columns == {
        "chiacchio": {"coverage": "chiacchio_coverage"},
        "chiacchio_w2": {
            "coverage": "chiacchio_w2_coverage",
            "coverage_stderr": "chiacchio_w2_coverage_stderr",
        },
        "volume_like": {"volume": "volume_like_volume"},
        "mvie_ratio": {"coverage": "mvie_ratio_coverage"},
    }
    assert found.unresolved == () and found.capacity is None and found.recorded
    bare = score_columns(columns)
    assert bare.kinds == ["chiacchio"] and not bare.recorded
    assert bare.unresolved == tuple(columns[4:])  # refused by to_long, not guessed
    frame = pd.DataFrame([np.arange(len(columns), dtype=float)], columns=columns)
    long = to_long(frame, kinds=["chiacchio_w2", "volume_like", "mvie_ratio"], capacity="force")
    assert long.loc[(0.0, "force", "mvie_ratio"), "coverage"] == 7.0
    assert long.loc[(0.0, "force", "chiacchio_w2"), "coverage_stderr"] == 5.0


def test_no_score_name_is_another_after_an_underscore():
    # Why exact <kind>_<score> names never collide: f"{k1}_{s1}" == f"{k2}_{s2}" with
    # k2 = k1 + "_" + x needs s1 = x + "_" + s2, a score ending in another score.
    for score in SCORE_NAMES:
        for other in SCORE_NAMES:
            assert not score.endswith(f"_{other}")
    assert set(BUILT_IN_SCORED_KINDS) == {"chiacchio", "yoshikawa", "static", "mvie", "outer"}


# -- bad inputs ----------------------------------------------------------------------------


def _refused(call, argument: str, fragment: str = "") -> str:
    with pytest.raises(pe.InputError) as info:
        call()
    assert info.value.argument == argument, str(info.value)
    assert fragment in str(info.value), str(info.value)
    return str(info.value)


def test_bad_inputs_are_refused_naming_the_argument():
    frame = sweep("acceleration")
    _refused(lambda: to_long(5), "frames", "a wide results DataFrame")
    _refused(lambda: to_long("chiacchio_coverage"), "frames")
    _refused(lambda: to_long([]), "frames")
    _refused(lambda: to_long([frame, 3]), "frames")
    _refused(lambda: to_long(frame[["configuration", "q1"]]), "frames", "<kind>_<score>")
    _refused(lambda: to_long([frame, frame]), "frames", "one frame per capacity")
    _refused(lambda: to_long(frame, kinds=5), "kinds", "a sequence of names")
    _refused(lambda: to_long(frame, kinds=[3]), "kinds", "non-empty names")
    _refused(lambda: to_long(frame, kinds=["polytope"]), "kinds", "'polytope'")
    _refused(lambda: to_long(frame, kinds=["heavy_wirst"]), "kinds", "heavy_wirst")
    _refused(lambda: to_long(frame, capacity="force"), "capacity", "its attrs['capacity']")
    _refused(lambda: to_long(frame, capacity="forces"), "capacity", "did you mean 'force'")
    _refused(lambda: to_long([frame, sweep("force")], capacity="force"), "capacity", "None with")
    _refused(lambda: to_long({"acceleration": frame}, capacity="force"), "capacity")
    _refused(lambda: to_long({"speed": frame}), "frames key 'speed'")
    doubled = pd.concat([frame, frame], ignore_index=True)
    _refused(lambda: to_long(doubled), "frames", "configuration 0 more than once")
    _refused(lambda: to_long(frame.assign(coverage=1.0)), "frames", "'coverage'")
    _refused(lambda: to_long(frame.assign(kind="x")), "frames", "'kind'")
    _refused(lambda: to_long(frame.assign(extra_volume=1.0)), "frames", "extra_volume")
    renamed = frame.rename(columns={"q1": 1})
    _refused(lambda: to_long(renamed), "frames", "column names (str)")
    twice = pd.concat([frame, frame["q1"]], axis=1)
    _refused(lambda: to_long(twice), "frames", "'q1' more than once")
    broken = frame.copy()
    broken.attrs["kinds"] = 5
    _refused(lambda: to_long(broken), "frames.attrs['kinds']", "a sequence of names")
    broken.attrs = {"capacity": "speed"}
    _refused(lambda: to_long(broken), "frames.attrs['capacity']")
    optima = pd.DataFrame({"mvie_coverage": [0.5]})  # no ellipsoid of a capacity's own
    _refused(lambda: to_long(optima), "capacity", "pass capacity=")
    _refused(lambda: to_long([frame.assign(robot="a"), sweep("force")]), "frames", "'robot'")


def test_bad_long_frames_are_refused():
    frame = sweep("acceleration")
    long = to_long({"acceleration": frame, "force": sweep("force")})
    _refused(lambda: to_wide(frame), "long", "indexed by (configuration, capacity, kind)")
    _refused(lambda: to_wide(5), "long", "a long results DataFrame")
    _refused(lambda: to_wide(long, capacity="velocity"), "capacity", "'velocity'")
    _refused(lambda: to_wide(long), "capacity", "holds several")
    _refused(lambda: to_wide(pd.concat([long, long])), "long", "twice")
    one = to_long(frame)
    _refused(lambda: to_wide(one.drop(columns="volume")), "long", "'volume'")
    _refused(lambda: to_wide(one.drop(index="yoshikawa", level="kind")), "long", "'yoshikawa'")
    damaged = one.copy()
    damaged.attrs["wide"] = {"acceleration": {"columns": []}}
    _refused(lambda: to_wide(damaged), "long.attrs['wide']", "the record pe.to_long writes")
    empty = one.iloc[:0].copy()
    empty.attrs = {}
    _refused(lambda: to_wide(empty), "long", "an empty frame")
    # integer score columns stay integers; a kind's row dropped cannot come back as one
    counts = {f"{k}_directions_used": int for k in frame.attrs["kinds"]}
    ints = frame.astype(counts)
    long_ints = to_long(ints)
    assert long_ints["directions_used"].dtype == np.int64
    assert_same_wide(to_wide(long_ints), ints)
    dropped = long_ints.drop(index=(0, "acceleration", "chiacchio"))
    _refused(lambda: to_wide(dropped), "long", "fit its wide dtype int64")
    # (a float column takes NaN there: the missing value)
    assert np.isnan(
        to_wide(one.drop(index=(0, "acceleration", "chiacchio")))["chiacchio_volume"][0]
    )


def test_wide_attrs_checks_its_arguments():
    assert wide_attrs("velocity", ["yoshikawa"], ["coverage"]) == {
        "capacity": "velocity",
        "kinds": ["yoshikawa"],
        "scores": ["coverage"],
    }
    _refused(lambda: wide_attrs("speed", [], []), "capacity")
    _refused(lambda: wide_attrs("force", ["a"], ["cover"]), "scores", "score names among")
    _refused(lambda: score_columns(5), "frame", "a wide results DataFrame")
    _refused(lambda: score_columns([1, 2]), "frame", "column names (str)")


# -- the summaries use the same structure ---------------------------------------------------


def test_summaries_take_the_kinds_from_the_structure():
    frame = sweep("force", True, True)
    kinds = frame.attrs["kinds"]
    assert result_kinds(frame) == kinds
    assert result_kinds(frame.columns) == kinds  # bare names: built-ins, then the old rule
    # a per-configuration column named like a score is no kind where the kinds are recorded
    stray = frame.assign(tool_volume=1.0)
    assert result_kinds(stray) == kinds
    assert "tool" not in summarize(stray).index.get_level_values("ellipsoid")
    assert result_kinds(stray.columns, kinds=NAMES) == kinds
    summary = summarize(frame)

    def finite(kind: str) -> bool:
        columns = [f"{kind}_{s}" for s in SUMMARY_SCORES if f"{kind}_{s}" in frame]
        return bool(np.isfinite(frame[columns].to_numpy(dtype=float)).any())

    held = list(dict.fromkeys(summary.index.get_level_values("ellipsoid")))
    assert held == [kind for kind in kinds if finite(kind)]
    # the statistics against an independent computation over the finite values
    for (kind, score), record in summary.iterrows():
        values = frame[f"{kind}_{score}"].to_numpy(dtype=float)
        finite = values[np.isfinite(values)]
        assert record["defined"] == finite.size
        assert record["mean"] == pytest.approx(finite.mean(), rel=1e-12, abs=1e-300)
        assert record["median"] == pytest.approx(np.median(finite), rel=1e-12, abs=1e-300)
        assert record["max"] == finite.max() and record["min"] == finite.min()
        if finite.size > 1:
            assert record["std"] == pytest.approx(finite.std(ddof=1), rel=1e-9, abs=1e-300)
    # read back without attrs: the candidates by name
    bare = pd.DataFrame(frame.to_dict("list"))
    assert bare.attrs == {}
    pd.testing.assert_frame_equal(summarize(bare, kinds=NAMES), summary)
    assert split_column("chiacchio_w2_coverage", kinds) == ("chiacchio_w2", "coverage")
    assert split_column("volume_like_volume", kinds) == ("volume_like", "volume")
    assert split_column("tool_volume", kinds) is None
    assert split_column("chiacchio_coverage") == ("chiacchio", "coverage")
    assert split_column("polytope_volume") is None and split_column("q1") is None
    _refused(lambda: split_column("chiacchio_coverage", "chiacchio"), "kinds")
    _refused(lambda: split_column("chiacchio_coverage", [1]), "kinds")
    _refused(lambda: result_kinds("chiacchio_coverage"), "columns")


def test_every_function_refuses_a_wrong_first_argument():
    # as tests/test_bad_inputs.py holds every module of tables and figures to
    import inspect

    from polyell.comparison import long_form

    an = pe.analyze(ARM.dynamics(Q[0]), ARM.tau_max)
    wrong = [None, 5, "x", pe.compare(an, 8, mvie=False, outer=False), an, np.zeros(3), []]
    checked = 0
    for name in long_form.__all__:
        function = getattr(long_form, name)
        if not inspect.isfunction(function):
            continue
        required = [
            p
            for p in inspect.signature(function).parameters.values()
            if p.default is p.empty and p.kind is p.POSITIONAL_OR_KEYWORD
        ]
        for value in wrong:
            try:
                function(value, *["x"] * (len(required) - 1))
            except pe.PolyellError:
                checked += 1
            except Exception as exn:  # pragma: no cover - the failure to report
                pytest.fail(f"{name}({type(value).__name__}): {type(exn).__name__}: {exn}")
    assert checked >= 3 * len(wrong) - 1  # score_columns([]) is an empty frame's columns
