"""Scripted studies: TOML descriptions of robots and configurations, run to tables and figures."""

from polyell.studies.along import limits_along
from polyell.studies.cluster import local_cluster
from polyell.studies.configurations import grid, random_configurations
from polyell.studies.runner import run_study
from polyell.studies.spec import StudySpec, load_robot_file, load_study
from polyell.studies.sweep import sweep
from polyell.studies.trajectory import Trajectory, load_trajectory, tangent_limits

__all__ = [
    "StudySpec",
    "Trajectory",
    "grid",
    "limits_along",
    "load_robot_file",
    "load_study",
    "load_trajectory",
    "local_cluster",
    "random_configurations",
    "run_study",
    "sweep",
    "tangent_limits",
]
