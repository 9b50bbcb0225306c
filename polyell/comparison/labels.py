r"""The one table of labels: what every table, report and figure calls a set or a quantity.

Plain text for Markdown, CSV and HTML, and the LaTeX of the few labels with mathematics
(trusted markup; every other label is escaped where it is written).  Units are added by
:func:`quantity_header`, in brackets, the same way in every format.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from polyell.errors import InputError
from polyell.validation import check_instance

__all__ = [
    "CAPACITY_SET_LABELS",
    "ELLIPSOID_LABELS",
    "QUANTITIES",
    "SET_LABELS",
    "Quantity",
    "ellipsoid_label",
    "quantity",
    "set_label",
]

#: The sets' labels (columns or rows of every table, legends of the report).
SET_LABELS = {
    "polytope": "polytope",
    "chiacchio": "new (eq. 32/38)",
    "yoshikawa": "classic (eq. 27)",
    "mvie": "MVIE",
    "outer": "outer (min. volume)",
}
#: The ellipsoids' labels (every set but the polytope).
ELLIPSOID_LABELS = {kind: label for kind, label in SET_LABELS.items() if kind != "polytope"}
#: Where another capacity gives a kind another meaning: ``{capacity: {kind: label}}``
#: (accelerations use :data:`SET_LABELS` alone).
CAPACITY_SET_LABELS = {
    "velocity": {"yoshikawa": "unit ball"},
    "force": {"chiacchio": "with gravity", "yoshikawa": "classic", "static": "no gravity"},
}


def set_label(kind: str, capacity: str = "acceleration") -> str:
    """The label of a set of a capacity (plain text); a candidate's is its name."""
    check_instance("kind", kind, str, "pass a set name, e.g. 'polytope'.")
    return CAPACITY_SET_LABELS.get(capacity, {}).get(kind) or SET_LABELS.get(kind, kind)


def ellipsoid_label(kind: str, capacity: str = "acceleration") -> str:
    """The label of an ellipsoid of a capacity (plain text); a candidate's is its name."""
    check_instance("kind", kind, str, "pass a kind name, e.g. 'chiacchio'.")
    return set_label(kind, capacity) if kind != "polytope" else kind


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
#: directional limits and their errors.
QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in (
        _q("dimension", "dimension r", "count", "dimension $r$"),
        _q("volume", "volume", "volume"),
        _q("inscribed_scale", "inscribed scale", "number"),
        _q("enclosing_scale", "enclosing scale", "number"),
        _q("coverage", "coverage", "share"),
        _q("overreach", "overreach", "share"),
        _q("mvie_ratio", "volume / MVIE volume", "number"),
        _q("outer_ratio", "volume / outer volume", "number"),
        _q("direction_error_mean", "direction error, mean", "share", r"dir.\ error, mean"),
        _q("direction_error_max", "direction error, max", "share", r"dir.\ error, max"),
        _q("direction_error_rms", "direction error, RMS", "share", r"dir.\ error, RMS"),
        _q("direction_bias", "direction bias", "share", r"dir.\ bias"),
        _q("feasibility_mismatch", "feasibility mismatches", "count"),
        _q(
            "witness_torque_max",
            "witness max abs(tau_n)",
            "number",
            r"witness $\max \|\tilde\tau\|_\infty$",
        ),
        _q("lower", "lower", "task"),
        _q("upper", "upper", "task"),
        _q("lower_error", "lower error", "share"),
        _q("upper_error", "upper error", "share"),
    )
}

#: Where another capacity gives a quantity another meaning: ``{capacity: {name: quantity}}``
#: (a velocity ellipsoid's witness is the normalized joint velocity its points need).
CAPACITY_QUANTITIES = {
    "velocity": {
        "witness_torque_max": _q(
            "witness_torque_max",
            "witness max abs(qd_n)",
            "number",
            r"witness $\max \|\tilde{\dot q}\|_\infty$",
        )
    }
}


def quantity(name: str, capacity: str = "acceleration") -> Quantity:
    """The quantity ``name`` (a key of :data:`QUANTITIES`) as a capacity labels it."""
    if not isinstance(name, str) or name not in QUANTITIES:
        raise InputError("name", f"a quantity among {sorted(QUANTITIES)}", repr(name)[:80])
    return CAPACITY_QUANTITIES.get(capacity, {}).get(name) or QUANTITIES[name]
