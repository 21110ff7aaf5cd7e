"""Signals at set times after ``robin-pil episode`` starts, and what each run left behind.

:func:`signal_at` starts the real command in its own process group, sends ``how`` to the whole
group ``delay`` seconds after the process was started (render workers included, as a terminal
does), and returns what came of it. Run as a script it sweeps SIGINT and SIGTERM over
0.3-4.8 s in 0.3 s steps, optionally with busy processes beside it::

    MUJOCO_GL=egl PYTHONPATH=. python tests/interrupt_sweep.py --busy 2
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from robin_sim.render.video import probe_video

ARGV = [
    "episode",
    "--scenario",
    "one_handover",
    "--size",
    "160x120",
    "--fps",
    "10",
    "--no-verify",
    "--no-progress",
]
DELAYS = tuple(round(0.3 * k, 1) for k in range(1, 17))  # 0.3 ... 4.8 s


@dataclass
class Outcome:
    """What one interrupted run left: exit code, stderr, summary (None: none) and MP4 frames."""

    code: int
    stderr: str
    summary: dict | None
    video_frames: int | None

    def problems(self) -> list[str]:
        """Everything that breaks the promise (exit 130, interrupted summary, MP4 = summary)."""
        found = []
        if self.code != 130:
            found.append(f"exit code {self.code}")
        if "Traceback" in self.stderr:
            found.append("a traceback")
        if self.summary is None:
            return [*found, "no summary"]
        if self.summary["status"] != "interrupted":
            found.append(f"status {self.summary['status']} ({self.summary['error']})")
        frames = self.summary.get("video", {}).get("frames")
        if self.video_frames is None or frames is None or self.video_frames != frames:
            found.append(f"MP4 frames {self.video_frames} vs summary {frames}")
        return found


def signal_at(delay: float, how: signal.Signals, out: Path) -> Outcome:
    """Run the episode into ``out`` and send ``how`` to its group ``delay`` s after the start."""
    process = subprocess.Popen(
        [sys.executable, "-m", "robin_sim.cli.main", *ARGV, "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )
    started = time.monotonic()
    try:
        time.sleep(max(0.0, delay - (time.monotonic() - started)))
        os.killpg(process.pid, how)
        _, stderr = process.communicate(timeout=180)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    summary_path = out / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else None
    try:
        frames: int | None = probe_video(out / "episode.mp4")["frames"]
    except Exception:  # missing or unreadable: reported as None
        frames = None
    return Outcome(process.returncode, stderr.decode(), summary, frames)


def _sweep(busy: int) -> int:
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(busy)]
    failures = 0
    try:
        with tempfile.TemporaryDirectory() as folder:
            for how in (signal.SIGINT, signal.SIGTERM):
                for delay in DELAYS:
                    began = time.monotonic()
                    result = signal_at(delay, how, Path(folder) / f"{how.name}_{delay}")
                    problems = result.problems()
                    failures += bool(problems)
                    status = None if result.summary is None else result.summary["status"]
                    print(
                        f"{how.name:7} {delay:4.1f} s  exit {result.code}  {status}  "
                        f"mp4 {result.video_frames} frames  {time.monotonic() - began:5.1f} s  "
                        f"{'; '.join(problems) or 'ok'}",
                        flush=True,
                    )
    finally:
        for burner in burners:
            burner.kill()
            burner.wait()
    print(f"{failures} of {2 * len(DELAYS)} runs broke the promise")
    return 1 if failures else 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--busy", type=int, default=0, help="busy processes beside the sweep")
    sys.exit(_sweep(parser.parse_args().busy))
