"""A library of robots by name.

``"chiacchio2000"``: the 3-link planar arm of Chiacchio (2000), section 6, with its torque
limits (100, 30, 4) N m.
"""

from __future__ import annotations

from collections.abc import Callable

from polyell.errors import InputError
from polyell.models.planar_arm import PlanarArm

__all__ = ["load", "names"]


def _chiacchio2000() -> PlanarArm:
    return PlanarArm(
        lengths=[1.0, 0.8, 0.5],
        masses=[4.0, 2.0, 0.6],
        com=[0.5, 0.4, 0.25],
        tau_max=[100.0, 30.0, 4.0],
    )


_LIBRARY: dict[str, Callable[[], PlanarArm]] = {"chiacchio2000": _chiacchio2000}


def names() -> list[str]:
    """The names :func:`load` accepts."""
    return sorted(_LIBRARY)


def load(name: str) -> PlanarArm:
    """A robot of the library, with its torque limits.

    Parameters
    ----------
    name : str
        One of :func:`names`.

    Examples
    --------
    >>> import polyell as pe
    >>> pe.robots.load("chiacchio2000").tau_max.tolist()
    [100.0, 30.0, 4.0]
    """
    if name not in _LIBRARY:
        raise InputError("name", f"one of {names()}", repr(name))
    return _LIBRARY[name]()
