"""What a line of a benchmark journal (``runs.jsonl``) must hold, checked field by field.

A row is read back from a file a user can edit, damage or replace, and everything the results
compute is taken from it: :func:`row_problem` says what is wrong with a parsed line (an unknown
or missing field, a value of the wrong type, a track or condition the suite does not have), or
"" when it is a run's row. The fields are those :func:`pil.bench.tracks.run_track` (and the
physical track's runner) write, with :mod:`pil.bench.run`'s key and parameters; a metric of a
failed run is ``null``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

from pil.bench.suite import Suite
from pil.errors import quote


def _whole(value: Any) -> bool:
    return type(value) is int and value >= 0


def _signed(value: Any) -> bool:
    return type(value) is int


def _share(value: Any) -> bool:
    return type(value) in (int, float) and math.isfinite(value) and value >= 0


def _text(value: Any) -> bool:
    return isinstance(value, str)


def _name(value: Any) -> bool:
    return isinstance(value, str) and bool(value.strip()) and value.isprintable()


def _flag(value: Any) -> bool:
    return type(value) is bool


def _curve(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(_whole(v) for v in value)


# field -> (its check, what it must be, when it may be null: never, for a failed run, always)
NEVER, IF_FAILED, ALWAYS = "never", "for a failed run", "always"
Check = tuple[Callable[[Any], bool], str, str]
_WHOLE_COUNT: Check = (_whole, "a whole number >= 0", IF_FAILED)
ROW_FIELDS: dict[str, Check] = {
    "track": (_name, "a track of the suite", NEVER),
    "condition": (_name, "a condition of the track", NEVER),
    "agent": (_name, "an agent's name", NEVER),
    "seed": (_whole, "a whole number >= 0", NEVER),
    "params": (_text, "the parameters as JSON text", NEVER),
    "actions": _WHOLE_COUNT,
    "gestures": _WHOLE_COUNT,
    "rejected": _WHOLE_COUNT,
    "first_actions": _WHOLE_COUNT,
    "scratch_actions": _WHOLE_COUNT,
    "savings": (_signed, "a whole number", IF_FAILED),
    "curve": (_curve, "a list of whole numbers >= 0, one per table", NEVER),
    "curve_area": (_share, "a finite number >= 0", IF_FAILED),
    "recovery": (_share, "a finite number >= 0", ALWAYS),
    "sim_time_s": (_share, "a finite number >= 0", ALWAYS),
    "failed": (_text, "text (empty: the run finished)", NEVER),
    "stalled": (_flag, "true or false", NEVER),
    "longest_wait": (_whole, "a whole number >= 0", NEVER),
    "scripted": (lambda v: _whole(v) and v >= 1, "a whole number >= 1", NEVER),
}
ROW_REQUIRED = (
    *("track", "condition", "agent", "seed", "params"),
    *("actions", "gestures", "curve", "curve_area", "failed", "scripted"),
)


def row_problem(row: Any, suite: Suite) -> str:
    """What is wrong with ``row`` as a run's row ("" if nothing)."""
    if not isinstance(row, Mapping):
        return f"expected a run's row (a JSON object), got {type(row).__name__}"
    unknown = [k for k in row if k not in ROW_FIELDS]
    if unknown:
        return f"unknown field {quote(unknown[0])}; a run's row has " + ", ".join(ROW_FIELDS)
    missing = [k for k in ROW_REQUIRED if k not in row]
    if missing:
        return f"the field {quote(missing[0])} is missing"
    failed = row["failed"]
    for key, value in row.items():
        check, what, null = ROW_FIELDS[key]
        if value is None and (null == ALWAYS or (null == IF_FAILED and failed)):
            continue
        if not check(value):
            return f"{quote(key)} is {quote(value)}, not {what}" + (
                f" (null {null})" if null != NEVER else ""
            )
    track, condition = row["track"], row["condition"]
    if track not in suite.tracks:
        return f"unknown track {quote(track)}; valid choices: " + ", ".join(suite.tracks)
    if condition not in suite.tracks[track].conditions:
        return f"unknown condition {quote(condition)} of track {track}; valid choices: " + (
            ", ".join(suite.tracks[track].conditions)
        )
    return ""
