"""Run functions for the sweep tests, named by import path (``"sweep_test_runs:paced_run"``).

They wrap a real learner-only run (:func:`learner_rows.learner_row`) and add what a test needs to
control: a pause (so a sweep can be interrupted midway), a worker process that dies, and a
run that fails on its first attempt only. Not collected by pytest (no ``test_`` prefix).
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

from learner_rows import learner_row

from pil.task.parts import DEFAULT_VALUES
from pil.task.systems import SYSTEMS

PARAMS: dict[str, Any] = {**DEFAULT_VALUES, "delay": 0.0, "die": "", "marks": ""}
__all__ = ["PARAMS", "SYSTEMS", "flaky_run", "learner_run", "paced_run", "self_failing_run"]


def learner_run(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """A learner run's row, as a custom run function (its values parsed again: its own)."""
    return learner_row(system, rate, seed, **params)


def paced_run(
    system: str, rate: float, seed: int, *, delay: float = 0.0, die: str = "", **params: Any
) -> dict[str, Any]:
    """A learner run after ``delay`` seconds; the worker process exits (code 3) when
    ``die`` names ``system``, as a crash in native code would end it."""
    if die == system:
        os._exit(3)
    time.sleep(delay)
    return learner_row(system, rate, seed, **params)


def flaky_run(system: str, rate: float, seed: int, *, marks: str, **params: Any) -> dict[str, Any]:
    """A learner run, but the first attempt of each run raises (a mark file records it)."""
    mark = Path(marks) / f"{system}-{rate}-{seed}"
    if not mark.exists():
        mark.touch()
        raise RuntimeError(f"first attempt of {mark.name} fails on purpose")
    return learner_row(system, rate, seed, **params)


def self_failing_run(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """A learner run's row marked ``status: failed`` by the run itself (as an episode may)."""
    return {**learner_row(system, rate, seed, **params), "status": "failed", "error": "gave up"}
