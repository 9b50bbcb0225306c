"""Every writer (LaTeX, Markdown, CSV, HTML) shows the same labels and the same numbers.

Properties over any labels (LaTeX and Markdown specials too), any values (NaN, infinities,
0, 1e-300, 1e300), 1 to 17 digits, percent or fractions, either orientation, one table or
one per posture: CSV reads back the exact doubles, Markdown, LaTeX and HTML the values to
the stated digits (checked in decimal, from the exact binary value).
"""

from __future__ import annotations

import csv
import io
import math
import re
from decimal import Decimal
from html.parser import HTMLParser

import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st
from latex_numbers import parse_all as parse_tables

from polyell.comparison.layout import TableLayout
from polyell.comparison.limits import LIMIT_COLUMNS
from polyell.comparison.tables import format_limits_table
from polyell.errors import InputError

SPECIALS = "\\{}$&%#_~^<>|*`[]"
LABEL = st.text(alphabet="abcxyz 0189." + SPECIALS, min_size=1, max_size=8).filter(
    lambda text: text.strip() != ""
)
VALUE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300, 0.5, 1.0, 5e-324]),
)


def normalized(text: str) -> str:
    """A label as every parser reads it back: whitespace runs as one space, ends stripped."""
    return re.sub(r"\s+", " ", text).strip()


@st.composite
def limits_frames(draw):
    """A directional-limits frame of 1-3 postures, 1-2 directions, 1-3 sets."""
    postures = draw(st.lists(LABEL, min_size=1, max_size=3, unique_by=normalized))
    directions = draw(st.lists(LABEL, min_size=1, max_size=2, unique_by=normalized))
    sets = draw(st.lists(LABEL, min_size=1, max_size=3, unique_by=normalized))
    rows = []
    for posture in postures:
        for direction in directions:
            for kind in sets:
                values = draw(st.lists(VALUE, min_size=4, max_size=4))
                defined = draw(st.booleans())
                rows.append((posture, direction, kind, defined, *values, "m/s^2"))
    return pd.DataFrame(rows, columns=["posture", *LIMIT_COLUMNS])


LAYOUTS = st.builds(
    TableLayout,
    text_width=st.just(None),  # (random tables are of any width; test_paper_tables checks it)
    transpose=st.booleans(),
    split=st.sampled_from(["combined", "posture"]),
    digits=st.integers(1, 17),
    percent=st.booleans(),
)


def expected_cells(frame: pd.DataFrame, layout: TableLayout) -> dict[tuple[str, ...], tuple]:
    """(posture, direction, set, quantity) -> (value, shift, missing text), from the frame."""
    cells = {}
    for row in frame.itertuples(index=False):
        for quantity in ("lower", "upper", "lower_error", "upper_error"):
            share = quantity.endswith("error")
            missing = "n/a" if share or not row.defined else "empty"
            key = (normalized(row.posture), normalized(row.direction), normalized(row.set))
            cells[(*key, quantity)] = (
                getattr(row, quantity),
                2 if share and layout.percent else 0,
                missing,
            )
    return cells


def zero_errors(values) -> bool:
    """An error column left out: 0 wherever it has a number, and 0 somewhere."""
    numbers = [v for v in values if not math.isnan(v)]
    return bool(numbers) and all(v == 0 for v in numbers)


def shown_cells(frame: pd.DataFrame, layout: TableLayout) -> int:
    """How many cells the tables show: error columns zero in every row are left out.

    Transposed, a column is one set's error; else one error over every set.  (The layouts
    here choose no scores: the defaults leave those columns out.)
    """
    count = 0
    for quantity in ("lower", "upper", "lower_error", "upper_error"):
        if not quantity.endswith("error"):
            count += len(frame)
            continue
        groups = frame.groupby("set", sort=False) if layout.transpose else [("", frame)]
        for _, part in groups:
            if not zero_errors(part[quantity].tolist()):
                count += len(part)
    return count


QUANTITY = re.compile(r"(lower|upper)( error)?")


def check_number(text: str, value: float, shift: int, missing: str, digits: int | None) -> None:
    """``text`` shows ``value * 10**shift``: exactly (digits None) or to ``digits`` digits."""
    if math.isnan(value):
        assert text == missing, (text, value)
        return
    if math.isinf(value):
        assert text == ("inf" if value > 0 else "-inf"), (text, value)
        return
    shown = Decimal(text)
    if digits is None:  # full precision: reads back as the very same double
        assert float(shown.scaleb(-shift)) == value, (text, value)
        return
    exact = Decimal(value).scaleb(shift)
    assert len(shown.normalize().as_tuple().digits) <= digits, (text, digits)
    if exact == 0:
        assert shown == 0
        return
    half_unit = Decimal(5).scaleb(exact.adjusted() - digits)
    assert abs(shown - exact) <= half_unit, (text, value, digits)


def check_grid(
    header: list[str], rows: list[list[str]], frame, layout, digits, title: str = ""
) -> int:
    """A parsed grid (labels first) against the frame's values; returns the cells checked.

    ``title``: the posture of a table per posture (its rows have no posture label).
    """
    expected = expected_cells(frame, layout)
    stub = [h for h in header if h in ("posture", "direction", "set")]
    seen = 0
    for row in rows:
        labels = {h: normalized(label) for h, label in zip(stub, row, strict=False)}
        posture = labels.get("posture", normalized(title))
        for head, text in zip(header[len(stub) :], row[len(stub) :], strict=True):
            if layout.transpose:
                kind, _, name = head.rpartition(": ")
                kind = normalized(kind)
            else:
                kind, name = labels["set"], head
            quantity = QUANTITY.match(name).group().replace(" ", "_")
            value, shift, missing = expected[(posture, labels["direction"], kind, quantity)]
            check_number(text, value, shift, missing, digits)
            seen += 1
    return seen


def _unentity(text: str) -> str:
    """Markdown's entities back to text: a label's ``<``, ``>`` (and ``&`` of one) escaped."""
    return text.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")


def _unescape(text: str) -> str:
    """Markdown's backslash escapes (``\\|``, ``\\*``, ``\\_``, ...) back to their characters."""
    return re.sub(r"\\(.)", r"\1", text)


def markdown_grids(text: str) -> tuple[list[list[list[str]]], list[str]]:
    """Each Markdown table's rows (header first) as unescaped cells, and the bold titles."""
    grids, titles, current = [], [], None
    for line in text.splitlines():
        if line.startswith("**"):
            titles.append(_unentity(_unescape(line[2:-2])))
        elif line.startswith("| "):
            cells = re.split(r"(?<!\\)\|", line.replace("\\\\", "\x00"))[1:-1]
            cells = [_unentity(_unescape(c.strip().replace("\x00", "\\\\"))) for c in cells]
            if current is None:
                current = [cells]
                grids.append(current)
            elif not set("".join(cells)) <= set(":-"):
                current.append(cells)
        else:
            current = None
    return grids, titles


class _Cells(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.tables: list[list[list[str]]] = []
        self.captions: list[str] = []
        self._row: list[str] | None = None
        self._text: str | None = None
        self._caption = False

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self._row = []
        elif tag in ("td", "th"):
            self._text = ""
            self._span = int(dict(attrs).get("colspan", 1))
        elif tag == "caption":
            self._caption, self._text = True, ""

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._row is not None:
            self._row += [self._text] * self._span
        elif tag == "tr":
            self.tables[-1].append(self._row)
        elif tag == "caption":
            self.captions.append(self._text)
            self._caption = False

    def handle_data(self, data):
        if self._text is not None:
            self._text += data


@given(frame=limits_frames(), layout=LAYOUTS)
def test_every_writer_shows_the_same_numbers(frame, layout):
    digits, total = layout.digits, shown_cells(frame, layout)
    tables = frame["posture"].nunique() if layout.split == "posture" else 1
    # Markdown (a table per posture is headed by the posture in bold)
    grids, titles = markdown_grids(format_limits_table(frame, "markdown", layout=layout))
    assert len(grids) == tables and len(titles) == (tables if layout.split == "posture" else 0)
    seen = sum(
        check_grid(grid[0], grid[1:], frame, layout, digits, titles[k] if titles else "")
        for k, grid in enumerate(grids)
    )
    assert seen == total
    # LaTeX, the caption holding every special character; a posture is a line above its rows
    tex = format_limits_table(frame, "latex", layout=layout, caption=SPECIALS, label="tab:l")
    parsed = parse_tables(tex)
    assert len(parsed) == tables
    seen = 0
    for k, table in enumerate(parsed):
        assert table.caption.startswith(normalized(SPECIALS))
        posture_lines = table.stub > len([h for h in table.header if h in ("direction", "set")])
        header = ["posture", *table.header] if posture_lines else table.header
        seen += check_grid(header, table.rows, frame, layout, digits, titles[k] if titles else "")
    assert seen == total
    # HTML (grouped headers span their columns)
    cells = _Cells()
    cells.feed(format_limits_table(frame, "html", layout=layout, caption="<b>&"))
    assert len(cells.tables) == tables
    seen = 0
    for k, table in enumerate(cells.tables):
        header, rows = table[0], table[1:]
        if layout.transpose:
            header = [h if not g else f"{g}: {h}" for g, h in zip(table[0], table[1], strict=True)]
            rows = table[2:]
        seen += check_grid(header, rows, frame, layout, digits, titles[k] if titles else "")
        assert cells.captions[k].startswith("<b>&")
    assert seen == total
    # CSV: every table in one file (a posture column), the exact doubles
    records = list(csv.reader(io.StringIO(format_limits_table(frame, "csv", layout=layout))))
    assert check_grid(records[0], records[1:], frame, layout, None) == total


@pytest.mark.parametrize(
    ("fields", "field"),
    [
        ({"digits": 0}, "layout.digits"),
        ({"digits": 18}, "layout.digits"),
        ({"digits": 3.0}, "layout.digits"),
        ({"digits": True}, "layout.digits"),
        ({"split": "rows"}, "layout.split"),
        ({"transpose": "yes"}, "layout.transpose"),
        ({"percent": 1}, "layout.percent"),
        ({"sets": "chiacchio"}, "layout.sets"),
        ({"sets": []}, "layout.sets"),
        ({"sets": ["mvie", "mvie"]}, "layout.sets"),
        ({"scores": [3]}, "layout.scores"),
    ],
)
def test_a_bad_layout_names_its_field(fields, field):
    with pytest.raises(InputError) as info:
        TableLayout(**fields)
    assert info.value.argument == field


def test_a_layout_naming_what_the_table_lacks_names_its_field():
    frame = pd.DataFrame(
        [("x", "polytope", True, -1.0, 1.0, 0.0, 0.0, "m/s^2")], columns=list(LIMIT_COLUMNS)
    )
    with pytest.raises(InputError) as info:
        format_limits_table(frame, "markdown", layout=TableLayout(sets=["mvie"]))
    assert info.value.argument == "layout.sets"
    with pytest.raises(InputError) as info:
        format_limits_table(frame, "markdown", layout=TableLayout(scores=["lower", "uper"]))
    assert info.value.argument == "layout.scores"
    with pytest.raises(InputError) as info:
        format_limits_table(frame, "pdf")  # type: ignore[arg-type]
    assert info.value.argument == "style"
    with pytest.raises(InputError) as info:
        format_limits_table(frame.drop(columns="unit"), "csv")
    assert info.value.argument == "frame"
    only = format_limits_table(frame, "markdown", layout=TableLayout(scores=["upper", "coverage"]))
    assert "upper [m/s^2]" in only and "lower" not in only


def test_percent_and_fractions_show_the_same_digits():
    frame = pd.DataFrame(
        [("x", "mvie", True, -1.0, 1.0, 0.123456, -1e-300, "m/s^2")], columns=list(LIMIT_COLUMNS)
    )
    percent = format_limits_table(frame, "markdown", layout=TableLayout(digits=4))
    fraction = format_limits_table(frame, "markdown", layout=TableLayout(digits=4, percent=False))

    def last_cells(table: str) -> list[str]:
        return [cell.strip() for cell in table.splitlines()[-1].split("|")[1:-1]]

    # every number at its 4 significant digits, trailing zeros included
    assert last_cells(percent)[-2:] == ["12.35", "-1.000e-298"] and "lower error [%]" in percent
    assert last_cells(fraction)[-2:] == ["0.1235", "-1.000e-300"] and "| lower error |" in fraction
    rows = list(csv.reader(io.StringIO(format_limits_table(frame, "csv"))))
    assert rows[1][-2:] == ["12.3456", "-1e-298"]
    assert float(Decimal(rows[1][-2]).scaleb(-2)) == 0.123456  # exactly, not 12.3456 / 100
