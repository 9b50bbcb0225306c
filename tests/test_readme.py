"""Every Python example in the README runs, and its commented numbers are right."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"


def python_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.DOTALL)


def test_readme_python_examples_run_and_match_their_comments(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the blocks write files (sets.html): never into the checkout
    blocks = python_blocks()
    assert blocks
    namespace: dict[str, object] = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)
    pe, cmp = namespace["pe"], namespace["cmp"]
    an = cmp.analysis  # the paper's arm (the later block analyses the Panda)
    assert round(float(an.xg[1]), 3) == -12.392
    lo, hi = an.polytope.limits([1.0, 0.0])
    assert (round(float(lo), 3), round(float(hi), 3)) == (-57.305, 53.700)
    assert round(cmp["chiacchio"].coverage, 4) == 0.5967
    assert round(cmp["yoshikawa"].witness_torque_max, 2) == 1.04
    assert isinstance(cmp, pe.Comparison)
    force, forces = namespace["force"], namespace["forces"]
    lo, hi = force.polytope.limits([0.0, -1.0])
    assert (round(float(lo), 3), round(float(hi), 3)) == (-21.804, 53.196)
    assert round(forces["chiacchio"].inscribed_scale, 4) == 1.0029
    assert round(forces["static"].witness_torque_max, 2) == 1.38
    velocity = namespace["velocity"]
    assert np.allclose(velocity.polytope.limits([1.0, 0.0]), (-4.0, 4.0), rtol=1e-12)
    assert round(pe.compare(velocity)["yoshikawa"].coverage, 4) == 0.4605
    assert namespace["an"].dynamics.n == 7 and namespace["moving"].xdd_bias.any()
    assert (tmp_path / "sets.html").stat().st_size > 0


def test_quick_start_commands_are_the_ones_ci_runs():
    text = README.read_text()
    ci = (README.parent / ".ci" / "run").read_text()
    assert "polyell study studies/chiacchio2000.toml --out results/" in text
    assert '.venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest' in text
    assert '.venv/bin/pip install --quiet -e ".[test]"' in ci
    assert ".venv/bin/python -m pytest" in ci
