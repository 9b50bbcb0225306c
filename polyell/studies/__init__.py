"""Scripted studies: TOML descriptions of robots and configurations, run to tables and figures."""

from polyell.studies.runner import run_study
from polyell.studies.spec import StudySpec, load_robot_file, load_study

__all__ = ["StudySpec", "load_robot_file", "load_study", "run_study"]
