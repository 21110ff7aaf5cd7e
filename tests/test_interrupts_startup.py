"""Ctrl-C (SIGINT) and SIGTERM to the process group during the episode's start-up, render
workers still importing included: every run exits 130 with an ``interrupted`` summary and an MP4
whose decoded frames equal the summary's count.

The CI test sends the two signals in turns at every other time of the full sweep, 0.6 s apart
(SIGINT at 0.3, 1.5, 2.7, 3.9 s; SIGTERM at 0.9, 2.1, 3.3, 4.5 s), to keep the suite short;
``python tests/interrupt_sweep.py --busy 2`` sends both at all 16 times (0.3-4.8 s in 0.3 s
steps) with two busy processes beside it.
"""

from __future__ import annotations

import signal
from pathlib import Path

import pytest
from interrupt_sweep import DELAYS, signal_at

pytestmark = pytest.mark.slow

TURNS = [
    (delay, signal.SIGINT if k % 2 == 0 else signal.SIGTERM) for k, delay in enumerate(DELAYS[::2])
]


@pytest.mark.parametrize(("delay", "how"), TURNS, ids=[f"{h.name}-{d}s" for d, h in TURNS])
def test_a_signal_during_start_up_leaves_consistent_outputs(
    tmp_path: Path, delay: float, how: signal.Signals
) -> None:
    result = signal_at(delay, how, tmp_path / "out")
    assert result.problems() == [], result.stderr
    assert "interrupted" in result.stderr
