from __future__ import annotations

import json
import shutil
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.comparison.labels import set_label
from polyell.studies import load_study, run_study
from polyell.studies.runner import STUDY_FILES, STUDY_LOCK
from reference import PAPER_Q_REDUNDANT, paper_analysis

REPO = Path(__file__).resolve().parents[2]

SMALL_GRID = """
    title = "small"
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = { start = "-pi/2", stop = 0, num = 3 }
    q3 = { start = "-pi/2", stop = "pi/2", num = 4 }
    [compare]
    directions = 36
    mvie = false
    [output]
    formats = ["png"]
    dpi = 50
    maps = ["chiacchio_coverage", "yoshikawa_inscribed_scale"]
"""


@pytest.fixture(scope="module")
def paper_study(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("paper")
    run_study(load_study(REPO / "studies" / "chiacchio2000.toml"), out)
    return out


def test_paper_study_writes_numbers_tables_and_figures(paper_study):
    manifest = json.loads((paper_study / "manifest.json").read_text())
    for name in (
        "numbers.md",
        "comparison.md",
        "comparison.tex",
        "comparison.csv",
        "limits.md",
        "limits.tex",
        "limits.csv",
        "scores.csv",
        "sets_redundant.pdf",
        "sets_redundant.png",
        "sets_singular.pdf",
        "limits_redundant.png",
    ):
        assert name in manifest["files"] and (paper_study / name).stat().st_size > 0
    numbers = (paper_study / "numbers.md").read_text()
    for printed in ("-12.392", "[-43.401, 35.284]", "[-70.922, 52.69]", "1.5281", "61.806"):
        assert printed in numbers


def test_paper_study_table_equals_compare(paper_study):
    table = pd.read_csv(paper_study / "scores.csv", index_col="ellipsoid")
    expected = pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 360)
    # the paper's own study names the sets as the paper does ([output] labels)
    new, classic = (set_label(kind, labels="chiacchio2000") for kind in ("chiacchio", "yoshikawa"))
    for name in pe.SCORE_NAMES:
        np.testing.assert_allclose(
            table.loc[f"redundant: {new}", name], getattr(expected["chiacchio"], name)
        )
    assert np.isnan(table.loc[f"singular: {classic}", "coverage"])


def test_grid_study_results_and_maps(tmp_path):
    spec_path = tmp_path / "grid.toml"
    spec_path.write_text(textwrap.dedent(SMALL_GRID))
    out = tmp_path / "out"
    run_study(load_study(spec_path), out)
    results = pd.read_csv(out / "results.csv")
    assert len(results) == 12
    arm = pe.robots.load("chiacchio2000")
    row = results.iloc[5]
    q = row[["q1", "q2", "q3"]].to_numpy(dtype=float)
    expected = pe.compare(pe.analyze(arm.dynamics(q), arm.tau_max), 36, mvie=False)
    assert row["chiacchio_coverage"] == pytest.approx(expected["chiacchio"].coverage)
    summary = pd.read_csv(out / "summary.csv", index_col=[0, 1])
    assert summary.loc[("chiacchio", "coverage"), "mean"] == pytest.approx(
        results["chiacchio_coverage"].mean()
    )
    assert (out / "map_chiacchio_coverage.png").exists()
    assert (out / "map_yoshikawa_inscribed_scale.png").exists()


def test_unwritable_output_folder(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(pe.InputError, match="out: expected a folder polyell can write to"):
        run_study(load_study(REPO / "studies" / "chiacchio2000.toml"), blocker / "sub")


RANDOM_PANDA = """
    title = "panda"
    [robot]
    library = "panda"
    [random]
    count = 6
    seed = 3
    [compare]
    directions = 50
    mvie = false
    [output]
    formats = ["png"]
    dpi = 40
    histograms = ["coverage", "witness_torque_max"]
"""


def test_random_study_of_a_real_robot(tmp_path):
    spec_path = tmp_path / "panda.toml"
    spec_path.write_text(textwrap.dedent(RANDOM_PANDA))
    spec = load_study(spec_path)
    q = spec.configurations()
    low, high = spec.robot.model.position_limits
    assert q.shape == (6, 7) and np.all((q >= low) & (q <= high))
    np.testing.assert_array_equal(q, load_study(spec_path).configurations())  # seeded
    out = tmp_path / "out"
    run_study(spec, out)
    results = pd.read_csv(out / "results.csv")
    robot = pe.robots.load("panda")
    expected = pe.compare(pe.analyze(robot.dynamics(q[2]), robot.tau_max), 50, mvie=False)
    assert results.loc[2, "yoshikawa_coverage"] == pytest.approx(expected["yoshikawa"].coverage)
    assert (out / "histogram_coverage.png").exists()
    assert (out / "histogram_witness_torque_max.png").exists()


def test_the_shipped_panda_study_parses():
    spec = load_study(REPO / "studies" / "panda_random.toml")
    assert spec.configurations().shape == (300, 7)
    assert spec.robot.model.joint_names[-1] == "panda_joint7"


#: A candidate that neither lies inside the polytope nor around it at these configurations,
#: and whose parts beyond two facets meet (it holds a vertex, not all): its coverage is a
#: quasi-Monte-Carlo estimate (the scalar path), which depends on samples and seed.
MONTE_CARLO_STUDY = """
    title = "monte carlo"
    description = "A disc around some vertices: its coverage is estimated."
    [robot]
    library = "chiacchio2000"
    {configurations}
    [compare]
    directions = 16
    mvie = false
    outer = false
    samples = {samples}
    seed = {seed}
    [[candidates]]
    name = "disc"
    core = [[2e-4, 0], [0, 2e-4]]
    [output]
    formats = ["svg"]
    dpi = 20
"""
CONFIGURATIONS = {
    "grid": '[grid]\nq1 = "pi/2"\nq2 = { start = -1, stop = 1, num = 2 }\nq3 = 0.5\n',
    "random": "[random]\ncount = 2\nseed = 4\nlow = [1, -1, -1]\nhigh = [2, 1, 1]\n",
    "trajectory": '[trajectory]\nfile = "path.csv"\n',
}


@pytest.mark.parametrize("kind", list(CONFIGURATIONS))
def test_samples_and_seed_reach_every_kind_of_study(tmp_path, kind):
    path = REPO / "studies" / "planar3r_path.csv"
    (tmp_path / "path.csv").write_text("".join(path.read_text().splitlines(True)[:3]))  # 2 rows
    arm = pe.robots.load("chiacchio2000")
    coverage = {}
    for samples, seed in ((16, 0), (4096, 0), (4096, 7)):
        spec_path = tmp_path / f"{samples}_{seed}.toml"
        spec_path.write_text(
            textwrap.dedent(MONTE_CARLO_STUDY).format(
                configurations=CONFIGURATIONS[kind], samples=samples, seed=seed
            )
        )
        spec = load_study(spec_path)
        out = tmp_path / f"out_{samples}_{seed}"
        run_study(spec, out)
        results = pd.read_parquet(out / "results").sort_values("configuration")
        coverage[samples, seed] = results["disc_coverage"].to_numpy()
        for k, q in enumerate(spec.configurations()):
            # The row is pe.compare's with the study's samples and seed: the same points and
            # counts (the batch's share times its volume ratio: equal to rounding).
            expected = pe.compare(
                pe.analyze(arm.dynamics(q), arm.tau_max),
                16,
                samples=samples,
                seed=seed,
                mvie=False,
                outer=False,
                candidates=spec.candidates,
            )
            assert coverage[samples, seed][k] == pytest.approx(expected["disc"].coverage, rel=1e-12)
    # Neither is ignored: other samples or another seed give other estimates.
    assert np.all(coverage[16, 0] != coverage[4096, 0])
    assert np.all(coverage[4096, 7] != coverage[4096, 0])


@pytest.mark.parametrize(
    ("samples", "fragment"),
    [
        (0, "from 2 to"),
        (1, "from 2 to"),
        (2**22 + 1, "from 2 to"),
        (2.5, "float"),
        ("'8'", "str"),
        (True, "bool"),
    ],
)
def test_bad_samples_are_refused_when_the_study_loads(tmp_path, samples, fragment):
    spec_path = tmp_path / "s.toml"
    text = textwrap.dedent(MONTE_CARLO_STUDY).format(
        configurations=CONFIGURATIONS["grid"], samples=str(samples).lower(), seed=0
    )
    spec_path.write_text(text)
    with pytest.raises(pe.InputError, match=r"compare\.samples: expected an integer") as info:
        load_study(spec_path)
    assert fragment in str(info.value)
    spec_path.write_text(
        text.replace("samples = ", "samples = 8\n#").replace("seed = 0", "seed = -1")
    )
    with pytest.raises(pe.InputError, match=r"compare\.seed: expected an integer from 0"):
        load_study(spec_path)


def test_the_description_is_kept_in_every_written_summary(tmp_path):
    description = "Free text: kept *as written*."
    for kind, configurations in (
        ("points", '[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'),
        ("grid", CONFIGURATIONS["grid"]),
    ):
        spec_path = tmp_path / f"{kind}.toml"
        spec_path.write_text(
            f'title = "T"\ndescription = "{description}"\n[robot]\nlibrary = "chiacchio2000"\n'
            f"{configurations}[compare]\ndirections = 8\nmvie = false\nouter = false\n"
            '[output]\nformats = ["html"]\n'
        )
        out = tmp_path / kind
        run_study(load_study(spec_path), out)
        manifest = json.loads((out / "manifest.json").read_text())
        assert manifest["description"] == description
        markdown = ["numbers.md", "comparison.md"] if kind == "points" else ["summary.md"]
        for name in markdown:  # the paragraph under the title
            assert (out / name).read_text().split("\n")[1:4] == ["", description, ""], name
        report = (out / "report.html").read_text()
        assert "<h2>About this study</h2><p>Free text: kept *as written*.</p>" in report


def test_a_study_without_description_writes_no_empty_paragraph(tmp_path):
    spec_path = tmp_path / "s.toml"
    spec_path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'
        '[compare]\ndirections = 8\nmvie = false\nouter = false\n[output]\nformats = ["svg"]\n'
    )
    run_study(load_study(spec_path), tmp_path / "o")
    assert (tmp_path / "o" / "numbers.md").read_text().split("\n")[1:3] == ["", "## p"]
    assert json.loads((tmp_path / "o" / "manifest.json").read_text())["description"] == ""


def test_every_file_a_study_writes_is_one_it_cleans_up_after(paper_study, tmp_path):
    """STUDY_FILES (what a run removes the stale temporary files of) covers every output."""
    spec_path = tmp_path / "grid.toml"
    spec_path.write_text(
        textwrap.dedent(SMALL_GRID).replace('formats = ["png"]', 'formats = ["png", "svg"]')
        + 'histograms = ["coverage"]\n'
    )
    run_study(load_study(spec_path), tmp_path / "grid")
    path_study = REPO / "studies" / "planar3r_path.toml"
    shutil.copy(REPO / "studies" / "planar3r_path.csv", tmp_path)
    text = path_study.read_text().replace("mvie = true", "mvie = false")
    text = text.replace('"mvie_ratio", ', "").replace('"pdf", "png", "html"', '"svg"')
    (tmp_path / "path.toml").write_text(text)
    run_study(load_study(tmp_path / "path.toml"), tmp_path / "path")
    names = set()
    for out in (paper_study, tmp_path / "grid", tmp_path / "path"):
        names |= set(json.loads((out / "manifest.json").read_text())["files"]) | {"manifest.json"}
    assert {"map_chiacchio_coverage.svg", "tangent_limits.svg", "sets_singular.pdf"} <= names
    assert [name for name in names if not STUDY_FILES.fullmatch(name)] == []


def test_a_killed_runs_temporary_files_are_removed_and_no_others(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    stale = [".summary.md.k2j_x9q0.tmp", ".sets_p.png.abcdefgh.tmp", ".report.html.a1b2c3d4.tmp"]
    foreign = [".notes.md.abcdefgh.tmp", ".sets_p.png.tmp", "summary.md.abcdefgh.tmp"]
    for name in stale + foreign:
        (out / name).write_text("left by a run killed with SIGKILL")
    spec_path = tmp_path / "s.toml"
    spec_path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.5, 0.7]\n'
        '[compare]\ndirections = 8\nmvie = false\nouter = false\n[output]\nformats = ["svg"]\n'
    )
    run_study(load_study(spec_path), out)
    left = {path.name for path in out.iterdir() if path.name.startswith(".")}
    assert left == set(foreign[:2])  # the study's lock file is gone with the lock
    assert (out / foreign[2]).exists()


def test_a_folder_another_study_is_writing_is_refused(tmp_path):
    from polyell.storage import folder_lock

    out = tmp_path / "o"
    out.mkdir()
    spec = load_study(REPO / "studies" / "chiacchio2000.toml")
    with folder_lock(out, STUDY_LOCK, "study"):
        with pytest.raises(pe.InputError, match="locked by a running study"):
            run_study(spec, out)
        assert list(out.iterdir()) == [out / STUDY_LOCK]  # nothing written
    assert list(out.iterdir()) == []  # released: the lock file removed
    with folder_lock(out, STUDY_LOCK, "study"):  # and the folder can be locked again
        assert (out / STUDY_LOCK).exists()


@pytest.mark.parametrize(
    ("arguments", "fragment"),
    [
        ({"spec": "studies/chiacchio2000.toml"}, "spec: expected a StudySpec, got str"),
        ({"out": 5}, "out: expected a folder path"),
        ({"out": ""}, "out: expected a folder path"),
        ({"scheduler": "tcp://host:port"}, "scheduler: expected None, 'processes'"),
        ({"scheduler": "tcp://[::1"}, "scheduler: expected None, 'processes'"),
        ({"scheduler": 8786}, "scheduler: expected None, 'processes'"),
    ],
)
def test_bad_run_study_arguments(tmp_path, arguments, fragment):
    call = {"spec": load_study(REPO / "studies" / "chiacchio2000.toml"), "out": tmp_path / "o"}
    with pytest.raises(pe.InputError) as info:
        run_study(**(call | arguments))
    assert fragment in str(info.value)
    assert not (tmp_path / "o").exists()


def test_no_report_unless_html_is_asked_for(tmp_path):
    spec_path = tmp_path / "s.toml"
    spec_path.write_text(
        'description = "d"\n[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\n'
        "q = [0.3, 0.5, 0.7]\n[compare]\ndirections = 8\nmvie = false\nouter = false\n"
        '[output]\nformats = ["svg"]\n'
    )
    written = run_study(load_study(spec_path), tmp_path / "o")
    assert "report.html" not in {path.name for path in written}
    assert not (tmp_path / "o" / "report.html").exists()


# --- several robots and several directions (issue 24) ---------------------------------------


def _interval_by_linear_program(dynamics, tau_max, tau_min, t):
    """[lo, hi] of a with a t = J B^-1 (tau - g) + xdd_bias, tau_min <= tau <= tau_max, by
    scipy's LP on the raw dynamics (independent of polyell's polytope)."""
    from scipy.optimize import linprog

    A = dynamics.J @ np.linalg.solve(dynamics.B, np.eye(dynamics.n))
    n = A.shape[1]
    # variables (a, tau): a t - A tau = xdd_bias - A g
    equality = np.hstack([t[:, None], -A])
    right = dynamics.xdd_bias - A @ dynamics.g
    bounds = [(None, None), *zip(tau_min, tau_max, strict=True)]
    ends = []
    for sign in (1.0, -1.0):
        cost = np.zeros(n + 1)
        cost[0] = sign
        result = linprog(cost, A_eq=equality, b_eq=right, bounds=bounds, method="highs")
        assert result.status == 0, result.message
        ends.append(result.x[0])
    return ends


def _shrunk_two_robot_study(tmp_path):
    text = (REPO / "studies" / "two_robots.toml").read_text()
    for old, new in (
        ("directions = 1000", "directions = 50"),
        ("mvie = true", "mvie = false"),
        ("outer = true", "outer = false"),
        ('formats = ["pdf", "png"]', 'formats = ["svg", "html"]'),
        ("dpi = 200", "dpi = 20"),
    ):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "two_robots.toml"
    path.write_text(text)
    return path


def test_the_shipped_two_robot_study_runs_from_one_file(tmp_path):
    spec = load_study(_shrunk_two_robot_study(tmp_path))
    out = tmp_path / "out"
    run_study(spec, out)
    files = set(json.loads((out / "manifest.json").read_text())["files"])
    for stem in ("panda.ready", "ur5.ready", "panda.reach", "ur5.reach"):
        assert f"sets_{stem}.svg" in files and (out / f"sets_{stem}.svg").stat().st_size > 0
    table = pd.read_csv(out / "scores.csv", index_col="ellipsoid")
    numbers = (out / "numbers.md").read_text()
    for point in spec.points:
        robot = pe.robots.load(point.robot, task="linear")
        # the q of the file, written out: the robot's own joint count
        assert point.q.size == robot.n
        expected = pe.compare(
            pe.analyze(robot.dynamics(point.q), robot.tau_max), 50, mvie=False, outer=False
        )
        for score in ("coverage", "inscribed_scale", "volume"):
            assert table.loc[f"{point.label}: Chiacchio", score] == pytest.approx(
                getattr(expected["chiacchio"], score), rel=1e-12
            )
        section = numbers.split(f"## {point.label}")[1].split("\n## ")[0]
        assert point.labels == ("x", "y", "z", "x+z")
        for label, t in zip(point.labels, point.directions, strict=True):
            line = section.split(f"Achievable accelerations along {label} = ")[1]
            polytope = line.split("\n")[1].split()  # "polytope [lo, hi]"
            assert polytope[0] == "polytope"
            lo, hi = (float(v) for v in " ".join(polytope[1:]).strip("[]").split(","))
            exact = _interval_by_linear_program(
                robot.dynamics(point.q), robot.tau_max, robot.tau_min, t
            )
            np.testing.assert_allclose([lo, hi], exact, rtol=1e-4, atol=1e-6)
    report = (out / "report.html").read_text()
    assert "panda/ready" in report and "ur5/reach" in report


def test_a_random_study_of_two_robots_runs_one_sweep_each(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        '[[robots]]\nname = "ur5"\nlibrary = "ur5"\n'
        '[[robots]]\nname = "arm"\nlibrary = "chiacchio2000"\ntau_max = [50, 20, 2]\n'
        "[random]\ncount = 3\nseed = 5\n[compare]\ndirections = 12\nmvie = false\n"
        'outer = false\n[output]\nformats = ["svg"]\ndpi = 20\nhistograms = ["coverage"]\n'
    )
    spec = load_study(path)
    out = tmp_path / "out"
    run_study(spec, out)
    robots = {"ur5": pe.robots.load("ur5"), "arm": pe.robots.load("chiacchio2000")}
    results = pd.read_csv(out / "results.csv")
    assert list(results.columns[:2]) == ["robot", "configuration"]
    assert results["robot"].tolist() == ["ur5"] * 3 + ["arm"] * 3
    # the manifest counts the rows computed one at a time, per robot's dataset
    per_row = {name: int(results.loc[results["robot"] == name, "per_row"].sum()) for name in robots}
    assert json.loads((out / "manifest.json").read_text())["per_row"] == [
        f"{name} acceleration: {per_row[name]} of 3 rows per row ({100 * per_row[name] / 3:.2f} %)"
        for name in ("arm", "ur5")
    ]
    limits = {"ur5": None, "arm": np.array([50.0, 20.0, 2.0])}
    for index, row in results.iterrows():
        robot = robots[row["robot"]]
        q = row[[f"q{i + 1}" for i in range(robot.n)]].to_numpy(dtype=float)
        np.testing.assert_array_equal(
            q, spec.configurations(0 if row["robot"] == "ur5" else 1)[index % 3]
        )
        tau = robot.tau_max if limits[row["robot"]] is None else limits[row["robot"]]
        expected = pe.compare(pe.analyze(robot.dynamics(q), tau), 12, mvie=False, outer=False)
        assert row["chiacchio_coverage"] == pytest.approx(expected["chiacchio"].coverage, rel=1e-12)
    assert np.isnan(results.loc[results["robot"] == "arm", "q4"]).all()
    summary = pd.read_csv(out / "summary.csv", index_col=[0, 1, 2])
    for name in ("ur5", "arm"):
        mean = results.loc[results["robot"] == name, "yoshikawa_coverage"].mean()
        assert summary.loc[(name, "yoshikawa", "coverage"), "mean"] == pytest.approx(mean)
    dataset = pd.read_parquet(out / "results")  # a Hive partition per robot
    assert sorted(set(dataset["robot"].astype(str))) == ["arm", "ur5"] and len(dataset) == 6
    assert (out / "histogram_ur5.coverage.svg").exists() and (
        out / "histogram_arm.coverage.svg"
    ).exists()
    assert "## ur5" in (out / "summary.md").read_text()
    assert (out / "summary.tex").read_text().count("\\begin{table}") == 2


def test_markdown_outputs_carry_no_live_html(tmp_path):
    # The third attack (issue 33): titles and descriptions went into .md files as HTML.
    path = tmp_path / "s.toml"
    path.write_text(
        'title = "<script>alert(1)</script> & co"\n'
        'description = "<img src=x onerror=alert(2)>"\n'
        '[robot]\nlibrary = "chiacchio2000"\n'
        '[[points]]\nname = "p"\ntitle = "<b>bold</b>"\nq = [1.5707963, -1.5707963, -1.5707963]\n'
        "[compare]\ndirections = 8\nmvie = false\nouter = false\n"
        '[output]\nformats = ["svg"]\n'
    )
    out = tmp_path / "out"
    run_study(load_study(path), out)
    written = sorted(out.glob("*.md"))
    assert written
    for markdown in written:
        text = markdown.read_text()
        assert "<script" not in text and "<img" not in text and "<b>" not in text, markdown.name
    numbers = (out / "numbers.md").read_text()
    assert "&lt;script&gt;alert(1)&lt;/script&gt; & co" in numbers


def test_a_rerun_of_an_edited_study_replaces_the_previous_outputs(tmp_path):
    # The third attack (issue 33): re-running an edited study into the same folder left the
    # old run's tables (here: a force capacity dropped, its tables stale).
    path = tmp_path / "s.toml"
    study = (
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 3\nseed = 5\n'
        "[compare]\ndirections = 8\nmvie = false\nouter = false\ncapacities = {}\n"
        '[output]\nformats = ["svg"]\nhistograms = []\n'
    )
    out = tmp_path / "out"
    path.write_text(study.format('["acceleration", "force"]'))
    run_study(load_study(path), out)
    assert (out / "summary_force.md").exists() and (out / "results_force.csv").exists()
    (out / "notes.txt").write_text("mine")  # not a study's output: kept
    path.write_text(study.format('["acceleration"]'))
    run_study(load_study(path), out)
    manifest = json.loads((out / "manifest.json").read_text())
    assert not (out / "summary_force.md").exists() and not (out / "results_force.csv").exists()
    assert {"summary_force.md", "results_force.csv"} <= set(manifest["removed"])
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "results_force").is_dir()  # the dataset stays, to resume
    assert manifest["per_row"] == ["acceleration: 0 of 3 rows per row (0.00 %)"]
    assert sorted(p.name for p in out.iterdir() if p.is_file()) == sorted(
        [*manifest["files"], "manifest.json", "notes.txt"]
    )
