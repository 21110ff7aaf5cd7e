"""A study's log across participants, ``log.jsonl``: one line per thing that happened.

Each line: the UTC time, the participant, the event (``assigned``, ``consent``,
``demographics``, ``block_started``, ``block_ended``, ``block`` (its questionnaires
answered), ``debrief``, ``run_over``, ``withdrawn``, ``released``) and its fields, with every
path relative to the study folder. Lines are appended whole and flushed. Pure Python.
"""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path
from typing import Any

from pil.experiments.study_export import read_jsonl
from robin_sim.lab.registry import utc_now

STUDY_LOG_NAME = "log.jsonl"


class StudyLog:
    """Appends to the log of the study in ``folder``."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)
        self.path = self.folder / STUDY_LOG_NAME
        self._lock = threading.Lock()

    def write(self, participant: str, event: str, **fields: Any) -> dict[str, Any]:
        """One line (paths made relative to the study folder); the entry."""
        entry = {
            "utc": utc_now(),
            "participant": participant,
            "event": event,
            **{k: self._plain(v) for k, v in fields.items()},
        }
        line = json.dumps(entry, default=str) + "\n"
        with self._lock, self.path.open("a", encoding="utf-8") as log:
            log.write(line)
            log.flush()
            os.fsync(log.fileno())
        return entry

    def _plain(self, value: Any) -> Any:
        if isinstance(value, Path):
            try:
                return value.resolve().relative_to(self.folder.resolve()).as_posix()
            except ValueError:
                return str(value)
        if isinstance(value, dict):
            return {k: self._plain(v) for k, v in value.items()}
        return value

    def entries(self) -> list[dict[str, Any]]:
        """Every line read back ([] before the first); a line that is not JSON is skipped
        (a line cut by a crash)."""
        return read_jsonl(self.path, strict=False)
