"""The episode's step log (JSON lines, flushed per step) and the atomic summary writer."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from pil.types import Action, Gesture
from robin_sim.episode.log import StepLog, read_step_log, write_json_atomic


def test_each_step_is_one_complete_line_on_disk_as_soon_as_it_is_written(tmp_path: Path) -> None:
    path = tmp_path / "log" / "episode.jsonl"
    with StepLog(path) as log:
        log.write({"t": 1, "action": Action.OBJECT, "pos": np.array([0.5, 0.25])})
        # flushed: another reader sees the complete line while the log is still open
        assert json.loads(path.read_text().splitlines()[0]) == {
            "t": 1,
            "action": "object",
            "pos": [0.5, 0.25],
        }
        log.write({"t": 2, "gesture": Gesture.GIVE_ME, "n": np.int64(3), "ok": np.bool_(True)})
    assert read_step_log(path) == [
        {"t": 1, "action": "object", "pos": [0.5, 0.25]},
        {"t": 2, "gesture": "give me", "n": 3, "ok": True},
    ]
    assert log.lines == 2


class _Unwritable:
    """A value whose text form fails, as a disk or a bug might fail halfway through a write."""

    def __str__(self) -> str:
        raise RuntimeError("this value cannot be written")


def test_atomic_summary_keeps_the_old_file_when_writing_fails(tmp_path: Path) -> None:
    path = tmp_path / "summary.json"
    write_json_atomic(path, {"status": "finished", "legs": 4})
    with pytest.raises(RuntimeError, match="cannot be written"):
        write_json_atomic(path, {"bad": _Unwritable()})
    assert json.loads(path.read_text()) == {"status": "finished", "legs": 4}
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]  # no temporary file left
