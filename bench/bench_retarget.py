"""What a retargeting fit costs: the closed-form guess alone against the guess refined.

Run: ``python bench/bench_retarget.py [--repeats 5]``. Pinned to one core. Each repeat fits
every stored tracker reading of the real footage (``tests/data/hands/landmarks.npz``: the fist,
palm and thumb-up clips) onto the person's right hand with
:meth:`robin_sim.figure.retarget.Retargeter.fit`, once with ``refine=False`` (the baseline,
measured in the same run) and once refined by least squares, interleaved. Prints the median
milliseconds per fit of each and the ratio to the baseline. ``live --webcam`` fits one reading
per tracker frame on the physics thread.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke

from robin_sim.figure.retarget import Retargeter
from robin_sim.model.scene import build_model

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from hand_data import footage

CLIPS = ("fist", "palm", "thumb_up")


def readings(limit: int | None) -> list[tuple[np.ndarray, float, bool]]:
    """The footage's readings with a hand: landmarks, aspect, whether to mirror."""
    reads = footage()
    out = []
    for i in np.flatnonzero(np.isin(reads["sequence"], CLIPS)):
        points = reads["landmarks"][i].astype(float)
        if np.isfinite(points).all() and reads["handedness"][i]:
            out.append((points, float(reads["aspect"][i]), reads["handedness"][i] == "Right"))
    return out[:limit]


def per_fit_ms(retargeter: Retargeter, frames: list, refine: bool) -> float:
    """Milliseconds per fit over ``frames``."""
    started = time.perf_counter()
    for points, aspect, mirror in frames:
        retargeter.fit(points, aspect, mirror, refine=refine)
    return (time.perf_counter() - started) * 1000 / len(frames)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--frames", type=int, default=None, help="readings per repeat (all)")
    args = smoke.parse_args(parser, repeats=1, frames=3)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    retargeter = Retargeter(build_model())
    frames = readings(args.frames)
    times: dict[bool, list[float]] = {False: [], True: []}
    for _ in range(args.repeats):
        for refine in (False, True):
            times[refine].append(per_fit_ms(retargeter, frames, refine))
    base = statistics.median(times[False])
    print(f"{len(frames)} readings per repeat, {args.repeats} repeats, medians")
    print("| fit | ms per fit | ratio to baseline |")
    print("|---|---|---|")
    for refine, label in ((False, "closed-form guess (baseline)"), (True, "guess + least squares")):
        median = statistics.median(times[refine])
        print(f"| {label} | {median:.3f} | {median / base:.1f} |")


if __name__ == "__main__":
    main()
