"""A few cells of the signal matrix (:mod:`signal_matrix`; the whole of it, 72 cells, runs by
hand): the commands and moments the twelve cases of ``test_signals.py`` leave out, the live
server and a signal while a command is still starting, with SIGINT inherited and ignored."""

from __future__ import annotations

import signal
from pathlib import Path

import pytest
from signal_matrix import cell

pytestmark = pytest.mark.slow

CELLS = [
    ("live", signal.SIGTERM, 2.0, True),
    ("live", signal.SIGINT, 0.5, False),
    ("people-appearance", signal.SIGTERM, 0.5, True),
]


@pytest.mark.parametrize(
    ("name", "how", "at", "ignored"),
    CELLS,
    ids=[f"{n}-{h.name}-{t}s-{'ignored' if i else 'inherited'}" for n, h, t, i in CELLS],
)
def test_a_cell_of_the_signal_matrix_keeps_the_promise(
    tmp_path: Path, name: str, how: signal.Signals, at: float, ignored: bool
) -> None:
    ended, problems = cell(name, how, at, ignored, tmp_path)
    assert problems == [], ended
