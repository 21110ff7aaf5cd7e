"""Ctrl-C (SIGINT to the whole process group) and SIGTERM at any moment of a video episode.

Each test starts ``robin-pil episode`` as a real process in its own process group, waits for a
moment of the episode (start-up, first frames, mid-episode, the last step, i.e. the final
encode), sends the signal to the whole group with ``os.killpg`` (render workers included, as a
terminal does), and checks: exit code 130, ``"status": "interrupted"``, and an MP4 that PyAV
decodes with exactly the number of frames the summary reports.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from robin_sim.render.video import probe_video

pytestmark = pytest.mark.slow

ARGV = [
    "episode",
    "--scenario",
    "one_handover",
    "--size",
    "160x120",
    "--fps",
    "10",
    "--no-verify",
    "--quiet",
]


def _lines(path: Path) -> list[dict]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.endswith("}")]


MOMENTS: dict[str, Callable[[Path], bool]] = {
    "startup": lambda out: out.is_dir(),  # the folder exists: set-up has begun
    "first_frames": lambda out: (
        (out / "episode.mp4").exists() and (out / "episode.mp4").stat().st_size > 0
    ),
    "mid_episode": lambda out: len(_lines(out / "episode.jsonl")) >= 3,
    "final_encode": lambda out: any(
        r.get("legs_delivered") == 1 for r in _lines(out / "episode.jsonl")
    ),
}


def interrupt(tmp_path: Path, moment: str, how: signal.Signals, workers: str = "2") -> dict:
    out = tmp_path / "out"
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            *ARGV,
            "--render-workers",
            workers,
            "--out",
            str(out),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    try:
        deadline = time.monotonic() + 240
        while not MOMENTS[moment](out):
            assert process.poll() is None, process.stderr.read().decode()
            assert time.monotonic() < deadline, f"the episode never reached {moment}"
            time.sleep(0.005)
        os.killpg(process.pid, how)
        _, stderr = process.communicate(timeout=120)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    text = stderr.decode()
    assert process.returncode == 130, text
    assert "Traceback" not in text and "interrupted" in text
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted", summary
    video = probe_video(out / "episode.mp4")
    assert video["frames"] == summary["video"]["frames"] >= 1
    assert (video["codec"], video["width"], video["height"]) == ("h264", 160, 120)
    assert len(_lines(out / "episode.jsonl")) == summary["actions"] + summary["repeats"]
    return summary


@pytest.mark.parametrize("moment", list(MOMENTS))
def test_ctrl_c_to_the_process_group_leaves_consistent_outputs(tmp_path: Path, moment: str) -> None:
    summary = interrupt(tmp_path, moment, signal.SIGINT)
    if moment == "final_encode":
        assert summary["legs_delivered"] == 1


@pytest.mark.parametrize("moment", ["first_frames", "mid_episode"])
def test_sigterm_is_handled_as_ctrl_c(tmp_path: Path, moment: str) -> None:
    interrupt(tmp_path, moment, signal.SIGTERM)


def test_ctrl_c_with_in_process_rendering(tmp_path: Path) -> None:
    interrupt(tmp_path, "mid_episode", signal.SIGINT, workers="0")
