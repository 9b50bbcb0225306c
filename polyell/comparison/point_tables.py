"""The tables of a points study: the comparison and the directional limits, in each format."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from polyell.comparison.latex_text import check_text, escape_latex, escape_markdown, markdown_text
from polyell.comparison.layout import TableLayout
from polyell.comparison.limits import Directions, limits_table, posture_comparisons
from polyell.comparison.tables import Style, format_comparison_table, format_limits_table
from polyell.errors import InputError
from polyell.storage import write_text_atomically
from polyell.validation import check_instance

if TYPE_CHECKING:
    from polyell.comparison.comparison import Comparison

__all__ = ["TABLE_FORMATS", "default_captions", "write_point_tables"]

#: File formats of the tables and the style each is written in.
TABLE_FORMATS: dict[str, Style] = {"tex": "latex", "md": "markdown", "csv": "csv"}


def default_captions(
    comparisons: Mapping[str, Comparison],
) -> tuple[tuple[str, str], tuple[str, str]]:
    """The default captions of the limits and the comparison table: ``(plain, latex)`` each.

    They name the capacity (but for the paper's, accelerations) and define the relative
    error in mathematics, ``$(e - p)/|p|$``; they do not start with a study's title.

    Examples
    --------
    >>> limits, comparison = default_captions({})
    >>> comparison[0]
    'Scores of each ellipsoid against the exact polytope.'
    """
    if not (isinstance(comparisons, Mapping) and not comparisons):  # {}: no posture yet
        comparisons = posture_comparisons(comparisons)
    capacities = {c.analysis.capacity for c in comparisons.values()}
    paper = bool(comparisons) and all(c.analysis.paper for c in comparisons.values())
    what = "" if paper or not capacities else f"{' and '.join(sorted(capacities))} "
    head = f"Directional {what}limits of the exact polytope and of each ellipsoid, and "
    limits = (
        head + "each limit's error relative to the polytope's, (e - p)/|p| for an "
        "ellipsoid's limit e and the polytope's p.",
        escape_latex(head + "each limit's error relative to the polytope's, ")
        + r"$(e - p)/|p|$ for an ellipsoid's limit $e$ and the polytope's $p$.",
    )
    plain = f"Scores of each {what}ellipsoid against the exact polytope."
    return limits, (plain, escape_latex(plain))


def write_point_tables(
    comparisons: Mapping[str, Comparison],
    directions_per_point: Directions,
    folder: str | os.PathLike[str],
    layout: TableLayout | None = None,
    title: str = "",
    formats: Sequence[str] = ("tex", "md", "csv"),
    description: str = "",
    suffix: str = "",
) -> list[Path]:
    """Write ``limits.<format>`` and ``comparison.<format>`` for comparisons at named postures.

    Parameters
    ----------
    comparisons : mapping of str to Comparison
        By posture name, in the order of the tables.
    directions_per_point : list, mapping or None
        The directions of the limits (:func:`polyell.limits_table`): one list for every
        posture, a list per posture name, or None (the task's coordinate axes).
    folder : str or Path
        An existing folder.
    layout : TableLayout, optional
        Default ``TableLayout()`` (fits a one-column page for up to three postures).  Its
        ``captions["limits"]`` and ``captions["comparison"]`` replace the default
        captions (:func:`default_captions`); its ``labels`` name sets and scores.
    title : str, optional
        Heads the Markdown files (the captions do not repeat it: a paper's table has its
        own context).
    formats : sequence of {"tex", "md", "csv"}
        The files written, each atomically.
    description : str, optional
        Free text under the Markdown files' heading.
    suffix : str, optional
        Appended to the file names and LaTeX labels (``"_force"``: ``limits_force.tex``,
        ``tab:limits_force``): the tables of another capacity beside the acceleration ones.

    Returns
    -------
    list of Path
        The files, limits first.

    Raises
    ------
    InputError
        For an unknown format, a folder that does not exist, bad directions (naming
        ``directions['home'][k]``) or a bad layout (naming its field); nothing is written
        then (every table is made before the first file is written).
    StorageError
        If a file cannot be written.
    """
    wanted = [formats] if isinstance(formats, str) else formats
    names = isinstance(wanted, Sequence) and all(isinstance(f, str) for f in wanted)
    if not names or not wanted or any(f not in TABLE_FORMATS for f in wanted):
        raise InputError(
            "formats",
            f"some of {list(TABLE_FORMATS)}",
            repr(formats)[:80],
            "pass formats among those listed, e.g. formats=('tex', 'md')",
        )
    if not isinstance(folder, str | os.PathLike) or not Path(folder).is_dir():
        raise InputError(
            "folder",
            "an existing folder",
            repr(folder)[:120],
            "create it first, e.g. Path(folder).mkdir(parents=True, exist_ok=True)"
            if isinstance(folder, str | os.PathLike)
            else "pass the folder's path as a str or Path, e.g. 'tables'",
        )
    title = check_text("title", title)
    description = check_text("description", description)
    about = f"{description}\n\n" if description else ""
    layout = TableLayout() if layout is None else layout
    check_instance("layout", layout, TableLayout, "pass pe.TableLayout(...) or leave it out.")
    named = posture_comparisons(comparisons)
    limits = limits_table(named, directions_per_point)
    prefix = f"{title}: " if title else ""
    defaults = dict(zip(("limits", "comparison"), default_captions(named), strict=True))
    captions: dict[str, tuple[str, str | None]] = {}
    for table, default in defaults.items():
        own = layout.caption(table)
        captions[table] = default if own is None else (own.plain, own.latex)
    limits_caption, comparison_caption = captions["limits"], captions["comparison"]
    texts: dict[str, str] = {}
    for extension in wanted:
        style = TABLE_FORMATS[extension]
        limits_text = format_limits_table(
            limits, style, layout=layout, caption=limits_caption, label=f"tab:limits{suffix}"
        )
        comparison_text = format_comparison_table(
            named,
            style,
            layout=layout,
            caption=comparison_caption,
            label=f"tab:comparison{suffix}",
        )
        if extension == "md":  # (the text without live HTML)
            head, intro = escape_markdown(prefix, "title"), markdown_text(about)
            # (the tables' Markdown starts with their captions)
            limits_text = f"# {head}directional limits\n\n{intro}{limits_text}"
            comparison_text = f"# {head}comparison\n\n{intro}{comparison_text}"
        texts[f"limits{suffix}.{extension}"] = limits_text
        texts[f"comparison{suffix}.{extension}"] = comparison_text
    order = sorted(texts, key=lambda name: (not name.startswith("limits"), name))
    return [write_text_atomically(Path(folder) / name, texts[name]) for name in order]
