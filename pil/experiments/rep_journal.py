"""The finished repetitions of a learner-only study, kept as they end so that a rerun resumes.

``OUT/reps.jsonl`` holds one line per finished repetition: the study's settings key, the
repetition, its seed and its rows. A line is appended whole by one ``write`` on a file opened
with ``O_APPEND`` and flushed to disk, so an interrupt (Ctrl-C, SIGTERM, ``kill -9``) leaves
every finished repetition and at most a torn last line, which is ignored. A rerun with the same
settings reads the finished repetitions back instead of running them again; their rows are
the very values the uninterrupted run computes (JSON keeps floats exactly), so the study's
files are byte for byte those of an uninterrupted run. A journal of other settings is started
anew. Used by ``robin-pil study`` and ``robin-pil people``.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

JOURNAL_NAME = "reps.jsonl"
FORMAT = 1  # of a journal line: a line of another format is not read back


def settings_key(settings: Mapping[str, Any]) -> str:
    """A short digest of a study's settings (what makes two runs the same study)."""
    text = json.dumps(settings, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _plain(value: Any) -> Any:
    """A numpy scalar as the Python number it holds (other values as they are)."""
    item = getattr(value, "item", None)
    return item() if callable(item) and not isinstance(value, str) else value


class RepJournal:
    """The journal of one study's finished repetitions in ``folder`` (see the module's doc)."""

    def __init__(self, folder: str | Path, settings: Mapping[str, Any]) -> None:
        self.path = Path(folder) / JOURNAL_NAME
        self.key = settings_key(settings)
        self._torn = False  # the file ends in a torn line: the next one starts on a new line
        self._done = self._read()
        if not self._done and self.path.exists():  # another study's, or torn only: anew
            self.path.unlink()
            self._torn = False

    def _read(self) -> dict[int, tuple[int, list[dict[str, Any]]]]:
        try:
            text = self.path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            return {}
        done: dict[int, tuple[int, list[dict[str, Any]]]] = {}
        self._torn = bool(text) and not text.endswith("\n")
        for line in text.splitlines():
            try:
                record = json.loads(line)
            except ValueError:  # a torn last line
                continue
            if not isinstance(record, dict) or record.get("format") != FORMAT:
                continue
            if record.get("key") != self.key:
                return {}  # another study's journal
            rep, seed, rows = record.get("rep"), record.get("seed"), record.get("rows")
            if isinstance(rep, int) and isinstance(seed, int) and isinstance(rows, list):
                done[rep] = (seed, rows)
        return done

    def finished(self, rep: int, seed: int) -> list[dict[str, Any]] | None:
        """The rows of repetition ``rep`` when it finished with ``seed``, else None."""
        found = self._done.get(rep)
        return found[1] if found is not None and found[0] == seed else None

    def count(self) -> int:
        """How many finished repetitions the journal held when it was opened."""
        return len(self._done)

    def add(self, rep: int, seed: int, rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
        """Keep repetition ``rep``'s rows: one whole line, on disk before this returns; the
        rows as kept (plain Python values, as a rerun reads them back)."""
        plain = [{key: _plain(value) for key, value in row.items()} for row in rows]
        record = {"format": FORMAT, "key": self.key, "rep": rep, "seed": seed, "rows": plain}
        line = json.dumps(record, separators=(",", ":")) + "\n"
        data = memoryview((("\n" if self._torn else "") + line).encode())
        self.path.parent.mkdir(parents=True, exist_ok=True)  # a seed folder: made by its first
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            while data:
                data = data[os.write(fd, data) :]
            os.fsync(fd)
        finally:
            os.close(fd)
        self._torn = False
        return plain
