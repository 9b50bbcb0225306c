"""LaTeX, Markdown and CSV tables: every user string escaped, no row lost, exact round trips.

The LaTeX tables are compiled with pdfLaTeX and LuaLaTeX where they are installed (CI
installs them; see .ci/run); where an engine is missing its test skips and says so, and
the parser checks (which run everywhere) still verify every row and every escape.
"""

from __future__ import annotations

import re
import string
import unicodedata
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st
from latex_check import compile_tables, engine, unescape
from latex_numbers import parse as parse_table
from latex_numbers import pdf_pattern

import polyell as pe
from polyell.comparison.labels import QUANTITIES
from polyell.comparison.print_scores import DEFAULT_SCORES
from polyell.comparison.summary import format_summary_table, summarize
from polyell.comparison.tables import (
    check_text,
    escape_latex,
    escape_markdown,
    format_comparison_table,
    format_limits_table,
    format_scores_table,
)
from polyell.comparison.write_markdown import markdown_grid
from polyell.errors import InputError
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis

HOSTILE = r"50% & 30 % \input{/etc/passwd} _#$ ~^ {x} <a|b> \\ τ_max ± 5° \% end"


@pytest.fixture(scope="module")
def paper() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 36, mvie=False)


@pytest.fixture(scope="module")
def singular() -> pe.Comparison:
    return pe.compare(paper_analysis(PAPER_Q_SINGULAR), 36, mvie=False)


def summary_of(*comparisons: pe.Comparison) -> pd.DataFrame:
    return summarize(pd.DataFrame([c.to_row() for c in comparisons]))


def normalized(text: str) -> str:
    """The documented normalization: each run of whitespace becomes one space."""
    return re.sub(r"\s+", " ", text)


def test_summary_rows_with_percent_survive_as_text(paper, singular):
    # The reported defect: "coverage [%]" was written bare, a LaTeX comment.
    tex = format_summary_table(summary_of(paper, singular), "latex", caption="50 % of it")
    parsed = parse_table(tex)
    labels = [(row[0], row[1]) for row in parsed.rows]  # the set's line, the score
    assert ("Chiacchio", "coverage [%]") in labels
    assert len(parsed.rows) == len(summary_of(paper, singular))
    assert parsed.caption == "50 % of it"


def test_hostile_caption_and_names_are_printed_not_run(paper):
    frame = paper.to_frame().rename(index={"outer": "x_y & z % w"})
    tex = format_scores_table(frame, 2, "latex", caption=HOSTILE, label="tab:x")
    assert r"\input{" not in tex
    parsed = parse_table(tex)
    assert parsed.caption == HOSTILE
    assert parsed.header[-1] == "x_y & z % w"
    assert [row[0] for row in parsed.rows][4] == "coverage [%]"
    # every default score some set has (not the ratio to an MVIE that was not computed),
    # but a count or share that is zero for every set (the feasibility mismatches)
    shown = [
        s
        for s in DEFAULT_SCORES
        if frame[s].notna().any()
        and not (QUANTITIES[s].kind in ("count", "share") and (frame[s].dropna() == 0).all())
    ]
    assert len(parsed.rows) == len(shown) and "feas.\\ mismatches" not in tex


def test_a_label_that_is_not_a_key_is_refused(paper):
    for label in ("tab}\\input{x", "a b", "", 5, "x%"):
        with pytest.raises(InputError, match="label"):
            paper.to_latex(label=label)  # type: ignore[arg-type]


def test_text_with_control_characters_is_refused_with_the_argument(paper):
    with pytest.raises(InputError, match="caption"):
        paper.to_latex(caption="a\x00b")
    with pytest.raises(InputError, match="caption"):
        paper.to_latex(caption="a\ud800b")  # a lone surrogate: UTF-8 cannot write it
    with pytest.raises(InputError, match="caption"):
        paper.to_latex(caption=5)  # type: ignore[arg-type]
    assert check_text("x", "a\n\tb  c") == "a b c"  # line breaks cannot end a row


@given(st.text(max_size=40))
def test_escape_latex_round_trips_or_refuses(text):
    try:
        escaped = escape_latex(text)
    except InputError:
        assert any(ord(c) < 32 or 0x7F <= ord(c) < 0xA0 or 0xD800 <= ord(c) < 0xE000 for c in text)
        return
    assert unescape(escaped) == normalized(text)


@given(st.text(alphabet=st.characters(blacklist_categories=("Cc", "Cs")), max_size=30))
def test_markdown_rows_keep_their_columns(text):
    frame = pd.DataFrame([[text, "1"], ["2", text]], index=[text, "b"], columns=[text, "c"])
    body = [[name, *row] for name, row in zip(frame.index, frame.to_numpy().tolist(), strict=True)]
    table = markdown_grid(["score", *frame.columns], body)
    lines = table.splitlines()
    assert len(lines) == 2 + len(frame)  # header, rule, one line per row
    for line in lines:  # 3 columns: 4 unescaped pipes on every line
        cells = line.replace("\\\\", "").replace("\\|", "").count("|")
        assert cells == 4, line
    plain = re.sub(r"\\(.)", r"\1", escape_markdown(text))
    plain = plain.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
    assert plain == normalized(text)


@given(st.text(alphabet=st.characters(blacklist_categories=("Cc", "Cs")), max_size=30))
def test_markdown_text_renders_as_typed(text):
    """An independent Markdown parser (markdown-it: CommonMark with GitHub's tables and
    strike-through) reads an escaped label as the plain text typed: no emphasis, code,
    link, HTML or entity."""
    from markdown_it import MarkdownIt

    escaped = escape_markdown(f"x {text} x")  # (no leading #, -, 1. or > block markers)
    parser = MarkdownIt("commonmark").enable(["strikethrough", "table"])
    tokens = parser.parseInline(escaped)[0].children
    assert {token.type for token in tokens} <= {"text"}, escaped
    assert "".join(token.content for token in tokens) == normalized(f"x {text} x")


def test_markdown_escapes_emphasis_code_maths_and_links():
    assert escape_markdown("*a* _b_ ~~s~~ `c` $d$ [e](f) [g][h] [m/s^2] i|j \\") == (
        "\\*a\\* \\_b\\_ \\~\\~s\\~\\~ \\`c\\` \\$d\\$ [e\\](f) [g\\][h] [m/s^2] i\\|j \\\\"
    )


EVERY_SCORE = pe.TableLayout(scores=list(DEFAULT_SCORES))


@pytest.mark.filterwarnings("ignore:The LaTeX table")  # (long random names: wide, and said)
@given(
    caption=st.text(max_size=30),
    name=st.from_regex(r"[a-z][a-z0-9_]{0,10}", fullmatch=True),
    values=st.lists(
        st.one_of(
            st.floats(allow_nan=True, allow_infinity=True),
            st.sampled_from([1e-300, 1e300, -1e-300, -1e300, 0.0, -0.0]),
        ),
        min_size=len(pe.SCORE_NAMES),
        max_size=len(pe.SCORE_NAMES),
    ),
)
def test_any_scores_any_caption_every_row_kept(paper, caption, name, values):
    frame = paper.to_frame().astype({score: float for score in pe.SCORE_NAMES})
    frame.loc[name] = frame.loc["chiacchio"]
    frame.loc[name, list(pe.SCORE_NAMES)] = values
    try:
        # every score chosen: kept even where zero for every set (the defaults drop those)
        tex = format_scores_table(
            frame, 2, "latex", caption=caption, label="tab:s", layout=EVERY_SCORE
        )
    except InputError as exn:  # only a caption with control characters is refused
        assert exn.argument == "caption"
        assert any(ord(c) < 32 or 0x7F <= ord(c) < 0xA0 for c in caption)
        return
    markdown = format_scores_table(frame, 2, "markdown", layout=EVERY_SCORE)
    parsed = parse_table(tex)
    assert parsed.caption == normalized(caption)
    assert len(parsed.rows) == len(DEFAULT_SCORES) == len(markdown.splitlines()) - 2
    assert parsed.header[-1] == name
    for row, score in zip(parsed.rows, DEFAULT_SCORES, strict=True):
        value = frame.loc[name, score]
        if np.isnan(value):
            assert row[-1] == "n/a"
        elif np.isinf(value):
            assert row[-1] == ("inf" if value > 0 else "-inf")
        else:
            assert row[-1] not in ("", "n/a")


@given(
    values=st.lists(
        st.one_of(st.floats(), st.sampled_from([1e-300, 1e300, np.inf, -np.inf])),
        min_size=len(pe.SCORE_NAMES),
        max_size=len(pe.SCORE_NAMES),
    ),
    # Any text, a bare carriage return too (it split the row in two before text was quoted).
    reason=st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=20),
)
def test_csv_reads_back_the_same_columns_and_values(paper, tmp_path_factory, values, reason):
    records = dict(paper.records)
    records["outer"] = pe.Scores(
        "outer", reason=reason, **dict(zip(pe.SCORE_NAMES, values, strict=True))
    )
    comparison = object.__new__(pe.Comparison)
    comparison.__dict__.update(paper.__dict__)
    comparison.records = records
    path = tmp_path_factory.mktemp("csv") / "scores.csv"
    text = comparison.to_csv(path)
    with open(path, encoding="utf-8", newline="") as handle:  # a "\r" kept as written
        assert handle.read() == text
    back = pd.read_csv(path, index_col="kind", keep_default_na=False, na_values=[""])
    frame = comparison.to_frame()
    assert list(back.columns) == list(frame.columns) and list(back.index) == list(frame.index)
    for name in pe.SCORE_NAMES:  # bit for bit: pandas writes repr() of each float
        np.testing.assert_array_equal(back[name].to_numpy(float), frame[name].to_numpy(float))
    assert (back.loc["outer", "reason"] if reason else "") in (reason, "")


# ---- a real LaTeX engine -------------------------------------------------------------------

# Text pdfLaTeX's UTF-8 support prints: ASCII, Latin-1 letters, and the Greek letters the
# escape writes as math symbols.
PDF_ALPHABET = string.printable.replace("\x0b", "").replace("\x0c", "")
PDF_ALPHABET += "äöüßéèçñÅØ±°µτΩλΣ\N{MULTIPLICATION SIGN}"


def random_strings(alphabet: str, count: int, seed: int) -> list[str]:
    rng = np.random.default_rng(seed)
    return ["".join(rng.choice(list(alphabet), size=rng.integers(1, 30))) for _ in range(count)]


def bmp_alphabet(seed: int, size: int = 400) -> str:
    """Random printable characters of the Basic Multilingual Plane (not controls or surrogates)."""
    rng = np.random.default_rng(seed)
    found = []
    while len(found) < size:
        c = chr(int(rng.integers(0x20, 0xFFFE)))
        if unicodedata.category(c) not in ("Cc", "Cs", "Cn", "Co"):
            found.append(c)
    return "".join(found) + string.punctuation


def tables_for(paper, singular, strings: list[str]) -> list[str]:
    tables = [
        paper.to_latex(caption="Scores", label="tab:paper"),
        singular.to_latex(),
        format_summary_table(summary_of(paper, singular), "latex", caption="x", label="tab:s"),
    ]
    for k, text in enumerate(strings):
        frame = paper.to_frame().rename(index={"outer": text})
        tables.append(format_scores_table(frame, 2, "latex", caption=text, label=f"tab:{k}"))
    return tables


def check_compiled(tables: list[str], text: str) -> None:
    """Every row of every table is in the compiled document (no row became a comment)."""
    if not text:
        return  # no pdftotext: the engine's clean log is the check
    lines = text.splitlines()
    for tex in tables:
        parsed = parse_table(tex)
        for row in parsed.rows:
            numbers = [cell for cell in row[parsed.stub :] if cell.isascii()]
            pattern = ".*".join(map(pdf_pattern, numbers))
            assert any(re.search(pattern, line) for line in lines), row
    for label in ("coverage [%]", "overreach [%]", "Chiacchio"):
        assert label in text, label


@pytest.mark.filterwarnings("ignore:The LaTeX table")  # (long random names: wide, and said)
@pytest.mark.parametrize("program", ["pdflatex", "lualatex"])
def test_tables_compile_with_a_real_engine_and_keep_every_row(paper, singular, tmp_path, program):
    path = engine(program)
    if path is None:
        pytest.skip(f"{program} is not installed (CI installs it: .ci/run); the parser checks ran")
    alphabet = PDF_ALPHABET if program == "pdflatex" else bmp_alphabet(seed=7)
    strings = [HOSTILE, *random_strings(alphabet, 40, seed=11)]
    tables = tables_for(paper, singular, strings)
    for tex, text in zip(tables[3:], strings, strict=True):
        # The micro sign prints as the Greek mu (the same glyph; pdfLaTeX has no other).
        assert parse_table(tex).caption == normalized(text).replace(
            "\N{MICRO SIGN}", "\N{GREEK SMALL LETTER MU}"
        )
    check_compiled(tables, compile_tables(path, tables, tmp_path))


# ---- a study's tables, end to end ------------------------------------------------------

HOSTILE_STUDY = r"""
    title = 'Grid 100% & #1 _x_ \input{y} ~ {z}'
    [robot]
    library = "chiacchio2000"
    [grid]
    q1 = "pi/2"
    q2 = { start = "-pi/2", stop = 0, num = 2 }
    q3 = { start = "-pi/2", stop = "pi/2", num = 2 }
    [compare]
    directions = 16
    mvie = false
    [output]
    formats = ["png"]
    dpi = 20
"""


def test_a_study_with_a_hostile_title_writes_tables_that_keep_every_row(tmp_path):
    from polyell.studies import load_study, run_study

    spec_file = tmp_path / "study.toml"
    spec_file.write_text(HOSTILE_STUDY, encoding="utf-8")
    spec = load_study(spec_file)
    run_study(spec, tmp_path / "out")
    summary = pd.read_csv(tmp_path / "out" / "summary.csv", index_col=[0, 1])
    tex = (tmp_path / "out" / "summary.tex").read_text(encoding="utf-8")
    parsed = parse_table(tex)
    # the captions do not repeat the study's title (the runner's rule since issue 32)
    assert parsed.caption == "Summary of the scores over 4 configurations."
    assert len(parsed.rows) == len(summary)  # no row lost to a comment
    assert ("Chiacchio", "coverage [%]") in [(row[0], row[1]) for row in parsed.rows]
    markdown = (tmp_path / "out" / "summary.md").read_text(encoding="utf-8")
    assert sum(line.startswith("| ") for line in markdown.splitlines()) == len(summary) + 2
    for program in ("pdflatex", "lualatex"):
        path = engine(program)
        if path is not None:  # compiled where an engine is installed (the test above skips)
            check_compiled([tex], compile_tables(path, [tex], tmp_path / program))


def test_the_summary_table_takes_the_layout_sets_scores_and_digits(paper, singular):
    summary = summary_of(paper, singular)
    layout = pe.TableLayout(sets=["yoshikawa"], scores=["coverage", "lower"], digits=2)
    parsed = parse_table(format_summary_table(summary, "latex", layout=layout))
    assert [(row[0], row[1]) for row in parsed.rows] == [("Yoshikawa", "coverage [%]")]
    mean = summary.loc[("yoshikawa", "coverage"), "mean"]
    assert parsed.rows[0][parsed.stub + 1] == f"{100 * mean:.2g}"  # the mean, 2 digits


def test_markdown_text_shows_an_entity_as_itself():
    """``&amp;`` typed in a title shows as ``&amp;`` where the Markdown is rendered: the
    ``&`` that would start an entity is written as one (titles, captions and headings of
    every writer go through ``markdown_text``; ``escape_markdown`` escapes once)."""
    from polyell.comparison.latex_text import markdown_text

    assert markdown_text("R&amp;D <b> & co") == "R&amp;amp;D &lt;b&gt; & co"
    assert escape_markdown("R&amp;D|x") == r"R&amp;amp;D\|x"  # once, not twice


def test_a_points_study_title_with_an_entity_is_written_as_typed(tmp_path):
    from polyell.comparison.point_tables import write_point_tables

    arm = pe.robots.load("chiacchio2000")
    comparison = pe.compare(pe.analyze(arm.dynamics([0.3, 0.6, 0.9]), arm.tau_max), mvie=False)
    paths = write_point_tables({"home": comparison}, None, tmp_path, title="R&amp;D")
    text = next(Path(p) for p in paths if str(p).endswith(".md")).read_text()
    assert "R&amp;amp;D" in text and "R&amp;D:" not in text


@given(
    st.sampled_from(["", "# ", "## ", "> ", "- ", "+ ", "= ", "1. ", "12) ", "---", " - "]),
    st.text(alphabet=st.characters(blacklist_categories=("Cc", "Cs")), max_size=20),
)
def test_a_markdown_caption_is_one_paragraph_as_typed(marker, text):
    """A caption line that starts like a heading, quote, list or rule stays a paragraph
    (markdown-it, CommonMark with GitHub's tables and strike-through; found by the
    independent check of issue 31: "1. item" became a list)."""
    from markdown_it import MarkdownIt

    from polyell.comparison.latex_text import markdown_line

    typed = f"{marker}{text}x"
    if not typed.strip():
        return
    parser = MarkdownIt("commonmark").enable(["strikethrough", "table"])
    tokens = parser.parse(markdown_line(typed))
    assert [token.type for token in tokens] == ["paragraph_open", "inline", "paragraph_close"]
    children = tokens[1].children
    assert {token.type for token in children} <= {"text"}
    assert "".join(token.content for token in children) == normalized(typed).strip()


@pytest.mark.parametrize("caption", ["Limits, 1. of 2", ("- Scores", r"Scores, $h$")])
def test_a_markdown_table_carries_its_caption(paper, caption):
    """caption= of the writers is shown in Markdown (plain text above the table), as in
    LaTeX and HTML (it was dropped)."""
    plain = caption[0] if isinstance(caption, tuple) else caption
    for table in (
        format_comparison_table({"a": paper}, "markdown", caption=caption),
        format_limits_table(paper.limits_table(["x"]), "markdown", caption=caption),
    ):
        first = table.split("\n\n")[0]
        assert re.sub(r"\\(.)", r"\1", first) == plain
