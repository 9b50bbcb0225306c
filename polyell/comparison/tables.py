"""Paper-ready tables of scores: Markdown and LaTeX (booktabs), rounded, with units."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Literal

import numpy as np

if TYPE_CHECKING:  # pandas is imported where it is used (start-up time)
    import pandas as pd

__all__ = [
    "ELLIPSOID_LABELS",
    "PERCENT_SCORES",
    "SCORE_ROWS",
    "ellipsoid_label",
    "format_scores_table",
    "render_table",
    "score_display",
]

#: Column headers of the ellipsoids.
ELLIPSOID_LABELS = {
    "chiacchio": "new (eq. 32/38)",
    "yoshikawa": "classic (eq. 27)",
    "mvie": "MVIE",
    "outer": "outer (min. volume)",
}


def ellipsoid_label(kind: str, latex: bool = False) -> str:
    """The column header of an ellipsoid; a candidate's is its name (LaTeX-escaped)."""
    label = ELLIPSOID_LABELS.get(kind, kind)
    return label.replace("_", r"\_") if latex else label


def _significant(value: float) -> str:
    return f"{value:.4g}"


def _percent(value: float) -> str:
    return f"{round(100.0 * value, 2) + 0.0:.2f}"  # + 0.0: a rounded -0.0 shows as 0.00


def _count(value: float) -> str:
    return f"{int(value)}"


#: (score, Markdown label, LaTeX label, formatter, standard-error column or None).
SCORE_ROWS: tuple[tuple[str, str, str, Callable[[float], str], str | None], ...] = (
    ("dimension", "dimension r", "dimension $r$", _count, None),
    ("volume", "volume [{u}]", r"volume [${u}$]", _significant, None),
    ("inscribed_scale", "inscribed scale", "inscribed scale", _significant, None),
    ("enclosing_scale", "enclosing scale", "enclosing scale", _significant, None),
    ("coverage", "coverage [%]", r"coverage [\%]", _percent, "coverage_stderr"),
    ("overreach", "overreach [%]", r"overreach [\%]", _percent, "overreach_stderr"),
    ("mvie_ratio", "volume / MVIE volume", "volume / MVIE volume", _significant, None),
    ("outer_ratio", "volume / outer volume", "volume / outer volume", _significant, None),
    (
        "direction_error_mean",
        "direction error, mean [%]",
        r"dir.\ error, mean [\%]",
        _percent,
        None,
    ),
    ("direction_error_max", "direction error, max [%]", r"dir.\ error, max [\%]", _percent, None),
    ("direction_error_rms", "direction error, RMS [%]", r"dir.\ error, RMS [\%]", _percent, None),
    ("direction_bias", "direction bias [%]", r"dir.\ bias [\%]", _percent, None),
    ("feasibility_mismatch", "feasibility mismatches", "feasibility mismatches", _count, None),
    (
        "witness_torque_max",
        "witness max abs(tau_n)",
        r"witness $\max \|\tilde\tau\|_\infty$",
        _significant,
        None,
    ),
)


#: Scores shown in percent wherever they are shown (tables, summaries, figures); the
#: data (Scores, CSV, Parquet, JSON) keep them as fractions.
PERCENT_SCORES = frozenset(row[0] for row in SCORE_ROWS if row[3] is _percent)


def score_display(score: str) -> tuple[str, float]:
    """The label and the factor a score is displayed with: ``("coverage [%]", 100.0)``."""
    name = score.replace("_", " ")
    return (f"{name} [%]", 100.0) if score in PERCENT_SCORES else (name, 1.0)


def _cell(
    row: pd.Series, score: str, fmt: Callable[[float], str], stderr: str | None, pm: str
) -> str:
    if not row["defined"]:
        return "n/a"
    value = row[score]
    if isinstance(value, float) and np.isnan(value):
        return "n/a"
    text = fmt(value)
    if stderr is not None and row[stderr] > 0:
        text += f" {pm} {fmt(row[stderr])}"
    return text


def format_scores_table(
    frame: pd.DataFrame,
    dimension: int | None,
    style: Literal["markdown", "latex"],
    *,
    unit: str = "m/s^2",
    caption: str | None = None,
    label: str | None = None,
) -> str:
    """Render scores with one column per ellipsoid and one row per score.

    Parameters
    ----------
    frame : DataFrame
        Scores, indexed by ellipsoid kind, as from ``Comparison.to_frame``.
    dimension : int or None
        Dimension r of the polytope (the power of the volume unit); None for a table
        mixing dimensions (the unit is then written with the power ``r``).
    style : {"markdown", "latex"}
    unit : str, optional
        The acceleration unit.
    caption, label : str, optional
        LaTeX caption and label.
    """
    latex = style == "latex"
    pm = r"$\pm$" if latex else "±"
    base = rf"\mathrm{{{unit}}}" if latex else unit
    power = "r" if dimension is None else str(dimension)
    volume_unit = base
    if power != "1":
        volume_unit = f"({base})^{{{power}}}" if latex else f"({base})^{power}"
    rows = {}
    for score, md_label, tex_label, fmt, stderr in SCORE_ROWS:
        name = (tex_label if latex else md_label).format(u=volume_unit)
        rows[name] = {
            ellipsoid_label(str(kind), latex): _cell(row, score, fmt, stderr, pm)
            for kind, row in frame.iterrows()
        }
    import pandas as pd

    return render_table(pd.DataFrame.from_dict(rows, orient="index"), style, caption, label)


def render_table(
    table: pd.DataFrame,
    style: Literal["markdown", "latex"],
    caption: str | None = None,
    label: str | None = None,
) -> str:
    """Render a table of preformatted strings: Markdown, or LaTeX with booktabs rules.

    The index is the first (left-aligned) column, every other column is right-aligned.
    """
    if style == "markdown":
        table = table.rename_axis("score")
        align = ["left"] + ["right"] * table.shape[1]
        return table.to_markdown(colalign=align, disable_numparse=True) + "\n"
    return table.style.to_latex(
        hrules=True,
        caption=caption,
        label=label,
        position_float="centering",
        column_format="l" + "r" * table.shape[1],
    )
