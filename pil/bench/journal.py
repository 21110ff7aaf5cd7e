"""Where a benchmark run keeps its results: a journal of runs, stamped, resumable.

``OUT/stamp.json`` says what the folder holds (suite version, the suite's hash over its file
and its conditions' files, each condition file's hash, seed block, quick or not, the git
commit of the code that started it, and of any that resumed it: ``resumed_at``);
``OUT/runs.jsonl`` has one JSON line per finished run, appended and flushed as each ends, so an
interrupted run loses only the runs under way and the same command resumes it (finished keys
are skipped). A folder of another suite (its file or a file its conditions read), block or
mode is refused before anything runs, naming what changed.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.bench.suite import Suite, SuiteError
from pil.provenance import source_commit

STAMP, RUNS = "stamp.json", "runs.jsonl"
KEY = ("track", "condition", "agent", "seed")
_SAME = ("suite_version", "suite_sha256", "block", "quick")


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
        self.rows = read_runs(self.out)
        self.done = {key_of(r) for r in self.rows}

    @staticmethod
    def read_stamp(out: Path) -> dict[str, Any] | None:
        """The folder's stamp (None: a new folder)."""
        path = Path(out) / STAMP
        if not path.is_file():
            return None
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as error:
            raise SuiteError(f"{path}: not a benchmark stamp ({error})") from None
        return data if isinstance(data, dict) else None

    def open(self) -> None:
        """Create the folder and write the stamp (the commit of this session's code)."""
        self.out.mkdir(parents=True, exist_ok=True)
        write_text_atomic(self.out / STAMP, json.dumps(self.stamp, indent=1) + "\n")

    def add(self, rows: Iterable[Mapping[str, Any]]) -> None:
        """Append finished runs (one line each, flushed)."""
        with open(self.out / RUNS, "a", encoding="utf-8") as handle:
            for row in rows:
                handle.write(json.dumps(_plain(row), sort_keys=True) + "\n")
                self.rows.append(dict(row))
                self.done.add(key_of(row))
            handle.flush()


def _plain(row: Mapping[str, Any]) -> dict[str, Any]:
    return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in row.items()}


def read_runs(out: str | Path) -> list[dict[str, Any]]:
    """The journal's rows (NaN for the nulls; a torn last line is left out)."""
    path = Path(out) / RUNS
    if not path.is_file():
        return []
    rows = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            row = json.loads(line)
        except ValueError:
            continue  # the line being written when the run was stopped
        rows.append({k: (math.nan if v is None else v) for k, v in row.items()})
    return rows


def sorted_runs(rows: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Rows in a fixed order (by key), the last of a duplicated key kept."""
    by_key = {key_of(r): dict(r) for r in rows}
    return [by_key[k] for k in sorted(by_key)]
