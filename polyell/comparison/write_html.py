"""HTML of printed tables (for reports): the same labels, units and numbers as the LaTeX.

Each table sits in a box that scrolls sideways rather than overflowing the page.
"""

from __future__ import annotations

from collections.abc import Sequence
from html import escape as _text  # quotes too

from polyell.comparison.printable import PrintTable

__all__ = ["html_tables"]


def html_tables(tables: Sequence[PrintTable], digits: int, caption: str | None = None) -> str:
    """The tables as HTML fragments (``<div class="polyell-table"><table>...``), escaped."""
    parts = []
    for table in tables:
        title = " ".join(t for t in (caption or "", f"({table.title})" if table.title else "") if t)
        rows = [f"<caption>{_text(title)}</caption>"] if title else []
        s = len(table.stub)
        head = []
        if table.groups:
            spans = [f'<th colspan="{s}"></th>'] + [
                f'<th colspan="{span}" scope="colgroup">{_text(group.plain)}</th>'
                for group, span in table.groups
            ]
            head.append("<tr>" + "".join(spans) + "</tr>")
        head.append(
            "<tr>"
            + "".join(
                f'<th scope="col">{_text(h.plain)}</th>' for h in (*table.stub, *table.columns)
            )
            + "</tr>"
        )
        rows.append("<thead>" + "".join(head) + "</thead>")
        body: list[str] = []
        for labels, cells in table.rows:
            body.append(
                "<tr>"
                + "".join(f'<th scope="row">{_text(label.plain)}</th>' for label in labels)
                + "".join(f"<td>{_text(cell.text(digits))}</td>" for cell in cells)
                + "</tr>"
            )
        rows.append("<tbody>" + "".join(body) + "</tbody>")
        parts.append(
            '<div class="polyell-table" style="overflow-x:auto;max-width:100%">'
            f"<table>{''.join(rows)}</table></div>"
        )
    return "\n".join(parts)
