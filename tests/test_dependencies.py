"""The declared dependencies against the imports: nothing declared that is never imported.

The default install holds what the README's Quick start job imports (and pyarrow, for the
Parquet datasets); cvxpy and Clarabel are the extra ``lp``, imported only inside the
functions of the cross-checks; the test extra installs every other extra.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
SOURCES = {path: path.read_text(encoding="utf-8") for path in (ROOT / "polyell").rglob("*.py")}
#: The module a distribution installs, where the names differ.
MODULES = {"pycddlib-standalone": "cdd", "pin": "pinocchio", "tomli": "tomli"}


def name(requirement: str) -> str:
    return re.match(r"[A-Za-z0-9_.-]+", requirement)[0].lower()


def imports(module: str) -> list[tuple[Path, str]]:
    pattern = re.compile(rf"^(\s*)(import {module}\b|from {module}\b)", re.MULTILINE)
    return [(path, m.group(1)) for path, text in SOURCES.items() for m in pattern.finditer(text)]


def test_every_core_dependency_is_imported():
    for requirement in PROJECT["dependencies"]:
        module = MODULES.get(name(requirement), name(requirement))
        assert imports(module), f"{requirement} is declared but polyell never imports it"


def test_jinja2_tabulate_and_cvxpy_are_not_core_dependencies():
    core = {name(r) for r in PROJECT["dependencies"]}
    assert not core & {"jinja2", "tabulate", "cvxpy", "clarabel"}
    assert {name(r) for r in PROJECT["optional-dependencies"]["lp"]} == {"cvxpy", "clarabel"}


def test_cvxpy_is_imported_only_where_a_cross_check_runs():
    found = imports("cvxpy")
    assert found
    for path, indent in found:
        assert indent, f"{path.relative_to(ROOT)} imports cvxpy at module level"


def test_the_test_extra_installs_every_other_extra():
    extras = PROJECT["optional-dependencies"]
    (own,) = [r for r in extras["test"] if r.startswith("polyell[")]
    included = set(own[len("polyell[") : -1].split(","))
    assert included >= set(extras) - {"test", "bench"}
    assert "polyell[lp]" in extras["docs"]  # the tutorials call method="lp"
