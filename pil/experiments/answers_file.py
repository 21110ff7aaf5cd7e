"""Reading a block's ``questionnaires.jsonl``: every record checked before it is summarised.

The live page appends one line per questionnaire answered (:mod:`robin_sim.live.questioning`):
participant, condition, the questionnaire, its answers, its ``scores`` and their ``ranges``
(score -> ``[lowest, highest]``, the span of the items it is made of). A record that is not an
object with :data:`REQUIRED`, a score that is not a finite number, or one outside its range
(999 on a 5-point item) raises :class:`SessionsError` naming the file, the line and the score.
Records written before ``ranges`` existed are checked for finite numbers only. The file is read
with :func:`pil.regular_files.read_kind_text` (a device, a FIFO or a huge file is refused).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.errors import quote
from pil.experiments.sessions_load import SessionsError
from pil.regular_files import UnreadableFileError, parse_json, read_kind_text

REQUIRED = ("participant", "condition", "questionnaire", "scores")
RANGES_KEY = "ranges"  # score -> [lowest, highest] (written since the ranges were recorded)


def read_answers(path: Path) -> list[dict[str, Any]]:
    """The checked records of one ``questionnaires.jsonl`` ([] when there is none)."""
    path = Path(path)
    if not os.path.lexists(path):
        return []
    try:
        text = read_kind_text(path, "questionnaires", "the questionnaires")
    except UnreadableFileError as error:
        raise SessionsError(str(error)) from None
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        if line.strip():
            try:
                row = parse_json(line, finite=True)
            except ValueError as error:
                raise SessionsError(
                    f"{path}:{number}: not a questionnaire record ({error}; a JSON object with "
                    + ", ".join(REQUIRED)
                    + ")"
                ) from None
            rows.append(check_record(row, f"{path}:{number}"))
    return rows


def check_record(row: Any, where: str) -> dict[str, Any]:
    """``row`` if it is a questionnaire record with finite scores within their ranges."""
    bad = not isinstance(row, dict) or any(k not in row for k in REQUIRED)
    if bad or not isinstance(row["scores"], Mapping):
        raise SessionsError(
            f"{where}: not a questionnaire record (a JSON object with " + ", ".join(REQUIRED) + ")"
        )
    ranges = row.get(RANGES_KEY)
    if ranges is not None and not isinstance(ranges, Mapping):
        raise SessionsError(f"{where}: {RANGES_KEY} must map each score to [lowest, highest]")
    for name, value in row["scores"].items():
        number = isinstance(value, int | float) and not isinstance(value, bool)
        if not number or not math.isfinite(value):
            raise SessionsError(f"{where}: score {quote(name)} is {quote(value)}, not a number")
        if ranges is None:
            continue
        span: Any = ranges.get(name)
        if not _is_span(span):
            raise SessionsError(f"{where}: score {quote(name)} has no [lowest, highest] range")
        if not span[0] <= value <= span[1]:
            raise SessionsError(
                f"{where}: score {quote(name)} is {value:g}, outside its scale "
                f"{span[0]:g} to {span[1]:g}; the file was edited or damaged"
            )
    return row


def _is_span(span: Any) -> bool:
    return (
        isinstance(span, list)
        and len(span) == 2
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in span)
        and all(math.isfinite(v) for v in span)
        and span[0] <= span[1]
    )
