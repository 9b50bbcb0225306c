"""What callers ask of a capacity is asked of its class, never of its name (issue 31, item 4).

Every registered capacity defines the attributes the command line, the reports, the
figures and the studies read (its limit keywords, output suffix, labels and symbols), and
they agree with what :func:`polyell.analyze` does; outside ``polyell/capacities/`` at most
:data:`ALLOWED` comparisons with a capacity's name remain.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

import polyell as pe
from polyell.capacities import CAPACITIES, capacity_class
from polyell.capacities.acceleration import ELLIPSOID_KINDS
from polyell.capacities.zonotope import ZonotopeAnalysis

PACKAGE = Path(pe.__file__).resolve().parent
#: Capacity-name comparisons allowed outside polyell/capacities/ and the places below.
ALLOWED = 2
#: Where comparisons stay: the batch paths' dispatch (``file``, or ``(file, function)``)
#: and the command line's parser.
EXEMPT = {
    ("studies/batch.py", None),
    ("studies/sweep.py", "_batch"),
    ("cli.py", "_parser"),
}
Q = [0.3, 0.6, 0.9]


def _arm() -> pe.PlanarArm:
    return pe.PlanarArm(
        lengths=[1.0, 0.8, 0.5],
        masses=[4.0, 2.0, 0.6],
        tau_max=[100.0, 30.0, 4.0],
        qd_max=[2.0, 3.0, 4.0],
    )


@pytest.mark.parametrize("capacity", CAPACITIES)
def test_limit_keywords_are_those_analyze_takes(capacity):
    cls = capacity_class(capacity)
    arm = _arm()
    keywords = cls.limit_keywords
    assert len(set(keywords)) == 2
    assert set(keywords) <= set(inspect.signature(pe.analyze).parameters)
    upper, lower = cls._robot_limits(arm)
    analysis = pe.analyze(arm.dynamics(Q), capacity=capacity, **cls.limit_arguments(upper, lower))
    assert type(analysis) is cls
    assert tuple(analysis.joint_limits()) == keywords
    np.testing.assert_array_equal(analysis.joint_limits()[keywords[0]], upper)
    np.testing.assert_array_equal(analysis.joint_limits()[keywords[1]], lower)
    for checked, own in zip(
        cls._source_limits(arm, None, None, arm.n), (upper, lower), strict=True
    ):
        np.testing.assert_array_equal(checked, own)
    with pytest.raises(pe.InputError) as missing:
        pe.analyze(arm.dynamics(Q), capacity=capacity)
    assert missing.value.argument == keywords[0]
    assert cls.limit_description in str(missing.value)
    assert cls.limit_hint in str(missing.value)


@pytest.mark.parametrize("capacity", CAPACITIES)
def test_labels_symbols_and_suffix_are_defined_and_consistent(capacity):
    cls = capacity_class(capacity)
    for name in (
        "output_suffix",
        "polytope_label",
        "point_symbol",
        "centre_label",
        "centre_label_tex",
        "rank_matrix",
        "limit_description",
        "limit_hint",
    ):
        assert isinstance(getattr(cls, name), str), name
    for name in ("paper", "in_motion", "unique_inverse"):
        assert isinstance(getattr(cls, name), bool), name
    # the paper's capacity (the default) keeps its names; the others carry theirs
    assert cls.output_suffix == ("" if cls.paper else f"_{capacity}")
    assert cls.paper == (capacity == inspect.signature(pe.analyze).parameters["capacity"].default)
    assert cls.polytope_label.startswith("polytope")
    assert cls.centre_label.startswith("centre")
    assert cls.centre_label_tex.startswith("centre")
    assert cls.rank_matrix in ("M", "J")


def test_exactly_one_capacity_is_the_papers():
    assert [c for c in CAPACITIES if capacity_class(c).paper] == ["acceleration"]


@pytest.mark.parametrize("capacity", CAPACITIES)
def test_a_unique_inverse_is_the_same_for_every_kind(capacity):
    cls = capacity_class(capacity)
    arm = _arm()
    limits = cls.limit_arguments(*cls._robot_limits(arm))
    analysis = pe.analyze(arm.dynamics(Q), capacity=capacity, **limits)
    x = analysis.center + 0.1 * analysis.polytope.limits(np.eye(analysis.m)[0])[1]
    witnesses = [analysis.witness_map(kind)(x) for kind in cls.ellipsoid_kinds]
    same = all(np.allclose(w, witnesses[0], rtol=1e-12, atol=1e-12) for w in witnesses)
    if cls.unique_inverse:
        assert same
    elif len(witnesses) > 1:
        assert not same


ZONOTOPES = [c for c in CAPACITIES if issubclass(capacity_class(c), ZonotopeAnalysis)]


@pytest.mark.parametrize("capacity", ZONOTOPES)
def test_zonotope_capacities_name_the_block_paths_sets(capacity):
    cls = capacity_class(capacity)
    names = cls.acceleration_names
    assert set(names) <= {"polytope", *ELLIPSOID_KINDS}
    assert sorted(names.values()) == sorted(["polytope", *cls.ellipsoid_kinds])
    arm = _arm()
    batch = arm.dynamics(np.array([Q, [0.1, 0.2, 0.3]]))
    as_zonotope = cls._acceleration_dynamics(batch)
    upper, lower = cls._robot_limits(arm)
    one = pe.analyze(batch[0], capacity=capacity, **cls.limit_arguments(upper, lower))
    same = pe.analyze(as_zonotope[0], upper, lower)  # the acceleration zonotope
    for acceleration, own in names.items():
        theirs = same.polytope if acceleration == "polytope" else same.ellipsoid(acceleration)
        ours = one.polytope if own == "polytope" else one.ellipsoid(own)
        np.testing.assert_allclose(theirs.limits(np.eye(2)[0]), ours.limits(np.eye(2)[0]))


def _exempt_lines(path: str, tree: ast.Module) -> set[int]:
    lines: set[int] = set()
    for file, function in EXEMPT:
        if file != path:
            continue
        if function is None:
            return {node.lineno for node in ast.walk(tree) if hasattr(node, "lineno")}
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name == function:
                assert node.end_lineno is not None
                lines |= set(range(node.lineno, node.end_lineno + 1))
    return lines


def _names_a_capacity(node: ast.expr) -> bool:
    """A capacity's name as a string, or a tuple, list or set holding one."""
    if isinstance(node, ast.Constant):
        return node.value in CAPACITIES
    if isinstance(node, ast.Tuple | ast.List | ast.Set):
        return any(_names_a_capacity(item) for item in node.elts)
    return False


def capacity_name_comparisons() -> list[str]:
    """``file:line`` of every comparison with a capacity's name outside the capacities."""
    found = []
    for file in sorted(PACKAGE.rglob("*.py")):
        path = file.relative_to(PACKAGE).as_posix()
        if path.startswith("capacities/"):
            continue
        tree = ast.parse(file.read_text(encoding="utf-8"))
        exempt = _exempt_lines(path, tree)
        for node in ast.walk(tree):
            if not isinstance(node, ast.Compare) or node.lineno in exempt:
                continue
            if any(_names_a_capacity(operand) for operand in (node.left, *node.comparators)):
                found.append(f"polyell/{path}:{node.lineno}")
    return found


def test_the_count_sees_a_comparison():
    tree = ast.parse('if capacity == "velocity" or kind in ("force", "x"):\n    pass\n')
    compares = [node for node in ast.walk(tree) if isinstance(node, ast.Compare)]
    assert all(any(_names_a_capacity(o) for o in (c.left, *c.comparators)) for c in compares)


def test_few_capacity_name_comparisons_remain_outside_the_capacities():
    found = capacity_name_comparisons()
    assert len(found) <= ALLOWED, (
        "ask the capacity class (capacity_class(name).<attribute>) instead of comparing "
        f"its name: {found}"
    )
