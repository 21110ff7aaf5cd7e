"""Where a benchmark run keeps its results: a journal of runs, stamped, resumable.

``OUT/stamp.json`` says what the folder holds (suite version, the suite's hash over its file
and its conditions' files, each condition file's hash, seed block, quick or not, the git
commit of the code that started it, and of any that resumed it: ``resumed_at``);
``OUT/runs.jsonl`` has one JSON line per finished run, appended whole as each ends, so an
interrupted run loses only the runs under way and the same command resumes it (finished keys
are skipped). A folder of another suite (its file or a file its conditions read), block or
mode is refused before anything runs, naming what changed.

Both files are read through the guarded reader (:mod:`pil.regular_files`): a link to a device,
a FIFO or a folder is one :class:`~pil.regular_files.UnreadableFileError` naming the file,
before anything runs. Every line of the journal is parsed strictly (no NaN or infinities) and
each field checked (:func:`pil.bench.journal_rows.row_problem`): a bad line is an error naming
the file and the line. Only a damaged *last* line without its line end (a run stopped while its
line was written) is left out and said (:attr:`Journal.dropped`): its run runs again, and every
finished run before it is kept.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.bench.journal_rows import row_problem
from pil.bench.suite import Suite, SuiteError
from pil.provenance import source_commit
from pil.regular_files import UnreadableFileError, parse_json, read_json_file, read_kind_bytes

STAMP, RUNS = "stamp.json", "runs.jsonl"
KEY = ("track", "condition", "agent", "seed")
_SAME = ("suite_version", "suite_sha256", "block", "quick")
# stamp field -> what it must be (suite_inputs and resumed_at are optional)
_STAMP_TYPES: dict[str, tuple[type, ...]] = {
    "suite_version": (str,),
    "suite_sha256": (str,),
    "block": (str,),
    "quick": (bool,),
    "commit": (str,),
    "suite_inputs": (dict,),
    "resumed_at": (list,),
}


def key_of(row: Mapping[str, Any]) -> tuple[str, str, str, int]:
    """The journal key of a run row."""
    return (str(row["track"]), str(row["condition"]), str(row["agent"]), int(row["seed"]))


class Journal:
    """The results folder of one benchmark run (module docstring)."""

    def __init__(
        self, out: str | Path, suite: Suite, block: str, quick: bool, commit: str | None = None
    ) -> None:
        """``commit``: the code's commit when the command started (default: now)."""
        self.out = Path(out)
        made_by = source_commit().label() if commit is None else commit
        self.stamp = {**suite.stamp(), "block": block, "quick": quick, "commit": made_by}
        found = self.read_stamp(self.out)
        if found is not None:
            commit = str(found.get("commit", "unknown"))
            later = [c for c in found.get("resumed_at", []) if c != commit]
            if self.stamp["commit"] not in (commit, *later):
                later.append(self.stamp["commit"])
            self.stamp.update(commit=commit, resumed_at=later)  # who made the first runs
            for name in _SAME:
                if found.get(name) != self.stamp[name]:
                    why = suite.stale(found) if name == "suite_sha256" else ""
                    raise SuiteError(
                        f"{self.out} holds runs with {name} {found.get(name)!r}, not "
                        f"{self.stamp[name]!r}{f' ({why})' if why else ''}; give a new --out "
                        "folder"
                    )
        self._file = read_journal(self.out, suite)
        self.rows = self._file.rows
        self.dropped = self._file.dropped  # what a damaged last line lost ("": nothing)
        self.done = {key_of(r) for r in self.rows}

    @staticmethod
    def read_stamp(out: Path) -> dict[str, Any] | None:
        """The folder's stamp (None: a new folder); :class:`UnreadableFileError` naming it
        when it is not a readable stamp."""
        path = Path(out) / STAMP
        if not (path.exists() or path.is_symlink()):
            return None
        data = read_json_file(path, "settings", "the benchmark's stamp", finite=True)
        problem = _stamp_problem(data)
        if problem:
            raise UnreadableFileError(
                f"{path}: not a stamp of robin-pil bench ({problem}); give a new --out folder"
            )
        return dict(data)

    def start(self) -> None:
        """Create the folder and write the stamp (the commit of this session's code)."""
        self.out.mkdir(parents=True, exist_ok=True)
        write_text_atomic(self.out / STAMP, json.dumps(self.stamp, indent=1) + "\n")

    def add(self, rows: Iterable[Mapping[str, Any]]) -> None:
        """Append finished runs, each line whole in one write. The first append cuts a damaged
        last line off (or ends a whole one) so that the new lines stand on their own."""
        path = self.out / RUNS
        lead = self._file.before_append(path)
        data = lead + b"".join(
            (json.dumps(_plain(row), sort_keys=True) + "\n").encode() for row in rows
        )
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view) :]
        finally:
            os.close(fd)
        for row in rows:
            self.rows.append(dict(row))
            self.done.add(key_of(row))


def _plain(row: Mapping[str, Any]) -> dict[str, Any]:
    return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in row.items()}


def _stamp_problem(data: Any) -> str:
    """What is wrong with ``data`` as a stamp ("" if nothing)."""
    if not isinstance(data, dict):
        return f"a JSON object expected, got {type(data).__name__}"
    for name, kinds in _STAMP_TYPES.items():
        value = data.get(name)
        optional = name in ("suite_inputs", "resumed_at")
        if (value is None and not optional) or (value is not None and type(value) not in kinds):
            return f"{name!r} is {value!r}"
    inputs, resumed = data.get("suite_inputs", {}), data.get("resumed_at", [])
    if not all(isinstance(k, str) and isinstance(v, str) for k, v in inputs.items()):
        return "'suite_inputs' must map file names to their sha256"
    if not all(isinstance(c, str) for c in resumed):
        return "'resumed_at' must list commits"
    return ""


@dataclass
class JournalFile:
    """A journal as read: its rows, what a damaged last line lost, and where it ends."""

    rows: list[dict[str, Any]] = field(default_factory=list)
    dropped: str = ""  # the damaged last line left out ("": none)
    keep: int = 0  # bytes up to the end of the last whole line (or of a kept last line)
    size: int = 0  # bytes read
    whole: bool = True  # the kept bytes end with a line end (or are none)

    def before_append(self, path: Path) -> bytes:
        """Ready ``path`` for the first append: cut the damaged last line off (unless the file
        changed since it was read); the bytes to write first (a line end, or none)."""
        lead = b""
        if self.keep < self.size and path.stat().st_size == self.size:
            os.truncate(path, self.keep)
        elif not self.whole or self.keep < self.size:
            lead = b"\n"
        self.keep = self.size = 0
        self.whole = True
        return lead


def _row(raw: bytes, suite: Suite) -> tuple[dict[str, Any] | None, str]:
    """A journal line as its row (NaN for the nulls), or None and what is wrong with it."""
    try:
        row = parse_json(raw.decode("utf-8"), finite=True)
    except UnicodeDecodeError as error:
        return None, f"not UTF-8 text (byte {error.start})"
    except ValueError as error:
        return None, str(error)
    problem = row_problem(row, suite)
    if problem:
        return None, problem
    return {k: (math.nan if v is None else v) for k, v in row.items()}, ""


def read_journal(out: str | Path, suite: Suite) -> JournalFile:
    """The journal of ``out`` (module docstring): a bad line raises naming it, a damaged last
    line without its line end is left out and said."""
    path = Path(out) / RUNS
    if not (path.exists() or path.is_symlink()):
        return JournalFile()
    data = read_kind_bytes(path, "log", "the benchmark's journal")
    *lines, tail = data.split(b"\n")
    found = JournalFile(keep=len(data), size=len(data), whole=not tail)
    for number, raw in enumerate(lines, 1):
        if raw.strip():
            row, problem = _row(raw, suite)
            if row is None:
                raise UnreadableFileError(
                    f"{path}:{number}: {problem}; mend or delete that line, or give a new "
                    "--out folder"
                )
            found.rows.append(row)
    if tail.strip():
        row, problem = _row(tail, suite)
        if row is not None:
            found.rows.append(row)
        else:
            found.keep = len(data) - len(tail)
            found.dropped = (
                f"{path}:{len(lines) + 1}: left out a damaged last line ({len(tail)} bytes, "
                f"{problem}): a run stopped while its line was written; that run runs again"
            )
    return found


def read_runs(out: str | Path, suite: Suite) -> list[dict[str, Any]]:
    """The journal's rows (NaN for the nulls; a damaged last line is left out)."""
    return read_journal(out, suite).rows


def sorted_runs(rows: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Rows in a fixed order (by key), the last of a duplicated key kept."""
    by_key = {key_of(r): dict(r) for r in rows}
    return [by_key[k] for k in sorted(by_key)]
