"""Reading a folder of live sessions: one checked row per ``summary.json`` with a "live" block.

A sessions folder holds ``<participant>/<session>/summary.json`` files written by
``robin-pil live``; summaries without a ``"live"`` block (episodes) are skipped. A summary that
is not JSON, not an object, or lacks a field the report needs raises :class:`SessionsError`
naming the file. Pure Python: no MuJoCo.
"""

from __future__ import annotations

import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.errors import quote
from pil.experiments.report import ReportError, number
from pil.file_names import SUMMARY_NAME
from pil.regular_files import UnreadableFileError, parse_json, read_kind_text

INPUTS_NAME = "inputs.jsonl"  # a live session's first file (robin_sim.live.files)
SESSION_LOG_NAME = "log.jsonl"  # a live session's step log (robin_sim.live.run)
EVENTS_NAME = "events.jsonl"  # what a live session did of itself (robin_sim.live.files)
COUNTED_STATUS = "finished"
SESSION_ID = ("participant", "session", "block", "scenario")  # one session's identity
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
    rows: list[dict[str, Any]] = []
    seen: dict[tuple[Any, ...], str] = {}  # a session's identity -> its summary
    for path in sorted(folder.rglob(SUMMARY_NAME)):
        summary = _read_summary(path)
        if "live" in summary:
            row = session_row(summary, path, folder)
            ident = tuple(row[k] for k in SESSION_ID)
            if ident in seen:  # a copied folder would count one session twice
                raise SessionsError(
                    f"{path}: the session {row['participant']}/{row['session']} "
                    f"(block {row['block']}) is also in {seen[ident]}; each session is "
                    "reported once: remove the copy"
                )
            seen[ident] = row["summary"]
            rows.append(row)
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
    """A summary read as :func:`pil.regular_files.read_json_file` reads (a link to a device, a
    FIFO or a huge file is refused before it is read), or :class:`SessionsError`."""
    try:
        text = read_kind_text(path, "summary", "the summary")
    except UnreadableFileError as error:
        raise SessionsError(str(error)) from None
    try:
        summary = parse_json(text, finite=True)  # NaN or an infinity anywhere: corrupt
    except ValueError as error:  # bad JSON, a key twice, 5000 levels deep
        at = re.search(r" at line \d+", str(error))
        raise SessionsError(
            f"{path}: not a JSON summary{at.group(0) if at else f' ({error})'}; the file is "
            "corrupt or cut short (remove it or rerun the session)"
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
