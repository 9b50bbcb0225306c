"""The showcase follows from the code (issue 33): ``python -m polyell.showcase`` makes it all.

Every study of the showcase is run again here, from scratch, into a temporary folder (by
the shipped command's own function, :func:`polyell.showcase.run_showcase`); the Panda
studies need the extra ``polyell[robots]`` and are left out without it (said in the skip
reason).  Every study takes a few seconds (about 45 s for all seven on one core), so none
is left to an opt-in variable.  Then:

* every number ``docs/showcase.md`` prints in its generated paragraphs equals the one the
  fresh outputs give (:func:`polyell.showcase.render_blocks`), the text around it
  unchanged.  Tolerance: a number printed with a decimal point, or followed by ``%``, may
  differ by one unit in its last printed digit (a value on a rounding boundary, another
  BLAS); every other number (counts, grid sizes) must be equal;
* the numbers of the prose (the configurations, the direction counts, the replicates,
  U1 of the singular configuration) follow from the fresh outputs and the library;
* every figure and table the page links is written by the fresh run, and is shipped.
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import inspect
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from polyell.comparison.caps import cap_union_share
from polyell.comparison.labels import set_label
from polyell.geometry.directions import default_direction_count
from polyell.showcase import (
    BLOCK,
    SHOWCASE_STUDIES,
    render_blocks,
    run_showcase,
    showcase_numbers,
    update_document,
)
from polyell.studies import load_study

REPO = Path(__file__).resolve().parents[1]
DOCUMENT = REPO / "docs" / "showcase.md"
#: A number of the page's text: digits, an optional sign and decimals.
NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?")
#: A file of a study's folder that the page links (a figure, a table, a toctree entry).
LINKED = re.compile(r"showcase/(?P<study>[a-z0-9_]+)/(?P<file>[A-Za-z0-9_.-]+\.[a-z]+)")


def _robots() -> bool:
    """Whether the extra polyell[robots] is installed (Pinocchio, example-robot-data)."""
    try:
        importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return False
    return importlib.util.find_spec("pinocchio") is not None


@pytest.fixture(scope="module")
def fresh(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Every showcase study run again (the Panda's with the robots extra only)."""
    out = tmp_path_factory.mktemp("showcase")
    only = [study.name for study in SHOWCASE_STUDIES if _robots() or not study.robots]
    run_showcase(out, REPO / "studies", only=only)
    return out


def _blocks(text: str) -> dict[str, str]:
    return {match["name"]: match["text"] for match in BLOCK.finditer(text)}


def _tolerance(text: str, match: re.Match[str]) -> float:
    """One unit in the last printed digit of a rounded number, else 0 (a count)."""
    token = match.group(0)
    rounded = "." in token or text[match.end() :].startswith(" %")
    if not rounded:
        return 0.0
    decimals = len(token.split(".")[1]) if "." in token else 0
    return 10.0**-decimals


def _assert_same_numbers(name: str, printed: str, expected: str) -> None:
    """The page's paragraph ``printed`` says what the fresh one ``expected`` says."""
    assert NUMBER.split(printed) == NUMBER.split(expected), (
        f"the text of the generated paragraph {name!r} differs from what "
        "python -m polyell.showcase writes: regenerate the showcase"
    )
    found = list(NUMBER.finditer(printed))
    fresh = [float(m.group(0)) for m in NUMBER.finditer(expected)]
    for match, value in zip(found, fresh, strict=True):
        quoted, tolerance = float(match.group(0)), _tolerance(printed, match)
        assert abs(quoted - value) <= tolerance + 1e-12, (
            f"{name}: docs/showcase.md prints {match.group(0)}, the code now gives {value} "
            f"(tolerance {tolerance:g}): regenerate with python -m polyell.showcase"
        )


def test_every_generated_number_follows_from_the_code(fresh):
    printed = _blocks(DOCUMENT.read_text(encoding="utf-8"))
    expected = render_blocks(showcase_numbers(fresh))
    wanted = {"planar3r_sweep"} | ({"panda_random", "posture"} if _robots() else set())
    assert wanted <= set(expected)
    assert set(expected) <= set(printed), "a generated paragraph lost its markers"
    for name, text in expected.items():
        _assert_same_numbers(name, printed[name], text)


def test_the_tolerance_catches_a_stale_number(fresh, tmp_path):
    """The check fails on the drift issue 33 found (rho -0.22 printed, -0.24 computed)."""
    expected = render_blocks(showcase_numbers(fresh))
    name, text = next(iter(expected.items()))
    numbers = list(NUMBER.finditer(text))
    last = numbers[-1]
    token = last.group(0)
    unit = 10.0 ** -(len(token.split(".")[1]) if "." in token else 0)
    shifted = f"{float(token) + 2 * unit:.{len(token.split('.')[1]) if '.' in token else 0}f}"
    stale = text[: last.start()] + shifted + text[last.end() :]
    with pytest.raises(AssertionError, match="regenerate"):
        _assert_same_numbers(name, stale, text)
    # the command writes the fresh paragraphs into a page: then it agrees
    page = tmp_path / "showcase.md"
    page.write_text(DOCUMENT.read_text(encoding="utf-8"))
    update_document(page, {name: stale})
    assert _blocks(page.read_text())[name] == stale
    update_document(page, expected)
    for block, fresh_text in expected.items():
        _assert_same_numbers(block, _blocks(page.read_text())[block], fresh_text)


def test_the_prose_numbers_follow_from_the_code(fresh):
    text = DOCUMENT.read_text(encoding="utf-8")
    # the direction sets of the scores' table and the coverage's replicates
    directions = re.search(
        r"\((\d+) evenly spaced in 2-D, a (\d+)-point Fibonacci lattice in 3-D "
        r"\(([\d,]+) in the Panda study",
        text,
    )
    assert directions is not None
    two, three, panda = (int(v.replace(",", "")) for v in directions.groups())
    assert (two, three) == (default_direction_count(2), default_direction_count(3))
    assert panda == load_study(REPO / "studies" / "panda_random.toml").file.compare.directions
    replicates = re.search(r"(\d+) seeded replicates", text)
    assert replicates is not None
    default = inspect.signature(cap_union_share).parameters["replicates"].default
    assert int(replicates.group(1)) == default
    # the paper's configurations and U1 = (-1/2, sqrt(3)/2) of the singular one
    assert "Figure 1: q = (π/2, −π/2, −π/2)" in text  # noqa: RUF001
    assert "Figure 2: q = (π/6, 0, 0)" in text
    numbers = (fresh / "chiacchio2000" / "numbers.md").read_text()
    assert "q = (1.5708, -1.5708, -1.5708) rad" in numbers and "q = (0.523599, 0, 0) rad" in numbers
    singular = numbers.split("## singular")[1]
    rows = singular.split("vertices [m/s^2]:")[1].split("]]")[0]
    vertices = np.array([[float(v) for v in NUMBER.findall(row)] for row in rows.splitlines()[1:]])
    along = vertices[1] - vertices[0]
    along *= np.sign(along[1]) / np.linalg.norm(along)
    assert "U₁ = (−1/2, √3/2)" in text  # noqa: RUF001
    np.testing.assert_allclose(along, [-0.5, np.sqrt(3) / 2], atol=1e-4)  # 5 printed digits
    scores = pd.read_csv(fresh / "chiacchio2000" / "scores.csv", index_col="ellipsoid")
    preset = "chiacchio2000"
    for kind in ("chiacchio", "mvie"):  # segments there, and the classic one undefined
        assert scores.loc[f"singular: {set_label(kind, labels=preset)}", "dimension"] == 1
    assert not scores.loc[f"singular: {set_label('yoshikawa', labels=preset)}", "defined"]


def test_every_linked_figure_and_table_is_written_and_shipped(fresh):
    text = DOCUMENT.read_text(encoding="utf-8")
    linked = {(m["study"], m["file"]) for m in LINKED.finditer(text)}
    toctree = re.search(r"```\{toctree\}\n(.*?)```", text, re.S)
    assert toctree is not None
    for line in toctree.group(1).splitlines():
        if line.startswith("showcase/"):
            study, stem = line.split("/")[1:]
            linked.add((study, f"{stem}.md"))
    studies = {study.name for study in SHOWCASE_STUDIES}
    assert {study for study, _ in linked} == studies  # every study shown, none unknown
    for study, name in sorted(linked):
        assert (REPO / "docs" / "showcase" / study / name).is_file(), (study, name)
        if (fresh / study).is_dir():
            assert (fresh / study / name).is_file(), f"{study}/{name} is no longer written"
    # the shipped outputs are those of one run of the command: their manifests list them
    for study in studies:
        shipped = REPO / "docs" / "showcase" / study / "manifest.json"
        assert shipped.is_file(), study
        if (fresh / study).is_dir():
            files = pd.read_json(fresh / study / "manifest.json", typ="series")["files"]
            assert sorted(files) == sorted(pd.read_json(shipped, typ="series")["files"]), (
                f"docs/showcase/{study} was not regenerated: python -m polyell.showcase"
            )


def test_the_command_refuses_what_it_cannot_run(tmp_path, capsys):
    from polyell.errors import InputError
    from polyell.showcase import main

    with pytest.raises(InputError, match="only: expected names among"):
        run_showcase(tmp_path, REPO / "studies", only=["chiacchio_2000"])
    with pytest.raises(InputError, match="studies: expected the folder"):
        run_showcase(tmp_path, tmp_path / "nowhere", only=["chiacchio2000"])
    page = tmp_path / "page.md"
    page.write_text("# A page without markers\n")
    with pytest.raises(InputError, match="document: expected a page with the markers"):
        update_document(page, {"posture": "text"})
    assert update_document(page, {}) == [] and page.read_text() == "# A page without markers\n"
    missing = tmp_path / "missing.md"
    assert main(["--only", "posture_paper", "--document", str(missing), "--quiet"]) == 2
    assert "document: expected the showcase page" in capsys.readouterr().err
    assert not (tmp_path / "posture_paper").exists()  # refused before any study ran
