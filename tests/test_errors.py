"""Error messages (issue 24): composed without doubled periods, however their parts end."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

import polyell as pe
from polyell.errors import clause, install_hint, sentence

#: Text of a message part: words, then perhaps one or more periods or an ellipsis.
words = st.text(st.sampled_from("abc xyz'[]()=01"), min_size=1, max_size=30).filter(
    lambda t: t.strip()
)
endings = st.sampled_from(["", ".", "..", ". ", "...", " ."])
part = st.builds(lambda w, e: w + e, words, endings)


def doubled_period(message: str) -> bool:
    """Two periods in a row that are not part of an ellipsis."""
    return re.search(r"(?<!\.)\.\.(?!\.)|\.\.\.\.", message) is not None


@given(argument=words, expected=part, got=part, fix=st.one_of(st.just(""), part))
def test_input_error_messages_never_double_a_period(argument, expected, got, fix):
    message = str(pe.InputError(argument, expected, got, fix))
    assert not doubled_period(message), message
    assert message.endswith((".", "...")), message
    assert f"expected {clause(expected)}, got {clause(got)}" in message
    assert ("Fix:" in message) == bool(clause(fix))


@given(inner_expected=part, inner_got=part, inner_fix=part, fix=st.one_of(st.just(""), part))
def test_nested_messages_never_double_a_period(inner_expected, inner_got, inner_fix, fix):
    inner = pe.InputError("path", inner_expected, inner_got, inner_fix)
    outer = pe.InputError("robot", "a robot file", str(inner), fix)
    assert not doubled_period(str(outer)), str(outer)
    assert str(inner).rstrip(".") in str(outer)  # the nested message, whole


def test_clause_and_sentence():
    assert clause("a float.") == "a float"
    assert clause("a float..") == "a float"
    assert clause("rows [1, 2]...") == "rows [1, 2]..."  # an ellipsis stays
    assert sentence("use a float") == sentence("use a float.") == "use a float."
    assert sentence("what now?") == "what now?"
    assert sentence("  ") == ""


def test_a_long_value_cut_with_an_ellipsis_ends_the_message_once():
    message = str(pe.InputError("x", "a number", "'" + "a" * 40 + "'...", ""))
    assert message.endswith("'...") and not doubled_period(message)


def test_install_hints_point_to_the_repository_not_pypi():
    assert install_hint("robots") == (
        "in a checkout of the polyell repository, run pip install '.[robots]'"
    )
    assert "pip install polyell" not in install_hint("studies")


@pytest.mark.parametrize("fix", ["do this", "do this.", "do this.."])
def test_fix_is_one_sentence(fix):
    assert str(pe.InputError("a", "b", "c", fix)) == "a: expected b, got c. Fix: do this."


def test_no_text_tells_to_install_polyell_from_pypi():
    """polyell installs from its repository: no message or page says pip install polyell."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    files = [root / "README.md", *(root / "polyell").rglob("*.py")]
    files += [p for p in (root / "docs").rglob("*") if p.suffix in {".md", ".py", ".ipynb"}]
    wrong = re.compile(r"pip install (--upgrade )?['\"]?polyell")
    offenders = [
        str(p.relative_to(root))
        for p in files
        if "_build" not in p.parts and wrong.search(p.read_text(encoding="utf-8"))
    ]
    assert offenders == []
