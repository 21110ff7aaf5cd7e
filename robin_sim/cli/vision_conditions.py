"""``robin-pil vision-conditions``: measured detection rate per camera condition, PIL's costs.

Renders the gesture data set under each light scale x pixel noise condition, reads it with
the shipped gesture model, writes each condition's measured error model and runs the
learner-only study with it beside the paper's dice (see :mod:`robin_sim.vision.conditions`).
Resumable: rendered chunks under ``OUT/chunks`` are kept.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.cli.options import add_progress_switch, whole_number


def _numbers(text: str, what: str, low: float, high: float) -> tuple[float, ...]:
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise RobinPilError(f"{what}: give numbers separated by commas, got {text!r}") from None
    if not values or any(not low <= v <= high for v in values):
        raise RobinPilError(f"{what}: each value must lie in [{low:g}, {high:g}], got {text!r}")
    return values


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options."""
    parser.add_argument("--lighting", default="1,0.5,0.25,0.12", help="light scales (1 = scene)")
    parser.add_argument("--noise", default="0,12,24", help="pixel noise sds, 8-bit units")
    parser.add_argument("--samples", type=whole_number, default=336, help="samples per condition")
    parser.add_argument("--reps", type=whole_number, default=10, help="study repetitions per point")
    parser.add_argument("--seed", type=whole_number, default=0, help="seed (default: %(default)s)")
    parser.add_argument("--workers", type=whole_number, default=2, help="render processes")
    parser.add_argument(
        "--out", type=Path, default=Path("out/vision_conditions"), help="output folder"
    )
    add_progress_switch(parser)


def run(args: argparse.Namespace) -> int:
    """Validate, render (resuming), measure, study; print what was written."""
    from tqdm import tqdm

    from pil.cpus import cpu_count
    from robin_sim.vision.build_config import MIN_SAMPLES
    from robin_sim.vision.conditions import run_conditions

    lighting = _numbers(args.lighting, "--lighting", 0.0, 5.0)
    noise = _numbers(args.noise, "--noise", 0.0, 128.0)
    if args.samples < MIN_SAMPLES:
        raise RobinPilError(f"--samples must be >= {MIN_SAMPLES}, got {args.samples}")
    if args.reps < 2 or not 1 <= args.workers <= cpu_count():
        raise RobinPilError(
            f"--reps must be >= 2 and --workers from 1 to {cpu_count()} (the CPUs here), got "
            f"{args.reps}, {args.workers}"
        )
    total = len(lighting) * len(noise) * (-(-args.samples // 48) * 48)
    with tqdm(
        total=total, desc="render", unit="sample", file=sys.stderr, disable=args.no_progress
    ) as bar:
        written = run_conditions(
            args.out,
            seed=args.seed,
            samples=args.samples,
            reps=args.reps,
            workers=args.workers,
            lighting=lighting,
            noise=noise,
            progress=bar.update,
        )
    print("wrote " + ", ".join(str(p) for p in written))
    return 0
