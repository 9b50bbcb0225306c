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
    r"\_": "_",
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


#: The fixed LaTeX markup of score labels (trusted; not user text).
MARKUP_LABELS = {
    "dimension $r$",
    r"witness $\max \|\tilde\tau\|_\infty$",
    r"dir.\ error, mean [\%]",
    r"dir.\ error, max [\%]",
    r"dir.\ error, RMS [\%]",
    r"dir.\ bias [\%]",
}
_VOLUME = re.compile(r"volume \[(?P<unit>.*)\]")


@dataclass
class ParsedTable:
    caption: str | None
    label: str | None
    header: list[str]
    rows: list[list[str]]


def parse_table(tex: str) -> ParsedTable:
    """Parse a table written by ``render_table`` into plain text; AssertionError if malformed."""
    lines = tex.splitlines()
    assert lines[:2] == [r"\begin{table}", r"\centering"], lines[:2]
    assert lines[-3:] == [r"\bottomrule", r"\end{tabular}", r"\end{table}"], lines[-3:]
    i, caption, label = 2, None, None
    if lines[i].startswith(r"\caption{"):
        assert lines[i].endswith("}")
        caption = unescape(lines[i][len(r"\caption{") : -1])
        i += 1
    if lines[i].startswith(r"\label{"):
        label = lines[i][len(r"\label{") : -1]
        assert re.fullmatch(r"[A-Za-z0-9:._/+-]+", label), label
        i += 1
    spec = re.fullmatch(r"\\begin\{tabular\}\{l(r*)\}", lines[i])
    assert spec is not None, lines[i]
    columns = 1 + len(spec.group(1))
    assert lines[i + 1] == r"\toprule" and lines[i + 3] == r"\midrule"

    def cells(line: str) -> list[str]:
        assert line.endswith(r" \\"), line
        parts = re.split(r"(?<!\\)&", line[: -len(r" \\")])
        assert len(parts) == columns, (line, columns)
        return [part.strip() for part in parts]

    header = [unescape(cell) for cell in cells(lines[i + 2])]
    rows = []
    for line in lines[i + 4 : -3]:
        first, *rest = cells(line)
        volume = _VOLUME.fullmatch(first)
        if first in MARKUP_LABELS:
            plain = first
        elif volume is not None:  # the unit's powers are superscripts: m/s$^{2}$
            plain = "volume [" + unescape(re.sub(r"\$\^\{([-\w]+)\}\$", "", volume["unit"])) + "]"
        else:
            plain = unescape(first)
        rows.append([plain, *(unescape(cell) for cell in rest)])
    return ParsedTable(caption, label, header, rows)


def engine(name: str) -> str | None:
    """The path of a LaTeX engine, or None where it is not installed."""
    return shutil.which(name)


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
