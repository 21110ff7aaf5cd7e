"""Vision episode speed: the same episode read by the study's detector and by the eye cameras.

Run: ``python bench/bench_vision_episode.py [--repeats 3] [--video]
[--scenario scenarios/one_handover.yaml]``.
Runs the episode (seed 0, render checks off) with ``--detector exact`` (the baseline) and
``--detector vision``, in turns, ``--repeats`` times each, without video (``--video``: 640x480
at 30 fps, the eye inset showing each reading), and prints the medians: wall and simulated
seconds, real-time factor, readings, and the vision episode's wall time over the baseline's.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from pil.task.scenario import SCENARIOS_DIR  # noqa: E402
from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402

DETECTORS = ("exact", "vision")


def one(scenario: Path, detector: str, video: bool) -> tuple[float, float, int]:
    """(wall s, simulated s, readings) of one episode."""
    with tempfile.TemporaryDirectory() as folder:
        config = EpisodeConfig(
            scenario=scenario,
            out=Path(folder),
            video=video,
            verify=False,
            progress=False,
            params={"detector": detector},
        )
        started = time.perf_counter()
        summary = run_episode(config)
        wall = time.perf_counter() - started
    vision = summary.get("vision", {})
    readings = vision.get("gestures_read", 0) + vision.get("feedback_read", 0)
    return wall, summary["sim_time_s"], readings


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--video", action="store_true")
    parser.add_argument("--scenario", type=Path, default=SCENARIOS_DIR / "one_handover.yaml")
    args = smoke.parse_args(parser, repeats=1)
    runs: dict[str, list[tuple[float, float, int]]] = {d: [] for d in DETECTORS}
    for _ in range(args.repeats):
        for detector in DETECTORS:  # in turns: load changes hit both alike
            runs[detector].append(one(args.scenario, detector, args.video))
    walls = {d: statistics.median(r[0] for r in runs[d]) for d in DETECTORS}
    print(
        f"{args.scenario.name}, {'video 640x480' if args.video else 'no video'}, "
        f"median of {args.repeats}"
    )
    print("| detector | wall s | simulated s | × real time | readings | wall × exact |")
    print("|---|---|---|---|---|---|")
    for detector in DETECTORS:
        sim = statistics.median(r[1] for r in runs[detector])
        readings = statistics.median(r[2] for r in runs[detector])
        print(
            f"| {detector} | {walls[detector]:.1f} | {sim:.1f} | {sim / walls[detector]:.1f} "
            f"| {readings:.0f} | {walls[detector] / walls['exact']:.2f} |"
        )


if __name__ == "__main__":
    main()
