"""The results of a sweep on disk: a journal written run by run, and a merged CSV.

Layout of a sweep directory::

    sweep.json    the settings the directory is bound to (run kind and function, base seed)
    runs.jsonl    the journal: one JSON object per finished attempt, appended, flushed, fsynced
    results.csv   the merged results: one row per run of the grid, sorted by run id
    timings.csv   where and how long each run of results.csv ran (host, wall time)

Why a JSON-lines journal plus a merged CSV: a run's row reaches the disk the moment it ends
(one ``write`` + ``fsync`` of one line, only the parent process writes), the columns do not
have to be known in advance (failed runs have no metrics), floats round-trip exactly, and a
line torn by a kill is recognised (it does not parse and ends without a newline) and cut off
when the directory is opened again. ``results.csv`` is rewritten whole through a temporary
file and ``os.replace``, so it is either the old or the new file, never half of one; its bytes
depend only on the grid and the results, not on workers, order or retries.

A lock on the directory (:class:`pil.folder_lock.FolderLock`, released by the kernel even
after ``kill -9``) stops two sweeps, or a sweep and an episode, from writing it at once.
"""

from __future__ import annotations

import csv
import io
import json
import os
import socket
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError
from pil.file_names import RESULTS_NAME as RESULTS
from pil.folder_lock import FolderInUseError, FolderLock
from pil.regular_files import UnreadableFileError, read_json_file, read_kind_bytes

MANIFEST = "sweep.json"
JOURNAL = "runs.jsonl"
TIMINGS = "timings.csv"
# metrics that measure the machine, not the run: kept in the journal and timings.csv only,
# so that results.csv is the same bytes however and wherever the grid was executed
TIMING_COLUMNS: tuple[str, ...] = ("wall_time_s", "real_time_factor")
FORMAT = 1
STATUS_OK = "ok"
STATUS_FAILED = "failed"


class SweepStoreError(RobinPilError):
    """A sweep directory that is locked, corrupt or bound to other settings."""


def read_journal(path: Path) -> tuple[list[dict[str, Any]], int]:
    """The journal's records and the byte length of its intact part.

    A last line without a newline that does not parse (torn by a kill) is left out; any
    other line that does not parse is an error naming the file and the line.
    """
    if not os.path.lexists(path):
        return [], 0
    try:  # a link to /dev/zero, a FIFO: refused before a byte is read
        data = read_kind_bytes(path, "log", "the journal")
    except UnreadableFileError as error:
        raise SweepStoreError(
            f"{error}; it must be the file the sweep wrote; use another --out"
        ) from None
    records: list[dict[str, Any]] = []
    intact = 0
    for number, line in enumerate(data.splitlines(keepends=True), start=1):
        try:
            record = json.loads(line)
            if not isinstance(record, dict) or "run_id" not in record:
                raise ValueError("not a run record")
        except ValueError:
            if not line.endswith(b"\n"):
                break  # torn tail from an interrupted write: ignore it
            raise SweepStoreError(
                f"{path}: line {number} is not a run record; the journal "
                "was edited or written by another program"
            ) from None
        if line.endswith(b"\n"):
            records.append(record)
            intact += len(line)
        else:
            break  # a complete object without its newline: treat as torn, rerun it
    return records, intact


def is_done(record: Mapping[str, Any]) -> bool:
    """Whether a journal record is a successful attempt: status ok and its metrics a mapping
    (an ``ok`` record without metrics was not written by a finished run; it is run again)."""
    return record.get("status") == STATUS_OK and isinstance(record.get("metrics"), dict)


class RunStore:
    """A sweep directory opened for writing: use as a context manager.

    ``manifest`` is what the directory is bound to; opening it again with other settings
    raises :class:`SweepStoreError`, so a resumed sweep never mixes runs of two setups.
    """

    def __init__(self, directory: str | Path, manifest: Mapping[str, Any]) -> None:
        self.directory = Path(directory)
        self.manifest = {"format": FORMAT, **manifest}
        self._records: list[dict[str, Any]] = []
        self._attempts: dict[str, int] = {}
        self._journal: io.BufferedWriter | None = None
        self._lock = FolderLock(self.directory)

    # --- opening and closing ----------------------------------------------------------------
    def __enter__(self) -> RunStore:
        if self.directory.exists() and not self.directory.is_dir():
            raise SweepStoreError(f"--out {self.directory} exists and is not a directory")
        self.directory.mkdir(parents=True, exist_ok=True)
        for name in (MANIFEST, JOURNAL, RESULTS, TIMINGS):
            path = self.directory / name
            if (path.exists() or path.is_symlink()) and not path.is_file():
                raise SweepStoreError(
                    f"{path} is not a regular file (a folder, a dangling link or a device); "
                    "the sweep writes its own files there: remove it or use another --out"
                )
        self._take_lock()
        try:
            self._bind_manifest()
            journal = self.directory / JOURNAL
            records, intact = read_journal(journal)
            for record in records:
                self._remember(record)
            self._journal = open(journal, "ab")
            if self._journal.tell() != intact:
                self._journal.truncate(intact)  # cut a torn last line off
                self._journal.seek(intact)
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def close(self) -> None:
        """Close the journal and release the lock (idempotent)."""
        if self._journal is not None:
            self._journal.close()
            self._journal = None
        self._lock.release()

    def _take_lock(self) -> None:
        try:
            self._lock.acquire()
        except FolderInUseError as error:
            raise SweepStoreError(str(error)) from None

    def _bind_manifest(self) -> None:
        path = self.directory / MANIFEST
        if path.exists():
            try:
                bound = read_json_file(path, "settings", "the sweep's settings")
            except UnreadableFileError as error:
                raise SweepStoreError(f"{error}; remove the directory") from None
            if not isinstance(bound, dict):
                raise SweepStoreError(
                    f"{path} holds {type(bound).__name__} JSON, not the sweep's settings "
                    "(an object); remove the directory or use another --out"
                )
            if bound != self.manifest:
                diff = ", ".join(
                    f"{key}: {bound.get(key)!r} there, {self.manifest.get(key)!r} now"
                    for key in sorted(set(bound) | set(self.manifest))
                    if bound.get(key) != self.manifest.get(key)
                )
                raise SweepStoreError(
                    f"{self.directory} holds a sweep with other settings ({diff}); "
                    "use another --out or the same settings"
                )
        else:
            write_text_atomic(path, json.dumps(self.manifest, indent=2, sort_keys=True) + "\n")

    # --- reading ------------------------------------------------------------------------------
    @property
    def records(self) -> list[dict[str, Any]]:
        """Every attempt recorded so far, in the order written."""
        return list(self._records)

    def finished_ids(self) -> set[str]:
        """Ids of runs with a successful attempt (a resumed sweep skips them)."""
        return {r["run_id"] for r in self._records if is_done(r)}

    def attempts(self, run_id: str) -> int:
        """How many attempts of ``run_id`` the journal holds."""
        return self._attempts.get(run_id, 0)

    # --- writing ------------------------------------------------------------------------------
    def append(self, record: Mapping[str, Any]) -> None:
        """Write one attempt's record durably (one line, flush, fsync) before returning."""
        if self._journal is None:
            raise SweepStoreError("the sweep directory is not open")
        line = json.dumps(dict(record), default=_plain).encode() + b"\n"
        self._journal.write(line)
        self._journal.flush()
        os.fsync(self._journal.fileno())
        self._remember(json.loads(line))

    def _remember(self, record: dict[str, Any]) -> None:
        self._records.append(record)
        self._attempts[record["run_id"]] = self._attempts.get(record["run_id"], 0) + 1

    def write_results(self, run_ids: Sequence[str], id_columns: Sequence[str]) -> Path:
        """Merge the journal into ``results.csv``: one row per finished run of ``run_ids``.

        A run's row is its first successful attempt, else its last failed one; runs with no
        attempt yet are left out. Columns: ``id_columns``, status, error, then the metrics in
        order of first appearance, less :data:`TIMING_COLUMNS`, which go to ``timings.csv``
        with the host and wall time. Both files are replaced atomically.
        """
        final: dict[str, dict[str, Any]] = {}
        for record in self._records:
            previous = final.get(record["run_id"])
            if previous is None or not is_done(previous):
                final[record["run_id"]] = record
        rows, timings = [], []
        for run_id in sorted(set(run_ids) & set(final)):
            record = final[run_id]
            row = dict(record.get("columns", {}))
            row["status"] = record.get("status", "")
            row["error"] = record.get("error", "")
            if row["status"] == STATUS_OK and not is_done(record):
                row["status"], row["error"] = STATUS_FAILED, "journal record without metrics"
            timing = {"run_id": run_id, "host": record.get("host"), "wall_s": record.get("wall_s")}
            for key, value in (record.get("metrics") or {}).items():
                (timing if key in TIMING_COLUMNS else row).setdefault(key, value)
            rows.append(row)
            timings.append(timing)
        columns = [*id_columns, "status", "error"]
        for row in rows:
            columns += [key for key in row if key not in columns]
        write_text_atomic(
            self.directory / TIMINGS,
            rows_to_csv(timings, ["run_id", "host", "wall_s", *TIMING_COLUMNS]),
        )
        path = self.directory / RESULTS
        write_text_atomic(path, rows_to_csv(rows, columns))
        return path


def make_record(
    columns: Mapping[str, Any], outcome: Mapping[str, Any], attempt: int
) -> dict[str, Any]:
    """A journal record: a run's identifying columns plus one attempt's outcome."""
    return {
        "run_id": columns["run_id"],
        "attempt": attempt,
        "status": outcome["status"],
        "error": outcome.get("error", ""),
        "wall_s": outcome.get("wall_s"),
        "host": outcome.get("host", socket.gethostname()),
        "columns": dict(columns),
        "metrics": dict(outcome.get("metrics") or {}),
    }


def rows_to_csv(rows: Iterable[Mapping[str, Any]], columns: Sequence[str]) -> str:
    """CSV text with a header; missing cells empty, floats by ``repr``, ``\\n`` line ends."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), restval="", lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({key: "" if value is None else value for key, value in row.items()})
    return buffer.getvalue()


def _plain(value: Any) -> Any:
    """JSON fallback for numpy scalars and other objects with ``item()`` (else ``str``)."""
    item = getattr(value, "item", None)
    return item() if callable(item) else str(value)
