r"""Regenerate the showcase: every figure, table and number of ``docs/showcase.md``.

One command, run from the repository's root (the Panda studies need the extra
``polyell[robots]``)::

    python -m polyell.showcase                       # every study, then the quoted numbers
    python -m polyell.showcase --only posture_paper  # some studies (the numbers of the others kept)

Each study of :data:`SHOWCASE_STUDIES` runs from ``studies/<name>.toml`` into
``docs/showcase/<name>/`` (as ``polyell study studies/<name>.toml --out
docs/showcase/<name>`` does), from scratch: a sweep's Parquet dataset (``results/``) is
removed before the run, so that nothing resumes from a dataset of older code, and after it
(``results.csv`` holds its rows).  Then the numbers that ``docs/showcase.md`` quotes are
read from the outputs (:func:`showcase_numbers`) and written into its generated paragraphs,
between ``<!-- showcase:<name> -->`` and ``<!-- /showcase:<name> -->``
(:func:`render_blocks`, :func:`update_document`).  ``tests/test_showcase.py`` runs the
studies again and fails when a number printed in ``docs/showcase.md`` no longer follows
from the code.
"""

from __future__ import annotations

import argparse
import math
import re
import shutil
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from polyell.errors import InputError, PolyellError

__all__ = [
    "BLOCK",
    "SHOWCASE_STUDIES",
    "ShowcaseStudy",
    "main",
    "render_blocks",
    "run_showcase",
    "showcase_numbers",
    "update_document",
]


@dataclass(frozen=True)
class ShowcaseStudy:
    """A study of the showcase: ``studies/<name>.toml``, written to ``<out>/<name>/``.

    Attributes
    ----------
    name : str
        The study file's stem and the output folder's name.
    robots : bool
        Whether it needs the extra ``polyell[robots]`` (Pinocchio, example-robot-data).
    """

    name: str
    robots: bool = False


#: The studies of ``docs/showcase.md``, in the order of the page.
SHOWCASE_STUDIES = (
    ShowcaseStudy("chiacchio2000"),
    ShowcaseStudy("planar3r_sweep"),
    ShowcaseStudy("panda_random", robots=True),
    ShowcaseStudy("panda_postures", robots=True),
    ShowcaseStudy("two_robots", robots=True),
    ShowcaseStudy("posture_paper"),
    ShowcaseStudy("posture_panda", robots=True),
    ShowcaseStudy("panda_horizon", robots=True),
)
_BY_NAME = {study.name: study for study in SHOWCASE_STUDIES}
#: A generated paragraph of the page: ``<!-- showcase:NAME -->`` ... ``<!-- /showcase:NAME -->``.
BLOCK = re.compile(
    r"(<!-- showcase:(?P<name>[a-z0-9_]+) -->\n)(?P<text>.*?)(\n<!-- /showcase:(?P=name) -->)",
    re.S,
)


def _names(only: Sequence[str] | None) -> list[ShowcaseStudy]:
    """The studies of ``only`` (all of them: None), checked."""
    if only is None:
        return list(SHOWCASE_STUDIES)
    if isinstance(only, str) or not all(isinstance(name, str) for name in only):
        raise InputError(
            "only",
            "a list of showcase study names",
            repr(only)[:80],
            f"pass a list of names, e.g. only=[{SHOWCASE_STUDIES[0].name!r}]",
        )
    unknown = [name for name in only if name not in _BY_NAME]
    if unknown:
        raise InputError(
            "only",
            f"names among {list(_BY_NAME)}",
            repr(unknown)[:120],
            "pass the stems of the study files the showcase runs.",
        )
    return [study for study in SHOWCASE_STUDIES if study.name in only]


def _remove_datasets(folder: Path) -> None:
    """Remove a study folder's sweep datasets (``results/``, ``results_force/``)."""
    for path in folder.glob("results*"):
        if path.is_dir():
            shutil.rmtree(path)


def run_showcase(
    out: str | Path,
    studies: str | Path = "studies",
    *,
    only: Sequence[str] | None = None,
    progress: bool = False,
) -> dict[str, Path]:
    """Run the showcase's studies, each from scratch into ``out/<name>/``.

    Parameters
    ----------
    out : str or Path
        The showcase folder (``docs/showcase``).
    studies : str or Path, optional
        The folder of the study files (``studies`` of the repository).
    only : sequence of str, optional
        Names of :data:`SHOWCASE_STUDIES` to run; default all.
    progress : bool, optional
        Progress bars of the sweeps on standard error.

    Returns
    -------
    dict of str to Path
        Each study's output folder, by name.

    Raises
    ------
    InputError
        If ``only`` names an unknown study, or a study file is missing (naming ``studies``).
    MissingDependencyError
        If a Panda study runs without the extra ``polyell[robots]``.
    """
    from polyell.studies import load_study, run_study

    chosen = _names(only)
    folder = Path(studies)
    missing = [s.name for s in chosen if not (folder / f"{s.name}.toml").is_file()]
    if missing:
        raise InputError(
            "studies",
            "the folder of the showcase's study files",
            f"{folder} without {', '.join(f'{n}.toml' for n in missing)}",
            "run from the repository's root, or pass --studies path/to/studies.",
        )
    written: dict[str, Path] = {}
    for study in chosen:
        target = Path(out) / study.name
        _remove_datasets(target)  # a fresh sweep: nothing resumed from older code
        run_study(load_study(folder / f"{study.name}.toml"), target, progress=progress)
        _remove_datasets(target)  # results.csv holds the rows
        written[study.name] = target
    return written


def _posture_numbers(folder: Path, prefix: str) -> dict[str, float]:
    """What the page quotes of a posture study: postures, regret and rho along its direction.

    Besides the choice table's numbers, the regret of the classic ellipsoid's pick on the
    first component of the self-motion alone (q0's elbow branch), from the values of
    every posture (``posture_values.csv``).
    """
    import pandas as pd

    table = pd.read_csv(folder / "posture_choice.csv", index_col=["kind", "criterion"])
    values = pd.read_csv(folder / "posture_values.csv", index_col="posture")
    sizes = values.groupby("component").size()
    numbers: dict[str, float] = {
        f"{prefix}.postures": int(sizes.iloc[0]),
        f"{prefix}.components": int(sizes.size),
        f"{prefix}.all_postures": int(sizes.sum()),
    }
    for kind in ("chiacchio", "yoshikawa"):
        record = table.loc[(kind, "limit")]
        numbers[f"{prefix}.{kind}.regret"] = 100.0 * float(record["regret"])
        numbers[f"{prefix}.{kind}.spearman"] = float(record["spearman"])
    first = values[values["component"] == sizes.index[0]]
    truth = first["polytope_limit"].to_numpy(dtype=float)
    pick = int(first["yoshikawa_limit"].to_numpy(dtype=float).argmax())
    numbers[f"{prefix}.yoshikawa.regret_first"] = 100.0 * (1.0 - truth[pick] / truth.max())
    return numbers


def showcase_numbers(out: str | Path) -> dict[str, float]:
    """The numbers ``docs/showcase.md`` quotes, read from the outputs in ``out``.

    Only of the studies whose outputs are there (a study not run gives none).

    Returns
    -------
    dict of str to float
        ``planar3r_sweep.q2``, ``planar3r_sweep.q3`` (grid values per axis),
        ``panda_random.configurations``, and of each posture study (``posture_paper``,
        ``posture_panda``): ``postures`` (on q0's component), ``components``,
        ``chiacchio.regret`` and ``yoshikawa.regret`` (percent, along the study's
        direction), their ``spearman``, and ``yoshikawa.regret_first`` (the classic
        ellipsoid's pick on q0's component alone).
    """
    import pandas as pd

    out = Path(out)
    numbers: dict[str, float] = {}
    sweep = out / "planar3r_sweep" / "results.csv"
    if sweep.is_file():
        grid = pd.read_csv(sweep, usecols=["q2", "q3"])
        numbers["planar3r_sweep.q2"] = int(grid["q2"].nunique())
        numbers["planar3r_sweep.q3"] = int(grid["q3"].nunique())
    random = out / "panda_random" / "results.csv"
    if random.is_file():
        numbers["panda_random.configurations"] = len(pd.read_csv(random, usecols=["q1"]))
    for name in ("posture_paper", "posture_panda"):
        if (out / name / "posture_choice.csv").is_file():
            numbers |= _posture_numbers(out / name, name)
    if (out / "panda_horizon" / "results.csv").is_file():
        numbers |= _horizon_numbers(out / "panda_horizon" / "results.csv")
    return numbers


def _horizon_numbers(results: Path) -> dict[str, float]:
    """What the page quotes of the Panda approaching its elbow limit (``panda_horizon``).

    The set's volume at the last sample against the first, and against the set at the
    same state without the horizon (recomputed here); each ellipsoid's overreach (the
    share of it beyond the set) at the first and the last sample.
    """
    import pandas as pd

    from polyell import robots
    from polyell.models import UrdfRobot

    frame = pd.read_csv(results)
    first, last = frame.iloc[0], frame.iloc[-1]
    q = last[[f"q{i}" for i in range(1, 8)]].to_numpy(dtype=float)
    path = pd.read_csv(Path(__file__).parents[1] / "studies" / "panda_horizon_path.csv")
    qd = path.iloc[-1][[f"qd{i}" for i in range(1, 8)]].to_numpy(dtype=float)
    panda = robots.load("panda")
    assert isinstance(panda, UrdfRobot)
    unlimited = panda.analyze(q, qd).polytope.volume
    numbers = {
        "panda_horizon.samples": float(len(frame)),
        "panda_horizon.volume_change": 100.0
        * (last["polytope_volume"] / first["polytope_volume"] - 1),
        "panda_horizon.volume_share": 100.0 * last["polytope_volume"] / unlimited,
    }
    for kind in ("chiacchio", "yoshikawa"):
        numbers[f"panda_horizon.{kind}.first"] = 100.0 * first[f"{kind}_overreach"]
        numbers[f"panda_horizon.{kind}.last"] = 100.0 * last[f"{kind}_overreach"]
    return numbers


def _percent(value: float) -> str:
    """A share in percent as the page prints it: two significant digits, "nothing" for 0."""
    if abs(value) < 5e-3:
        return "nothing"
    digits = 1 if abs(value) < 10 else 0
    return f"{value:.{digits}f} %"


def _count(value: float) -> str:
    """A small count in words ("two"), a larger one in digits."""
    words = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five"}
    return words.get(int(value), f"{value:.0f}")


def _rho(value: float) -> str:
    """A rank correlation as the page prints it, two decimals and a minus sign."""
    return f"{value:.2f}"


def render_blocks(numbers: Mapping[str, float]) -> dict[str, str]:
    """The generated paragraphs of ``docs/showcase.md`` for these numbers, by block name.

    A block whose numbers are missing (its study not run) is left out.
    """
    blocks: dict[str, str] = {}
    n = numbers
    if "planar3r_sweep.q2" in n:
        blocks["planar3r_sweep"] = (
            "[`summary.md`](showcase/planar3r_sweep/summary.md) (also `.tex`, `.csv`) "
            f"summarises the\nscores over {n['planar3r_sweep.q2']:.0f} \u00d7 "
            f"{n['planar3r_sweep.q3']:.0f} configurations; "
            "[`results.csv`](showcase/planar3r_sweep/results.csv)\n"
            "holds one row per configuration."
        )
    if "panda_random.configurations" in n:
        blocks["panda_random"] = (
            f"{n['panda_random.configurations']:.0f} seeded random configurations within the "
            "URDF's joint limits, fingers locked, linear\ntask at `panda_hand_tcp`, torque "
            "limits from the URDF's effort limits:\n"
            "[`summary.md`](showcase/panda_random/summary.md) (also `.tex`, `.csv`),\n"
            "[`results.csv`](showcase/panda_random/results.csv)."
        )
    if "posture_paper.postures" in n and "posture_panda.postures" in n:
        p, q = "posture_paper", "posture_panda"
        blocks["posture"] = "\n".join(
            [
                "`studies/posture_paper.toml`: the paper's arm at its redundant point, whose "
                "self-motion has",
                f"{_count(n[p + '.components'])} components (the elbow branches), "
                f"{n[p + '.postures']:.0f} postures on each; every index picks the posture it",
                "rates best and the polytope says what that pick is worth",
                "([`posture_choice.md`](showcase/posture_paper/posture_choice.md), also "
                "`.tex`, `.csv`;",
                "every posture in `posture_values.csv`). Along x, picking by the classic ellipsoid",
                f"(eq. 27) loses {_percent(n[p + '.yoshikawa.regret'])} of the acceleration "
                "available both ways (Spearman's rho with the",
                f"truth {_rho(n[p + '.yoshikawa.spearman'])}), by the new ellipsoid (eq. 32/38) "
                f"{_percent(n[p + '.chiacchio.regret'])} (rho "
                f"{_rho(n[p + '.chiacchio.spearman'])}); q0's branch",
                f"alone would give {_percent(n[p + '.yoshikawa.regret_first'])} for the "
                "classic one.",
                f"`studies/posture_panda.toml` ({n[q + '.postures']:.0f} postures of the "
                "Panda's 4-D self-motion):",
                "[`posture_choice.md`](showcase/posture_panda/posture_choice.md) — along x "
                "the Yoshikawa",
                f"ellipsoid's pick loses {_percent(n[q + '.yoshikawa.regret'])} (rho "
                f"{_rho(n[q + '.yoshikawa.spearman'])}), the Chiacchio ellipsoid's "
                f"{_percent(n[q + '.chiacchio.regret'])} (rho "
                f"{_rho(n[q + '.chiacchio.spearman'])}).",
            ]
        )
    if "panda_horizon.samples" in n:
        h = "panda_horizon"
        blocks[h] = "\n".join(
            [
                f"{n[h + '.samples']:.0f} samples, 10 ms apart: at the limit the set within "
                "the joint limits over the next 20 ms",
                f"holds {_percent(n[h + '.volume_share'])} of the volume of the torque-limited "
                f"set at the same state, and {_percent(abs(n[h + '.volume_change']))} "
                f"{'less' if n[h + '.volume_change'] < 0 else 'more'} than at the start of the "
                "path. The classic ellipsoid's",
                f"overreach (its share beyond the set) grows from "
                f"{_percent(n[h + '.yoshikawa.first'])} to "
                f"{_percent(n[h + '.yoshikawa.last'])}, the new ellipsoid's",
                f"from {_percent(n[h + '.chiacchio.first'])} to "
                f"{_percent(n[h + '.chiacchio.last'])}: neither knows the joint limits",
                "([`summary.md`](showcase/panda_horizon/summary.md), every sample in "
                "[`results.csv`](showcase/panda_horizon/results.csv)).",
            ]
        )
    return blocks


def _check_document(path: Path) -> None:
    """Refuse a showcase page that is not a file (before any study runs)."""
    if not path.is_file():
        raise InputError(
            "document",
            "the showcase page, a Markdown file",
            f"{path} (not a file)",
            "run from the repository's root, or pass --document docs/showcase.md.",
        )


def update_document(document: str | Path, blocks: Mapping[str, str]) -> list[str]:
    """Write ``blocks`` into their generated paragraphs of ``document`` (``docs/showcase.md``).

    Returns
    -------
    list of str
        The names of the blocks whose text changed.

    Raises
    ------
    InputError
        If ``document`` is not a file, or a block of ``blocks`` has no
        ``<!-- showcase:NAME -->`` markers in it.
    """
    from polyell.storage import write_text_atomically

    path = Path(document)
    _check_document(path)
    text = path.read_text(encoding="utf-8")
    found = {match["name"] for match in BLOCK.finditer(text)}
    missing = sorted(set(blocks) - found)
    if missing:
        raise InputError(
            "document",
            "a page with the markers <!-- showcase:NAME --> ... <!-- /showcase:NAME -->",
            f"{path} without {missing}",
            "put the markers around the paragraph the block replaces.",
        )
    changed: list[str] = []

    def replace(match: re.Match[str]) -> str:
        name = match["name"]
        if name not in blocks or blocks[name] == match["text"]:
            return match.group(0)
        changed.append(name)
        return f"{match.group(1)}{blocks[name]}{match.group(4)}"

    new = BLOCK.sub(replace, text)
    if new != text:
        write_text_atomically(path, new)
    return changed


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m polyell.showcase``: run the studies, then update the quoted numbers."""
    parser = argparse.ArgumentParser(
        prog="python -m polyell.showcase",
        description="Regenerate docs/showcase/ and the numbers docs/showcase.md quotes "
        "(run from the repository's root).",
    )
    parser.add_argument("--studies", default="studies", help="folder of the study files")
    parser.add_argument("--out", default="docs/showcase", help="the showcase's folder")
    parser.add_argument("--document", default="docs/showcase.md", help="the showcase page")
    parser.add_argument(
        "--only", nargs="+", metavar="NAME", help=f"some of {[s.name for s in SHOWCASE_STUDIES]}"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    args = parser.parse_args(argv)
    try:
        _check_document(Path(args.document))
        folders = run_showcase(args.out, args.studies, only=args.only, progress=not args.quiet)
        for name, folder in folders.items():
            print(f"{name}: {folder}")
        numbers = showcase_numbers(args.out)
        changed = update_document(args.document, render_blocks(numbers))
    except PolyellError as exn:
        print(f"error: {exn}", file=sys.stderr)
        return 2
    for name in sorted(numbers):
        value = numbers[name]
        shown = f"{value:.6g}" if not math.isnan(value) else "nan"
        print(f"  {name} = {shown}")
    said = ", ".join(changed) if changed else "none changed"
    print(f"{args.document}: generated paragraphs updated ({said})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
