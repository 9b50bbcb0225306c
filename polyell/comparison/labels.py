r"""The one table of labels: what every table, report and figure calls a set or a quantity.

One name per set kind, whatever the robot and the capacity (:data:`SET_LABELS`): the
same kind is ``"Yoshikawa"`` in the tables, the CSV files, the figures and the reports of
accelerations, velocities and forces.  The equation numbers of Chiacchio's paper are a
preset (:data:`LABEL_PRESETS`, ``labels="chiacchio2000"``) for the paper's own study.

A user renames any set or score with a mapping (``TableLayout(labels={"chiacchio": "DME",
"coverage": "share covered"})``): a value is plain text (escaped in LaTeX), or a pair
``(plain, latex)`` whose LaTeX is written as is (checked by :func:`check_markup`).  Units
are added by :func:`~polyell.comparison.printable.quantity_label`, in brackets, the same
way in every format.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from difflib import get_close_matches
from types import MappingProxyType
from typing import Literal, NamedTuple, TypeAlias

from polyell.comparison.latex_text import check_text, escape_latex
from polyell.errors import InputError
from polyell.validation import _describe, check_instance

__all__ = [
    "CAPACITY_QUANTITIES",
    "CAPACITY_SET_LABELS",
    "ELLIPSOID_LABELS",
    "LABEL_PRESETS",
    "QUANTITIES",
    "SET_LABELS",
    "LabelText",
    "Labels",
    "Quantity",
    "check_labels",
    "check_markup",
    "ellipsoid_label",
    "label_text",
    "quantity",
    "resolve_labels",
    "set_label",
]


class LabelText(NamedTuple):
    """A label in plain text (Markdown, CSV, HTML, figures) and in LaTeX.

    ``latex`` is None where the LaTeX is the plain text escaped.
    """

    plain: str
    latex: str | None = None


#: A label as given: plain text, or ``(plain, latex)``.
LabelValue: TypeAlias = str | tuple[str, str] | LabelText
#: Labels as a layout holds them: a preset's name, a mapping of set or score names to
#: labels, or None (the defaults).
Labels: TypeAlias = str | Mapping[str, LabelValue] | None

#: The sets' labels (columns or rows of every table, legends of figures and reports): one
#: name per kind, for every robot and every capacity.
SET_LABELS = {
    "polytope": "polytope",
    "chiacchio": "Chiacchio",
    "yoshikawa": "Yoshikawa",
    "static": "static (no gravity)",
    "mvie": "MVIE",
    "outer": "outer (min. volume)",
}
#: The ellipsoids' labels (every set but the polytope).
ELLIPSOID_LABELS = {kind: label for kind, label in SET_LABELS.items() if kind != "polytope"}
#: Kept for compatibility: no capacity renames a kind any more (one name per kind).
CAPACITY_SET_LABELS: dict[str, dict[str, str]] = {}

#: Named sets of labels.  ``"chiacchio2000"``: the names and equation numbers of
#: P. Chiacchio, *A new dynamic manipulability ellipsoid for redundant manipulators*
#: (Robotica 18, 2000), for the paper's own study of accelerations; they mean nothing to
#: another paper's reader.
LABEL_PRESETS: dict[str, dict[str, LabelValue]] = {
    "chiacchio2000": {
        "polytope": "polytope (eq. 15)",
        "chiacchio": "new (eq. 32/38)",
        "yoshikawa": "classic (eq. 27)",
        "witness_torque_max": (
            "witness max abs(tau_n)",
            r"witness $\max \|\tilde\tau\|_\infty$",
        ),
    }
}

#: How a quantity's numbers are shown: whole numbers, numbers (unit-free), shares and
#: relative errors (percent or fraction), values in the task's unit, or volumes (its
#: power r).
QuantityKind = Literal["count", "number", "share", "task", "volume"]


@dataclass(frozen=True)
class Quantity:
    """A shown quantity: its name in the data, its label and how it is shown.

    Attributes
    ----------
    name : str
        Column of the data (``"coverage"``, ``"lower"``).
    plain : str
        Label without its unit (``"coverage"``).
    latex : str
        LaTeX of that label (trusted markup; the same text escaped where it has no maths).
    kind : {"count", "number", "share", "task", "volume"}
    stderr : str or None
        Column of its standard error, if estimated.
    """

    name: str
    plain: str
    latex: str
    kind: QuantityKind
    stderr: str | None = None


def _q(name: str, plain: str, kind: QuantityKind, latex: str | None = None) -> Quantity:
    stderr = f"{name}_stderr" if name in ("coverage", "overreach") else None
    return Quantity(name, plain, plain if latex is None else latex, kind, stderr)


#: Every quantity a table shows, in the default order: the comparison's scores, then the
#: directional limits and their errors.  The witness (the data column
#: ``witness_torque_max``, for compatibility) is named for what it holds in each
#: capacity: the largest normalized torque ``max |tau_n|`` a point of the ellipsoid needs
#: (accelerations, forces), the largest normalized joint velocity (velocities,
#: :data:`CAPACITY_QUANTITIES`).
QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in (
        _q("dimension", "dimension r", "count", "dimension $r$"),
        _q("volume", "volume", "volume"),
        _q("inscribed_scale", "inscribed scale", "number"),
        _q("enclosing_scale", "enclosing scale", "number"),
        _q("coverage", "coverage", "share"),
        _q("overreach", "overreach", "share"),
        # (abbreviated in LaTeX, as the direction errors and the feasibility mismatches:
        # the widest stubs of a comparison table, whose five force sets then fit a
        # one-column page)
        _q("mvie_ratio", "volume / MVIE volume", "number", r"vol.\ / MVIE vol."),
        _q("outer_ratio", "volume / outer volume", "number", r"vol.\ / outer vol."),
        _q("direction_error_mean", "direction error, mean", "share", r"dir.\ error, mean"),
        _q("direction_error_max", "direction error, max", "share", r"dir.\ error, max"),
        _q("direction_error_rms", "direction error, RMS", "share", r"dir.\ error, RMS"),
        _q("direction_bias", "direction bias", "share", r"dir.\ bias"),
        _q("feasibility_mismatch", "feasibility mismatches", "count", r"feas.\ mismatches"),
        _q("witness_torque_max", "torque witness", "number"),
        _q("lower", "lower", "task"),
        _q("upper", "upper", "task"),
        _q("lower_error", "lower error", "share"),
        _q("upper_error", "upper error", "share"),
    )
}

#: Where another capacity gives a quantity another meaning: ``{capacity: {name: quantity}}``
#: (a velocity ellipsoid's witness is the normalized joint velocity its points need; an
#: acceleration's or a force's, the normalized torque).
CAPACITY_QUANTITIES = {
    "velocity": {"witness_torque_max": _q("witness_torque_max", "joint velocity witness", "number")}
}

_NAME = re.compile(r"[a-z][a-z0-9_]{0,31}")


def _known_names() -> tuple[str, ...]:
    return (*SET_LABELS, *QUANTITIES)


def check_markup(argument: str, latex: object) -> str:
    r"""Check LaTeX a user gives for a label or a caption: one line that cannot break a table.

    Braces balanced (``\{`` and ``\}`` aside), math shifts ``$`` paired, and no ``&``,
    ``%``, ``#`` or ``\\`` outside their escapes (they would end a cell, comment out the rest
    of the row, or end the row).  The commands themselves are the user's: they must be
    defined in the document.

    Raises
    ------
    InputError
        Naming ``argument``, for anything else.
    """
    text = check_text(argument, latex)
    fix = r"write the LaTeX of one cell: escape & % # as \& \% \#, balance { } and $."
    if not text.strip():
        raise InputError(argument, "LaTeX that prints something", repr(text), fix)
    depth, math, k = 0, False, 0
    while k < len(text):
        c = text[k]
        if c == "\\":
            following = text[k + 1 : k + 2]
            if following in ("\\", ""):
                raise InputError(argument, r"LaTeX without \\ (a row's end)", repr(text)[:80], fix)
            k += 2
            continue
        if c in "&%#":
            raise InputError(argument, f"LaTeX without a bare {c!r}", repr(text)[:80], fix)
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth < 0:
                raise InputError(argument, "balanced braces", repr(text)[:80], fix)
        elif c == "$":
            math = not math
        k += 1
    if depth or math:
        what = "balanced braces" if depth else "paired math shifts $...$"
        raise InputError(argument, what, repr(text)[:80], fix)
    return text


def _label_value(argument: str, value: object) -> LabelText:
    """A label as given (text, or ``(plain, latex)``), checked."""
    if isinstance(value, LabelText):
        value = tuple(value) if value.latex is not None else value.plain
    if isinstance(value, str):
        plain = check_text(argument, value)
        if not plain.strip():
            raise InputError(
                argument,
                "a label that is not blank",
                repr(value),
                "give a label with some text, e.g. 'DME', or leave the name out for its default",
            )
        return LabelText(plain.strip())
    if isinstance(value, list | tuple) and len(value) == 2:
        plain = check_text(f"{argument}[0]", value[0])
        if not plain.strip():
            raise InputError(
                f"{argument}[0]",
                "a plain label that is not blank",
                repr(value[0]),
                "give the plain text beside the LaTeX, e.g. ('DME', '$E_D$')",
            )
        return LabelText(plain.strip(), check_markup(f"{argument}[1]", value[1]).strip())
    raise InputError(
        argument,
        "a label: plain text, or a pair (plain text, LaTeX)",
        _describe(value),
        'e.g. "share covered" or ("max |tau_n|", r"$\\max_i |\\tilde\\tau_i|$").',
    )


def check_labels(labels: object, argument: str = "labels") -> Labels:
    """Labels as a layout keeps them: a preset's name, or a read-only checked mapping.

    Parameters
    ----------
    labels : str, mapping or None
        A name of :data:`LABEL_PRESETS`, or a mapping from set names (``"chiacchio"``,
        a candidate's name) and score names (``"coverage"``, ``"lower_error"``) to labels:
        plain text, or a pair ``(plain, latex)``.
    argument : str
        Its name in messages (``"layout.labels"``).

    Raises
    ------
    InputError
        For an unknown preset, a key that is not a name (or a near miss of a known one:
        ``"chiachio"``), or a label that cannot be written.
    """
    if labels is None:
        return None
    if isinstance(labels, str):
        if labels not in LABEL_PRESETS:
            close = get_close_matches(labels, LABEL_PRESETS, n=1)
            raise InputError(
                argument,
                f"a preset among {list(LABEL_PRESETS)} or a mapping of names to labels",
                repr(labels)[:80],
                f"did you mean {close[0]!r}?" if close else 'e.g. {"chiacchio": "DME"}.',
            )
        return labels
    if not isinstance(labels, Mapping):
        raise InputError(
            argument,
            "a mapping of set or score names to labels, or a preset's name",
            _describe(labels),
            'e.g. {"chiacchio": "DME", "coverage": "share covered"}.',
        )
    known = _known_names()
    checked: dict[str, LabelText] = {}
    for key, value in labels.items():
        where = f"{argument}[{key!r}]"
        if not isinstance(key, str) or not _NAME.fullmatch(key):
            raise InputError(
                argument,
                "keys that are set names (a candidate's too) or score names",
                _describe(key),
                "key each label by a lower-case set or score name, e.g. 'chiacchio' or 'coverage'",
            )
        if key not in known:
            close = get_close_matches(key, known, n=1, cutoff=0.85)
            if close:
                raise InputError(
                    argument,
                    f"keys among the sets {list(SET_LABELS)}, candidate names, the scores "
                    "of polyell.SCORE_NAMES and lower, upper, lower_error, upper_error",
                    repr(key),
                    f"did you mean {close[0]!r}?",
                )
        checked[key] = _label_value(where, value)
    return MappingProxyType(checked)


def resolve_labels(labels: Labels = None) -> Mapping[str, LabelText]:
    """The user's labels by name (empty for the defaults); a preset expanded."""
    labels = check_labels(labels)
    if labels is None:
        return {}
    if isinstance(labels, str):
        return {key: _label_value(key, value) for key, value in LABEL_PRESETS[labels].items()}
    return labels  # type: ignore[return-value]  # (checked: LabelText values)


def label_text(kind: str, capacity: str = "acceleration", labels: Labels = None) -> LabelText:
    """A set's label in plain text and, where the user gave it, in LaTeX.

    The user's label of ``kind`` (``labels``), else :data:`SET_LABELS`; a candidate's
    default label is its name.  ``capacity`` is accepted for compatibility: a kind has one
    name in every capacity.
    """
    check_instance("kind", kind, str, "pass a set name, e.g. 'polytope'.")
    own = resolve_labels(labels).get(kind)
    return own if own is not None else LabelText(SET_LABELS.get(kind, kind))


def set_label(kind: str, capacity: str = "acceleration", labels: Labels = None) -> str:
    """The label of a set (plain text): the user's, else one name per kind.

    Examples
    --------
    >>> set_label("yoshikawa"), set_label("yoshikawa", "velocity")
    ('Yoshikawa', 'Yoshikawa')
    >>> set_label("chiacchio", labels="chiacchio2000")
    'new (eq. 32/38)'
    """
    return label_text(kind, capacity, labels).plain


def ellipsoid_label(kind: str, capacity: str = "acceleration", labels: Labels = None) -> str:
    """The label of an ellipsoid (plain text); a candidate's is its name."""
    check_instance("kind", kind, str, "pass a kind name, e.g. 'chiacchio'.")
    return set_label(kind, capacity, labels)


def quantity(name: str, capacity: str = "acceleration", labels: Labels = None) -> Quantity:
    """The quantity ``name`` (a key of :data:`QUANTITIES`) as a capacity and ``labels`` label it.

    Examples
    --------
    >>> quantity("witness_torque_max", "velocity").plain
    'joint velocity witness'
    >>> quantity("coverage", labels={"coverage": "share covered"}).plain
    'share covered'
    """
    if not isinstance(name, str) or name not in QUANTITIES:
        close = get_close_matches(str(name), QUANTITIES, n=1)
        raise InputError(
            "name",
            f"a quantity among {sorted(QUANTITIES)}",
            repr(name)[:80],
            f"did you mean {close[0]!r}?"
            if close
            else "use one of the names listed, e.g. 'coverage'",
        )
    found = CAPACITY_QUANTITIES.get(capacity, {}).get(name) or QUANTITIES[name]
    own = resolve_labels(labels).get(name)
    if own is None:
        return found
    latex = own.latex if own.latex is not None else escape_latex(own.plain, "labels")
    return replace(found, plain=own.plain, latex=latex)
