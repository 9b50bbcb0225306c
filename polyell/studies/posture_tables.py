r"""The choice table of a posture study as LaTeX (booktabs), Markdown and CSV.

Every text that reaches a table is escaped by the one escaping place of the package
(:func:`~polyell.comparison.tables.escape_latex`,
:func:`~polyell.comparison.tables.escape_markdown`); the LaTeX needs
``\usepackage{booktabs}``.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from polyell.comparison.latex_text import check_latex_label, check_text, latex_unit
from polyell.comparison.layout import TableLayout
from polyell.comparison.printable import Cell, Label, PrintTable, given_label, text_label
from polyell.comparison.tables import Caption, escape_latex, escape_markdown, render_tables
from polyell.errors import InputError
from polyell.storage import write_text_atomically
from polyell.validation import check_frame

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "JOINT_UNITS",
    "POSTURE_TABLE_STEM",
    "format_posture_table",
    "joint_units",
    "write_posture_tables",
]

#: File names of the written tables: ``<stem>.tex``, ``<stem>.md``, ``<stem>.csv``.
POSTURE_TABLE_STEM = "posture_choice"
#: The columns shown: header lines (stacked in LaTeX, one line elsewhere) and kind.
_COLUMNS = {
    "picked": (("posture", "picked"), "index"),
    "true_at_pick": (("truth", "at pick"), "value"),
    "true_best": (("best", "truth"), "value"),
    "regret": (("regret", "[%]"), "share"),
    "spearman": (("Spear-", "man"), "value"),
    "kendall": (("Kendall",), "value"),
    "median_regret": (("median", "regret [%]"), "share"),
    "worst_regret": (("worst", "regret [%]"), "share"),
    "mean_regret": (("mean", "regret [%]"), "share"),
    "median_spearman": (("median", "Spearman"), "value"),
    "median_kendall": (("median", "Kendall"), "value"),
    "targets": (("targets",), "index"),
}
#: Significant digits of the values (regret, correlations, the criteria's values).
DIGITS = 3
#: A joint position column of a choice table (``q1`` .. ``qn``: the picked posture).
_JOINT = re.compile(r"q([1-9][0-9]*)")
#: The unit of a revolute joint's position column header, and of a prismatic joint's.
JOINT_UNIT = "rad"
PRISMATIC_UNIT = "m"
#: The units a joint position may have.
JOINT_UNITS = (JOINT_UNIT, PRISMATIC_UNIT)
#: Pinocchio's models of a prismatic joint (``JointModelPX``, ``JointModelPrismaticUnaligned``).
_PRISMATIC = re.compile(r"JointModelP[XYZ]|JointModelPrismatic\w*")


def joint_units(robot: object) -> tuple[str, ...]:
    """The unit of each joint's position: ``"rad"`` (revolute) or ``"m"`` (prismatic).

    A URDF robot (:class:`polyell.UrdfRobot`) by the kinds of its Pinocchio joints, after
    its locked joints are removed; a planar arm's joints are revolute.

    Examples
    --------
    >>> import polyell as pe
    >>> joint_units(pe.robots.load("chiacchio2000"))
    ('rad', 'rad', 'rad')
    """
    n = getattr(robot, "n", None)
    if not isinstance(n, int) or n < 1:
        raise InputError(
            "robot",
            "a robot model (pe.PlanarArm or pe.UrdfRobot)",
            type(robot).__name__,
            "pass the robot itself, e.g. joint_units(pe.robots.load('chiacchio2000')).",
        )
    units = [JOINT_UNIT] * n
    model = getattr(robot, "model", None)  # a URDF robot's Pinocchio model
    for joint in list(getattr(model, "joints", ()))[1:]:  # (the first is the universe)
        if _PRISMATIC.fullmatch(str(joint.shortname())) and 0 <= joint.idx_v < n:
            units[joint.idx_v] = PRISMATIC_UNIT
    return tuple(units)


def _joint_units(units: object, table: pd.DataFrame) -> tuple[str, ...] | None:
    """``joint_units`` as given (or the table's ``attrs``), checked against its columns."""
    if units is None:
        units = table.attrs.get("joint_units")
        if units is None:
            return None
    joints = [c for c in table.columns if isinstance(c, str) and _JOINT.fullmatch(c)]
    if (
        isinstance(units, str)
        or not isinstance(units, list | tuple)
        or not all(isinstance(unit, str) and unit in JOINT_UNITS for unit in units)
    ):
        raise InputError(
            "joint_units",
            f"a unit per joint, each among {list(JOINT_UNITS)}",
            repr(units)[:80],
            "pass polyell.studies.posture_tables.joint_units(robot), or None (every joint "
            "revolute).",
        )
    highest = max((int(c[1:]) for c in joints), default=0)
    if len(units) < highest:
        raise InputError(
            "joint_units",
            f"a unit for each of the table's {highest} joints",
            f"{len(units)} units",
            "pass one unit per joint of the robot: joint_units(robot).",
        )
    return tuple(units)


def _shown(column: object) -> bool:
    """Whether a column of the table is shown: a known column or a joint position."""
    return column in _COLUMNS or (isinstance(column, str) and bool(_JOINT.fullmatch(column)))


def _header(column: str, units: tuple[str, ...] | None = None) -> Label:
    """A column's header: its lines (stacked in LaTeX), or ``q1 [rad]`` (``[m]``) for a joint."""
    joint = _JOINT.fullmatch(column)
    if joint:
        symbol = f"$q_{{{joint.group(1)}}}$"
        unit = JOINT_UNIT if units is None else units[int(joint.group(1)) - 1]
        return Label(f"{column} [{unit}]", f"{symbol} [{unit}]", (symbol, f"[{unit}]"))
    lines = _COLUMNS[column][0]
    plain = " ".join(lines).replace("- ", "")
    if len(lines) == 1:
        return Label(plain, escape_latex(plain, "column"))
    return Label(
        plain,
        escape_latex(plain, "column"),
        tuple(escape_latex(line, "column") for line in lines),
    )


def _criterion(criterion: str, unit: object) -> Label:
    """A criterion's row label, with the unit of its values in brackets (``limit [m/s^2]``).

    ``unit`` is the table's ``unit`` cell (:func:`polyell.studies.posture.criterion_units`:
    ``m/s^2``, ``(m/s^2)^3``); none (a table without units, a summary over targets): the
    criterion alone.
    """
    from pandas import NA

    if unit is None or unit is NA or (isinstance(unit, float) and math.isnan(unit)):
        return text_label(criterion, "criterion")  # (a row without a unit)
    if not isinstance(unit, str) or not unit:
        raise InputError(
            "table['unit']",
            "units such as 'm/s^2'",
            repr(unit)[:80],
            "give each row's unit as a non-empty string, e.g. 'm/s^2', or None for none.",
        )
    # the volume's: (m/s^2)^3, or N^3 (a unit of one symbol)
    power = re.fullmatch(r"\((.+)\)\^([0-9]+)|([A-Za-z]+)\^([0-9]+)", unit)
    if power is None:
        latex = latex_unit(unit)
    elif power.group(1) is not None:
        latex = latex_unit(power.group(1), power.group(2))
    else:
        latex = latex_unit(power.group(3), power.group(4))
    head = escape_latex(criterion, "criterion")
    return Label(f"{criterion} [{unit}]", f"{head} [{latex}]")


def _number(value: object, column: str) -> float:
    """A cell of the choice table as a float, or an InputError naming its column."""
    fix = (
        f"convert the column to numbers, e.g. table[{column!r}] = "
        f"pd.to_numeric(table[{column!r}]), or pass the table posture_choice returned."
    )
    if isinstance(value, str | bytes):
        raise InputError(f"table[{column!r}]", "numbers", repr(value)[:80], fix)
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"table[{column!r}]", "numbers", repr(value)[:80], fix) from None


def _print_table(
    table: pd.DataFrame,
    layout: TableLayout,
    units: tuple[str, ...] | None = None,
    *,
    criteria_units: bool = True,
) -> PrintTable:
    """The choice table laid out by the package's table writers: a line per set.

    ``criteria_units=False``: each criterion without the unit of its values (a table of
    the picks' joint positions, which are in the joints' units).
    """
    if table.index.nlevels != 2:
        raise InputError(
            "table",
            "a choice table indexed by (kind, criterion)",
            f"an index of {table.index.nlevels} levels",
            "pass PostureChoice.table or PostureChoiceOverTargets.summary.",
        )
    columns = [c for c in table.columns if _shown(c)]
    if not any(c in _COLUMNS for c in columns):
        raise InputError(
            "table",
            f"columns among {list(_COLUMNS)}",
            f"{list(table.columns)}",
            "pass PostureChoice.table or PostureChoiceOverTargets.summary, or keep one "
            "of these columns, e.g. 'regret'.",
        )
    headers = [_header(column, units) for column in columns]
    with_units = "unit" in table.columns
    from pandas import NA

    capacity = table.attrs.get("capacity", "acceleration")  # set by posture_choice
    rows = []
    for (kind, criterion), record in table.iterrows():
        cells = []
        for column in columns:
            # <NA>: no posture picked (a set undefined at every posture)
            value = (
                math.nan
                if record[column] is None or record[column] is NA
                else _number(record[column], column)
            )
            kind_of = _COLUMNS[column][1] if column in _COLUMNS else "value"
            cells.append(Cell(value, 2 if kind_of == "share" else 0, count=kind_of == "index"))
        stub = (
            given_label(layout.set_text(str(kind), capacity), "sets"),
            _criterion(str(criterion), record["unit"] if with_units and criteria_units else None),
        )
        rows.append((stub, tuple(cells)))
    stub_head = (Label("set", "set"), Label("criterion", "criterion"))
    # mixed: a column holds each criterion's values, in its own unit (siunitx: unaligned)
    return PrintTable(stub_head, tuple(headers), tuple(rows), grouped=True, mixed=True)


def format_posture_table(
    table: pd.DataFrame,
    style: str,
    title: str = "",
    label: str | None = None,
    layout: TableLayout | None = None,
    *,
    caption: Caption | None = None,
    joint_units: Sequence[str] | None = None,
) -> str:
    """A choice table as ``"latex"`` (booktabs, a ``table`` float), ``"markdown"`` or ``"csv"``.

    Written by the package's table writers (the same labels and rounding as every table:
    a line per set, :data:`DIGITS` significant digits, regret in percent).  A choice table's
    picked posture is its row number and its joint positions (``q1 [rad]`` ..), and each
    criterion's cell carries the unit of its values (``limit [m/s^2]``, ``volume
    [(m/s^2)^3]``: the table's ``unit`` column).  In LaTeX the joint positions are a
    second float after the first (each keeps to a one-column page): a row per set and
    criterion, the posture picked and ``$q_1$ [rad]`` .. ``$q_n$`` (``[m]`` for a
    prismatic joint), labelled ``<label>-q``.

    Parameters
    ----------
    table : DataFrame
        :attr:`PostureChoice.table` or :attr:`PostureChoiceOverTargets.summary`.
    style : {"latex", "markdown", "csv"}
    title : str, optional
        The LaTeX caption (unless ``caption`` or the layout's caption is given), or a
        Markdown heading line (plain text, escaped).
    label : str, optional
        A LaTeX label (letters, digits and ``:-_.``).
    layout : TableLayout, optional
        Its ``sets`` (the rows shown, in that order), ``digits``, ``labels``, ``siunitx``
        and ``text_width`` (the LaTeX table is checked against it), as in a study's
        ``[output]``, and its caption of ``"posture_choice"`` (a choice table) or
        ``"posture_targets"`` (a summary over targets); default every set at
        :data:`DIGITS` digits.
    caption : str or (str, str), optional
        The LaTeX caption: plain text, or ``(plain, latex)`` with the LaTeX as is; default
        the layout's caption of this table, else ``title``.
    joint_units : sequence of str, optional
        The unit of each joint's position, ``"rad"`` or ``"m"`` (a prismatic joint):
        :func:`joint_units` of the robot; default the table's ``attrs["joint_units"]``,
        else ``"rad"`` for every joint.
    """
    check_frame("table", table, "pass PostureChoice.table or PostureChoiceOverTargets.summary.")
    title = check_text("title", title)
    units = _joint_units(joint_units, table)
    name = "posture_choice" if "picked" in table.columns else "posture_targets"
    table, digits = _laid_out(table, layout)
    layout = layout or TableLayout(digits=DIGITS)
    if style not in ("latex", "markdown", "csv"):
        raise InputError(
            "style",
            "'latex', 'markdown' or 'csv'",
            repr(style),
            "pass one of the three names, e.g. style='latex'.",
        )
    joints = [c for c in table.columns if re.fullmatch(r"q\d+", str(c))]
    angles = None
    if style == "latex" and joints:  # a one-column page: the angles in a table of their own
        angles = _print_table(table[["picked", *joints]], layout, units, criteria_units=False)
        table = table.drop(columns=joints)
    printable = _print_table(table, layout, units)
    if caption is None:
        own = layout.caption(name)
        caption = (own.plain, own.latex) if own is not None else None
    if style == "markdown":  # the heading, and the caption given (if any) under it
        heading = f"# {escape_markdown(title, 'title')}\n\n" if title else ""
        return heading + render_tables([printable], "markdown", digits, caption)
    caption = caption if caption is not None else (title or None)
    text = render_tables(
        [printable],
        style,  # type: ignore[arg-type]
        digits,
        caption,
        label,
        layout=layout,
    )
    if angles is None:
        return text
    joint_caption = _joints_caption(caption)
    joint_label = None if label is None else f"{check_latex_label(label)}-q"[:200]
    angles_text = render_tables(
        [angles], "latex", digits, joint_caption, joint_label, layout=layout
    )
    return f"{text}\n{angles_text}"


def _joints_caption(caption: Caption | None) -> tuple[str, str]:
    """The joint positions' caption: a sentence, then the choice table's caption.

    ``Joint positions of each posture picked.`` and the context (direction, postures).
    """
    head = "Joint positions of each posture picked."
    if caption is None:
        return head, head
    plain, latex = caption if isinstance(caption, tuple) else (caption, None)
    latex = escape_latex(plain, "caption") if latex is None else latex
    return f"{head} {plain}", f"{head} {latex}"


def _laid_out(table: pd.DataFrame, layout: TableLayout | None) -> tuple[pd.DataFrame, int]:
    """The rows of the sets ``layout`` shows (in its order), and its digits."""
    if layout is None:
        return table, DIGITS
    if not isinstance(layout, TableLayout):
        raise InputError(
            "layout",
            "a pe.TableLayout",
            type(layout).__name__,
            "pass pe.TableLayout(...), e.g. layout=pe.TableLayout(digits=3), or None.",
        )
    if layout.sets is not None and table.index.nlevels == 2:
        present = list(dict.fromkeys(table.index.get_level_values(0)))
        shown = [name for name in layout.sets if name in present]
        if not shown:
            raise InputError(
                "layout.sets",
                f"some of {present}",
                repr(layout.sets),
                f"name sets of the table, e.g. pe.TableLayout(sets={tuple(present[:2])!r}), or "
                "sets=None for every set.",
            )
        table = table.loc[shown]
    return table, layout.digits


def write_posture_tables(
    table: pd.DataFrame,
    folder: str | os.PathLike[str],
    title: str = "Posture choice",
    *,
    label: str | None = None,
    stem: str = POSTURE_TABLE_STEM,
    layout: TableLayout | None = None,
    caption: Caption | None = None,
    joint_units: Sequence[str] | None = None,
) -> dict[str, Path]:
    """Write a choice table as ``<stem>.tex``, ``<stem>.md`` and ``<stem>.csv`` in ``folder``.

    Parameters
    ----------
    table : DataFrame
        :attr:`PostureChoice.table` or :attr:`PostureChoiceOverTargets.summary`.
    folder : str or Path
        An existing folder.
    title : str, optional
        The LaTeX caption and the Markdown heading.
    label : str, optional
        The LaTeX label.
    stem : str, optional
        The file names' stem.
    layout : TableLayout, optional
        The sets, digits and labels of the LaTeX and Markdown tables, the LaTeX's caption,
        ``siunitx`` and ``text_width`` (:func:`format_posture_table`); the CSV holds every
        set.
    caption : str or (str, str), optional
        The LaTeX caption (default the layout's, else ``title``).
    joint_units : sequence of str, optional
        ``"rad"`` or ``"m"`` per joint (:func:`joint_units`): the Markdown headers
        ``q1 [rad]``, ``q2 [m]``.

    Returns
    -------
    dict of str to Path
        ``{"latex": ..., "markdown": ..., "csv": ...}``.  The CSV holds the full-precision
        values (regret as a fraction, the joint positions ``q1`` .. ``qn``) and the
        ``unit`` column.

    Raises
    ------
    InputError
        For a table of another shape, a folder that does not exist, a stem with a path
        separator, text that cannot be written.
    """
    if not isinstance(folder, str | os.PathLike) or not str(folder) or not Path(folder).is_dir():
        raise InputError("folder", "an existing folder", repr(folder), "create it first.")
    if not isinstance(stem, str) or not stem or "/" in stem or "\\" in stem or stem[0] == ".":
        raise InputError(
            "stem",
            "a file name without a path",
            repr(stem),
            f"give a bare name that does not start with '.', e.g. stem={POSTURE_TABLE_STEM!r}; "
            "choose the folder with folder=.",
        )
    units = joint_units
    texts = {
        "latex": format_posture_table(
            table, "latex", title, label, layout, caption=caption, joint_units=units
        ),
        "markdown": format_posture_table(
            table, "markdown", title, layout=layout, caption=caption, joint_units=units
        ),
        "csv": table.to_csv(),
    }
    paths = {}
    for style, suffix in (("latex", ".tex"), ("markdown", ".md"), ("csv", ".csv")):
        paths[style] = write_text_atomically(Path(folder) / f"{stem}{suffix}", texts[style])
    return paths
