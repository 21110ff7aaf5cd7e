"""The recorded sessions a simulated person is fitted to: found, consent checked, read once.

``robin-pil people --from-sessions DIR`` takes a study folder (``robin-pil study-init``, run
with ``robin-pil live --study``), a folder inside one, or a folder of them. A session counts
when its participant's consent is on record: the study's ``log.jsonl`` has their ``consent``
line with ``agree`` and ``registry.json`` lists the session among theirs. A withdrawn or
declined participant is left out (named); a session whose consent is not on record (a plain
``robin-pil live`` folder, a study whose log lacks the line, a session the registry does not
list) is refused, and so is a folder with no session: one message each
(:class:`PeopleSourceError`, exit 2). Practice blocks are never fitted. Every file is read
through :func:`pil.regular_files.read_regular_text` (no FIFO, device or huge file hangs the
command) and its SHA-256 kept, so a fitted person names the exact bytes it came from. Pure
Python: no MuJoCo.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.experiments.sessions_load import (
    EVENTS_NAME,
    INPUTS_NAME,
    SESSION_LOG_NAME,
    SUMMARY_NAME,
)
from pil.experiments.study_export import EXCLUDED  # the registry's statuses never analysed
from pil.regular_files import UnreadableFileError, parse_json, read_kind_text

STUDY_FILE = "study.yaml"
REGISTRY_FILE = "registry.json"
STUDY_LOG_FILE = "log.jsonl"
SESSION_FILES = (SUMMARY_NAME, INPUTS_NAME, EVENTS_NAME, SESSION_LOG_NAME)


class PeopleSourceError(RobinPilError):
    """Recorded sessions that cannot be fitted (no consent, none at all, unreadable)."""


@dataclass(frozen=True)
class RecordedSession:
    """One block of a participant, read: its files' rows and their checksums."""

    participant: str
    name: str  # its folder relative to DIR
    summary: dict[str, Any]
    inputs: list[dict[str, Any]]
    events: list[dict[str, Any]]
    log: list[dict[str, Any]]
    sha256: dict[str, str] = field(default_factory=dict)  # file name -> checksum

    @property
    def live(self) -> dict[str, Any]:
        block = self.summary.get("live")
        return block if isinstance(block, dict) else {}


@dataclass(frozen=True)
class Sources:
    """Every consented session under DIR, by participant, and who was left out and why."""

    sessions: dict[str, list[RecordedSession]]
    left_out: dict[str, str]  # participant -> why


def read_text(path: Path, kind: str = "log") -> str:
    """A file's text, read as :mod:`pil.regular_files` reads every found file (a regular
    file within its kind's size limit, UTF-8); one :class:`PeopleSourceError` naming it."""
    try:
        return read_kind_text(path, kind, "a session file")
    except UnreadableFileError as error:
        raise PeopleSourceError(str(error)) from None


def read_json(path: Path, kind: str = "summary") -> Any:
    """A JSON file's value (strict: :func:`pil.regular_files.parse_json`)."""
    return _parsed(read_text(path, kind), path)


def _parsed(text: str, path: Path, number: int | None = None) -> Any:
    try:
        return parse_json(text)
    except ValueError as error:
        where = path if number is None else f"{path}:{number}"
        raise PeopleSourceError(f"{where}: {error}") from None


def parse_lines(text: str, path: Path) -> list[dict[str, Any]]:
    """The objects of a JSON-lines file's ``text`` (read from ``path``)."""
    rows = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        row = _parsed(line, path, number)
        if not isinstance(row, dict):
            raise PeopleSourceError(f"{path}:{number}: expected a JSON object")
        rows.append(row)
    return rows


def read_lines(path: Path, *, required: bool = True) -> list[dict[str, Any]]:
    """A JSON-lines file's objects; a missing optional file is []."""
    if not required and not path.exists():
        return []
    return parse_lines(read_text(path), path)


def find_sources(folder: Path) -> Sources:
    """Every consented, non-practice session under ``folder`` (see the module doc)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise PeopleSourceError(
            f"--from-sessions {quote(str(folder))}: not a folder; give a study folder "
            "(robin-pil live --study) or a folder of them"
        )
    summaries = sorted(p for p in folder.rglob(SUMMARY_NAME) if _is_live(p))
    if not summaries:
        raise PeopleSourceError(
            f"--from-sessions {quote(str(folder))}: no live session (no summary.json with a "
            "'live' block) under it; record sessions with robin-pil live --study"
        )
    studies: dict[Path, tuple[dict[str, str], set[str], dict[str, list[str]]]] = {}
    sessions: dict[str, list[RecordedSession]] = {}
    left_out: dict[str, str] = {}
    refused: list[str] = []
    for path in summaries:
        session_dir = path.parent
        study = _study_of(session_dir)
        name = session_dir.relative_to(folder).as_posix()
        if study is None:
            refused.append(f"{name} (in no study folder)")
            continue
        if study not in studies:
            studies[study] = _consent(study)
        statuses, agreed, registered = studies[study]
        summary = read_json(path)
        live = summary.get("live") if isinstance(summary, dict) else None
        if not isinstance(live, dict) or not isinstance(live.get("participant"), str):
            raise PeopleSourceError(f"{path}: its live block names no participant")
        who = str(live["participant"])
        if live.get("practice"):
            continue  # a practice block is never analysed
        status = statuses.get(who)
        if status in EXCLUDED:
            left_out[who] = f"{status} (registry)"
            continue
        if status is None or who not in agreed:
            refused.append(f"{name} ({who}: no consent line with 'agree' in the study's log)")
            continue
        if session_dir.resolve().relative_to(study).as_posix() not in registered.get(who, []):
            refused.append(f"{name} (not among {who}'s sessions in the study's registry)")
            continue
        sessions.setdefault(who, []).append(read_session(session_dir, folder, who, summary))
    if refused:
        more = f"; and {len(refused) - 5} more" if len(refused) > 5 else ""
        shown = "; ".join(refused[:5]) + more
        raise PeopleSourceError(
            f"--from-sessions: {len(refused)} session(s) without a recorded consent: {shown}. "
            "Only sessions of a study whose participant agreed on its consent screen are "
            "fitted; move the others out of the folder"
        )
    if not sessions:
        raise PeopleSourceError(
            f"--from-sessions {quote(str(folder))}: no session left to fit (left out: "
            + (", ".join(f"{k} {v}" for k, v in left_out.items()) or "practice blocks only")
            + ")"
        )
    return Sources(sessions, left_out)


def read_session(
    session_dir: Path, root: Path, who: str, summary: dict[str, Any]
) -> RecordedSession:
    """One session's files, read and checksummed (the summary already read)."""
    sha: dict[str, str] = {}
    texts: dict[str, str] = {}
    for name in SESSION_FILES:
        path = session_dir / name
        if name == EVENTS_NAME and not path.exists():
            texts[name] = ""  # a session where nothing happened of itself
            continue
        texts[name] = read_text(path, "summary" if name == SUMMARY_NAME else "log")
        sha[name] = hashlib.sha256(texts[name].encode("utf-8")).hexdigest()
    return RecordedSession(
        participant=who,
        name=session_dir.relative_to(root).as_posix(),
        summary=summary,
        inputs=parse_lines(texts[INPUTS_NAME], session_dir / INPUTS_NAME),
        events=parse_lines(texts[EVENTS_NAME], session_dir / EVENTS_NAME),
        log=parse_lines(texts[SESSION_LOG_NAME], session_dir / SESSION_LOG_NAME),
        sha256=sha,
    )


def _is_live(path: Path) -> bool:
    """A summary that looks like a live session's (read fully later)."""
    return (path.parent / INPUTS_NAME).exists() or '"live"' in read_text(path, "summary")


def _study_of(session_dir: Path) -> Path | None:
    """The nearest folder above ``session_dir`` holding a study file (DIR may be in it)."""
    for parent in session_dir.resolve().parents:
        if (parent / STUDY_FILE).is_file():
            return parent
    return None


def _consent(study: Path) -> tuple[dict[str, str], set[str], dict[str, list[str]]]:
    """The registry's status and sessions per participant, and who agreed in the log."""
    registry = study / REGISTRY_FILE
    if not registry.exists():
        return {}, set(), {}
    data = read_json(registry, "registry")
    people = data.get("participants") if isinstance(data, dict) else None
    if not isinstance(people, list):
        raise PeopleSourceError(f"{registry}: expected {{'participants': [...]}}")
    statuses = {str(p.get("id")): str(p.get("status")) for p in people if isinstance(p, dict)}
    sessions = {
        str(p.get("id")): [str(s) for s in p.get("sessions") or []]
        for p in people
        if isinstance(p, dict)
    }
    agreed = {
        str(line.get("participant"))
        for line in read_lines(study / STUDY_LOG_FILE, required=False)
        if line.get("event") == "consent" and line.get("value") == "agree"
    }
    return statuses, agreed, sessions
