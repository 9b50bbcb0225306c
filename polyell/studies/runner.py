"""Run a study: every configuration analysed and compared, tables and figures written."""

from __future__ import annotations

import json
import logging
import os
import re
import time
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from polyell.capacities import analyze, capacity_class
from polyell.comparison.comparison import SCORE_NAMES, Comparison, compare, compared_kinds
from polyell.comparison.latex_text import markdown_text
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
    ellipsoid_label,
    format_comparison_table,
    format_limits_table,
    score_display,
)
from polyell.errors import InputError
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
from polyell.studies.sweep import PER_ROW, per_row_note, sweep
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
#: The lock a running study holds on its folder (hidden: not one of its outputs).
STUDY_LOCK = ".polyell-study.lock"
#: Notes on standard error (``polyell study`` shows INFO).
_log = logging.getLogger("polyell")


def _prepare(out: str | os.PathLike[str]) -> Path:
    if not isinstance(out, str | os.PathLike) or not str(out):
        raise InputError("out", "a folder path (str or pathlib.Path)", repr(out)[:120])
    folder = Path(out)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / ".polyell-write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as exn:
        raise InputError(
            "out", "a folder polyell can write to", f"{folder} ({exn.strerror})"
        ) from None
    return folder


def _layout(spec: StudySpec, capacity: str) -> TableLayout:
    """The tables' layout of a capacity: ``[output] sets`` kept to this capacity's sets.

    A set of another compared capacity (``static`` beside accelerations) is left out of
    this capacity's tables; that every set exists in some capacity is checked at load.
    """
    layout = spec.file.output.layout
    if layout.sets is None:
        return layout
    own = {"polytope", *compared_kinds(capacity), *(c.name for c in spec.candidates)}
    kept = tuple(name for name in layout.sets if name in own)
    return replace(layout, sets=kept or ("polytope",))


def _run_points(spec: StudySpec, folder: Path) -> list[Path]:
    """Every capacity of the study at every point: tables, figures, numbers, report."""
    written: list[Path] = []
    numbers = [_heading(spec, f"{spec.title}: the numbers").rstrip("\n"), ""]
    report: list[tuple[str, Any]] = _about(spec)
    for capacity in spec.file.compare.capacities:
        # The acceleration outputs keep their names; another capacity's carry its name.
        suffix = capacity_class(capacity).output_suffix
        if len(spec.file.compare.capacities) > 1:
            numbers += [f"# {capacity.capitalize()} capacity", ""]
        written += _run_points_capacity(spec, folder, capacity, suffix, numbers, report)
    written.append(write_text_atomically(folder / "numbers.md", "\n".join(numbers)))
    if "html" in spec.file.output.formats:
        from polyell.interactive import write_report

        written.append(write_report(folder / "report.html", spec.title, report))
    return written


def _analyze_point(spec: StudySpec, point: Point, capacity: str) -> Analysis:
    """A point's analysis; in motion (``qd``, a URDF robot) with the torque limits at qd."""
    robot = _robot_of(spec, point.robot)
    cls = capacity_class(capacity)
    limits = cls.limit_arguments(*cls.robot_limits(robot, point.qd))
    if point.qd is None:
        dynamics = robot.model.dynamics(point.q)
    else:  # (no points in motion in a study of velocities: checked at load)
        assert isinstance(robot.model, UrdfRobot)  # checked at load
        dynamics = robot.model.dynamics(point.q, point.qd)
    return analyze(dynamics, capacity=capacity, **limits)


def _run_points_capacity(
    spec: StudySpec,
    folder: Path,
    capacity: str,
    suffix: str,
    numbers: list[str],
    report: list[tuple[str, Any]],
) -> list[Path]:
    from polyell.figures import plot_directional_limits, plot_sets, plot_sets_3d

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
            markdown_text(
                f"## {point.label}{': ' + point.table.title if point.table.title else ''}"
            ),
            "",
            f"q = ({q_text}) rad",
            "",
            *motion,
            "```text",
            _along_directions(analysis, point),
            "```",
            "",
            "Scores (`pe.compare`):",
            "",
            cmp.to_markdown(),
        ]
        frame = cmp.to_frame()
        frame.index = [f"{point.label}: {ellipsoid_label(k, capacity)}" for k in frame.index]
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
                report.append((heading, interactive_sets(cmp)))
            limits = limits_table(cmp, directions[point.label])
            for name, text in (
                ("scores", format_comparison_table(cmp, "html", layout=layout)),
                ("directional limits", format_limits_table(limits, "html", layout=layout)),
            ):
                report.append((f"{heading}: {name}", HtmlTable(text)))
        P = analysis.polytope
        if not getattr(P, "is_bounded", True) or getattr(P, "is_empty", False):
            continue  # an unbounded or empty force polytope has no figure (said in numbers.md)
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
        if analysis.m == 2:
            figure = plot_sets(analysis, kinds=kinds, mvie=mvie, extra=extra, title=title)
            written += _save(spec, figure, stem)
            if P.dim == 2:
                figure = plot_directional_limits(analysis, kinds=kinds, mvie=mvie, extra=extra)
                written += _save(spec, figure, folder / f"limits_{point.stem}{suffix}")
        elif analysis.m == 3:
            figure = plot_sets_3d(analysis, kinds=kinds, mvie=mvie, extra=extra, title=title)
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


def _run_posture(spec: StudySpec, folder: Path) -> list[Path]:
    """A posture study: the self-motion through q0, the choice of each index, the figure.

    The postures are sampled once; for each capacity of ``[compare] capacities`` writes
    ``posture_choice.{tex,md,csv}`` (:func:`polyell.write_posture_tables`),
    ``posture_values.csv`` (one row per posture: its joint angles, its position along the
    manifold and every set's values), ``posture_indices.<format>`` and, with ``targets``,
    ``posture_targets.{tex,md,csv}`` (the choice aggregated over random targets); the
    names of a capacity other than accelerations end in ``_<capacity>``.
    """
    from polyell.models.self_motion import self_motion

    posture = spec.posture
    assert posture is not None
    robot = spec.robots[0]  # a posture study has one robot (checked when it loads)
    motions = [
        self_motion(robot.model, q, posture.table.count, seed=posture.table.seed)
        for q in posture.starts
    ]

    def one(spec: StudySpec, folder: Path, capacity: str, *_: Any) -> Any:
        return _posture_outputs(spec, folder, capacity, motions)

    return _each_capacity(one, spec, folder, False, None, {})


def _posture_outputs(
    spec: StudySpec, folder: Path, capacity: str, motions: list[Any]
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity's choice over the sampled postures: tables, values, figure, sections."""
    from polyell.figures import plot_posture_indices
    from polyell.studies.posture import posture_choice
    from polyell.studies.posture_tables import write_posture_tables
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
    limits = cls.limit_arguments(*cls.robot_limits(robot))
    choice = posture_choice(robot.model, configurations, **limits, **options)
    along = f"along {posture.label}"
    written = list(
        write_posture_tables(
            choice.table,
            folder,
            f"{spec.title}: {named}the posture each index picks ({along}, "
            f"{len(configurations)} postures)",
            label=f"tab:posture-choice{suffix.replace('_', '-')}",
            stem=f"posture_choice{suffix}",
            layout=_layout(spec, capacity),
        ).values()
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
    figure = plot_posture_indices(
        choice.values,
        choice.table,
        position=motions[0].position if traced else None,
        title=f"{spec.title} ({named}{along})",
    )
    stem = folder / f"posture_indices{suffix}"
    written += _save(spec, figure, stem)
    sections: list[tuple[str, Any]] = [
        (f"{named}The posture each index picks ({along}; regret as a fraction)", choice.table)
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
        )
        title = f"{spec.title}: {named}regret over {len(over.targets)} random targets ({along})"
        written += write_posture_tables(
            over.summary,
            folder,
            title,
            label=f"tab:posture-targets{suffix.replace('_', '-')}",
            stem=f"posture_targets{suffix}",
            layout=_layout(spec, capacity),
        ).values()
        sections.append((f"{named}Over {posture.table.targets} random targets", over.summary))
    return written, sections


def _run_many(
    spec: StudySpec, folder: Path, progress: bool, scheduler: str | None, seconds: dict[str, float]
) -> list[Path]:
    """A grid or random study: one sweep per robot, tables and figures side by side.

    A study of ``[[robots]]`` keeps each robot's dataset in ``results/robot=<name>/`` (a
    Hive partition: ``pd.read_parquet(out / "results")`` reads a ``robot`` column), and
    writes a ``robot`` column into ``results.csv`` and ``summary.csv``; its figures are
    named ``map_<robot>.<name>``, ``histogram_<robot>.<score>``.
    """
    if spec.trajectory is not None:
        return _run_trajectory(spec, folder, progress, scheduler, seconds)
    return _each_capacity(_run_many_capacity, spec, folder, progress, scheduler, seconds)


def _each_capacity(
    run_one: Any,
    spec: StudySpec,
    folder: Path,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
) -> list[Path]:
    """``run_one`` for each capacity of ``[compare] capacities``, then the HTML report."""
    written: list[Path] = []
    sections = _about(spec)
    for capacity in spec.file.compare.capacities:
        files, capacity_sections = run_one(spec, folder, capacity, progress, scheduler, seconds)
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
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity of a grid or random study: its sweep, tables, figures, report sections.

    The acceleration outputs keep their names (``results/``, ``summary.tex``,
    ``map_<name>.png``); another capacity's carry its name (``results_force/``,
    ``summary_force.tex``, ``map_<name>_force.png``).
    """
    import pandas as pd

    suffix = capacity_class(capacity).output_suffix
    runs: dict[str, pd.DataFrame] = {}
    for index, robot in enumerate(spec.robots):
        configurations = spec.configurations(index)
        results_folder = folder / f"results{suffix}"
        out = results_folder / f"robot={robot.name}" if spec.by_robot else results_folder
        dataset = _sweep(spec, robot, configurations, out, progress, scheduler, seconds, capacity)
        results = pd.read_parquet(dataset).sort_values("configuration").reset_index(drop=True)
        runs[robot.name if spec.by_robot else ""] = results
    if spec.by_robot:
        table = pd.concat([r.assign(robot=name) for name, r in runs.items()], ignore_index=True)
        table = table[["robot", *[c for c in table.columns if c != "robot"]]]
    else:
        table = runs[""]
    results_csv = folder / f"results{suffix}.csv"
    written = [write_atomically(results_csv, lambda name: _csv(name, table))]
    summaries = {name: summarize(results) for name, results in runs.items()}
    written += _write_summary(spec, folder, summaries, len(table), capacity)
    # Maps of one score share one colour scale, so that colours compare across candidates
    # (and robots).  A map of a kind this capacity does not have is not drawn for it.
    maps = [name for name in spec.file.output.maps if name in table.columns]
    scales: dict[str, tuple[float, float]] = {}
    for name in maps:
        _, score = _split(name)
        finite = table[name].to_numpy(dtype=float)
        finite = finite[np.isfinite(finite)] * score_display(score, capacity)[1]
        if finite.size:
            low, high = scales.get(score, (np.inf, -np.inf))
            scales[score] = (min(low, finite.min()), max(high, finite.max()))
    sections: list[tuple[str, Any]] = []
    for name, results in runs.items():
        files, robot_sections = _many_outputs(
            spec, folder, name, results, summaries[name], scales, capacity, maps
        )
        written += files
        sections += robot_sections
    return written, sections


def _many_outputs(
    spec: StudySpec,
    folder: Path,
    robot: str,
    results: pd.DataFrame,
    summary: pd.DataFrame,
    scales: dict[str, tuple[float, float]],
    capacity: str,
    maps: list[str],
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """The figures of one robot's sweep of a capacity, and its sections of the report.

    ``robot`` is its name in a study of several robots, else ``""``; ``maps`` the study's
    maps this capacity has columns for.
    """
    suffix = capacity_class(capacity).output_suffix
    if maps or spec.file.series or spec.file.output.histograms:  # matplotlib: a second of start-up
        from polyell.figures import plot_score_histogram, plot_score_map, plot_score_series

    prefix, by = (f"{robot}.", f"{robot}: ") if robot else ("", "")
    if suffix:
        by = f"{by}{capacity}: "
    written: list[Path] = []
    kinds = result_kinds(results.columns)
    varying = [axis for axis in spec.grid if axis.values.size > 1]
    for name in maps:
        if len(varying) != 2:
            break
        x_axis, y_axis = varying[1], varying[0]  # the last joint varies fastest: columns
        kind, score = _split(name)
        label, factor = score_display(score, capacity)
        values = factor * results[name].to_numpy().reshape(y_axis.values.size, x_axis.values.size)
        figure = plot_score_map(
            values,
            x_axis.values,
            y_axis.values,
            xlabel=f"${x_axis.name[0]}_{x_axis.name[1:]}$ [rad]",
            ylabel=f"${y_axis.name[0]}_{y_axis.name[1:]}$ [rad]",
            label=label,
            title=f"{by}{ellipsoid_label(kind, capacity)}: {label}",
            limits=scales.get(score),
        )
        stem = folder / f"map_{prefix}{name}{suffix}"
        written += _save(spec, figure, stem)
    title = f"{by}{spec.title}"
    for score in spec.file.series:
        figure = plot_score_series(results, score, kinds=kinds, title=title, capacity=capacity)
        stem = folder / f"series_{prefix}{score}{suffix}"
        written += _save(spec, figure, stem)
    measured = [kind for kind in kinds if kind not in ("mvie", "outer")]  # not the optima
    for score in spec.file.output.histograms:
        figure = plot_score_histogram(
            results, score, kinds=measured, title=title, capacity=capacity
        )
        stem = folder / f"histogram_{prefix}{score}{suffix}"
        written += _save(spec, figure, stem)
    sections: list[tuple[str, Any]] = []
    if "html" in spec.file.output.formats:
        sections = _many_report(spec, by, results, summary, varying, measured, capacity, maps)
    return written, sections


def _previous_outputs(folder: Path) -> list[str]:
    """The files a previous run into ``folder`` wrote (its manifest's), or none.

    Only plain file names in the folder: the outputs of a study, never a dataset (a sweep's
    ``results*/`` stays, to resume).
    """
    try:
        files = json.loads((folder / "manifest.json").read_text(encoding="utf-8"))["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return []
    if not isinstance(files, list):
        return []
    return [
        name
        for name in files
        if isinstance(name, str)
        and name == Path(name).name
        and STUDY_FILES.fullmatch(name) is not None
        and (folder / name).is_file()
    ]


def _per_row_notes(spec: StudySpec, folder: Path) -> list[str]:
    """How many rows of each sweep dataset of a study left the batch (:func:`per_row_note`).

    One note per dataset of the study's capacities (``results<suffix>/``, a robot's
    ``robot=<name>/``), from its ``_sweep.json`` (the capacity) and its ``per_row`` column.
    """
    import pandas as pd

    if not spec.is_batch or spec.posture is not None:
        return []
    notes = []
    datasets = [f"results{capacity_class(c).output_suffix}" for c in spec.file.compare.capacities]
    found = (meta for name in datasets for meta in (folder / name).glob("**/_sweep.json"))
    for meta in sorted(found):
        capacity = json.loads(meta.read_text(encoding="utf-8")).get("capacity", "acceleration")
        note = per_row_note(pd.read_parquet(meta.parent, columns=[PER_ROW]), capacity)
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
    limits = cls.limit_arguments(*cls.robot_limits(robot))
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
    options: dict[str, Any] = {"layout": _layout(spec, capacity), "capacity": capacity}
    what = "summary" if not suffix else f"{capacity} summary"
    markdown = _heading(spec, f"{spec.title}: {what} over {count} configurations")
    if list(summaries) == [""]:
        summary = summaries[""]
        caption = f"{spec.title}: {scores} over {count} configurations."
        latex = format_summary_table(
            summary, "latex", caption=caption, label=f"tab:summary{tag}", **options
        )
        markdown += format_summary_table(summary, "markdown", **options)
        csv = summary.to_csv()
    else:
        latex_tables, markdown_tables = [], []
        for robot, summary in summaries.items():
            caption = f"{spec.title}: {scores} of {robot} over its configurations."
            latex_tables.append(
                format_summary_table(
                    summary, "latex", caption=caption, label=f"tab:summary{tag}-{robot}", **options
                )
            )
            table = format_summary_table(summary, "markdown", **options)
            markdown_tables.append(f"## {robot}\n\n{table}")
        latex = "\n".join(latex_tables)
        markdown += "\n".join(markdown_tables)
        csv = pd.concat(summaries, names=["robot"]).to_csv()
    return [
        write_text_atomically(folder / f"summary{suffix}.csv", csv),
        write_text_atomically(folder / f"summary{suffix}.md", markdown),
        write_text_atomically(folder / f"summary{suffix}.tex", latex),
    ]


def _run_trajectory(
    spec: StudySpec, folder: Path, progress: bool, scheduler: str | None, seconds: dict[str, float]
) -> list[Path]:
    """A trajectory study, its memory independent of the number of samples but for two terms.

    The sweep writes one Parquet part per chunk; the parts are then read one at a time:
    the tangent limits of a part's samples are computed, its rows appended to
    ``results.csv`` and passed to the series' decimators (:class:`SeriesDecimator`: the
    figures and the report draw at most a few thousand points per curve, and say so).
    The two terms that grow with the samples are the trajectory itself (``(2n + 1) * 8``
    bytes a sample) and one score column at a time (8 bytes a sample) for the summary's
    medians and the histograms.  Each capacity of ``[compare] capacities`` in turn.
    """
    return _each_capacity(_run_trajectory_capacity, spec, folder, progress, scheduler, seconds)


def _run_trajectory_capacity(
    spec: StudySpec,
    folder: Path,
    capacity: str,
    progress: bool,
    scheduler: str | None,
    seconds: dict[str, float],
) -> tuple[list[Path], list[tuple[str, Any]]]:
    """One capacity of a trajectory study: its sweep, tables, figures, report sections.

    The acceleration outputs keep their names; another capacity's carry its name
    (``results_force.csv``, ``series_coverage_velocity.png``).  Where the trajectory has
    velocities, what the capacity allows along the path's tangent is added to its results
    (``tangent_<set>_lo``, ``_hi``) and drawn (``tangent_limits_force.png``).
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

    parts = [path for _, path in sorted(existing_parts(Path(dataset)).items())]
    columns = pq.read_schema(parts[0]).names
    count = len(trajectory)
    kinds = result_kinds(columns)
    x = "t" if trajectory.t is not None else "configuration"
    tangent = trajectory.qd is not None
    cls = capacity_class(capacity)
    limits = cls.limit_arguments(*cls.robot_limits(robot)) if tangent else {}
    series = {
        score: SeriesDecimator(count, [f"{k}_{score}" for k in kinds if f"{k}_{score}" in columns])
        for score in spec.file.series
    }
    sets = ("polytope", *cls.ellipsoid_kinds)
    tangents = [f"tangent_{name}_{end}" for name in sets for end in ("lo", "hi")]
    along = SeriesDecimator(count, tangents) if tangent else None

    def write_results(name: str) -> None:
        with open(name, "wb") as handle:
            start = 0
            for index, part in enumerate(parts):
                frame = pd.read_parquet(part)
                stop = start + len(frame)
                if tangent:  # what the capacity allows along the path, where the arm moves
                    assert trajectory.qd is not None
                    piece = Trajectory(trajectory.q[start:stop], trajectory.qd[start:stop])
                    along_path = tangent_limits(model, piece, capacity=capacity, **limits)
                    frame = frame.assign(**along_path)
                write_csv(frame, handle, header=index == 0)
                for decimator in series.values():
                    decimator.add(frame[[x, *decimator.traces]])
                if along is not None:
                    along.add(frame[[x, *tangents]])
                start = stop

    written = [write_atomically(folder / f"results{suffix}.csv", write_results)]
    summaries = []
    for kind in kinds:  # the order of summarize(): ellipsoids, then scores
        for score in SUMMARY_SCORES:
            column = f"{kind}_{score}"
            if column in columns:
                values = pd.read_parquet(dataset, columns=[column])
                summaries.append(summarize(values, (score,)))
    summary = pd.concat(summaries) if summaries else summarize(pd.DataFrame())
    written += _write_summary(spec, folder, {"": summary}, count, capacity)
    shown = {score: decimator.result() for score, decimator in series.items()}
    for score, frame in shown.items():
        figure = plot_score_series(
            frame, score, kinds=kinds, title=f"{by}{spec.title}", capacity=capacity
        )
        stem = folder / f"series_{score}{suffix}"
        written += _save(spec, figure, stem)
    if along is not None:
        unit = task_unit(first.task, tex=True, capacity=capacity)
        figure = plot_tangent_limits(along.result(), unit=unit, capacity=capacity)
        stem = folder / f"tangent_limits{suffix}"
        written += _save(spec, figure, stem)
    measured = [kind for kind in kinds if kind not in ("mvie", "outer")]  # not the optima
    histograms = {
        score: pd.read_parquet(
            dataset, columns=[f"{k}_{score}" for k in measured if f"{k}_{score}" in columns]
        )
        for score in spec.file.output.histograms
    }
    for score, frame in histograms.items():
        figure = plot_score_histogram(
            frame, score, kinds=measured, title=f"{by}{spec.title}", capacity=capacity
        )
        stem = folder / f"histogram_{score}{suffix}"
        written += _save(spec, figure, stem)
    sections: list[tuple[str, Any]] = []
    if "html" in spec.file.output.formats:
        from polyell.interactive import interactive_histogram, interactive_series

        for score, frame in shown.items():
            figure = interactive_series(frame, score, total=count, capacity=capacity)
            sections.append((by + score_display(score, capacity)[0], figure))
        for score, frame in histograms.items():
            figure = interactive_histogram(frame, score, measured, capacity=capacity)
            sections.append((by + score_display(score, capacity)[0], figure))
        sections.append((f"{by}Summary over {count} configurations (fractions)", summary))
    return written, sections


def _many_report(
    spec: StudySpec,
    by: str,
    results: pd.DataFrame,
    summary: pd.DataFrame,
    varying: list[GridAxis],
    measured: list[str],
    capacity: str,
    maps: list[str],
) -> list[tuple[str, Any]]:
    """The report's sections of one robot's sweep of a capacity (``formats`` "html").

    ``by`` opens each section's title (the robot's name, the capacity, or ``""``).
    """
    from polyell.interactive import (
        HtmlTable,
        interactive_histogram,
        interactive_map,
        interactive_series,
    )

    sections: list[tuple[str, Any]] = []
    if len(varying) == 2 and maps:  # one figure, a menu over the maps
        figure = interactive_map(results, maps, varying[1].name, varying[0].name, capacity=capacity)
        sections.append((f"{by}Heat maps (choose the score in the menu)", figure))
    for score in spec.file.series:
        figure = interactive_series(results, score, capacity=capacity)
        sections.append((by + score_display(score, capacity)[0], figure))
    for score in spec.file.output.histograms:
        figure = interactive_histogram(results, score, measured, capacity=capacity)
        sections.append((by + score_display(score, capacity)[0], figure))
    layout = _layout(spec, capacity)
    text = format_summary_table(summary, "html", layout=layout, capacity=capacity)
    sections.append((f"{by}Summary over {len(results)} configurations", HtmlTable(text)))
    return sections


def _named_or_vectors(point: Point) -> list[Any]:
    """The point's directions for :func:`polyell.limits_table`: names where it has them."""
    return [
        label if not label.startswith("(") else vector
        for label, vector in zip(point.labels, point.directions, strict=True)
    ]


def _along_directions(analysis: Analysis, point: Point) -> str:
    """The numbers of a point: its sets once, then its limits along each direction.

    :func:`format_analysis` along the first direction, then the limits and inverse maps
    along each further one.
    """
    texts = [
        format_analysis(
            analysis, direction, "t" if label.startswith("(") else label, point.table.inverse_at
        )
        for direction, label in zip(point.directions, point.labels, strict=True)
    ]
    marker = f"\nAchievable {analysis.quantity} along "
    return "\n".join([texts[0], *(text[text.index(marker) :] for text in texts[1:])])


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


def _csv(name: str, frame: pd.DataFrame) -> None:
    with open(name, "wb") as handle:
        write_csv(frame, handle)


def _heading(spec: StudySpec, heading: str) -> str:
    """A Markdown file's title, with the study's description below it (if it has one)."""
    description = f"{markdown_text(spec.file.description)}\n\n" if spec.file.description else ""
    return f"# {markdown_text(heading)}\n\n{description}"


def _about(spec: StudySpec) -> list[tuple[str, Any]]:
    """The first section of a report: the study's description (if it has one)."""
    return [("About this study", spec.file.description)] if spec.file.description else []


def _split(column: str) -> tuple[str, str]:
    """(kind, score) of a map's column (validated when the study was loaded)."""
    split = split_column(column)
    assert split is not None
    return split


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
        Show a progress bar on standard error (grid and random studies).
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
    a whole: the files its manifest lists that this run does not write are removed (listed
    under ``removed``); the sweep datasets stay, to resume.
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
    with folder_lock(folder, STUDY_LOCK, "study"):
        remove_stale_temporaries(folder, STUDY_FILES)  # what a killed run left
        previous = _previous_outputs(folder)
        if spec.posture is not None:
            written = _run_posture(spec, folder)
        elif spec.is_batch:
            written = _run_many(spec, folder, progress, scheduler, seconds)
        else:
            written = _run_points(spec, folder)
        seconds["total"] = time.perf_counter() - started
        manifest = {
            "study": spec.title,
            "description": spec.file.description,
            "spec": spec.path.name,
            "files": sorted(p.name for p in written),
            "seconds": {name: round(value, 3) for name, value in seconds.items()},
            "per_row": _per_row_notes(spec, folder),
        }
        stale = sorted(set(previous) - {p.name for p in written} - {"manifest.json"})
        for name in stale:  # the previous run's outputs this run does not write
            (folder / name).unlink(missing_ok=True)
        if stale:
            manifest["removed"] = stale
            _log.info("note: removed %d outputs of the previous run: %s", len(stale), stale)
        written.append(
            write_text_atomically(folder / "manifest.json", json.dumps(manifest, indent=2) + "\n")
        )
    return written
