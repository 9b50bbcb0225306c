"""Exceptions raised by polyell.

Every error the package raises on purpose derives from :class:`PolyellError`, so a
caller can catch the package's failures with one ``except`` clause.  Messages name the
argument, what was expected, what arrived and how to fix it; they are composed with
:func:`clause` and :func:`sentence`, so that a part which already ends in a period (a
nested message) never gives a doubled one.
"""

from __future__ import annotations

__all__ = [
    "DeratingWarning",
    "InputError",
    "JointLimitWarning",
    "MissingDependencyError",
    "PolyellError",
    "PolyellWarning",
    "ProjectedInputWarning",
    "SolverError",
    "StorageError",
    "UndefinedEllipsoidError",
    "UnreachableAccelerationError",
    "clause",
    "install_hint",
    "sentence",
]

#: How polyell is installed: from a checkout of its repository (it is not on PyPI).
_INSTALL = "in a checkout of the polyell repository, run pip install '.[{extra}]'"


def clause(text: str) -> str:
    """``text`` ready to be followed by punctuation: stripped, without its final period.

    An ellipsis (``...``) is kept: it is not a sentence's end.

    Examples
    --------
    >>> clause("a float. "), clause("rows [1, 2]..."), clause("3")
    ('a float', 'rows [1, 2]...', '3')
    """
    text = str(text).strip()
    while text.endswith(".") and not text.endswith("..."):
        text = text[:-1].rstrip()
    return text


def sentence(text: str) -> str:
    """``text`` as a sentence: stripped and ending in exactly one period (or ``!``, ``?``).

    Examples
    --------
    >>> sentence("use a float"), sentence("use a float.."), sentence("")
    ('use a float.', 'use a float.', '')
    """
    text = clause(text)
    if not text or text.endswith(("...", "!", "?")):
        return text
    return text + "."


def install_hint(extra: str) -> str:
    """How to install an optional extra of polyell (from its repository: not on PyPI).

    Examples
    --------
    >>> install_hint("robots")
    "in a checkout of the polyell repository, run pip install '.[robots]'"
    """
    return _INSTALL.format(extra=extra)


class PolyellError(Exception):
    """Base class of every error polyell raises on purpose."""


class InputError(PolyellError, ValueError):
    """An argument has the wrong type, shape, value or mathematical property.

    Parameters
    ----------
    argument : str
        Name of the offending argument, as the caller wrote it.
    expected : str
        What the argument should have been.
    got : str
        What arrived instead.
    fix : str
        A concrete way to repair the call (required: every refusal says how to repair it).
    """

    def __init__(self, argument: str, expected: str, got: str, fix: str) -> None:
        self.argument = argument
        self.expected = expected
        self.got = got
        self.fix = fix
        message = sentence(f"{clause(argument)}: expected {clause(expected)}, got {clause(got)}")
        if clause(fix):
            message += f" Fix: {sentence(fix)}"
        super().__init__(message)


class UndefinedEllipsoidError(PolyellError):
    """An ellipsoid definition does not exist at this configuration.

    The classic (Yoshikawa) ellipsoid of eq. (27) needs ``J J^T`` to be invertible; at a
    singular configuration it is undefined.
    """


class UnreachableAccelerationError(PolyellError, ValueError):
    """A task-space acceleration lies outside the set the robot can reach at all.

    Raised by the inverse maps when ``xdd`` is not in the affine set ``xdd_g + Im(M)``
    (a singular configuration), so no joint acceleration produces it.
    """


class SolverError(PolyellError):
    """A numerical solver (linear program, log-det program) failed to return a solution."""


class StorageError(PolyellError, OSError):
    """A file of a study could not be written (a full disk, a size limit, permissions).

    Nothing partial is left: every file is written to a temporary name and renamed.
    """


class MissingDependencyError(PolyellError, ImportError):
    """An optional dependency is not installed; the message names the extra to install."""


class PolyellWarning(UserWarning):
    """Base class of every warning polyell issues on purpose.

    A computation that goes on with input that is probably a slip (joint angles in
    degrees, rated torque limits for a moving robot) says so with a subclass of this
    warning.  Python's warning filters select them: ``warnings.simplefilter("error",
    pe.PolyellWarning)`` makes them errors, ``"ignore"`` silences them.
    """


class ProjectedInputWarning(PolyellWarning):
    """Input taken as rounded and projected onto the affine set of a singular configuration.

    A direction or an acceleration within :data:`~polyell.AFFINE_RTOL` of the set
    ``xg + Im(M)`` (eq. 35) is treated as lying in it; polyell says so with this warning.
    """


class TableWidthWarning(PolyellWarning):
    """A LaTeX table estimated wider than the text width, written anyway.

    The message names the table, its estimated width and the text width (set by
    ``pe.TableLayout(text_width=...)``); the fixes are fewer sets or scores, the
    transposed layout, or a wider page.
    """


class JointLimitWarning(PolyellWarning):
    """Joint positions or velocities outside a robot's limits.

    Positions beyond its URDF's ``lower``, ``upper``; velocities beyond its velocity
    limits (``robot.velocity_limits()``).  Issued once per call of
    :meth:`~polyell.UrdfRobot.dynamics` or :meth:`~polyell.UrdfRobot.tip_kinematics` (a
    batch of K configurations gives one warning), naming the joints, by how much they are
    beyond their limits and, where revolute joints are beyond a full turn
    (``|q| > 2 pi``), that the angles look like degrees (velocities: where they would lie
    within the limits in radians per second).  Continuous joints have no position limits
    and never warn for them.  The values are computed anyway: a robot is allowed to be
    evaluated anywhere.

    Attributes
    ----------
    joints : tuple of str
        Names of the joints outside their limits.
    degrees : bool
        True where the values look like degrees.
    """

    def __init__(self, message: str, joints: tuple[str, ...] = (), degrees: bool = False) -> None:
        super().__init__(message)
        self.joints = tuple(joints)
        self.degrees = bool(degrees)


class DeratingWarning(PolyellWarning):
    """Torque limits beyond what a moving robot's drives give at its joint velocities.

    A robot with a torque-speed model (:class:`~polyell.TorqueSpeed`) moving at
    ``qd != 0`` can give less torque in the direction of motion than its rated limits;
    an analysis given the rated limits (or any limits beyond the derated ones) gets a set
    that is too large.  The message names the joints and both limits; the fix is the
    robot's limits at ``qd``, ``robot.torque_limits(qd)``, or
    :meth:`~polyell.UrdfRobot.analyze`, which uses them.

    Attributes
    ----------
    joints : tuple of str
        Names of the joints whose limits exceed the derated ones.
    """

    def __init__(self, message: str, joints: tuple[str, ...] = ()) -> None:
        super().__init__(message)
        self.joints = tuple(joints)
