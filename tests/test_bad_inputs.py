"""The bad-input matrix: every row must fail with the package's exception and a message that
names the problem.  API, TOML robot/study files and the command line."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

import polyell as pe
from polyell.cli import main
from polyell.studies import load_robot_file, load_study, run_study

ARM = pe.robots.load("chiacchio2000")
DYN = ARM.dynamics([0.3, 0.4, 0.5])
AN = pe.analyze(DYN, ARM.tau_max)
SINGULAR = pe.analyze(ARM.dynamics([0.3, 0.0, 0.0]), ARM.tau_max)
EYE3 = np.eye(3)


def toml(tmp: Path, text: str) -> Path:
    path = tmp / "file.toml"
    path.write_text(textwrap.dedent(text))
    return path


STUDY = '[robot]\nlibrary = "chiacchio2000"\n[[points]]\nname = "a"\nq = [0.1, 0.2, 0.3]\n'

# (identifier, function of a temporary folder, exception class, message fragment)
API = [
    ("J not 2-D", lambda t: pe.Dynamics([1, 2, 3], EYE3, [0, 0, 0]), pe.InputError, "J: expected"),
    (
        "J with NaN",
        lambda t: pe.Dynamics([[np.nan, 0, 0]], EYE3, [0, 0, 0]),
        pe.InputError,
        "finite values",
    ),
    (
        "J with inf",
        lambda t: pe.Dynamics([[np.inf, 0, 0]], EYE3, [0, 0, 0]),
        pe.InputError,
        "finite values",
    ),
    (
        "B wrong shape",
        lambda t: pe.Dynamics([[1, 0, 0]], np.eye(2), [0, 0, 0]),
        pe.InputError,
        "B: expected an array of real numbers with shape (3, 3)",
    ),
    (
        "B asymmetric",
        lambda t: pe.Dynamics([[1, 0, 0]], EYE3 + np.diag([0.5, 0.5], k=1), [0, 0, 0]),
        pe.InputError,
        "B: expected a symmetric matrix",
    ),
    (
        "B indefinite",
        lambda t: pe.Dynamics([[1, 0, 0]], np.diag([1, -1, 1]), [0, 0, 0]),
        pe.InputError,
        "positive-definite",
    ),
    (
        "B singular",
        lambda t: pe.Dynamics([[1, 0, 0]], np.diag([1, 0, 1]), [0, 0, 0]),
        pe.InputError,
        "positive-definite",
    ),
    (
        "g wrong length",
        lambda t: pe.Dynamics([[1, 0, 0]], EYE3, [0, 0]),
        pe.InputError,
        "g: expected",
    ),
    ("g is None", lambda t: pe.Dynamics([[1, 0, 0]], EYE3, None), pe.InputError, "got None"),
    (
        "g not numbers",
        lambda t: pe.Dynamics([[1, 0, 0]], EYE3, ["a", "b", "c"]),
        pe.InputError,
        "g: expected",
    ),
    (
        "tau_max zero",
        lambda t: pe.analyze(DYN, [1, 0, 1]),
        pe.InputError,
        "tau_max: expected strictly positive",
    ),
    (
        "tau_max negative",
        lambda t: pe.analyze(DYN, [1, -2, 1]),
        pe.InputError,
        "tau_max: expected strictly positive",
    ),
    (
        "tau_min = tau_max",
        lambda t: pe.analyze(DYN, [1, 1, 1], [0, 1, 0]),
        pe.InputError,
        "tau_min[1] = 1 >= tau_max[1] = 1",
    ),
    (
        "tau_min > tau_max",
        lambda t: pe.analyze(DYN, [1, 1, 1], [2, 0, 0]),
        pe.InputError,
        "tau_min[0] = 2 >= tau_max[0] = 1",
    ),
    (
        "tau_max wrong length",
        lambda t: pe.analyze(DYN, [1, 1]),
        pe.InputError,
        "tau_max: expected an array of real numbers with shape (3,)",
    ),
    ("not a Dynamics", lambda t: pe.analyze("dyn", [1, 1, 1]), pe.InputError, "pe.Dynamics"),
    (
        "a batch to analyze",
        lambda t: pe.analyze(ARM.dynamics(np.zeros((2, 3))), ARM.tau_max),
        pe.InputError,
        "pe.sweep",
    ),
    (
        "bad rank tolerance",
        lambda t: pe.analyze(DYN, ARM.tau_max, rank_rtol=2.0),
        pe.InputError,
        "rank_rtol",
    ),
    (
        "unknown ellipsoid kind",
        lambda t: AN.ellipsoid("new"),
        pe.InputError,
        "kind: expected one of 'chiacchio', 'yoshikawa'",
    ),
    (
        "classic at a singularity",
        lambda t: SINGULAR.ellipsoid("yoshikawa"),
        pe.UndefinedEllipsoidError,
        "J J^T",
    ),
    (
        "classic inverse at a singularity",
        lambda t: SINGULAR.inverse(SINGULAR.xg, "yoshikawa"),
        pe.UndefinedEllipsoidError,
        "rank J = 1",
    ),
    (
        "unreachable acceleration",
        lambda t: SINGULAR.inverse(SINGULAR.xg + SINGULAR.svd.U2[:, 0]),
        pe.UnreachableAccelerationError,
        "project it",
    ),
    (
        "zero direction",
        lambda t: AN.polytope.limits([0, 0]),
        pe.InputError,
        "zero-length direction",
    ),
    (
        "non-unit direction",
        lambda t: AN.ellipsoid().limits([[1, 1]]),
        pe.InputError,
        "unit direction vectors",
    ),
    (
        "direction of wrong size",
        lambda t: AN.polytope.limits([1, 0, 0]),
        pe.InputError,
        "2 coordinates",
    ),
    (
        "unknown limits method",
        lambda t: AN.polytope.limits([1, 0], method="simplex"),
        pe.InputError,
        "'closed_form' or 'lp'",
    ),
    (
        "unknown halfspace method",
        lambda t: AN.polytope.halfspaces("qhull"),
        pe.InputError,
        "'zonotope' or 'cdd'",
    ),
    (
        "non-orthonormal axes",
        lambda t: pe.Ellipsoid([0, 0], [[1, 1], [0, 1]], [1, 1]),
        pe.InputError,
        "orthonormal",
    ),
    (
        "zero semi-axis",
        lambda t: pe.Ellipsoid([0, 0], np.eye(2), [1, 0]),
        pe.InputError,
        "strictly positive",
    ),
    (
        "unknown comparison kind",
        lambda t: pe.compare(AN, 8, mvie=False)["best"],
        pe.InputError,
        "kind: expected one of",
    ),
    ("compare without analysis", lambda t: pe.compare(DYN), pe.InputError, "pe.analyze"),
    (
        "negative link length",
        lambda t: pe.PlanarArm([1, -1], [1, 1]),
        pe.InputError,
        "lengths: expected strictly positive",
    ),
    ("wrong number of angles", lambda t: ARM.dynamics([0.1, 0.2]), pe.InputError, "q: expected"),
    ("unknown robot", lambda t: pe.robots.load("kuka"), pe.InputError, "name: expected one of"),
    (
        "mixed task rows",
        lambda t: pe.robots.load("panda", task=["x", "wz"]),
        pe.InputError,
        "all linear or all angular",
    ),
    (
        "missing URDF",
        lambda t: pe.UrdfRobot(t / "none.urdf", "tip"),
        pe.InputError,
        "an existing URDF file",
    ),
    (
        "missing tip frame",
        lambda t: pe.robots.load("ur5", tip="nose"),
        pe.InputError,
        "tip: expected a frame",
    ),
    (
        "unknown locked joint",
        lambda t: pe.robots.load("ur5", locked_joints=["finger"]),
        pe.InputError,
        "locked_joints",
    ),
    (
        "sweep scheduler",
        lambda t: pe.sweep(ARM, np.zeros((2, 3)), scheduler="gpu"),
        pe.InputError,
        "scheduler",
    ),
    (
        "sweep unknown score",
        lambda t: pe.sweep(ARM, np.zeros((2, 3)), scores=("beauty",)),
        pe.InputError,
        "scores",
    ),
    (
        "grid with no points",
        lambda t: pe.grid(0.0, (0.0, 1.0, 0), 0.0),
        pe.InputError,
        "q2 num: expected an integer from 1",
    ),
    (
        "random box upside down",
        lambda t: pe.random_configurations(3, [1.0], [0.0]),
        pe.InputError,
        "low <= high",
    ),
    # issue 33's attack, round 3: raw TypeErrors and silently written non-content
    (
        "save_figure formats not a sequence",
        lambda t: _figures().save_figure(_figures().plot_sets(AN), t / "x", formats=3),
        pe.InputError,
        "formats: expected a sequence of formats",
    ),
    (
        "interactive_sets kinds not a list",
        lambda t: _interactive().interactive_sets(pe.compare(AN, mvie=False), kinds=3),
        pe.InputError,
        "kinds: expected a list of the comparison's kinds",
    ),
    (
        "interactive_sets an unknown kind",
        lambda t: _interactive().interactive_sets(pe.compare(AN, mvie=False), kinds=["x"]),
        pe.InputError,
        "kinds: expected a list of the comparison's kinds",
    ),
    (
        "write_report a section of None",
        lambda t: _interactive().write_report(t / "r.html", "t", [("s", None)]),
        pe.InputError,
        "sections['s']: expected a plotly figure",
    ),
    (
        "load_trajectory of None",
        lambda t: _load_trajectory()(None, 3),
        pe.InputError,
        "trajectory: expected a file path",
    ),
]


def _figures():
    import matplotlib

    matplotlib.use("Agg")
    import polyell.figures as figures

    return figures


def _interactive():
    import polyell.interactive as interactive

    return interactive


def _load_trajectory():
    from polyell.studies.trajectory import load_trajectory

    return load_trajectory


FILES = [
    (
        "unknown top-level key",
        lambda t: load_study(toml(t, STUDY + "[outputs]\n")),
        pe.InputError,
        "keys among ['title', 'description', 'robot'",
    ),
    (
        "unknown robot key",
        lambda t: load_study(toml(t, STUDY.replace("library", "librar"))),
        pe.InputError,
        "unknown key(s) ['librar']",
    ),
    (
        "unknown compare key",
        lambda t: load_study(toml(t, STUDY + "[compare]\nsample = 3\n")),
        pe.InputError,
        "keys among ['directions', 'mvie', 'outer', 'samples', 'seed', 'chunk', 'horizon', "
        "'braking', 'capacities']",
    ),
    (
        "unknown output key",
        lambda t: load_study(toml(t, STUDY + "[output]\nformat = 'png'\n")),
        pe.InputError,
        "keys among ['formats', 'dpi', 'maps', 'histograms', 'series', 'sets', 'scores',",
    ),
    ("invalid TOML", lambda t: load_study(toml(t, "robot = [")), pe.InputError, "valid TOML"),
    (
        "missing study",
        lambda t: load_study(t / "none.toml"),
        pe.InputError,
        "an existing TOML file",
    ),
    (
        "bad angle expression",
        lambda t: load_study(toml(t, STUDY.replace("0.1,", "'pi/x',"))),
        pe.InputError,
        "points[0].q[0]",
    ),
    (
        "robot file without limits",
        lambda t: load_robot_file(toml(t, "planar = { lengths = [1], masses = [1] }\n")),
        pe.InputError,
        "torque limits",
    ),
    (
        "URDF robot without tip",
        lambda t: load_robot_file(toml(t, 'urdf = "arm.urdf"\ntau_max = [1]\n')),
        pe.InputError,
        "a 'tip' frame",
    ),
    (
        "unwritable output folder",
        lambda t: run_study(load_study(toml(t, STUDY)), _blocked(t) / "out"),
        pe.InputError,
        "a folder polyell can write to",
    ),
]


def _huge(a: np.ndarray) -> np.ndarray:
    """The array rescaled so that its largest entry is 1e308 (no overflow on the way)."""
    return a / np.max(np.abs(a)) * 1e308


Q3 = np.array([[0.1, 0.2, 0.3], [0.3, 0.2, 0.1]])
E2 = AN.ellipsoid("chiacchio")

# Issue 20: raw exceptions, NaN, inf and warnings at the edges of the API.
EDGES = [
    ("sweep scores 5", lambda t: pe.sweep(ARM, Q3, scores=5), "scores: expected"),
    ("sweep scores empty", lambda t: pe.sweep(ARM, Q3, scores=[]), "at least one score"),
    ("sweep scores not str", lambda t: pe.sweep(ARM, Q3, scores=[1]), "score names"),
    ("sweep out 5", lambda t: pe.sweep(ARM, Q3, out=5), "out: expected a folder path"),
    ("sweep rank_rtol str", lambda t: pe.sweep(ARM, Q3, rank_rtol="x"), "rank_rtol"),
    ("sweep rank_rtol < 0", lambda t: pe.sweep(ARM, Q3, rank_rtol=-1.0), "rank_rtol"),
    ("sweep rank_rtol None", lambda t: pe.sweep(ARM, Q3, rank_rtol=None), "rank_rtol"),
    ("sweep mvie str", lambda t: pe.sweep(ARM, Q3, mvie="yes"), "mvie: expected True"),
    ("sweep scheduler 5", lambda t: pe.sweep(ARM, Q3, scheduler=5), "scheduler"),
    ("boundary_curve None", lambda t: E2.boundary_curve(None), "count: expected an integer"),
    ("boundary_curve 1e10", lambda t: E2.boundary_curve(10**10), "count: expected an integer"),
    ("boundary_curve 2.5", lambda t: E2.boundary_curve(2.5), "count: expected an integer"),
    (
        "ellipsoid of semi-axes 1e300",
        lambda t: pe.Ellipsoid([0, 0], EYE3[:2, :2], [1e300, 1e300]),
        "semi_axes: expected lengths within",
    ),
    (
        "ellipsoid of semi-axes 1e-300",
        lambda t: pe.Ellipsoid([0, 0], EYE3[:2, :2], [1e-300, 1.0]),
        "semi_axes: expected lengths within",
    ),
    ("compare samples 0", lambda t: pe.compare(AN, 8, samples=0), "samples: expected"),
    ("compare seed str", lambda t: pe.compare(AN, 8, seed="a"), "seed: expected"),
    ("compare directions True", lambda t: pe.compare(AN, True), "directions: expected"),
    ("q of 1e308", lambda t: ARM.dynamics([1e308, 0, 0]), "q: expected joint angles"),
    ("directions of 1e308", lambda t: AN.polytope.limits([1e308, 0]), "directions: expected"),
    ("points of 1e308", lambda t: AN.polytope.contains([1e308, 0]), "points: expected"),
    ("xdd of 1e308", lambda t: AN.inverse([1e308, 0]), "xdd: expected"),
    ("tau_max of 1e308", lambda t: pe.analyze(DYN, [1e308] * 3), "tau_max: expected"),
    ("tau_min of -1e308", lambda t: pe.analyze(DYN, [1.0] * 3, [-1e308] * 3), "tau_min"),
    ("J of 1e308", lambda t: pe.analyze(pe.Dynamics(_huge(DYN.J), DYN.B, DYN.g), [1] * 3), "dyn"),
    ("B of 1e308", lambda t: pe.analyze(pe.Dynamics(DYN.J, _huge(DYN.B), DYN.g), [1] * 3), "dyn"),
    ("g of 1e308", lambda t: pe.analyze(pe.Dynamics(DYN.J, DYN.B, _huge(DYN.g)), [1] * 3), "dyn"),
    (
        "B of subnormal entries",
        lambda t: pe.analyze(pe.Dynamics(DYN.J, np.eye(3) * 1e-320, DYN.g), [1] * 3),
        "dyn",
    ),
    (
        "weak torques against gravity",
        lambda t: pe.analyze(DYN, ARM.tau_max * 1e-16),
        "free-fall acceleration",
    ),
    ("arm length 1e308", lambda t: pe.PlanarArm([1e308, 1], [1, 1]), "lengths: expected"),
    ("arm gravity 1e308", lambda t: pe.PlanarArm([1, 1], [1, 1], gravity=1e308), "gravity"),
    (
        "candidate core 1e308",
        lambda t: pe.compare(AN, 8, candidates=[pe.Candidate("c", core=np.eye(2) * 1e300)]),
        "candidate 'c'",
    ),
    (
        "candidate centre 1e308",
        lambda t: pe.Candidate("c", core=np.eye(2), center=[1e308, 0]),
        "c.center",
    ),
]


@pytest.mark.parametrize(("name", "call", "fragment"), EDGES, ids=[r[0] for r in EDGES])
def test_edges_are_refused_without_a_warning(tmp_path, name, call, fragment):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning (overflow) on the way
        with pytest.raises(pe.InputError) as info:
            call(tmp_path)
    assert fragment in str(info.value), str(info.value)


def test_a_sweep_with_more_task_rows_than_joints_takes_the_scalar_path():
    """m = 3 > n = 1: every row singular; no ZeroDivisionError in the block sizes."""
    rng = np.random.default_rng(0)
    J = rng.normal(size=(3, 3, 1))
    dyn = pe.Dynamics(J, np.ones((3, 1, 1)), np.zeros((3, 1)), task=("x", "y", "z"))
    frame = pe.sweep(dyn, tau_max=[1.0], directions=8)
    assert (frame["polytope_dim"] == 1).all()
    expected = pe.compare(pe.analyze(dyn[1], [1.0]), 8).to_row()
    assert frame.loc[1, "chiacchio_coverage"] == expected["chiacchio_coverage"]


def _blocked(tmp: Path) -> Path:
    blocker = tmp / "blocker"
    blocker.write_text("")
    return blocker


@pytest.mark.parametrize(
    ("name", "call", "error", "fragment"), API + FILES, ids=[r[0] for r in API + FILES]
)
def test_bad_input(tmp_path, name, call, error, fragment):
    with pytest.raises(error) as info:
        call(tmp_path)
    assert isinstance(info.value, pe.PolyellError)
    assert fragment in str(info.value), str(info.value)


CLI = [
    (["analyze", "--q", "1,2"], "q: expected"),
    (["analyze", "--tau-max", "1,0,1"], "tau_max: expected strictly positive"),
    (["analyze", "--robot", "kuka"], "name: expected one of"),
    (["analyze", "--robot", "missing.toml"], "an existing TOML file"),
    (["analyze", "--direction", "1,1"], "add --normalize to scale it"),
    (["study", "missing.toml", "--out", "x"], "an existing TOML file"),
]


@pytest.mark.parametrize(("argv", "fragment"), CLI, ids=[" ".join(a) for a, _ in CLI])
def test_bad_command_line_is_one_line_and_exit_2(capsys, argv, fragment):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("polyell: error:") and fragment in err
    assert len(err.splitlines()) == 1 and "Traceback" not in err


def test_the_matrix_has_at_least_forty_rows():
    assert len(API) + len(FILES) + len(CLI) >= 40


def test_rank_n_and_title_of_the_wrong_type_are_refused(tmp_path):
    # Found by the third attack (issue 33): raw TypeError / AttributeError, and a negative
    # rank that silently made a square unbounded.
    from polyell.interactive import write_report
    from polyell.studies import load_trajectory

    square = (np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
    for rank in (-1, 3, 1.5, "a", True):
        with pytest.raises(pe.InputError, match="rank"):
            pe.HPolytope(*square, rank=rank)
    assert pe.HPolytope(*square, rank=2).volume == pytest.approx(4.0)
    path = tmp_path / "a.csv"
    path.write_text("q1,q2,q3\n0,0,0\n0.1,0.1,0.1\n")
    for n in (3.0, True, 0):
        with pytest.raises(pe.InputError, match="n:"):
            load_trajectory(path, n)
    for title in (None, 5):
        with pytest.raises(pe.InputError, match="title"):
            write_report(tmp_path / "r.html", title, [])


@pytest.mark.parametrize(
    "module",
    [
        "polyell.figures",
        "polyell.interactive",
        "polyell.comparison.labels",
        "polyell.comparison.limits",
        "polyell.comparison.summary",
        "polyell.studies.posture",
        "polyell.comparison.tables",
        "polyell.comparison.metrics",
        "polyell.geometry.subspace",
    ],
)
def test_every_figure_function_refuses_a_wrong_first_argument(module):
    # The third attack (issue 33): figure functions given a Comparison for an Analysis (and
    # the like) raised raw AttributeError / TypeError / IndexError.
    import importlib
    import inspect

    functions = importlib.import_module(module)
    analysis = pe.analyze(ARM.dynamics([np.pi / 2, -np.pi / 2, -np.pi / 2]), ARM.tau_max)
    comparison = pe.compare(analysis, 8, mvie=False, outer=False)
    wrong = [None, 5, "x", comparison, analysis, np.zeros(3), []]
    checked = 0
    for name in functions.__all__:
        function = getattr(functions, name)
        if not inspect.isfunction(function) or name in ("check_title", "decimation_note"):
            continue
        parameters = list(inspect.signature(function).parameters.values())
        required = [p for p in parameters if p.default is p.empty]
        positional = [p for p in required if p.kind is p.POSITIONAL_OR_KEYWORD]
        keywords = {p.name: "x" for p in required if p.kind is p.KEYWORD_ONLY}
        for value in wrong:
            arguments = [value, *["x"] * (len(positional) - 1)]
            try:
                function(*arguments, **keywords)
            except pe.PolyellError:
                checked += 1
                continue
            except Exception as exn:
                pytest.fail(f"{name}({type(value).__name__}, ...): {type(exn).__name__}: {exn}")
    assert checked > 0
