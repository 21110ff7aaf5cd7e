"""Reading a folder of live sessions: one checked row per ``summary.json`` with a "live" block.

A sessions folder holds ``<participant>/<session>/summary.json`` files written by
``robin-pil live``; summaries without a ``"live"`` block (episodes) are skipped. A summary that
is not JSON, not an object, or lacks a field the report needs raises :class:`SessionsError`
naming the file. Pure Python: no MuJoCo.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.errors import quote
from pil.experiments.report import ReportError, number
from pil.file_names import SUMMARY_NAME

INPUTS_NAME = "inputs.jsonl"  # a live session's first file (robin_sim.live.files)
SESSION_LOG_NAME = "log.jsonl"  # a live session's step log (robin_sim.live.run)
EVENTS_NAME = "events.jsonl"  # what a live session did of itself (robin_sim.live.files)
COUNTED_STATUS = "finished"
# measure -> what it is (the summary's field names; sim_time_s is the session's physics time)
MEASURES: dict[str, str] = {
    "gestures": "instruction gestures",
    "actions": "robot actions",
    "rejected": "rejected actions",
    "interrupted_actions": "interrupted actions",
    "sim_time_s": "session time (sim s)",
    "mean_handover_s": "mean handover time (s)",
    "legs_delivered": "legs delivered",
}
NULLABLE: tuple[str, ...] = ("mean_handover_s",)  # null when no leg was delivered
LIVE_REQUIRED: tuple[str, ...] = ("participant", "session", "condition")
LIVE_OPTIONAL: tuple[str, ...] = (
    "block",
    "protocol",
    "handover_types",
    "inputs",
    "inputs_rejected",
    "frames_streamed",
    "stream_fps",
    "started_utc",
    "practice",  # a study's practice block (never counted)
)
SESSION_COLUMNS: tuple[str, ...] = (
    "participant",
    "session",
    "condition",
    "block",
    "scenario",
    "protocol",
    "status",
    "counted",
    *MEASURES,
    "legs_total",
    *LIVE_OPTIONAL[2:],
    "summary",
)
EXPECTED = (
    f"a folder of live sessions (<participant>/<session>/{SUMMARY_NAME} files whose summary "
    'has a "live" block, as robin-pil live writes them under out/live)'
)


class SessionsError(ReportError):
    """A sessions folder or a summary in it that cannot be reported."""


def load_sessions(folder: str | Path) -> list[dict[str, Any]]:
    """One row per live session under ``folder`` (``[]`` when it holds none).

    Every ``summary.json`` is read; one that is not a JSON object raises naming it, and so
    does a live summary that lacks a field the report needs. Summaries without a ``"live"``
    block (episodes) are skipped. Rows are sorted by participant, block and session.
    """
    folder = Path(folder)
    rows = []
    for path in sorted(folder.rglob(SUMMARY_NAME)):
        summary = _read_summary(path)
        if "live" in summary:
            rows.append(session_row(summary, path, folder))
    rows.sort(
        key=lambda r: (
            _natural(r["participant"]),
            r["block"] is None,
            r["block"] or 0,
            _natural(r["session"]),
        )
    )
    return rows


def _natural(text: str) -> list[tuple[int, int | str]]:
    """Sort key reading digit runs as numbers: P2 before P10."""
    return [(0, int(part)) if part.isdigit() else (1, part) for part in re.split(r"(\d+)", text)]


def session_row(summary: Mapping[str, Any], path: Path, folder: Path) -> dict[str, Any]:
    """The sessions.csv row of one live ``summary`` (read from ``path``); checked."""
    live = summary["live"]
    if not isinstance(live, Mapping):
        raise SessionsError(f'{path}: the "live" block is not a mapping')
    row: dict[str, Any] = {}
    for key in LIVE_REQUIRED:
        value = live.get(key)
        if not isinstance(value, str) or not value:
            raise SessionsError(f"{path}: live.{key}: expected a non-empty text, got {value!r}")
        row[key] = value
    block = live.get("block")
    if block is not None and (isinstance(block, bool) or not isinstance(block, int)):
        raise SessionsError(f"{path}: live.block: expected a whole number or null, got {block!r}")
    row["block"] = block
    scenario = summary.get("scenario")
    row["scenario"] = scenario if isinstance(scenario, str) and scenario else "unknown"
    row["protocol"] = live.get("protocol")
    status = summary.get("status")
    if not isinstance(status, str) or not status:
        raise SessionsError(f"{path}: status: expected a text (e.g. 'finished'), got {status!r}")
    practice = live.get("practice") is True
    row["status"], row["counted"] = status, status == COUNTED_STATUS and not practice
    for key in MEASURES:
        if key not in summary:
            raise SessionsError(
                f"{path}: missing field {key!r}; a live summary has " + ", ".join(MEASURES)
            )
        row[key] = _number(summary[key], key, path, nullable=key in NULLABLE)
    row["legs_total"] = summary.get("legs_total")
    for key in LIVE_OPTIONAL[2:]:
        value = live.get(key)
        row[key] = " ".join(map(str, value)) if isinstance(value, list) else value
    row["summary"] = path.relative_to(folder).as_posix()
    return row


def _number(value: Any, key: str, path: Path, *, nullable: bool) -> float | None:
    if value is None and nullable:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        kind = "a number or null" if nullable else "a number"
        raise SessionsError(f"{path}: {key}: expected {kind}, got {quote(value)}")
    try:
        number(value, key)  # NaN, infinities and 400-digit numbers are refused here
    except ReportError as error:
        raise SessionsError(f"{path}: {error}") from None
    return value


def _read_summary(path: Path) -> Mapping[str, Any]:
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise SessionsError(f"{path}: cannot read the summary: {error.strerror}") from None
    except UnicodeDecodeError as error:
        raise SessionsError(f"{path}: not UTF-8 text (byte {error.start})") from None
    except (ValueError, RecursionError) as error:  # ValueError: bad JSON, a 5000-digit number
        where = getattr(error, "lineno", None)
        at = f" at line {where}" if where else ""
        raise SessionsError(
            f"{path}: not a JSON summary{at}; the file is corrupt or cut "
            "short (remove it or rerun the session)"
        ) from None
    if not isinstance(summary, Mapping):
        raise SessionsError(f"{path}: expected a JSON object (a session's summary)")
    return summary


def unreported_sessions(folder: str | Path) -> list[tuple[str, str]]:
    """Session folders under ``folder`` that hold no readable summary, as (folder relative to
    ``folder``, why): a ``summary.json`` that is a dangling link, or an ``inputs.jsonl``
    without a summary (a session killed before it ended). The report lists them."""
    folder = Path(folder)
    found = []
    for root, _dirs, files in os.walk(folder):
        here = Path(root)
        where = here.relative_to(folder).as_posix()
        if SUMMARY_NAME in files and not (here / SUMMARY_NAME).exists():
            target = os.readlink(here / SUMMARY_NAME)
            found.append((where, f"{SUMMARY_NAME} is a link to {target}, which does not exist"))
        elif INPUTS_NAME in files and SUMMARY_NAME not in files:
            found.append((where, f"no {SUMMARY_NAME}: the session was killed before it ended"))
    return sorted(found)
