"""A study's participant registry, ``registry.json``: every id ever given, and what became of it.

One entry per participant: id, group, condition order, status (:data:`PARTICIPANT_STATUSES`),
when it was assigned, started and ended, the run's outcome, the session folders (relative to
the study folder) and, for a withdrawal, its reason. An id is never given twice: a new
participant gets the next number, and an id that is in the registry is refused whatever its
status. Changes are made under an exclusive lock (``.registry.lock``: two experimenters'
machines sharing a folder never assign one id twice) and written atomically. Pure Python.
"""

from __future__ import annotations

import fcntl
import json
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError, quote
from pil.regular_files import UnreadableFileError, read_json_file

REGISTRY_NAME = "registry.json"
LOCK_NAME = ".registry.lock"
REGISTRY_FORMAT = 1
# assigned: registered, not started; running: started (or stopped without a trace);
# completed: every block and the debrief; unfinished: the run ended early (closed, ended,
# interrupted); declined: no consent, nothing kept; withdrawn: excluded from the analysis
PARTICIPANT_STATUSES: tuple[str, ...] = (
    "assigned",
    "running",
    "completed",
    "unfinished",
    "declined",
    "withdrawn",
)
FILLING: tuple[str, ...] = ("assigned", "running", "completed", "unfinished")  # fill a cell
LEFT_OUT: tuple[str, ...] = ("declined", "withdrawn")  # never analysed


class RegistryError(RobinPilError):
    """A registry that cannot be read, or a participant id that cannot be used."""


def utc_now() -> str:
    """The UTC time, to the second, as the registry and the log write it."""
    return datetime.now(UTC).isoformat(timespec="seconds")


class Registry:
    """The registry of the study in ``folder`` (see the module doc)."""

    def __init__(self, folder: Path, study: str) -> None:
        self.folder, self.study = Path(folder), study
        self.path = self.folder / REGISTRY_NAME

    def entries(self) -> list[dict[str, Any]]:
        """Every participant's entry, in the order they were registered ([] before any)."""
        if not self.path.exists():
            return []
        try:
            data = read_json_file(self.path, "registry", "the registry")
        except UnreadableFileError as error:
            raise RegistryError(
                f"not a readable registry ({error}); restore it from the study's "
                "archive, it is the one list of the ids given"
            ) from None
        people = data.get("participants") if isinstance(data, dict) else None
        if not isinstance(people, list) or not all(
            isinstance(p, dict) and isinstance(p.get("id"), str) for p in people
        ):
            raise RegistryError(f"{self.path}: expected {{'participants': [{{'id': ...}}, ...]}}")
        return people

    def entry(self, participant: str) -> dict[str, Any]:
        """``participant``'s entry (ids compare as :func:`same_id`); :class:`RegistryError`
        naming the ids if it has none."""
        for entry in self.entries():
            if same_id(entry["id"], participant):
                return entry
        ids = ", ".join(e["id"] for e in self.entries()) or "none yet"
        raise RegistryError(f"participant {quote(participant)} is not in the registry; ids: {ids}")

    @contextmanager
    def changing(self) -> Iterator[list[dict[str, Any]]]:
        """The entries under the lock; what the block leaves in the list is written back."""
        self.folder.mkdir(parents=True, exist_ok=True)
        with (self.folder / LOCK_NAME).open("a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                entries = self.entries()
                yield entries
                body = {"format": REGISTRY_FORMAT, "study": self.study, "participants": entries}
                write_text_atomic(self.path, json.dumps(body, indent=2) + "\n")
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    def update(self, participant: str, **fields: Any) -> dict[str, Any]:
        """Change ``participant``'s entry (under the lock); the new entry."""
        status = fields.get("status")
        if status is not None and status not in PARTICIPANT_STATUSES:
            raise RegistryError(
                f"unknown status {status!r}; valid: {', '.join(PARTICIPANT_STATUSES)}"
            )
        with self.changing() as entries:
            for entry in entries:
                if same_id(entry["id"], participant):
                    entry.update(fields)
                    return dict(entry)
        raise RegistryError(f"participant {quote(participant)} is not in the registry")


def same_id(one: str, other: str) -> bool:
    """Whether two ids name the same participant: equal but for case (on a case-insensitive
    file system ``sessions/p01`` is ``sessions/P01``)."""
    return one.casefold() == other.casefold()


def since(entry: dict[str, Any]) -> str:
    """When ``entry`` took its status: withdrawn, ended or assigned."""
    if entry.get("status") == "withdrawn" and entry.get("withdrawn_utc"):
        return str(entry["withdrawn_utc"])
    return str(entry.get("ended_utc") or entry.get("assigned_utc"))


def check_new(entries: list[dict[str, Any]], participant: str, next_id: str) -> None:
    """Refuse an id that is in the registry already, but for case (ids are never reused)."""
    for entry in entries:
        if same_id(entry["id"], participant):
            raise RegistryError(
                f"participant id {quote(participant)} was given already as "
                f"{quote(entry['id'])} ({entry['status']} since {since(entry)}); an id is "
                f"never reused: leave out --participant for the next one ({next_id})"
            )


def next_number(entries: list[dict[str, Any]], prefix: str) -> int:
    """The number after every id of the form prefix + number in the registry."""
    numbers = [
        int(e["id"][len(prefix) :])
        for e in entries
        if e["id"].startswith(prefix) and e["id"][len(prefix) :].isdigit()
    ]
    return max(numbers, default=0) + 1
