"""Section (s): a grid study at the loader's largest size, wall time and memory (issue 33).

The study file's loader accepts up to 10^7 configurations (``MAX_STUDY_CONFIGURATIONS``).
Each count runs ``polyell study FILE --out DIR`` in a fresh process: the planar 3R arm of
Chiacchio (2000) (``[robot] library = "chiacchio2000"``) over a ``[grid]`` of (q2, q3)
with q1 = pi/2, every other key at its default (acceleration capacity, the MVIE and the
outer ellipsoid, 360 directions, chunks of 20,000 configurations, ``[output] csv =
"auto"``, the summary tables; no maps nor histograms, which are opt-in).  The whole
command is measured: the interpreter, the imports, the sweep (Pinocchio-free planar
dynamics and every score), the Parquet parts, the streamed summary and the outputs.

Memory: the peak resident set of the study's process (``ru_maxrss`` of that child, by
``os.wait4``), and its resident set sampled every few seconds from ``/proc`` against the
rows written so far (the Parquet parts in ``results/``): bounded by the chunk, the
samples after the first tenth of the rows stay at the level of the first tenth.  After
each run: the dataset read back with ``pandas.read_parquet`` (one column of every part,
and one part whole), whether ``results.csv`` was written and the manifest's note.

Run alone with ``python tests/benchmarks/run_benchmarks.py --sections scale --memory``
(about 40 minutes on one core of the benchmark machine), or ``python
tests/benchmarks/scale_bench.py [COUNT ...]`` to print the section for other counts.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

__all__ = ["SECTIONS", "bench_scale", "measure"]

#: The counts of the section: 10^6 for comparison, and the loader's limit.
COUNTS = (1_000_000, 10_000_000)
#: Seconds between two samples of the study's resident set.
SAMPLE_SECONDS = 2.0

STUDY = """\
title = "Scale: {count:,} configurations"
description = "A grid study at the defaults (tests/benchmarks/scale_bench.py)."

[robot]
library = "chiacchio2000"

[grid]
q1 = "pi/2"
q2 = {{ start = "-pi", stop = "pi", num = {rows} }}
q3 = {{ start = "-pi", stop = "pi", num = {columns} }}
"""


def grid_shape(count: int) -> tuple[int, int]:
    """Two grid sizes whose product is ``count`` (as square as divisors allow)."""
    rows = math.isqrt(count)
    while count % rows:
        rows -= 1
    return rows, count // rows


def _rss_kib(pid: int) -> int | None:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        return None
    return None


def _rows_written(results: Path, chunk: int) -> int:
    return chunk * len(list(results.glob("part-*.parquet"))) if results.exists() else 0


def measure(count: int, folder: Path, chunk: int = 20_000) -> dict:
    """Run the study of ``count`` configurations in ``folder``; its time, memory, outputs."""
    rows, columns = grid_shape(count)
    spec = folder / f"scale_{count}.toml"
    spec.write_text(STUDY.format(count=count, rows=rows, columns=columns))
    out = folder / f"out_{count}"
    polyell = str(Path(sys.executable).parent / "polyell")
    start = time.perf_counter()
    process = subprocess.Popen(
        [polyell, "study", str(spec), "--out", str(out), "--quiet"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    samples: list[tuple[float, int, int]] = []  # (seconds, rows written, RSS KiB)
    while True:
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
        if pid:
            break
        rss = _rss_kib(process.pid)
        if rss is not None:
            written = _rows_written(out / "results", chunk)
            samples.append((time.perf_counter() - start, written, rss))
        time.sleep(SAMPLE_SECONDS)
    seconds = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    errors = process.stderr.read().decode() if process.stderr else ""
    if process.returncode:
        raise RuntimeError(f"polyell study failed ({process.returncode}): {errors}")
    manifest = json.loads((out / "manifest.json").read_text())
    return {
        "count": count,
        "grid": (rows, columns),
        "seconds": seconds,
        "peak_kib": usage.ru_maxrss,
        "samples": samples,
        "manifest": manifest,
        **_read_back(out, count),
    }


def _read_back(out: Path, count: int) -> dict:
    """The dataset read with pandas, and the CSV's fate."""
    import pandas as pd

    results = out / "results"
    parts = sorted(results.glob("part-*.parquet"))
    ids = pd.read_parquet(results, columns=["configuration"])["configuration"].to_numpy()
    whole = pd.read_parquet(parts[-1])
    return {
        "parts": len(parts),
        "rows_read": len(ids),
        "distinct": len(np.unique(ids)),
        "part_rows": len(whole),
        "part_columns": whole.shape[1],
        "dataset_bytes": sum(p.stat().st_size for p in parts),
        "csv": (out / "results.csv").exists(),
    }


def phases(samples: list[tuple[float, int, int]], count: int) -> dict[str, float]:
    """RSS (MiB) while the sweep wrote its parts, and after its last part (the outputs).

    ``first``: the largest while the first tenth of the rows was written; ``median`` and
    ``max``: over the sweep after that tenth; ``after``: the largest once every part was
    written (the summary's passes over the parts, the manifest's notes).
    """
    early = [rss for _, rows, rss in samples if 0 < rows <= count / 10]
    late = [rss for _, rows, rss in samples if count / 10 < rows < count] or early
    after = [rss for _, rows, rss in samples if rows >= count]
    return {
        "first": max(early, default=0) / 1024,
        "median": float(np.median(late)) / 1024 if late else float("nan"),
        "max": max(late, default=0) / 1024,
        "after": max(after, default=0) / 1024,
    }


def section(results: list[dict]) -> list[str]:
    table = []
    notes = []
    for r in results:
        rss = phases(r["samples"], r["count"])
        rows, columns = r["grid"]
        sweep = r["manifest"]["seconds"].get("sweep", float("nan"))
        rate = r["count"] / sweep
        table.append(
            f"| {r['count']:,} ({rows:,} × {columns:,}) | {r['seconds'] / 60:.1f} min | "
            f"{sweep / 60:.1f} min ({rate:,.0f} /s) | {rss['first']:.0f} MiB | "
            f"{rss['median']:.0f} MiB | {rss['max']:.0f} MiB | {rss['after']:.0f} MiB | "
            f"{r['peak_kib'] / 1024:.0f} MiB | "
            f"{r['dataset_bytes'] / 2**30:.2f} GiB, {r['parts']:,} parts | "
            f"{'written' if r['csv'] else 'not written'} |"
        )
        note = next(iter(r["manifest"].get("notes", [])), "")
        notes.append(
            f"{r['count']:,}: `pandas.read_parquet` read {r['rows_read']:,} rows "
            f"({r['distinct']:,} distinct configurations) of `results/`, and its last part "
            f"whole ({r['part_rows']:,} rows, {r['part_columns']} columns)"
            + (f'; the manifest: "{note}"' if not r["csv"] else "")
            + "."
        )
    first, last = results[0], results[-1]
    a, b = phases(first["samples"], first["count"]), phases(last["samples"], last["count"])
    fold = last["count"] // first["count"]
    return [
        "## (s) A grid study at the loader's limit, 10⁷ configurations",
        "",
        "From `python tests/benchmarks/run_benchmarks.py --sections scale --memory` "
        "(`tests/benchmarks/scale_bench.py`): `polyell study FILE --out DIR` in a fresh "
        "process, one run per count, the planar 3R arm of Chiacchio (2000) "
        '(`library = "chiacchio2000"`) over a `[grid]` of (q2, q3) in [-π, π]² with '
        "q1 = π/2, every other key at its default: the acceleration capacity, the MVIE and "
        'the outer ellipsoid, 360 directions, chunks of 20,000, `[output] csv = "auto"`, '
        "the summary tables (maps and histograms are opt-in: none). Time: the whole "
        "command (interpreter, imports, sweep, Parquet parts, the streamed summary) and the "
        "sweep as the manifest gives it (`seconds.sweep`). Memory: the resident set of the "
        f"study's process sampled every {SAMPLE_SECONDS:.0f} s from `/proc` against the rows "
        "written so far: the largest while the first tenth of the rows was written, the "
        "median and the largest over the rest of the sweep, the largest after its last "
        "part (the summary's passes over the parts and the manifest); and the peak of the "
        "whole process (`ru_maxrss`, by `os.wait4`).",
        "",
        "| configurations (grid) | command | sweep | RSS, first tenth | sweep after, median "
        "| sweep after, max | after the sweep | peak RSS | dataset | results.csv |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *table,
        "",
        *(line for note in notes for line in (note, "")),
        f"While the sweep runs, memory is bounded by the chunk: {a['median']:.0f} and "
        f"{b['median']:.0f} MiB (median; at most {a['max']:.0f} and {b['max']:.0f} MiB) "
        f"over a {fold}-fold range of configurations. "
        + (
            f"After it, the peak grows with the count ({a['after']:.0f} MiB at "
            f"{first['count']:,}, {b['after']:.0f} MiB at {last['count']:,}), as a read of "
            "one whole column of the dataset does: `pd.read_parquet(folder, "
            "columns=[PER_ROW])` after the sweep (`polyell/studies/sweep.py`) and in "
            "`_per_row_notes` (`polyell/studies/runner.py`) peaks at +184 MiB over a "
            "fresh process's baseline on 500 parts of 20,000 rows, +40 MiB on 50 (measured "
            "apart, issue 33). Both now count the parts one at a time "
            "(`per_row_note(folder)`); a rerun of this section measures that."
            if b["after"] > 1.2 * a["after"]
            else f"After it too: {a['after']:.0f} and {b['after']:.0f} MiB."
        )
        + " The machine was shared with other jobs: the rates vary from run to run.",
        "",
    ]


def bench_scale(repeats: int, counts: tuple[int, ...] = COUNTS) -> list[str]:
    """(s) The study of 10^6 and 10^7 configurations (one run each: ``repeats`` unused)."""
    del repeats
    folder = Path(tempfile.mkdtemp(prefix="polyell-scale-"))
    try:
        results = []
        record = os.environ.get("SCALE_BENCH_RECORD")
        for count in counts:
            results.append(measure(count, folder))
            print(f"scale: {count:,} done ({results[-1]['seconds']:.0f} s)", file=sys.stderr)
            shutil.rmtree(folder / f"out_{count}")  # 10^7 rows are ~4 GB of Parquet
            if record:  # the raw measurements so far, samples included
                Path(record).write_text(json.dumps(results, indent=1, default=str))
        return section(results)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


SECTIONS = {"scale": bench_scale}


if __name__ == "__main__":
    chosen = tuple(int(c) for c in sys.argv[1:]) or COUNTS
    print("\n".join(bench_scale(1, chosen)))
