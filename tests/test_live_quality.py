"""The live stream gives way on a busy machine, and says so (robin_sim.live.quality).

The governor's rules on a given clock (fast), then a real session whose stream is held at a
lowered level: every third frame is rendered and stands for three frames of the MP4, which
keeps its rate and length; the page's status and ``events.jsonl`` tell of each change.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import av
import pytest

from robin_sim.live.quality import LEVELS, UP_AFTER_S, WARMUP_S, WINDOW_S, StreamGovernor
from robin_sim.live.session import LiveConfig, LiveSession


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_no_headroom_lowers_one_level_a_window_and_calm_raises_it_again() -> None:
    clock, changes = Clock(), []
    governor = StreamGovernor(clock, lambda level, why: changes.append((level, why)))
    slept = 0.0
    clock.now += WARMUP_S  # the warm-up is not measured
    governor.observe(slept, 0)
    for _ in range(3):  # busy: 5 % of each second slept
        clock.now += WINDOW_S
        slept += 0.05 * WINDOW_S
        governor.observe(slept, 0)
    assert [level for level, _ in changes] == [1, 2, 3]
    assert "busy (5% of the time to spare)" in changes[0][1]
    assert governor.state(15.0) == {
        "level": 3,
        "lowered": True,
        "fps": round(15.0 / LEVELS[3].stride, 2),
        "inset": False,
        "changes": 3,
    }
    steps = 0
    while governor.level == 3:  # calm: 80 % slept
        clock.now += WINDOW_S
        slept += 0.8 * WINDOW_S
        governor.observe(slept, 0)
        steps += 1
    assert governor.level == 2 and steps * WINDOW_S >= UP_AFTER_S
    governor.hold(30.0)  # a pause of 30 s: nothing slept, nothing measured
    clock.now += 30.0 + WINDOW_S
    governor.observe(slept + 0.8 * WINDOW_S, 0)
    assert governor.level == 2


def test_falling_behind_lowers_and_a_fixed_stream_never_moves() -> None:
    clock = Clock()
    governor = StreamGovernor(clock)
    clock.now += WARMUP_S + WINDOW_S
    governor.observe(0.9, 2)  # slept plenty, but physics fell behind twice
    assert governor.level == 1
    fixed = StreamGovernor(clock, adaptive=False, level=2)
    for k in range(10):
        clock.now += WINDOW_S
        fixed.observe(0.0, k)
    assert fixed.level == 2 and fixed.changes == 0


@pytest.mark.slow
def test_a_lowered_stream_keeps_the_videos_rate_and_length(tmp_path: Path) -> None:
    config = LiveConfig(
        out_root=tmp_path, speed=3.0, fps=10.0, stream_level=3, adaptive_stream=False
    )
    live = LiveSession(config)
    live.start()
    deadline = time.monotonic() + 120
    while (live.latest_frame() is None or live.body.world.time < 15.0) and not live.done.is_set():
        assert time.monotonic() < deadline, live.status()
        time.sleep(0.05)
    shown = live.status()["stream"]
    summary = live.stop("ended")
    assert shown == {"level": 3, "lowered": True, "fps": 3.33, "inset": False, "changes": 0}
    streamed, video = summary["live"]["frames_streamed"], summary["video"]["frames"]
    seconds = summary["sim_time_s"]
    # a frame is due every speed / fps s of sim time (at pace: fps a wall second), lowered or not
    assert video == pytest.approx(seconds * 10.0 / 3.0, abs=2)
    assert streamed == pytest.approx(video / 3, abs=2)  # every third frame rendered
    with av.open(str(tmp_path / "P01" / live.out_dir.name / "episode.mp4")) as mp4:
        decoded = sum(1 for _ in mp4.decode(video=0))
    assert decoded == video
    assert not (live.out_dir / "events.jsonl").exists() or all(
        json.loads(line)["event"] != "stream"
        for line in (live.out_dir / "events.jsonl").read_text().splitlines()
    )
