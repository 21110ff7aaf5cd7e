"""A typed parameter (:class:`ParamSpec`): its type, range or choices, default and parsing.

A spec turns a value given as text (a command line, a sweep's ``--param``, a CSV cell) or
already typed (a YAML scenario, a Python call) into the typed value, or raises
:class:`ParamError` naming the parameter, the valid range or choices, and what it got (cut to
:data:`pil.errors.QUOTE_LIMIT` characters). The registries of specs are :mod:`pil.task.params`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

from pil.errors import RobinPilError, quote
from pil.numbers import is_decimal_text, is_whole_text
from pil.task.detector import (
    CAMERAS,
    MEASURED_PREFIX,
    NO_CAMERAS,
    DetectorError,
    check_confusion,
    load_measured,
)

MAX_TEXT = 4096  # longest text a matrix value may be given as
_TRUE, _FALSE = ("true", "yes", "1", "on"), ("false", "no", "0", "off")
_KINDS = ("int", "float", "bool", "choice", "matrix", "text", "auto", "detector")


class ParamError(RobinPilError):
    """A parameter or option value of the wrong type or outside its valid range."""


@dataclass(frozen=True, slots=True)
class ParamSpec:
    """One parameter: ``kind`` (int, float, bool, choice, matrix), its range or choices.

    ``optional``: None is a valid value (e.g. "the scenario file's"); ``low`` / ``high``
    bound numbers (inclusive; ``low`` excluded when ``low_open``); ``choices`` lists a
    choice's valid names.
    """

    name: str
    kind: str
    default: Any
    doc: str
    low: float | None = None
    high: float | None = None
    choices: tuple[str, ...] = ()
    optional: bool = False
    empty: str = "the scenario's"  # what None (an empty value) means for an optional spec
    low_open: bool = False  # ``low`` itself is not valid: (low, high]
    why_low: str = ""  # said when a value at or below ``low`` is refused
    # the smallest positive value (a float spec with ``low`` 0): below it is refused as 0 is,
    # with ``why_low``; e.g. a detection rate of 1e-320 would read no gesture either
    smallest: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"ParamSpec {self.name}: unknown kind {self.kind!r}")

    def valid(self) -> str:
        """What a valid value is, in words (used in every error message)."""
        if self.kind == "choice":
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind == "detector":
            return (
                "one of "
                + ", ".join(repr(c) for c in self.choices)
                + f" or '{MEASURED_PREFIX}FILE'"
            )
        if self.kind == "bool":
            return "true or false"
        if self.kind == "text":
            return f"text of at most {MAX_TEXT} characters"
        if self.kind == "auto":
            return "a number or text"
        if self.kind == "matrix":
            return "a 4x4 confusion matrix: rows 'a b c d; e f g h; ...' or [[a, b, c, d], ...]"
        noun = "a whole number" if self.kind == "int" else "a number"
        low, high = _show(self.low), _show(self.high)
        if self.low is not None and self.high is not None:
            if self.kind == "int":
                return f"{noun} from {low} to {high}"
            return f"{noun} in {'(' if self.low_open else '['}{low}, {high}]"
        if self.low is not None:
            return f"{noun} >= {low}"
        return noun

    def required(self) -> ParamSpec:
        """This spec with None refused (e.g. for a scenario file, where a value must be set)."""
        return replace(self, optional=False)

    def parse(self, value: Any, label: str | None = None) -> Any:
        """``value`` (text or typed) as this parameter's typed value, or :class:`ParamError`.

        ``label`` names the value in the message (default ``parameter 'NAME'``).
        """
        if value is None or (self.optional and isinstance(value, str) and not value.strip()):
            if self.optional or self.default is None:
                return None
            self._fail(value, label)
        try:
            converted = _CONVERT[self.kind](self, value)
        except _InvalidValueError as problem:
            self._fail(value, label, str(problem))
        if converted is _BAD:
            self._fail(value, label, self._why_bad(value))
        return converted

    def _why_bad(self, value: Any) -> str:
        """:attr:`why_low` when ``value`` is the excluded lower bound itself, else nothing."""
        if not (self.low_open and self.why_low) or isinstance(value, bool):
            return ""
        try:
            return self.why_low if float(value) == self.low else ""
        except (TypeError, ValueError, OverflowError):
            return ""

    def _fail(self, value: Any, label: str | None, reason: str = "") -> None:
        where = label or f"parameter {self.name!r}"
        extra = f" (or empty: {self.empty})" if self.optional else ""
        why = f" ({reason})" if reason else ""
        raise ParamError(f"{where} must be {self.valid()}{extra}, got {quote(value)}{why}")


_BAD = object()


class _InvalidValueError(Exception):
    """Raised by a converter that can say why a value is wrong."""


def _in_range(spec: ParamSpec, number: float) -> bool:
    above = spec.low is None or (number > spec.low if spec.low_open else number >= spec.low)
    return above and (spec.high is None or number <= spec.high)


def _to_int(spec: ParamSpec, value: Any) -> Any:
    if isinstance(value, bool):
        return _BAD
    if isinstance(value, str):
        text = value.strip()
        if is_whole_text(text):
            number = int(text)
        elif is_decimal_text(text) and float(text).is_integer():  # "10.0", "1e3"
            number = int(float(text))
        else:  # "1_0", other scripts' digits, "inf": not a number the user typed
            return _BAD
    elif isinstance(value, int) or (
        isinstance(value, float) and math.isfinite(value) and value.is_integer()
    ):
        number = int(value)
    else:
        item = getattr(value, "item", None)  # numpy integers
        return _to_int(spec, item()) if callable(item) else _BAD
    return number if _in_range(spec, number) else _BAD


def _to_float(spec: ParamSpec, value: Any) -> Any:
    if isinstance(value, bool):
        return _BAD
    if isinstance(value, str) and not is_decimal_text(value):
        return _BAD  # "1_0", other scripts' digits, "nan", "inf": not a number the user typed
    try:
        number = float(value)
    except (TypeError, ValueError):
        return _BAD
    if spec.smallest is not None and 0 < number < spec.smallest:
        why = f" as 0 is: {spec.why_low}" if spec.why_low else ""
        raise _InvalidValueError(
            f"the smallest positive value is {spec.smallest:g}; less is refused{why}"
        )
    return number if math.isfinite(number) and _in_range(spec, number) else _BAD


def _to_bool(spec: ParamSpec, value: Any) -> Any:
    if isinstance(value, bool):
        return value
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    if isinstance(value, str):
        text = value.strip().lower()
        if text in _TRUE or text in _FALSE:
            return text in _TRUE
    return _BAD


def _to_choice(spec: ParamSpec, value: Any) -> Any:
    return value.strip() if isinstance(value, str) and value.strip() in spec.choices else _BAD


def _to_matrix(spec: ParamSpec, value: Any) -> Any:
    rows: Any = value
    if isinstance(value, str):
        text = value.strip()
        if len(text) > MAX_TEXT:
            return _BAD
        if text.startswith("["):
            if text.count("[") > 5:  # deeper than a 4x4 matrix: refuse before parsing
                return _BAD
            try:
                rows = json.loads(text)
            except ValueError:
                return _BAD
        else:
            rows = [row.split() for row in text.split(";")]
    if not isinstance(rows, Sequence) or isinstance(rows, str):
        return _BAD
    try:
        return [list(row) for row in check_confusion(rows)]
    except DetectorError as error:
        raise _InvalidValueError(str(error)) from None


def _to_text(spec: ParamSpec, value: Any) -> Any:
    return value if isinstance(value, str) and 0 < len(value) <= MAX_TEXT else _BAD


def _to_auto(spec: ParamSpec, value: Any) -> Any:
    """A value of unknown type: text becomes an int, else a float, else stays text."""
    if not isinstance(value, str):
        return value
    for kind in (_to_int, _to_float, _to_text):
        converted = kind(spec, value)
        if converted is not _BAD:
            return converted
    return _BAD


def _to_detector(spec: ParamSpec, value: Any) -> Any:
    if not isinstance(value, str):
        return _BAD
    text = value.strip()
    if text == CAMERAS and text not in spec.choices:
        raise _InvalidValueError(NO_CAMERAS)
    if text in spec.choices:
        return text
    if text.startswith(MEASURED_PREFIX) and text[len(MEASURED_PREFIX) :]:
        load_measured(text[len(MEASURED_PREFIX) :])  # a missing or broken file: refused now
        return text
    return _BAD


_CONVERT = {
    "detector": _to_detector,
    "int": _to_int,
    "float": _to_float,
    "bool": _to_bool,
    "choice": _to_choice,
    "matrix": _to_matrix,
    "text": _to_text,
    "auto": _to_auto,
}


def spec_for(name: str, default: Any, doc: str = "") -> ParamSpec:
    """A spec for a parameter known only by its default (e.g. a custom run function's)."""
    if isinstance(default, ParamSpec):
        return default
    if isinstance(default, bool):
        return ParamSpec(name, "bool", default, doc)
    if isinstance(default, int):
        return ParamSpec(name, "int", default, doc)
    if isinstance(default, float):
        return ParamSpec(name, "float", default, doc)
    if isinstance(default, str):
        return ParamSpec(name, "text", default, doc)
    return ParamSpec(name, "auto", default, doc, optional=default is None, empty="the default")


def _show(number: float | None) -> str:
    if number is None:
        return ""
    return str(int(number)) if float(number).is_integer() else repr(number)
