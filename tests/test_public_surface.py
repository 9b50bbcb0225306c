"""Every documented function, given one wrong argument: a polyell error or a result.

The public surface is what docs/api.md documents (``autofunction`` entries and the
``__all__`` of each ``automodule``), not only ``pe.__all__``.  Each function is called with
its required positional arguments all of one wrong kind (None, NaN, a str, empty
containers, 1e300, negative, 0, a bool, a 3-D array, 1e-300): it must raise
a :class:`~polyell.PolyellError` (an InputError with its "Fix: ..." sentence) or
return, never raise a raw Python exception (a TypeError, AttributeError, KeyError,
StopIteration...).
"""

from __future__ import annotations

import importlib
import inspect
import operator
import re
import warnings
from functools import partial
from pathlib import Path

import numpy as np
import pytest

import polyell as pe

API = Path(__file__).resolve().parents[1] / "docs" / "api.md"
WRONG = [None, np.nan, "x", [], {}, 1e300, -1, 0, True, np.zeros((2, 2, 2)), 1e-300]


def _documented_functions() -> list[tuple[str, object]]:
    """(qualified name, callable) of every function and class docs/api.md documents."""
    text = API.read_text(encoding="utf-8")
    found: dict[str, object] = {}
    pattern = r"^\.\. (autofunction|automodule|autoclass):: (\S+)"
    for directive, target in re.findall(pattern, text, re.M):
        if directive == "automodule":
            module = importlib.import_module(target)
            for name in getattr(module, "__all__", []):
                value = getattr(module, name)
                if inspect.isfunction(value) or inspect.isclass(value):
                    found[f"{target}.{name}"] = value
        else:
            module_name, _, name = target.rpartition(".")
            found[target] = getattr(importlib.import_module(module_name), name)
    return sorted(found.items())


def _required(function: object) -> int | None:
    """How many positional arguments the function requires; None if it requires a keyword."""
    try:
        parameters = inspect.signature(function).parameters.values()  # type: ignore[arg-type]
    except ValueError:  # a builtin type without one (str subclasses): no argument to check
        return None
    required = [
        p
        for p in parameters
        if p.default is p.empty and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]
    if any(p.kind is p.KEYWORD_ONLY for p in required):
        return None
    return len(required)


def _defect(label: str, call) -> str | None:
    """What is wrong with ``call()``'s outcome, or None: a result, a PolyellError, or an
    InputError with its fix are fine; a raw exception or a fix-less InputError is not."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            call()
        except pe.InputError as exn:
            return None if "Fix: " in str(exn) else f"{label}: no fix: {exn}"[:200]
        except pe.PolyellError:
            return None
        except Exception as exn:  # the test's point: any other exception is a defect
            return f"{label}: {type(exn).__name__}: {exn}"[:200]
    return None


FUNCTIONS = [
    (name, f, _required(f))
    for name, f in _documented_functions()
    if _required(f) and not inspect.isabstract(f)
]


def test_the_surface_is_the_documented_one():
    """The list is read from the docs (not a fixed list that could go stale), and holds
    the submodules' functions as well as pe's."""
    names = [name for name, _, _ in FUNCTIONS]
    assert len(names) >= 40
    for module in ("polyell.figures", "polyell.interactive", "polyell.export", "polyell.robots"):
        assert any(name.startswith(module + ".") for name in names), module


@pytest.mark.parametrize("name, function, count", FUNCTIONS, ids=[f[0] for f in FUNCTIONS])
def test_wrong_arguments_give_a_polyell_error_or_a_result(
    name, function, count, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)  # a function that writes a file writes it here
    found = [
        _defect(f"{name}({value!r:.30})", partial(function, *[value] * count)) for value in WRONG
    ]
    raw = [text for text in found if text]
    assert not raw, "\n".join(raw)


def _documented_members() -> dict[str, list[str] | None]:
    """Per documented class, its ``:members:`` (None: every public one)."""
    text = API.read_text(encoding="utf-8")
    members: dict[str, list[str] | None] = {}
    for target, options in re.findall(r"^\.\. autoclass:: (\S+)\n((?:   :.*\n)*)", text, re.M):
        listed = re.search(r":members:(.*)", options)
        if listed is not None:
            names = [name.strip() for name in listed.group(1).split(",") if name.strip()]
            members[target] = names or None
    return members


@pytest.fixture(scope="module")
def instances():
    """One valid instance of every documented class with documented members."""
    arm = pe.robots.load("chiacchio2000")
    q = [0.3, 0.6, 0.9]
    acceleration = pe.analyze(arm.dynamics(q), arm.tau_max)
    velocity = pe.analyze(arm.dynamics(q), capacity="velocity", qd_max=[2.0, 3.0, 4.0])
    force = pe.analyze(arm.dynamics(q), arm.tau_max, capacity="force")
    panda = pe.robots.load("panda")
    horizon = panda.analyze(np.mean(panda.position_limits, axis=0), np.zeros(7), horizon=1e-3)
    box = pe.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
    bare = pe.compare(box)
    comparison = pe.compare(acceleration)
    columns = pe.comparison.long_form.score_columns(["q1", "chiacchio_coverage"])
    return {
        "polyell.InverseSolution": [acceleration.inverse([[0.0, 0.0]])],
        "polyell.Polytope": [acceleration.polytope, velocity.polytope],
        "polyell.Ellipsoid": [acceleration.ellipsoid("chiacchio"), comparison.mvie],
        "polyell.Scores": [comparison["chiacchio"]],
        "polyell.Dynamics": [arm.dynamics(q)],
        "polyell.PlanarArm": [arm],
        "polyell.UrdfRobot": [panda],
        "polyell.TorqueSpeed": [
            pe.TorqueSpeed.linear(tau_stall=[100.0, 30.0], qd_no_load=[4.0, 6.0])
        ],
        "polyell.comparison.long_form.ScoreColumns": [columns],
        "polyell.Analysis": [acceleration, velocity, force, horizon],
        "polyell.capacities.AccelerationAnalysis": [acceleration],
        "polyell.capacities.horizon.HorizonAnalysis": [horizon],
        "polyell.HPolytope": [box, force.polytope, horizon.polytope],
        "polyell.DirectionalLimits": [acceleration.polytope.limits(np.eye(2))],
        "polyell.AffineSubspace": [acceleration.polytope.affine_set],
        "polyell.Comparison": [comparison],
        "polyell.Candidate": [pe.Candidate("w", weighting=np.diag([1.0, 2.0, 3.0]))],
        "polyell.comparison.set_comparison.SetComparison": [bare],
        "polyell.comparison.set_comparison.SetScores": [bare["mvie"]],
    }


def test_every_documented_class_with_members_has_an_instance(instances):
    assert set(_documented_members()) == set(instances)


@pytest.mark.parametrize("target", sorted(_documented_members()))
def test_documented_methods_give_a_polyell_error_or_a_result(
    target, instances, tmp_path, monkeypatch
):
    """Each documented method with required positional arguments, all of one wrong kind."""
    monkeypatch.chdir(tmp_path)
    listed = _documented_members()[target]
    raw = []
    for instance in instances[target]:
        names = listed or [name for name in dir(type(instance)) if not name.startswith("_")]
        for name in names:
            method = getattr(instance, name)
            if not callable(method) or inspect.isclass(method):
                continue
            count = _required(method)
            if not count:
                continue
            for value in WRONG:
                label = f"{type(instance).__name__}.{name}({value!r:.30})"
                raw.append(_defect(label, partial(method, *[value] * count)))
    raw = [text for text in raw if text]
    assert not raw, "\n".join(raw)


@pytest.mark.parametrize("target", sorted(_documented_members()))
def test_documented_options_give_a_polyell_error_or_a_result(
    target, instances, tmp_path, monkeypatch
):
    """Each optional argument of a documented method without required ones, and each
    instance's ``[...]``, given values of every wrong kind."""
    monkeypatch.chdir(tmp_path)
    listed = _documented_members()[target]
    raw = []
    for instance in instances[target]:
        calls = []
        if hasattr(type(instance), "__getitem__") and not isinstance(instance, tuple):
            calls += [
                (f"[{value!r:.30}]", partial(operator.getitem, instance, value)) for value in WRONG
            ]
        names = listed or [name for name in dir(type(instance)) if not name.startswith("_")]
        for name in names:
            method = getattr(instance, name)
            if not callable(method) or inspect.isclass(method) or _required(method) != 0:
                continue
            for parameter in inspect.signature(method).parameters.values():
                if parameter.kind in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD):
                    continue
                for value in WRONG:
                    label = f"{name}({parameter.name}={value!r:.30})"
                    calls.append((label, partial(method, **{parameter.name: value})))
        raw += [_defect(f"{type(instance).__name__}{label}", call) for label, call in calls]
    raw = [text for text in raw if text]
    assert not raw, "\n".join(raw)


@pytest.fixture(scope="module")
def valid_calls():
    """A valid call of documented functions: positional and keyword arguments."""
    arm = pe.robots.load("chiacchio2000")
    q = np.array([0.3, 0.6, 0.9])
    configurations = np.array([[0.3, 0.6, 0.9], [0.5, 0.2, -0.4], [1.0, -0.7, 0.3]])
    acceleration = pe.analyze(arm.dynamics(q), arm.tau_max)
    comparison = pe.compare(acceleration, mvie=False, outer=False, directions=36)
    results = pe.sweep(arm, configurations, directions=36)
    box = pe.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4))
    motion = pe.self_motion(arm, [np.pi / 2, -np.pi / 2, -np.pi / 2], count=6)
    choice = pe.posture_choice(arm, motion, direction="x", mvie=False, outer=False)
    task = ("x", "y")
    return {
        "polyell.analyze": ((arm.dynamics(q), arm.tau_max), {}),
        "polyell.compare": ((acceleration,), {"mvie": False, "outer": False}),
        "polyell.sweep": ((arm, configurations), {"directions": 36}),
        "polyell.limits_along": ((arm, configurations, [[1.0, 0.0]] * 3), {}),
        "polyell.limits_table": ((comparison,), {}),
        "polyell.self_motion": ((arm, [np.pi / 2, -np.pi / 2, -np.pi / 2]), {"count": 4}),
        "polyell.posture_choice": (
            (arm, motion),
            {"direction": "x", "mvie": False, "outer": False},
        ),
        "polyell.to_long": ((results,), {}),
        "polyell.to_wide": ((pe.to_long(results),), {}),
        "polyell.write_posture_tables": ((choice.table, "."), {}),
        "polyell.studies.posture_tables.format_posture_table": ((choice.table, "latex"), {}),
        "polyell.comparison.directions.named_direction": (("x", task), {}),
        "polyell.comparison.directions.resolve_directions": ((["x"], task), {}),
        "polyell.comparison.labels.ellipsoid_label": (("chiacchio",), {}),
        "polyell.comparison.labels.label_text": (("chiacchio",), {}),
        "polyell.comparison.labels.set_label": (("polytope",), {}),
        "polyell.comparison.long_form.score_columns": ((results,), {}),
        "polyell.comparison.summary.summarize": ((results,), {}),
        "polyell.comparison.tables.format_comparison_table": ((comparison, "latex"), {}),
        "polyell.comparison.tables.format_limits_table": ((comparison.limits_table(), "latex"), {}),
        "polyell.comparison.point_tables.write_point_tables": (({"a": comparison}, None, "."), {}),
        "polyell.export.mesh": ((acceleration.polytope,), {}),
        "polyell.export.comparison_meshes": ((comparison,), {}),
        "polyell.export.export_comparison": ((comparison, "sets.obj"), {}),
        "polyell.figures.plot_sets": ((acceleration,), {}),
        "polyell.figures.plot_directional_limits": ((acceleration,), {}),
        "polyell.figures.plot_score_histogram": ((results, "coverage"), {}),
        "polyell.figures.plot_score_series": ((results, "coverage"), {}),
        "polyell.interactive.interactive_sets": ((comparison,), {}),
        "polyell.interactive.interactive_histogram": ((results, "coverage"), {}),
        "polyell.interactive.interactive_series": ((results, "coverage"), {}),
        "polyell.geometry.combine.minkowski_sum": ((box, box), {}),
        "polyell.geometry.combine.intersection": ((box, box), {}),
        "polyell.geometry.combine.in_frame": ((box, np.eye(2)), {}),
        "polyell.geometry.mvie.max_volume_inscribed_ellipsoid": ((box,), {}),
        "polyell.geometry.outer.min_volume_enclosing_ellipsoid": ((box,), {}),
        "polyell.models.task.task_unit": ((task,), {}),
        "polyell.models.task.row_label": (("x",), {}),
        "polyell.robots.load": (("chiacchio2000",), {}),
    }


def test_the_valid_calls_are_valid_and_documented(valid_calls, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the writers write here
    documented = dict(_documented_functions())
    for name, (args, kwargs) in valid_calls.items():
        assert name in documented, name
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            documented[name](*args, **kwargs)


def test_documented_function_options_give_a_polyell_error_or_a_result(
    valid_calls, tmp_path, monkeypatch
):
    """Each optional argument of a documented function, in an otherwise valid call, given
    values of every wrong kind."""
    monkeypatch.chdir(tmp_path)
    documented = dict(_documented_functions())
    raw = []
    for name, (args, kwargs) in valid_calls.items():
        function = documented[name]
        parameters = list(inspect.signature(function).parameters.values())
        for parameter in parameters[len(args) :]:
            if parameter.kind in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD):
                continue
            for value in WRONG:
                label = f"{name}({parameter.name}={value!r:.30})"
                call = partial(function, *args, **{**kwargs, parameter.name: value})
                raw.append(_defect(label, call))
    raw = [text for text in raw if text]
    assert not raw, "\n".join(raw)


def test_the_judge_itself():
    """:func:`_defect` flags a raw exception and a fix-less InputError, and passes the rest."""

    def raises(error):
        def call():
            raise error

        return call

    assert _defect("f", raises(ZeroDivisionError("x"))) == "f: ZeroDivisionError: x"
    assert "no fix" in _defect("f", raises(pe.InputError("a", "b", "c", "")))
    assert _defect("f", raises(pe.InputError("a", "b", "c", "do d"))) is None
    assert _defect("f", raises(pe.SolverError("s"))) is None
    assert _defect("f", lambda: 1) is None
