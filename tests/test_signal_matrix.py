"""A cell of the signal matrix (:mod:`signal_matrix`; the whole of it, 72 cells, runs by hand)
that the twelve cases of ``test_signals.py`` leave out: the live server, started with SIGINT
ignored, SIGTERM to its group while it starts (its rerun stopped in turn)."""

from __future__ import annotations

import signal
from pathlib import Path

import pytest
from signal_matrix import cell

pytestmark = pytest.mark.slow

CELLS = [("live", signal.SIGTERM, 2.0, True)]


@pytest.mark.parametrize(
    ("name", "how", "at", "ignored"),
    CELLS,
    ids=[f"{n}-{h.name}-{t}s-{'ignored' if i else 'default'}" for n, h, t, i in CELLS],
)
def test_a_cell_of_the_signal_matrix_keeps_the_promise(
    tmp_path: Path, name: str, how: signal.Signals, at: float, ignored: bool
) -> None:
    ended, problems = cell(name, how, at, ignored, tmp_path)
    assert problems == [], ended
