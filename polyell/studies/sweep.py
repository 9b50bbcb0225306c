"""``sweep``: scores over thousands to millions of configurations, chunked, resumable, on Dask.

Each chunk of configurations is computed by the vectorised path
(:mod:`polyell.studies.batch`), singular configurations by the scalar one, so every row
equals ``compare(analyze(...)).to_row()``.  With ``out=`` every chunk becomes one Parquet
file, written atomically (a temporary file renamed into place): a run stopped at any point
and started again with the same arguments computes only the missing chunks.

Chunks are sized by time (``chunk=None``, :func:`chunk_for`): as many configurations
as take about :data:`CHUNK_SECONDS` on this core, measured on the sweep's first rows, at
most :data:`MAX_CHUNK`; so that a stopped run loses seconds, and the progress bar (one
step per configuration) moves every few seconds.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import pickle
import re
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from difflib import get_close_matches
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray
from tqdm import tqdm

from polyell.capacities import capacity_class, check_capacity, joint_limits_of, state_of
from polyell.capacities.horizon import (
    JointHorizon,
    horizon_block,
    moving_dynamics,
    refuse_without_horizon,
    robot_horizon,
)
from polyell.capacities.zonotope import ZonotopeAnalysis
from polyell.comparison.candidates import Candidate, check_candidates
from polyell.comparison.comparison import (
    MAX_SAMPLES,
    MAX_SEED,
    MIN_SAMPLES,
    SCORE_NAMES,
    compare,
    compared_kinds,
)
from polyell.comparison.directions import direction_vectors, has_names
from polyell.comparison.long_form import wide_attrs
from polyell.errors import (
    InputError,
    MissingDependencyError,
    PolyellWarning,
    SolverError,
    StorageError,
    install_hint,
)
from polyell.geometry.directions import default_direction_count, sphere_directions
from polyell.geometry.subspace import RANK_RTOL
from polyell.models.dynamics import Dynamics
from polyell.storage import (
    dataset_lock,
    existing_parts,
    part_is_complete,
    part_path,
    read_metadata,
    write_atomically,
    write_text_atomically,
)
from polyell.studies.along import analysis_within
from polyell.studies.batch import BLOCK, BatchOptions, batch_rows
from polyell.studies.cluster import check_scheduler, local_cluster
from polyell.studies.configurations import ConfigurationSet
from polyell.studies.force_batch import force_rows
from polyell.studies.trajectory import Trajectory
from polyell.validation import (
    check_array,
    check_directions,
    check_fraction,
    check_integer,
)

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "CHUNK_SECONDS",
    "DEFAULT_SCORES",
    "MAX_CHUNK",
    "PER_ROW",
    "chunk_for",
    "per_row_note",
    "sweep",
]

#: Progress notes (a resumed dataset), at level INFO: silent unless the application shows
#: them (``polyell study`` does, on standard error).
_log = logging.getLogger("polyell")

#: Scores a sweep computes by default: all but the ratios to the MVIE and to the outer
#: ellipsoid (see ``mvie=True``, ``outer=True``) and the enclosing scales (their vertex
#: enumeration costs about a fifth of a sweep's time); ask for them in ``scores``.
_OPT_IN = ("mvie_ratio", "outer_ratio", "enclosing_scale")
DEFAULT_SCORES = tuple(name for name in SCORE_NAMES if name not in _OPT_IN)

#: The column that says which rows were computed one configuration at a time
#: (``compare(analyze(...))``, cddlib) instead of by the batch: singular configurations,
#: sets the batch cannot certify.  Counted in the log and in a study's manifest.
PER_ROW = "per_row"


def _log_per_row(rows: pd.DataFrame | Path, capacity: str, where: str = "") -> None:
    """Log :func:`per_row_note`: at INFO (shown by ``polyell study``) where rows left the batch."""
    count, total = _per_row_counts(rows)
    level = logging.INFO if count else logging.DEBUG
    _log.log(level, "note: sweep of %s%s", per_row_note((count, total), capacity), where)


def _per_row_counts(rows: pd.DataFrame | Path | tuple[int, int]) -> tuple[int, int]:
    """``(rows per row, rows)`` of a frame, or of a dataset read part by part.

    Part by part: the whole column of 10^7 rows read at once cost 180 MiB more than the
    sweep itself.
    """
    if isinstance(rows, tuple):
        return rows
    if not isinstance(rows, Path):
        return int(rows[PER_ROW].sum()), len(rows)
    import pyarrow.parquet as pq

    count = total = 0
    for part in sorted(rows.rglob("part-*.parquet")):
        column = pq.read_table(part, columns=[PER_ROW]).column(0).to_numpy()
        count, total = count + int(column.sum()), total + len(column)
    return count, total


def per_row_note(rows: pd.DataFrame | Path | tuple[int, int], capacity: str) -> str:
    """``"force: 3 of 2000 rows per row (0.15 %)"``: how much of a sweep left the batch.

    ``rows``: a sweep's frame, its Parquet dataset's folder, or ``(count, total)``.
    """
    count, total = _per_row_counts(rows)
    share = 100.0 * count / total if total else 0.0
    return f"{capacity}: {count} of {total} rows per row ({share:.2f} %)"


@dataclass(frozen=True)
class _Job:
    """Everything a worker needs to compute chunks (pickled once per task)."""

    source: Any  # a robot or a batched Dynamics
    configurations: Any  # ConfigurationSet, ndarray (K, n), or None for Dynamics
    tau_max: NDArray[np.float64]
    tau_min: NDArray[np.float64]
    directions: NDArray[np.float64]
    # What the scalar path passes to compare(): the user's count, the vectors, or None for
    # compare's default (its count follows the rank: 360 on a singular 3-D configuration).
    scalar_directions: Any
    columns: tuple[str, ...]
    options: BatchOptions
    joints: int = 0  # q columns written: n, or more (NaN) to match other robots' datasets
    # The joint limits over a horizon (sweep(horizon=)), at q = qd = 0: moved to each state.
    horizon: JointHorizon | None = None

    def size(self) -> int:
        if self.configurations is None:
            return len(self.source)
        return len(self.configurations)

    def chunk(self, start: int, stop: int) -> pd.DataFrame:
        """The results of configurations ``start`` to ``stop - 1``."""
        if self.configurations is None:
            dyn, q = self.source[start:stop], None
        else:
            q = (
                self.configurations.rows(start, stop)
                if isinstance(self.configurations, ConfigurationSet)
                else self.configurations[start:stop]
            )
            dyn = self.source.dynamics(q)
        state = None
        if self.horizon is not None:  # the states: at rest, or a trajectory's velocities
            assert q is not None  # a robot's configurations (checked by _job)
            qd = getattr(self.configurations, "qd", None)
            state = self.horizon.at(q, np.zeros_like(q) if qd is None else qd[start:stop])
            dyn = moving_dynamics(self.source, q, state.qd)
        if dyn.m > dyn.n:  # singular everywhere: the scalar path
            scalar = np.ones(len(dyn), dtype=bool)
            values = _scalar_rows(dyn, scalar, self, state, start)
        else:
            values, scalar = _batch(dyn, self)
            if state is not None:  # a set cut by the joints' intervals: the exact path
                scalar |= horizon_block(dyn, state, self.tau_max, self.tau_min).cut
            if scalar.any():
                for name, column in _scalar_rows(dyn, scalar, self, state, start).items():
                    values[name][scalar] = column[scalar]
        import pandas as pd

        frame = pd.DataFrame({"configuration": np.arange(start, start + len(dyn))})
        if isinstance(self.configurations, Trajectory) and self.configurations.t is not None:
            frame["t"] = self.configurations.t[start:stop]
        if q is not None:
            padded = np.full((len(q), max(self.joints, q.shape[1])), np.nan)
            padded[:, : q.shape[1]] = q
            names = [f"q{i + 1}" for i in range(padded.shape[1])]
            frame = frame.join(pd.DataFrame(padded, columns=names))
        frame[PER_ROW] = scalar
        frame = frame.join(pd.DataFrame({name: values[name] for name in self.columns}))
        frame.attrs.update(_frame_attrs(self))  # written into the Parquet parts too
        return frame


#: The polytope's own columns, before every ``<kind>_<score>`` one.
_POLYTOPE = ("polytope_dim", "polytope_volume", "polytope_ball_radius", "polytope_origin_radius")


def _kinds(options: BatchOptions) -> list[str]:
    """The ellipsoids a sweep scores: the capacity's, the optima computed, the candidates."""
    computed = {"mvie": options.mvie, "outer": options.outer}
    kinds = [kind for kind in compared_kinds(options.capacity) if computed.get(kind, True)]
    return kinds + [candidate.name for candidate in options.candidates]


def _frame_attrs(job: _Job) -> dict[str, Any]:
    """The structure a sweep's frame records in ``attrs``: capacity, kinds, score names.

    The score names are those of the first kind's columns, ``f"{kinds[0]}_{score}"`` by
    construction (:func:`_job`), in column order.
    """
    kinds = _kinds(job.options)
    width = (len(job.columns) - len(_POLYTOPE)) // len(kinds)
    first = job.columns[len(_POLYTOPE) : len(_POLYTOPE) + width]
    scores = [column[len(kinds[0]) + 1 :] for column in first]
    return wide_attrs(job.options.capacity, kinds, scores)


def _batch(dyn: Dynamics, job: _Job) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.bool_]]:
    """The batch path's columns and the rows it leaves to the scalar path.

    Velocities are the accelerations of the same arm with ``B = I``, no gravity and the
    velocity limits as torque limits: the zonotope ``{J qd_c + J L_v u}``, whose image of the
    unit ball (the velocity kind ``"yoshikawa"``) is the acceleration kind ``"chiacchio"``
    with the same minimum-norm witness.
    """
    if job.options.capacity == "force":
        return force_rows(dyn, job.tau_max, job.tau_min, job.directions, job.options)
    if job.options.capacity != "velocity":
        return batch_rows(dyn, job.tau_max, job.tau_min, job.directions, job.options)
    K, n = len(dyn), dyn.n
    still = Dynamics(dyn.J, np.broadcast_to(np.eye(n), (K, n, n)), np.zeros((K, n)), task=dyn.task)
    values, scalar = batch_rows(still, job.tau_max, job.tau_min, job.directions, job.options)
    # Exact column names, not prefixes: a candidate may be named "chiacchio_w" or
    # "yoshikawa_x" (its columns then start like a built-in kind's).
    classic = {f"yoshikawa_{score}" for score in SCORE_NAMES}  # no velocity counterpart
    unit_ball = {f"chiacchio_{score}": f"yoshikawa_{score}" for score in SCORE_NAMES}
    renamed = {
        unit_ball.get(name, name): column for name, column in values.items() if name not in classic
    }
    return renamed, scalar


def _scalar_rows(
    dyn: Dynamics,
    rows: NDArray[np.bool_],
    job: _Job,
    state: JointHorizon | None = None,
    first: int = 0,
) -> dict[str, NDArray[np.float64]]:
    """``compare(analyze(...)).to_row()`` for the flagged rows (NaN elsewhere).

    A set no solver builds (a SolverError: a 6-D set cut by the joints' intervals with
    thousands of vertices) leaves its row NaN, ``polytope_dim`` included, and is logged as
    a warning naming the configuration (``first``: the chunk's first); the sweep goes on.
    """
    values = {name: np.full(len(dyn), np.nan) for name in job.columns}
    options = job.options
    for k in np.flatnonzero(rows):
        # (a capacity's limits come in the torque slots, whatever they are)
        analysis = analysis_within(
            dyn[int(k)],
            options.capacity,
            job.tau_max,
            job.tau_min,
            options.rank_rtol,
            None if state is None else state[int(k)],
        )
        try:
            row = compare(
                analysis,
                job.scalar_directions,
                samples=options.samples,
                seed=options.seed,
                mvie=options.mvie,
                outer=options.outer,
                candidates=options.candidates,
            ).to_row()
        except SolverError as exn:  # one set the solvers cannot build: NaN, said, not fatal
            _log.warning("configuration %d: every score NaN (%s)", first + k, exn)
            continue
        for name in job.columns:
            values[name][k] = row[name]
    return values


def _run_chunk(job: _Job, index: int, chunk: int, out: str | None) -> Any:
    """Compute one chunk; write it (returning its path) or return the frame."""
    frame = job.chunk(index * chunk, min((index + 1) * chunk, job.size()))
    if out is None:
        return frame
    path = part_path(Path(out), index)
    return str(write_atomically(path, lambda name: frame.to_parquet(name, index=False)))


def _fingerprint(job: _Job, chunk: int) -> str:
    """A digest of what determines the numbers.

    The arguments, and the robot model's content: a URDF robot pickles by its path, so the
    digest of its text is added (an edited URDF is a different sweep).
    """
    model = getattr(job.source, "content_digest", None)
    digest = hashlib.sha256(pickle.dumps((job, chunk, model), protocol=4))
    return digest.hexdigest()


#: How long a chunk of the automatic size takes [s]: what a stopped run loses at most (per
#: worker), and how often the progress bar moves.  Parquet's cost per part (about 10 ms)
#: is then under 1 % of it (``docs/performance.md`` (q)).
CHUNK_SECONDS = 2.0

#: The largest automatic chunk: the fixed chunk size of earlier versions, whose peak memory
#: it keeps (about 430 MiB for the Panda, ``docs/performance.md`` (d)).
MAX_CHUNK = 20_000

#: The chunk size of the datasets written before ``_sweep.json`` recorded it (the default
#: then, and the study files' default).
_LEGACY_CHUNK = 20_000

#: The pilot run of :func:`_automatic_chunk`: the sweep's first rows, each count in turn,
#: until one takes ``_PILOT_SECONDS``.
_PILOT_ROWS = (16, 64, 256, 1024)
_PILOT_SECONDS = 0.1


def chunk_for(seconds_per_configuration: float) -> int:
    """The automatic chunk size for a cost per configuration [s].

    ``CHUNK_SECONDS / seconds_per_configuration`` rounded down to two significant digits,
    from 1 to :data:`MAX_CHUNK`.

    Examples
    --------
    >>> chunk_for(55e-6), chunk_for(300e-6), chunk_for(0.021)
    (20000, 6600, 95)
    """
    if not seconds_per_configuration > 0.0:  # (a clock too coarse to see the pilot)
        return MAX_CHUNK
    rows = CHUNK_SECONDS / seconds_per_configuration
    if rows >= MAX_CHUNK:
        return MAX_CHUNK
    whole = max(1, int(rows))
    scale = 10 ** max(0, len(str(whole)) - 2)
    return whole // scale * scale


def _automatic_chunk(job: _Job) -> int:
    """:func:`chunk_for` the cost per configuration of the job's first rows (a pilot run).

    The first 16 rows are computed once untimed (the first call of a process imports
    and warms up what the rows need), then the pilot grows through ``_PILOT_ROWS`` until
    one takes ``_PILOT_SECONDS`` (0.1 s) or already gives :data:`MAX_CHUNK` or the whole
    job in one chunk: at most about 0.2 s (0.4 s on a busy machine), or twice 16
    configurations, of work done again by the first chunk (the results are dropped).  Its
    warnings are silenced: the same rows warn when the first chunk computes them.  A job
    of 16 configurations or fewer is one chunk, without a pilot.
    """
    size = job.size()
    if size <= _PILOT_ROWS[0]:
        return size
    times: list[tuple[int, float]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        job.chunk(0, _PILOT_ROWS[0])
        for pilot in _PILOT_ROWS:
            rows = min(pilot, size)
            started = time.perf_counter()
            job.chunk(0, rows)
            times.append((rows, time.perf_counter() - started))
            if times[-1][1] >= _PILOT_SECONDS or rows == size:
                break
            if chunk_for(_seconds_per_row(times)) >= min(size, MAX_CHUNK):
                break  # one chunk, or the largest: no need to know better
    chunk = chunk_for(_seconds_per_row(times))
    _log.debug(
        "sweep of %s: chunks of %d configurations (pilot: %s)",
        job.options.capacity,
        chunk,
        ", ".join(f"{rows} in {seconds:.3g} s" for rows, seconds in times),
    )
    return chunk


def _seconds_per_row(times: list[tuple[int, float]]) -> float:
    """A configuration's time in a chunk of full blocks, from the pilot's (rows, seconds).

    The batch computes blocks of ``BLOCK`` (512) rows at a cost ``a + b r`` each: the
    last two pilots give ``b`` and ``a``, and a row of a full block costs
    ``b + a / BLOCK`` (the MVIE's solver, a fixed number of vectorised iterations per
    block, has a large ``a``).  With one pilot, or two that contradict this, the last
    one's average (an overestimate: smaller chunks).
    """
    rows, seconds = times[-1]
    if len(times) < 2:
        return seconds / rows
    before, earlier = times[-2]
    per_row = (seconds - earlier) / (rows - before)
    per_call = seconds - per_row * rows
    if per_row <= 0.0 or per_call < 0.0:
        return seconds / rows
    return per_row + per_call / max(rows, BLOCK)


#: How long to wait for a Dask scheduler to answer.
CONNECT_TIMEOUT = "10s"


def _client(scheduler: str) -> Any:
    check_scheduler(scheduler)
    try:
        from dask.distributed import Client
    except ImportError as exn:
        raise MissingDependencyError(
            "Distributed sweeps need Dask. Fix: " + install_hint("studies") + "."
        ) from exn
    if scheduler == "processes":
        return Client(local_cluster())
    if scheduler.startswith(("tcp://", "tls://", "inproc://")):
        try:
            return Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError) as exn:
            raise InputError(
                "scheduler",
                "the address of a running Dask scheduler",
                f"{scheduler}, silent for {CONNECT_TIMEOUT} ({exn.__class__.__name__})",
                "start one with 'dask scheduler' (and workers), or use scheduler='processes'.",
            ) from None
        except (TypeError, ValueError) as exn:  # e.g. tls:// without Dask's TLS settings
            raise InputError(
                "scheduler",
                "a Dask scheduler address this client can connect to",
                f"{scheduler} ({exn.__class__.__name__}: {str(exn)[:160]})",
                "for tls:// set Dask's distributed.comm.tls options; or use tcp://host:port.",
            ) from None
    raise InputError(
        "scheduler",
        "None, 'processes' or a Dask scheduler address (tcp://host:port)",
        repr(scheduler),
        "pass 'processes', or the address 'dask scheduler' prints, e.g. tcp://127.0.0.1:8786.",
    )


def _job(
    source: Any,
    configurations: Any,
    tau_max: ArrayLike | None,
    tau_min: ArrayLike | None,
    scores: Sequence[str],
    directions: int | ArrayLike | None,
    options: BatchOptions,
    horizon: dict[str, Any] | None = None,
) -> _Job:
    if isinstance(source, Dynamics) and horizon is not None:
        raise InputError(
            "source",
            "a robot and its configurations (the states' positions) with horizon=",
            "a batched Dynamics",
            "pass the robot, e.g. pe.sweep(panda, q, horizon=0.001).",
        )
    if isinstance(source, Dynamics):
        if source.batch_size is None:
            raise InputError(
                "source",
                "a batched Dynamics (J of shape (K, m, n))",
                "a single one",
                "pass robot.dynamics(q) of a (K, n) q, or the robot and q: pe.sweep(robot, q).",
            )
        if configurations is not None:
            raise InputError(
                "configurations",
                "None with a batched Dynamics",
                "configurations",
                "drop them (the Dynamics holds its configurations): pe.sweep(dyn), or pass "
                "the robot instead: pe.sweep(robot, q).",
            )
        if len(source) == 0:
            raise InputError(
                "source",
                "at least one configuration",
                "a batch of none",
                "pass the dynamics of at least one configuration: robot.dynamics(q) with "
                "q of shape (K, n), K >= 1.",
            )
        n, m, task = source.n, source.m, source.task
    else:
        if not hasattr(source, "dynamics"):
            raise InputError(
                "source",
                "a robot or a batched pe.Dynamics",
                type(source).__name__,
                "pass a robot, e.g. pe.sweep(pe.robots.load('panda'), q), or a batched "
                "robot.dynamics(q).",
            )
        n = source.n
        if configurations is None:
            raise InputError(
                "configurations",
                "a (K, n) array or pe.grid(...)",
                "None",
                f"pass the configurations, e.g. pe.sweep(robot, pe.random_configurations(robot, "
                f"1000)) or a (K, {n}) array of joint angles.",
            )
        if not isinstance(configurations, ConfigurationSet):
            configurations = check_array("configurations", configurations, ("K", n))
            if len(configurations) == 0:
                raise InputError(
                    "configurations",
                    "at least one configuration",
                    "an empty (0, n) array",
                    f"pass at least one row of {n} joint angles, e.g. "
                    "pe.random_configurations(robot, 100).",
                )
        elif configurations.n != n:
            raise InputError(
                "configurations",
                f"{n} joints",
                f"{configurations.n}",
                f"make the set for this {n}-joint robot, e.g. pe.random_configurations(robot, "
                f"1000), or a pe.grid of {n} axes.",
            )
        first = source.dynamics(
            configurations.rows(0, 1)[0]
            if isinstance(configurations, ConfigurationSet)
            else configurations[0]
        )
        m, task = first.m, first.task
    # (the joint velocity limits come in the torque slots)
    upper, lower = capacity_class(options.capacity)._source_limits(source, tau_max, tau_min, n)
    unknown = sorted(set(scores) - set(SCORE_NAMES))
    if unknown:
        close = get_close_matches(unknown[0], SCORE_NAMES, n=1)
        raise InputError(
            "scores",
            f"names among {list(SCORE_NAMES)}",
            f"unknown {unknown}",
            f"did you mean {close[0]!r} for {unknown[0]!r}?"
            if close
            else "use names of the list, e.g. scores=['coverage', 'inscribed_scale'].",
        )
    for kind, wanted in (("mvie", options.mvie), ("outer", options.outer)):
        if f"{kind}_ratio" in scores and not wanted:
            raise InputError(
                "scores",
                f"no '{kind}_ratio' without {kind}=True",
                f"'{kind}_ratio'",
                f"pass {kind}=True.",
            )
    for candidate in options.candidates:
        candidate.check_sizes(m, n)
    # The default of pe.compare, so that rows equal compare(...) as they are: on full-rank
    # configurations (the batch) its count for m, on the others the count for their rank.
    if isinstance(directions, bool | float | np.floating | np.bool_):
        raise InputError(
            "directions",
            "None, a count (int) or unit vectors of shape (k, m)",
            repr(directions),
            "pass e.g. directions=256, or leave the default.",
        )
    count = default_direction_count(m) if directions is None else directions
    scalar_directions: Any
    if isinstance(count, int | np.integer) and not isinstance(count, bool):
        T = sphere_directions(int(count), m)
        scalar_directions = None if directions is None else int(count)
    elif has_names(directions):  # names of the task's rows, as compare reads them
        T = np.atleast_2d(direction_vectors(cast(Any, directions), task, "directions"))
        scalar_directions = T
    else:
        T = np.atleast_2d(check_directions("directions", cast(ArrayLike, directions), m))
        scalar_directions = T
    kinds = _kinds(options)
    columns = (*_POLYTOPE, *(f"{k}_{s}" for k in kinds for s in scores))
    options = replace(options, vertices=options.outer or "enclosing_scale" in scores)
    template = None if horizon is None else robot_horizon(source, **horizon)
    return _Job(
        source, configurations, upper, lower, T, scalar_directions, columns, options, n, template
    )


def sweep(
    source: Any,
    configurations: ArrayLike | ConfigurationSet | None = None,
    tau_max: ArrayLike | None = None,
    tau_min: ArrayLike | None = None,
    *,
    scores: Sequence[str] | None = None,
    directions: int | ArrayLike | None = None,
    out: str | os.PathLike[str] | None = None,
    scheduler: str | None = None,
    chunk: int | None = None,
    mvie: bool = False,
    outer: bool = False,
    candidates: Sequence[Candidate] = (),
    samples: int = 2**13,
    seed: int = 0,
    rank_rtol: float = RANK_RTOL,
    progress: bool = False,
    capacity: str = "acceleration",
    qd_max: ArrayLike | None = None,
    qd_min: ArrayLike | None = None,
    horizon: float | None = None,
    q_min: ArrayLike | None = None,
    q_max: ArrayLike | None = None,
    braking: ArrayLike | None = None,
) -> pd.DataFrame | Path:
    """Score the ellipsoids of a capacity, optionally the MVIE, the outer one, candidates.

    Parameters
    ----------
    source : robot, Dynamics, or several robots
        A robot (``PlanarArm``, ``UrdfRobot``) with ``configurations``, or a batched
        :class:`Dynamics` (J of shape (K, m, n)).  Several robots, side by side: a dict
        of names to robots (or a list, named ``"0"``, ``"1"``, ...) with one set of
        configurations each (the same keys, or a list of the same length; one array or
        set is shared when every robot has its joint count), each with its own torque
        limits; the frame then starts with a ``robot`` column, and ``out=`` holds one
        dataset per robot in ``robot=<name>/`` (``pd.read_parquet(out)`` reads them all,
        the ``robot`` column included).
    configurations : array-like (K, n) or ConfigurationSet, optional
        Joint configurations, e.g. :func:`polyell.grid` or
        :func:`polyell.random_configurations` (lazy: never all in memory).
    tau_max, tau_min : array-like, shape (n,), optional
        Torque limits; default the robot's own (always, for several robots).
    scores : sequence of str
        Score names (:data:`polyell.SCORE_NAMES`); columns ``<kind>_<score>``.  Default
        (None): :data:`DEFAULT_SCORES`, all but ``enclosing_scale`` (a vertex enumeration,
        about a fifth of the time) and the ratios to the optimal ellipsoids not computed:
        ``mvie_ratio`` with ``mvie=True``, ``outer_ratio`` with ``outer=True``.
    directions : int, array-like (k, m), sequence of names or None
        The directional-statistics set, exactly as :func:`polyell.compare` takes it: a count
        of the default near-uniform set (at a singular configuration, drawn in its affine
        set), or unit vectors (or names of the task's rows, ``["x", "-z"]``) used at every
        configuration; default, as in
        :func:`polyell.compare`, 360 in 2-D, 256 in 3-D and 2,000 above (see
        :func:`~polyell.geometry.directions.default_direction_count` for why).
    out : path, optional
        A folder for a Parquet dataset, one ``part-NNNNNN.parquet`` per chunk; the
        function then returns the folder.  Restarting with the same arguments resumes.
    scheduler : None, "processes" or str
        None: in this process.  ``"processes"``: a local Dask cluster, one worker per
        core (:func:`polyell.local_cluster`).  ``"tcp://host:port"``: an existing Dask
        cluster (start its workers without ``MALLOC_TRIM_THRESHOLD_``, see
        :mod:`polyell.studies.cluster`).
    chunk : int or None
        Configurations per task (and per Parquet file).  Default (None): sized by time,
        :func:`chunk_for` the cost per configuration of a pilot run on the first rows: as
        many as take about :data:`CHUNK_SECONDS` (2 s) here, at most :data:`MAX_CHUNK`
        (20,000, the fixed default of earlier versions), so that a stopped run loses
        seconds and the progress bar moves.  On the Panda's 3-D task (a busy 2-core
        machine, ``docs/performance.md`` (q)) 13,000 to 20,000 at the defaults (about
        9,500 for forces) and 2,700 to 4,200 with ``mvie=True, outer=True``; in its 6-D
        task 9,500, 270 for forces and 58 for accelerations with both.  The rows do not
        depend on it; in memory without ``progress`` or ``scheduler`` it is
        20,000 without a pilot.  A dataset in ``out`` keeps the chunk size it was written
        with (recorded in its ``_sweep.json``; one written before chunk sizes were
        recorded resumes at 20,000, or says which ``chunk`` to pass), and an explicit
        ``chunk`` other than the dataset's is refused, naming it.
    mvie : bool
        Also compute the maximum-volume inscribed ellipsoid at every configuration
        (batched interior-point solver) and every ``mvie_ratio``.
    outer : bool
        Also compute the minimum-volume enclosing (outer) ellipsoid at every configuration
        (the same solver on the vertices) and every ``outer_ratio``.

        Both default to False here and to true in study files (``[compare] mvie``,
        ``outer``), which therefore cost more per configuration.  On the Panda's 3-D
        position task (one core, Pinocchio's dynamics included; three runs on a shared
        machine, ``docs/performance.md`` (q)) each takes 2.9 to 5.8 times the time of the
        defaults (the MVIE of forces 1.8 to 2.7 times), and both 4.6 to 6.5 times for
        accelerations and velocities and 3.9 to 4.7 times for forces; in its 6-D task
        both take 6.5 times for velocities, 1.7 times for forces and 81 times for
        accelerations.  Set them in a study file to false for this function's cost.
    candidates : sequence of Candidate
        User-defined ellipsoids (:class:`polyell.Candidate`), scored like the built-in
        ones under ``<name>_<score>``.  One that is not inside P where the vertices are not
        enumerated takes the per-row path there (``per_row``).
    samples : int
        Sampling budget where an ellipsoid leaves the polytope, as in
        :func:`polyell.compare` (from 2 to 2^22).
    seed : int
        Seed of those estimates, a non-negative integer.
    rank_rtol : float
        Rank tolerance, as in :func:`polyell.analyze`.
    progress : bool
        A progress bar on standard error (tqdm), one step per configuration, advanced as
        each chunk finishes, named after the capacity (and the robot, for several robots
        or a ``robot=<name>`` dataset); a resumed dataset starts it at the configurations
        already done, and one with nothing left to compute shows none.
    capacity : {"acceleration", "velocity", "force"}
        As in :func:`polyell.analyze`: the columns are ``<kind>_<score>`` over the
        capacity's own kinds (``static_*`` for forces).  Velocities take ``qd_max`` and
        ``qd_min`` (default the robot's own, ``robot.velocity_limits()``) instead of torque
        limits; forces take their own batch path
        (:mod:`polyell.studies.force_batch`).
    qd_max, qd_min : array-like, shape (n,), optional
        Joint velocity limits [rad/s] of the velocity capacity, or of the horizon.
    horizon : float, optional
        A control period [s] (accelerations, robots): score the ellipsoids against the
        accelerations that also keep every joint within its position limits over the
        period and within its velocity limits at its end
        (:class:`~polyell.capacities.horizon.HorizonAnalysis`), from the state
        ``(q, qd)``: ``qd`` a :class:`~polyell.Trajectory`'s velocities, else 0 (at rest).
        Rows whose joint intervals cut the set take the per-row path (``per_row``; they
        are counted in the log); the others are the sets without a horizon.
    q_min, q_max, braking : array-like, shape (n,), optional
        With ``horizon``: the position limits (default the robot's ``position_limits``)
        and the braking decelerations of viability (default none), as in
        :func:`polyell.analyze`.

    Returns
    -------
    DataFrame or Path
        One row per configuration: ``configuration`` (its index), ``q1``..``qn`` (for a
        robot), ``per_row`` (True where the row left the batch for ``compare``, one
        configuration at a time: counted in the log, :func:`per_row_note`),
        ``polytope_dim``, ``polytope_volume``, ``polytope_ball_radius``,
        ``polytope_origin_radius`` and the score columns; or the dataset folder with
        ``out=``.  Its ``attrs`` record its structure
        (:func:`~polyell.comparison.long_form.wide_attrs`): ``"capacity"``, ``"kinds"``
        (the ellipsoids with columns, candidates too) and ``"scores"``; Parquet parts keep
        them, and :func:`polyell.to_long` reads them.
    """
    robots = (
        _named("source", source, "robots") if isinstance(source, Mapping | list | tuple) else None
    )
    if chunk is not None:  # None: sized by time (_automatic_chunk)
        chunk = check_integer("chunk", chunk, 1, 10_000_000)
    for name, flag in (("mvie", mvie), ("outer", outer), ("progress", progress)):
        if not isinstance(flag, bool | np.bool_):
            raise InputError(
                name, "True or False", repr(flag), f"pass {name}=True or {name}=False."
            )
    if scores is None:  # the ratios to the optima computed
        optima = {"mvie_ratio": mvie, "outer_ratio": outer}
        scores = tuple(name for name in SCORE_NAMES if optima.get(name, name in DEFAULT_SCORES))
    scores = _check_scores(scores)
    rank_rtol = check_fraction("rank_rtol", rank_rtol)
    if out is not None and not isinstance(out, str | os.PathLike):
        raise InputError(
            "out",
            "a folder path (str or pathlib.Path) or None",
            repr(out),
            "pass a folder, e.g. out='results', or None to get a DataFrame back.",
        )
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError(
            "scheduler",
            "None, 'processes' or a Dask scheduler address",
            repr(scheduler),
            "pass None to run here, 'processes' for a local cluster, or an address as a "
            "string, e.g. 'tcp://127.0.0.1:8786'.",
        )
    capacity = check_capacity(capacity)
    limits = None
    refuse_without_horizon(horizon, q_min=q_min, q_max=q_max, braking=braking)
    if horizon is not None:  # the velocity limits are the horizon's
        state_of(capacity_class(capacity), horizon)
        limits = {"horizon": horizon, "q_min": q_min, "q_max": q_max, "braking": braking}
        limits |= {"qd_min": qd_min, "qd_max": qd_max}
        qd_max = qd_min = None
    # velocities: the velocity limits in the torque limits' slots of the batch
    tau_max, tau_min = joint_limits_of(capacity, tau_max, tau_min, qd_max, qd_min)
    options = BatchOptions(
        mvie=bool(mvie), outer=bool(outer), rank_rtol=rank_rtol, capacity=capacity
    )
    options = replace(options, candidates=check_candidates(candidates))
    weighted = [c.name for c in options.candidates if c.weighting is not None]
    if weighted and not issubclass(capacity_class(capacity), ZonotopeAnalysis):
        warnings.warn(
            f"candidates {weighted}: a weighting of normalized joint quantities defines no "
            f"ellipsoid of the {capacity} capacity: their columns are NaN in every row (as "
            "compare reports them undefined). Fix: give them a core (and a centre) instead.",
            PolyellWarning,
            stacklevel=2,
        )
    options = replace(
        options,
        samples=check_integer("samples", samples, MIN_SAMPLES, MAX_SAMPLES),
        seed=check_integer("seed", seed, 0, MAX_SEED),
    )
    check_scheduler(scheduler)  # before any work: a malformed address is refused at once
    if robots is not None:
        return _sweep_robots(
            robots, configurations, tau_max, tau_min, scores, directions, options, out,
            lambda job, folder, name: _run(job, folder, chunk, scheduler, progress, name),
            limits,
        )  # fmt: skip
    job = _job(source, configurations, tau_max, tau_min, scores, directions, options, limits)
    if out is not None:
        _refuse_mixed(Path(out), several=False)
    return _run(job, out, chunk, scheduler, progress)


def _run(
    job: _Job,
    out: Any,
    chunk: int | None,
    scheduler: str | None,
    progress: bool,
    robot: str = "",
) -> pd.DataFrame | Path:
    """Compute a job: returned as a frame, or into the dataset ``out`` (resuming it).

    ``chunk`` None: the dataset's own, or sized by time (:func:`_automatic_chunk`); in
    memory without a progress bar or a scheduler, :data:`MAX_CHUNK` (no pilot run).
    ``robot`` names the progress bar's robot; a dataset ``robot=<name>/`` (one robot of
    several, as :func:`sweep` and ``polyell study`` write them) names it too.
    """
    if out is None:
        if chunk is None:  # the time of a chunk matters to a bar and to Dask's tasks only
            timed = progress or scheduler is not None
            chunk = _automatic_chunk(job) if timed else min(MAX_CHUNK, job.size())
        count = -(-job.size() // chunk)
        frame = _execute(job, list(range(count)), chunk, None, scheduler, progress, robot)
        frame.attrs.update(_frame_attrs(job))  # capacity, kinds, scores: pe.to_long
        _log_per_row(frame, job.options.capacity)
        return frame
    folder = _folder(out)
    if not robot and folder.name.startswith("robot="):
        robot = folder.name.removeprefix("robot=")
    with dataset_lock(folder):
        chunk = _dataset_chunk(folder, job, chunk)
        count = -(-job.size() // chunk)
        todo = _resume(folder, job, chunk, count)
        if len(todo) < count:
            _log.info("resuming %s: %d of %d chunks done", folder, count - len(todo), count)
        _execute(job, todo, chunk, folder, scheduler, progress, robot)
        unfinished = [i for i in range(count) if not _done(folder, job, chunk, i)]
        if unfinished:  # pragma: no cover - a worker's write that vanished
            raise StorageError(f"{len(unfinished)} parts of {folder} are missing after the run.")
    _log_per_row(folder, job.options.capacity, f" into {folder}")
    return folder


#: A robot's name in a sweep of several: a folder name (``robot=<name>``) on every system.
_ROBOT_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")


def _named(argument: str, value: Mapping[Any, Any] | Sequence[Any], what: str) -> dict[str, Any]:
    """A dict of checked names to items, from a dict or a list (named by position)."""
    items = dict(value) if isinstance(value, Mapping) else {str(i): v for i, v in enumerate(value)}
    if not items:
        raise InputError(
            argument,
            f"at least one of the {what}",
            "an empty collection",
            f"pass at least one, e.g. {argument}={{'panda': pe.robots.load('panda')}}."
            if argument == "source"
            else f"pass one per robot by its name, e.g. {argument}={{'panda': q}}.",
        )
    for name in items:
        if not isinstance(name, str) or not _ROBOT_NAME.fullmatch(name):
            raise InputError(
                argument,
                "names of letters, digits, '_', '.' and '-' (a folder name), at most 64",
                repr(name)[:80],
                "rename the robot, e.g. 'panda' or 'ur5'.",
            )
    return items


def _folder(out: Any) -> Path:
    folder = Path(out)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exn:
        raise InputError(
            "out",
            "a folder polyell can create",
            f"{folder} ({exn.strerror})",
            "choose a folder where you may write, e.g. out='results' in the working folder.",
        ) from None
    return folder


#: The list of robots of a dataset of several (one ``robot=<name>/`` dataset each).
_ROBOTS_FILE = "_robots.json"


def _refuse_mixed(folder: Path, several: bool, names: Sequence[str] = ()) -> None:
    """Refuse to mix a sweep of one robot and one of several (or other robots) in ``out``."""
    if not folder.is_dir():
        return
    partitions = sorted(p.name for p in folder.iterdir() if p.name.startswith("robot="))
    single = (folder / "_sweep.json").exists() or bool(existing_parts(folder))
    listed = folder / _ROBOTS_FILE
    if not several and (partitions or listed.exists()):
        raise InputError(
            "out",
            "an empty folder, or one holding a sweep of one robot",
            f"{folder} holds a sweep of several robots ({', '.join(partitions)})",
            "choose another folder for this sweep.",
        )
    if several and single:
        raise InputError(
            "out",
            "an empty folder, or one holding a sweep of the same robots",
            f"{folder} holds a sweep of one robot",
            "choose another folder for this sweep.",
        )
    if several and listed.exists():
        try:
            held = json.loads(listed.read_text(encoding="utf-8"))["robots"]
        except (OSError, ValueError, KeyError, TypeError):
            held = f"an unreadable {_ROBOTS_FILE}"
        if held != list(names):
            raise InputError(
                "out",
                f"an empty folder, or one holding a sweep of the robots {list(names)}",
                f"{folder} holds a sweep of {held}",
                "choose another folder, or delete it to start over.",
            )


def _sweep_robots(
    robots: dict[str, Any],
    configurations: Any,
    tau_max: Any,
    tau_min: Any,
    scores: tuple[str, ...],
    directions: Any,
    options: BatchOptions,
    out: Any,
    run: Callable[[_Job, Path | None, str], pd.DataFrame | Path],
    horizon: dict[str, Any] | None = None,
) -> pd.DataFrame | Path:
    """:func:`sweep` of several robots: one job each, side by side under a ``robot`` key."""
    names = capacity_class(options.capacity).limit_keywords  # (given in the torque slots)
    for name, value in zip(names, (tau_max, tau_min), strict=True):
        if value is not None:
            raise InputError(
                name,
                "None with several robots (each sweeps within its own limits)",
                "limits",
                f"give each robot its limits: pe.robots.load(name, {name[:-4]}_max=...).",
            )
    for name, robot in robots.items():
        if isinstance(robot, Dynamics) or not hasattr(robot, "dynamics"):
            raise InputError(
                f"source[{name!r}]",
                "a robot",
                type(robot).__name__,
                f"pass robots only, e.g. {{{name!r}: pe.robots.load('panda')}}; sweep a batched "
                "Dynamics on its own.",
            )
    if isinstance(configurations, Mapping | list | tuple) and not _is_rows(configurations):
        sets = _named("configurations", configurations, "configuration sets")
        if set(sets) != set(robots):
            raise InputError(
                "configurations",
                f"one set per robot, for {sorted(robots)}",
                f"sets for {sorted(sets)}",
                f"key the sets by the robots' names {sorted(robots)}, or pass one set for all.",
            )
    else:
        sets = dict.fromkeys(robots, configurations)
    jobs = {}
    for name, robot in robots.items():
        try:
            jobs[name] = _job(robot, sets[name], None, None, scores, directions, options, horizon)
        except InputError as exn:  # which robot: its name in the argument
            argument = f"{exn.argument} of robot {name!r}"
            raise InputError(argument, exn.expected, exn.got, exn.fix) from None
    joints = max(job.joints for job in jobs.values())  # every dataset: the same q columns
    jobs = {name: replace(job, joints=joints) for name, job in jobs.items()}
    import pandas as pd

    if out is None:
        frames = [
            cast("pd.DataFrame", run(job, None, n)).assign(robot=n) for n, job in jobs.items()
        ]
        frame = pd.concat(frames, ignore_index=True)
        frame = frame[["robot", *(c for c in frame.columns if c != "robot")]]
        frame.attrs.update(_frame_attrs(next(iter(jobs.values()))))  # the same for every robot
        return frame
    folder = _folder(out)
    _refuse_mixed(folder, several=True, names=list(jobs))
    write_text_atomically(folder / _ROBOTS_FILE, json.dumps({"robots": list(jobs)}) + "\n")
    for name, job in jobs.items():
        run(job, folder / f"robot={name}", name)
    return folder


def _is_rows(value: Sequence[Any] | Mapping[Any, Any]) -> bool:
    """True for one (K, n) array written as nested lists (a set shared by the robots)."""
    return not isinstance(value, Mapping) and len(value) > 0 and np.ndim(value[0]) == 1


def _check_scores(scores: object) -> tuple[str, ...]:
    """Score names: a sequence of str (one name alone is taken as a sequence of one)."""
    if isinstance(scores, str):
        scores = (scores,)
    if isinstance(scores, bytes) or not isinstance(scores, Sequence | tuple | list):
        raise InputError(
            "scores",
            f"a sequence of score names among {list(SCORE_NAMES)}",
            f"{type(scores).__name__} {scores!r}"[:120],
            "pass e.g. scores=['coverage', 'inscribed_scale'], or leave the default.",
        )
    names = tuple(scores)
    wrong = [item for item in names if not isinstance(item, str)]
    if wrong:
        raise InputError(
            "scores",
            "score names (str)",
            f"an item {wrong[0]!r}",
            "give each score by its name as a str, e.g. scores=['coverage', 'volume'].",
        )
    if not names:
        raise InputError(
            "scores",
            "at least one score name",
            "an empty sequence",
            "name at least one, e.g. scores=['coverage'], or leave scores=None for the default.",
        )
    return names


def _rows(job: _Job, chunk: int, index: int) -> int:
    return min(chunk, job.size() - index * chunk)


def _done(folder: Path, job: _Job, chunk: int, index: int) -> bool:
    return part_is_complete(part_path(folder, index), _rows(job, chunk, index))


def _check_capacity(record: dict[str, Any], folder: Path, capacity: str) -> None:
    """Refuse a dataset of another capacity, saying so (its columns are another's kinds)."""
    held = record.get("capacity", "acceleration")  # datasets before capacities: accelerations
    if held != capacity:
        raise InputError(
            "out",
            f"an empty folder, or one holding the {capacity} capacity's sweep with the same "
            "arguments",
            f"{folder} holds the {held} capacity's sweep (its columns are {held}'s kinds)",
            "choose another folder for each capacity, or delete it to start over.",
        )


def _dataset_chunk(folder: Path, job: _Job, chunk: int | None) -> int:
    """The chunk size of the sweep into ``folder``: the dataset's own, ``chunk``, or by time.

    A dataset records its chunk size in ``_sweep.json`` (``"chunk"``); one written before
    it did was in chunks of 20,000 (the default then) or of an explicit ``chunk``, and its
    fingerprint, which includes the chunk size, tells which.  ``chunk=None`` resumes a
    dataset in its own chunks; an explicit ``chunk`` other than the dataset's is refused,
    naming the dataset's (the parts would not line up).
    """
    meta = folder / "_sweep.json"
    if not meta.exists():
        return _automatic_chunk(job) if chunk is None else chunk
    record = read_metadata(meta)
    _check_capacity(record, folder, job.options.capacity)
    held = record.get("chunk")
    recorded = isinstance(held, int) and not isinstance(held, bool) and held >= 1
    own = cast(int, held) if recorded else _LEGACY_CHUNK
    if chunk is None:
        if recorded or _fingerprint(job, own) == record["fingerprint"]:
            return own  # (a different sweep is refused by _resume)
        _refuse_legacy(folder, job, record)
    elif chunk != own and _fingerprint(job, chunk) != record["fingerprint"]:
        if _fingerprint(job, own) == record["fingerprint"]:
            raise InputError(
                "chunk",
                f"{own} (the chunk size of the sweep in {folder}) to resume it",
                f"{chunk}",
                f"pass chunk={own}, or leave chunk=None; or use another folder.",
            )
    return own if chunk is None else chunk


def _refuse_legacy(folder: Path, job: _Job, record: dict[str, Any]) -> NoReturn:
    """Refuse a dataset without its chunk size that is not this sweep in chunks of 20,000.

    Either a different sweep, or this one in the chunks of an explicit ``chunk``: the
    error gives the chunk sizes that make its number of parts.
    """
    parts, size = record.get("chunks"), record.get("configurations")
    hint = ""
    if isinstance(parts, int) and parts >= 1 and size == job.size():
        low = -(-size // parts)
        if parts == 1:
            hint = f" (chunk={low} or more)"
        elif low <= (size - 1) // (parts - 1):
            hint = f" (chunk={low} to {(size - 1) // (parts - 1)})"
    raise InputError(
        "out",
        "an empty folder, or one holding a sweep with the same arguments",
        f"{folder} holds a different sweep, or this one in chunks other than {_LEGACY_CHUNK:,} "
        "(its _sweep.json predates recorded chunk sizes)",
        f"to resume it, pass the chunk it was written with{hint}; or choose another folder, "
        "or delete it to start over.",
    )


def _resume(folder: Path, job: _Job, chunk: int, count: int) -> list[int]:
    """Check the dataset's metadata (or write it) and list the chunks still to compute.

    Parts are trusted only under a ``_sweep.json`` of the same capacity and fingerprint
    (the capacity is recorded and checked first, to say so), within its chunk count, and
    with a readable footer of the expected row count; a torn or truncated part is computed
    again.
    """
    meta = folder / "_sweep.json"  # "_" and "." files are not part of the dataset
    fingerprint = _fingerprint(job, chunk)
    parts = existing_parts(folder)
    capacity = job.options.capacity
    if meta.exists():
        record = read_metadata(meta)
        _check_capacity(record, folder, capacity)
        if record["fingerprint"] != fingerprint:
            raise InputError(
                "out",
                "an empty folder, or one holding a sweep with the same arguments",
                f"{folder} holds a different sweep",
                "choose another folder, or delete it to start over.",
            )
    elif parts:
        raise InputError(
            "out",
            "a sweep dataset with its _sweep.json",
            f"{len(parts)} part files in {folder} without one",
            "delete the part files (their origin is unknown), or use another folder.",
        )
    else:
        record = {
            "fingerprint": fingerprint,
            "chunks": count,
            "chunk": chunk,  # the configurations per part (in the fingerprint too)
            "configurations": job.size(),
            "capacity": capacity,
        }
        write_text_atomically(meta, json.dumps(record, indent=2) + "\n")
    beyond = sorted(i for i in parts if i >= count)
    if beyond:
        raise InputError(
            "out",
            f"parts 0..{count - 1} of this sweep",
            f"part {beyond[0]} in {folder}",
            "delete the folder to start over.",
        )
    return [i for i in range(count) if not (i in parts and _done(folder, job, chunk, i))]


def _progress_bar(job: _Job, todo: list[int], chunk: int, progress: bool, robot: str) -> Any:
    """The progress bar of a sweep: one step per configuration, from those already done.

    Named after the capacity (and the robot); none where there is nothing left to compute.
    """
    left = sum(_rows(job, chunk, i) for i in todo)
    return tqdm(
        total=job.size(),
        initial=job.size() - left,
        desc=f"{robot} {job.options.capacity}".strip(),
        unit=" configurations",
        unit_scale=job.size() >= 10_000,  # 46.6k/200k; but 30/30, not 30.0/30.0
        disable=not progress or left == 0,
    )


def _execute(
    job: _Job,
    todo: list[int],
    chunk: int,
    folder: Path | None,
    scheduler: str | None,
    progress: bool,
    robot: str = "",
) -> pd.DataFrame:
    """Run the chunks ``todo``: written to ``folder``, or returned as one frame."""
    target = None if folder is None else str(folder)
    results = []
    with _progress_bar(job, todo, chunk, progress, robot) as bar:
        if scheduler is None:
            for i in todo:
                results.append(_run_chunk(job, i, chunk, target))
                bar.update(_rows(job, chunk, i))
        else:
            client = _client(scheduler)
            try:
                from dask.distributed import as_completed

                scattered = client.scatter(job, broadcast=True)
                futures = {
                    i: client.submit(_run_chunk, scattered, i, chunk, target, pure=False)
                    for i in todo
                }
                rows = {futures[i].key: _rows(job, chunk, i) for i in todo}
                for future in as_completed(list(futures.values())):
                    results.append(future.result())
                    bar.update(rows[future.key])
            finally:
                cluster = client.cluster
                client.close()
                if scheduler == "processes" and cluster is not None:
                    cluster.close()
    import pandas as pd

    frames = [r for r in results if isinstance(r, pd.DataFrame)]
    if not frames:
        return pd.DataFrame()
    return pd.concat(frames).sort_values("configuration").reset_index(drop=True)
