"""Check written LaTeX tables: with a real engine where one is installed, else by parsing.

The parser knows only what an escaped table may hold: the commands that print a special
character, the fixed markup of the score labels, and the table's own structure.  Anything
else (a bare ``%``, ``#``, ``&`` in a cell, an unknown command such as ``\\input``) fails.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import unicodedata
from dataclasses import dataclass
from pathlib import Path

# How each escaped special character is written (independent of the code under test).
_TEXT_COMMANDS = {
    r"\textbackslash{}": "\\",
    r"\textasciitilde{}": "~",
    r"\textasciicircum{}": "^",
    r"\textless{}": "<",
    r"\textgreater{}": ">",
    r"\textbar{}": "|",
    r"\textdegree{}": "\N{DEGREE SIGN}",
    r"\{": "{",
    r"\}": "}",
    r"\$": "$",
    r"\&": "&",
    r"\%": "%",
    r"\#": "#",
    "\\ ": " ",  # a control space (after an abbreviation's full stop: "vol.\ / MVIE vol.")
    r"\_": "_",
    "$-$": "-",  # a sign typeset as a minus (a direction's name: "$-$z")
    r"$\pm$": "\N{PLUS-MINUS SIGN}",
    r"$\times$": "\N{MULTIPLICATION SIGN}",
    r"$\mu$": "\N{GREEK SMALL LETTER MU}",  # the micro sign is written as mu too
}
_GREEK = re.compile(r"\$\\([A-Za-z]+)\$")
_TOKEN = re.compile(
    "|".join(re.escape(token) for token in sorted(_TEXT_COMMANDS, key=len, reverse=True))
    + r"|\$\\[A-Za-z]+\$"
)
#: The characters LaTeX gives a meaning: none may remain once the escapes are removed.
SPECIAL = set("\\{}$&%#_~^")


def _greek(command: str) -> str:
    name = {"lambda": "lamda"}.get(command.lower(), command.lower())
    case = "CAPITAL" if command[0].isupper() else "SMALL"
    return unicodedata.lookup(f"GREEK {case} LETTER {name}")


def unescape(text: str) -> str:
    """The plain text an escaped LaTeX fragment prints; AssertionError on a raw special."""
    rest = _TOKEN.sub("", text)
    raw = SPECIAL & set(rest)
    assert not raw, f"unescaped {sorted(raw)} in {text!r}"

    def replace(match: re.Match[str]) -> str:
        token = match.group()
        if token in _TEXT_COMMANDS:
            return _TEXT_COMMANDS[token]
        greek = _GREEK.fullmatch(token)
        assert greek is not None
        return _greek(greek.group(1))

    return _TOKEN.sub(replace, text)


#: The fixed LaTeX markup of labels (trusted; not user text), without their units.
MARKUP_LABELS = {
    "dimension $r$": "dimension r",
    r"witness $\max \|\tilde\tau\|_\infty$": "witness max abs(tau_n)",
    r"dir.\ error, mean": "direction error, mean",
    r"dir.\ error, max": "direction error, max",
    r"dir.\ error, RMS": "direction error, RMS",
    r"dir.\ bias": "direction bias",
}
_MARKUP = re.compile("|".join(re.escape(k) for k in sorted(MARKUP_LABELS, key=len, reverse=True)))
_SUPERSCRIPT = re.compile(r"\$\^\{([-\w]+)\}\$")  # a unit's power: m/s$^{2}$
_STACK = re.compile(r"\\begin\{tabular\}\[b\]\{@\{\}[lcr]@\{\}\}(.*)\\end\{tabular\}")
_GROUP = re.compile(r"\\multicolumn\{(\d+)\}\{c\}\{(.*)\}")
_POSTURE = re.compile(r"\\multicolumn\{(\d+)\}\{@\{\}l\}\{\\itshape (.*)\} \\\\")
_SIZES = {r"\small", r"\footnotesize", r"\setlength{\tabcolsep}{4pt}"}


def label_text(tex: str) -> str:
    """The plain text of a label: stacked lines joined, markup and unit powers undone."""
    stack = _STACK.fullmatch(tex)
    if stack is not None:
        return " ".join(label_text(line) for line in stack.group(1).split(r"\\{}"))
    tex = _SUPERSCRIPT.sub(r"^\1", tex)
    parts = _MARKUP.split(tex)
    found = _MARKUP.findall(tex)
    out = unescape_units(parts[0])
    for markup, rest in zip(found, parts[1:], strict=True):
        out += MARKUP_LABELS[markup] + unescape_units(rest)
    return out


def unescape_units(text: str) -> str:
    """:func:`unescape` where the unit powers were already written back as ``^2``."""
    pieces = re.split(r"(\^[-\w]+)", text)
    return "".join(p if p.startswith("^") else unescape(p) for p in pieces)


def cell_text(tex: str) -> str:
    """The plain text of a cell: braces of text cells removed, infinities as inf."""
    if tex.startswith("{") and tex.endswith("}"):
        tex = tex[1:-1]
    if tex in (r"$\infty$", r"$-\infty$"):
        return "inf" if tex == r"$\infty$" else "-inf"
    return unescape(tex)


@dataclass
class ParsedTable:
    caption: str | None
    label: str | None
    header: list[str]
    rows: list[list[str]]
    stub: int = 1
    size: str = ""


def _cells(line: str, columns: int) -> list[str]:
    assert line.endswith(r" \\"), line
    if line.startswith("{}["):
        line = line[2:]
    parts = re.split(r"(?<!\\)&", line[: -len(r" \\")])
    assert len(parts) == columns, (line, columns)
    return [part.strip() for part in parts]


def parse_table(tex: str) -> ParsedTable:
    """Parse one LaTeX table float written by polyell into plain text; AssertionError if not.

    Rows get every stub label (blank repeats filled in, a posture line above its rows
    prepended as the first label); grouped headers read ``group: header``.
    """
    lines = tex.strip("\n").splitlines()
    assert lines[:2] == [r"\begin{table}", r"\centering"], lines[:2]
    assert lines[-3:] == [r"\bottomrule", r"\end{tabular}", r"\end{table}"], lines[-3:]
    i, caption, label, size = 2, None, None, ""
    while lines[i] in _SIZES:
        size = size or lines[i]
        i += 1
    if lines[i].startswith(r"\caption{"):
        assert lines[i].endswith("}")
        caption = unescape(lines[i][len(r"\caption{") : -1])
        i += 1
    if lines[i].startswith(r"\label{"):
        label = lines[i][len(r"\label{") : -1]
        assert re.fullmatch(r"[A-Za-z0-9:._/+-]+", label), label
        i += 1
    spec = re.fullmatch(r"\\begin\{tabular\}\{(l+)(r*)\}", lines[i])
    assert spec is not None, lines[i]
    stub, columns = len(spec.group(1)), len(spec.group(1)) + len(spec.group(2))
    assert lines[i + 1] == r"\toprule"
    i += 2
    groups: list[str] = []
    if r"\multicolumn" in lines[i] and r"\cmidrule" in lines[i + 1]:
        parts = re.split(r"(?<!\\)&", lines[i][: -len(r" \\")])
        assert all(not p.strip() for p in parts[:stub]), lines[i]
        for part in parts[stub:]:
            group = _GROUP.fullmatch(part.strip())
            assert group is not None, part
            groups += [label_text(group.group(2))] * int(group.group(1))
        assert len(groups) == columns - stub
        i += 2
    header = [label_text(cell) for cell in _cells(lines[i], columns)]
    if groups:
        header[stub:] = [f"{g}: {h}" for g, h in zip(groups, header[stub:], strict=True)]
    assert lines[i + 1] == r"\midrule"
    rows: list[list[str]] = []
    posture: list[str] = []
    previous: list[str] = []
    for line in lines[i + 2 : -3]:
        if line == r"\midrule":
            continue
        spanning = _POSTURE.fullmatch(line)
        if spanning is not None:
            assert int(spanning.group(1)) == columns, line
            posture, previous = [unescape(spanning.group(2))], []
            continue
        cells = _cells(line, columns)
        labels = [label_text(cell) for cell in cells[:stub]]
        for k in range(stub - 1):  # a blank label repeats the one above
            if not labels[k]:
                assert previous, line
                labels[k] = previous[k]
        previous = labels
        rows.append(posture + labels + [cell_text(cell) for cell in cells[stub:]])
    return ParsedTable(caption, label, header, rows, stub + len(posture), size)


def parse_tables(tex: str) -> list[ParsedTable]:
    """Every table float of a text (a table per posture)."""
    blocks = re.findall(r"\\begin\{table\}.*?\\end\{table\}", tex, flags=re.S)
    return [parse_table(block) for block in blocks]


def engine(name: str) -> str | None:
    """The path of a LaTeX engine, or None where it is not installed."""
    return shutil.which(name)


def fit_warnings(program: str, tables: list[str], folder: Path) -> list[str]:
    """Compile tables in a one-column article (default margins, ``\\textwidth``) and return
    the log's warnings that a table does not fit: overfull boxes and floats too large.

    AssertionError with the log's first error if the engine reports any.
    """
    folder.mkdir(parents=True, exist_ok=True)
    body = "\n\\clearpage\n".join(tables)
    document = (
        "\\documentclass{article}\n\\usepackage{booktabs}\n"
        f"\\begin{{document}}\n{body}\n\\end{{document}}\n"
    )
    (folder / "fit.tex").write_text(document, encoding="utf-8")
    run = subprocess.run(
        [program, "-interaction=nonstopmode", "-halt-on-error", "fit.tex"],
        cwd=folder,
        capture_output=True,
        check=False,
    )
    log = (folder / "fit.log").read_text(encoding="utf-8", errors="replace")
    errors = [line for line in log.splitlines() if line.startswith("!")]
    assert run.returncode == 0 and not errors, f"{program}: {errors[:3]}\n{log[-2000:]}"
    return [
        line
        for line in log.splitlines()
        if line.startswith(("Overfull \\hbox", "Overfull \\vbox")) or "Float too large" in line
    ]


def compile_tables(program: str, tables: list[str], folder: Path) -> str:
    """Compile tables in one document; return its text (pdftotext -layout) or ''.

    AssertionError with the log's first error if the engine reports any.
    """
    folder.mkdir(parents=True, exist_ok=True)
    for k, table in enumerate(tables):
        (folder / f"table{k}.tex").write_text(table, encoding="utf-8")
    inputs = "\n".join(rf"\input{{table{k}}}\clearpage" for k in range(len(tables)))
    document = (
        "\\documentclass{article}\n\\usepackage{booktabs}\n"
        # A page wide enough for any table: a clipped column would hide a value.
        "\\usepackage[paperwidth=150cm,paperheight=60cm,margin=1cm]{geometry}\n"
        f"\\begin{{document}}\n{inputs}\n\\end{{document}}\n"
    )
    (folder / "doc.tex").write_text(document, encoding="utf-8")
    run = subprocess.run(
        [program, "-interaction=nonstopmode", "-halt-on-error", "doc.tex"],
        cwd=folder,
        capture_output=True,
        check=False,
    )
    log = (folder / "doc.log").read_text(encoding="utf-8", errors="replace")
    errors = [line for line in log.splitlines() if line.startswith("!")]
    assert run.returncode == 0 and not errors, f"{program}: {errors[:3]}\n{log[-2000:]}"
    pdftotext = shutil.which("pdftotext")
    if pdftotext is None:
        return ""
    out = subprocess.run(
        [pdftotext, "-layout", "doc.pdf", "-"], cwd=folder, capture_output=True, check=True
    )
    return out.stdout.decode("utf-8", errors="replace")
