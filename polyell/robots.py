"""A library of robots by name.

* ``"chiacchio2000"``: the 3-link planar arm of Chiacchio (2000), section 6, with its torque
  limits (100, 30, 4) N m and joint velocity limits (2, 3, 4) rad/s -- polyell's choice for
  the velocity capacity: the paper gives none.  No extra needed.
* Arms shipped by ``example-robot-data``, with Pinocchio (extra ``polyell[robots]``):
  ``"panda"`` (fingers locked), ``"ur3"``, ``"ur5"``, ``"ur10"``, ``"kinova"`` (Jaco 2,
  6 joints), ``"xarm7"``, ``"z1"`` (gripper locked).  Their torque limits are the URDFs'
  effort limits; the tip is the tool frame.
"""

from __future__ import annotations

import difflib
import importlib.metadata
from pathlib import Path
from typing import Any, NamedTuple

from polyell.errors import InputError, MissingDependencyError, install_hint
from polyell.models.planar_arm import PlanarArm
from polyell.models.urdf import UrdfRobot

__all__ = ["PLANAR_OPTIONS", "URDF_ARMS", "URDF_OPTIONS", "load", "names", "urdf_path"]


class _Arm(NamedTuple):
    urdf: str  # relative to example-robot-data's robots/ folder
    tip: str
    locked_joints: tuple[str, ...] = ()


#: The arms of example-robot-data that :func:`load` knows.
URDF_ARMS = {
    "panda": _Arm(
        "panda_description/urdf/panda.urdf",
        "panda_hand_tcp",
        ("panda_finger_joint1", "panda_finger_joint2"),
    ),
    "ur3": _Arm("ur_description/urdf/ur3_robot.urdf", "tool0"),
    "ur5": _Arm("ur_description/urdf/ur5_robot.urdf", "tool0"),
    "ur10": _Arm("ur_description/urdf/ur10_robot.urdf", "tool0"),
    "kinova": _Arm("kinova_description/robots/kinova.urdf", "j2s6s200_end_effector"),
    "xarm7": _Arm("xarm_description/urdf/xarm7.urdf", "link_eef"),
    "z1": _Arm("z1_description/urdf/z1.urdf", "gripperStator", ("jointGripper",)),
}


#: The keyword arguments of :class:`~polyell.UrdfRobot` that :func:`load` passes on.
URDF_OPTIONS = (
    "task",
    "tip",
    "locked_joints",
    "gravity",
    "tau_max",
    "tau_min",
    "weights",
    "payload",
    "qd_max",
    "qd_min",
    "torque_speed",
)
#: The keyword arguments of :class:`~polyell.PlanarArm` that :func:`load` passes on for
#: the planar arm (its links are the paper's).
#: Joint velocity limits [rad/s] of the paper's arm: a choice (the paper gives none), lower
#: towards the base as on real arms.
PAPER_VELOCITY_LIMITS = (2.0, 3.0, 4.0)
PLANAR_OPTIONS = ("tau_max", "tau_min", "qd_max", "qd_min", "torque_speed")


def names() -> list[str]:
    """The names :func:`load` accepts."""
    return ["chiacchio2000", *sorted(URDF_ARMS)]


def _suggest(name: str, known: list[str]) -> str:
    """The fix for an unknown robot name: the closest of ``known``, if one is close."""
    close = difflib.get_close_matches(name.strip().lower(), known, n=1, cutoff=0.6)
    if close:
        return f"did you mean {close[0]!r}?"
    return f"use one of {known}, or a URDF file with pe.UrdfRobot(path, tip=...)."


def _check_name(name: object, known: list[str], example: str) -> None:
    """An InputError naming ``name`` unless it is one of ``known`` (a str)."""
    if not isinstance(name, str):
        raise InputError(
            "name",
            f"one of {known}",
            f"{type(name).__name__} {name!r}"[:120],
            f"pass the name as a str, e.g. {example}",
        )
    if name not in known:
        raise InputError("name", f"one of {known}", repr(name), _suggest(name, known))


def urdf_path(name: str) -> Path:
    """The URDF file of a library arm inside the installed ``example-robot-data``."""
    _check_name(name, sorted(URDF_ARMS), "pe.robots.urdf_path('panda')")
    try:
        distribution = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError as exn:
        raise MissingDependencyError(
            f"The robot {name!r} comes from example-robot-data, which is not installed. "
            f"Fix: {install_hint('robots')}."
        ) from exn
    root = Path(str(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    path = root / URDF_ARMS[name].urdf
    if not path.is_file():
        raise MissingDependencyError(
            f"example-robot-data {distribution.version} has no {URDF_ARMS[name].urdf}. "
            f"Fix: {install_hint('robots')} --upgrade."
        )
    return path


def load(name: str, **options: Any) -> PlanarArm | UrdfRobot:
    """A robot of the library, with its torque limits.

    Parameters
    ----------
    name : str
        One of :func:`names`.
    **options
        For the URDF arms, keyword arguments of :class:`~polyell.UrdfRobot` that
        replace the library's defaults (``task``, ``tip``, ``locked_joints``,
        ``gravity``, ``tau_max``, ``tau_min``, ``weights``, ``payload``, ``qd_max``,
        ``qd_min``, ``torque_speed``); for the planar arm, those of
        :class:`~polyell.PlanarArm` among ``tau_max``, ``tau_min``, ``qd_max``, ``qd_min``
        and ``torque_speed``.

    Examples
    --------
    >>> import polyell as pe
    >>> pe.robots.load("chiacchio2000").tau_max.tolist()
    [100.0, 30.0, 4.0]
    """
    _check_name(name, names(), "pe.robots.load('chiacchio2000')")
    if name == "chiacchio2000":
        unknown = sorted(set(options) - set(PLANAR_OPTIONS))
        if unknown:
            raise InputError(
                "options",
                f"keyword arguments among {list(PLANAR_OPTIONS)} for the planar arm",
                f"{unknown}",
                "its links are the paper's; build other arms with pe.PlanarArm.",
            )
        planar: dict[str, Any] = {"tau_max": [100.0, 30.0, 4.0]} | options
        if "qd_max" not in options and "qd_min" not in options:
            planar["qd_max"] = PAPER_VELOCITY_LIMITS
        return PlanarArm(
            lengths=[1.0, 0.8, 0.5], masses=[4.0, 2.0, 0.6], com=[0.5, 0.4, 0.25], **planar
        )
    unknown = sorted(set(options) - set(URDF_OPTIONS))
    if unknown:
        raise InputError(
            "options",
            f"keyword arguments among {list(URDF_OPTIONS)}",
            f"{unknown}",
            "see pe.UrdfRobot for what each one means.",
        )
    arm = URDF_ARMS[name]
    settings: dict[str, Any] = {"tip": arm.tip, "locked_joints": arm.locked_joints} | options
    return UrdfRobot(urdf_path(name), **settings)
