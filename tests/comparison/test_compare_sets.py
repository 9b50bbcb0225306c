"""``pe.compare`` of a bare set: each score against an independent computation."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from numpy.typing import NDArray
from scipy.optimize import linprog
from scipy.special import gammaln
from scipy.stats import special_ortho_group

import polyell as pe
from polyell.comparison.set_comparison import SET_SCORE_NAMES, SetComparison, SetScores
from polyell.geometry.combine import in_frame, intersection, minkowski_sum
from polyell.geometry.directions import sphere_directions
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis, random_problem

Array = NDArray[np.float64]


def same_record(a: pe.Scores | SetScores, b: SetScores, rtol: float = 1e-9) -> None:
    """Every score of ``b`` equal to ``a``'s (NaN to NaN), to ``rtol``."""
    for name in SET_SCORE_NAMES:
        x, y = float(getattr(a, name)), float(getattr(b, name))
        if math.isnan(x) or math.isnan(y):
            assert math.isnan(x) and math.isnan(y), name
        else:
            assert y == pytest.approx(x, rel=rtol, abs=1e-12), name


def ball_volume(r: int) -> float:
    return float(np.exp(0.5 * r * np.log(np.pi) - gammaln(0.5 * r + 1)))


def inscribed_scale_by_bisection(E: pe.Ellipsoid, A: Array, b: Array, points: int) -> float:
    """Largest k with every sampled boundary point of c + k (E - c) in {A x <= b}."""
    u = sphere_directions(points, E.rank)
    boundary = (u * E.semi_axes) @ E.axes.T
    lo, hi = 0.0, 10.0
    for _ in range(60):
        k = 0.5 * (lo + hi)
        inside = np.all((E.center + k * boundary) @ A.T <= b, axis=1).all()
        lo, hi = (k, hi) if inside else (lo, k)
    return lo


def uniform_in(E: pe.Ellipsoid, count: int, seed: int) -> Array:
    """Points uniform in a full-dimensional ellipsoid (exact sampler)."""
    rng = np.random.default_rng(seed)
    r = E.rank
    g = rng.normal(size=(count, r))
    u = g / np.linalg.norm(g, axis=1)[:, None] * rng.uniform(size=(count, 1)) ** (1.0 / r)
    return np.asarray(E.center + (u * E.semi_axes) @ E.axes.T)


def force_set(seed: int, m: int, n: int) -> pe.HPolytope:
    """A random arm's force set, gravity well within the limits: bounded, not empty."""
    P = random_problem(seed, m, n, gravity=0.3, capacity="force").polytope
    assert isinstance(P, pe.HPolytope) and P.is_bounded and not P.is_empty
    return P


# --- the same set as an analysis's polytope: the same records ---------------------------


@pytest.mark.parametrize(
    ("capacity", "m", "n", "seed"),
    [
        ("acceleration", 2, 3, 1),
        ("acceleration", 3, 5, 2),
        ("velocity", 3, 4, 3),
        ("force", 2, 3, 4),
        ("force", 3, 4, 5),
        ("force", 4, 6, 6),
    ],
)
def test_an_analysis_polytope_scores_as_the_analysis(
    capacity: str, m: int, n: int, seed: int
) -> None:
    """MVIE, outer and a given ellipsoid (the capacity's own) score as in compare(analysis)."""
    an = random_problem(seed, m, n, gravity=0.3, capacity=capacity)
    kind = an.ellipsoid_kinds[0]
    by_analysis = pe.compare(an, 64)
    by_set = pe.compare(an.polytope, 64, ellipsoids={"own": an.ellipsoid(kind)})
    assert isinstance(by_set, SetComparison)
    assert by_set.kinds == ("mvie", "outer", "own")
    for name in ("mvie", "outer"):
        assert by_set[name].defined
        same_record(by_analysis[name], by_set[name])
    same_record(by_analysis[kind], by_set["own"])
    np.testing.assert_array_equal(by_set.directions, by_analysis.directions)


def test_a_singular_analysis_polytope_a_segment_scores_as_the_analysis() -> None:
    """At the paper's singular posture the set is a segment in 2-D: scored on its line."""
    an = paper_analysis(PAPER_Q_SINGULAR)
    assert an.polytope.dim == 1
    by_analysis = pe.compare(an)
    by_set = pe.compare(an.polytope, ellipsoids={"own": an.ellipsoid("chiacchio")})
    for ours, theirs in (("mvie", "mvie"), ("outer", "outer"), ("own", "chiacchio")):
        same_record(by_analysis[theirs], by_set[ours])
    assert by_set["mvie"].dimension == 1.0


def test_an_ellipsoid_given_to_an_analysis_scores_as_the_built_in_one() -> None:
    """Given to compare(analysis), the new ellipsoid scores as "chiacchio", witness too.

    (Its witness is the minimum-norm inverse, eq. 33/40: the new ellipsoid's own.)
    """
    an = paper_analysis(PAPER_Q_REDUNDANT)
    cmp = pe.compare(an, ellipsoids={"given": an.ellipsoid("chiacchio")})
    assert cmp.kinds[-1] == "given"
    same_record(cmp["chiacchio"], cmp["given"], rtol=1e-12)
    assert cmp["given"].witness_torque_max == pytest.approx(
        cmp["chiacchio"].witness_torque_max, rel=1e-12
    )
    with pytest.raises(pe.InputError, match="other than"):
        pe.compare(an, ellipsoids={"yoshikawa": an.ellipsoid("chiacchio")})


def test_an_independently_built_h_polytope_has_the_same_optimum_ellipsoids() -> None:
    """The force set rebuilt from its facets alone (another centre, another walk).

    The MVIE and the outer ellipsoid are certified to a gap of 1e-8 in log det: their
    volumes agree to about that, the scale of one in the other's set to about 1e-8.
    """
    an = random_problem(7, 3, 5, capacity="force")
    P = an.polytope
    rebuilt = pe.HPolytope(P.A, P.b)  # Chebyshev centre, not the least-residual force
    assert np.abs(rebuilt.center - P.center).max() > 1e-3
    reference, ours = pe.compare(an), pe.compare(rebuilt)
    for kind in ("mvie", "outer"):
        assert ours[kind].volume == pytest.approx(reference[kind].volume, rel=1e-7)
        assert ours[kind].coverage == pytest.approx(reference[kind].coverage, rel=1e-7)
    assert ours["mvie"].inscribed_scale == pytest.approx(1.0, abs=1e-9)
    assert ours["outer"].enclosing_scale == pytest.approx(1.0, abs=1e-9)


# --- given ellipsoids: scale by brute force, coverage by Monte Carlo ----------------------


def test_a_given_ellipsoid_inscribed_scale_matches_bisection_and_an_lp() -> None:
    P = force_set(8, 2, 3)
    rng = np.random.default_rng(9)
    axes = special_ortho_group.rvs(2, random_state=10)
    size = P.extent
    E = pe.Ellipsoid(P.center + 0.05 * size * rng.normal(size=2), axes, [0.5 * size, 0.2 * size])
    cmp = pe.compare(P, ellipsoids={"mine": E})
    # bisection on 20,000 boundary points against the facets
    k = inscribed_scale_by_bisection(E, P.A, P.b, 20000)
    assert cmp["mine"].inscribed_scale == pytest.approx(k, rel=1e-6)
    # an LP per facet: the reach of E - c along a_i, max a_i . x over a 4,000-gon
    # inscribed in E (within 1 - cos(pi / 4000) = 3e-7 of the ellipse's), then min over
    # the facets of slack / reach
    polygon = E.center + (sphere_directions(4000, 2) * E.semi_axes) @ E.axes.T
    scales = []
    for a, b in zip(P.A, P.b, strict=True):
        result = linprog(
            -(polygon @ a),
            A_eq=np.ones((1, len(polygon))),
            b_eq=[1.0],
            bounds=(0, 1),
            method="highs",
        )
        assert result.success
        scales.append((b - a @ E.center) / (-result.fun - a @ E.center))
    assert cmp["mine"].inscribed_scale == pytest.approx(min(scales), rel=1e-6)


@pytest.mark.parametrize(("m", "n", "seed"), [(2, 3, 11), (3, 4, 12)])
def test_coverage_and_overreach_of_a_crossing_ellipsoid_by_monte_carlo(
    m: int, n: int, seed: int
) -> None:
    """An ellipsoid leaving the set: vol(E & P) / vol(P) and vol(E \\ P) / vol(E) by sampling."""
    P = force_set(seed, m, n)
    mvie = pe.compare(P, outer=False).mvie
    E = pe.Ellipsoid(mvie.center, mvie.axes, 1.35 * mvie.semi_axes)
    cmp = pe.compare(P, ellipsoids={"wide": E}, samples=2**14, seed=3)
    record = cmp["wide"]
    assert record.inscribed_scale < 1.0 < record.enclosing_scale  # it crosses the boundary
    count = 400_000
    x = uniform_in(E, count, seed)
    inside = np.all(x @ P.A.T <= P.b, axis=1).mean()
    overreach = 1.0 - inside
    coverage = inside * E.volume / P.volume
    sigma = math.sqrt(inside * (1.0 - inside) / count)  # binomial standard error
    tolerance = 5.0 * math.hypot(sigma, record.overreach_stderr)
    assert record.overreach == pytest.approx(overreach, abs=tolerance)
    assert record.coverage == pytest.approx(coverage, abs=tolerance * E.volume / P.volume)
    assert record.volume == pytest.approx(ball_volume(m) * np.prod(E.semi_axes), rel=1e-12)


def test_a_core_defined_candidate_scores_as_the_same_ellipsoid_given() -> None:
    P = force_set(13, 3, 4)
    N = np.diag([1.0, 2.0, 3.0]) / P.extent**2
    c = P.center + 0.01 * P.extent
    candidate = pe.Candidate("cand", core=N, center=c)
    w, V = np.linalg.eigh(N)
    E = pe.Ellipsoid(c, V, 1.0 / np.sqrt(w))
    cmp = pe.compare(P, candidates=[candidate], ellipsoids={"same": E})
    assert cmp.kinds == ("mvie", "outer", "cand", "same")
    same_record(cmp["same"], cmp["cand"], rtol=1e-9)


# --- two arms: the sum and the intersection, with base poses ---------------------------


def test_two_arm_sum_with_base_poses_scores_its_own_optimum_and_chebyshev_ball() -> None:
    """The sum of two rotated 3-D force sets; the largest ball inside it by an LP."""
    P1, P2 = force_set(14, 3, 4), force_set(15, 3, 5)
    R1 = special_ortho_group.rvs(3, random_state=16)
    R2 = special_ortho_group.rvs(3, random_state=17)
    S = minkowski_sum(in_frame(P1, R1), in_frame(P2, R2))
    # Chebyshev ball of S by an LP on its facets: max t s.t. a_i . x + t <= b_i
    lp = linprog(
        np.r_[np.zeros(3), -1.0],
        A_ub=np.column_stack([S.A, np.ones(len(S.A))]),
        b_ub=S.b,
        bounds=[(None, None)] * 3 + [(0, None)],
        method="highs",
    )
    assert lp.success
    x0, radius = lp.x[:3], lp.x[3]
    ball = pe.Ellipsoid(x0, np.eye(3), [radius] * 3)
    cmp = pe.compare(S, ellipsoids={"ball": ball}, unit="N")
    assert cmp["ball"].inscribed_scale == pytest.approx(1.0, abs=1e-6)  # HiGHS tolerances
    assert cmp["mvie"].inscribed_scale == pytest.approx(1.0, abs=1e-9)
    assert cmp["outer"].enclosing_scale == pytest.approx(1.0, abs=1e-9)
    assert cmp["outer"].coverage == 1.0
    # the ball is no larger than the MVIE; John: the outer is within 3^3 of the MVIE's volume
    assert cmp["ball"].mvie_ratio <= 1.0 + 1e-7
    assert 1.0 < cmp["outer"].mvie_ratio <= 27.0
    # directional statistics use every default direction (a bounded set with the origin in)
    assert cmp["ball"].directions_used == len(cmp.directions) == 256


def test_scores_do_not_depend_on_the_common_frame() -> None:
    """Rotating a set and its ellipsoid changes no score (all are rigid-motion invariant)."""
    P = force_set(18, 3, 4)
    R = special_ortho_group.rvs(3, random_state=19)
    E = pe.Ellipsoid(P.center, np.eye(3), [0.3 * P.extent, 0.2 * P.extent, 0.1 * P.extent])
    turned = pe.Ellipsoid(R @ E.center, R @ E.axes, E.semi_axes)
    directions = sphere_directions(200, 3)
    a = pe.compare(P, directions, ellipsoids={"e": E})
    b = pe.compare(in_frame(P, R), directions @ R.T, ellipsoids={"e": turned})
    for kind in ("mvie", "outer", "e"):
        same_record(a[kind], b[kind], rtol=1e-6)  # the optima: certified to 1e-8


def test_a_wrench_sum_at_two_base_poses_in_6d_is_scored() -> None:
    """Two 6-D wrench sets moved by their adjoints, added: MVIE and outer touch the sum."""
    P1, P2 = force_set(20, 6, 6), force_set(21, 6, 6)
    R1 = special_ortho_group.rvs(3, random_state=22)
    R2 = special_ortho_group.rvs(3, random_state=23)
    S = minkowski_sum(in_frame(P1, R1, [0.4, 0.0, 0.0]), in_frame(P2, R2, [-0.4, 0.0, 0.0]))
    cmp = pe.compare(S, 300)
    assert cmp["mvie"].inscribed_scale == pytest.approx(1.0, abs=1e-9)
    assert cmp["outer"].enclosing_scale == pytest.approx(1.0, abs=1e-9)
    # John's theorem in 6-D: vol(outer) / vol(MVIE) <= 6^6
    assert 1.0 < cmp["outer"].mvie_ratio <= 6.0**6
    # lines through the origin: those that miss the sum are counted, not scored
    record = cmp["mvie"]
    assert record.directions_used > 0
    assert record.directions_used + record.feasibility_mismatch <= 300


def test_an_intersection_is_scored() -> None:
    P1, P2 = force_set(24, 2, 3), force_set(25, 2, 3)
    both = intersection(P1, pe.HPolytope(P2.A, P2.b + P2.A @ (P1.center - P2.center)))
    cmp = pe.compare(both)
    assert cmp["mvie"].inscribed_scale == pytest.approx(1.0, abs=1e-9)
    assert cmp["outer"].coverage == 1.0


def test_a_flat_set_in_3d_is_scored_in_its_plane() -> None:
    """A square in the plane z = 0.5 of R^3: a lower-dimensional set, compared in its plane."""
    A = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    square = pe.HPolytope(A, [1, 1, 1, 1, 0.5, -0.5])
    assert square.dim == 2
    disc = pe.Ellipsoid([0, 0, 0.5], [[1, 0], [0, 1], [0, 0]], [1.0, 1.0])
    cmp = pe.compare(square, ellipsoids={"disc": disc})
    assert cmp["disc"].inscribed_scale == pytest.approx(1.0, abs=1e-12)
    assert cmp["disc"].coverage == pytest.approx(np.pi / 4, rel=1e-12)
    assert cmp["mvie"].volume == pytest.approx(np.pi, rel=1e-7)  # the inscribed disc
    assert cmp["outer"].volume == pytest.approx(2 * np.pi, rel=1e-7)  # radius sqrt(2)


# --- the outputs: no witness column, files in tmp_path ---------------------------------


def test_tables_and_files_have_no_witness(tmp_path) -> None:  # type: ignore[no-untyped-def]
    P = paper_analysis(PAPER_Q_REDUNDANT).polytope
    cmp = pe.compare(P, unit="m/s^2")
    frame = cmp.to_frame()
    assert "witness_torque_max" not in frame.columns
    assert not any("witness" in key for key in cmp.to_row())
    assert not hasattr(cmp["mvie"], "witness_torque_max")
    assert "witness" not in cmp.to_markdown()
    assert r"\begin{tabular}" in cmp.to_latex()
    path = tmp_path / "scores.csv"
    cmp.to_csv(path)
    back = pd.read_csv(path, index_col="kind")
    np.testing.assert_allclose(back["volume"].to_numpy(), frame["volume"].to_numpy(), rtol=1e-15)
    table = cmp.limits_table(["x", "y"])
    assert table["set"].tolist()[:3] == ["polytope", "mvie", "outer"]
    assert set(table["unit"]) == {"m/s^2"}
    hi = P.limits(np.array([1.0, 0.0])).hi
    assert float(table.loc[0, "upper"]) == pytest.approx(float(hi), rel=1e-15)


def test_mvie_off_gives_an_undefined_record_with_a_reason() -> None:
    P = force_set(26, 2, 3)
    cmp = pe.compare(P, mvie=False)
    assert not cmp["mvie"].defined and "mvie=False" in cmp["mvie"].reason
    assert math.isnan(cmp["outer"].mvie_ratio)
    assert cmp["outer"].defined


# --- refused input -----------------------------------------------------------------------


def test_an_unbounded_set_is_refused_naming_the_argument() -> None:
    strip = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0]], [1.0, 1.0])
    with pytest.raises(pe.InputError, match="unbounded") as caught:
        pe.compare(strip)
    assert caught.value.argument == "analysis"
    assert "intersection" in caught.value.fix


def test_empty_and_point_sets_are_refused() -> None:
    empty = pe.HPolytope([[1.0, 0.0], [-1.0, 0.0], [0, 1], [0, -1]], [-1.0, 0.0, 1, 1])
    with pytest.raises(pe.InputError, match="empty"):
        pe.compare(empty)
    point = pe.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.zeros(4))
    with pytest.raises(pe.PolyellError):
        pe.compare(point)


def test_wrong_types_are_refused_naming_the_argument() -> None:
    P = force_set(27, 2, 3)
    with pytest.raises(pe.InputError) as caught:
        pe.compare(P.A)  # type: ignore[call-overload]
    assert caught.value.argument == "analysis"
    with pytest.raises(pe.InputError) as caught:
        pe.compare(P, ellipsoids=[pe.Ellipsoid([0, 0], np.eye(2), [1, 1])])  # type: ignore[arg-type]
    assert caught.value.argument == "ellipsoids"
    with pytest.raises(pe.InputError, match="other than"):
        pe.compare(P, ellipsoids={"mvie": pe.Ellipsoid(P.center, np.eye(2), [1, 1])})
    with pytest.raises(pe.InputError) as caught:
        pe.compare(P, ellipsoids={"e": "not an ellipsoid"})  # type: ignore[dict-item]
    assert caught.value.argument == "ellipsoids['e']"
    with pytest.raises(pe.InputError) as caught:  # of another space
        pe.compare(P, ellipsoids={"e": pe.Ellipsoid(np.zeros(3), np.eye(3), [1, 1, 1])})
    assert caught.value.argument == "ellipsoids['e']"
    with pytest.raises(pe.InputError) as caught:  # a segment in a 2-D set
        pe.compare(P, ellipsoids={"e": pe.Ellipsoid(P.center, [[1.0], [0.0]], [1.0])})
    assert caught.value.argument == "ellipsoids['e']"
    weighted = pe.Candidate("w", weighting=np.eye(3))
    with pytest.raises(pe.InputError, match="core"):
        pe.compare(P, candidates=[weighted])
    with pytest.raises(pe.InputError) as caught:
        pe.compare(P, unit=3)  # type: ignore[call-overload]
    assert caught.value.argument == "unit"
    an = random_problem(28, 2, 3, capacity="force")
    with pytest.raises(pe.InputError) as caught:
        pe.compare(an, unit="N")
    assert caught.value.argument == "unit"
