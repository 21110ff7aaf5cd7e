"""The finished repetitions of a learner-only study, kept as they end so that a rerun resumes.

``OUT/reps.jsonl`` holds one line per finished repetition: the study's settings key, the
repetition, its seed and its rows. A line is appended whole by one ``write`` on a file opened
with ``O_APPEND`` and flushed to disk, so an interrupt (Ctrl-C, SIGTERM, ``kill -9``) leaves
every finished repetition and at most a torn last line. A rerun with the same settings reads
the finished repetitions back instead of running them again; their rows are the very values
the uninterrupted run computes (JSON keeps floats exactly), so the study's files are byte for
byte those of an uninterrupted run. A journal of other settings is started anew.

The journal is read through the guarded reader (:func:`pil.regular_files.read_kind_bytes`): a
link to a device, a FIFO or a folder is one :class:`pil.regular_files.UnreadableFileError`
naming it, before anything runs. Each line is decoded and parsed on its own: a damaged line (a
torn tail, a torn UTF-8 character, a line of another format) is dropped and counted in
:attr:`RepJournal.dropped`, and every line that parses is kept, so a damaged tail never costs a
finished repetition. Used by ``robin-pil study`` and ``robin-pil people``.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.regular_files import parse_json, read_kind_bytes

JOURNAL_NAME = "reps.jsonl"
JOURNAL_FORMAT = 1  # of a journal line: a line of another format is not read back


def settings_key(settings: Mapping[str, Any]) -> str:
    """A short digest of a study's settings (what makes two runs the same study)."""
    text = json.dumps(settings, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _plain(value: Any) -> Any:
    """A numpy scalar as the Python number it holds (other values as they are)."""
    item = getattr(value, "item", None)
    return item() if callable(item) and not isinstance(value, str) else value


def _record(raw: bytes) -> dict[str, Any] | None:
    """One journal line as its record (None: damaged, or of another format)."""
    try:
        record = parse_json(raw.decode("utf-8"), finite=True)
    except (UnicodeDecodeError, ValueError):
        return None
    if not isinstance(record, dict) or record.get("format") != JOURNAL_FORMAT:
        return None
    return record


def _is_rep(rep: Any, seed: Any, rows: Any) -> bool:
    """Whether a record's fields are a repetition's: whole numbers and a list of rows."""
    return (
        type(rep) is int
        and type(seed) is int
        and isinstance(rows, list)
        and all(isinstance(row, dict) for row in rows)
    )


class RepJournal:
    """The journal of one study's finished repetitions in ``folder`` (see the module's doc)."""

    def __init__(self, folder: str | Path, settings: Mapping[str, Any]) -> None:
        self.path = Path(folder) / JOURNAL_NAME
        self.key = settings_key(settings)
        self._torn = False  # the file ends in a torn line: the next one starts on a new line
        self.dropped = 0  # damaged lines left out (a torn tail, bytes that are not a record)
        other = False
        self._done: dict[int, tuple[int, list[dict[str, Any]]]] = {}
        if self.path.exists() or self.path.is_symlink():
            other = self._read(read_kind_bytes(self.path, "log", "the study's journal"))
        if other:  # another study's journal: this one starts anew
            self.path.unlink()
            self._torn, self.dropped, self._done = False, 0, {}

    def _read(self, data: bytes) -> bool:
        """Keep every finished repetition of ``data``; True if it is another study's."""
        self._torn = bool(data) and not data.endswith(b"\n")
        for raw in data.split(b"\n"):
            if not raw.strip():
                continue
            record = _record(raw)
            if record is None:
                self.dropped += 1
                continue
            if record.get("key") != self.key:
                return True
            rep: Any = record.get("rep")
            seed: Any = record.get("seed")
            rows: Any = record.get("rows")
            if _is_rep(rep, seed, rows):
                self._done[rep] = (seed, rows)
            else:
                self.dropped += 1
        return False

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
        record = {
            "format": JOURNAL_FORMAT,
            "key": self.key,
            "rep": rep,
            "seed": seed,
            "rows": plain,
        }
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


def report_journal(command: str, journal: RepJournal) -> None:
    """Say on stderr what a rerun of ``command`` keeps of ``journal`` and what it dropped."""
    if journal.count():
        print(
            f"robin-pil {command}: resuming: {journal.count()} finished repetitions kept in "
            f"{journal.path}",
            file=sys.stderr,
        )
    if journal.dropped:
        print(
            f"robin-pil {command}: {journal.dropped} damaged line(s) of {journal.path} left "
            "out (a torn tail or bytes that are not a repetition); their repetitions run again",
            file=sys.stderr,
        )
