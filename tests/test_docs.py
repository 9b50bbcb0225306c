"""The documentation's examples run, and show what they print."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / "docs" / "tutorials"
spec = importlib.util.spec_from_file_location("tutorial_runner", TUTORIALS / "run.py")
runner = importlib.util.module_from_spec(spec)
spec.loader.exec_module(runner)


@pytest.mark.parametrize("name", runner.TUTORIALS)
def test_tutorial_runs_and_its_shown_output_is_current(name):
    shown = (TUTORIALS / f"{name}.out").read_text()
    assert runner.output(name) == shown, f"regenerate with python docs/tutorials/run.py ({name})"
