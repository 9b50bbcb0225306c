"""The study and robot file format: one typed model (pydantic v2) per TOML table.

The one source of the format: what :func:`parse_study` and :func:`parse_robot` accept, their
defaults, their error messages (the key's path, what was expected, what arrived and the fix,
"did you mean" for a misspelled key or name), the reference page ``docs/study_format.md``
(:func:`reference_page`) and the JSON Schemas ``docs/study.schema.json`` and
``docs/robot.schema.json`` (:func:`json_schema`).

The models check everything a file says on its own, and are what a study reads its keys
from (``spec.file.compare.samples``); what needs the robot (joint counts, task rows, joint
limits) is derived and checked when :mod:`polyell.studies.spec` loads the study, before any
output is written.  This module imports pydantic: only the study loader imports it
(``import polyell`` does not).
"""

from __future__ import annotations

import json
import math
import re
import sys
import types
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from difflib import get_close_matches
from typing import Annotated, Any, ClassVar, Literal, TypeGuard, Union, get_args, get_origin

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator
from pydantic_core import PydanticUndefined, core_schema

from polyell import robots
from polyell.capacities import CAPACITIES
from polyell.capacities.horizon import check_horizon
from polyell.comparison.comparison import (
    MAX_SAMPLES,
    MAX_SEED,
    MIN_SAMPLES,
    SCORE_NAMES,
    compared_kinds,
)
from polyell.comparison.layout import (
    CAPTION_TABLES,
    LAYOUT_SETS,
    LIMIT_QUANTITIES,
    MAX_DIGITS,
    MAX_TEXT_WIDTH,
    TEXT_WIDTH,
    TableLayout,
)
from polyell.errors import InputError
from polyell.expressions import evaluate, evaluate_list
from polyell.models.self_motion import MAX_COUNT
from polyell.models.torque_speed import TorqueSpeed
from polyell.studies.posture_targets import MAX_TARGETS
from polyell.validation import MAX_DIRECTIONS, ROUNDED_INPUT_RTOL, _describe, check_integer

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "CSV_AUTO_ROWS",
    "FORMATS",
    "MAX_STUDY_CONFIGURATIONS",
    "ROBOT_NAME",
    "TABLES",
    "CandidateTable",
    "CompareTable",
    "OutputTable",
    "PayloadTable",
    "PlanarTable",
    "PointTable",
    "PostureTable",
    "RandomTable",
    "RangeTable",
    "RobotTable",
    "StudyFile",
    "TorqueSpeedTable",
    "TrajectoryTable",
    "did_you_mean",
    "json_schema",
    "keys",
    "parse_robot",
    "parse_study",
    "reference_page",
]

#: Most configurations of a grid or random study (its results are streamed chunk by chunk:
#: the bound is one of time and disk, about 0.4 kB of Parquet a configuration at the study
#: defaults; larger sweeps go through pe.sweep(..., out=...)).
MAX_STUDY_CONFIGURATIONS = 10_000_000
#: ``[output] csv = "auto"`` writes ``results.csv`` for studies of at most this many
#: configurations (about 1 kB of CSV a configuration with every score).
CSV_AUTO_ROWS = 100_000
#: Figure formats, and "html": one self-contained interactive report (plotly).
FORMATS = ("pdf", "png", "svg", "html")
#: A point's name becomes part of file names: letters, digits, ``_ . -``, not leading ``.``.
POINT_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")
#: A robot's name prefixes its points' file names (``sets_<robot>.<point>``): no ``.``.
ROBOT_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,31}")
#: A named direction: task rows, each with an optional sign (``"x"``, ``"x-y"``, ``"wx"``).
DIRECTION_NAME = re.compile(r"[+-]?[A-Za-z0-9][A-Za-z0-9+-]{0,63}")
#: The keys of a robot table that only URDF robots take.
URDF_KEYS = ("tip", "task", "locked_joints", "gravity", "weights", "payload")


def did_you_mean(given: Sequence[object], valid: Sequence[str]) -> str:
    """A fix naming the valid word closest to each misspelled one (difflib), if any."""
    pairs = [
        (str(word), close[0])
        for word in given
        if (close := get_close_matches(str(word), valid, n=1, cutoff=0.6))
    ]
    if not pairs:
        return ""
    return "did you mean " + ", ".join(f"{close!r} for {word!r}" for word, close in pairs) + "?"


# ---------------------------------------------------------------------------------------
# Value types: a validator that raises InputError with a path relative to the key, the
# JSON Schema of the value and the phrase the reference page and the messages use.


@dataclass(frozen=True, eq=False)
class Check:
    """A value type's check, JSON Schema and name, as ``Annotated`` metadata pydantic reads.

    ``check`` returns the value or raises InputError with a path relative to the key
    (``""``, ``"[0]"``, ``".num"``); ``phrase`` names the type on the reference page.
    """

    check: Callable[[Any], Any]
    schema: dict[str, Any]
    phrase: str

    def __get_pydantic_core_schema__(self, source: Any, handler: Any) -> Any:
        return core_schema.no_info_plain_validator_function(self.check)

    def __get_pydantic_json_schema__(self, schema: Any, handler: Any) -> dict[str, Any]:
        return dict(self.schema)


_NUMBER_SCHEMA: dict[str, Any] = {
    "type": ["number", "string"],
    "description": "a number or an expression",
}
_NUMBERS_SCHEMA: dict[str, Any] = {"type": ["array", "string"], "items": _NUMBER_SCHEMA}
_NUMBERS = "list of numbers or expressions"


def _numbers(value: object) -> tuple[float, ...]:
    return tuple(evaluate_list("", value))  # type: ignore[arg-type]


def _number_rows(value: list[Any]) -> tuple[tuple[float, ...], ...]:
    """Each item of ``value`` as a row of numbers (errors name the row: ``[1][0]``)."""
    return tuple(tuple(evaluate_list(f"[{i}]", row)) for i, row in enumerate(value))


def _is_strings(value: object) -> TypeGuard[list[str]]:
    """Whether ``value`` is a list of strings."""
    return isinstance(value, list) and all(isinstance(v, str) for v in value)


@contextmanager
def _under(prefix: str) -> Iterator[None]:
    """Prefix the argument of an InputError raised inside with ``prefix`` (``"[0]"``)."""
    try:
        yield
    except InputError as exn:
        raise InputError(prefix + exn.argument, exn.expected, exn.got, exn.fix) from None


def _string(value: object) -> str:
    if not isinstance(value, str):
        raise InputError(
            "",
            "a string",
            _describe(value),
            f'put it in double quotes: "{value}"'
            if isinstance(value, int | float) and not isinstance(value, bool)
            else 'write the text in double quotes, e.g. "panda".',
        )
    return value


def _strings(value: object) -> tuple[str, ...]:
    if not _is_strings(value):
        raise InputError(
            "",
            "a list of strings",
            _describe(value),
            'write the strings in double quotes within brackets, e.g. ["j6", "j7"].',
        )
    return tuple(value)


def _title(value: object) -> str:
    """A title that figures show: a ``$...$`` typo is refused when the file loads."""
    title = _string(value)
    if "$" not in title:  # no mathtext: no need to load matplotlib
        return title
    from polyell.figures import check_title

    return check_title(title, "")


def _name(pattern: re.Pattern[str], expected: str, fix: str) -> Check:
    """A string that ``pattern`` matches in full (a name that becomes part of file names)."""

    def check(value: object) -> str:
        name = _string(value)
        if not pattern.fullmatch(name):
            raise InputError("", expected, repr(name), fix)
        return name

    return Check(check, {"type": "string", "pattern": f"^{pattern.pattern}$"}, "string")


def _library(value: object) -> str:
    name = _string(value)
    if name not in robots.names():
        raise InputError(
            "",
            f"one of {robots.names()}",
            repr(name),
            did_you_mean([name], robots.names())
            or f'use a robot of the library, e.g. library = "{robots.names()[0]}", or your '
            'own with urdf = "arm.urdf".',
        )
    return name


def _task(value: object) -> str | tuple[str, ...]:
    if isinstance(value, str):
        return value
    if not _is_strings(value):
        raise InputError(
            "",
            'a list of task rows (among x y z wx wy wz), or "linear", "angular" or "planar"',
            _describe(value),
            'e.g. task = ["x", "z"] or task = "linear".',
        )
    return tuple(value)


def _vector3(value: object) -> tuple[float, ...]:
    if not isinstance(value, list):
        raise InputError(
            "",
            "a list of 3 numbers (x, y, z)",
            _describe(value),
            "write the three coordinates in brackets, e.g. [0, 0, 0.05].",
        )
    vector = _numbers(value)
    if len(vector) != 3:
        raise InputError(
            "",
            "3 numbers (x, y, z)",
            f"{len(vector)}: {_describe(value)}",
            "give exactly x, y and z, e.g. [0, 0, 0.05].",
        )
    return vector


def _matrix3(value: object) -> tuple[tuple[float, ...], ...]:
    example = "e.g. [[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]]."
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(
            "",
            "a 3 x 3 list of lists",
            _describe(value),
            f"write three rows of three numbers, {example}",
        )
    rows = _number_rows(value)
    if any(len(row) != 3 for row in rows):
        raise InputError(
            "",
            "a 3 x 3 list of lists",
            f"rows of {[len(r) for r in rows]}",
            f"give every row three numbers, {example}",
        )
    return rows


def _matrix(value: object) -> tuple[tuple[float, ...], ...]:
    """A square matrix: a list of rows, or a list of numbers (its diagonal)."""
    if not isinstance(value, list):
        raise InputError(
            "",
            "a list of rows, or a list of numbers (the diagonal)",
            _describe(value),
            "e.g. [1, 1, 4] for a diagonal matrix, or rows such as [[1e-3, 0], [0, 2e-3]].",
        )
    if value and all(isinstance(row, list) for row in value):
        rows = _number_rows(value)
        if any(len(row) != len(rows) for row in rows):
            lengths = [len(row) for row in rows]
            raise InputError(
                "",
                f"{len(rows)} rows of {len(rows)} numbers",
                f"{lengths}",
                f"give each of the {len(rows)} rows {len(rows)} numbers (a square matrix), or "
                "a list of numbers for a diagonal one.",
            )
        return rows
    diagonal = evaluate_list("", value)
    return tuple(
        tuple(d if i == j else 0.0 for j in range(len(diagonal))) for i, d in enumerate(diagonal)
    )


def _rows(value: object) -> tuple[tuple[float, ...], ...]:
    """A list of rows of numbers (one per joint), of any lengths (checked where used)."""
    if not isinstance(value, list) or not value or not all(isinstance(r, list) for r in value):
        raise InputError(
            "",
            "a list of rows, one list of numbers per joint",
            _describe(value),
            "write one bracketed list per joint, e.g. [[150, 120, 0], [40, 30, 0]].",
        )
    return _number_rows(value)


def _numbers_or_rows(value: object) -> tuple[float, ...] | tuple[tuple[float, ...], ...]:
    """A list of numbers, or a list of rows of numbers (one per joint)."""
    if isinstance(value, list) and value and all(isinstance(r, list) for r in value):
        return _rows(value)
    return _numbers(value)


_DIRECTION = 'a direction named by task rows ("x", "-z", "xy", "wx") or a unit vector'


def _direction(value: object) -> str | tuple[float, ...]:
    """A named direction (checked against the robot's task rows later) or a unit vector."""
    if isinstance(value, str):
        if not DIRECTION_NAME.fullmatch(value):
            raise InputError(
                "",
                _DIRECTION,
                repr(value)[:60],
                'name task rows, each with an optional sign, e.g. "x", "-z" or "x-y", or give '
                'a unit vector such as ["-1/2", "sqrt(3)/2"].',
            )
        return value
    if not isinstance(value, list):
        raise InputError(
            "",
            _DIRECTION,
            _describe(value),
            'write a name in quotes, e.g. "x", or a vector in brackets, e.g. [0, 1].',
        )
    vector = _numbers(value)
    norm = math.sqrt(math.fsum(v * v for v in vector))
    # The rule of every direction polyell takes (validation.check_directions): unit length
    # to ROUNDED_INPUT_RTOL, so that a vector typed to 5 digits is accepted.
    if not abs(norm - 1.0) <= ROUNDED_INPUT_RTOL:
        raise InputError(
            "",
            f"a unit vector (norm within {ROUNDED_INPUT_RTOL:g} of 1), or a direction "
            "named by task rows",
            f"norm {norm!r}",
            'divide by the norm, or name it: "xy" is the unit diagonal (1, 1, 0)/sqrt(2).',
        )
    return vector


def _directions(value: object) -> tuple[str | tuple[float, ...], ...]:
    if not isinstance(value, list) or not value:
        raise InputError(
            "",
            'a non-empty list of directions: names ("x", "-z", "xy") or unit vectors',
            _describe(value),
            'e.g. directions = ["x", "y", "xy"].',
        )
    items = []
    for j, item in enumerate(value):
        with _under(f"[{j}]"):
            items.append(_direction(item))
    return tuple(items)


def _per_robot(value: object) -> tuple[float, ...] | dict[str, tuple[float, ...]]:
    """Joint angles, or a table of them per robot (``{ panda = [...], ur5 = [...] }``)."""
    if isinstance(value, dict):
        for name in value:
            if not ROBOT_NAME.fullmatch(name):
                raise InputError(
                    "",
                    "a table of joint angles by robot name",
                    f"a key {name!r}",
                    "key the angles by the names of [[robots]] (letters, digits, '_' or '-'), "
                    "e.g. { panda = [...], ur5 = [...] }.",
                )
        return {name: tuple(evaluate_list(f".{name}", q)) for name, q in value.items()}
    return _numbers(value)


def Choices(valid: tuple[str, ...]) -> Check:
    """A list of strings among ``valid``."""

    def check(value: object) -> tuple[str, ...]:
        if not _is_strings(value):
            raise InputError("", "a list of strings", _describe(value), f"among {list(valid)}.")
        unknown = [v for v in value if v not in valid]
        if unknown:
            at = value.index(unknown[0])
            raise InputError(
                f"[{at}]",
                f"one of {list(valid)}",
                repr(unknown[0]),
                did_you_mean(unknown, valid) or f'use names of the list only, e.g. ["{valid[0]}"].',
            )
        return tuple(value)

    return Check(check, {"type": "array", "items": {"enum": list(valid)}}, "list of strings")


def Integer(low: int, high: int) -> Check:
    """An integer from ``low`` to ``high`` (refused with the fix: a whole number in range)."""

    def check(value: object) -> int:
        try:
            return check_integer("", value, low, high)
        except InputError as exn:  # check_integer's fix speaks Python: a file's, in TOML
            number = isinstance(value, int | float) and not isinstance(value, bool)
            near = low
            if number and math.isfinite(float(value)):  # type: ignore[arg-type]
                near = int(min(max(float(value), low), high))  # type: ignore[arg-type]
            raise InputError(
                exn.argument,
                exn.expected,
                exn.got,
                f"write a whole number from {low:,} to {high:,} without quotes, e.g. {near}.",
            ) from None

    return Check(check, {"type": "integer", "minimum": low, "maximum": high}, "integer")


#: A seed of ``numpy.random.default_rng``; how many configurations a study may hold.
Seed = Annotated[int, Integer(0, MAX_SEED)]
Count = Annotated[int, Integer(1, MAX_STUDY_CONFIGURATIONS)]


def _grid_value(value: object) -> float | RangeTable:
    if isinstance(value, dict):
        return validate(RangeTable, value)
    return evaluate("", value)  # type: ignore[arg-type]


Number = Annotated[float, Check(lambda value: evaluate("", value), _NUMBER_SCHEMA, "number")]
Horizon = Annotated[
    float,
    Check(
        lambda value: check_horizon("", value),
        {"type": "number", "exclusiveMinimum": 0},
        "positive number of seconds",
    ),
]
Numbers = Annotated[tuple[float, ...], Check(_numbers, _NUMBERS_SCHEMA, _NUMBERS)]
String = Annotated[str, Check(_string, {"type": "string"}, "string")]
Strings = Annotated[
    tuple[str, ...],
    Check(_strings, {"type": "array", "items": {"type": "string"}}, "list of strings"),
]
Title = Annotated[str, Check(_title, {"type": "string"}, "string")]
FileName = Annotated[
    str,
    _name(
        POINT_NAME,
        "1-64 letters, digits, '_', '.' or '-', not starting with '.' (it names files)",
        "no '/' or '..': nothing a study says may write outside the output folder.",
    ),
]
RobotName = Annotated[
    str,
    _name(
        ROBOT_NAME,
        "1-32 letters, digits, '_' or '-' (it prefixes file names: sets_<robot>.<point>)",
        'e.g. name = "panda".',
    ),
]
Library = Annotated[str, Check(_library, {"type": "string", "enum": robots.names()}, "string")]
Task = Annotated[
    str | tuple[str, ...],
    Check(
        _task,
        {"oneOf": [{"type": "string"}, {"type": "array", "items": {"type": "string"}}]},
        "string or list of strings",
    ),
]
Vector3 = Annotated[
    tuple[float, ...], Check(_vector3, {**_NUMBERS_SCHEMA, "minItems": 3, "maxItems": 3}, _NUMBERS)
]
Matrix3 = Annotated[
    tuple[tuple[float, ...], ...],
    Check(
        _matrix3,
        {"type": "array", "items": {"type": "array", "items": _NUMBER_SCHEMA}},
        "3 x 3 list of lists",
    ),
]
Matrix = Annotated[
    tuple[tuple[float, ...], ...],
    Check(
        _matrix,
        {
            "type": "array",
            "items": {"oneOf": [_NUMBER_SCHEMA, {"type": "array", "items": _NUMBER_SCHEMA}]},
        },
        "matrix: list of rows, or the diagonal",
    ),
]
_ROWS_SCHEMA: dict[str, Any] = {"type": "array", "items": _NUMBERS_SCHEMA, "minItems": 1}
Rows = Annotated[
    tuple[tuple[float, ...], ...], Check(_rows, _ROWS_SCHEMA, "list of rows (one per joint)")
]
NumbersOrRows = Annotated[
    tuple[float, ...] | tuple[tuple[float, ...], ...],
    Check(
        _numbers_or_rows,
        {"anyOf": [_NUMBERS_SCHEMA, _ROWS_SCHEMA]},
        f"{_NUMBERS}, or one per joint",
    ),
]
_DIRECTION_SCHEMA = {"oneOf": [{"type": "string"}, {"type": "array", "items": _NUMBER_SCHEMA}]}
Direction = Annotated[
    str | tuple[float, ...],
    Check(_direction, _DIRECTION_SCHEMA, "name of task rows or unit vector"),
]
Directions = Annotated[
    tuple[str | tuple[float, ...], ...],
    Check(
        _directions,
        {"type": "array", "items": _DIRECTION_SCHEMA, "minItems": 1},
        "list of names or vectors",
    ),
]
JointAngles = Annotated[
    tuple[float, ...] | dict[str, tuple[float, ...]],
    Check(
        _per_robot,
        {"oneOf": [_NUMBERS_SCHEMA, {"type": "object", "additionalProperties": _NUMBERS_SCHEMA}]},
        f"{_NUMBERS}, or a table of them per robot",
    ),
]


def _csv_choice(value: object) -> bool | str:
    if isinstance(value, bool) or (isinstance(value, str) and value == "auto"):
        return value
    raise InputError(
        "",
        'true, false or "auto"',
        _describe(value),
        f'"auto" writes results.csv up to {CSV_AUTO_ROWS:,} configurations; true always.',
    )


CsvChoice = Annotated[
    bool | str,
    Check(_csv_choice, {"oneOf": [{"type": "boolean"}, {"const": "auto"}]}, 'boolean or "auto"'),
]


def _table_labels(value: object) -> str | Mapping[str, str | tuple[str, str]]:
    """A preset's name, or a table of labels (text, or ``[plain, latex]``) by name.

    Checked as :class:`~polyell.comparison.layout.TableLayout` checks its ``labels``; that
    every key is a set, a candidate or a score is checked with the candidates
    (:class:`StudyFile`).
    """
    from polyell.comparison.labels import check_labels

    if isinstance(value, str):
        check_labels(value, "")  # a preset's name (the message lists them)
        return value
    if not isinstance(value, dict):
        raise InputError(
            "",
            "a table of set or score names to labels, or a preset's name",
            _describe(value),
            'e.g. labels = { chiacchio = "DME", coverage = "share covered" }.',
        )
    checked: dict[str, str | tuple[str, str]] = {}
    for name, label in value.items():
        try:
            check_labels({name: label}, "")
        except InputError as exn:  # ["name"][1] as .name[1]
            rest = exn.argument.removeprefix(f"[{name!r}]")
            raise InputError(f".{name}{rest}", exn.expected, exn.got, exn.fix) from None
        checked[name] = tuple(label) if isinstance(label, list) else label
    return types.MappingProxyType(checked)


_LABEL_SCHEMA: dict[str, Any] = {
    "oneOf": [
        {"type": "string"},
        {"type": "array", "items": {"type": "string"}, "minItems": 2, "maxItems": 2},
    ]
}
TableLabels = Annotated[
    str | Mapping[str, str | tuple[str, str]],
    Check(
        _table_labels,
        {
            "oneOf": [
                {"type": "string", "description": "a preset's name"},
                {"type": "object", "additionalProperties": _LABEL_SCHEMA},
            ]
        },
        "table of labels, or a preset's name",
    ),
]


#: The suffixes of another capacity's tables (``comparison_force``): a caption's key may
#: carry one (the acceleration tables' names have none).
_CAPTION_SUFFIXES = ("_velocity", "_force")
#: A caption's key: a table's file name without its extension.
CAPTION_KEY = re.compile(rf"(?:{'|'.join(CAPTION_TABLES)})(?:{'|'.join(_CAPTION_SUFFIXES)})?")


def _table_captions(value: object) -> Mapping[str, str | tuple[str, str]]:
    """A table of captions by table file name (``comparison``, ``summary_force``).

    Each caption is plain text or ``[plain, latex]``, checked as
    :class:`~polyell.comparison.layout.TableLayout` checks its ``captions``; that the
    study writes the table is checked with the study (:class:`StudyFile`).
    """
    from polyell.comparison.labels import _label_value

    names = [f"{table}{suffix}" for suffix in ("", *_CAPTION_SUFFIXES) for table in CAPTION_TABLES]
    if not isinstance(value, dict):
        raise InputError(
            "",
            "a table of captions by table name",
            _describe(value),
            'e.g. captions = { limits = "Limits of the Panda.", comparison_force = '
            '["Force scores.", "Force scores, $F$."] }.',
        )
    checked: dict[str, str | tuple[str, str]] = {}
    for name, caption in value.items():
        if not CAPTION_KEY.fullmatch(name):
            raise InputError(
                f".{name}",
                f"a key that names a table: {', '.join(CAPTION_TABLES)}, with an optional "
                f"capacity suffix ({', '.join(_CAPTION_SUFFIXES)})",
                repr(name),
                did_you_mean([name], names)
                or "a key is the table's file name (limits.tex: limits).",
            )
        pair = isinstance(caption, list) and len(caption) == 2
        if not isinstance(caption, str) and not (pair and all(isinstance(c, str) for c in caption)):
            raise InputError(
                f".{name}",
                "a caption: text, or a pair [plain text, LaTeX]",
                _describe(caption),
                f'e.g. {name} = "Limits of the Panda." or {name} = ["Limits along x+z.", '
                '"Limits along $x + z$."].',
            )
        blank = [k for k, text in enumerate(caption if pair else [caption]) if not text.strip()]
        if blank:
            where = f".{name}[{blank[0]}]" if pair else f".{name}"
            raise InputError(
                where,
                "a caption that is not blank",
                repr(caption),
                "write the caption, or leave the key out for the table's default caption.",
            )
        text = _label_value(f".{name}", tuple(caption) if pair else caption)
        checked[name] = text.plain if text.latex is None else (text.plain, text.latex)
    return types.MappingProxyType(checked)


TableCaptions = Annotated[
    Mapping[str, str | tuple[str, str]],
    Check(
        _table_captions,
        {"type": "object", "additionalProperties": _LABEL_SCHEMA},
        "table of captions",
    ),
]


def _siunitx(value: object) -> bool:
    if not isinstance(value, bool):
        raise InputError(
            "",
            "true or false",
            _describe(value),
            "siunitx = true: S columns (the document needs \\usepackage{siunitx}); false: r "
            "columns, booktabs only.",
        )
    return value


SiunitxChoice = Annotated[bool, Check(_siunitx, {"type": "boolean"}, "boolean")]


def _text_width(value: object) -> float | bool:
    if value is False:
        return False
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or not 0 < value <= MAX_TEXT_WIDTH
    ):
        raise InputError(
            "",
            f"a width in pt above 0 and up to {MAX_TEXT_WIDTH:g}, or false (no check)",
            _describe(value),
            f"e.g. {TEXT_WIDTH:g} (a one-column article) or 252 (a two-column journal's "
            "column); LaTeX prints it with \\showthe\\textwidth.",
        )
    return float(value)


TextWidth = Annotated[
    float | bool,
    Check(
        _text_width,
        {
            "oneOf": [
                {"type": "number", "exclusiveMinimum": 0, "maximum": MAX_TEXT_WIDTH},
                {"const": False},
            ]
        },
        "number (pt), or false",
    ),
]


_GRID_SCHEMA: dict[str, Any] = {
    "type": "object",
    "patternProperties": {
        "^q[1-9][0-9]*$": {
            "oneOf": [
                _NUMBER_SCHEMA,
                {
                    "type": "object",
                    "properties": {
                        "start": _NUMBER_SCHEMA,
                        "stop": _NUMBER_SCHEMA,
                        "num": {"type": "integer", "minimum": 1},
                    },
                    "required": ["start", "stop", "num"],
                    "additionalProperties": False,
                },
            ]
        }
    },
    "additionalProperties": False,
}


def _grid(value: object) -> dict[str, float | RangeTable]:
    if not isinstance(value, dict):
        raise InputError(
            "",
            "a table: q1 = value or q1 = { start, stop, num } per joint",
            _describe(value),
            'e.g. grid = { q1 = "pi/2", q2 = { start = "-pi", stop = "pi", num = 61 } }, or '
            "a [grid] table with one key per joint.",
        )
    values = {}
    for name, item in value.items():
        if not re.fullmatch(r"q[1-9][0-9]{0,8}", name):
            raise InputError(
                "",
                "keys q1, q2, ... (one per joint)",
                f"a key {name!r}",
                "name the joints q1, q2, ... in order, e.g. q1 = 0.5.",
            )
        with _under(f".{name}"):
            values[name] = _grid_value(item)
    return values


Grid = Annotated[
    dict[str, "float | RangeTable"],
    Check(_grid, _GRID_SCHEMA, "number or { start, stop, num } per joint"),
]


def key(
    default: Any = PydanticUndefined,
    *,
    what: str,
    example: str = "",
    default_text: str | None = None,
    factory: Callable[[], Any] | None = None,
) -> Any:
    """A key of a table: its meaning, a TOML example of its value and how its default reads.

    A key without a default value of its own (None, or a table made by ``factory``) reads
    ``—`` unless ``default_text`` says more.
    """
    extra: dict[str, Any] = {"x-example": example}
    if default_text is None and (default is None or factory is not None):
        default_text = "—"
    if default_text is not None:
        extra["x-default"] = default_text
    if factory is not None:
        return Field(default_factory=factory, description=what, json_schema_extra=extra)
    if default is PydanticUndefined:
        return Field(description=what, json_schema_extra=extra)
    return Field(default=default, description=what, json_schema_extra=extra)


# ---------------------------------------------------------------------------------------
# Tables


class Table(BaseModel):
    """A TOML table: its keys are the model's fields; unknown keys are refused by name."""

    model_config = ConfigDict(
        extra="forbid", strict=True, frozen=True, arbitrary_types_allowed=True
    )

    #: The table's heading on the reference page (``"[robot]"``).
    heading: ClassVar[str] = ""
    #: A study (or robot file) that uses the table: the reference page shows it, the tests load it.
    example: ClassVar[str] = ""

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        valid = list(cls.model_fields)
        if not isinstance(data, dict):
            example = _example(cls.model_fields[valid[0]]) or "..."
            raise InputError(
                "",
                f"a table with keys among {valid}",
                _describe(data),
                f"write a table of these keys, e.g. {{ {valid[0]} = {example} }}.",
            )
        unknown = sorted(str(name) for name in set(data) - set(valid))
        if unknown:
            raise InputError(
                "",
                f"keys among {valid}",
                f"unknown key(s) {unknown}",
                did_you_mean(unknown, valid) or "check the spelling against the valid keys.",
            )
        for name, field in cls.model_fields.items():
            if field.is_required() and name not in data:
                example = _example(field)
                raise InputError(
                    "",
                    f"a '{name}' {phrase(field.annotation, field.metadata)}",
                    "no such key",
                    f"add {name} = {example}" if example else f"add the key {name} to the table.",
                )
        return data

    def _given(self, names: Sequence[str]) -> list[str]:
        """Those of the keys ``names`` that the table gives (their value is not None)."""
        return [name for name in names if getattr(self, name) is not None]


class PlanarTable(Table):
    """A planar arm in the vertical plane.

    Relative joint angles, gravity along -y, the end-effector position as task.
    """

    heading: ClassVar[str] = "[robot.planar]"
    example: ClassVar[str] = """[robot]
tau_max = [100, 30, 4]
[robot.planar]
lengths = [1.0, 0.8, 0.5]
masses = [4.0, 2.0, 0.6]
com = [0.5, 0.4, 0.25]
inertia = [0.3, 0.1, 0.01]
gravity = 9.81
[[points]]
name = "p"
q = [0.1, 0.2, 0.3]"""

    lengths: Numbers = key(what="Link lengths [m].", example="[1.0, 0.8, 0.5]")
    masses: Numbers = key(what="Link masses [kg].", example="[4.0, 2.0, 0.6]")
    com: Numbers | None = key(
        None,
        what="Centre of mass along each link [m].",
        example="[0.5, 0.4, 0.25]",
        default_text="half the lengths",
    )
    inertia: Numbers | None = key(
        None,
        what="Link inertia about its centre of mass [kg m^2].",
        example="[0.3, 0.1, 0.01]",
        default_text="m l^2 / 12",
    )
    gravity: Number = key(9.81, what="Gravity [m/s^2].", example="9.81")


class PayloadTable(Table):
    """A rigid load attached to the tip frame of a URDF robot."""

    heading: ClassVar[str] = "[robot.payload]"
    example: ClassVar[str] = """[robot]
library = "panda"
payload = { mass = 1.5, com = [0, 0, 0.05], inertia = [[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]] }
[[points]]
name = "ready"
q = [0, -0.5, 0, -2, 0, 1.6, 0.8]"""

    mass: Number = key(what="Mass [kg].", example="1.5")
    com: Vector3 = key(
        (0.0, 0.0, 0.0), what="Centre of mass in the tip frame [m].", example="[0, 0, 0.05]"
    )
    inertia: Matrix3 = key(
        ((0.0,) * 3,) * 3,
        what="Inertia about the com [kg m^2].",
        example="[[1e-3, 0, 0], [0, 1e-3, 0], [0, 0, 1e-3]]",
        default_text="zero",
    )


class TorqueSpeedTable(Table):
    """The torque-speed curves of a robot's joints, for its torque limits in motion.

    Either the linear derating of DC drives (`tau_stall` and `qd_no_load`: the torque a
    joint gives in the direction of motion falls from its stall torque at rest to 0 at
    its no-load speed; the braking torque keeps the rated limit), or tabulated curves
    (`speeds` and `torques`, interpolated linearly; past the last speed the torque is 0
    if the curve ends at 0, else the speed is refused). The rated limits `tau_max`,
    `tau_min` may not exceed the stall torques. See `pe.TorqueSpeed`.
    """

    heading: ClassVar[str] = "[robot.torque_speed]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
qd_max = [3, 3, 5]
qd_min = [-3, -2, -5]
torque_speed = { tau_stall = [150, 40, 6], qd_no_load = [4, 5, 8] }
[[points]]
name = "p"
q = [0.1, 0.2, 0.3]"""

    tau_stall: Numbers | None = key(
        None, what="Linear derating: the stall torque of each joint [N m].", example="[150, 40, 6]"
    )
    qd_no_load: Numbers | None = key(
        None, what="Linear derating: the no-load speed of each joint [rad/s].", example="[4, 5, 8]"
    )
    speeds: NumbersOrRows | None = key(
        None,
        what="Tabulated curves: speeds from 0, increasing [rad/s]; one list for all "
        "joints, or one per joint.",
        example="[0, 2, 4]",
    )
    torques: Rows | None = key(
        None,
        what="Tabulated curves: one row per joint, the torque in the direction of motion "
        "at each speed [N m], not increasing.",
        example="[[150, 120, 0], [40, 30, 0], [6, 5, 0]]",
    )

    @model_validator(mode="after")
    def _one_form(self) -> TorqueSpeedTable:
        linear = self._given(("tau_stall", "qd_no_load"))
        table = self._given(("speeds", "torques"))
        if {len(linear), len(table)} != {0, 2}:  # both keys of one form, none of the other
            raise InputError(
                "",
                "either tau_stall and qd_no_load (linear derating), or speeds and torques "
                "(a table)",
                f"keys {sorted(self.model_fields_set)}",
                "e.g. torque_speed = { tau_stall = [150, 40, 6], qd_no_load = [4, 5, 8] }.",
            )
        if linear and len(self.tau_stall or ()) != len(self.qd_no_load or ()):  # which is wrong?
            raise InputError(
                "",
                "tau_stall and qd_no_load of one length (one of each per joint)",
                f"{len(self.tau_stall or ())} stall torques and "
                f"{len(self.qd_no_load or ())} no-load speeds",
                "give both for every joint of the robot, in joint order.",
            )
        self.build()  # the curves' own checks (shapes, signs, order), naming the key
        return self

    def build(self) -> TorqueSpeed:
        """The :class:`~polyell.TorqueSpeed` the table describes."""
        if self.tau_stall is not None:
            return TorqueSpeed.linear(self.tau_stall, self.qd_no_load)  # type: ignore[arg-type]
        return TorqueSpeed.table(self.speeds, self.torques)  # type: ignore[arg-type]


class RobotTable(Table):
    """A robot: exactly one of `library`, `planar` and `urdf`.

    A robot file is this table at the top level of its own TOML file; a study has one
    `[robot]` or several `[[robots]]`, each of these keys plus a `name`.
    """

    heading: ClassVar[str] = "[robot]"
    example: ClassVar[str] = """[robot]
name = "panda"
library = "panda"
task = "linear"
payload = { mass = 1.0, com = [0, 0, 0.05] }
[[points]]
name = "ready"
q = [0, -0.5, 0, -2, 0, 1.6, 0.8]"""

    name: RobotName | None = key(
        None,
        what="Names the robot in outputs (`panda/home`); required in `[[robots]]`.",
        example='"panda"',
    )
    library: Library | None = key(None, what="A robot of `pe.robots.names()`.", example='"panda"')
    planar: PlanarTable | None = key(None, what="A planar arm: see `[robot.planar]`.")
    urdf: String | None = key(
        None, what="A URDF file, relative to the study file.", example='"arm.urdf"'
    )
    tip: String | None = key(
        None, what="The task frame of a URDF.", example='"tool0"', default_text="required with urdf"
    )
    task: Task | None = key(
        None,
        what='URDF robots: "linear", "angular", "planar" or rows among x y z wx wy wz.',
        example='["x", "z"]',
        default_text='"linear"',
    )
    locked_joints: Strings | None = key(
        None, what="URDF joints held fixed.", example='["j7"]', default_text="[]"
    )
    gravity: Numbers | None = key(
        None,
        what="URDF robots: gravity [m/s^2].",
        example="[0, 0, -9.81]",
        default_text="[0, 0, -9.81]",
    )
    weights: Numbers | None = key(
        None, what="Per task row, to mix linear and angular rows.", example="[1, 1, 0.2]"
    )
    payload: PayloadTable | None = key(
        None, what="A load at the tip: see `[robot.payload]`.", example="{ mass = 1.0 }"
    )
    tau_max: Numbers | None = key(
        None,
        what="Upper torque limits [N m].",
        example="[100, 30, 4]",
        default_text="the robot's own",
    )
    tau_min: Numbers | None = key(
        None, what="Lower torque limits [N m].", example="[-90, -30, -4]", default_text="-tau_max"
    )
    qd_max: Numbers | None = key(
        None,
        what="Upper joint velocity limits [rad/s], above qd_min (positive without it).",
        example="[2, 2, 2.5]",
        default_text="the URDF's velocity limits; none for planar arms",
    )
    qd_min: Numbers | None = key(
        None,
        what="Lower joint velocity limits [rad/s], below qd_max: usually at most 0; above 0 "
        "a joint that must move forward (its velocity set lies away from rest), as "
        '`pe.analyze(..., capacity="velocity", qd_min=...)` takes it.',
        example="[-2, -2, -2.5]",
        default_text="-qd_max",
    )
    torque_speed: TorqueSpeedTable | None = key(
        None,
        what="Torque-speed curves of the joints: see `[robot.torque_speed]`.",
        example="{ tau_stall = [150, 40, 6], qd_no_load = [4, 5, 8] }",
    )

    @model_validator(mode="after")
    def _one_source(self) -> RobotTable:
        sources = self._given(("library", "planar", "urdf"))
        if len(sources) != 1:
            raise InputError(
                "",
                "exactly one of 'library' (a name), 'planar' (a link table), 'urdf' (a file)",
                f"keys {sorted(self.model_fields_set)}",
                f'e.g. library = "chiacchio2000"; names: {robots.names()}.',
            )
        options = self._given(URDF_KEYS)
        if options and (self.planar is not None or self.library == "chiacchio2000"):
            raise InputError("", "no URDF options for a planar arm", f"{options}", "drop them.")
        if self.urdf is not None and self.tip is None:
            raise InputError(
                "", "a 'tip' frame name for a URDF robot", "no tip key", 'add tip = "tool0".'
            )
        return self


class PointTable(Table):
    """Named configurations (postures).

    Each gets its numbers, its scores, its directional limits along each of its
    `directions` and its figures. A named direction is task rows, each with an optional
    sign: "x", "-z", "xy" (the unit diagonal (1, 1, 0)/sqrt 2), "x-y", "-x+z", "wx" on an
    angular task; a vector is a unit vector of the task's size. With several robots each
    point is evaluated on every robot (`panda/home`); give `q` per robot as a table when
    their joint counts differ.
    """

    heading: ClassVar[str] = "[[points]]"
    example: ClassVar[str] = '''[robot]
library = "chiacchio2000"
[[points]]
name = "singular"
title = "Figure 2"
q = ["pi/6", 0, 0]
directions = ["x", "xy", ["-1/2", "sqrt(3)/2"]]
inverse_at = "lo"'''

    name: FileName = key(what="Names files: letters, digits, `_ . -`.", example='"redundant"')
    q: JointAngles = key(
        what="Joint angles [rad]; several robots: `{ panda = [...], ur5 = [...] }`.",
        example='["pi/2", "-pi/2", "-pi/2"]',
    )
    qd: JointAngles | None = key(
        None,
        what="Joint velocities [rad/s] of a URDF robot in motion (accelerations and forces): "
        "the torque limits at qd from its torque-speed curves, and its Coriolis terms. "
        "Several robots: `{ panda = [...] }`, a robot left out is at rest (a planar arm is "
        "modelled at rest: leave it out, or give it zeros).",
        example="[0.5, 0, -1, 0, 0, 0, 0]",
        default_text="at rest",
    )
    directions: Directions | None = key(
        None,
        what="Directions of the reported limits: names of task rows or unit vectors.",
        example='["x", "xy", ["-1/2", "sqrt(3)/2"]]',
        default_text="the task's axes",
    )
    direction: Numbers | None = key(
        None,
        what="One unit direction: the same as `directions = [direction]` (kept for older files).",
        example='["-1/2", "sqrt(3)/2"]',
    )
    inverse_at: Literal["lo", "hi"] = key(
        "hi", what='End of the interval mapped back: "lo" or "hi".', example='"lo"'
    )
    title: Title = key("", what="Figure title.", example='"Figure 1"')

    @model_validator(mode="after")
    def _one_direction_key(self) -> PointTable:
        if self.direction is not None and self.directions is not None:
            raise InputError(
                "",
                "one of 'directions' (a list) and 'direction' (one vector)",
                "both",
                "move the vector into directions and drop direction.",
            )
        if self.direction is not None:
            with _under(".direction"):  # (numbers already: only the norm may be refused)
                _direction(list(self.direction))
        return self


class RangeTable(Table):
    """Evenly spaced values of one joint, ends included."""

    start: Number = key(what="First value [rad].", example='"-pi"')
    stop: Number = key(what="Last value [rad].", example='"pi"')
    num: Count = key(what="How many values.", example="61")


class RandomTable(Table):
    """Seeded uniform configurations within the joint limits.

    With several robots each samples within its own limits.
    """

    heading: ClassVar[str] = "[random]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
[random]
count = 5
seed = 1
low = [-1, -1, -1]
high = [1, 1, 1]"""

    count: Count = key(what="How many.", example="300")
    seed: Seed = key(0, what="Seed of the generator.", example="2000")
    low: Numbers | None = key(
        None,
        what="Lower joint bounds [rad].",
        example="[-1, -1, -1]",
        default_text="the URDF's limits, or -pi",
    )
    high: Numbers | None = key(
        None,
        what="Upper joint bounds [rad].",
        example="[1, 1, 1]",
        default_text="the URDF's limits, or pi",
    )


class TrajectoryTable(Table):
    """A path the user already has.

    CSV, Parquet, .npy or .npz with columns `q1..qn`, optionally `qd1..qdn` (then what
    each capacity allows along the path's tangent, the columns `tangent_<set>_lo` and
    `_hi`) and `t`. One robot only. The sets along the path have the robot's rated
    limits (no torque-speed derating). Without `[compare] horizon` they are those of the
    robot at rest: `qd` gives the tangent only (no Coriolis or centrifugal terms). With
    it, the acceleration sets (scores and tangent limits) are those of each sample's state
    `q`, `qd`: the dynamics in motion (Coriolis and centrifugal torques, `Jdot qd`), within
    the joint limits over the period (a planar arm's dynamics take no velocities: its path
    with `qd` is then refused); the velocity and force sets stay at rest. A `[[points]]`
    entry with `qd` analyzes one configuration in motion, its torque limits derated.
    """

    heading: ClassVar[str] = "[trajectory]"
    example: ClassVar[str] = '''[robot]
library = "chiacchio2000"
[trajectory]
file = "planar3r_path.csv"'''

    file: String = key(what="The file, relative to the study file.", example='"path.csv"')


class PostureTable(Table):
    """Which posture? The choice among a redundant arm's postures by each index.

    The self-motion through `q0` (the postures with its task coordinates,
    `pe.self_motion`) is sampled at `count` postures; every set's indices are computed
    there and the posture each index picks is compared with the truth, the polytope
    (`pe.posture_choice`): `posture_choice.{tex,md,csv}`, `posture_values.csv` and the
    figure `posture_indices`. The criteria: the acceleration (velocity, force) available
    both ways along `direction`, the largest ball about the origin, the volume. With
    `targets`, the same choice at that many seeded random reachable targets, aggregated
    (`pe.posture_choice_over_targets`): `posture_targets.{tex,md,csv}`. Uses the
    ellipsoids of `[compare]` (`mvie`, `outer`, `capacities`: one set of these files per
    capacity, `posture_choice_force.md`, ...) and `[[candidates]]`; one robot.
    """

    heading: ClassVar[str] = "[posture]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
[posture]
q0 = ["pi/2", "-pi/2", "-pi/2"]
components = [["0.2213144423477912", "pi/2", "-pi - 0.2213144423477912"]]
direction = "x"
count = 40
seed = 0
targets = 2
[compare]
mvie = false
outer = false"""

    q0: Numbers = key(
        what="The configuration whose self-motion is sampled [rad]: non-singular, within "
        "the joint limits, one angle per joint.",
        example='["pi/2", "-pi/2", "-pi/2"]',
    )
    direction: Direction = key(
        what='The task direction of the "limit" criterion: a name of task rows or a unit vector.',
        example='"x"',
    )
    count: Annotated[int, Integer(2, MAX_COUNT)] = key(
        200, what=f"Postures sampled, 2 to {MAX_COUNT:,}.", example="200"
    )
    seed: Seed = key(
        0,
        what="Seed of the sampling (a manifold of dimension > 1) and of the targets.",
        example="0",
    )
    targets: Annotated[int, Integer(1, MAX_TARGETS)] | None = key(
        None,
        what="Also aggregate the choice over this many seeded random targets.",
        example="200",
        default_text="the single q0",
    )
    components: list[Numbers] | None = key(
        None,
        what="Further postures with q0's task coordinates, each in another connected "
        "component of the self-motion (a planar arm's other elbow branch): each component "
        "is sampled like q0's (`count` postures) and the choice is over all of them.",
        example='[["0.2213", "pi/2", "-pi - 0.2213"]]',
        default_text="q0's component only",
    )


class CompareTable(Table):
    """How the ellipsoids are scored (`pe.compare`, `pe.sweep`)."""

    heading: ClassVar[str] = "[compare]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
[random]
count = 100
[compare]
directions = 72
mvie = true
outer = false
samples = 4096
seed = 3
chunk = 5000
capacities = ["acceleration", "force"]
horizon = 0.01
braking = 50"""

    directions: Annotated[int, Integer(1, MAX_DIRECTIONS)] | None = key(
        None,
        what="Directions of the directional statistics.",
        example="72",
        default_text="360 in 2-D, 256 in 3-D, 2000 above",
    )
    mvie: bool = key(True, what="Compute the maximum-volume inscribed ellipsoid.", example="true")
    outer: bool = key(True, what="Compute the minimum-volume enclosing ellipsoid.", example="false")
    samples: Annotated[int, Integer(MIN_SAMPLES, MAX_SAMPLES)] = key(
        2**13,
        what="Sampling budget where an ellipsoid leaves the polytope and its parts beyond "
        "two facets meet (else its coverage is exact): samples / 512 heights per pair of "
        "caps and replicate (16 at the default), samples directions where three caps meet; "
        "2 to 4194304 (2^22), in every kind of study.",
        example="4096",
    )
    seed: Seed = key(0, what="Seed of those estimates, 0 or more.", example="3")
    chunk: Annotated[int, Integer(1, 10_000_000)] | None = key(
        None,
        what="Configurations per chunk of a sweep (one Parquet part; a killed study resumes "
        "from the finished ones, and the progress bar moves a chunk at a time). By default "
        "sized by time, as `pe.sweep(chunk=None)`: as many as take about 2 s on this core "
        "(a pilot run on the first rows), at most 20,000. A dataset being resumed keeps the "
        "chunk it was written with. Grid, random and trajectory studies (the others refuse "
        "it).",
        example="5000",
        default_text="about 2 s of work, at most 20000",
    )
    horizon: Horizon | None = key(
        None,
        what="A control period [s]: the acceleration set becomes the accelerations that also "
        "keep every joint within its position limits over the period and within its "
        "velocity limits at its end (`pe.analyze(..., horizon=)`), from the state: a point's "
        "`q` and `qd`, a trajectory's samples (whose `qd` then also gives the dynamics in "
        "motion: Coriolis and centrifugal torques and `Jdot qd`, at the rated torque limits, "
        "not derated; without a horizon a trajectory's sets are at rest, `qd` its tangent "
        "only), every other configuration at rest. The limits are the robot's own (a planar "
        "arm's joints turn freely: velocity limits only). Only the acceleration capacity "
        "takes it (a study without it among its capacities refuses the key); the "
        "ellipsoids ignore these limits, which is what the comparison then measures.",
        example="0.001",
        default_text="none: the sets without joint position and velocity limits",
    )
    braking: Number | None = key(
        None,
        what="With `horizon` (refused without it): the deceleration [rad/s^2] every joint "
        "can still brake with after the period (viability: it can stop before its position "
        "limit).",
        example="50",
        default_text="none",
    )
    capacities: Annotated[tuple[str, ...], Choices(CAPACITIES)] = key(
        ("acceleration",),
        what="The capacities compared, each with its own tables and figures: "
        '"acceleration" (the paper\'s), "velocity" (needs the robot\'s qd_max), '
        '"force", in every kind of study (a posture study chooses by each over the same '
        "postures, a trajectory study draws each one's limits along the path: "
        "tangent_limits_velocity.png, the speeds along it). The acceleration outputs keep "
        "their names; another capacity's carry it (comparison_force.tex, "
        "summary_velocity.tex, results_force/, posture_choice_velocity.md).",
        example='["acceleration", "force", "velocity"]',
        default_text='["acceleration"]',
    )


class CandidateTable(Table):
    """Your own ellipsoids (`pe.Candidate`), scored like the built-in ones.

    Exactly one of `weighting` and `core`. A matrix is a list of rows, or a list of
    numbers (its diagonal).
    """

    heading: ClassVar[str] = "[[candidates]]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
[[points]]
name = "p"
q = [0.1, 0.2, 0.3]
[[candidates]]
name = "heavy_wrist"
weighting = [1, 1, 4]
[[candidates]]
name = "disc"
core = [[1e-3, 0], [0, 2e-3]]
center = [0, -9.81]"""

    name: String = key(what="Lower-case identifier; prefixes its columns.", example='"heavy_wrist"')
    weighting: Matrix | None = key(
        None, what="W of normalized torques: tau_n^T W tau_n <= 1 (n x n).", example="[1, 1, 4]"
    )
    core: Matrix | None = key(
        None,
        what="N of {(x - c)^T N (x - c) <= 1} [(m/s^2)^-2] (m x m).",
        example="[[1e-3, 0], [0, 2e-3]]",
    )
    center: Numbers | None = key(
        None,
        what="Centre c of a core-defined candidate [m/s^2].",
        example="[0, -9.81]",
        default_text="xg",
    )


class OutputTable(Table):
    """What is written besides the tables, and how the tables are laid out.

    `sets` to `text_width` lay out the tables for print (`pe.TableLayout`). A grid,
    random or trajectory study keeps its results in a Parquet dataset, `results/` (one
    part per chunk: a killed study resumes), and reads it back one part at a time, so that
    its memory does not grow with its configurations: `results.csv` is written from the
    parts (`csv`); the summary tables are over every configuration, its count, minimum,
    median and maximum exact and its mean and standard deviation to rounding; a heat map
    of more than 300 values along an axis draws every k-th grid value, and histograms of
    more than 100,000 configurations a seeded random sample of about 100,000 of them (the
    figures say so).
    """

    heading: ClassVar[str] = "[output]"
    example: ClassVar[str] = """[robot]
library = "chiacchio2000"
[grid]
q1 = "pi/2"
q2 = { start = "-pi", stop = "pi", num = 3 }
q3 = { start = "-pi", stop = "pi", num = 3 }
[output]
formats = ["png", "html"]
dpi = 200
maps = ["chiacchio_coverage"]
histograms = ["coverage"]
sets = ["polytope", "chiacchio", "yoshikawa"]
scores = ["coverage", "inscribed_scale"]
digits = 4
percent = false
labels = { chiacchio = "DME", coverage = "share covered" }
captions = { summary = ["Coverage over the grid.", "Coverage over the grid of $q_2$, $q_3$."] }
siunitx = true
text_width = 252
csv = true"""

    formats: Annotated[tuple[str, ...], Choices(FORMATS)] = key(
        ("pdf", "png"),
        what='Among "pdf", "png", "svg", "html" (one interactive report).',
        example='["png", "html"]',
    )
    dpi: Annotated[int, Integer(10, 2400)] = key(
        300, what="Resolution of raster figures.", example="200"
    )
    maps: Strings = key(
        (),
        what="Grid studies with two varying joints: `<ellipsoid>_<score>` heat maps, of any "
        "compared capacity's ellipsoids (`static_coverage` for forces); each capacity draws "
        "those it has (`map_<name>_force.png`).",
        example='["chiacchio_coverage"]',
    )
    histograms: Annotated[tuple[str, ...], Choices(SCORE_NAMES)] = key(
        (), what="Grid and random studies: score histograms.", example='["coverage"]'
    )
    series: Annotated[tuple[str, ...], Choices(SCORE_NAMES)] | None = key(
        None,
        what="Trajectory studies: scores over time.",
        example='["mvie_ratio"]',
        default_text='["coverage", "inscribed_scale"] for a trajectory',
    )
    sets: Strings | None = key(
        None,
        what=f"Sets the tables show, in order: among {', '.join(LAYOUT_SETS)} and candidate names.",
        example='["polytope", "chiacchio", "yoshikawa"]',
        default_text="all",
    )
    scores: Annotated[tuple[str, ...], Choices((*SCORE_NAMES, *LIMIT_QUANTITIES))] | None = key(
        None,
        what="Scores the tables show, in order: score names for the comparison and summary "
        "tables, `lower`, `upper`, `lower_error`, `upper_error` for the limits table; not "
        "in a posture study (its tables show its criteria: it refuses the key).",
        example='["coverage", "inscribed_scale"]',
        default_text="the defaults",
    )
    transpose: bool = key(
        False,
        what="Studies of points: sets as columns (true) or as rows (other studies refuse it).",
        example="true",
    )
    split: Literal["posture", "combined"] = key(
        "combined",
        what='Studies of points: "posture": one table per posture; "combined": one table '
        "(other studies refuse it).",
        example='"posture"',
    )
    digits: Annotated[int, Integer(1, MAX_DIGITS)] = key(
        3, what="Significant digits of the tables.", example="4"
    )
    percent: bool = key(
        True,
        what="Fractions as percentages (true) or fractions; not in a posture study (its "
        "tables show its criteria: it refuses the key).",
        example="false",
    )
    labels: TableLabels | None = key(
        None,
        what="Names of sets and scores in the tables: a table of set names (a candidate's "
        "too) and score names to labels, each plain text or `[plain, latex]`; or a "
        'preset\'s name ("chiacchio2000": the equation numbers of the paper).',
        example='{ chiacchio = "DME", coverage = "share covered" }',
        default_text="one name per set",
    )
    captions: TableCaptions | None = key(
        None,
        what="Captions of the LaTeX tables, by the table's file name: "
        "`comparison` and `limits` (points), `summary` (grid, random, trajectory), "
        "`posture_choice` and `posture_targets` (posture); another capacity's tables by "
        "theirs (`comparison_force`, `summary_velocity`): a table left out keeps its default. "
        "Each is plain text (escaped) or `[plain, latex]` (the LaTeX written as is). A table "
        "split into several floats (one per posture or robot) adds the posture's or "
        "robot's name to each; the Markdown of a points or posture study shows the plain text "
        "as typed (the characters Markdown would read as emphasis, code, maths or a link are "
        "escaped).",
        example='{ limits = "Limits of the Panda.", comparison_force = ["Force scores.", '
        '"Scores of the force ellipsoids, $h$ in N."] }',
        default_text="a default per table, without the study's title",
    )
    siunitx: SiunitxChoice = key(
        False,
        what="Number columns of the LaTeX tables as siunitx `S` columns (the document needs "
        "`\\usepackage{siunitx}`, version 3: it typesets the minus signs and powers of ten "
        "and aligns a column on the decimal marker), or `r` columns (false: no package "
        "beyond booktabs).",
        example="true",
    )
    text_width: TextWidth = key(
        TEXT_WIDTH,
        what="The page's text width [pt] the LaTeX tables are checked against: a wider table "
        "is set in a smaller size, then written with a warning that names its width. 345 "
        "is a one-column `article` at 10 pt; a two-column journal's column is about "
        "240-260; false: no check.",
        example="252",
        default_text=f"{TEXT_WIDTH:g}",
    )
    csv: CsvChoice = key(
        "auto",
        what="Grid, random and trajectory studies: write `results.csv` (every configuration "
        "and score, streamed from the Parquet dataset `results/`): true, false, or "
        f'"auto": only for at most {CSV_AUTO_ROWS:,} configurations (the log and '
        "`manifest.json` say when it is left out).",
        example="true",
    )

    @property
    def layout(self) -> TableLayout:
        """The tables' layout: ``sets`` to ``text_width``, the acceleration tables' captions."""
        return self.layout_of("")

    def layout_of(self, suffix: str = "") -> TableLayout:
        """The layout of the tables whose file names end in ``suffix`` (``"_force"``).

        Their captions are those of ``captions`` whose keys are a table's name with this
        suffix (``comparison_force``), by the table's name (``comparison``).
        """
        captions = None
        if self.captions:
            tables = [table for table in CAPTION_TABLES if f"{table}{suffix}" in self.captions]
            captions = {table: self.captions[f"{table}{suffix}"] for table in tables}
        return TableLayout(
            sets=self.sets,
            scores=self.scores,
            transpose=self.transpose,
            split=self.split,
            digits=self.digits,
            percent=self.percent,
            labels=self.labels,
            captions=captions or None,
            siunitx=self.siunitx,
            text_width=None if self.text_width is False else float(self.text_width),
        )

    def writes_csv(self, configurations: int) -> bool:
        """Whether a study of ``configurations`` writes ``results.csv`` (``csv``)."""
        if self.csv == "auto":
            return configurations <= CSV_AUTO_ROWS
        return bool(self.csv)

    @property
    def figure_formats(self) -> tuple[str, ...]:
        """The static figure formats (all but ``"html"``)."""
        return tuple(f for f in self.formats if f != "html")


def _check_file_names(argument: str, names: list[Any]) -> None:
    """Refuse names whose output files would collide.

    Equal up to case (one file on macOS and Windows), or one another's with a capacity's
    suffix (``p`` and ``p_force``).
    """
    from polyell.capacities import capacity_class

    suffixes = list(dict.fromkeys(["", *(capacity_class(c).output_suffix for c in CAPACITIES)]))
    keys: dict[str, tuple[int, str]] = {}
    for index, name in enumerate(names):
        for suffix in suffixes:
            key = f"{name}{suffix}".casefold()
            if key in keys and keys[key][0] != index:
                other = names[keys[key][0]]
                raise InputError(
                    argument,
                    "names whose output files differ: distinct up to case, none another's "
                    "with a capacity suffix (they name files)",
                    f"{other!r} and {name!r} (both {key!r})",
                    "rename one of them.",
                )
            keys[key] = (index, suffix)


class StudyFile(Table):
    """A study file.

    It holds a robot (`[robot]`) or several (`[[robots]]`), exactly one of `[[points]]`,
    `[grid]`, `[random]`, `[trajectory]` and `[posture]`, and optional comparison,
    candidate and output settings.
    """

    heading: ClassVar[str] = "top level"
    example: ClassVar[str] = """title = "The paper's arm"
[robot]
library = "chiacchio2000"
[[points]]
name = "redundant"
q = ["pi/2", "-pi/2", "-pi/2"]"""

    title: Title | None = key(
        None, what="Heading of every output.", example='"Panda study"', default_text="the file name"
    )
    description: String = key(
        "",
        what="Free text, written under the title of `numbers.md`, `comparison.md` and "
        "`summary.md`, at the top of `report.html` and into `manifest.json`.",
        example='"..."',
    )
    robot: RobotTable | None = key(
        None, what="The robot: see `[robot]`.", default_text="one of robot and robots"
    )
    robots: list[RobotTable] | None = key(
        None, what="Several robots compared side by side: `[robot]` tables with a `name`."
    )
    points: list[PointTable] | None = key(None, what="Named configurations: `[[points]]`.")
    grid: Grid | None = key(
        None,
        what="A grid over the joints: one key per joint, `q1` to `qn`: a fixed value, or a "
        "range `{ start, stop, num }` (all three keys; `num` evenly spaced values, ends "
        "included); several robots need the same joint count.",
        example='{ q1 = "pi/2", q2 = { start = "-pi", stop = "pi", num = 61 } }',
    )
    random: RandomTable | None = key(None, what="Random configurations: `[random]`.")
    trajectory: TrajectoryTable | None = key(None, what="A path from a file: `[trajectory]`.")
    posture: PostureTable | None = key(
        None, what="The choice among a redundant arm's postures: `[posture]`."
    )
    compare: CompareTable = key(factory=CompareTable, what="Comparison settings: `[compare]`.")
    candidates: list[CandidateTable] = key(factory=list, what="Your ellipsoids: `[[candidates]]`.")
    output: OutputTable = key(
        factory=OutputTable, what="Formats, figures, table layout: `[output]`."
    )

    @property
    def series(self) -> tuple[str, ...]:
        """The scores drawn over time: ``[output] series``, for a trajectory by default two."""
        if self.output.series is not None:
            return self.output.series
        return ("coverage", "inscribed_scale") if self.trajectory is not None else ()

    @model_validator(mode="after")
    def _consistent(self) -> StudyFile:
        if (self.robot is None) == (self.robots is None):
            raise InputError(
                "",
                "one [robot] table, or [[robots]] tables (each with a name)",
                "both" if self.robot is not None else "neither",
                'e.g. [robot]\nlibrary = "chiacchio2000"'.replace("\n", " "),
            )
        if self.robots is not None:
            if not self.robots:
                raise InputError(
                    "robots",
                    "at least one [[robots]] table",
                    "none",
                    'add [[robots]] with name = "arm" and library = "chiacchio2000", or use '
                    "one [robot] table.",
                )
            for i, robot in enumerate(self.robots):
                if robot.name is None:
                    raise InputError(
                        f"robots[{i}]",
                        "a 'name' (it labels the robot's outputs)",
                        "no such key",
                        'add name = "panda".',
                    )
            _check_file_names("robots", [robot.name for robot in self.robots])
        kinds = self._given(("points", "grid", "random", "trajectory", "posture"))
        if len(kinds) != 1:
            raise InputError(
                "",
                "exactly one of [[points]], [grid], [random], [trajectory] and [posture]",
                f"keys {sorted(self.model_fields_set)}",
                'add one, e.g. [[points]] with name = "p" and q = [0.1, 0.2, 0.3].'
                if not kinds
                else f"keep one of {kinds} and move the others to their own study files.",
            )
        if self.posture is not None and self.robots is not None and len(self.robots) > 1:
            raise InputError(
                "posture",
                "one robot (q0 is one robot's joint angles)",
                f"{len(self.robots)} [[robots]]",
                "run one posture study per robot.",
            )
        if self.trajectory is not None and self.robots is not None and len(self.robots) > 1:
            raise InputError(
                "trajectory",
                "one robot (a path's columns q1..qn are one robot's joints)",
                f"{len(self.robots)} [[robots]]",
                "run one study per robot, or compare several robots on [[points]], [grid] "
                "or [random].",
            )
        if self.points is not None:
            if not self.points:
                raise InputError(
                    "points",
                    "at least one [[points]] table",
                    "none",
                    'add [[points]] with name = "p" and q = [0.1, 0.2, 0.3] (one angle per joint).',
                )
            _check_file_names("points", [point.name for point in self.points])
        self._check_capacities()
        self._check_output()
        self._check_used_keys()
        return self

    def _kind(self) -> str:
        """The study's kind, as the messages name it."""
        for key_, kind in (
            ("points", "a study of points"),
            ("posture", "a posture study"),
            ("grid", "a grid study"),
            ("random", "a random study"),
        ):
            if getattr(self, key_) is not None:
                return kind
        return "a trajectory study"

    def _check_used_keys(self) -> None:
        """Refuse the keys this study would not use (no key is silently ignored).

        ``[output] split`` and ``transpose`` lay out the tables of a study of points;
        ``scores`` and ``percent`` every kind's but a posture study's (its tables show its
        criteria); ``[compare] chunk`` sizes a sweep (grid, random, trajectory);
        ``horizon`` bounds the acceleration capacity only; ``braking`` goes with ``horizon``.
        """
        output, compare, kind = self.output, self.compare, self._kind()
        given = output.model_fields_set
        for name in ("split", "transpose"):
            if name in given and self.points is None:
                raise InputError(
                    f"output.{name}",
                    "a key of a study of points (it lays out its comparison and limits tables)",
                    f"{kind}, whose tables do not use it",
                    f"drop {name} from [output].",
                )
        for name in ("scores", "percent"):
            if name in given and self.posture is not None:
                raise InputError(
                    f"output.{name}",
                    "a key of a points, grid, random or trajectory study (their "
                    "comparison, limits and summary tables)",
                    "a posture study, whose tables show its criteria, not these scores",
                    f"drop {name} from [output]; [output] sets, digits and labels lay out "
                    "the posture tables.",
                )
        if compare.chunk is not None and (self.points is not None or self.posture is not None):
            raise InputError(
                "compare.chunk",
                "a key of a grid, random or trajectory study (the configurations per part "
                "of its sweep)",
                f"{kind}, which runs no sweep",
                "drop chunk from [compare].",
            )
        if compare.horizon is not None and "acceleration" not in compare.capacities:
            raise InputError(
                "compare.horizon",
                'a study that compares the "acceleration" capacity (only its set takes a horizon)',
                f"capacities = {list(compare.capacities)}",
                'drop horizon, or add "acceleration" to [compare] capacities.',
            )
        if compare.braking is not None and compare.horizon is None:
            raise InputError(
                "compare.braking",
                "a [compare] horizon as well (braking is the deceleration after it)",
                f"braking = {compare.braking} without horizon",
                "add horizon = 0.01 (your control period [s]) to [compare], or drop braking.",
            )

    def _check_capacities(self) -> None:
        capacities = self.compare.capacities
        if len(set(capacities)) != len(capacities) or not capacities:
            raise InputError(
                "compare.capacities",
                "distinct capacity names, at least one",
                f"{list(capacities)}",
                f"list each of {list(CAPACITIES)} at most once, e.g. capacities = "
                '["acceleration", "force"].',
            )

    def _check_output(self) -> None:
        output = self.output
        candidates = [candidate.name for candidate in self.candidates]
        compared = {kind: None for c in self.compare.capacities for kind in compared_kinds(c)}
        kinds = (*compared, *candidates)  # every compared capacity's kinds (force: static)
        valid_maps = [f"{kind}_{score}" for kind in kinds for score in SCORE_NAMES]
        for name in output.maps:
            if name not in valid_maps:
                raise InputError(
                    "output.maps",
                    "names <ellipsoid>_<score>",
                    repr(name),
                    did_you_mean([name], valid_maps)
                    or f"for example 'chiacchio_coverage'; valid: {valid_maps}",
                )
        if output.histograms and (self.points is not None or self.posture is not None):
            raise InputError(
                "output.histograms",
                "a grid or random study",
                self._kind(),
                "drop histograms from [output]: the tables give every score of each "
                + ("point." if self.points is not None else "posture."),
            )
        # A score of an optimum, or a ratio to it, exists only where the optimum is computed.
        computed = {"mvie": self.compare.mvie, "outer": self.compare.outer}
        for field in ("maps", "histograms", "series", "sets", "scores"):
            for name in getattr(output, field) or ():
                for optimum, wanted in computed.items():
                    if not wanted and (
                        name == optimum
                        or name.startswith(f"{optimum}_")
                        or name.endswith(f"{optimum}_ratio")
                    ):
                        raise InputError(
                            f"output.{field}",
                            f"no score of the {_OPTIMA[optimum]} with [compare] {optimum} = false",
                            repr(name),
                            f"set {optimum} = true in [compare], or drop {name!r}.",
                        )
        if output.series and self.trajectory is None:
            raise InputError(
                "output.series",
                "a [trajectory] study",
                self._kind(),
                "drop series from [output] (it draws scores over a trajectory's time).",
            )
        if "csv" in output.model_fields_set and (
            self.points is not None or self.posture is not None
        ):
            raise InputError(
                "output.csv",
                "a grid, random or trajectory study (results.csv holds its configurations)",
                self._kind(),
                "drop csv: a study of points writes scores.csv, a posture study "
                "posture_values.csv.",
            )
        if isinstance(output.labels, Mapping):
            from polyell.comparison.labels import QUANTITIES

            valid = list(dict.fromkeys([*LAYOUT_SETS, *candidates, *SCORE_NAMES, *QUANTITIES]))
            for name in output.labels:
                if name not in valid:
                    raise InputError(
                        f"output.labels.{name}",
                        "a key that names a set (a candidate's too) or a score",
                        repr(name),
                        did_you_mean([name], valid) or f"valid: {valid}.",
                    )
        if output.captions:
            self._check_captions()
        for field in ("sets", "scores"):
            values = getattr(output, field)
            if values is not None and len(set(values)) != len(values):
                raise InputError(
                    f"output.{field}",
                    "distinct names",
                    f"{list(values)}",
                    "list each name once.",
                )
            if values is not None and not values:
                raise InputError(
                    f"output.{field}", "a non-empty list", "[]", "leave the key out for all."
                )
        # each set is some compared capacity's or a candidate, and each capacity's tables
        # show one of its own
        known = ["polytope", *candidates, *(kind for kind in compared if kind not in candidates)]
        unknown = [name for name in output.sets or () if name not in known]
        if unknown:
            raise InputError(
                "output.sets",
                f"sets among {known} (the compared capacities' ellipsoids and the candidates)",
                repr(unknown),
                did_you_mean(unknown, known)
                or "check the spelling, or add the capacity to [compare] capacities.",
            )
        for capacity in self.compare.capacities if output.sets else ():
            own = [*compared_kinds(capacity), *candidates]
            if not any(name in own for name in output.sets or ()):
                raise InputError(
                    "output.sets",
                    f"at least one set of each compared capacity (the {capacity} capacity's "
                    f"are {list(compared_kinds(capacity))})",
                    repr(list(output.sets or ())),
                    f"add one of them, or leave {capacity!r} out of [compare] capacities.",
                )

    def _check_captions(self) -> None:
        """Each caption names a table this study writes (its kind and its capacities)."""
        from polyell.capacities import capacity_class

        if self.points is not None:
            kind, tables = "a study of points", ["comparison", "limits"]
        elif self.posture is not None:
            kind, tables = "a posture study", ["posture_choice"]
            if self.posture.targets is not None:
                tables.append("posture_targets")
        else:
            kind, tables = "a grid, random or trajectory study", ["summary"]
        suffixes = [capacity_class(c).output_suffix for c in self.compare.capacities]
        written = [f"{table}{suffix}" for suffix in suffixes for table in tables]
        for name in self.output.captions or ():
            if name not in written:
                raise InputError(
                    f"output.captions.{name}",
                    f"a table that {kind} with [compare] capacities = "
                    f"{list(self.compare.capacities)} writes: one of {written}",
                    repr(name),
                    did_you_mean([name], written)
                    or f"drop it, or give the caption of one of {written}.",
                )


#: The optima a study computes on request, by their [compare] key.
_OPTIMA = {"mvie": "MVIE", "outer": "outer ellipsoid"}


#: The tables of the format, in the order of the reference page.
TABLES: dict[str, type[Table]] = {
    "top": StudyFile,
    "robot": RobotTable,
    "planar": PlanarTable,
    "payload": PayloadTable,
    "torque_speed": TorqueSpeedTable,
    "points": PointTable,
    "random": RandomTable,
    "trajectory": TrajectoryTable,
    "posture": PostureTable,
    "compare": CompareTable,
    "candidates": CandidateTable,
    "output": OutputTable,
}


# ---------------------------------------------------------------------------------------
# Parsing: pydantic's errors as the package's own


def _join(path: str, argument: str) -> str:
    """A relative argument (``""``, ``"[0]"``, ``".q"``, or a key) appended to ``path``."""
    if not argument:
        return path
    if argument[0] in "[.":
        return path + argument
    return f"{path}.{argument}"


def _tables() -> dict[str, type[Table]]:
    """Every table model by its class name (a ValidationError's ``title``)."""
    found: dict[str, type[Table]] = {}
    pending: list[type[Table]] = [Table]
    while pending:
        model = pending.pop()
        found[model.__name__] = model
        pending.extend(model.__subclasses__())
    return found


def _table_in(annotation: Any) -> type[Table] | None:
    """The table model within a field's annotation (``list[PointTable] | None``), if any."""
    if isinstance(annotation, type) and issubclass(annotation, Table):
        return annotation
    for arg in get_args(annotation):
        model = _table_in(arg)
        if model is not None:
            return model
    return None


def _field_at(model: type[Table] | None, loc: Sequence[int | str]) -> tuple[str, Any] | None:
    """The key and field where a validation error's location ends, if it names a key."""
    found = None
    for step in loc:
        if isinstance(step, int):  # an item of a list of tables
            continue
        if model is None or step not in model.model_fields:
            return None
        found = (step, model.model_fields[step])
        model = _table_in(found[1].annotation)
    return found


def _example(field: Any) -> str:
    """The TOML example of a key's value (the reference page's), ``""`` without one."""
    extra = field.json_schema_extra
    return str(extra.get("x-example") or "") if isinstance(extra, dict) else ""


def _list_of(field: Any) -> str:
    """What a list key that is not a list of tables holds (``posture.components``)."""
    for annotation in (field.annotation, *get_args(field.annotation)):
        if get_origin(annotation) is list and get_args(annotation):
            return f"a list, each item a {phrase(get_args(annotation)[0])}"
    return "a list"


def _type_fix(kind: str, name: str, field: Any, example: str, path: str) -> str:
    """How to write a key's value that pydantic refused as of the wrong type ``kind``."""
    inner = None if field is None else _table_in(field.annotation)
    if kind == "bool_type":
        return f"write true or false without quotes, e.g. {name} = true."
    if kind == "string_type":
        quoted = example or '"..."'
        return f"put the text in double quotes, e.g. {name} = {quoted}."
    if kind == "list_type" and inner is not None:
        return f"write each entry as a [[{path}]] table with its keys below it."
    if kind in ("model_type", "dict_type") and inner is not None:
        return f"write a [{path}] table with its keys below it."
    if kind == "literal_error":
        valid = [] if field is None else list(get_args(field.annotation))
        if valid:
            return f'use one of them in double quotes, e.g. {name} = "{valid[0]}".'
    if example:
        return f"e.g. {name} = {example}."
    return f"write {name} as the reference page docs/study_format.md shows."


def as_input_error(error: ValidationError, root: str = "") -> InputError:
    """The first error of a validation as an InputError naming the key's path.

    ``root`` names the file for errors of its top level; ``""`` leaves the argument
    relative (``".num"``), for a caller that prefixes its own path.  Every error has a
    fix: the cause's own, else one from the key's type and the reference page's example.
    """
    first = error.errors(include_url=False)[0]
    path = "".join(f"[{step}]" if isinstance(step, int) else f".{step}" for step in first["loc"])
    field = _field_at(_tables().get(error.title), first["loc"])
    name = field[0] if field is not None else (path.lstrip(".").rsplit(".", 1)[-1] or "value")
    example = "" if field is None else _example(field[1])
    where = re.sub(r"\[[0-9]+\]", "", path.lstrip(".")) or name
    cause = first.get("ctx", {}).get("error")
    kind = ""  # pydantic's type of error (``bool_type``); "" for a value type's own
    if isinstance(cause, InputError):
        argument = _join(path, cause.argument)
        expected, got, fix = cause.expected, cause.got, cause.fix
    else:
        kind = first["type"]
        listed = field is not None and _table_in(field[1].annotation) is not None
        expected = {
            "bool_type": "true or false",
            "string_type": "a string",
            "list_type": "a list of tables" if listed or field is None else _list_of(field[1]),
            "model_type": "a table",
            "dict_type": "a table",
            "literal_error": str(first.get("ctx", {}).get("expected", "")),
        }.get(kind, first["msg"])
        argument, got, fix = path, _describe(first["input"]), ""
        if kind == "literal_error" and isinstance(first["input"], str):
            valid = re.findall(r"'([^']*)'", expected)
            fix = did_you_mean([first["input"]], valid)
    if not fix:
        fix = _type_fix(kind, name, None if field is None else field[1], example, where)
    if root:
        argument = argument.lstrip(".") or root
    return InputError(argument, expected, got, fix)


def validate(model: type[Table], data: object, root: str = "") -> Any:
    """``model`` validated from ``data``; any failure is one InputError (:func:`as_input_error`)."""
    try:
        return model.model_validate(data)
    except ValidationError as error:
        raise as_input_error(error, root) from None
    except RecursionError:  # nesting deeper than the validators follow
        raise InputError(
            root or "",
            "values nested at most a few levels",
            "nesting too deep to follow",
            "write the values as the reference (docs/study_format.md) shows: lists of "
            "numbers, or of rows of numbers.",
        ) from None


def parse_study(table: dict[str, Any], file_name: str) -> StudyFile:
    """A study file's table, validated (errors name the key, or ``file_name`` at the top)."""
    study: StudyFile = validate(StudyFile, table, file_name)
    return study


def parse_robot(table: object, where: str) -> RobotTable:
    """A robot file's table (or a study's ``[robot]``), validated; errors start with ``where``."""
    try:
        return RobotTable.model_validate(table)
    except ValidationError as error:
        relative = as_input_error(error)
        raise InputError(
            _join(where, relative.argument), relative.expected, relative.got, relative.fix
        ) from None


# ---------------------------------------------------------------------------------------
# The reference page and the JSON Schemas, from the models


def phrase(annotation: Any, metadata: Sequence[Any] = ()) -> str:
    """The reference page's name of a value's type, from its annotation."""
    for item in metadata:
        if isinstance(item, Check):
            return item.phrase
    origin = get_origin(annotation)
    if origin is Annotated:
        return phrase(get_args(annotation)[0], get_args(annotation)[1:])
    if origin in (Union, types.UnionType):
        return " or ".join(phrase(arg) for arg in get_args(annotation) if arg is not type(None))
    if origin is list:
        item = get_args(annotation)[0]
        inner = get_args(item)[0] if get_origin(item) is Annotated else item
        if isinstance(inner, type) and issubclass(inner, BaseModel):
            return "array of tables"
        return f"array, each item a {phrase(item)}"
    if origin is Literal:
        return "string"
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "table"
    return {bool: "boolean", str: "string", int: "integer", float: "number"}[annotation]


def keys(table: str) -> tuple[str, ...]:
    """The valid keys of a table (what the parser accepts)."""
    return tuple(TABLES[table].model_fields)


def _toml(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml(item) for item in value) + "]"
    return repr(value)


def _default(field: Any) -> str:
    extra = field.json_schema_extra
    if "x-default" in extra:
        return str(extra["x-default"])
    if field.is_required():
        return "required"
    return _toml(field.default)


def reference_page() -> str:
    """The Markdown reference page of the format (``docs/study_format.md``)."""
    lines = [
        "# Study and robot files",
        "",
        "<!-- Generated by `python docs/study_format.py` from the models the parser validates"
        " with (polyell/studies/models.py); the tests keep it current. -->",
        "",
        "A study is a TOML file run by `polyell study FILE --out DIR` (or",
        "`pe.studies.run_study(pe.studies.load_study(FILE), DIR)`). Numbers may be",
        'expressions of numbers, `pi`, `sqrt()` and `+ - * / **` written as strings (`"-pi/2"`).',
        "Unknown keys are refused with the list of valid ones (and the closest, if it is a",
        "misspelling); every message names the key's path, e.g. `points[2].directions[0]`.",
        "The same models give JSON Schemas for editors that check TOML (e.g. Even Better TOML,",
        "with `#:schema ./study.schema.json` as the first line): `docs/study.schema.json` and",
        "`docs/robot.schema.json`.",
        "",
    ]
    for model in TABLES.values():
        description = " ".join((model.__doc__ or "").split())
        lines += [f"## {model.heading}", "", description, ""]
        lines += ["| key | type | default | meaning | example |", "|---|---|---|---|---|"]
        for name, field in model.model_fields.items():
            example = _example(field)
            kind = phrase(field.annotation, field.metadata)
            cells = [f"`{name}`", kind, _default(field), str(field.description)]
            cells.append(f"`{example}`" if example else "")
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines += ["", "```toml", model.example, "```", ""]
    return "\n".join(lines)


def _clean(schema: Any, properties: bool = False) -> Any:
    """Pydantic's schema without titles, with the TOML examples as JSON values."""
    if isinstance(schema, list):
        return [_clean(item) for item in schema]
    if not isinstance(schema, dict):
        return schema
    if properties:  # a map of key names to schemas: keep every name
        return {name: _clean(value) for name, value in schema.items()}
    options = schema.get("anyOf")
    if isinstance(options, list) and {"type": "null"} in options:  # TOML has no null
        rest = [option for option in options if option != {"type": "null"}]
        schema = {key: value for key, value in schema.items() if key != "anyOf"}
        schema = {**rest[0], **schema} if len(rest) == 1 else {"anyOf": rest, **schema}
    cleaned: dict[str, Any] = {}
    for name, value in schema.items():
        if name in ("title", "x-default") or (name == "default" and value is None):
            continue
        if name == "description" and isinstance(value, str):
            cleaned[name] = " ".join(value.split())
            continue
        if name == "x-example":
            if value:
                cleaned["examples"] = [tomllib.loads(f"v = {value}")["v"]]
            continue
        cleaned[name] = _clean(
            value, properties=name in ("properties", "$defs", "patternProperties")
        )
    return cleaned


def json_schema(kind: str = "study") -> dict[str, Any]:
    """A JSON Schema (draft 2020-12) of study files (``"study"``) or robot files (``"robot"``).

    For editors that check TOML against a schema (e.g. Even Better TOML, with
    ``#:schema ./study.schema.json`` on the first line); the parser's checks go further
    (values, sizes, names, what needs the robot).
    """
    model = StudyFile if kind == "study" else RobotTable
    title = "polyell study file" if kind == "study" else "polyell robot file"
    schema = _clean(model.model_json_schema())
    schema.pop("description", None)
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": title,
        "description": " ".join((model.__doc__ or "").split()),
        **schema,
    }
