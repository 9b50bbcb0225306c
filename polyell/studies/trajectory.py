"""Trajectories from files: configurations (and velocities, time) a user already has.

A trajectory file holds one row per sample with the columns ``q1 .. qn`` (joint angles,
rad), optionally ``qd1 .. qdn`` (joint velocities, rad/s) and ``t`` (time, s, strictly
increasing).  Formats: CSV (a header row), Parquet, NumPy ``.npy`` (an array (K, n) of
joint angles) or ``.npz`` (arrays ``q``, and optionally ``qd`` and ``t``).  A
:class:`Trajectory` is a configuration set: :func:`polyell.sweep` takes it like a grid.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polyell.errors import InputError
from polyell.studies.along import limits_along
from polyell.studies.configurations import ConfigurationSet
from polyell.validation import source_torque_limits

__all__ = ["Trajectory", "load_trajectory", "tangent_limits"]

#: Most samples of a trajectory file (they are held in memory).
MAX_SAMPLES = 10_000_000


class Trajectory(ConfigurationSet):
    """Samples of a path: joint angles, and optionally velocities and time.

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


def _columns(source: str, table: dict[str, NDArray[np.float64]], n: int) -> Trajectory:
    """Check the named columns of a table and build the trajectory."""
    names = list(table)
    q_names = [f"q{i + 1}" for i in range(n)]
    missing = [name for name in q_names if name not in table]
    if missing:
        raise InputError(
            source,
            f"columns {q_names[0]}..{q_names[-1]} (joint angles) for the robot's {n} joints",
            f"columns {names}, without {missing}",
            "name the columns q1..qn (and qd1..qdn, t if you have them).",
        )
    extra = sorted(
        {name for name in names if name.startswith("q") and name[1:].isdigit()} - set(q_names)
    )
    if extra:
        raise InputError(
            source, f"{n} joint-angle columns for this robot", f"also {extra}", "check the robot."
        )
    qd_names = [f"qd{i + 1}" for i in range(n)]
    has_qd = [name in table for name in qd_names]
    if any(has_qd) and not all(has_qd):
        raise InputError(
            source,
            f"all of {qd_names[0]}..{qd_names[-1]} or none",
            f"only {[n for n, h in zip(qd_names, has_qd, strict=True) if h]}",
        )
    chosen = q_names + (qd_names if all(has_qd) else []) + (["t"] if "t" in table else [])
    samples = len(np.asarray(table[q_names[0]]))
    if not 1 <= samples <= MAX_SAMPLES:
        raise InputError(source, f"1 to {MAX_SAMPLES:,} samples", f"{samples}")
    for name in chosen:
        column = np.asarray(table[name])
        if not np.issubdtype(column.dtype, np.number) or np.iscomplexobj(column):
            raise InputError(source, f"real numbers in column {name}", f"{column.dtype} values")
        bad = np.flatnonzero(~np.isfinite(column.astype(float)))
        if bad.size:
            raise InputError(
                source,
                "finite numbers in every row",
                f"{column[bad[0]]} at row {int(bad[0])}, column {name}",
                "remove or fill the row.",
            )
    q = np.column_stack([np.asarray(table[name], dtype=float) for name in q_names])
    qd = (
        np.column_stack([np.asarray(table[name], dtype=float) for name in qd_names])
        if all(has_qd)
        else None
    )
    t = np.asarray(table["t"], dtype=float) if "t" in table else None
    if t is not None:
        steps = np.flatnonzero(np.diff(t) <= 0)
        if steps.size:
            k = int(steps[0]) + 1
            raise InputError(
                source,
                "strictly increasing time in column t",
                f"t = {t[k]} at row {k} after {t[k - 1]} at row {k - 1}",
                "sort the samples by time and drop duplicates.",
            )
    return Trajectory(q, qd, t, source)


def load_trajectory(path: str | Path, n: int) -> Trajectory:
    """Read a trajectory file for a robot of ``n`` joints.

    Parameters
    ----------
    path : str or Path
        A ``.csv``, ``.parquet``, ``.npy`` or ``.npz`` file (see the module's text).
    n : int
        The robot's number of joints.

    Returns
    -------
    Trajectory

    Raises
    ------
    InputError
        For a missing or unreadable file, missing columns, a wrong joint count, a
        non-finite value (naming its row and column) or time that does not increase
        (naming the row).
    """
    file = Path(path)
    source = file.name
    if not file.is_file():
        raise InputError("trajectory", "an existing file", repr(str(path)))
    suffix = file.suffix.lower()
    try:
        if suffix == ".csv":
            import pandas as pd

            frame = pd.read_csv(file)
            table = {str(name): frame[name].to_numpy() for name in frame.columns}
        elif suffix == ".parquet":
            import pandas as pd

            frame = pd.read_parquet(file)
            table = {str(name): frame[name].to_numpy() for name in frame.columns}
        elif suffix == ".npy":
            array = np.load(file, allow_pickle=False)
            if array.ndim != 2 or array.shape[1] != n:
                raise InputError(
                    source, f"an array of shape (K, {n}): joint angles", f"shape {array.shape}"
                )
            table = {f"q{i + 1}": array[:, i] for i in range(n)}
        elif suffix == ".npz":
            with np.load(file, allow_pickle=False) as arrays:
                if "q" not in arrays:
                    raise InputError(source, "an array 'q' (K, n)", f"arrays {sorted(arrays)}")
                q = arrays["q"]
                if q.ndim != 2 or q.shape[1] != n:
                    raise InputError(source, f"q of shape (K, {n})", f"shape {q.shape}")
                table = {f"q{i + 1}": q[:, i] for i in range(n)}
                if "qd" in arrays:
                    if arrays["qd"].shape != q.shape:
                        raise InputError(
                            source, f"qd of shape {q.shape}", f"shape {arrays['qd'].shape}"
                        )
                    table |= {f"qd{i + 1}": arrays["qd"][:, i] for i in range(n)}
                if "t" in arrays:
                    if arrays["t"].shape != (len(q),):
                        raise InputError(
                            source, f"t of shape ({len(q)},)", f"shape {arrays['t'].shape}"
                        )
                    table["t"] = arrays["t"]
        else:
            raise InputError("trajectory", "a .csv, .parquet, .npy or .npz file", repr(file.name))
    except (OSError, ValueError) as exn:
        if isinstance(exn, InputError):
            raise
        raise InputError(source, "a readable trajectory file", f"{exn}"[:200]) from None
    return _columns(source, table, n)


def tangent_limits(
    source: Any, trajectory: Trajectory, tau_max: Any = None, tau_min: Any = None
) -> dict[str, NDArray[np.float64]]:
    """The achievable accelerations along the path's tangent ``J q̇ / |J q̇|``, per sample.

    Parameters
    ----------
    source : robot
        Its dynamics give J at each sample.
    trajectory : Trajectory
        With velocities ``qd``.
    tau_max, tau_min : array-like, optional
        Torque limits; default the robot's own.

    Returns
    -------
    dict of str to ndarray (K,)
        ``tangent_<set>_lo`` and ``tangent_<set>_hi`` for the polytope and both
        ellipsoids (:func:`polyell.limits_along`); NaN where the task velocity is zero
        (no tangent) or the line misses the set.
    """
    if trajectory.qd is None:
        raise InputError(
            "trajectory", "joint velocities qd1..qdn for the tangent", f"{trajectory!r}"
        )
    dyn = source.dynamics(trajectory.q)
    velocity = np.einsum("kmn,kn->km", dyn.J, trajectory.qd)
    speed = np.linalg.norm(velocity, axis=1)
    moving = speed > 1e-12 * np.maximum(1.0, np.abs(velocity).max())
    T = np.where(moving[:, None], velocity / np.where(moving, speed, 1.0)[:, None], 0.0)
    T[~moving, 0] = 1.0  # a placeholder direction; its rows are NaN below
    upper, lower = source_torque_limits(source, tau_max, tau_min, dyn.n)
    limits = limits_along(dyn, None, T, upper, lower)
    columns = {}
    for name, (lo, hi) in limits.items():
        columns[f"tangent_{name}_lo"] = np.where(moving, lo, np.nan)
        columns[f"tangent_{name}_hi"] = np.where(moving, hi, np.nan)
    return columns
