"""Issue 32: the Panda's tables pasted into a one-column paper.

Labels that fit any robot (the paper's equation numbers only as a preset), the user's
labels and captions in every format, a math minus and typeset powers of ten in LaTeX,
siunitx ``S`` columns that compile, a warning that names the width of a table too wide for
the page (checked against pdfLaTeX's own measure), error columns that are zero in every
row left out, and the table of pycapacity's functions in docs/api.md (checked against
pycapacity itself).  Every value is checked against the comparison's own numbers, read
back from the table independently of the writers.
"""

from __future__ import annotations

import csv
import io
import re
import shutil
import subprocess
import warnings
from decimal import Decimal
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from latex_check import engine, fit_warnings
from latex_numbers import parse_all

import polyell as pe
from polyell.comparison.point_tables import write_point_tables
from polyell.comparison.summary import format_summary_table, summarize
from polyell.comparison.tables import format_comparison_table, format_limits_table
from reference import PAPER_Q_REDUNDANT, PAPER_Q_SINGULAR, paper_analysis

REPO = Path(__file__).resolve().parents[2]
POSTURES = {
    "ready": [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785],
    "reach": [0.3, 0.2, 0.0, -1.5, 0.0, 1.8, 0.7],
    "side": [0.8, -0.3, 0.4, -1.9, 0.2, 1.4, -0.5],
}
#: A reader's own names, with LaTeX for two of them.
LABELS = {
    "chiacchio": "DME (Chiacchio)",
    "yoshikawa": "DME (Yoshikawa)",
    "mvie": "best inscribed",
    "coverage": "share covered",
    "witness_torque_max": ("max. norm. torque", r"$\max_i |\tilde\tau_i|$"),
    "lower_error": ("rel. error, lower", r"$\epsilon_{\mathrm{lo}}$"),
}
#: Words that belong to Chiacchio's paper only.
PAPER_WORDS = re.compile(r"eq\. ?\d|\(15\)|\(27\)|32/38|classic|\bnew\b|tilde")


@pytest.fixture(scope="module")
def panda() -> dict[str, pe.Comparison]:
    robot = pe.robots.load("panda")
    return {
        name: pe.compare(pe.analyze(robot.dynamics(q), robot.tau_max), 64, samples=256)
        for name, q in POSTURES.items()
    }


@pytest.fixture(scope="module")
def paper() -> dict[str, pe.Comparison]:
    return {
        "redundant": pe.compare(paper_analysis(PAPER_Q_REDUNDANT), 32, samples=256),
        "singular": pe.compare(paper_analysis(PAPER_Q_SINGULAR), 32, samples=256),
    }


def quiet(call, *args, **kwargs):
    """The call's result, and the warnings it gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call(*args, **kwargs)
    return result, [str(w.message) for w in caught]


def body_cells(tex: str) -> list[str]:
    """The number cells of every body row of LaTeX tables (after the stub columns)."""
    cells = []
    for block in re.findall(r"\\midrule\n(.*?)\\bottomrule", tex, flags=re.S):
        for line in block.splitlines():
            if not line.endswith(r" \\") or line.startswith(r"\multicolumn"):
                continue
            parts = re.split(r"(?<!\\)&", line[: -len(r" \\")])
            cells += [part.strip() for part in parts[1:]]
    return cells


# ---- labels -----------------------------------------------------------------------------


@pytest.mark.filterwarnings("ignore:The LaTeX table")  # (transposed: too wide, and said)
def test_the_default_labels_fit_any_robot(panda):
    """No table, figure legend or report of the Panda speaks of the paper's equations."""
    limits = pe.limits_table(panda, ["x", "y", "z", "xz"])
    for style in ("latex", "markdown", "csv", "html"):
        for table in (
            format_comparison_table(panda, style),
            format_limits_table(limits, style),
            format_limits_table(limits, style, layout=pe.TableLayout(transpose=True)),
        ):
            assert not PAPER_WORDS.search(table), (style, PAPER_WORDS.search(table))
            assert "Chiacchio" in table and "Yoshikawa" in table and "MVIE" in table
    frame = next(iter(panda.values())).to_frame()
    assert "torque witness" in format_comparison_table(panda, "markdown")
    assert "witness_torque_max" in frame.columns  # the data column keeps its name


def test_one_name_per_kind_in_every_capacity():
    from polyell.comparison.labels import set_label

    arm = pe.robots.load("chiacchio2000")
    dyn = arm.dynamics([1.5707963, -1.5707963, -1.5707963])
    analyses = {
        "acceleration": pe.analyze(dyn, arm.tau_max),
        "force": pe.analyze(dyn, arm.tau_max, capacity="force"),
        "velocity": pe.analyze(pe.Kinematics(dyn.J), capacity="velocity", qd_max=np.ones(3)),
    }
    for capacity, analysis in analyses.items():
        table = pe.compare(analysis, 16, mvie=False, outer=False).to_markdown()
        header = table.splitlines()[0]
        for kind in analysis.ellipsoid_kinds:
            assert set_label(kind, capacity) == set_label(kind)  # one name per kind
            assert set_label(kind) in header
        witness = "joint velocity witness" if capacity == "velocity" else "torque witness"
        assert f"| {witness}" in table, capacity
    assert set_label("yoshikawa") == "Yoshikawa" and set_label("static") == "static (no gravity)"


def test_the_papers_own_study_keeps_its_equation_numbers(paper):
    layout = pe.TableLayout(labels="chiacchio2000")
    markdown = format_comparison_table(paper, "markdown", layout=layout)
    assert "new (eq. 32/38)" in markdown and "classic (eq. 27)" in markdown
    assert r"witness max abs(tau\_n)" in markdown
    tex = format_comparison_table(paper, "latex", layout=layout)
    assert r"witness $\max \|\tilde\tau\|_\infty$" in tex  # the paper's notation, as LaTeX
    limits = format_limits_table(pe.limits_table(paper), "markdown", layout=layout)
    assert "| polytope (eq. 15) " in limits
    # figures take the same labels; the report its equation numbers
    from polyell.figures import plot_sets
    from polyell.report import format_analysis

    analysis = paper["redundant"].analysis
    legends = {t.get_text() for t in plot_sets(analysis).axes[0].get_legend().get_texts()}
    assert {"polytope", "Chiacchio", "Yoshikawa"} <= legends
    figure = plot_sets(analysis, labels="chiacchio2000")
    legends = {t.get_text() for t in figure.axes[0].get_legend().get_texts()}
    assert {"polytope (eq. 15)", "new (eq. 32/38)", "classic (eq. 27)"} <= legends
    direction = np.array([1.0, 0.0])
    assert "Polytope (eq. 15)" in format_analysis(analysis, direction, "x", equations=True)
    plain = format_analysis(analysis, direction, "x", equations=False)
    assert "eq." not in plain and "Exact set" in plain
    with pytest.raises(pe.InputError, match="equations"):
        format_analysis(analysis, direction, "x", equations="yes")  # type: ignore[arg-type]


def test_custom_labels_in_every_format(panda):
    layout = pe.TableLayout(labels=LABELS)
    comparison = {
        style: format_comparison_table(panda, style, layout=layout)
        for style in ("latex", "markdown", "csv", "html")
    }
    limits_frame = pe.limits_table(panda, ["x", "z"])
    limits = {
        style: format_limits_table(limits_frame, style, layout=layout)
        for style in ("latex", "markdown", "csv", "html")
    }
    # CSV: the plain labels in the header and the stub, the exact values beside them
    records = list(csv.reader(io.StringIO(comparison["csv"])))
    assert records[0][2:] == [
        "DME (Chiacchio)",
        "DME (Yoshikawa)",
        "best inscribed",
        "outer (min. volume)",
    ]
    kinds = ["chiacchio", "yoshikawa", "mvie", "outer"]
    rows = {(r[0], r[1]): r[2:] for r in records[1:]}
    for posture, comparison_ in panda.items():
        shares = rows[(posture, "share covered [%]")]
        witness = rows[(posture, "max. norm. torque")]
        for kind, share, torque in zip(kinds, shares, witness, strict=True):
            assert float(Decimal(share).scaleb(-2)) == comparison_[kind].coverage
            assert float(torque) == comparison_[kind].witness_torque_max
    records = list(csv.reader(io.StringIO(limits["csv"])))
    assert "rel. error, lower [%]" in records[0]
    assert {r[2] for r in records[1:]} == {
        "polytope",
        "DME (Chiacchio)",
        "DME (Yoshikawa)",
        "best inscribed",
        "outer (min. volume)",
    }
    # Markdown and HTML: the plain labels
    for style in ("markdown", "html"):
        assert "share covered [%]" in comparison[style] and "max. norm. torque" in comparison[style]
        assert "DME (Yoshikawa)" in limits[style] and "rel. error, lower [%]" in limits[style]
        assert "coverage" not in comparison[style].replace("share covered", "")
    # LaTeX: the escaped plain labels and the user's markup as given
    tex = comparison["latex"]
    assert r"$\max_i |\tilde\tau_i|$" in tex and "share covered [\\%]" in tex
    assert r"\begin{tabular}[b]{@{}r@{}}DME\\{}(Chiacchio)\end{tabular}" in tex
    assert (
        r"\begin{tabular}[b]{@{}r@{}}$\epsilon_{\mathrm{lo}}$\\{}[\%]\end{tabular}"
        in (limits["latex"])
    )
    assert "& DME (Chiacchio) &" in limits["latex"]  # a row's set, escaped plain text


def test_the_summary_and_the_figures_take_the_same_labels(panda):
    from polyell.figures import plot_score_histogram, plot_sets_3d

    rows = pd.DataFrame([c.to_row() for c in panda.values()])
    layout = pe.TableLayout(labels=LABELS, captions={"summary": "Over three postures."})
    markdown = format_summary_table(summarize(rows), "markdown", layout=layout)
    assert "DME (Chiacchio)" in markdown and "share covered [%]" in markdown
    assert "max. norm. torque" in markdown and "Chiacchio |" not in markdown
    tex = format_summary_table(summarize(rows), "latex", layout=layout)
    assert r"\caption{Over three postures.}" in tex and r"$\max_i |\tilde\tau_i|$" in tex
    explicit = format_summary_table(summarize(rows), "latex", layout=layout, caption="Mine.")
    assert r"\caption{Mine.}" in explicit  # an explicit caption wins
    figure = plot_sets_3d(panda["ready"].analysis, labels=LABELS)
    legend = {t.get_text() for t in figure.legends[0].get_texts()}
    assert {"polytope", "DME (Chiacchio)", "DME (Yoshikawa)"} <= legend
    histogram = plot_score_histogram(rows, "coverage", labels=LABELS)
    assert histogram.axes[0].get_xlabel() == "share covered [%]"
    with pytest.raises(pe.InputError, match=r"labels\['chiacchio'\]"):
        plot_score_histogram(rows, "coverage", labels={"chiacchio": "a $x^$ b"})


def test_custom_labels_compile(panda, tmp_path):
    program = engine("pdflatex")
    if program is None:
        pytest.skip("pdflatex is not installed (CI installs it: .ci/run)")
    layout = pe.TableLayout(labels=LABELS)
    tables = [
        format_comparison_table(panda, "latex", layout=layout),
        format_limits_table(pe.limits_table(panda), "latex", layout=layout),
    ]
    assert fit_warnings(program, tables, tmp_path) == []


# ---- numbers ----------------------------------------------------------------------------

NUMBER = r"(?:\$-\$)?[0-9]+(?:\.[0-9]+)?(?:\$\\times 10\^\{-?[0-9]+\}\$)?"


def latex_value(cell: str) -> float:
    """The value of a typeset number cell, read independently of the writer."""
    match = re.fullmatch(r"(\$-\$)?([0-9.]+)(?:\$\\times 10\^\{(-?[0-9]+)\}\$)?", cell)
    assert match is not None, cell
    sign, mantissa, power = match.groups()
    value = float(mantissa) * 10.0 ** int(power or 0)
    return -value if sign else value


def test_latex_numbers_have_a_math_minus_and_powers_of_ten(panda):
    tex = format_comparison_table(panda, "latex")
    cells = body_cells(tex)
    assert cells and all(re.fullmatch(NUMBER, c) or c.startswith("{") for c in cells), cells
    assert "$-$" in tex
    assert not re.search(r"e[+-][0-9]", tex) and "e+05" not in tex
    assert not re.search(r"(?<![$\w])-[0-9]", tex)  # no hyphen before a digit
    # the volume of each set, read from its typeset cell, is the comparison's
    lines = [line for line in tex.splitlines() if line.startswith("volume [")]
    kinds = ["chiacchio", "yoshikawa", "mvie", "outer"]
    for line, comparison in zip(lines, panda.values(), strict=True):
        values = [latex_value(cell.strip()) for cell in line[: -len(r" \\")].split("&")[1:]]
        for kind, value in zip(kinds, values, strict=True):
            assert value == pytest.approx(comparison[kind].volume, rel=5e-3)
    bias = next(line for line in tex.splitlines() if line.startswith(r"dir.\ bias"))
    first = latex_value(bias.split("&")[1].strip())
    assert first == pytest.approx(100 * panda["ready"]["chiacchio"].direction_bias, rel=5e-3)
    assert first < 0


def test_markdown_and_csv_keep_plain_numbers(panda):
    markdown = format_comparison_table(panda, "markdown")
    assert "$" not in markdown and re.search(r"\| +-[0-9]", markdown)
    assert re.search(r"[0-9]e\+0[0-9]", markdown)  # (Markdown shows what a program reads)
    records = list(csv.reader(io.StringIO(format_comparison_table(panda, "csv"))))
    volume = next(r for r in records if r[0] == "ready" and r[1].startswith("volume"))
    assert float(volume[2]) == panda["ready"]["chiacchio"].volume  # every digit


def s_columns(tex: str) -> list[tuple[str, list[str], list[list[str]]]]:
    """Each float's column specification, header cells and body rows (structure only)."""
    found = []
    for block in re.findall(
        r"\\begin\{tabular\}\{(.*?)\}\n\\toprule\n(.*?)\\bottomrule", tex, re.S
    ):
        spec, rest = block
        lines = [line for line in rest.splitlines() if line.endswith(r" \\")]
        lines = [line for line in lines if r"\multicolumn" not in line]
        split = [re.split(r"(?<!\\)&", line[: -len(r" \\")]) for line in lines]
        found.append(
            (spec, [c.strip() for c in split[0]], [[c.strip() for c in r] for r in split[1:]])
        )
    return found


def balanced(text: str) -> bool:
    """Braces balanced, escaped characters (``\\{``, ``\\\\``) aside."""
    depth, k = 0, 0
    while k < len(text):
        if text[k] == "\\":
            k += 2
            continue
        depth += {"{": 1, "}": -1}.get(text[k], 0)
        if depth < 0:
            return False
        k += 1
    return depth == 0


def check_s_structure(tex: str) -> int:
    """Every S column's header braced, every cell a bare number or braced text; formats fit.

    A column of one quantity has a ``table-format`` that holds each of its numbers; a
    column of unlike quantities (a row per score) is formatted without alignment.
    """
    checked = 0
    for spec, header, rows in s_columns(tex):
        columns = re.findall(r"S\[[^\]]*\]|[lr]", spec)
        stub = sum(1 for column in columns if column == "l")
        numbers = columns[stub:]
        assert stub + len(numbers) == len(header) and all(c.startswith("S[") for c in numbers)
        for j, column in enumerate(numbers):
            head = header[stub + j]
            assert head.startswith("{") and head.endswith("}") and balanced(head[1:-1]), head
            fmt = re.fullmatch(r"S\[table-format=(-?)([0-9]+)\.([0-9]+)(e-?[0-9]+)?\]", column)
            if fmt is None:
                assert column == "S[table-alignment-mode=none,table-number-alignment=right]"
            for row in rows:
                cell = row[stub + j]
                number = re.fullmatch(r"(-?)([0-9]+)(?:\.([0-9]+))?(?:e(-?[0-9]+))?", cell)
                if number is None:
                    assert cell.startswith("{") and cell.endswith("}"), cell
                    assert balanced(cell[1:-1]), cell
                    continue
                checked += 1
                if fmt is None:
                    continue
                sign, integer, decimals, exponent = fmt.groups()
                minus, whole, fraction, power = number.groups()
                assert not minus or sign, (cell, column)
                assert len(whole) <= int(integer) and len(fraction or "") <= int(decimals)
                assert (power is None) or exponent, (cell, column)
    return checked


def test_siunitx_columns_are_braced_and_compile(panda, paper, tmp_path):
    layout = pe.TableLayout(siunitx=True)
    limits = pe.limits_table(panda, ["x", "y", "z"])
    tables = [
        format_comparison_table(panda, "latex", layout=layout),
        format_comparison_table(paper, "latex", layout=layout),  # n/a cells (singular)
        format_limits_table(limits, "latex", layout=layout),
        format_limits_table(pe.limits_table(paper), "latex", layout=layout),
        format_summary_table(
            summarize(pd.DataFrame([c.to_row() for c in panda.values()])),
            "latex",
            layout=layout,
        ),
    ]
    assert sum(check_s_structure(tex) for tex in tables) > 100
    assert "$-$" not in "".join(tables) and r"\times" not in "".join(tables)
    assert re.search(r" -[0-9]", tables[0]) and re.search(r"[0-9]e[0-9]", tables[0])
    program = engine("pdflatex")
    if program is None or not kpse("siunitx.sty"):
        pytest.skip("pdflatex with siunitx is not installed; the structure was checked")
    text = compile_with(program, tables, ["booktabs", "siunitx"], tmp_path)
    assert not text or "\N{MINUS SIGN}" in text  # siunitx's minus, not a hyphen


def kpse(name: str) -> bool:
    kpsewhich = shutil.which("kpsewhich")
    if kpsewhich is None:
        return False
    found = subprocess.run([kpsewhich, name], capture_output=True, text=True, check=False)
    return bool(found.stdout.strip())


def compile_with(program: str, tables: list[str], packages: list[str], folder: Path) -> str:
    """Compile tables in one article with ``packages``: the PDF's text ('' without pdftotext).

    AssertionError with the log's errors if the engine reports any, or an overfull box.
    """
    folder.mkdir(parents=True, exist_ok=True)
    uses = "".join(f"\\usepackage{{{p}}}\n" for p in packages)
    body = "\n\\clearpage\n".join(tables)
    (folder / "doc.tex").write_text(
        f"\\documentclass{{article}}\n{uses}\\begin{{document}}\n{body}\n\\end{{document}}\n",
        encoding="utf-8",
    )
    run = subprocess.run(
        [program, "-interaction=nonstopmode", "-halt-on-error", "doc.tex"],
        cwd=folder,
        capture_output=True,
        check=False,
    )
    log = (folder / "doc.log").read_text(encoding="utf-8", errors="replace")
    errors = [line for line in log.splitlines() if line.startswith("!")]
    assert run.returncode == 0 and not errors, (errors[:3], log[-1500:])
    overfull = [line for line in log.splitlines() if line.startswith("Overfull")]
    assert not overfull, overfull
    pdftotext = shutil.which("pdftotext")
    if pdftotext is None:
        return ""
    out = subprocess.run([pdftotext, "doc.pdf", "-"], cwd=folder, capture_output=True, check=True)
    return out.stdout.decode("utf-8", errors="replace")


def test_default_r_columns_compile_without_siunitx(panda, tmp_path):
    program = engine("pdflatex")
    if program is None:
        pytest.skip("pdflatex is not installed (CI installs it: .ci/run)")
    tables = [
        format_comparison_table(panda, "latex"),
        format_limits_table(pe.limits_table(panda), "latex"),
    ]
    text = compile_with(program, tables, ["booktabs"], tmp_path)
    if text:  # a minus sign, a power of ten: no hyphen before a digit, no "e+05"
        assert "\N{MINUS SIGN}" in text and "\N{MULTIPLICATION SIGN}10" in text
        assert not re.search(r"(?<![\w])-[0-9]", text) and "e+0" not in text


# ---- captions ---------------------------------------------------------------------------


def test_captions_do_not_start_with_the_title_and_are_the_users_when_set(panda, tmp_path):
    quiet(write_point_tables, panda, None, tmp_path, title="Panda, three postures")
    limits = (tmp_path / "limits.tex").read_text()
    caption = re.search(r"\\caption\{(.*)\}", limits).group(1)
    assert caption.startswith("Directional limits") and "Panda" not in caption
    assert r"$(e - p)/|p|$" in caption and "(e - p)/\\textbar" not in caption
    assert "$e$" in caption and "$p$" in caption  # the notation is defined
    assert (tmp_path / "limits.md").read_text().startswith("# Panda, three postures: directional")
    comparison = (tmp_path / "comparison.tex").read_text()
    assert r"\caption{Scores of each ellipsoid against the exact polytope.}" in comparison
    own = pe.TableLayout(
        captions={
            "limits": ("Limits of the arm, $e$ against $p$.", r"Limits, $e$ against $p$."),
            "comparison": "Scores at 3 postures & 50% more.",
        }
    )
    folder = tmp_path / "own"
    folder.mkdir()
    quiet(write_point_tables, panda, None, folder, own, "Panda")
    assert r"\caption{Limits, $e$ against $p$.}" in (folder / "limits.tex").read_text()
    comparison = (folder / "comparison.tex").read_text()
    assert r"\caption{Scores at 3 postures \& 50\% more.}" in comparison
    assert r"Limits of the arm, \$e\$ against \$p\$." in (folder / "limits.md").read_text()
    # the writers take a layout's caption where none is given
    html = format_comparison_table(panda, "html", layout=own)
    assert "<caption>Scores at 3 postures &amp; 50% more.</caption>" in html


# ---- width ------------------------------------------------------------------------------


def overflow_of(program: str, table: str, folder: Path) -> float:
    """pdfLaTeX's own measure: how far the table overflows the text width [pt]."""
    found = fit_warnings(program, [table], folder)
    widths = [float(m) for line in found for m in re.findall(r"\(([0-9.]+)pt too wide\)", line)]
    return max(widths, default=0.0)


def test_a_transposed_panda_table_warns_with_its_width(panda, tmp_path):
    limits = pe.limits_table(panda)
    wide = pe.TableLayout(transpose=True)
    table, messages = quiet(format_limits_table, limits, "latex", layout=wide, label="tab:l")
    assert len(messages) == 1  # one table, one warning
    found = [
        re.search(r"'tab:l' is about (\d+) pt wide, (\d+) pt wider than the text width 345 pt", m)
        for m in messages
    ]
    assert all(found), messages
    comparison, messages_c = quiet(format_comparison_table, panda, "latex", layout=wide)
    assert len(messages_c) == 1 and "wider than the text width 345 pt" in messages_c[0]
    program = engine("pdflatex")
    if program is None:
        return
    for tex, match in zip(parse_floats(table), found, strict=True):
        real = overflow_of(program, tex, tmp_path / f"l{match.group(1)}")
        assert int(match.group(2)) == pytest.approx(real, rel=0.05, abs=6), (match.group(0), real)
    real = overflow_of(program, comparison, tmp_path / "c")
    stated = int(re.search(r"(\d+) pt wider", messages_c[0]).group(1))
    assert stated == pytest.approx(real, rel=0.05, abs=6)


def parse_floats(tex: str) -> list[str]:
    return re.findall(r"\\begin\{table\}.*?\\end\{table\}\n", tex, flags=re.S)


def test_the_default_tables_do_not_warn_and_a_narrow_page_does(panda, paper):
    limits = pe.limits_table(panda, ["x", "y", "z", "xz"])
    for comparisons, frame in ((panda, limits), (paper, pe.limits_table(paper))):
        for split in ("combined", "posture"):
            layout = pe.TableLayout(split=split)
            _, messages = quiet(format_comparison_table, comparisons, "latex", layout=layout)
            _, more = quiet(format_limits_table, frame, "latex", layout=layout)
            assert messages + more == []
    narrow = pe.TableLayout(text_width=200)
    _, messages = quiet(format_comparison_table, panda, "latex", layout=narrow, label="tab:c")
    assert len(messages) == 1 and "than the text width 200 pt" in messages[0]
    unchecked = pe.TableLayout(transpose=True, text_width=None)
    assert quiet(format_limits_table, limits, "latex", layout=unchecked)[1] == []
    # Markdown, CSV and HTML have no page
    assert (
        quiet(format_limits_table, limits, "markdown", layout=pe.TableLayout(transpose=True))[1]
        == []
    )


def test_the_warning_points_at_the_callers_line(panda):
    with pytest.warns(UserWarning, match="wider than the text width") as record:
        format_comparison_table(panda, "latex", layout=pe.TableLayout(transpose=True))
    assert record[0].filename == __file__


def test_the_estimate_is_within_a_few_percent_of_pdflatex(panda, paper, tmp_path):
    """Widths of tables that fit, measured by pdfLaTeX in a box, against the estimate."""
    from polyell.comparison.write_latex import table_width

    program = engine("pdflatex")
    if program is None or not kpse("siunitx.sty"):
        pytest.skip("pdflatex with siunitx is not installed")
    floats = []
    for siunitx in (False, True):
        for layout in (
            pe.TableLayout(siunitx=siunitx),
            pe.TableLayout(siunitx=siunitx, transpose=True, text_width=None),
            pe.TableLayout(siunitx=siunitx, digits=6, percent=False, text_width=None),
        ):
            floats += parse_floats(format_comparison_table(panda, "latex", layout=layout))
            floats += parse_floats(format_comparison_table(paper, "latex", layout=layout))
            frame = pe.limits_table(panda, ["x", "xz"])
            floats += parse_floats(format_limits_table(frame, "latex", layout=layout))
    boxed = []
    for k, tex in enumerate(floats):
        tex = re.sub(r"\\(caption|label)\{.*\}\n", "", tex)
        tex = tex.replace(r"\begin{table}", r"\begingroup").replace(r"\centering", "")
        tex = tex.replace(r"\begin{tabular}{", r"\setbox0=\hbox{\begin{tabular}{", 1)
        tex = tex.replace(
            "\\end{tabular}\n\\end{table}",
            f"\\end{{tabular}}}}\\typeout{{W{k} \\the\\wd0}}\\endgroup",
        )
        boxed.append(tex)
    folder = tmp_path / "widths"
    folder.mkdir()
    (folder / "w.tex").write_text(
        "\\documentclass{article}\n\\usepackage{booktabs}\n\\usepackage{siunitx}\n"
        "\\begin{document}\n" + "\n".join(boxed) + "\n\\end{document}\n"
    )
    subprocess.run([program, "-interaction=nonstopmode", "w.tex"], cwd=folder, capture_output=True)
    log = (folder / "w.log").read_text(errors="replace")
    real = {int(k): float(w) for k, w in re.findall(r"W(\d+) ([0-9.]+)pt", log)}
    assert len(real) == len(floats)
    for k, tex in enumerate(floats):
        estimate = table_width(tex.splitlines())
        assert estimate == pytest.approx(real[k], rel=0.03), (k, estimate, real[k])


# ---- columns that are always zero --------------------------------------------------------


class _Headers(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.headers: list[str] = []
        self._th = False

    def handle_starttag(self, tag, attrs):
        self._th = tag == "th" and ("scope", "col") in attrs

    def handle_data(self, data):
        if self._th:
            self.headers.append(data)
            self._th = False


def test_columns_that_are_zero_in_every_row_are_left_out(panda):
    limits = pe.limits_table(panda, ["x", "z"])
    # the polytope's own errors are 0 (it is the reference): the frame says so
    own = limits[limits["set"] == "polytope"][["lower_error", "upper_error"]]
    assert (own.to_numpy() == 0).all()
    transposed = pe.TableLayout(transpose=True, text_width=None)
    records = list(csv.reader(io.StringIO(format_limits_table(limits, "csv", layout=transposed))))
    header = records[0]
    assert [h for h in header if h.startswith("polytope:")] == [
        "polytope: lower [m/s^2]",
        "polytope: upper [m/s^2]",
    ]
    assert len([h for h in header if h.startswith("Chiacchio:")]) == 4
    assert len(header) == 2 + 2 + 4 * 4  # posture, direction, then the sets' columns
    tex = format_limits_table(limits, "latex", layout=transposed)
    assert r"\multicolumn{2}{c}{polytope}" in tex and r"\cmidrule(lr){2-3}" in tex
    parsed = parse_all(tex)
    assert all(len(row) == len(parsed[0].header) + 1 for row in parsed[0].rows)  # + posture
    cells = _Headers()
    cells.feed(format_limits_table(limits, "html", layout=transposed))
    assert len(cells.headers) == 2 + 2 + 4 * 4
    # the polytope alone, in the default orientation: no error columns
    alone = format_limits_table(limits, "markdown", layout=pe.TableLayout(sets=["polytope"]))
    assert "error" not in alone and "lower [m/s^2]" in alone
    # chosen scores are shown even when zero
    chosen = pe.TableLayout(sets=["polytope"], scores=["lower", "lower_error"])
    assert "lower error [%]" in format_limits_table(limits, "markdown", layout=chosen)
    # the comparison, transposed: no mismatch anywhere, so no mismatch column
    assert all(c[k].feasibility_mismatch == 0 for c in panda.values() for k in c.kinds)
    scores = format_comparison_table(panda, "markdown", layout=transposed)
    assert "feasibility" not in scores and "coverage [%]" in scores
    kept = pe.TableLayout(transpose=True, scores=["coverage", "feasibility_mismatch"])
    assert "feasibility mismatches" in format_comparison_table(panda, "markdown", layout=kept)
    # scores as rows (the default): left out too, as in the summary (both orientations)
    assert "feasibility mismatches" not in format_comparison_table(panda, "markdown")
    kept = pe.TableLayout(scores=["coverage", "feasibility_mismatch"])
    assert "| feasibility mismatches" in format_comparison_table(panda, "markdown", layout=kept)


# ---- the pycapacity table in docs/api.md --------------------------------------------------

PYCAPACITY = {
    "acceleration_ellipsoid": '"chiacchio"',
    "force_ellipsoid": '"static"',
    "velocity_ellipsoid": '"yoshikawa"',
    "acceleration_polytope": ".polytope",
    "velocity_polytope": ".polytope",
    "force_polytope": ".polytope",
    "force_polytope_sum": "polyell.geometry.combine.minkowski_sum",
    "force_polytope_intersection": "polyell.geometry.combine.intersection",
}


def test_docs_map_pycapacity_to_polyell():
    text = (REPO / "docs" / "api.md").read_text()
    section = text[text.index("### From pycapacity") :]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    for function, target in PYCAPACITY.items():
        row = next(r for r in rows if r.startswith(f"| `{function}("))
        assert target in row, (function, row)
    import polyell.geometry.combine as combine

    assert {"minkowski_sum", "intersection"} <= set(combine.__all__)  # the names are real
    assert "no gravity" in next(r for r in rows if "acceleration_ellipsoid" in r).lower()


def test_the_pycapacity_mapping_holds_on_the_panda():
    """Each row of the table, numerically: pycapacity's sets are polyell's (symmetric limits)."""
    robot_module = pytest.importorskip("pycapacity.robot")
    from scipy.spatial import ConvexHull

    from polyell.geometry.combine import intersection, minkowski_sum

    arm = pe.robots.load("panda")
    dyn = arm.dynamics(POSTURES["ready"])
    other = arm.dynamics(POSTURES["reach"])
    tau, qd = np.asarray(arm.tau_max, float), np.asarray(arm.qd_max, float)
    acceleration = pe.analyze(dyn, tau)
    force = pe.analyze(dyn, tau, capacity="force")
    velocity = pe.analyze(pe.Kinematics(dyn.J), capacity="velocity", qd_max=qd)

    def same_ellipsoid(theirs, ours: pe.Ellipsoid) -> None:
        order = np.argsort(theirs.radii)[::-1]
        np.testing.assert_allclose(theirs.radii[order], np.sort(ours.semi_axes)[::-1], rtol=1e-9)
        mine = ours.axes[:, np.argsort(ours.semi_axes)[::-1]]
        np.testing.assert_allclose(np.abs(theirs.rotation[:, order].T @ mine), np.eye(3), atol=1e-7)

    same_ellipsoid(
        robot_module.acceleration_ellipsoid(dyn.J, dyn.B, tau), acceleration.ellipsoid("chiacchio")
    )
    assert np.linalg.norm(acceleration.ellipsoid("chiacchio").center) > 1.0  # gravity: not 0
    same_ellipsoid(robot_module.force_ellipsoid(dyn.J, tau), force.ellipsoid("static"))
    same_ellipsoid(robot_module.velocity_ellipsoid(dyn.J, qd), velocity.ellipsoid("yoshikawa"))

    def volume(theirs) -> float:
        return ConvexHull(np.asarray(theirs.vertices).T).volume

    cases = [
        (
            robot_module.acceleration_polytope(dyn.J, dyn.B, tau, -tau, t_bias=dyn.g),
            acceleration.polytope,
        ),
        (robot_module.velocity_polytope(dyn.J, qd, -qd), velocity.polytope),
        (robot_module.force_polytope(dyn.J, tau, -tau, t_bias=dyn.g), force.polytope),
    ]
    second = pe.analyze(other, tau, capacity="force").polytope
    cases += [
        (
            robot_module.force_polytope_sum(dyn.J, other.J, tau, -tau, tau, -tau, dyn.g, other.g),
            minkowski_sum(force.polytope, second),
        ),
        (
            robot_module.force_polytope_intersection(
                dyn.J, other.J, tau, -tau, tau, -tau, dyn.g, other.g
            ),
            intersection(force.polytope, second),
        ),
    ]
    for theirs, ours in cases:
        assert volume(theirs) == pytest.approx(ours.volume, rel=1e-8)
        # every vertex of theirs is in ours (to their rounding of 1e-7 torques)
        vertices = np.asarray(theirs.vertices).T
        assert np.all(ours.A @ vertices.T <= ours.b[:, None] + 1e-6 * (1 + np.abs(ours.b[:, None])))
