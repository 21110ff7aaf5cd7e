"""A study's data as a lab analyses them: three CSV files built from its session folders.

* ``trials.csv``: one row per step of every block (practice included, marked): participant,
  group, the block's position in the participant's run, block, condition, practice, the block's
  seed and status, the step, handover, gestures (made, detected, corrected), state, action,
  the action meant, feedback, its outcome, and its timings in simulated seconds: when the robot
  began the action (``acted_at``), when the learner had the feedback (``logged_at``), and the
  step's length since the one before (``step_s``).
* ``questionnaires_wide.csv``: one row per participant: group, order, status, the demographics
  answers (``demographics_<item>``), and per questionnaire after each block its answers, scores
  (items reverse-scored where marked, subscales, means) and attention checks, in columns named
  ``<condition>_<k>_<questionnaire>_<item>``, ``..._score_<score>`` and ``..._check_<item>``
  (``k``: the participant's k-th block of that condition).
* ``long.csv``: the same tidily, one value a row (participant, group, block position, block,
  condition, practice, session, source, instrument, variable, kind, value): the blocks'
  measures, the questionnaires' answers, scores and checks, the demographics.

``participants`` are the registry's entries (id, group, order, status); declined and withdrawn
participants are left out. Every path is relative to the study folder. Pure Python.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.answers_file import read_answers
from pil.experiments.sessions_load import (
    EVENTS_NAME,
    MEASURES,
    SESSION_LOG_NAME,
    SUMMARY_NAME,
    SessionsError,
)
from pil.file_names import QUESTIONNAIRES_NAME
from pil.regular_files import UnreadableFileError, read_json_file, read_jsonl_file

SESSIONS_DIR = "sessions"  # a study folder's sessions: <participant>/<session> (robin_sim.lab)
DEMOGRAPHICS_NAME = "demographics.jsonl"  # in the participant's folder (robin_sim.live)
EXCLUDED = ("declined", "withdrawn")  # never exported nor analysed
STEP_FIELDS = (
    "t",
    "handover",
    "handover_type",
    "step",
    "true_gesture",
    "detected_gesture",
    "corrected_gesture",
    "state",
    "action",
    "intended_action",
    "feedback",
    "succeeded",
    "interrupted",
    "proactive",
    "delivered",
    "legs_delivered",
)
BLOCK_COLUMNS = (
    "participant",
    "group",
    "position",
    "block",
    "condition",
    "practice",
    "seed",
    "block_status",
    "session",
)
TRIAL_COLUMNS = (*BLOCK_COLUMNS, *STEP_FIELDS, "acted_at", "logged_at", "step_s")
LONG_COLUMNS = (
    *BLOCK_COLUMNS[:6],
    "session",
    "source",
    "instrument",
    "variable",
    "kind",
    "value",
)


def read_jsonl(path: Path, *, strict: bool = True) -> list[dict[str, Any]]:
    """A JSON-lines file's objects ([] when it is missing); a bad line names the file, or is
    skipped when not ``strict`` (a line a crash cut short). Read as
    :func:`pil.regular_files.read_jsonl_file` reads: a device, a FIFO or a huge file is refused."""
    if not os.path.lexists(path):
        return []
    try:
        lines = read_jsonl_file(Path(path), "log", "the log", strict=strict)
    except UnreadableFileError as error:
        raise SessionsError(str(error)) from None
    return [row for row in lines if isinstance(row, dict)]


def read_summary(path: Path) -> dict[str, Any]:
    """A session's ``summary.json`` as an object, read as the sessions report reads it."""
    try:
        summary = read_json_file(path, "summary", "the summary")
    except UnreadableFileError as error:
        raise SessionsError(str(error)) from None
    if not isinstance(summary, dict):
        raise SessionsError(f"{path}: expected a JSON object (a session's summary)")
    return summary


def study_blocks(folder: Path, participants: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Every block session of the included participants, in their order: the block's columns
    (:data:`BLOCK_COLUMNS`), its folder (``path``) and its summary (``summary``)."""
    blocks = []
    for person in participants:
        if person.get("status") in EXCLUDED:
            continue
        for position, session in enumerate(person.get("sessions", ())):
            path = folder / session
            summary_path = path / SUMMARY_NAME
            if not summary_path.is_file():
                continue  # a session killed before its summary: listed by study-status
            summary = read_summary(summary_path)
            live = summary.get("live", {})
            practice = bool(live.get("practice"))
            blocks.append(
                {
                    "participant": person["id"],
                    "group": person.get("group"),
                    "position": position,  # 0 is the practice block when there is one
                    "block": None if live.get("block") is None else live["block"] + 1,
                    "condition": live.get("condition"),
                    "practice": practice,
                    "seed": live.get("seed"),
                    "block_status": summary.get("status"),
                    "session": session,
                    "path": path,
                    "summary": summary,
                }
            )
    return blocks


def trial_rows(blocks: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """``trials.csv``'s rows: one per logged step."""
    rows = []
    for block in blocks:
        acted = {
            e.get("t"): e.get("sim_time")
            for e in read_jsonl(block["path"] / EVENTS_NAME)
            if e.get("event") == "acts"
        }
        before = 0.0
        for entry in read_jsonl(block["path"] / SESSION_LOG_NAME):
            logged = entry.get("sim_time")
            row = {c: block[c] for c in BLOCK_COLUMNS}
            row.update({f: _cell(entry.get(f)) for f in STEP_FIELDS})
            row["acted_at"] = acted.get(entry.get("t"))
            row["logged_at"] = logged
            row["step_s"] = None if logged is None else round(logged - before, 4)
            before = logged if logged is not None else before
            rows.append(row)
    return rows


def _cell(value: Any) -> Any:
    return json.dumps(value) if isinstance(value, dict | list) else value


def _name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", str(text)).strip("_")


def answer_values(entry: Mapping[str, Any]) -> list[tuple[str, str, Any]]:
    """A questionnaire line's (kind, variable, value): answers, scores, attention checks."""
    values = [("answer", k, v) for k, v in entry.get("answers", {}).items()]
    values += [("score", k, v) for k, v in entry.get("scores", {}).items()]
    values += [("attention", k, int(bool(v))) for k, v in entry.get("attention", {}).items()]
    return values


def long_rows(
    folder: Path, participants: Sequence[Mapping[str, Any]], blocks: Sequence[Mapping[str, Any]]
) -> list[dict[str, Any]]:
    """``long.csv``'s rows (see the module doc)."""
    rows = []
    for block in blocks:
        head = {c: block[c] for c in LONG_COLUMNS[:7]}
        summary = block["summary"]
        for measure in (*MEASURES, "status"):
            rows.append(
                {
                    **head,
                    "source": "block",
                    "instrument": "session",
                    "variable": measure,
                    "kind": "measure",
                    "value": summary.get(measure),
                }
            )
        for entry in read_answers(block["path"] / QUESTIONNAIRES_NAME):
            for kind, variable, value in answer_values(entry):
                rows.append(
                    {
                        **head,
                        "source": "questionnaire",
                        "instrument": entry.get("questionnaire"),
                        "variable": variable,
                        "kind": kind,
                        "value": value,
                    }
                )
    for person in participants:
        if person.get("status") in EXCLUDED:
            continue
        path = folder / SESSIONS_DIR / person["id"] / DEMOGRAPHICS_NAME
        for entry in read_jsonl(path):
            head = {"participant": person["id"], "group": person.get("group")}
            for variable, value in entry.get("answers", {}).items():
                rows.append(
                    {
                        **head,
                        "source": "demographics",
                        "instrument": "demographics",
                        "variable": variable,
                        "kind": "answer",
                        "value": value,
                    }
                )
    return rows


def wide_rows(
    folder: Path, participants: Sequence[Mapping[str, Any]], blocks: Sequence[Mapping[str, Any]]
) -> tuple[list[dict[str, Any]], list[str]]:
    """``questionnaires_wide.csv``'s rows and columns (see the module doc)."""
    rows: dict[str, dict[str, Any]] = {}
    columns = ["participant", "group", "order", "status"]
    for person in participants:
        if person.get("status") in EXCLUDED:
            continue
        row = rows[person["id"]] = {
            "participant": person["id"],
            "group": person.get("group"),
            "order": " ".join(person.get("order", ())),
            "status": person.get("status"),
        }
        for entry in read_jsonl(folder / SESSIONS_DIR / person["id"] / DEMOGRAPHICS_NAME):
            for variable, value in entry.get("answers", {}).items():
                _put(row, columns, f"demographics_{_name(variable)}", value)
    seen: dict[tuple[str, str], int] = {}
    for block in blocks:
        if block["practice"] or block["participant"] not in rows:
            continue
        key = (block["participant"], block["condition"])
        seen[key] = seen.get(key, 0) + 1
        prefix = f"{_name(block['condition'])}_{seen[key]}"
        for entry in read_answers(block["path"] / QUESTIONNAIRES_NAME):
            stem = f"{prefix}_{_name(entry.get('questionnaire', ''))}"
            for kind, variable, value in answer_values(entry):
                middle = {"answer": "", "score": "score_", "attention": "check_"}[kind]
                _put(
                    rows[block["participant"]], columns, f"{stem}_{middle}{_name(variable)}", value
                )
    return list(rows.values()), columns


def _put(row: dict[str, Any], columns: list[str], column: str, value: Any) -> None:
    if column not in columns:
        columns.append(column)
    row[column] = value
