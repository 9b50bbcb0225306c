"""User-defined candidates (issue 12, part 4): weighted and core-defined ellipsoids, scored
like the built-in ones in compare, sweeps, tables and study files."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import polyell as pe
from polyell.studies import load_study, run_study
from reference import PAPER_ARM, PAPER_TAU_MAX, paper_analysis, random_problem, random_spd

Q = np.array([0.3, 0.9, -0.7])


def test_identity_weighting_is_the_new_ellipsoid():
    analysis = paper_analysis(Q)
    cmp = pe.compare(analysis, 64, candidates=[pe.Candidate("plain", weighting=np.eye(3))])
    new, plain = cmp["chiacchio"].as_dict(), cmp["plain"].as_dict()
    for name in pe.SCORE_NAMES:
        assert plain[name] == pytest.approx(new[name], rel=1e-12, abs=1e-15), name


@pytest.mark.parametrize("seed", range(3))
def test_weighted_candidate_is_the_set_reachable_with_the_weighted_torques(seed):
    """Boundary torques tau^T W tau = 1 map onto E's boundary, and E's boundary points come
    from such torques (the minimum-W-norm preimage has W-norm exactly 1)."""
    rng = np.random.default_rng(seed)
    analysis = random_problem(seed, 3, 6)
    W = random_spd(rng, 6, condition=30.0)
    E = pe.Candidate("w", weighting=W).ellipsoid(analysis)
    L = np.linalg.cholesky(W)
    u = rng.normal(size=(200, 6))
    tau = np.linalg.solve(L.T, (u / np.linalg.norm(u, axis=1, keepdims=True)).T).T
    np.testing.assert_allclose(np.einsum("ki,ij,kj->k", tau, W, tau), 1.0, rtol=1e-12)
    norms = np.linalg.norm(((tau @ analysis.M.T) @ E.axes) / E.semi_axes, axis=1)
    assert norms.max() <= 1 + 1e-9  # every such torque lands in E
    boundary = E.center + (rng.normal(size=(50, 3)) @ np.diag(E.semi_axes)) @ E.axes.T
    x = boundary - analysis.xg
    x = x / np.linalg.norm((x @ E.axes) / E.semi_axes, axis=1, keepdims=True)
    Winv = np.linalg.inv(W)  # min tau^T W tau s.t. M tau = x: tau = W^-1 M^T (M W^-1 M^T)^-1 x
    tau = (Winv @ analysis.M.T @ np.linalg.solve(analysis.M @ Winv @ analysis.M.T, x.T)).T
    np.testing.assert_allclose(np.einsum("ki,ij,kj->k", tau, W, tau), 1.0, rtol=1e-9)


def test_core_candidate_at_full_rank_is_that_ellipsoid():
    analysis = paper_analysis(Q)
    core, center = np.array([[2e-3, 5e-4], [5e-4, 1e-3]]), analysis.xg + np.array([1.0, -2.0])
    E = pe.Candidate("mine", core=core, center=center).ellipsoid(analysis)
    reference = pe.Ellipsoid.from_core(center, core)
    np.testing.assert_allclose(E.core, reference.core, rtol=1e-12)
    np.testing.assert_allclose(E.center, center, rtol=1e-12)
    cmp = pe.compare(analysis, 64, candidates=[pe.Candidate("mine", core=core, center=center)])
    assert cmp["mine"].volume == pytest.approx(reference.volume, rel=1e-12)
    # an off-centre ellipsoid's inscribed scale: against bisection on its shrunk copies
    assert cmp["mine"].inscribed_scale == pytest.approx(
        pe.comparison.metrics.inscribed_scale(reference, analysis.polytope), rel=1e-12
    )


def test_core_candidate_at_a_singular_configuration_is_its_section():
    """At q2 = q3 = 0 the reachable set is a segment: the candidate is cut to it; points of
    the section have core norm at most 1 and its end points exactly 1."""
    analysis = pe.analyze(PAPER_ARM.dynamics([np.pi / 6, 0.0, 0.0]), tau_max=PAPER_TAU_MAX)
    core = np.array([[1e-3, 2e-4], [2e-4, 4e-3]])
    center = analysis.xg + analysis.svd.U1[:, 0] * 3.0 + np.array([-0.2, 0.1])
    E = pe.Candidate("cut", core=core, center=center).ellipsoid(analysis)
    assert E.rank == 1
    ends = E.center + np.outer([-1.0, 1.0], E.semi_axes[0] * E.axes[:, 0])
    assert np.all(analysis.polytope.affine_set.distance(ends) < 1e-9)
    np.testing.assert_allclose(np.einsum("ki,ij,kj->k", ends - center, core, ends - center), 1.0)
    far = pe.Candidate("far", core=core * 1e4, center=analysis.xg + np.array([50.0, 50.0]))
    cmp = pe.compare(analysis, 16, candidates=[far])
    assert not cmp["far"].defined and "misses" in cmp["far"].reason


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"name": "MVIE", "weighting": np.eye(3)}, "lower-case identifier"),
        ({"name": "a b", "weighting": np.eye(3)}, "lower-case identifier"),
        ({"name": "outer", "weighting": np.eye(3)}, "a name other than"),
        ({"name": "polytope", "core": np.eye(2)}, "a name other than"),
        ({"name": "x"}, "exactly one of"),
        ({"name": "x", "weighting": np.eye(3), "core": np.eye(2)}, "exactly one of"),
        ({"name": "x", "weighting": -np.eye(3)}, "positive-definite"),
        ({"name": "x", "weighting": [[1.0, 2.0], [0.0, 1.0]]}, "symmetric"),
        ({"name": "x", "weighting": np.ones((2, 3))}, "square"),
        ({"name": "x", "core": [[1.0, np.nan], [np.nan, 1.0]]}, "NaN"),
        ({"name": "x", "core": np.eye(2), "center": [0.0]}, "center"),
        ({"name": "x", "weighting": np.eye(3), "center": [0.0, 0.0]}, "no center"),
    ],
)
def test_bad_candidates_are_refused_with_the_argument_named(arguments, message):
    with pytest.raises(pe.InputError, match=message):
        pe.Candidate(**arguments)


def test_wrong_sizes_and_repeated_names_are_refused():
    analysis = paper_analysis(Q)
    with pytest.raises(pe.InputError, match=r"w.weighting.*\(3, 3\)"):
        pe.compare(analysis, 8, candidates=[pe.Candidate("w", weighting=np.eye(4))])
    with pytest.raises(pe.InputError, match=r"c.core.*\(2, 2\)"):
        pe.compare(analysis, 8, candidates=[pe.Candidate("c", core=np.eye(3))])
    twice = [pe.Candidate("a", weighting=np.eye(3)), pe.Candidate("a", core=np.eye(2))]
    with pytest.raises(pe.InputError, match="distinct names"):
        pe.compare(analysis, 8, candidates=twice)
    with pytest.raises(pe.InputError, match="candidates"):
        pe.sweep(PAPER_ARM, [Q], PAPER_TAU_MAX, candidates=["a"])
    with pytest.raises(pe.InputError, match=r"w.weighting"):
        pe.sweep(PAPER_ARM, [Q], PAPER_TAU_MAX, candidates=[pe.Candidate("w", weighting=np.eye(2))])


def test_sweep_with_candidates_equals_compare_row_by_row():
    """Inside P (a heavy weighting), around it (a large ball, exact overreach) and neither
    (an off-centre core: the scalar path, Monte Carlo there) at random Panda configurations."""
    panda = pe.robots.load("panda")
    low, high = panda.position_limits
    q = pe.random_configurations(12, low, high, seed=3).rows(0, 12)
    candidates = [
        pe.Candidate("heavy_wrist", weighting=np.diag([1, 1, 1, 1, 4, 4, 4.0])),
        pe.Candidate("ball", core=np.eye(3) * 1e-8),
        pe.Candidate("shifted", core=np.eye(3) * 1e-3, center=[0.0, 0.0, -9.81]),
    ]
    frame = pe.sweep(
        panda,
        q,
        candidates=candidates,
        scores=pe.SCORE_NAMES[:-3],
        directions=16,
        mvie=True,
        outer=True,
    )
    assert frame["ball_coverage"].eq(1.0).all()  # around every P: exact
    for k in range(len(q)):
        expected = pe.compare(
            pe.analyze(panda.dynamics(q[k]), panda.tau_max), 16, candidates=candidates
        ).to_row()
        for name in frame.columns.intersection(list(expected)):
            rtol = 1e-7 if "mvie" in name or "outer" in name else 1e-9
            np.testing.assert_allclose(
                frame[name][k], expected[name], rtol=rtol, atol=1e-12, err_msg=f"{name} at {k}"
            )


STUDY = """
title = "candidates"
[robot]
planar = { lengths = [1.0, 0.8, 0.5], masses = [4.0, 2.0, 0.6], com = [0.5, 0.4, 0.25] }
tau_max = [100, 30, 4]
[[points]]
name = "p"
q = [0.3, 0.9, -0.7]
[compare]
directions = 64
[[candidates]]
name = "heavy_elbow"
weighting = [1, 4, 1]
[[candidates]]
name = "ball"
core = [[1e-3, 0], [0, "1e-3"]]
center = [0, -9.81]
[output]
formats = ["png"]
dpi = 40
"""


def test_study_file_candidates_appear_in_every_output(tmp_path):
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    spec = load_study(path)
    assert [c.name for c in spec.candidates] == ["heavy_elbow", "ball"]
    np.testing.assert_array_equal(spec.candidates[0].weighting, np.diag([1.0, 4.0, 1.0]))
    run_study(spec, tmp_path / "out")
    table = (tmp_path / "out" / "comparison.md").read_text()
    assert r"heavy\_elbow" in table and "ball" in table and "outer (min. volume)" in table
    assert r"heavy\_elbow" in (tmp_path / "out" / "comparison.tex").read_text()
    expected = pe.compare(
        paper_analysis(Q),
        64,
        candidates=[pe.Candidate("heavy_elbow", weighting=np.diag([1, 4, 1.0]))],
    )
    assert f"{100 * expected['heavy_elbow'].coverage:.3g}" in table


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[[candidates]]\nweighting = [1, 1, 1]\n", "a 'name'"),
        ('[[candidates]]\nname = "a"\nweight = [1, 1, 1]\n', "keys among"),
        ('[[candidates]]\nname = "Bad"\nweighting = [1, 1, 1]\n', "lower-case identifier"),
        ('[[candidates]]\nname = "a"\nweighting = [[1, 2], [3]]\n', r"2 rows of 2 numbers"),
        ('[[candidates]]\nname = "a"\nweighting = {x = 1}\n', "a list"),
        ('[[candidates]]\nname = "a"\nweighting = [1e400, 1, 1]\n', "finite"),
        (
            '[[candidates]]\nname = "a"\nweighting = [1, "x", 1]\n',
            r"candidates\[0\].weighting\[1\]",
        ),
        (
            '[[candidates]]\nname = "a"\nweighting = [1, 1, 1]\n[[candidates]]\nname = "a"\n'
            "core = [1, 1]\n",
            "distinct names",
        ),
    ],
)
def test_bad_study_candidates_are_refused(tmp_path, text, message):
    path = tmp_path / "study.toml"
    path.write_text(STUDY.split("[[candidates]]")[0] + text)
    with pytest.raises(pe.InputError, match=message):
        load_study(path)


@pytest.mark.parametrize("entry", [1e-300, 1e300, 1e308])
def test_a_core_singular_in_double_precision_is_refused_without_a_warning(entry):
    # Found by the independent check (issue 20): eigenvalues of 0 or below divided by.
    arm = pe.robots.load("chiacchio2000")
    an = pe.analyze(arm.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), arm.tau_max)
    candidate = pe.Candidate("c", core=[[entry, 0.0], [0.0, 1e-3]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(pe.InputError, match=r"c\.core"):
            pe.compare(an, 10, mvie=False, outer=False, candidates=[candidate])


def test_a_core_candidate_at_an_unbounded_force_set(recwarn):
    # The paper's arm stretched (q2 = q3 = 0): the force set is unbounded along the arm.
    # The candidate is scored (no MVIE to compare with: its ratio is NaN, not an error that
    # stopped a study), and along the unbounded directions it states none of the set: a
    # relative error of -1 (the limit of (e - p) / |p|), without a RuntimeWarning.
    arm = pe.robots.load("chiacchio2000")
    analysis = pe.analyze(arm.dynamics([np.pi / 2, 0.0, 0.0]), arm.tau_max, capacity="force")
    assert not analysis.polytope.is_bounded
    candidate = pe.Candidate("round", core=np.eye(2) * 400.0)
    T = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    scores = pe.compare(analysis, T, candidates=[candidate])["round"]
    assert scores.defined and np.isnan(scores.mvie_ratio) and scores.coverage == 0.0
    hi = analysis.polytope.limits(T).hi
    assert np.isinf(hi).any()
    errors = pe.comparison.metrics.relative_error(np.full(len(T), 0.05), hi)
    np.testing.assert_array_equal(errors[np.isinf(hi)], -1.0)
    assert scores.direction_error_max >= 1.0 - 1e-12  # the unbounded directions count
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]
