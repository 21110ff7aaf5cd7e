"""Whole-table vision episodes: every place read right, per seed.

Run: ``python bench/bench_vision_places.py [--seeds 0,1,2,3,4] [--lighting 1] [--out DIR]``.
One at a time, runs ``robin-pil episode --detector vision --no-video`` (the default assembly:
one table, four legs) at each seed and prints per seed: status, gestures, actions, legs, the
``vision`` block's measured detection rate and outcomes (misread, discarded, no hand), and per
leg and spot how often a pointing at it was read right (each performance of an instruction
gesture counts once, from ``episode.jsonl``); then the places over all seeds. An episode's
files stay under ``--out/seed-N``.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import Counter
from pathlib import Path

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402

PLACES = [f"leg {k}" for k in range(4)] + [f"spot {k}" for k in range(4)]


def pointings(log: Path) -> tuple[Counter[str], Counter[str]]:
    """(read right, performed) per pointed place, each performance counted once."""
    right: Counter[str] = Counter()
    seen: Counter[str] = Counter()
    counted: set[int] = set()
    for line in log.read_text().splitlines():
        entry = json.loads(line)
        if entry["true_gesture"] != "pointing" or entry["target"] is None:
            continue
        if entry["gesture_count"] in counted:
            continue
        counted.add(entry["gesture_count"])
        place = f"{entry['target']['kind']} {entry['target']['index']}"
        seen[place] += 1
        right[place] += entry["detected_gesture"] == "pointing"
    return right, seen


def cell(right: int, seen: int) -> str:
    return f"{right}/{seen}" if seen else "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0,1,2,3,4")
    parser.add_argument("--lighting", default="1")
    parser.add_argument("--out", type=Path, default=Path("out/vision_places"))
    args = parser.parse_args()
    total_right: Counter[str] = Counter()
    total_seen: Counter[str] = Counter()
    print(
        "| seed | status | gestures | actions | legs | wall s | detection rate | misread | "
        "discarded | no hand | " + " | ".join(PLACES) + " |"
    )
    print("|---" * (10 + len(PLACES)) + "|", flush=True)
    for seed in (int(s) for s in args.seeds.split(",")):
        out = args.out / f"seed-{seed}"
        params = {"detector": "vision", "lighting": args.lighting}
        config = EpisodeConfig(seed=seed, out=out, video=False, progress=False, params=params)
        started = time.perf_counter()
        summary = run_episode(config)
        wall = time.perf_counter() - started
        v = summary["vision"]
        right, seen = pointings(out / "episode.jsonl")
        total_right.update(right)
        total_seen.update(seen)
        cells = " | ".join(cell(right[p], seen[p]) for p in PLACES)
        print(
            f"| {seed} | {summary['status']} | {summary['gestures']} | {summary['actions']} | "
            f"{summary['legs_delivered']}/{summary['legs_total']} | {wall:.0f} | "
            f"{v['detection_rate']:.3f} | {v['misread']} | {v['discarded']} | {v['no_hand']} | "
            f"{cells} |",
            flush=True,
        )
    cells = " | ".join(cell(total_right[p], total_seen[p]) for p in PLACES)
    print(f"| all | | | | | | | | | | {cells} |")


if __name__ == "__main__":
    main()
