"""CSV of printed tables: the same labels and units, every number at full precision.

A number is written as the shortest decimal that reads back as the double it shows
(``repr``), its point moved two places for a percentage: ``pandas.read_csv`` gives the
same values (a percentage divided by 100 in decimal gives back the fraction exactly).
A column holding estimates is followed by one of their standard errors.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence

from polyell.comparison.printable import PrintTable, decimal_text
from polyell.comparison.write_markdown import flat_headers

__all__ = ["csv_tables"]


def csv_tables(tables: Sequence[PrintTable]) -> str:
    """One CSV of the tables: tables of one posture each get a leading ``posture`` column.

    Every table must have the same headers (as the tables of one layout do).
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    split = any(table.title for table in tables)
    with_error = sorted(
        {
            j
            for table in tables
            for _, cells in table.rows
            for j, c in enumerate(cells)
            if c.has_error()
        }
    )
    for k, table in enumerate(tables):
        headers = flat_headers(table)
        s = len(table.stub)
        if k == 0:
            head = headers[:s] + [
                name
                for j, column in enumerate(headers[s:])
                for name in ([column, f"{column} std. error"] if j in with_error else [column])
            ]
            writer.writerow((["posture"] if split else []) + head)
        for labels, cells in table.rows:
            values = []
            for j, cell in enumerate(cells):
                values.append(cell.exact())
                if j in with_error:
                    values.append(decimal_text(cell.stderr, cell.shift) if cell.has_error() else "")
            writer.writerow(
                ([table.title] if split else []) + [label.plain for label in labels] + values
            )
    return buffer.getvalue()
