"""The Jacobian of one configuration: all the velocity capacity needs."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.models.task import check_task
from polyell.validation import check_array

__all__ = ["Kinematics"]


class Kinematics:
    """Task Jacobian of a manipulator at one configuration, with the names of its rows.

    The velocity capacity (``pe.analyze(kin, capacity="velocity", qd_max=...)``) needs no
    inertia and no gravity; a :class:`~polyell.Dynamics` serves as well.

    Parameters
    ----------
    J : array-like, shape (m, n)
        Task Jacobian (rows all linear [m/rad] or all angular [1]).
    task : sequence of str, optional
        Names of the m task rows; default :func:`~polyell.models.task.default_task`.

    Examples
    --------
    >>> import polyell as pe
    >>> kin = pe.Kinematics([[1.0, 0.5, 0.2]])
    >>> kin.m, kin.n, kin.task
    (1, 3, ('x',))
    """

    J: NDArray[np.float64]
    task: tuple[str, ...]
    batch_size = None

    def __init__(self, J: ArrayLike, task: Sequence[str] | None = None) -> None:
        jacobian = check_array("J", J, ("m", "n"), what="Jacobian entries")
        if 0 in jacobian.shape:
            raise InputError(
                "J",
                "at least one task row and one joint",
                f"shape {jacobian.shape}",
                "pass a Jacobian of shape (m, n) with m, n >= 1, e.g. pe.Kinematics([[1.0, 0.5]])",
            )
        jacobian.flags.writeable = False
        self.J = jacobian
        self.task = check_task(task, jacobian.shape[0])

    @property
    def m(self) -> int:
        """Task-space dimension."""
        return int(self.J.shape[0])

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.J.shape[1])

    def __repr__(self) -> str:
        return f"Kinematics(m={self.m}, n={self.n}, task={self.task})"
