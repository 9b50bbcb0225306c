"""Each score against a value computed independently in the test."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest

import polyell as pe
from polyell.comparison.metrics import (
    enclosing_scale,
    inscribed_scale,
    overlap,
    witness_torque_max,
)
from polyell.comparison.tables import format_scores_table
from polyell.geometry.directions import sphere_directions
from polyell.geometry.mvie import max_volume_inscribed_ellipsoid
from reference import (
    PAPER_Q_REDUNDANT,
    PAPER_Q_SINGULAR,
    paper_analysis,
    random_directions,
    random_problem,
)


@pytest.fixture(scope="module")
def paper() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_REDUNDANT))


@pytest.fixture(scope="module")
def paper_singular() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_SINGULAR))


def scaled(E: pe.Ellipsoid, factor: float) -> pe.Ellipsoid:
    return pe.Ellipsoid(E.center, E.axes, factor * E.semi_axes)


def inscribed_scale_by_bisection(E: pe.Ellipsoid, P: pe.Polytope, points: int = 20000) -> float:
    """Largest k with every sampled boundary point of c + k (E - c) in P."""
    u = sphere_directions(points, E.rank)
    boundary = (u * E.semi_axes) @ E.axes.T
    lo, hi = 0.0, 10.0
    for _ in range(60):
        k = 0.5 * (lo + hi)
        lo, hi = (k, hi) if np.all(P.contains(E.center + k * boundary)) else (lo, k)
    return lo


def monte_carlo_overlap(E: pe.Ellipsoid, P: pe.Polytope, n: int, seed: int) -> tuple[float, float]:
    """Plain Monte Carlo in P's bounding box: (coverage, overreach) of a 2-D ellipsoid."""
    rng = np.random.default_rng(seed)
    low, high = P.vertices.min(axis=0), P.vertices.max(axis=0)
    e_low = E.center - E.semi_axes.max()
    e_high = E.center + E.semi_axes.max()
    low, high = np.minimum(low, e_low), np.maximum(high, e_high)
    x = rng.uniform(low, high, size=(n, 2))
    in_p, in_e = P.contains(x), E.contains(x)
    return (in_p & in_e).sum() / in_p.sum(), (in_e & ~in_p).sum() / in_e.sum()


@pytest.mark.parametrize("kind", ["chiacchio", "yoshikawa", "mvie"])
def test_inscribed_scale_equals_bisection(paper, kind):
    P = paper.analysis.polytope
    expected = inscribed_scale_by_bisection(paper.ellipsoid(kind), P)
    assert paper[kind].inscribed_scale == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("seed", range(4))
def test_inscribed_scale_in_three_dimensions(seed):
    analysis = random_problem(seed, 3, 5)
    E = analysis.ellipsoid("chiacchio")
    assert inscribed_scale(E, analysis.polytope) == pytest.approx(
        inscribed_scale_by_bisection(E, analysis.polytope), rel=1e-3
    )


@pytest.mark.parametrize("factor", [1.0, 1.3, 2.0])
def test_coverage_and_overreach_equal_monte_carlo(paper, factor):
    P = paper.analysis.polytope
    E = scaled(paper.ellipsoid("chiacchio"), factor)
    estimate = overlap(E, P, samples=2**13, seed=3)
    coverage, overreach = monte_carlo_overlap(E, P, 400_000, seed=11)
    # Plain MC on 4e5 points has a standard error below 2e-3 here.
    assert estimate.coverage == pytest.approx(coverage, abs=5e-3)
    assert estimate.overreach == pytest.approx(overreach, abs=5e-3)
    if factor == 1.0:  # inside: exact
        assert estimate.coverage_stderr == 0.0 and estimate.overreach == 0.0
    elif enclosing_scale(E, P) <= 1.0:  # around P (factor 2): exact, coverage 1
        assert estimate.coverage == 1.0 and estimate.overreach_stderr == 0.0
        assert estimate.overreach == pytest.approx(1.0 - P.volume / E.volume, rel=1e-12)
    else:
        assert 0 < estimate.coverage_stderr < 2e-3 and estimate.overreach > 0.01


def test_coverage_estimate_is_reproducible_and_seeded(paper):
    P = paper.analysis.polytope
    E = scaled(paper.ellipsoid("chiacchio"), 1.5)
    assert overlap(E, P, seed=5) == overlap(E, P, seed=5)
    assert overlap(E, P, seed=5) != overlap(E, P, seed=6)


def test_one_dimensional_overlap_is_exact(paper_singular):
    P = paper_singular.analysis.polytope
    E = scaled(paper_singular.ellipsoid("chiacchio"), 1.8)  # now longer than one side of P
    result = overlap(E, P)
    t = np.linspace(-1, 1, 200_001)
    points = E.center + np.outer(t * E.semi_axes[0], E.axes[:, 0])
    inside = P.contains(points).mean()
    assert result.overreach == pytest.approx(1 - inside, abs=1e-4)
    assert result.coverage == pytest.approx(inside * E.volume / P.volume, abs=1e-4)
    assert result.coverage_stderr == 0.0


def test_direction_errors_against_linear_programs(paper):
    analysis = paper.analysis
    T = sphere_directions(36, 2)
    cmp = pe.compare(analysis, T)
    hi_p = analysis.polytope.limits(T, method="lp").hi
    for kind in ("chiacchio", "yoshikawa"):
        hi_e = analysis.ellipsoid(kind).limits(T).hi
        error = (hi_e - hi_p) / np.abs(hi_p)
        record = cmp[kind]
        assert record.direction_error_mean == pytest.approx(np.mean(np.abs(error)), rel=1e-7)
        assert record.direction_error_max == pytest.approx(np.max(np.abs(error)), rel=1e-7)
        assert record.direction_error_rms == pytest.approx(np.sqrt(np.mean(error**2)), rel=1e-7)
        assert record.direction_bias == pytest.approx(np.mean(error), rel=1e-7)
        assert record.directions_used == 36 and record.feasibility_mismatch == 0


def test_feasibility_mismatch_counts_lines_that_miss_only_one_set():
    analysis = random_problem(1, 2, 3, gravity=3.0)
    T = random_directions(2, 200, 2)
    cmp = pe.compare(analysis, T, mvie=False)
    p, e = analysis.polytope.limits(T), analysis.ellipsoid("chiacchio").limits(T)
    expected = int(np.sum(p.feasible != e.feasible))
    assert expected > 0
    assert cmp["chiacchio"].feasibility_mismatch == expected
    assert cmp["chiacchio"].directions_used == int(np.sum(p.feasible & e.feasible))


@pytest.mark.parametrize("kind", ["chiacchio", "yoshikawa"])
def test_witness_torque_equals_the_maximum_over_sampled_boundary_points(paper, kind):
    analysis = paper.analysis
    E = analysis.ellipsoid(kind)
    u = sphere_directions(100_000, 2)
    boundary = E.center + (u * E.semi_axes) @ E.axes.T
    sampled = np.abs(analysis.inverse(boundary, kind=kind).tau_n).max()
    assert paper[kind].witness_torque_max == pytest.approx(sampled, rel=1e-6)


def test_witness_shows_the_classic_inverse_breaks_the_limits(paper):
    assert paper["chiacchio"].witness_torque_max <= 1.0 + 1e-12  # eq. 33 on its own boundary
    assert paper["yoshikawa"].witness_torque_max > 1.0


def test_witness_of_the_mvie_uses_the_minimum_torque_inverse(paper):
    expected = witness_torque_max(paper.mvie, paper.analysis.torque_map("chiacchio"))
    assert paper["mvie"].witness_torque_max == expected


# --- the maximum-volume inscribed ellipsoid ----------------------------------------------


def assert_is_the_mvie(E: pe.Ellipsoid, P: pe.Polytope) -> None:
    assert inscribed_scale(E, P) == pytest.approx(1.0, abs=1e-9)
    assert inscribed_scale(E, P) >= 1.0 - 1e-12  # inside P, exactly
    for i in range(E.rank):  # no enlargement along any axis fits
        bigger = E.semi_axes.copy()
        bigger[i] *= 1 + 1e-4
        assert inscribed_scale(pe.Ellipsoid(E.center, E.axes, bigger), P) < 1.0


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize(("m", "n", "rank"), [(2, 3, 2), (3, 5, 3), (3, 4, 2), (2, 3, 1)])
def test_mvie_is_inscribed_and_maximal(seed, m, n, rank):
    analysis = random_problem(seed, m, n, rank=rank)
    E = max_volume_inscribed_ellipsoid(analysis.polytope)
    assert E.rank == analysis.polytope.dim
    assert_is_the_mvie(E, analysis.polytope)
    assert E.volume >= analysis.ellipsoid("chiacchio").volume * (1 - 1e-9)


def test_mvie_of_a_box_is_the_inscribed_axis_aligned_ellipsoid():
    P = pe.Polytope(np.diag([3.0, 1.0, 2.0]), center=[1.0, 2.0, 3.0])
    E = max_volume_inscribed_ellipsoid(P)
    np.testing.assert_allclose(E.semi_axes, [3.0, 2.0, 1.0], rtol=1e-6)
    np.testing.assert_allclose(np.abs(E.axes), [[1, 0, 0], [0, 0, 1], [0, 1, 0]], atol=1e-6)


def test_mvie_of_a_segment_is_the_segment(paper_singular):
    P = paper_singular.analysis.polytope
    assert paper_singular.mvie.volume == pytest.approx(P.volume, rel=1e-12)
    assert paper_singular["mvie"].coverage == pytest.approx(1.0)


# --- records, directions and tables ------------------------------------------------------


def test_undefined_classic_ellipsoid_gives_a_record_that_says_so(paper_singular):
    record = paper_singular["yoshikawa"]
    assert not record.defined and "J J^T" in record.reason
    assert np.isnan(record.coverage) and np.isnan(record.inscribed_scale)
    assert paper_singular["chiacchio"].defined


def test_default_directions_lie_in_the_affine_set(paper_singular):
    T = paper_singular.directions
    assert T.shape == (2, 2)
    P = paper_singular.analysis.polytope
    np.testing.assert_allclose(P.affine_set.distance(T + P.center), 0, atol=1e-12)
    assert paper_singular["chiacchio"].directions_used == 2


def test_direction_arguments(paper):
    analysis = paper.analysis
    assert pe.compare(analysis, 12, mvie=False).directions.shape == (12, 2)
    assert pe.compare(analysis, [[0.0, 1.0]], mvie=False).directions.shape == (1, 2)
    with pytest.raises(pe.InputError, match="directions"):
        pe.compare(analysis, [[1.0, 1.0]])
    with pytest.raises(pe.InputError, match="positive number of directions"):
        pe.compare(analysis, 0)
    with pytest.raises(pe.InputError, match=r"pe\.analyze"):
        pe.compare("not an analysis")


def test_sphere_directions_are_unit_deterministic_and_balanced():
    for r, k in [(2, 360), (3, 1000), (4, 512)]:
        T = sphere_directions(k, r)
        assert T.shape == (k, r)
        np.testing.assert_allclose(np.linalg.norm(T, axis=1), 1.0)
        np.testing.assert_array_equal(T, sphere_directions(k, r))
        assert np.abs(T.mean(axis=0)).max() < 0.05
    np.testing.assert_allclose(
        sphere_directions(4, 2), [[1, 0], [0, 1], [-1, 0], [0, -1]], atol=1e-15
    )


def test_tables(paper, paper_singular):
    markdown = paper_singular.to_markdown()
    assert "| coverage [%]" in markdown and "n/a" in markdown
    assert "volume [m/s^2]" in markdown  # a segment: first power
    latex = paper.to_latex(caption="Scores at q = (pi/2, -pi/2, -pi/2).", label="tab:scores")
    for fragment in (r"\toprule", r"\midrule", r"\bottomrule", r"\label{tab:scores}", r"\caption{"):
        assert fragment in latex
    assert r"volume [(m/s$^{2}$)$^{2}$]" in latex
    frame = pd.read_csv(io.StringIO(paper.to_csv()), index_col="kind")
    for name in pe.SCORE_NAMES:
        np.testing.assert_allclose(frame.loc["chiacchio", name], getattr(paper["chiacchio"], name))


def test_mvie_of_a_panda_polytope_that_duplicate_facet_pairs_made_inaccurate():
    # Configuration 160 of studies/panda_random.toml: with both facets of every pair as
    # constraints, Clarabel stopped at "optimal_inaccurate" here.
    panda = pe.robots.load("panda")
    q = pe.random_configurations(300, *panda.position_limits, seed=2000).rows(160, 161)[0]
    cmp = pe.compare(pe.analyze(panda.dynamics(q), panda.tau_max), 64)
    assert cmp["mvie"].defined
    assert cmp["mvie"].inscribed_scale == pytest.approx(1.0, abs=1e-9)
    assert cmp["mvie"].volume >= cmp["chiacchio"].volume  # the largest inscribed one


def test_tables_show_a_negative_zero_as_zero_and_tiny_values_as_they_are(paper):
    frame = paper.to_frame()
    frame.loc["mvie", "direction_bias"] = -1e-12  # rounding noise about an exact 0
    frame.loc["chiacchio", "direction_bias"] = -0.0
    table = format_scores_table(frame, paper.analysis.rank, "markdown")
    row = next(line for line in table.splitlines() if line.startswith("| direction bias"))
    cells = [cell.strip() for cell in row.split("|")[2:-1]]
    assert cells[0] == "0" and cells[2] == "-1.00e-10"  # a fraction of -1e-12 in percent


def test_compare_without_mvie_is_explicit(paper):
    cmp = pe.compare(paper.analysis, mvie=False)
    assert not cmp["mvie"].defined and "mvie=False" in cmp["mvie"].reason
    assert np.isnan(cmp["chiacchio"].mvie_ratio)
    assert cmp["chiacchio"].coverage == paper["chiacchio"].coverage


def test_an_ellipsoid_touching_a_facet_is_inside_despite_rounding():
    # Regression: at a configuration where the new ellipsoid touches P, rounding gave an
    # inscribed scale of 1 - 6e-16 and sent coverage to a Monte Carlo estimate.
    P = pe.Polytope(np.eye(2), center=[0.0, 0.0])  # the square [-1, 1]^2
    E = pe.Ellipsoid([0.0, 0.0], np.eye(2), [1.0 + 4e-16, 1.0])
    assert inscribed_scale(E, P) < 1.0
    result = overlap(E, P)
    assert result.coverage == pytest.approx(np.pi / 4) and result.coverage_stderr == 0.0
    assert result.overreach == 0.0


# --- Issue 20: weak torques, thin polytopes, argument checks.


@pytest.mark.parametrize("exponent", [-7, -4, 0, 4, 8])
def test_the_new_ellipsoids_witness_is_at_most_one_however_weak_the_torques(exponent):
    """tau_n = M^# (x - xg) on the new ellipsoid: |tau_n|_2 <= 1 whatever gravity does.

    Torque limits scaled by 10^exponent with the gravity torques unchanged: the set moves
    far from the origin (1e7 of its size at -7); the witness is computed about the centre,
    so it keeps its digits (bound: 1 + the rounding of |V_1 u|, a few eps).
    """
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    dyn, tau = analysis.dynamics, analysis.tau_max * 10.0**exponent
    weak = pe.compare(pe.analyze(dyn, tau), 16, samples=256)
    reference = pe.compare(analysis, 16, samples=256)
    for kind in ("chiacchio", "mvie", "outer"):  # each a shape of M alone, mapped by M^#
        assert weak[kind].witness_torque_max == pytest.approx(
            reference[kind].witness_torque_max, rel=1e-7
        )
    assert weak["chiacchio"].witness_torque_max <= 1.0 + 1e-12


def test_a_polytope_below_the_resolution_of_its_own_points_is_refused():
    analysis = paper_analysis(PAPER_Q_REDUNDANT)
    from polyell.validation import MIN_RELATIVE_EXTENT

    with pytest.raises(pe.InputError, match="free-fall acceleration") as info:
        pe.analyze(analysis.dynamics, analysis.tau_max * 1e-16)
    assert info.value.argument == "tau_max" and MIN_RELATIVE_EXTENT < 1e-7


@pytest.mark.parametrize("delta", [1e-3, 1e-5, 1e-7, 1e-8])
def test_touching_ellipsoids_of_thin_polytopes_are_exact_without_monte_carlo(delta):
    """Near the stretched posture (cond(M) up to 6e7) the MVIE and the outer ellipsoid touch
    P to the rounding bound of their scales, never to a fixed 1e-9: their coverage is
    exactly 1 (outer) and vol(E)/vol(P) (MVIE), with no standard error."""
    from polyell.comparison.metrics import inside_rtol

    analysis = paper_analysis(np.array([0.3, delta, -delta]))
    result = pe.compare(analysis, 16, samples=256)
    P = analysis.polytope
    for kind in ("mvie", "outer"):
        E = result.ellipsoid(kind)
        tolerance = inside_rtol(E, P)
        scale = inscribed_scale(E, P) if kind == "mvie" else enclosing_scale(E, P)
        assert abs(scale - 1.0) <= tolerance
        assert result[kind].coverage_stderr == 0.0 and result[kind].overreach_stderr == 0.0
    assert result["outer"].coverage == 1.0
    assert result["mvie"].overreach == 0.0


@pytest.mark.parametrize("samples", [0, 1, -1, 2.5, 2**40, "8", None, True])
def test_compare_refuses_a_wrong_sample_count(paper, samples):
    with pytest.raises(pe.InputError, match="samples"):
        pe.compare(paper.analysis, 8, samples=samples)


@pytest.mark.parametrize("seed", ["a", 1.5, None, -1, [1]])
def test_compare_refuses_a_wrong_seed(paper, seed):
    with pytest.raises(pe.InputError, match="seed"):
        pe.compare(paper.analysis, 8, seed=seed)


def test_any_sample_count_draws_without_a_warning(paper):
    """1000 points: the first 1000 of a 1024-point Sobol' draw (no balance warning)."""
    import warnings

    E, P = scaled(paper.analysis.ellipsoid("chiacchio"), 1.5), paper.analysis.polytope
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        shares = overlap(E, P, samples=1000, seed=3)
    assert 0.0 < shares.coverage <= 1.0 and shares.coverage_stderr > 0
