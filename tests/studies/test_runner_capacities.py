"""Grid and random studies of every capacity: each capacity's files, equal to compare().

A ``[grid]`` study of the paper's arm over ``[compare] capacities`` writes one dataset,
results table, summary and set of figures per capacity (the acceleration ones under
today's names, the others with the capacity in the name); every row of a capacity's
``results_<capacity>.csv`` is checked against ``pe.compare(pe.analyze(..., capacity=...))``
at its own configuration, an independent route (no sweep, no batching) to 1e-12.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.comparison.labels import set_label
from polyell.geometry.free_center import MVIE_GAP
from polyell.studies import load_study, run_study

ARM = pe.robots.load("chiacchio2000")
GRID = """
title = "Capacities over a grid"
[robot]
library = "chiacchio2000"
[grid]
q1 = 0.2
q2 = {{ start = 0.3, stop = 1.5, num = 3 }}
q3 = {{ start = 0.4, stop = 2.0, num = 2 }}
[compare]
capacities = {capacities}
directions = 16
samples = 256
seed = 4
[output]
formats = ["png", "html"]
dpi = 20
maps = {maps}
histograms = ["coverage"]
"""
SCORES = ("inscribed_scale", "coverage", "direction_error_mean", "volume", "mvie_ratio")


def _study(tmp_path, capacities, maps='["chiacchio_coverage"]'):
    path = tmp_path / "study.toml"
    path.write_text(GRID.format(capacities=capacities, maps=maps))
    return load_study(path)


def _analysis(q, capacity):
    dyn = ARM.dynamics(q)
    if capacity == "velocity":
        return pe.analyze(dyn, capacity="velocity", qd_max=ARM.qd_max)
    return pe.analyze(dyn, ARM.tau_max, ARM.tau_min, capacity=capacity)


def test_a_grid_study_writes_each_capacity_equal_to_compare(tmp_path):
    spec = _study(tmp_path, '["acceleration", "force", "velocity"]', '["chiacchio_coverage"]')
    out = tmp_path / "out"
    written = {path.name for path in run_study(spec, out)}
    for suffix in ("", "_force", "_velocity"):
        for name in ("results.csv", "summary.csv", "summary.md", "summary.tex"):
            stem, ext = name.split(".")
            assert f"{stem}{suffix}.{ext}" in written
        assert f"histogram_coverage{suffix}.png" in written
    # The map of a kind the capacity has; velocities have no "chiacchio" ellipsoid.
    assert {"map_chiacchio_coverage.png", "map_chiacchio_coverage_force.png"} <= written
    assert not any(name.startswith("map_") and "velocity" in name for name in written)
    for capacity in ("acceleration", "force", "velocity"):
        suffix = "" if capacity == "acceleration" else f"_{capacity}"
        results = pd.read_csv(out / f"results{suffix}.csv")
        assert len(results) == 6
        kinds = pe.compare(_analysis([0.2, 0.3, 0.4], capacity), 16, samples=256).kinds
        assert {f"{kind}_coverage" for kind in kinds} <= set(results.columns)
        for _, row in results.iterrows():
            q = row[["q1", "q2", "q3"]].to_numpy(dtype=float)
            cmp = pe.compare(_analysis(q, capacity), 16, samples=256, seed=4)
            for kind in cmp.kinds:
                for score in SCORES:
                    expected = getattr(cmp[kind], score)
                    # an optimal volume is certified within MVIE_GAP of the optimum, in
                    # either computation (a force set's are solved in other frames), its
                    # shape to about the square root of that
                    rtol = 2 * MVIE_GAP if score == "mvie_ratio" else 1e-12
                    rtol = 2 * np.sqrt(2 * MVIE_GAP) if kind in ("mvie", "outer") else rtol
                    assert row[f"{kind}_{score}"] == pytest.approx(expected, rel=rtol, abs=0)
    # The datasets stay apart: one folder per capacity, each resumable on its own.
    assert (out / "results").is_dir() and (out / "results_force").is_dir()
    files = json.loads((out / "manifest.json").read_text())["files"]
    assert "summary_velocity.tex" in files


def test_summaries_and_report_name_each_capacitys_ellipsoids(tmp_path):
    spec = _study(tmp_path, '["force", "velocity"]', '["static_coverage", "yoshikawa_coverage"]')
    out = tmp_path / "out"
    written = {path.name for path in run_study(spec, out)}
    assert "summary.tex" not in written and "results.csv" not in written  # no accelerations
    force = (out / "summary_force.md").read_text()
    for kind in ("chiacchio", "yoshikawa", "static"):
        assert set_label(kind, "force") in force
    assert "new (eq. 32/38)" not in force  # the paper's labels only where asked for
    assert "force summary" in force
    tex = (out / "summary_force.tex").read_text()
    assert r"\label{tab:summary-force" in tex and "force scores" in tex
    velocity = (out / "summary_velocity.md").read_text()
    assert set_label("yoshikawa", "velocity") in velocity and "classic (eq. 27)" not in velocity
    summary = pd.read_csv(out / "summary_force.csv", index_col=[0, 1])
    results = pd.read_csv(out / "results_force.csv")
    median = summary.loc[("static", "coverage"), "median"]
    assert median == pytest.approx(np.median(results["static_coverage"]), rel=1e-12)
    assert {"map_static_coverage_force.png", "map_yoshikawa_coverage_velocity.png"} <= written
    assert "map_yoshikawa_coverage_force.png" in written
    report = (out / "report.html").read_text()
    assert "force: Heat maps" in report and "velocity: Summary over 6" in report
    assert "static (no gravity): coverage" in report  # the force map's menu names the ellipsoid


def test_a_random_study_of_forces(tmp_path):
    path = tmp_path / "random.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[random]\ncount = 5\nseed = 2\n'
        '[compare]\ncapacities = ["force"]\ndirections = 16\nsamples = 256\nouter = false\n'
        '[output]\nformats = ["png"]\ndpi = 20\n'
    )
    out = tmp_path / "out"
    run_study(load_study(path), out)
    results = pd.read_csv(out / "results_force.csv")
    q = results[["q1", "q2", "q3"]].to_numpy(dtype=float)
    frame = pe.sweep(
        ARM,
        q,
        ARM.tau_max,
        ARM.tau_min,
        capacity="force",
        directions=16,
        samples=256,
        mvie=True,
        outer=False,
    )
    for column in ("chiacchio_coverage", "static_inscribed_scale", "mvie_volume"):
        np.testing.assert_allclose(results[column], frame[column], rtol=1e-12, atol=0)


def test_a_trajectory_study_of_every_capacity(tmp_path):
    """Each capacity's series along the path and what it allows along the path's tangent."""
    t = np.linspace(0.0, 1.0, 7)
    q = np.column_stack([0.2 + 0.3 * t, 0.4 + 0.5 * t, 0.9 - 0.4 * t])
    table = np.column_stack([t, q, np.tile([0.3, 0.5, -0.4], (t.size, 1))])
    rows = ["t,q1,q2,q3,qd1,qd2,qd3"] + [",".join(repr(float(v)) for v in row) for row in table]
    (tmp_path / "path.csv").write_text("\n".join(rows) + "\n")
    path = tmp_path / "path.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[trajectory]\nfile = "path.csv"\n'
        '[compare]\ncapacities = ["acceleration", "force", "velocity"]\ndirections = 16\n'
        'samples = 256\nouter = false\n[output]\nformats = ["png", "html"]\ndpi = 20\n'
        'series = ["coverage"]\n'
    )
    out = tmp_path / "out"
    written = {p.name for p in run_study(load_study(path), out)}
    for suffix in ("", "_force", "_velocity"):
        assert {f"results{suffix}.csv", f"summary{suffix}.tex", f"series_coverage{suffix}.png"} <= (
            written
        )
    assert {"tangent_limits.png", "tangent_limits_force.png", "tangent_limits_velocity.png"} <= (
        written
    )
    velocity = pd.read_csv(out / "results_velocity.csv")
    force = pd.read_csv(out / "results_force.csv")
    assert "tangent_chiacchio_lo" not in velocity and "tangent_static_hi" in force
    # the speed along the path: the joint velocity box through J, along J qd / |J qd|
    for k in range(len(t)):
        J = ARM.dynamics(q[k]).J
        tangent = J @ table[k, 4:] / np.linalg.norm(J @ table[k, 4:])
        an = pe.analyze(
            ARM.dynamics(q[k]), capacity="velocity", qd_max=ARM.qd_max, qd_min=ARM.qd_min
        )
        lo, hi = an.polytope.limits(tangent)
        assert (velocity["tangent_polytope_lo"][k], velocity["tangent_polytope_hi"][k]) == (
            pytest.approx(float(lo), rel=1e-12),
            pytest.approx(float(hi), rel=1e-12),
        )
        an = pe.analyze(ARM.dynamics(q[k]), ARM.tau_max, ARM.tau_min, capacity="force")
        lo, hi = an.ellipsoid("static").limits(tangent)
        assert force["tangent_static_hi"][k] == pytest.approx(float(hi), rel=1e-12)
    for k in (0, 3, 6):
        an = _analysis(q[k], "velocity")
        cmp = pe.compare(an, 16, samples=256, seed=0, outer=False)
        for score in SCORES:
            expected = getattr(cmp["yoshikawa"], score)
            assert velocity[f"yoshikawa_{score}"][k] == pytest.approx(expected, rel=1e-12, abs=0)
    report = (out / "report.html").read_text()
    assert "force: Summary over 7" in report and "velocity: coverage [%]" in report


@pytest.mark.parametrize(
    ("study", "message"),
    [
        (  # a map of a kind no compared capacity has
            GRID.format(capacities='["acceleration"]', maps='["static_coverage"]'),
            r"output\.maps.*'static_coverage'",
        ),
        (  # velocities need the robot's joint velocity limits
            "[robot]\ntau_max = [5, 5]\n[robot.planar]\nlengths = [1.0, 1.0]\n"
            "masses = [1.0, 1.0]\n[grid]\nq1 = 0.1\nq2 = { start = 0.5, stop = 0.6, num = 2 }\n"
            '[compare]\ncapacities = ["velocity"]\n',
            r"robot\.qd_max",
        ),
        (  # a capacity whose tables would hold none of its sets
            '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.3, 0.6, 0.9]\n'
            '[compare]\ncapacities = ["acceleration", "force"]\n'
            '[output]\nsets = ["polytope", "static"]\n',
            r"output\.sets: expected at least one set of each compared capacity",
        ),
    ],
    ids=["map-kind", "no-qd", "sets-of-one-capacity"],
)
def test_capacities_of_sweeps_are_checked_at_load(tmp_path, study, message):
    path = tmp_path / "study.toml"
    path.write_text(study)
    with pytest.raises(pe.InputError, match=message):
        load_study(path)


def test_the_shipped_capacities_study_equals_compare(tmp_path):
    """studies/capacities_panda.toml (fewer directions and samples): every score of every
    capacity at every posture equals pe.compare of that capacity's analysis, to 1e-12."""
    shipped = Path(__file__).resolve().parents[2] / "studies" / "capacities_panda.toml"
    text = shipped.read_text().replace("[compare]\n", "[compare]\ndirections = 16\nsamples = 256\n")
    path = tmp_path / "capacities_panda.toml"
    path.write_text(text)
    spec = load_study(path)
    assert spec.capacities == ("acceleration", "force", "velocity")
    out = tmp_path / "out"
    run_study(spec, out)
    panda = pe.robots.load("panda")
    for capacity in spec.capacities:
        suffix = "" if capacity == "acceleration" else f"_{capacity}"
        scores = pd.read_csv(out / f"scores{suffix}.csv", index_col="ellipsoid")
        for point in spec.points:
            dyn = panda.dynamics(point.q)
            if capacity == "velocity":
                an = pe.analyze(dyn, capacity="velocity", qd_max=panda.qd_max, qd_min=panda.qd_min)
            else:
                an = pe.analyze(dyn, panda.tau_max, panda.tau_min, capacity=capacity)
            cmp = pe.compare(an, 16, samples=256, outer=False)
            for kind in cmp.kinds:
                row = scores.loc[f"{point.label}: {set_label(kind, capacity)}"]
                for score in SCORES:
                    expected = getattr(cmp[kind], score)
                    assert row[score] == pytest.approx(expected, rel=1e-12, abs=0, nan_ok=True)


def test_each_capacitys_summary_compiles_and_fits_a_one_column_page(tmp_path):
    from latex_check import engine, fit_warnings

    pdflatex = engine("pdflatex")
    if pdflatex is None:
        pytest.skip("pdflatex is not installed (.ci/run installs it)")
    spec = _study(tmp_path, '["acceleration", "force", "velocity"]', "[]")
    out = tmp_path / "out"
    run_study(spec, out)
    for name in ("summary.tex", "summary_force.tex", "summary_velocity.tex"):
        tex = (out / name).read_text()
        warnings = fit_warnings(pdflatex, [tex], tmp_path / f"tex_{Path(name).stem}")
        assert not warnings, f"{name}: {warnings}"


def test_the_command_line_points_to_each_capacitys_outputs(tmp_path, capsys):
    from polyell.cli import main

    path = tmp_path / "study.toml"
    path.write_text(GRID.format(capacities='["force", "velocity"]', maps="[]"))
    out = tmp_path / "out"
    assert main(["study", str(path), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    listed = {line.split(": ", 1)[0].strip(): line.split(": ", 1)[1] for line in lines[1:]}
    assert listed[str(out / "summary_force.md")].startswith("force: the scores' statistics")
    assert listed[str(out / "results_velocity.csv")].startswith("velocity: one row of scores")
    assert str(out / "report.html") in listed and str(out / "summary.md") not in listed
    assert all(Path(name).exists() for name in listed)


# --- points in motion (issue 21, item 5): qd, the torque limits at qd, Coriolis terms ----------

MOVING = """
title = "A moving arm"
[robot]
urdf = "arm.urdf"
tip = "tip"
task = "planar"
tau_max = [100, 30, 5]
torque_speed = {{ tau_stall = [150, 40, 6], qd_no_load = [4, 5, 8] }}
[[points]]
name = "moving"
q = [0.3, 0.8, -0.4]
qd = {qd}
[compare]
capacities = {capacities}
directions = 8
samples = 256
[output]
formats = ["png"]
dpi = 20
"""


def _moving(tmp_path, qd="[2.0, -1.0, 3.0]", capacities='["acceleration", "force"]'):
    from reference import PAPER_ARM, planar_urdf

    (tmp_path / "arm.urdf").write_text(planar_urdf(PAPER_ARM))
    path = tmp_path / "study.toml"
    path.write_text(MOVING.format(qd=qd, capacities=capacities))
    return path


def test_a_point_in_motion_uses_the_limits_at_qd_and_states_them(tmp_path):
    spec = load_study(_moving(tmp_path))
    run_study(spec, tmp_path / "out")
    robot = spec.robot
    q, qd = np.array([0.3, 0.8, -0.4]), np.array([2.0, -1.0, 3.0])
    tau_max, tau_min = robot.torque_limits(qd)
    # joint 1 forward at 2 rad/s: 150 (1 - 2/4) = 75 < 100; joint 3: 6 (1 - 3/8) = 3.75 < 5
    np.testing.assert_allclose(tau_max, [75.0, 30.0, 3.75], rtol=1e-15)
    numbers = (tmp_path / "out" / "numbers.md").read_text()
    assert "qd = (2, -1, 3) rad/s; torque limits at qd [N m]: tau_max = (75, 30, 3.75)" in numbers
    for capacity in ("acceleration", "force"):
        dyn = robot.model.dynamics(q, qd)  # with its Coriolis terms
        expected = pe.compare(pe.analyze(dyn, tau_max, tau_min, capacity=capacity), 8, samples=256)
        at_rest = pe.compare(
            pe.analyze(robot.model.dynamics(q), robot.tau_max, robot.tau_min, capacity=capacity),
            8,
            samples=256,
        )
        assert expected.to_markdown() in numbers, capacity
        assert at_rest.to_markdown() not in numbers, capacity


@pytest.mark.parametrize(
    ("qd", "capacities", "start"),
    [
        ("[1, 2]", '["acceleration"]', "points[0].qd: expected 3 joint velocities, got 2"),
        (
            "[1, 2, 3]",
            '["acceleration", "velocity"]',
            "compare.capacities: expected no 'velocity' with points in motion",
        ),
    ],
)
def test_points_in_motion_refused_with_the_key(tmp_path, qd, capacities, start):
    with pytest.raises(pe.InputError) as info:
        load_study(_moving(tmp_path, qd, capacities))
    assert str(info.value).startswith(start), str(info.value)


def test_a_planar_arm_point_cannot_move(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "p"\nq = [0.1, 0.2, 0.3]\n'
        "qd = [1, 0, 0]\n"
    )
    with pytest.raises(pe.InputError, match=r"points\[0\]\.qd: expected a URDF robot"):
        load_study(path)


# --- found by the third independent check (study files and the command line) ---------------

POINTS = """
[robot]
library = "chiacchio2000"
[[points]]
name = "p"
q = [0.3, 0.7, -1.1]
[compare]
capacities = {capacities}
directions = 8
samples = 64
mvie = false
outer = false
{extra}
[output]
formats = ["png"]
dpi = 20
{output}
"""


def _points_study(tmp_path, capacities, extra="", output=""):
    path = tmp_path / "study.toml"
    path.write_text(POINTS.format(capacities=capacities, extra=extra, output=output))
    return path


def test_output_sets_are_kept_per_capacity_and_checked_at_load(tmp_path):
    # "static" is a force set: the acceleration tables leave it out instead of refusing
    sets = 'sets = ["polytope", "static", "yoshikawa"]'
    path = _points_study(tmp_path, '["force", "acceleration"]', output=sets)
    run_study(load_study(path), tmp_path / "out")
    assert "no gravity" in (tmp_path / "out" / "comparison_force.tex").read_text()
    acceleration = (tmp_path / "out" / "comparison.tex").read_text()
    assert "no gravity" not in acceleration and "Yoshikawa" in acceleration
    path = _points_study(tmp_path, '["velocity"]', output='sets = ["polytope", "static"]')
    with pytest.raises(pe.InputError) as info:
        load_study(path)
    assert str(info.value).startswith("output.sets: expected sets among ['polytope', 'yoshikawa'")


def test_candidates_need_a_study_of_one_capacity(tmp_path):
    candidate = '[[candidates]]\nname = "c"\ncore = [[1e-3, 0], [0, 2e-3]]\ncenter = [0, -9.81]'
    path = tmp_path / "study.toml"
    path.write_text(
        POINTS.format(capacities='["velocity", "acceleration"]', extra="", output="") + candidate
    )
    with pytest.raises(pe.InputError) as info:
        load_study(path)
    assert str(info.value).startswith("candidates: expected a study of one capacity")


def test_moving_points_refuse_speeds_beyond_any_drive(tmp_path):
    path = _moving(tmp_path, qd="[0, 1e300, 0]")
    with pytest.raises(pe.InputError) as info:
        load_study(path)
    assert str(info.value).startswith("points[0].qd: expected joint velocities of at most 1e+06")


def test_a_posture_study_chooses_by_each_capacity(tmp_path):
    """The postures are sampled once; each capacity's choice is the API's over them."""
    path = tmp_path / "study.toml"
    path.write_text(
        '[robot]\nlibrary = "chiacchio2000"\n[posture]\nq0 = [1.5707963, -1.5707963, '
        '-1.5707963]\ndirection = "x"\ncount = 24\ntargets = 2\n[compare]\nmvie = false\n'
        'outer = false\ncapacities = ["acceleration", "velocity", "force"]\n'
        '[output]\nformats = ["svg", "html"]\n'
    )
    spec = load_study(path)
    out = tmp_path / "out"
    run_study(spec, out)
    arm = pe.robots.load("chiacchio2000")
    postures = pd.read_csv(out / "posture_values.csv")[["q1", "q2", "q3"]].to_numpy()
    for capacity, suffix, first in (
        ("acceleration", "", "Chiacchio"),
        ("velocity", "_velocity", "Yoshikawa"),
        ("force", "_force", "Chiacchio"),
    ):
        for name in ("posture_choice", "posture_targets"):
            for ending in (".md", ".tex", ".csv"):
                assert (out / f"{name}{suffix}{ending}").exists(), (capacity, name)
        assert (out / f"posture_indices{suffix}.svg").exists()
        values = pd.read_csv(out / f"posture_values{suffix}.csv")
        assert np.array_equal(values[["q1", "q2", "q3"]].to_numpy(), postures)  # one sampling
        choice = pe.posture_choice(
            arm, postures, direction=[1.0, 0.0], capacity=capacity, mvie=False, outer=False
        )
        for (kind, quantity), column in choice.values.items():
            np.testing.assert_allclose(
                values[f"{kind}_{quantity}"], column, rtol=1e-12, err_msg=f"{capacity} {kind}"
            )
        assert first in (out / f"posture_choice{suffix}.md").read_text()
    assert "force: The posture each index picks" in (out / "report.html").read_text()
