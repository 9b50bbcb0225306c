"""Run a study: every configuration analysed and compared, tables and figures written."""

from __future__ import annotations

import json
import logging
import math
import os
import re
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polyell.capacities import analyze, capacity_class, takes_horizon
from polyell.capacities.horizon import robot_horizon
from polyell.comparison.comparison import SCORE_NAMES, Comparison, compare, compared_kinds
from polyell.comparison.latex_text import (
    escape_latex,
    escape_markdown,
    latex_direction,
    markdown_line,
    markdown_text,
)
from polyell.comparison.limits import limits_table
from polyell.comparison.point_tables import write_point_tables
from polyell.comparison.summary import (
    SUMMARY_SCORES,
    format_summary_table,
    result_kinds,
    split_column,
    summarize,
)
from polyell.comparison.tables import (
    Caption,
    format_comparison_table,
    format_limits_table,
    score_display,
)
from polyell.errors import InputError, PolyellError, StorageError
from polyell.models.task import task_unit
from polyell.models.urdf import UrdfRobot
from polyell.report import format_analysis
from polyell.storage import (
    existing_parts,
    folder_lock,
    remove_stale_temporaries,
    write_atomically,
    write_csv,
    write_text_atomically,
)
from polyell.studies.cluster import check_scheduler
from polyell.studies.spec import Point, Robot, StudySpec
from polyell.studies.sweep import per_row_note, sweep
from polyell.studies.trajectory import Trajectory, tangent_limits

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

    from polyell.capacities import Analysis
    from polyell.comparison.layout import TableLayout
    from polyell.studies.spec import GridAxis

__all__ = ["STUDY_FILES", "run_study"]

#: The names of the files a study writes into its folder (the sweep's dataset goes into its
#: own folder, ``results/``); a study run removes what a killed run left of them.
STUDY_FILES = re.compile(
    r"numbers\.md|report\.html|manifest\.json|results\.csv"
    r"|(?:comparison|limits|summary|scores|results)(?:_velocity|_force)?\.(?:csv|md|tex)"
    r"|(?:sets|limits|map|series|histogram)_[A-Za-z0-9_.-]+\.(?:pdf|png|svg)"
    r"|tangent_limits(?:_velocity|_force)?\.(?:pdf|png|svg)"
    r"|posture_(?:choice|targets)(?:_velocity|_force)?\.(?:csv|md|tex)"
    r"|posture_values(?:_velocity|_force)?\.csv"
    r"|posture_indices(?:_velocity|_force)?\.(?:pdf|png|svg)"
)
#: The label preset of Chiacchio's paper: with it, ``numbers.md`` also carries the paper's
#: names and equation numbers (``xdd_g (eq. 8)``, ``M (eq. 14)``).
PAPER_PRESET = "chiacchio2000"
#: The lock a running study holds on its folder (hidden: not one of its outputs).
STUDY_LOCK = ".polyell-study.lock"
#: Notes on standard error (``polyell study`` shows INFO).
_log = logging.getLogger("polyell")


def _prepare(out: str | os.PathLike[str]) -> Path:
    if not isinstance(out, str | os.PathLike) or not str(out):
        raise InputError(
            "out",
            "a folder path (str or pathlib.Path)",
            repr(out)[:120],
            "pass the output folder, e.g. out='results/study1'.",
        )
    folder = Path(out)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".polyell-write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as exn:
        raise InputError(
            "out",
            "a folder polyell can write to",
            f"{folder} ({exn.strerror})",
            "choose another folder (--out), or fix its permissions or free space.",
        ) from None
    return folder


def _layout(spec: StudySpec, capacity: str) -> TableLayout:
    """The tables' layout of a capacity: ``[output] sets`` kept to this capacity's sets.

    A set of another compared capacity (``static`` beside accelerations) is left out of
    this capacity's tables; that every set exists in some capacity is checked at load.
    The captions are those ``[output] captions`` gives this capacity's tables
    (``comparison_force`` for the force capacity's ``comparison``); ``siunitx`` and
    ``text_width`` are the study's.
    """
    layout = spec.file.output.layout_of(capacity_class(capacity).output_suffix)
    if layout.sets is None:
        return layout
    own = {"polytope", *compared_kinds(capacity), *(c.name for c in spec.candidates)}
    kept = tuple(name for name in layout.sets if name in own)
    return replace(layout, sets=kept or ("polytope",))


def _run_points(spec: StudySpec, folder: Path, notes: list[str] | None = None) -> list[Path]:
    """Every capacity of the study at every point: tables, figures, numbers, report.

    A figure not drawn (an unbounded or empty set) is said in ``notes`` (the manifest's).
    """
    notes = [] if notes is None else notes
    written: list[Path] = []
    numbers = [_heading(spec, f"{spec.title}: the numbers").rstrip("\n"), ""]
    report: list[tuple[str, Any]] = _about(spec)
    for capacity in spec.file.compare.capacities:
        # The acceleration outputs keep their names; another capacity's carry its name.
        suffix = capacity_class(capacity).output_suffix
        if len(spec.file.compare.capacities) > 1:
            numbers += [f"# {capacity.capitalize()} capacity", ""]
        written += _run_points_capacity(spec, folder, capacity, suffix, numbers, report, notes)
    written.append(write_text_atomically(folder / "numbers.md", "\n".join(numbers)))
    if "html" in spec.file.output.formats:
        from polyell.interactive import write_report

        written.append(write_report(folder / "report.html", spec.title, report))
    return written


def _undrawn(analysis: Analysis) -> str:
    """Why a point's sets have no figure: its polytope is unbounded or empty."""
    if getattr(analysis.polytope, "is_empty", False):
        return (
            f"its {analysis.capacity} polytope is empty (no {analysis.quantity} within the limits)"
        )
    return (
        f"its {analysis.capacity} polytope is unbounded (a singular posture: "
        f"{analysis.quantity} along some direction need no joint torque); numbers.md and the "
        "tables give its numbers"
    )


def _analyze_point(spec: StudySpec, point: Point, capacity: str) -> Analysis:
    """A point's analysis; in motion (``qd``, a URDF robot) with the torque limits at qd."""
    robot = _robot_of(spec, point.robot)
    cls = capacity_class(capacity)
    limits = cls.limit_arguments(*cls._robot_limits(robot, point.qd))
    if point.qd is None:
        dynamics = robot.model.dynamics(point.q)
    else:  # (no points in motion in a study of velocities: checked at load)
        assert isinstance(robot.model, UrdfRobot)  # checked at load
        dynamics = robot.model.dynamics(point.q, point.qd)
    within = _horizon(spec, capacity)
    if within:  # the state's joint position and velocity limits over the horizon
        qd = np.zeros_like(point.q) if point.qd is None else point.qd
        limits |= robot_horizon(robot.model, **within).at(point.q, qd).arguments()
    return analyze(dynamics, capacity=capacity, **limits)


def _horizon(spec: StudySpec, capacity: str) -> dict[str, Any]:
    """``[compare] horizon`` and ``braking`` for a capacity that takes them, else none."""
    compare = spec.file.compare
    if compare.horizon is None or not takes_horizon(capacity):
        return {}
    return {"horizon": compare.horizon, "braking": compare.braking}


def _run_points_capacity(
    spec: StudySpec,
    folder: Path,
    capacity: str,
    suffix: str,
    numbers: list[str],
    report: list[tuple[str, Any]],
    notes: list[str],
) -> list[Path]:
    from polyell.figures import plot_directional_limits, plot_sets, plot_sets_3d

    figures = bool(spec.file.output.figure_formats)
    interactive = "html" in spec.file.output.formats

    layout = _layout(spec, capacity)
    written: list[Path] = []
    frames = []
    comparisons: dict[str, Comparison] = {}
    directions: dict[str, list[Any]] = {}
    for point in spec.points:
        analysis = _analyze_point(spec, point, capacity)
        cmp = compare(analysis, **_compared(spec))
        q_text = ", ".join(f"{v:.6g}" for v in point.q)
        motion = []
        if point.qd is not None:
            limits = "; ".join(
                f"{name} = ({', '.join(f'{v:.6g}' for v in values)})"
                for name, values in analysis.joint_limits().items()
            )
            qd_text = ", ".join(f"{v:.6g}" for v in point.qd)
            motion = [f"qd = ({qd_text}) rad/s; torque limits at qd [N m]: {limits}", ""]
        numbers += [
            "## "
            + escape_markdown(
                f"{point.label}{': ' + point.table.title if point.table.title else ''}", "label"
            ),
            "",
            f"q = ({q_text}) rad",
            "",
            *motion,
            *_code_block(_along_directions(analysis, point, layout)),
            "",
            "Scores (`pe.compare`):",
            "",
            cmp.to_markdown(replace(layout, sets=None)),  # every set, the study's labels
        ]
        frame = cmp.to_frame()
        frame.index = [f"{point.label}: {layout.set_label(k, capacity)}" for k in frame.index]
        frames.append(frame)
        comparisons[point.label] = cmp
        directions[point.label] = _named_or_vectors(point)
        heading = f"{point.label}{': ' + point.table.title if point.table.title else ''}"
        if suffix:
            heading = f"{heading} ({capacity})"
        if "html" in spec.file.output.formats:
            from polyell.interactive import HtmlTable, interactive_sets

            drawable = analysis.m in (2, 3) and getattr(analysis.polytope, "is_bounded", True)
            if drawable and not getattr(analysis.polytope, "is_empty", False):
                report.append((heading, interactive_sets(cmp, labels=layout)))
            elif analysis.m in (2, 3):
                report.append((heading, f"No figure of the sets: {_undrawn(analysis)}."))
            limits = limits_table(cmp, directions[point.label])
            for name, text in (
                ("scores", format_comparison_table(cmp, "html", layout=layout)),
                ("directional limits", format_limits_table(limits, "html", layout=layout)),
            ):
                report.append((f"{heading}: {name}", HtmlTable(text)))
        P = analysis.polytope
        if not getattr(P, "is_bounded", True) or getattr(P, "is_empty", False):
            # an unbounded or empty force polytope has no figure: said in the manifest's
            # notes and the log (and numbers.md)
            if analysis.m in (2, 3) and (figures or interactive):
                note = (
                    f"no figures of point {point.label!r} ({capacity}: sets_{point.stem}"
                    f"{suffix}, limits_{point.stem}{suffix}): {_undrawn(analysis)}"
                )
                notes.append(note)
                _log.info("note: %s", note)
            continue
        stem = folder / f"sets_{point.stem}{suffix}"
        title = point.table.title or point.label
        mvie = cmp.mvie if spec.file.compare.mvie and cmp["mvie"].defined else None
        kinds = (*analysis.ellipsoid_kinds, *(("mvie",) if mvie is not None else ()))
        first_extra = len(analysis.ellipsoid_kinds) + 1  # after the kinds and the MVIE
        extra = {
            kind: cmp.ellipsoid(kind)
            for kind in cmp.kinds[first_extra:]  # the outer ellipsoid (if computed), candidates
            if cmp[kind].defined
        }
        drawn: dict[str, Any] = {"kinds": kinds, "mvie": mvie, "extra": extra}
        drawn["labels"] = layout.labels  # the tables' names of the sets
        if analysis.m == 2:
            figure = plot_sets(analysis, title=title, **drawn)
            written += _save(spec, figure, stem)
            if P.dim == 2:
                figure = plot_directional_limits(analysis, **drawn)
                written += _save(spec, figure, folder / f"limits_{point.stem}{suffix}")
        elif analysis.m == 3:
            figure = plot_sets_3d(analysis, title=title, **drawn)
            written += _save(spec, figure, stem)
    import pandas as pd

    # The printed tables (LaTeX, Markdown, CSV: the same labels, units and percentages) and
    # the exact scores for scripts (scores.csv: fractions, every digit).
    written += write_point_tables(
        comparisons,
        directions,
        folder,
        layout,
        spec.title,
        description=spec.file.description,
        suffix=suffix,
    )
    scores = pd.concat(frames).to_csv(index_label="ellipsoid")
    written.append(write_text_atomically(folder / f"scores{suffix}.csv", scores))
    return written


def _run_posture(spec: StudySpec, folder: Path, progress: bool = False) -> list[Path]:
    """A posture study: the self-motion through q0, the choice of each index, the figure.

    The postures are sampled once; for each capacity of ``[compare] capacities`` writes
    ``posture_choice.{tex,md,csv}`` (:func:`polyell.write_posture_tables`: each pick's row,
    its joint angles and the truth there, in each criterion's unit),
    ``posture_values.csv`` (one row per posture: its joint angles, its position along the
    manifold and every set's values), ``posture_indices.<format>`` and, with ``targets``,
    ``posture_targets.{tex,md,csv}`` (the choice aggregated over random targets); the
    names of a capacity other than accelerations end in ``_<capacity>``.
    """
    from polyell.models.self_motion import self_motion

    posture = spec.posture
    assert posture is not None
    robot = spec.robots[0]  # a posture study has one robot (checked when it loads)
    from polyell.studies.posture import posture_bar

    motions = []
    with posture_bar(len(posture.starts), "sampling the self-motion", progress, " starts") as bar:
        for q in posture.starts:
            motions.append(
                self_motion(robot.model, q, posture.table.count, seed=posture.table.seed)
            )
            bar.update(1)

    def one(spec: StudySpec, folder: Path, capacity: str, progress: bool, *_: Any) -> Any:
        return _posture_outputs(spec, folder, capacity, motions, progress)

    return _each_capacity(one, spec, folder, progress, None, {}, [])


def _posture_outputs(
    spec: StudySpec, folder: Path, capacity: str, motions: list[Any], progress: bool = False
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity's choice over the sampled postures: tables, values, figure, sections."""
    from polyell.figures import plot_posture_indices
    from polyell.studies.posture import posture_bar, posture_choice
    from polyell.studies.posture_targets import posture_choice_over_targets

    posture = spec.posture
    assert posture is not None
    robot = spec.robots[0]
    cls = capacity_class(capacity)
    suffix = cls.output_suffix
    named = "" if len(spec.file.compare.capacities) == 1 else f"{capacity}: "
    configurations = np.vstack([motion.configurations for motion in motions])
    options: dict[str, Any] = {
        "direction": posture.direction,
        "mvie": spec.file.compare.mvie,
        "outer": spec.file.compare.outer,
        "candidates": spec.candidates,
        "capacity": capacity,
    }
    # velocities: the robot's own joint velocity limits; the others its torque limits
    limits = cls.limit_arguments(*cls._robot_limits(robot))
    options |= _horizon(spec, capacity)
    choice = posture_choice(robot.model, configurations, **limits, **options, progress=progress)
    along = f"along {posture.label}"
    along_tex = f"along {latex_direction(posture.label)}"  # "$-$z": a minus, not a hyphen
    layout = _layout(spec, capacity)
    picks = f"the posture each index picks ({{}}, {len(configurations)} postures)"
    written = _posture_tables(
        spec,
        choice.table,
        folder,
        f"{named}{picks.format(along)}",
        f"posture_choice{suffix}",
        layout,
        escape_latex(f"{named}{picks}").replace("\\{\\}", along_tex, 1),
    )
    import pandas as pd

    joints = pd.DataFrame(configurations, columns=[f"q{i + 1}" for i in range(robot.model.n)])
    values = choice.values.copy()
    values.columns = [f"{kind}_{quantity}" for kind, quantity in values.columns]
    component = np.concatenate([np.full(len(m.configurations), i) for i, m in enumerate(motions)])
    position = np.concatenate([m.position for m in motions])
    frame = pd.concat([joints, values], axis=1).assign(component=component, position=position)
    frame = frame[["component", "position", *[c for c in frame.columns[:-2]]]]
    frame.index.name = "posture"
    values_csv = folder / f"posture_values{suffix}.csv"
    written.append(write_text_atomically(values_csv, frame.to_csv()))
    # One traced curve has a position along it; a random walk's |q - q0|, or several
    # components, do not order the postures along one curve: the posture number then.
    traced = len(motions) == 1 and motions[0].method == "trace"
    with posture_bar(1, f"{capacity}: drawing posture_indices", progress, " figures") as bar:
        figure = plot_posture_indices(
            choice.values,
            choice.table,
            position=motions[0].position if traced else None,
            title=f"{spec.title} ({named}{along})",
            labels=layout.labels,
        )
        stem = folder / f"posture_indices{suffix}"
        written += _save(spec, figure, stem)
        bar.update(1)
    sections: list[tuple[str, Any]] = [
        (
            f"{named}The posture each index picks ({along}; regret as a fraction)",
            _labelled_sets(choice.table, layout, capacity),
        )
    ]
    if posture.table.targets is not None:
        over = posture_choice_over_targets(
            robot.model,
            None,
            **limits,
            count=posture.table.targets,
            seed=posture.table.seed,
            postures=posture.table.count,
            **options,
            progress=progress,
        )
        title = f"{named}regret over {len(over.targets)} random targets ({along})"
        title_tex = escape_latex(f"{named}regret over {len(over.targets)} random targets (")
        written += _posture_tables(
            spec,
            over.summary,
            folder,
            title,
            f"posture_targets{suffix}",
            layout,
            f"{title_tex}{along_tex})",
        )
        sections.append(
            (
                f"{named}Over {posture.table.targets} random targets",
                _labelled_sets(over.summary, layout, capacity),
            )
        )
    return written, sections


def _posture_tables(
    spec: StudySpec,
    table: pd.DataFrame,
    folder: Path,
    what: str,
    stem: str,
    layout: TableLayout,
    what_tex: str,
) -> list[Path]:
    """``<stem>.{tex,md,csv}`` of a posture table (:func:`polyell.write_posture_tables`).

    The LaTeX caption is ``what`` alone, a sentence (a paper's table has its own context:
    no study title before it; ``what_tex`` its LaTeX, the direction's signs a math minus),
    or the study's own (``[output] captions``, through ``layout``); the
    Markdown file's heading starts with the study's title, as every Markdown file of a
    study does.  The joint positions are headed in each joint's unit (``[m]`` for a
    prismatic joint).
    """
    from polyell.studies.posture_tables import (
        format_posture_table,
        joint_units,
        write_posture_tables,
    )

    label = "tab:" + stem.replace("_", "-")  # tab:posture-choice-force
    units = joint_units(spec.robots[0].model)  # (a posture study has one robot)
    own = layout.caption("posture_choice" if "picked" in table.columns else "posture_targets")
    caption = (
        (own.plain, own.latex)
        if own is not None
        else (f"{_sentence(what)}.", f"{_sentence(what_tex)}.")
    )
    written = write_posture_tables(
        table,
        folder,
        _sentence(what),
        label=label,
        stem=stem,
        layout=layout,
        caption=caption,
        joint_units=units,
    )
    heading = f"{spec.title}: {what}"
    markdown = format_posture_table(table, "markdown", heading, layout=layout, joint_units=units)
    written["markdown"] = write_text_atomically(folder / f"{stem}.md", markdown)
    return list(written.values())


def _labelled_sets(table: pd.DataFrame, layout: TableLayout, capacity: str) -> pd.DataFrame:
    """A posture table for the report: its sets (the index's first level) by their labels."""
    return table.rename(index=lambda kind: layout.set_label(str(kind), capacity), level=0)


#: Values along each axis of a heat map drawn in a figure; a grid with more draws every
#: k-th value (its title says so).  A figure's axes are about 1,000 pixels wide at 300 dpi,
#: and matplotlib draws each cell of a PDF as a path: 300 x 300 cells take about 70 MiB
#: (1,000 x 1,000 take 650 MiB and a 27 MB file).
MAP_AXIS_VALUES = 300
#: Values along each axis of a heat map in ``report.html`` (every cell carries the
#: configuration and its scores for the hover: about 0.5 kB).
REPORT_MAP_AXIS_VALUES = 128
#: Configurations a histogram is drawn from; a study of more draws a seeded random
#: sample of about as many (the figure says so).
HISTOGRAM_ROWS = 100_000
#: Bits of a sort key a pass of :class:`StreamedSummary` resolves, and the most values of
#: a column (or of one of its key ranges) kept whole.
_DIGIT_BITS = 12
_KEEP = 1 << 14
_SIGN = 1 << 63
_ALL_BITS = (1 << 64) - 1


def _parts(dataset: Path) -> list[Path]:
    """A sweep dataset's part files, in chunk order (configurations ascending)."""
    return [path for _, path in sorted(existing_parts(dataset).items())]


def _part_rows(part: Path) -> int:
    """A part's row count, from its Parquet footer."""
    import pyarrow.parquet as pq

    return int(pq.read_metadata(part).num_rows)


def _sort_keys(values: NDArray[np.float64]) -> NDArray[np.uint64]:
    """Unsigned keys in the order of the (finite) ``values``: IEEE bits, sign folded."""
    bits = np.ascontiguousarray(values, dtype=np.float64).view(np.uint64)
    sign = np.uint64(_SIGN)
    return np.where(bits & sign, ~bits, bits | sign)


def _key_value(key: int) -> float:
    """The float of a key of :func:`_sort_keys`."""
    bits = key ^ _SIGN if key & _SIGN else ~key & _ALL_BITS
    return float(np.array(bits, dtype=np.uint64).view(np.float64))


@dataclass
class _Range:
    """The values of a column whose sort keys start with ``prefix`` (``bits`` long).

    ``ranks`` are the ranks wanted among them (0-based), those of ``wanted`` among all the
    column's values; a pass counts their next digit (``histogram``) or keeps them whole.
    """

    prefix: int
    bits: int
    count: int
    ranks: list[int]
    wanted: list[int]
    histogram: NDArray[np.int64] | None = None
    kept: list[NDArray[np.uint64]] | None = None

    def start(self) -> None:
        """Ready for a pass: keep the range whole, or count its next digit."""
        if self.count <= _KEEP:
            self.kept = []
        else:
            self.histogram = np.zeros(1 << min(_DIGIT_BITS, 64 - self.bits), dtype=np.int64)

    def add(self, keys: NDArray[np.uint64]) -> None:
        """The keys of a part's values (all of them: this picks its range's)."""
        if self.bits:
            keys = keys[(keys >> np.uint64(64 - self.bits)) == np.uint64(self.prefix)]
        if self.kept is not None:
            self.kept.append(keys)
            return
        assert self.histogram is not None
        width = self.histogram.size.bit_length() - 1
        digits = (keys >> np.uint64(64 - self.bits - width)) & np.uint64(self.histogram.size - 1)
        self.histogram += np.bincount(digits.astype(np.int64), minlength=self.histogram.size)


def _narrow(range_: _Range, histogram: NDArray[np.int64], found: dict[int, float]) -> list[_Range]:
    """The ranges of the next digit that hold the wanted ranks (``found`` where resolved)."""
    width = histogram.size.bit_length() - 1
    below = np.concatenate([[0], np.cumsum(histogram)])
    narrower: dict[int, _Range] = {}
    for rank, wanted in zip(range_.ranks, range_.wanted, strict=True):
        digit = int(np.searchsorted(below, rank, side="right")) - 1
        prefix, bits = (range_.prefix << width) | digit, range_.bits + width
        if bits == 64:  # one key: the value itself
            found[wanted] = _key_value(prefix)
            continue
        if digit not in narrower:
            narrower[digit] = _Range(prefix, bits, int(histogram[digit]), [], [])
        narrower[digit].ranks.append(rank - int(below[digit]))
        narrower[digit].wanted.append(wanted)
    return list(narrower.values())


class StreamedSummary:
    """:func:`~polyell.comparison.summary.summarize` of results read one part at a time.

    The statistics of every ``<kind>_<score>`` column over all its finite values, in the
    order and layout of ``summarize``, with memory independent of the rows: ``defined``,
    ``min``, ``max`` and ``median`` are exact (the median by radix selection on the
    values' IEEE bits, ``_DIGIT_BITS`` a pass, its range kept whole once it holds at most
    ``_KEEP`` values); ``mean`` is the sum of the parts' sums (``math.fsum``) over the
    count and ``std`` the two-pass one of pandas (``ddof=1``) about that mean, both equal
    to the whole column's to rounding.  A column of at most ``_KEEP`` finite values is
    kept whole and summarised by ``summarize`` itself (every statistic exact).

    Parameters
    ----------
    columns : dict
        ``(kind, score)`` to its column, in the order of ``summarize``.
    """

    def __init__(self, columns: dict[tuple[str, str], str]) -> None:
        self.columns = columns
        self._count = dict.fromkeys(columns.values(), 0)
        self._sums: dict[str, list[float]] = {c: [] for c in columns.values()}
        self._low = dict.fromkeys(columns.values(), np.inf)
        self._high = dict.fromkeys(columns.values(), -np.inf)
        self._kept: dict[str, list[NDArray[np.float64]] | None] = {c: [] for c in columns.values()}
        self._first = {c: _Range(0, 0, 0, [], []) for c in columns.values()}
        for range_ in self._first.values():
            range_.histogram = np.zeros(1 << _DIGIT_BITS, dtype=np.int64)

    def add(self, frame: pd.DataFrame) -> None:
        """The next part's rows (the first pass)."""
        for column in self.columns.values():
            values = frame[column].to_numpy(dtype=float)
            values = values[np.isfinite(values)]
            if not values.size:
                continue
            self._count[column] += values.size
            self._sums[column].append(float(values.sum()))
            self._low[column] = min(self._low[column], float(values.min()))
            self._high[column] = max(self._high[column], float(values.max()))
            kept = self._kept[column]
            if kept is not None:
                kept.append(values)
                if self._count[column] > _KEEP:  # too many to keep: selected later
                    self._kept[column] = None
            self._first[column].add(_sort_keys(values + 0.0))  # (+ 0.0: -0.0 as 0.0)

    def extremes(self, column: str) -> tuple[float, float] | None:
        """The exact ``(min, max)`` of a column's finite values (None: it has none)."""
        if not self._count.get(column):
            return None
        return self._low[column], self._high[column]

    def summary(self, parts: Sequence[Path]) -> pd.DataFrame:
        """The summary, reading ``parts`` again for the columns too long to keep whole."""
        import pandas as pd

        statistics: dict[str, dict[str, float]] = {}
        means: dict[str, float] = {}
        ranges: dict[str, list[_Range]] = {}
        found: dict[str, dict[int, float]] = {}
        for (kind, score), column in self.columns.items():
            count, kept = self._count[column], self._kept[column]
            if not count:
                continue
            if kept is not None:  # every value: summarize's own numbers
                whole = summarize(
                    pd.DataFrame({column: np.concatenate(kept)}), (score,), kinds=[kind]
                )
                statistics[column] = {name: whole[name].iloc[0] for name in whole.columns}
                continue
            means[column] = math.fsum(self._sums[column]) / count
            middle = sorted({(count - 1) // 2, count // 2})
            found[column] = {}
            first = self._first[column]
            first.count, first.ranks, first.wanted = count, list(middle), list(middle)
            assert first.histogram is not None
            ranges[column] = _narrow(first, first.histogram, found[column])
        squares: dict[str, list[float]] = {column: [] for column in means}
        while any(ranges.values()) or squares:
            for group in ranges.values():
                for range_ in group:
                    range_.start()
            read = list(dict.fromkeys([*(c for c in ranges if ranges[c]), *squares]))
            for part in parts:
                frame = pd.read_parquet(part, columns=read)
                for column in read:
                    values = frame[column].to_numpy(dtype=float)
                    values = values[np.isfinite(values)] + 0.0
                    if column in squares:
                        squares[column].append(float(((means[column] - values) ** 2).sum()))
                    keys = _sort_keys(values) if ranges.get(column) else None
                    for range_ in ranges.get(column, ()):
                        assert keys is not None
                        range_.add(keys)
            for column, values in squares.items():
                count = self._count[column]
                variance = math.fsum(values) / (count - 1) if count > 1 else 0.0
                statistics[column] = {"std": float(np.sqrt(variance))}
            squares = {}
            for column, group in ranges.items():
                narrower = []
                for range_ in group:
                    if range_.kept is not None:
                        ordered = np.sort(np.concatenate([np.zeros(0, np.uint64), *range_.kept]))
                        for rank, wanted_rank in zip(range_.ranks, range_.wanted, strict=True):
                            found[column][wanted_rank] = _key_value(int(ordered[rank]))
                    else:
                        assert range_.histogram is not None
                        narrower += _narrow(range_, range_.histogram, found[column])
                ranges[column] = narrower
        rows: dict[tuple[str, str], dict[str, Any]] = {}
        for key, column in self.columns.items():
            count = self._count[column]
            if not count:
                continue
            if self._kept[column] is not None:
                rows[key] = statistics[column]
                continue
            lower, upper = found[column][(count - 1) // 2], found[column][count // 2]
            rows[key] = {
                "defined": int(count),
                "mean": means[column],
                "std": statistics[column]["std"],
                "min": self._low[column],
                # numpy's median of an even count: the mean of the two middle values
                "median": lower if count % 2 else float(np.mean(np.array([lower, upper]))),
                "max": self._high[column],
            }
        if not rows:
            return summarize(pd.DataFrame())
        # as summarize builds its frame (its columns, its index's names)
        empty = summarize(pd.DataFrame())
        summary = pd.DataFrame.from_dict(rows, orient="index", columns=list(empty.columns))
        summary.index = pd.MultiIndex.from_tuples(summary.index, names=empty.index.names)
        return summary


def _hash_rows(configuration: NDArray[np.int64]) -> NDArray[np.uint64]:
    """A fixed pseudo-random 64-bit number per configuration index (splitmix64)."""
    with np.errstate(over="ignore"):
        z = configuration.astype(np.uint64) + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))


class _RowSample:
    """Rows of a dataset kept for its histograms: all, or a seeded sample of about ``limit``.

    A configuration is kept when the hash of its index falls below ``limit / total`` of
    the 64-bit range: the sample does not depend on how the dataset was chunked.
    """

    def __init__(self, total: int, columns: Sequence[str], limit: int | None = None) -> None:
        self.total, self.columns = total, list(columns)
        limit = HISTOGRAM_ROWS if limit is None else limit
        self.threshold = None if total <= limit else np.uint64(int(limit / total * 2.0**64))
        self._kept: list[pd.DataFrame] = []

    @property
    def sampled(self) -> bool:
        """Whether the rows are a sample (the study has more than ``limit``)."""
        return self.threshold is not None

    def add(self, frame: pd.DataFrame) -> None:
        """A part's rows (in order)."""
        if not self.columns:
            return
        if self.threshold is None:
            self._kept.append(frame[self.columns])
            return
        keep = _hash_rows(frame["configuration"].to_numpy()) < self.threshold
        self._kept.append(frame.loc[keep, self.columns])

    def frame(self) -> pd.DataFrame:
        """The kept rows."""
        import pandas as pd

        if not self._kept:
            return pd.DataFrame(columns=self.columns)
        return pd.concat(self._kept, ignore_index=True)


class _SubGrid:
    """Every k-th value along each of a grid's two varying joints, read part by part.

    ``y`` varies slower than ``x`` (configuration ``iy * len(x) + ix``); along an axis of
    more than ``limit`` values, every ``ceil(len / limit)``-th is kept, the first included.
    ``columns`` None keeps whole rows (:meth:`frame`), else those columns (:meth:`values`).
    """

    def __init__(
        self, y: GridAxis, x: GridAxis, limit: int, columns: Sequence[str] | None = None
    ) -> None:
        self.y, self.x, self.columns = y, x, columns
        self.steps = (-(-y.values.size // limit), -(-x.values.size // limit))
        self._rows: list[pd.DataFrame] = []
        self._values: dict[str, list[NDArray[np.float64]]] = {c: [] for c in columns or ()}

    @property
    def decimated(self) -> bool:
        """Whether some grid values are left out."""
        return self.steps != (1, 1)

    @property
    def axes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The kept values of ``y`` and of ``x``."""
        return self.y.values[:: self.steps[0]], self.x.values[:: self.steps[1]]

    def shape_note(self) -> str:
        """What a figure draws: ``"1000 x 1000 of 3000 x 3000 grid points"``."""
        ys, xs = self.axes
        return f"{ys.size} x {xs.size} of {self.y.values.size} x {self.x.values.size} grid points"

    def note(self) -> str:
        """What is drawn: ``"1000 x 1000 of 3000 x 3000 grid points: every 3rd value ..."``."""
        ys, xs = self.axes
        return (
            f"{ys.size} x {xs.size} of {self.y.values.size} x {self.x.values.size} grid "
            f"points: {_every(self.steps[0])} of {self.y.name}, {_every(self.steps[1])} "
            f"of {self.x.name}"
        )

    def add(self, frame: pd.DataFrame) -> None:
        """A part's rows."""
        iy, ix = np.divmod(frame["configuration"].to_numpy(), self.x.values.size)
        keep = (iy % self.steps[0] == 0) & (ix % self.steps[1] == 0)
        if self.columns is None:
            self._rows.append(frame[keep])
            return
        for column in self.columns:
            self._values[column].append(frame[column].to_numpy(dtype=float)[keep])

    def values(self, column: str) -> NDArray[np.float64]:
        """A kept column as a map, shape (len(y kept), len(x kept))."""
        ys, xs = self.axes
        return np.concatenate(self._values[column]).reshape(ys.size, xs.size)

    def frame(self) -> pd.DataFrame:
        """The kept rows (``columns`` None)."""
        import pandas as pd

        return pd.concat(self._rows, ignore_index=True)


def _every(k: int) -> str:
    """``"every value"``, ``"every 2nd value"``, ``"every 11th value"``."""
    if k == 1:
        return "every value"
    suffix = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"every {k}{suffix} value"


class _Stream:
    """One robot's sweep dataset of a capacity, read one part at a time.

    The first pass (:meth:`add`, part by part) feeds what the study's outputs need, each of
    a size that does not grow with the rows: the summary's statistics
    (:class:`StreamedSummary`, its further passes in :meth:`summary`), the extremes of the
    mapped columns (one colour scale per score), the heat maps' values and the report's
    map (:class:`_SubGrid`) and the histograms' rows (:class:`_RowSample`).
    """

    def __init__(self, spec: StudySpec, dataset: Path, capacity: str) -> None:
        self.spec, self.capacity = spec, capacity
        self.parts = _parts(dataset)
        self.count = sum(_part_rows(part) for part in self.parts)
        self.varying = [axis for axis in spec.grid if axis.values.size > 1]
        self.kinds: list[str] = []
        self.maps: list[str] = []
        self.extremes: dict[str, tuple[float, float]] = {}
        self.statistics: StreamedSummary | None = None
        self.map: _SubGrid | None = None
        self.report_map: _SubGrid | None = None
        self.sample: _RowSample | None = None

    def _start(self, frame: pd.DataFrame) -> None:
        output = self.spec.file.output
        self.kinds = result_kinds(frame, _study_kinds(self.spec, self.capacity))
        self.statistics = StreamedSummary(
            {
                (kind, score): f"{kind}_{score}"
                for kind in self.kinds
                for score in SUMMARY_SCORES
                if f"{kind}_{score}" in frame.columns
            }
        )
        # A map of a kind this capacity does not have is not drawn for it.
        self.maps = [name for name in output.maps if name in frame.columns]
        if self.maps and len(self.varying) == 2:
            y, x = self.varying
            self.map = _SubGrid(y, x, MAP_AXIS_VALUES, self.maps)
            if "html" in output.formats:
                self.report_map = _SubGrid(y, x, REPORT_MAP_AXIS_VALUES)
        measured = [kind for kind in self.kinds if kind not in ("mvie", "outer")]
        columns = [
            f"{kind}_{score}"
            for score in output.histograms
            for kind in measured
            if f"{kind}_{score}" in frame.columns
        ]
        self.sample = _RowSample(self.count, columns)

    def add(self, frame: pd.DataFrame) -> None:
        """The next part's rows (the first pass)."""
        if self.statistics is None:
            self._start(frame)
        assert self.statistics is not None and self.sample is not None
        self.statistics.add(frame)
        for name in self.maps:
            values = frame[name].to_numpy(dtype=float)
            values = values[np.isfinite(values)]
            if values.size:
                low, high = self.extremes.get(name, (np.inf, -np.inf))
                self.extremes[name] = (min(low, values.min()), max(high, values.max()))
        for grid in (self.map, self.report_map):
            if grid is not None:
                grid.add(frame)
        self.sample.add(frame)

    def summary(self) -> pd.DataFrame:
        """The summary over every configuration (further passes where needed)."""
        assert self.statistics is not None
        return self.statistics.summary(self.parts)


def _run_many(
    spec: StudySpec,
    folder: Path,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    notes: list[str],
) -> list[Path]:
    """A grid or random study: one sweep per robot, tables and figures side by side.

    A study of ``[[robots]]`` keeps each robot's dataset in ``results/robot=<name>/`` (a
    Hive partition: ``pd.read_parquet(out / "results")`` reads a ``robot`` column), and
    writes a ``robot`` column into ``results.csv`` and ``summary.csv``; its figures are
    named ``map_<robot>.<name>``, ``histogram_<robot>.<score>``.
    """
    if spec.trajectory is not None:
        return _run_trajectory(spec, folder, progress, scheduler, seconds, notes)
    return _each_capacity(_run_many_capacity, spec, folder, progress, scheduler, seconds, notes)


def _each_capacity(
    run_one: Any,
    spec: StudySpec,
    folder: Path,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    notes: list[str],
) -> list[Path]:
    """``run_one`` for each capacity of ``[compare] capacities``, then the HTML report."""
    written: list[Path] = []
    sections = _about(spec)
    for capacity in spec.file.compare.capacities:
        files, capacity_sections = run_one(
            spec, folder, capacity, progress, scheduler, seconds, notes
        )
        written += files
        sections += capacity_sections
    if "html" in spec.file.output.formats:
        from polyell.interactive import write_report

        written.append(write_report(folder / "report.html", spec.title, sections))
    return written


def _run_many_capacity(
    spec: StudySpec,
    folder: Path,
    capacity: str,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    notes: list[str],
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity of a grid or random study: its sweep, tables, figures, report sections.

    The acceleration outputs keep their names (``results/``, ``summary.tex``,
    ``map_<name>.png``); another capacity's carry its name (``results_force/``,
    ``summary_force.tex``, ``map_<name>_force.png``).  The sweep's dataset is read back
    one part at a time (:class:`_Stream`): ``results.csv`` (``[output] csv``), the summary,
    the maps and the histograms all hold memory that does not grow with the
    configurations.
    """
    suffix = capacity_class(capacity).output_suffix
    streams: dict[str, _Stream] = {}
    for index, robot in enumerate(spec.robots):
        results_folder = folder / f"results{suffix}"
        out = results_folder / f"robot={robot.name}" if spec.by_robot else results_folder
        configurations = spec.configuration_set(index)  # lazy: made a chunk at a time
        dataset = _sweep(spec, robot, configurations, out, progress, scheduler, seconds, capacity)
        streams[robot.name if spec.by_robot else ""] = _Stream(spec, dataset, capacity)
    count = sum(stream.count for stream in streams.values())
    written = _stream_results(spec, folder, f"results{suffix}", streams, count, notes)
    summaries = {name: stream.summary() for name, stream in streams.items()}
    written += _write_summary(spec, folder, summaries, count, capacity)
    # Maps of one score share one colour scale, so that colours compare across candidates
    # (and robots): the extremes of every configuration's value, not only of those drawn.
    maps = next(iter(streams.values())).maps
    scales: dict[str, tuple[float, float]] = {}
    for stream in streams.values():
        for name, (low, high) in stream.extremes.items():
            score = _split(name, stream.kinds)[1]
            factor = score_display(score, capacity)[1]
            old = scales.get(score, (np.inf, -np.inf))
            scales[score] = (min(old[0], factor * low), max(old[1], factor * high))
    sections: list[tuple[str, Any]] = []
    for name, stream in streams.items():
        files, robot_sections = _many_outputs(
            spec, folder, name, stream, summaries[name], scales, capacity, maps, notes
        )
        written += files
        sections += robot_sections
    return written, sections


def _stream_results(
    spec: StudySpec,
    folder: Path,
    stem: str,
    streams: dict[str, _Stream],
    count: int,
    notes: list[str],
) -> list[Path]:
    """The first pass over the datasets' parts: each stream fed, ``<stem>.csv`` written.

    The CSV (``[output] csv``) is written part by part as it is read (a ``robot`` column
    first in a study of several robots), so that it never is in memory whole; without it,
    the log and the manifest say where the rows are.
    """
    import pandas as pd
    import pyarrow.parquet as pq

    # The columns of every robot's rows, as pandas.concat joins them (the first robot's,
    # then those only later ones have: a robot of fewer joints has no q7), robot first.
    columns: list[str] = ["robot"] if spec.by_robot else []
    for stream in streams.values():
        names = pq.read_schema(stream.parts[0]).names
        columns += [name for name in names if name not in columns]

    def read(handle: Any) -> None:
        header = True
        for robot, stream in streams.items():
            for part in stream.parts:
                frame = pd.read_parquet(part)
                stream.add(frame)
                if handle is not None:
                    if spec.by_robot:
                        frame.insert(0, "robot", robot)
                    write_csv(frame.reindex(columns=columns), handle, header=header)
                    header = False

    output = spec.file.output
    if output.writes_csv(count):
        return [write_atomically(folder / f"{stem}.csv", lambda name: _with_file(name, read))]
    read(None)
    why = (
        "[output] csv = false"
        if output.csv is False
        else f'{count:,} configurations, more than [output] csv = "auto" writes'
    )
    note = (
        f"{stem}.csv not written ({why}): every row is in the Parquet dataset {stem}/ "
        f"(pandas.read_parquet); csv = true writes it, streamed"
    )
    _log.info("note: %s", note)
    notes.append(note)
    return []


def _with_file(name: str, write: Any) -> None:
    """``write(handle)`` on the file ``name``, opened for binary writing."""
    with open(name, "wb") as handle:
        write(handle)


def _many_outputs(
    spec: StudySpec,
    folder: Path,
    robot: str,
    stream: _Stream,
    summary: pd.DataFrame,
    scales: dict[str, tuple[float, float]],
    capacity: str,
    maps: list[str],
    notes: list[str],
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """The figures of one robot's sweep of a capacity, and its sections of the report.

    ``robot`` is its name in a study of several robots, else ``""``; ``maps`` the study's
    maps this capacity has columns for.  A map of a grid larger than
    :data:`MAP_AXIS_VALUES` along an axis draws every k-th value, histograms of more than
    :data:`HISTOGRAM_ROWS` configurations a seeded sample: their titles, the log and the
    manifest say so.
    """
    suffix = capacity_class(capacity).output_suffix
    if maps or spec.file.output.histograms:  # matplotlib: a second of start-up
        from polyell.figures import plot_score_histogram, plot_score_map

    prefix, by = (f"{robot}.", f"{robot}: ") if robot else ("", "")
    if suffix:
        by = f"{by}{capacity}: "
    written: list[Path] = []
    grid = stream.map
    layout = _layout(spec, capacity)
    units = _grid_units(spec, robot, grid or stream.report_map)
    for name in maps:
        if grid is None:
            break
        kind, score = _split(name, stream.kinds)
        label, factor = score_display(score, capacity, layout.labels)
        ys, xs = grid.axes
        title = f"{by}{layout.set_label(kind, capacity)}: {label}"
        figure = plot_score_map(
            factor * grid.values(name),
            xs,
            ys,
            xlabel=f"${grid.x.name[0]}_{grid.x.name[1:]}$ [{units[0]}]",
            ylabel=f"${grid.y.name[0]}_{grid.y.name[1:]}$ [{units[1]}]",
            label=label,
            title=title + (f"\n({grid.shape_note()})" if grid.decimated else ""),
            limits=scales.get(score),
        )
        stem = folder / f"map_{prefix}{name}{suffix}"
        written += _save(spec, figure, stem)
    if grid is not None and grid.decimated and maps:
        notes.append(f"{by}maps map_{prefix}*{suffix}: {grid.note()}")
    measured = [kind for kind in stream.kinds if kind not in ("mvie", "outer")]  # not optima
    assert stream.sample is not None
    sample = stream.sample.frame() if spec.file.output.histograms else None
    sampled = ""
    if stream.sample.sampled and sample is not None:
        sampled = f"a seeded random sample of {len(sample):,} of {stream.count:,} configurations"
        notes.append(f"{by}histograms histogram_{prefix}*{suffix}: {sampled}")
    title = f"{by}{spec.title}"
    for score in spec.file.output.histograms:
        assert sample is not None
        figure = plot_score_histogram(
            sample,
            score,
            kinds=measured,
            title=title + (f"\n({sampled})" if sampled else ""),
            capacity=capacity,
            labels=layout.labels,
        )
        stem = folder / f"histogram_{prefix}{score}{suffix}"
        written += _save(spec, figure, stem)
    sections: list[tuple[str, Any]] = []
    if "html" in spec.file.output.formats:
        sections = _many_report(
            spec, by, stream, sample, sampled, summary, measured, capacity, maps, units
        )
    return written, sections


#: The names of a study's sweep datasets (folders), one per capacity.
_DATASETS = re.compile(r"results(?:_velocity|_force)?")


@dataclass
class _Previous:
    """What earlier runs into a folder left there: the outputs a new run replaces."""

    files: list[str]  # plain file names in the folder
    datasets: list[str]  # dataset folders, "results/"
    unfinished: str | None = None  # the study of an interrupted run, if the last was one
    spec: str | None = None  # the file name of the study that wrote them


def _previous_outputs(folder: Path) -> _Previous:
    """The files and datasets earlier runs into ``folder`` wrote (their manifest's), or none.

    Only names a study writes: plain file names matching :data:`STUDY_FILES` and the
    dataset folders ``results*/``.  A run writes its manifest first, marked incomplete
    (``"complete": false``), listing what the folder held then and the datasets it will
    write; if it was interrupted, every study file written since (newer than that
    manifest) is its too.
    """
    path = folder / "manifest.json"
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
        stamp = path.stat().st_mtime
    except (OSError, ValueError):
        return _Previous([], [])
    if not isinstance(manifest, dict):
        return _Previous([], [])
    files = manifest.get("files")
    datasets = manifest.get("datasets")
    names = [n for n in files if isinstance(n, str)] if isinstance(files, list) else []
    unfinished = None
    if manifest.get("complete") is False:  # an interrupted run: what it wrote since
        unfinished = str(manifest.get("study", ""))
        try:
            entries = list(os.scandir(folder))
        except OSError:
            entries = []
        for entry in entries:
            try:
                if entry.is_file() and entry.stat().st_mtime >= stamp:
                    names.append(entry.name)
            except OSError:
                continue
    found = sorted(
        {
            name
            for name in names
            if name == Path(name).name
            and name != "manifest.json"
            and STUDY_FILES.fullmatch(name) is not None
            and (folder / name).is_file()
        }
    )
    folders = (
        [n.rstrip("/") for n in datasets if isinstance(n, str)]
        if isinstance(datasets, list)
        else []
    )
    kept = sorted(
        {
            f"{name}/"
            for name in folders
            if _DATASETS.fullmatch(name) is not None and (folder / name).is_dir()
        }
    )
    spec = manifest.get("spec")
    return _Previous(found, kept, unfinished, spec if isinstance(spec, str) else None)


def _remove_dataset(path: Path) -> None:
    """Remove an earlier study's dataset folder (StorageError naming it if that fails)."""
    import shutil

    try:
        shutil.rmtree(path)
    except FileNotFoundError:
        return
    except OSError as exn:
        raise StorageError(
            f"Could not remove {path}, the dataset of an earlier study in this folder: "
            f"{exn.strerror or exn}. Fix: remove it by hand, or run the study into another "
            "folder."
        ) from exn


def _same_sweep_study(spec: StudySpec, previous: _Previous) -> bool:
    """Whether the earlier run was of this study file, and this study is a sweep too."""
    return spec.is_batch and spec.posture is None and previous.spec == spec.path.name


def _study_datasets(spec: StudySpec) -> list[str]:
    """The dataset folders a study writes (``results/``, ``results_force/``), or none."""
    if not spec.is_batch or spec.posture is not None:
        return []
    return [f"results{capacity_class(c).output_suffix}/" for c in spec.file.compare.capacities]


def _manifest_text(folder: Path) -> str | None:
    """The folder's manifest as it is (None: none, or unreadable)."""
    try:
        return (folder / "manifest.json").read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None


def _restore_if_untouched(folder: Path, text: str) -> None:
    """Put back the manifest ``text`` of the previous run if a refused run wrote nothing.

    A run refused before it wrote a file (the folder's dataset holds a different sweep)
    leaves the previous run's manifest as it was: marked incomplete, the next run would
    have taken that run's finished outputs for its own and removed them.
    """
    marker = folder / "manifest.json"
    try:
        stamp = marker.stat().st_mtime
        newer = [
            entry.name
            for entry in os.scandir(folder)
            if entry.is_file()
            and entry.name != "manifest.json"
            and STUDY_FILES.fullmatch(entry.name) is not None
            and entry.stat().st_mtime >= stamp
        ]
    except OSError:
        return
    if not newer:
        write_text_atomically(marker, text)


def _mark_incomplete(spec: StudySpec, folder: Path, previous: _Previous) -> None:
    """Write the manifest of a run that has not finished (replaced when it does).

    It lists the earlier runs' outputs still in the folder and the datasets this run
    writes, so that the next run into the folder removes all of them, and the files this
    run writes before it is interrupted (any study file newer than this manifest).
    """
    marker = {
        "study": spec.title,
        "spec": spec.path.name,
        "complete": False,
        "note": "this run did not finish (or is running): the files newer than this "
        "manifest are its, and the next study run into this folder removes them and the "
        "files and datasets listed here (a dataset of the same study is resumed instead)",
        "files": previous.files,
        "datasets": sorted({*previous.datasets, *_study_datasets(spec)}),
    }
    write_text_atomically(folder / "manifest.json", json.dumps(marker, indent=2) + "\n")


def _per_row_notes(spec: StudySpec, folder: Path) -> list[str]:
    """How many rows of each sweep dataset of a study left the batch (:func:`per_row_note`).

    One note per dataset of the study's capacities (``results<suffix>/``, a robot's
    ``robot=<name>/``), from its ``_sweep.json`` (the capacity) and its ``per_row`` column.
    """
    if not spec.is_batch or spec.posture is not None:
        return []
    notes = []
    datasets = [f"results{capacity_class(c).output_suffix}" for c in spec.file.compare.capacities]
    found = (meta for name in datasets for meta in (folder / name).glob("**/_sweep.json"))
    for meta in sorted(found):
        capacity = json.loads(meta.read_text(encoding="utf-8")).get("capacity", "acceleration")
        note = per_row_note(meta.parent, capacity)  # counted part by part
        robot = meta.parent.name.removeprefix("robot=")
        notes.append(f"{robot} {note}" if meta.parent.name.startswith("robot=") else note)
    return notes


def _sweep(
    spec: StudySpec,
    robot: Robot,
    configurations: Any,
    out: Path,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    capacity: str = "acceleration",
) -> Path:
    """A robot's sweep of a capacity: a Parquet dataset in ``out``, so that a killed study resumes.

    Its duration is added to ``seconds["sweep"]`` (the manifest's timings).  Velocities
    are bounded by the robot's joint velocity limits, the other capacities by its torques.
    """
    started = time.perf_counter()
    cls = capacity_class(capacity)
    limits = cls.limit_arguments(*cls._robot_limits(robot))
    dataset = sweep(
        robot.model,
        configurations,
        **limits,
        capacity=capacity,
        scores=_scores(spec),
        **_compared(spec),
        scheduler=scheduler,
        chunk=spec.file.compare.chunk,
        progress=progress,
        out=out,
        **_horizon(spec, capacity),
    )
    seconds["sweep"] = seconds.get("sweep", 0.0) + time.perf_counter() - started
    return Path(dataset)


def _write_summary(
    spec: StudySpec,
    folder: Path,
    summaries: dict[str, pd.DataFrame],
    count: int,
    capacity: str = "acceleration",
) -> list[Path]:
    """``summary.csv``, ``.md`` and ``.tex`` of a study over ``count`` configurations.

    Of the acceleration capacity; another's files carry its name (``summary_force.tex``),
    and its captions and headings say which capacity.

    ``summaries`` holds one summary per robot (the key ``""`` for a study of one): several
    give a ``robot`` column in the CSV and one table per robot in Markdown and LaTeX.
    """
    import pandas as pd

    suffix = capacity_class(capacity).output_suffix
    scores = "scores" if not suffix else f"{capacity} scores"
    tag = suffix.replace("_", "-")  # LaTeX labels: tab:summary-force
    layout = _layout(spec, capacity)
    options: dict[str, Any] = {"layout": layout, "capacity": capacity}
    what = "summary" if not suffix else f"{capacity} summary"
    markdown = _heading(spec, f"{spec.title}: {what} over {count} configurations")
    # The captions do not repeat the study's title (a paper's table has its own context);
    # the layout's own caption (captions["summary"]) replaces them.
    own = layout.caption("summary")
    if own is not None:  # the Markdown shows it under its heading, as a points study's does
        markdown += f"{markdown_line(own.plain, 'caption')}\n\n"
    if list(summaries) == [""]:
        summary = summaries[""]
        caption = (
            None if own is not None else f"Summary of the {scores} over {count} configurations."
        )
        latex = format_summary_table(
            summary, "latex", caption=caption, label=f"tab:summary{tag}", **options
        )
        markdown += format_summary_table(summary, "markdown", **options)
        csv = summary.to_csv()
    else:
        latex_tables, markdown_tables = [], []
        for robot, summary in summaries.items():
            named: Caption = f"Summary of the {scores} of {robot} over its configurations."
            if own is not None:  # the user's, with the robot's name: one caption per float
                text = own.latex if own.latex is not None else escape_latex(own.plain, "caption")
                named = (f"{own.plain} ({robot})", f"{text} ({escape_latex(robot, 'robot')})")
            latex_tables.append(
                format_summary_table(
                    summary, "latex", caption=named, label=f"tab:summary{tag}-{robot}", **options
                )
            )
            table = format_summary_table(summary, "markdown", **options)
            markdown_tables.append(f"## {escape_markdown(robot, 'robot')}\n\n{table}")
        latex = "\n".join(latex_tables)
        markdown += "\n".join(markdown_tables)
        csv = pd.concat(summaries, names=["robot"]).to_csv()
    return [
        write_text_atomically(folder / f"summary{suffix}.csv", csv),
        write_text_atomically(folder / f"summary{suffix}.md", markdown),
        write_text_atomically(folder / f"summary{suffix}.tex", latex),
    ]


def _run_trajectory(
    spec: StudySpec,
    folder: Path,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    notes: list[str],
) -> list[Path]:
    """A trajectory study, its memory independent of the number of samples but for one term.

    The sweep writes one Parquet part per chunk; the parts are then read one at a time:
    the tangent limits of a part's samples are computed and added to the part (rewritten:
    the dataset holds every column the study reports), its rows appended to
    ``results.csv`` (``[output] csv``) and passed to the series' decimators
    (:class:`SeriesDecimator`: the figures and the report draw at most a few thousand
    points per curve, and say so), to the summary's statistics (:class:`StreamedSummary`)
    and to the histograms' rows (:class:`_RowSample`).  The one term that grows with the
    samples is the trajectory itself (``(2n + 1) * 8`` bytes a sample).  Each capacity of
    ``[compare] capacities`` in turn.
    """
    return _each_capacity(
        _run_trajectory_capacity, spec, folder, progress, scheduler, seconds, notes
    )


def _run_trajectory_capacity(
    spec: StudySpec,
    folder: Path,
    capacity: str,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
    notes: list[str],
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity of a trajectory study: its sweep, tables, figures, report sections.

    The acceleration outputs keep their names; another capacity's carry its name
    (``results_force.csv``, ``series_coverage_velocity.png``).  Where the trajectory has
    velocities, what the capacity allows along the path's tangent is added to its results
    (``tangent_<set>_lo``, ``_hi``: the dataset's parts and the CSV) and drawn
    (``tangent_limits_force.png``).
    """
    from polyell.figures import plot_score_histogram, plot_score_series, plot_tangent_limits
    from polyell.interactive import SeriesDecimator

    suffix = capacity_class(capacity).output_suffix
    by = "" if not suffix else f"{capacity}: "
    trajectory = spec.trajectory
    assert trajectory is not None
    robot = spec.robot  # a trajectory study has one robot (checked when it loads)
    model = robot.model
    first = model.dynamics(trajectory.q[0])
    dataset = _sweep(
        spec, robot, trajectory, folder / f"results{suffix}", progress, scheduler, seconds, capacity
    )
    import pandas as pd
    import pyarrow.parquet as pq

    parts = _parts(Path(dataset))
    columns = pq.read_schema(parts[0]).names
    count = len(trajectory)
    kinds = result_kinds(columns, _study_kinds(spec, capacity))
    layout = _layout(spec, capacity)
    x = "t" if trajectory.t is not None else "configuration"
    tangent = trajectory.qd is not None
    cls = capacity_class(capacity)
    limits = cls.limit_arguments(*cls._robot_limits(robot)) if tangent else {}
    series = {
        score: SeriesDecimator(count, [f"{k}_{score}" for k in kinds if f"{k}_{score}" in columns])
        for score in spec.file.series
    }
    sets = ("polytope", *cls.ellipsoid_kinds)
    tangents = [f"tangent_{name}_{end}" for name in sets for end in ("lo", "hi")]
    along = SeriesDecimator(count, tangents) if tangent else None
    statistics = StreamedSummary(
        {
            (kind, score): f"{kind}_{score}"
            for kind in kinds  # the order of summarize(): ellipsoids, then scores
            for score in SUMMARY_SCORES
            if f"{kind}_{score}" in columns
        }
    )
    measured = [kind for kind in kinds if kind not in ("mvie", "outer")]  # not the optima
    sample = _RowSample(
        count,
        [
            f"{k}_{score}"
            for score in spec.file.output.histograms
            for k in measured
            if f"{k}_{score}" in columns
        ],
    )

    def read(handle: Any) -> None:
        start = 0
        for index, part in enumerate(parts):
            frame = pd.read_parquet(part)
            statistics.add(frame)
            sample.add(frame)
            stop = start + len(frame)
            along_path = {}
            if tangent:  # what the capacity allows along the path, where the arm moves
                assert trajectory.qd is not None
                piece = Trajectory(trajectory.q[start:stop], trajectory.qd[start:stop])
                along_path = tangent_limits(
                    model, piece, capacity=capacity, **limits, **_horizon(spec, capacity)
                )
            # The tangent limits are part of the dataset (its part rewritten with them), so
            # that the CSV streamed from the parts is the dataset, column for column.
            frame = _with_tangents(part, frame, along_path)
            if handle is not None:
                write_csv(frame, handle, header=index == 0)
            for decimator in series.values():
                decimator.add(frame[[x, *decimator.traces]])
            if along is not None:
                along.add(frame[[x, *tangents]])
            start = stop

    written: list[Path] = []
    if spec.file.output.writes_csv(count):
        csv = folder / f"results{suffix}.csv"
        written.append(write_atomically(csv, lambda name: _with_file(name, read)))
    else:
        read(None)
        why = (
            "[output] csv = false"
            if spec.file.output.csv is False
            else f'{count:,} samples, more than [output] csv = "auto" writes'
        )
        note = (
            f"results{suffix}.csv not written ({why}): every row is in the Parquet dataset "
            f"results{suffix}/ (pandas.read_parquet); csv = true writes it, streamed"
        )
        _log.info("note: %s", note)
        notes.append(note)
    summary = statistics.summary(parts)
    written += _write_summary(spec, folder, {"": summary}, count, capacity)
    shown = {score: decimator.result() for score, decimator in series.items()}
    for score, frame in shown.items():
        figure = plot_score_series(
            frame,
            score,
            kinds=kinds,
            title=f"{by}{spec.title}",
            capacity=capacity,
            labels=layout.labels,
        )
        stem = folder / f"series_{score}{suffix}"
        written += _save(spec, figure, stem)
    if along is not None:
        unit = task_unit(first.task, tex=True, capacity=capacity)
        figure = plot_tangent_limits(
            along.result(), unit=unit, capacity=capacity, labels=layout.labels
        )
        stem = folder / f"tangent_limits{suffix}"
        written += _save(spec, figure, stem)
    rows = sample.frame()
    sampled = ""
    if sample.sampled and spec.file.output.histograms:
        sampled = f"a seeded random sample of {len(rows):,} of {count:,} samples"
        notes.append(f"{by}histograms histogram_*{suffix}: {sampled}")
    title = f"{by}{spec.title}" + (f"\n({sampled})" if sampled else "")
    for score in spec.file.output.histograms:
        figure = plot_score_histogram(
            rows, score, kinds=measured, title=title, capacity=capacity, labels=layout.labels
        )
        stem = folder / f"histogram_{score}{suffix}"
        written += _save(spec, figure, stem)
    sections: list[tuple[str, Any]] = []
    if "html" in spec.file.output.formats:
        from polyell.interactive import HtmlTable, interactive_histogram, interactive_series

        for score, frame in shown.items():
            drawn = [kind for kind in kinds if f"{kind}_{score}" in frame]
            figure = interactive_series(
                frame, score, drawn, total=count, capacity=capacity, labels=layout
            )
            sections.append((by + score_display(score, capacity, layout.labels)[0], figure))
        for score in spec.file.output.histograms:
            figure = interactive_histogram(rows, score, measured, capacity=capacity, labels=layout)
            name = score_display(score, capacity, layout.labels)[0]
            sections.append((by + name + (f" ({sampled})" if sampled else ""), figure))
        text = format_summary_table(summary, "html", layout=layout, capacity=capacity)
        sections.append((f"{by}Summary over {count} configurations", HtmlTable(text)))
    return written, sections


def _with_tangents(
    part: Path, frame: pd.DataFrame, along_path: dict[str, NDArray[np.float64]]
) -> pd.DataFrame:
    """A trajectory part's rows with its tangent limits, the part rewritten to hold them.

    The columns ``tangent_<set>_lo``, ``_hi`` of ``along_path`` (none: a path without
    velocities) replace those the part holds (of an earlier run into the folder, whose
    dataset this one resumed): the part is written again, atomically, unless it already
    holds exactly these columns with the same values.  A run killed meanwhile leaves whole
    parts, each with or without its tangent columns; the next run rewrites them all.
    """
    held = [str(name) for name in frame.columns if str(name).startswith("tangent_")]
    if held == list(along_path) and all(
        np.array_equal(frame[name].to_numpy(dtype=float), values, equal_nan=True)
        for name, values in along_path.items()
    ):
        return frame
    rows = frame.drop(columns=held).assign(**along_path)
    write_atomically(part, lambda name: rows.to_parquet(name, index=False))
    return rows


def _many_report(
    spec: StudySpec,
    by: str,
    stream: _Stream,
    sample: pd.DataFrame | None,
    sampled: str,
    summary: pd.DataFrame,
    measured: list[str],
    capacity: str,
    maps: list[str],
    units: tuple[str, str],
) -> list[tuple[str, Any]]:
    """The report's sections of one robot's sweep of a capacity (``formats`` "html").

    ``by`` opens each section's title (the robot's name, the capacity, or ``""``); the
    heat maps show at most :data:`REPORT_MAP_AXIS_VALUES` values along each axis, the
    histograms the rows of :class:`_RowSample` (``sampled`` says which, if not all).
    """
    from polyell.interactive import HtmlTable, interactive_histogram, interactive_map

    sections: list[tuple[str, Any]] = []
    grid = stream.report_map
    layout = _layout(spec, capacity)
    if grid is not None and maps:  # one figure, a menu over the maps
        figure = interactive_map(
            grid.frame(), maps, grid.x.name, grid.y.name, capacity=capacity, labels=layout,
            units=units,
        )  # fmt: skip
        shown = f"; {grid.note()}" if grid.decimated else ""
        sections.append((f"{by}Heat maps (choose the score in the menu{shown})", figure))
    for score in spec.file.output.histograms:
        assert sample is not None
        figure = interactive_histogram(sample, score, measured, capacity=capacity, labels=layout)
        name = score_display(score, capacity, layout.labels)[0]
        sections.append((by + name + (f" ({sampled})" if sampled else ""), figure))
    text = format_summary_table(summary, "html", layout=layout, capacity=capacity)
    sections.append((f"{by}Summary over {stream.count} configurations", HtmlTable(text)))
    return sections


def _named_or_vectors(point: Point) -> list[Any]:
    """The point's directions for :func:`polyell.limits_table`: names where it has them."""
    return [
        label if not label.startswith("(") else vector
        for label, vector in zip(point.labels, point.directions, strict=True)
    ]


def _code_block(text: str) -> list[str]:
    """Markdown lines of ``text`` as a fenced code block (its labels shown, never rendered).

    The fence is longer than any run of backticks in ``text`` (a label of backticks
    cannot close it).
    """
    runs = [len(run) for run in re.findall(r"`+", text)]
    fence = "`" * max([3, *(n + 1 for n in runs)])
    return [f"{fence}text", text, fence]


def _along_directions(analysis: Analysis, point: Point, layout: TableLayout) -> str:
    """The numbers of a point: its sets once, then its limits along each direction.

    :func:`format_analysis` along the first direction, then the limits and inverse maps
    along each further one; the sets named as the study's tables name them
    (``layout.labels``), the paper's equation numbers only with its preset.
    """
    paper = layout.labels == PAPER_PRESET
    texts = [
        format_analysis(
            analysis,
            direction,
            "t" if label.startswith("(") else label,
            point.table.inverse_at,
            equations=paper,
            labels=layout.labels if layout.labels is not None else {},
        )
        for direction, label in zip(point.directions, point.labels, strict=True)
    ]
    marker = f"\nAchievable {analysis.quantity} along "
    return "\n".join([texts[0], *(text[text.index(marker) :] for text in texts[1:])])


def _grid_units(spec: StudySpec, robot: str, grid: Any) -> tuple[str, str]:
    """The units of a map's two joints (``"m"`` for a prismatic one), ``rad`` without one."""
    if grid is None:
        return ("rad", "rad")
    from polyell.studies.posture_tables import joint_units

    units = joint_units(_robot_of(spec, robot).model)
    x, y = (int(axis.name[1:]) - 1 for axis in (grid.x, grid.y))  # "q3": joint 3
    return (units[x], units[y])


def _robot_of(spec: StudySpec, name: str) -> Robot:
    """The robot a point (or sweep) of the study runs on (``""``: the study's only one)."""
    if not name:
        return spec.robot
    return next(robot for robot in spec.robots if robot.name == name)


def _save(spec: StudySpec, figure: Any, stem: Path) -> list[Path]:
    """A figure saved in the study's static formats (``[output] formats``) and ``dpi``."""
    from polyell.figures import save_figure

    output = spec.file.output
    return save_figure(figure, stem, output.figure_formats, output.dpi)


def _sentence(text: str) -> str:
    """``text`` with its first letter upper-case (a caption: ``"force: the ..."``)."""
    return text[:1].upper() + text[1:]


def _heading(spec: StudySpec, heading: str) -> str:
    """A Markdown file's title, with the study's description below it (if it has one)."""
    description = f"{markdown_text(spec.file.description)}\n\n" if spec.file.description else ""
    return f"# {escape_markdown(heading, 'title')}\n\n{description}"


def _about(spec: StudySpec) -> list[tuple[str, Any]]:
    """The first section of a report: the study's description (if it has one)."""
    return [("About this study", spec.file.description)] if spec.file.description else []


def _split(column: str, kinds: Sequence[str]) -> tuple[str, str]:
    """(kind, score) of a map's column among the study's ``kinds`` (validated at load)."""
    split = split_column(column, kinds)
    assert split is not None
    return split


def _study_kinds(spec: StudySpec, capacity: str) -> list[str]:
    """The ellipsoids a study scores in a capacity: its own, the MVIE, the outer, candidates.

    Given to :func:`~polyell.comparison.summary.result_kinds` and
    :func:`~polyell.comparison.summary.split_column`, so that no column name is split to
    guess its kind.
    """
    return [*compared_kinds(capacity), *(candidate.name for candidate in spec.candidates)]


def _compared(spec: StudySpec) -> dict[str, Any]:
    """What every comparison of the study takes: ``[compare]``'s options, the candidates.

    ``directions`` None is compare's default, by each configuration's rank.
    """
    keys = {"directions", "samples", "seed", "mvie", "outer"}
    return {**spec.file.compare.model_dump(include=keys), "candidates": spec.candidates}


def _scores(spec: StudySpec) -> tuple[str, ...]:
    """Every score the study's options allow (the ratios need their optimum computed)."""
    skipped = {"mvie_ratio": not spec.file.compare.mvie, "outer_ratio": not spec.file.compare.outer}
    return tuple(name for name in SCORE_NAMES if not skipped.get(name, False))


def run_study(
    spec: StudySpec, out: str | Path, *, progress: bool = False, scheduler: str | None = None
) -> list[Path]:
    """Run a study and write its tables and figures to ``out``.

    Parameters
    ----------
    spec : StudySpec
        From :func:`~polyell.studies.load_study`.
    out : str or Path
        Output folder (created if needed).
    progress : bool, optional
        Show progress bars on standard error (grid, random, trajectory and posture
        studies: the configurations, postures or targets scored).
    scheduler : None, "processes" or str, optional
        Where grid and random studies run, as in :func:`polyell.sweep`.

    Returns
    -------
    list of Path
        The files written, also listed in ``out/manifest.json``.

    Raises
    ------
    InputError
        If ``out`` cannot be written, another study is running into it, or ``scheduler``
        is malformed.
    StorageError
        If a file cannot be written (a full disk); finished parts of a sweep are kept.

    Notes
    -----
    The study holds a lock on ``out`` while it runs (``.polyell-study.lock``), and first
    removes the temporary files a killed run left of its outputs.  The study's
    ``description`` is written under the title of ``numbers.md``, ``comparison.md`` and
    ``summary.md``, at the top of ``report.html`` and into ``manifest.json``.  The manifest
    also records the study's wall-clock ``seconds``: ``total`` (this call, without the
    interpreter's start-up and imports) and, for many configurations, ``sweep`` (the
    scores, dynamics included), and ``per_row``: each dataset's rows computed one
    configuration at a time.  A run into a folder of an earlier run replaces its outputs as
    a whole: the files its manifest lists that this run does not write are removed, and so
    are its sweep datasets (``results*/``) unless this study writes the same ones (a killed
    sweep resumes; another study's sweep there is refused by :func:`polyell.sweep`), all
    listed under ``removed``; a dataset of a capacity an edited sweep study (the same
    file name) no longer compares is kept instead, to resume, and listed under
    ``datasets`` and ``notes``.  A run first writes its manifest marked incomplete
    (``"complete": false``); if it is interrupted, the next run into the folder also
    removes every study file written since, so that the folder never mixes two runs.

    A grid, random or trajectory study's memory does not grow with its configurations: its
    sweep writes one Parquet part per chunk (``results/``), read back one part at a time
    for ``results.csv`` (``[output] csv``: by default only up to
    :data:`~polyell.studies.models.CSV_AUTO_ROWS` configurations), the summary tables
    (over every configuration: :class:`StreamedSummary`), the heat maps (every k-th grid
    value beyond :data:`MAP_AXIS_VALUES` per axis) and the histograms (a seeded sample of
    about :data:`HISTOGRAM_ROWS` configurations beyond that many).  What was left out or
    sampled is listed under ``notes`` in the manifest (and logged).
    """
    if not isinstance(spec, StudySpec):
        raise InputError(
            "spec", "a StudySpec", type(spec).__name__, "load it with pe.studies.load_study(path)."
        )
    scheduler = check_scheduler(scheduler)
    if scheduler is not None and not spec.is_batch:
        raise InputError(
            "scheduler",
            "no scheduler for a study of points (they run in this process)",
            repr(scheduler),
            "drop --scheduler, or make it a [grid] or [random] study.",
        )
    started = time.perf_counter()
    folder = _prepare(out)
    seconds: dict[str, float] = {}
    notes: list[str] = []
    with folder_lock(folder, STUDY_LOCK, "study"):
        remove_stale_temporaries(folder, STUDY_FILES)  # what a killed run left
        previous = _previous_outputs(folder)
        if previous.unfinished is not None and previous.spec != spec.path.name:
            _log.info(
                "note: the previous run into %s (study %r) did not finish; this run "
                "replaces its outputs",
                folder,
                previous.unfinished,
            )
        before = _manifest_text(folder)
        _mark_incomplete(spec, folder, previous)
        try:
            with warnings.catch_warnings(record=True) as caught:
                if spec.posture is not None:
                    written = _run_posture(spec, folder, progress)
                elif spec.is_batch:
                    written = _run_many(spec, folder, progress, scheduler, seconds, notes)
                else:
                    written = _run_points(spec, folder, notes)
        except BaseException as exn:  # a failed or interrupted run: its warnings all the same
            if isinstance(exn, PolyellError) and before is not None:
                _restore_if_untouched(folder, before)  # a refused run changes nothing
            _warn_again(_unique_warnings(caught))
            raise
        raised = _unique_warnings(caught)
        seconds["total"] = time.perf_counter() - started
        manifest: dict[str, Any] = {
            "study": spec.title,
            "description": spec.file.description,
            "spec": spec.path.name,
            "files": sorted(p.name for p in written),
            "datasets": dataset_folders(spec, folder),
            "seconds": {name: round(value, 3) for name, value in seconds.items()},
            "per_row": _per_row_notes(spec, folder),
        }
        if notes:  # results.csv left out, figures of a sample or a sub-grid
            manifest["notes"] = notes
        if raised:  # each once: joint positions out of their limits, a table too wide
            manifest["warnings"] = [f"{w.category.__name__}: {w.message}" for w in raised]
        stale = sorted(set(previous.files) - {p.name for p in written} - {"manifest.json"})
        for name in stale:  # the previous run's outputs this run does not write
            (folder / name).unlink(missing_ok=True)
        # the previous runs' datasets this study does not use: another study's are removed,
        # an earlier run's of this study file (a capacity dropped) kept, to resume, and said
        unused = sorted(set(previous.datasets) - set(_study_datasets(spec)))
        if unused and _same_sweep_study(spec, previous):
            manifest["datasets"] = sorted({*manifest["datasets"], *unused})
            note = (
                f"kept {', '.join(unused)}: the sweep of an earlier run of {spec.path.name} "
                "that this run does not use (it resumes when the study compares that "
                "capacity again; remove it by hand if not)"
            )
            manifest.setdefault("notes", []).append(note)
            _log.info("note: %s", note)
        else:
            for name in unused:
                _remove_dataset(folder / name.rstrip("/"))
                stale.append(name)
        if stale:
            manifest["removed"] = stale
            _log.info("note: removed %d outputs of the previous run: %s", len(stale), stale)
        written.append(
            write_text_atomically(folder / "manifest.json", json.dumps(manifest, indent=2) + "\n")
        )
    _warn_again(raised)  # to the caller, once each (the manifest keeps them)
    return written


def _warn_again(caught: Sequence[warnings.WarningMessage]) -> None:
    """Raise recorded warnings again, under the caller's filters."""
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)


def _unique_warnings(
    caught: Sequence[warnings.WarningMessage],
) -> list[warnings.WarningMessage]:
    """The warnings of a run, each (category and text) once, in the order first raised.

    The same warning raised at two places (a point's joint positions checked when the
    study loads its robot and when it analyses them) is one warning to its reader.
    """
    seen: dict[tuple[type[Warning], str], warnings.WarningMessage] = {}
    for w in caught:
        seen.setdefault((w.category, str(w.message)), w)
    return list(seen.values())


def dataset_folders(spec: StudySpec, folder: Path) -> list[str]:
    """The study's resumable Parquet datasets in ``folder``: ``results/``, ``results_force/``.

    A grid, random or trajectory study keeps each capacity's sweep there (one part per
    chunk; a run killed midway resumes from them); ``pd.read_parquet`` reads one whole.
    """
    if not spec.is_batch or spec.posture is not None:
        return []
    names = [f"results{capacity_class(c).output_suffix}" for c in spec.file.compare.capacities]
    return [f"{name}/" for name in names if (folder / name).is_dir()]
