"""The episode's log: one JSON line per step, written and flushed as it happens, and a summary.

A step line is complete or absent: lines are written whole and flushed, so an interrupted
episode leaves a log of every finished step. The summary is written atomically.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.atomic import write_text_reserved
from pil.errors import naming
from pil.regular_files import read_jsonl_file
from robin_sim.closing import ClosesOnExit


def _plain(value: Any) -> Any:
    """Turn enums, dataclass-like records, numpy scalars and tuples into JSON-ready values."""
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if hasattr(value, "item") and callable(value.item) and getattr(value, "shape", None) == ():
        return value.item()
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple) or hasattr(value, "tolist"):
        items = value.tolist() if hasattr(value, "tolist") else value
        return [_plain(v) for v in items]
    return str(value)


class StepLog(ClosesOnExit):
    """Appends one JSON object per line to ``path`` (truncated when opened)."""

    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._file = self.path.open("w", encoding="utf-8")
        self.lines = 0

    def write(self, entry: Mapping[str, Any]) -> None:
        """Write one step, flushed to the operating system at once."""
        try:
            self._file.write(json.dumps(_plain(entry), sort_keys=False) + "\n")
            self._file.flush()
        except OSError as error:  # a full disk: a write to a handle names no file
            raise naming(error, self.path)  # noqa: B904 (chained all the same)
        self.lines += 1

    def close(self) -> None:
        """Close the file (idempotent)."""
        if not self._file.closed:
            try:
                self._file.close()
            except OSError as error:
                raise naming(error, self.path)  # noqa: B904 (chained all the same)


SUMMARY_RESERVE = 16_384  # bytes a running summary holds: room for the final one on a full disk


def write_json_atomic(path: Path, data: Mapping[str, Any], reserve: int = 0) -> None:
    """Write ``data`` as indented JSON to ``path``, whole or not at all; ``reserve``: pad the
    file to that many bytes, so that a later version can replace it in place on a full disk
    (:func:`pil.atomic.write_text_reserved`)."""
    write_text_reserved(path, json.dumps(_plain(data), indent=2) + "\n", reserve)


def read_step_log(path: Path) -> list[dict[str, Any]]:
    """Read a step log back (for tests and analysis), through the guarded reader."""
    return read_jsonl_file(Path(path), "log", "the step log")
