"""A live session's folder and files: ``inputs.jsonl`` as messages come, ``summary.json`` last.

The folder is ``out_root/<participant>/<session>``; an existing one is refused (a session never
overwrites another). ``inputs.jsonl`` gets one line per message from the controlling client,
flushed at once: wall-clock and monotonic time, the simulated time, the raw message, whether it
was accepted and, if not, why. ``summary.json`` holds the episode summary's fields
(:func:`robin_sim.episode.book.run_summary`) and a ``"live"`` block; ``notes.jsonl`` the
experimenter's timestamped notes; the step log and the MP4 are written by
:class:`robin_sim.live.run.LiveRun`.
"""

from __future__ import annotations

import json
import os
import threading
import time
from collections import deque
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pil.errors import RobinPilError, quote
from pil.experiments.sessions_load import (  # what the report and the exports read
    EVENTS_NAME,
    INPUTS_NAME,
    SUMMARY_NAME,
)
from robin_sim.episode.log import write_json_atomic
from robin_sim.live.config import LiveConfig
from robin_sim.live.take_back import TAKE_BACK_WINDOW_S

if TYPE_CHECKING:
    from robin_sim.live.run import LiveRun

NOTES_NAME = "notes.jsonl"
RECENT_EVENTS = 12  # events the experimenter's view shows
QUIET_EVENTS = ("acts",)  # events too frequent to show there (every action)
MAX_RAW_CHARS = 2000  # a raw message longer than this is logged cut (the server limits them)


class SessionExistsError(RobinPilError):
    """A session folder that exists already (sessions are never overwritten)."""


def block_folder(session: str | None, index: int, condition: str) -> str:
    """A protocol block's session folder: ``block<N>-<condition>``, after ``--session`` if given."""
    name = f"block{index + 1}-{condition}"
    return name if session is None else f"{session}-{name}"


def session_folder(config: LiveConfig) -> Path:
    """Where ``config``'s session goes; refuses a named session whose folder exists, and
    makes a new name from the UTC time (with -2, -3, ... if taken) when none is given."""
    base = Path(config.out_root) / config.participant
    if config.session is not None:
        folder = base / config.session
        if folder.exists():
            raise SessionExistsError(
                f"session folder {quote(str(folder))} exists already; a session is never "
                "overwritten: choose another session name or participant"
            )
        return folder
    stamp = datetime.now(UTC).strftime("%Y%m%d-%H%M%S")
    folder, n = base / stamp, 1
    while folder.exists():
        n += 1
        folder = base / f"{stamp}-{n}"
    return folder


class SessionFiles:
    """The session's folder (made here, never reused), its inputs log and its summary."""

    def __init__(self, out_dir: Path, config: LiveConfig) -> None:
        self.out_dir, self.config = Path(out_dir), config
        try:
            self.out_dir.parent.mkdir(parents=True, exist_ok=True)
            self.out_dir.mkdir()
        except FileExistsError:
            raise SessionExistsError(
                f"session folder {quote(str(self.out_dir))} exists already; a session is never "
                "overwritten: choose another session name or participant"
            ) from None
        except OSError as error:
            raise RobinPilError(
                f"cannot make the session folder {quote(str(self.out_dir))}: "
                f"{error.strerror or error}"
            ) from None
        self.started_utc = datetime.now(UTC).isoformat(timespec="seconds")
        self.started = time.perf_counter()
        self._lock = threading.Lock()
        self._inputs = (self.out_dir / INPUTS_NAME).open("w", encoding="utf-8")
        self.inputs = self.rejected = self.readings = 0
        self.recent_events: deque[dict[str, Any]] = deque(maxlen=RECENT_EVENTS)

    def log_input(
        self,
        raw: object,
        error: str,
        sim_time: float | None,
        reading: dict[str, Any] | None = None,
    ) -> None:
        """One line of ``inputs.jsonl`` (thread-safe, flushed). A webcam ``reading`` (what
        the hand tracker's message was read as) is logged with it and counted apart from the
        inputs (the page clears a shown error when the inputs grow, not on every reading)."""
        if isinstance(raw, bytes | bytearray):
            raw = raw.decode("utf-8", "replace")
        if isinstance(raw, str) and len(raw) > MAX_RAW_CHARS:
            raw = raw[:MAX_RAW_CHARS] + "..."
        entry = {
            "wall": time.time(),
            "monotonic": time.monotonic(),
            "sim_time": sim_time,
            "raw": raw,
            "accepted": not error,
            "error": error,
        }
        if reading is not None:
            entry["reading"] = reading
        line = json.dumps(entry, default=str) + "\n"
        with self._lock:
            if self._inputs.closed:  # after the summary: the questionnaires, late messages
                self._append_late(line)
                return
            self._inputs.write(line)
            self._inputs.flush()
            if reading is not None:
                self.readings += 1
                return
            self.inputs += 1
            self.rejected += bool(error)

    def _append_late(self, line: str) -> None:
        """A line after the summary was written (not in its counts); a full disk loses it."""
        try:
            with (self.out_dir / INPUTS_NAME).open("a", encoding="utf-8") as late:
                late.write(line)
        except OSError:
            pass

    def log_event(self, kind: str, fields: dict[str, Any]) -> None:
        """One line of ``events.jsonl`` (flushed): ``kind`` (e.g. ``silence``,
        ``handed_back``, ``watchdog``, ``reconnected``, ``stream``) with its fields."""
        entry = {"wall": time.time(), "event": kind, **fields}
        with self._lock, (self.out_dir / EVENTS_NAME).open("a", encoding="utf-8") as events:
            events.write(json.dumps(entry, default=str) + "\n")
            if kind not in QUIET_EVENTS:
                self.recent_events.append(entry)

    def log_note(self, text: str, sim_time: float | None) -> dict[str, Any]:
        """One experimenter's note, timestamped, appended to ``notes.jsonl`` (flushed); the
        entry. Written also after the session has ended (the folder stays)."""
        entry = {
            "utc": datetime.now(UTC).isoformat(timespec="milliseconds"),
            "wall": time.time(),
            "sim_time": sim_time,
            "text": text,
        }
        with self._lock, (self.out_dir / NOTES_NAME).open("a", encoding="utf-8") as notes:
            notes.write(json.dumps(entry) + "\n")
        return entry

    def save(
        self,
        status: str,
        error: str,
        run: LiveRun | None,
        vision: dict[str, Any] | None = None,
        limits: dict[str, Any] | None = None,
    ) -> dict[str, Any]:
        """Close the inputs log and write ``summary.json``; the summary (with the webcam's
        ``vision`` block and the block's ``limits`` in the live block, when given)."""
        from robin_sim.episode.book import run_summary  # imports MuJoCo

        with self._lock:
            self._inputs.close()
        config, wall = self.config, time.perf_counter() - self.started
        if run is None:  # it failed before the world was built
            summary: dict[str, Any] = {
                "status": status,
                "error": error,
                "system": config.system,
                "seed": config.seed,
                "wall_time_s": round(wall, 3),
            }
        else:
            summary = run_summary(
                spec=run.spec,
                run=run.parts,
                totals=run.totals,
                world=run.world,
                wall=wall,
                status=status,
                error=error,
            )
        summary["live"] = self._live_block(run)
        if limits is not None:
            summary["live"]["limits"] = limits
        if vision is not None:
            summary["vision"] = vision
        stream = None if run is None else run.stream
        if stream is not None and stream.writer is not None:
            summary["video"] = {
                # relative to the session folder: the same on every machine, and in an archive
                "path": os.path.relpath(stream.writer.path, self.out_dir),
                "fps": int(config.fps),
                "size": [config.width, config.height],
                "frames": stream.stats.video_frames,
            }
        write_json_atomic(self.out_dir / SUMMARY_NAME, summary)
        return summary

    def _live_block(self, run: LiveRun | None) -> dict[str, Any]:
        config = self.config
        stats = None if run is None or run.stream is None else run.stream.stats
        pacer = None if run is None else run.pacer
        fps = None if stats is None else stats.fps
        types = config.handover_types
        if run is not None:
            types = tuple(t.name for t in run.participant.types)
        return {
            "participant": config.participant,
            "session": self.out_dir.name,
            "condition": config.system,
            "block": config.block,
            "protocol": config.protocol,
            # the block's seed and what it came from (pil.task.seeds.block_seed)
            "seed": config.seed,
            "study_seed": config.study_seed,
            "handover_types": None if types is None else list(types),
            "inputs": self.inputs,
            "inputs_rejected": self.rejected,
            "hand_readings": self.readings,
            "frames_streamed": 0 if stats is None else stats.frames,
            "stream_fps": None if fps is None else round(fps, 2),
            "started_utc": self.started_utc,
            "speed": config.speed,
            "feedback_window_s": config.feedback_window,
            # "That was wrong": actions taken back, and for how long after one stood
            "taken_back": None if run is None else run.participant.take_backs.count,
            "take_back_window_s": TAKE_BACK_WINDOW_S,
            "latency_ms": None
            if stats is None
            else {"median": stats.latency_ms(0.5), "p95": stats.latency_ms(0.95)},
            "behind_s": None if pacer is None else round(pacer.behind_s, 3),
            # wall ms the physics thread spends on a frame (render, inset, JPEG, MP4)
            "frame_ms": None
            if not stats or not stats.frames
            else round((stats.render_s + stats.encode_s) / stats.frames * 1000, 1),
            "instructions": config.instructions,
            "practice": config.practice,  # a study's practice block: never analysed
        }
