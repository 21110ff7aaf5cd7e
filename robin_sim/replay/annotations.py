"""What a recorded run's files say happened, on the replay's timeline, and as a video overlay.

:func:`timeline` reads a run's folder beside its ``states.npz``: the steps of its log
(``log.jsonl`` of a live session, ``episode.jsonl`` of an episode: each step's gesture, action
and feedback, at the moment the robot began the action when ``events.jsonl`` says it, else when
the learner had the feedback), a live session's accepted gestures and thumbs (``inputs.jsonl``),
what the session did of itself (``events.jsonl``: silences, hand-backs, the watchdog, limits,
inactivity, reconnections), the experimenter's notes (``notes.jsonl``) and the questionnaires
answered after the block (``questionnaires.jsonl``: at the end). Each marker has a time in
seconds from the first recorded frame. Missing files give no markers; a damaged line is skipped.

:func:`with_log_overlay` gives a live session's recorded frames the episode's overlay (the
step, gesture, action, feedback, legs), built from its log, for ``robin-pil replay --overlay``.
"""

from __future__ import annotations

from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from pil.experiments.questionnaire_report import QUESTIONNAIRES_NAME
from pil.experiments.sessions_load import EVENTS_NAME, INPUTS_NAME, SESSION_LOG_NAME, SUMMARY_NAME
from pil.experiments.study_export import read_jsonl
from pil.file_names import EPISODE_LOG_NAME
from pil.regular_files import UnreadableFileError, read_json_file
from robin_sim.live.files import NOTES_NAME
from robin_sim.render.overlay import OverlayInfo
from robin_sim.render.state_log import RecordedStates

QUIET = ("acts", "stream")  # events kept off the timeline (every action; the stream's level)
MAX_MARKERS = 5000  # a timeline of more markers is cut (hand readings are never markers)


def _lines(path: Path) -> list[dict[str, Any]]:
    return read_jsonl(path, strict=False)


def steps_of(folder: Path) -> list[dict[str, Any]]:
    """The run's steps: ``step`` (t), ``start`` (sim s the action began), ``logged`` (sim s
    of the feedback), and the log entry."""
    log = folder / SESSION_LOG_NAME
    entries = _lines(log if log.is_file() else folder / EPISODE_LOG_NAME)
    began = {
        e.get("t"): e.get("sim_time")
        for e in _lines(folder / EVENTS_NAME)
        if e.get("event") == "acts"
    }
    steps = []
    for entry in entries:
        logged = entry.get("sim_time")
        if not isinstance(logged, int | float):
            continue
        start = began.get(entry.get("t"))
        steps.append(
            {
                "step": entry.get("t"),
                "start": start if isinstance(start, int | float) else logged,
                "logged": logged,
                "entry": entry,
            }
        )
    return steps


def timeline(folder: Path, recorded: RecordedStates) -> dict[str, Any]:
    """The markers of the run in ``folder`` (see the module doc) and its steps, timed from the
    first of ``recorded``'s frames (only those within its frames are kept)."""
    t0, end = recorded.states[0].time, recorded.states[-1].time
    markers: list[dict[str, Any]] = []

    def mark(at: Any, kind: str, label: str, **extra: Any) -> None:
        if isinstance(at, int | float) and t0 - 1e-6 <= at <= end + 1e-6:
            markers.append({"time": round(at - t0, 4), "kind": kind, "label": label, **extra})

    steps = steps_of(folder)
    for s in steps:
        e = s["entry"]
        gesture = e.get("corrected_gesture") or e.get("detected_gesture") or e.get("true_gesture")
        label = f"step {s['step']}: {gesture} -> {e.get('action') or 'again'}, {e.get('feedback')}"
        mark(s["start"], "step", label, step=s["step"])
    for line in _lines(folder / INPUTS_NAME):
        raw = line.get("raw")
        if not line.get("accepted") or not isinstance(raw, dict):
            continue
        kind = raw.get("type")
        if kind == "thumb":
            mark(line.get("sim_time"), "thumb", f"thumb {raw.get('value')}")
        elif kind in ("point", "gesture"):
            what = "pointing" if kind == "point" else raw.get("gesture")
            mark(line.get("sim_time"), "gesture", f"gesture {what}")
    for event in _lines(folder / EVENTS_NAME):
        if event.get("event") not in QUIET:
            detail = event.get("why") or event.get("reason") or event.get("limit") or ""
            mark(event.get("sim_time"), "event", f"{event.get('event')} {detail}".strip())
    for note in _lines(folder / NOTES_NAME):
        mark(note.get("sim_time"), "note", f"note: {str(note.get('text', ''))[:120]}")
    for answer in _lines(folder / QUESTIONNAIRES_NAME):
        mark(end, "questionnaire", f"questionnaire {answer.get('questionnaire')} answered")
    markers.sort(key=lambda m: m["time"])
    listed = [
        {"step": s["step"], "time": round(s["start"] - t0, 4)}
        for s in steps
        if t0 - 1e-6 <= s["start"] <= end + 1e-6
    ]
    return {"markers": markers[:MAX_MARKERS], "steps": listed}


def with_log_overlay(recorded: RecordedStates, folder: Path) -> RecordedStates:
    """``recorded`` with the episode's overlay on every frame, from the log: the step that runs
    (its gesture and action, feedback ``-`` until it is given) or the last one logged."""
    steps = steps_of(folder)
    summary = _summary(folder)
    total = int(summary.get("legs_total") or 0)
    overlays: list[dict[str, Any] | None] = []
    for state in recorded.states:
        now = state.time
        current = next((s for s in reversed(steps) if s["start"] <= now + 1e-9), None)
        if current is None:
            overlays.append({"info": _info(None, False, total), "eye": None})
            continue
        judged = current["logged"] <= now + 1e-9
        overlays.append({"info": _info(current["entry"], judged, total), "eye": None})
    meta = {**recorded.meta, "overlay": True}
    return replace(recorded, overlays=tuple(overlays), meta=meta)


def _summary(folder: Path) -> dict[str, Any]:
    try:  # a link to /dev/zero, a FIFO: nothing read (the timeline goes without it)
        data = read_json_file(folder / SUMMARY_NAME, "summary", "the summary")
    except UnreadableFileError:
        return {}
    return data if isinstance(data, dict) else {}


def _info(entry: dict[str, Any] | None, judged: bool, total: int) -> dict[str, Any]:
    if entry is None:
        info = OverlayInfo(step=0, sim_time=0.0, legs_total=total)
    else:
        corrected = entry.get("corrected_gesture")
        info = OverlayInfo(
            step=int(entry.get("t") or 0),
            sim_time=0.0,
            true_gesture=entry.get("true_gesture"),
            detected_gesture=entry.get("detected_gesture"),
            corrected_gesture=corrected,
            action=entry.get("action"),
            feedback=entry.get("feedback") if judged else None,
            legs_delivered=int(entry.get("legs_delivered") or 0),
            legs_total=total,
            state=entry.get("state"),
            intended=entry.get("intended_action"),
            handover=entry.get("handover"),
            handover_type=entry.get("handover_type"),
        )
    return {k: v for k, v in asdict(info).items() if k != "sim_time"}
