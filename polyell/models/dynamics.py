"""The dynamic quantities of a robot at one configuration (at rest, or moving)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from polyell.errors import InputError
from polyell.models.task import check_task
from polyell.validation import array_ndim, check_array, check_spd

__all__ = ["Dynamics"]


@dataclass(frozen=True, init=False)
class Dynamics:
    r"""Jacobian, inertia and gravity torques of a manipulator at one configuration.

    These are the inputs of the paper's eq. (4)-(8) for a robot at rest
    (:math:`\dot q = 0`, no contact force): :math:`\ddot x = J \ddot q` and
    :math:`\tau = B \ddot q + g`.  For a robot in motion (beyond the paper, eq. 2-3),
    :math:`\ddot x = J \ddot q + \dot J \dot q` and :math:`\tau = B \ddot q + c + g`:
    pass :math:`c + g` as ``g`` and :math:`\dot J \dot q` as ``xdd_bias``.

    A batch of configurations (for :func:`polyell.sweep`) stacks the arrays along a first
    axis: ``J`` (K, m, n), ``B`` (K, n, n), ``g`` (K, n), ``xdd_bias`` (K, m).

    Parameters
    ----------
    J : array-like, shape (m, n)
        Task Jacobian (rows all linear [m/rad] or all angular [1]).  More rows than
        joints (``m > n``) is allowed: the sets are then degenerate (rank at most n).
    B : array-like, shape (n, n)
        Joint-space inertia matrix [kg m^2], symmetric positive definite.
    g : array-like, shape (n,)
        Gravity torques [N m] (plus Coriolis and centrifugal torques for a moving robot).
    xdd_bias : array-like, shape (m,), optional
        Velocity-product acceleration ``Jdot qdot`` [m/s^2]; zero (default) at rest.
    task : sequence of str, optional
        Names of the m task rows (``x y z`` linear, ``wx wy wz`` angular), used for axis
        labels and units; default :func:`~polyell.models.task.default_task`.

    Raises
    ------
    InputError
        On mismatched shapes, non-finite entries, or an inertia matrix that is not
        symmetric positive definite.

    Examples
    --------
    >>> import polyell as pe
    >>> dyn = pe.Dynamics(J=[[1.0, 0.5]], B=[[2.0, 0.1], [0.1, 1.0]], g=[3.0, 1.0])
    >>> dyn.m, dyn.n
    (1, 2)
    """

    J: NDArray[np.float64]
    B: NDArray[np.float64]
    g: NDArray[np.float64]
    xdd_bias: NDArray[np.float64]
    task: tuple[str, ...]

    def __init__(
        self,
        J: ArrayLike,
        B: ArrayLike,
        g: ArrayLike,
        xdd_bias: ArrayLike | None = None,
        task: Sequence[str] | None = None,
    ) -> None:
        shape = ("K", "m", "n") if array_ndim(J) == 3 else ("m", "n")
        jacobian = check_array("J", J, shape, what="Jacobian entries")
        *batch, m, n = jacobian.shape
        if m == 0 or n == 0:
            raise InputError("J", "at least one task row and one joint", f"shape {jacobian.shape}")
        object.__setattr__(self, "J", jacobian)
        object.__setattr__(self, "B", check_spd("B", B, n, tuple(batch)))
        object.__setattr__(self, "g", check_array("g", g, (*batch, n)))
        bias = (
            np.zeros((*batch, m))
            if xdd_bias is None
            else check_array("xdd_bias", xdd_bias, (*batch, m))
        )
        object.__setattr__(self, "xdd_bias", bias)
        object.__setattr__(self, "task", check_task(task, m))
        for array in (self.J, self.B, self.g, self.xdd_bias):
            array.flags.writeable = False

    @property
    def m(self) -> int:
        """Task-space dimension."""
        return int(self.J.shape[-2])

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.J.shape[-1])

    @property
    def batch_size(self) -> int | None:
        """Number K of configurations in a batch, None for a single configuration."""
        return int(self.J.shape[0]) if self.J.ndim == 3 else None

    def __len__(self) -> int:
        if self.batch_size is None:
            raise TypeError("a single-configuration Dynamics has no length")
        return self.batch_size

    def __getitem__(self, index: int | slice) -> Dynamics:
        """One configuration (an int) or a sub-batch (a slice) of a batch."""
        if self.batch_size is None:
            raise InputError("index", "a batched Dynamics (J of shape (K, m, n))", "a single one")
        return Dynamics(
            self.J[index], self.B[index], self.g[index], self.xdd_bias[index], self.task
        )
