"""Typed parameter specs: the one place that knows each option's type, range and default.

A :class:`ParamSpec` turns a value given as text (a command line, a sweep's ``--param``, a CSV
cell) or already typed (a YAML scenario, a Python call) into the typed value, or raises
:class:`ParamError` naming the parameter, the valid range or choices, and what it got (cut to
:data:`pil.errors.QUOTE_LIMIT` characters). The run parameters (:data:`PARAMS`), the scenario file's
assembly keys, the sweep grid and the CLI options all validate through these specs::

    PARAMS["discard"].parse("0.3")        # 0.3
    PARAMS["discard"].parse("1.5")        # ParamError: parameter 'discard' must be a number
                                          #   in [0, 1], got '1.5'
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from pil.anticipation import DEFAULT_MIN_COUNT, DEFAULT_THRESHOLD
from pil.errors import InvalidChoiceError, RobinPilError, quote
from pil.exploration import DEFAULT_RULE, RULES
from pil.learner import ADAPTATIONS
from pil.task.detector import (
    CAMERAS,
    DEFAULT_DISCARD,
    MEASURED_PREFIX,
    MODELS,
    NO_CAMERAS,
    DetectorError,
    check_confusion,
)
from pil.task.watching import DEFAULT_REACTION_MEAN, DEFAULT_REACTION_SPREAD

MAX_TABLES = 1000  # tables of one run: 4000 handovers, a few seconds learner-only
MAX_LEGS = 12  # legs of one table (and table spots)
MAX_COUNT = 1000  # patience, actions per gesture
MAX_SEED = 2**63 - 1
MAX_TEXT = 4096  # longest text a matrix value may be given as
DRAWS: tuple[str, ...] = ("balanced", "cycle", "random")
_TRUE, _FALSE = ("true", "yes", "1", "on"), ("false", "no", "0", "off")
_KINDS = ("int", "float", "bool", "choice", "matrix", "text", "auto", "detector")


class ParamError(RobinPilError):
    """A parameter or option value of the wrong type or outside its valid range."""


@dataclass(frozen=True, slots=True)
class ParamSpec:
    """One parameter: ``kind`` (int, float, bool, choice, matrix), its range or choices.

    ``optional``: None is a valid value (e.g. "the scenario file's"); ``low`` / ``high``
    bound numbers (inclusive); ``choices`` lists a choice's valid names.
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
            return (
                f"{noun} from {low} to {high}"
                if self.kind == "int"
                else f"{noun} in [{low}, {high}]"
            )
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
            self._fail(value, label)
        return converted

    def _fail(self, value: Any, label: str | None, reason: str = "") -> None:
        where = label or f"parameter {self.name!r}"
        extra = f" (or empty: {self.empty})" if self.optional else ""
        why = f" ({reason})" if reason else ""
        raise ParamError(f"{where} must be {self.valid()}{extra}, got {quote(value)}{why}")


_BAD = object()


class _InvalidValueError(Exception):
    """Raised by a converter that can say why a value is wrong."""


def _in_range(spec: ParamSpec, number: float) -> bool:
    return (spec.low is None or number >= spec.low) and (spec.high is None or number <= spec.high)


def _to_int(spec: ParamSpec, value: Any) -> Any:
    if isinstance(value, bool):
        return _BAD
    if isinstance(value, str):
        text = value.strip()
        if len(text) > 40:
            return _BAD
        try:
            number = int(text)
        except ValueError:
            try:
                real = float(text)
            except ValueError:
                return _BAD
            if not math.isfinite(real) or not real.is_integer():
                return _BAD
            number = int(real)
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
    if isinstance(value, str) and len(value) > 40:
        return _BAD
    try:
        number = float(value)
    except (TypeError, ValueError):
        return _BAD
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
    if text in spec.choices or (text.startswith(MEASURED_PREFIX) and text[len(MEASURED_PREFIX) :]):
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


def _specs(*specs: ParamSpec) -> dict[str, ParamSpec]:
    return {spec.name: spec for spec in specs}


# The assembly's own settings: None (the default) keeps the scenario file's value; the
# scenario file's keys are checked by the same specs, with ASSEMBLY_DEFAULTS for missing keys.
ASSEMBLY: dict[str, ParamSpec] = _specs(
    ParamSpec("tables", "int", None, "test tables", 1, MAX_TABLES, optional=True),
    ParamSpec("legs_per_table", "int", None, "legs of each table", 1, MAX_LEGS, optional=True),
    ParamSpec(
        "training_tables", "int", None, "pre-training tables (c1-c4)", 0, MAX_TABLES, optional=True
    ),
    ParamSpec("draw", "choice", None, "order of the handover types", choices=DRAWS, optional=True),
    ParamSpec("spots", "int", None, "table spots for 'location'", 1, MAX_LEGS, optional=True),
)
ASSEMBLY_DEFAULTS: dict[str, Any] = {
    "tables": 10,
    "legs_per_table": 4,
    "training_tables": 5,
    "draw": "balanced",
    "spots": 4,
}
PARAMS: dict[str, ParamSpec] = {
    **ASSEMBLY,
    **_specs(
        ParamSpec("detector", "detector", "exact", "detection model", choices=MODELS),
        ParamSpec("discard", "float", DEFAULT_DISCARD, "share of misses discarded", 0.0, 1.0),
        ParamSpec(
            "confusion",
            "matrix",
            None,
            "how a miss of each gesture is misread",
            optional=True,
            empty="uniform",
        ),
        ParamSpec("repeat_discarded", "bool", True, "ask for a repeat of a discarded gesture"),
        ParamSpec("silent_ok", "float", 0.0, "chance of approving by saying nothing", 0.0, 1.0),
        ParamSpec("patience", "int", 0, "rejections before a repeat (0: off)", 0, MAX_COUNT),
        ParamSpec("max_actions_per_gesture", "int", 100, "actions before giving up", 1, MAX_COUNT),
        ParamSpec(
            "reaction_time",
            "float",
            DEFAULT_REACTION_MEAN,
            "s, the person's mean reaction to an unwanted action",
            0.0,
            10.0,
        ),
        ParamSpec(
            "reaction_spread",
            "float",
            DEFAULT_REACTION_SPREAD,
            "s, standard deviation of the reaction time",
            0.0,
            5.0,
        ),
        ParamSpec(
            "handover_timeout",
            "float",
            180.0,
            "s from a handover's first gesture (physical episodes)",
            1.0,
            1e6,
        ),
        ParamSpec(
            "exploration",
            "choice",
            DEFAULT_RULE,
            "the learner's rule after a not-OK",
            choices=tuple(RULES),
        ),
        ParamSpec(
            "adaptation",
            "choice",
            "none",
            "how a not-OK changes counts",
            choices=tuple(ADAPTATIONS),
        ),
        ParamSpec("proactive", "bool", False, "act on the likely next state before its gesture"),
        ParamSpec(
            "proactive_threshold",
            "float",
            DEFAULT_THRESHOLD,
            "P(next state | state) needed to act unasked",
            0.0,
            1.0,
        ),
        ParamSpec(
            "proactive_min_count",
            "int",
            DEFAULT_MIN_COUNT,
            "transitions seen before that share counts",
            1,
            MAX_COUNT,
        ),
        ParamSpec("epsilon", "float", 0.1, "the bandit baseline's exploration rate", 0.0, 1.0),
        ParamSpec("step_size", "float", 0.5, "the TAMER baseline's regression step", 0.0, 10.0),
    ),
}
SCENARIO = ParamSpec(
    "scenario",
    "text",
    None,
    "an assembly YAML or a shipped scenario's name",
    optional=True,
    empty="scenarios/assembly.yaml",
)
RUN_OPTIONS: dict[str, ParamSpec] = {"scenario": SCENARIO}  # run_one's keyword besides PARAMS
RATE = ParamSpec("rate", "float", 1.0, "gesture detection rate", 0.0, 1.0)
SEED = ParamSpec("seed", "int", 0, "seed of every random choice", 0, MAX_SEED)
REPS = ParamSpec("reps", "int", 20, "repetitions", 1, 100_000)


def parse_all(
    specs: Mapping[str, ParamSpec], values: Mapping[str, Any], what: str = "parameter"
) -> dict[str, Any]:
    """Every spec's value: ``values`` parsed, defaults for the others; unknown names raise."""
    for name in values:
        if name not in specs:
            raise InvalidChoiceError(what, name, specs)
    return {
        name: spec.parse(values[name]) if name in values else spec.default
        for name, spec in specs.items()
    }
