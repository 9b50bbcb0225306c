"""Markdown (GitHub) of printed tables: the same labels, units and numbers as the LaTeX."""

from __future__ import annotations

from collections.abc import Sequence

from polyell.comparison.latex_text import escape_markdown
from polyell.comparison.printable import PrintTable

__all__ = ["flat_headers", "markdown_grid", "markdown_tables"]


def flat_headers(table: PrintTable) -> list[str]:
    """One line of plain headers: ``set: quantity`` under a group, else the quantity's."""
    return [head.plain for head in table.stub] + [
        f"{group}: {head.plain}" if group else head.plain
        for group, head in zip(table.group_of(), table.columns, strict=True)
    ]


def markdown_grid(header: list[str], body: list[list[str]], stub: int = 1) -> str:
    """A GitHub Markdown table: the first ``stub`` columns left-aligned, the others right."""
    rows = [[escape_markdown(text, "cell") for text in row] for row in [header, *body]]
    widths = [max(3, *(len(row[i]) for row in rows)) for i in range(len(header))]
    rule = [":" + "-" * (w - 1) if i < stub else "-" * (w - 1) + ":" for i, w in enumerate(widths)]
    lines = [
        "| "
        + " | ".join(
            text.ljust(width) if i < stub else text.rjust(width)
            for i, (text, width) in enumerate(zip(row, widths, strict=True))
        )
        + " |"
        for row in rows
    ]
    lines.insert(1, "| " + " | ".join(rule) + " |")
    return "\n".join(lines) + "\n"


def markdown_tables(tables: Sequence[PrintTable], digits: int) -> str:
    """The tables in Markdown; a table of one posture is headed by its name in bold."""
    parts = []
    for table in tables:
        body = [
            [label.plain for label in labels] + [cell.text(digits) for cell in cells]
            for labels, cells in table.rows
        ]
        grid = markdown_grid(flat_headers(table), body, len(table.stub))
        name = escape_markdown(table.title, "posture").strip()
        title = f"**{name}**\n\n" if name else ""
        parts.append(title + grid)
    return "\n".join(parts)
