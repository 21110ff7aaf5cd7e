"""Held-out accuracy per factor: pose jitter, hand height, skin tone (robin_sim.vision.factors).

Run: ``python bench/bench_vision_factors.py [--samples 144] [--model FILE ...] [--workers 2]``.
Renders ``--samples`` held-out samples per factor level into ``--out`` (kept: a second run, or
a second model, reuses them) and prints, per model, the table of hands found, seven-class
accuracy with its 95 % interval and the in-context detection rate. Default model: the shipped
one.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from robin_sim.vision.classifier import GestureModel, shipped_path
from robin_sim.vision.factors import measure_factors, render_factors, table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=144, help="per factor level")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--model", type=Path, nargs="*", default=None)
    parser.add_argument("--out", type=Path, default=Path("out/vision_factors"))
    args = parser.parse_args()
    started = time.perf_counter()
    render_factors(args.out / "chunks", args.seed, args.samples, args.workers, lambda n: None)
    print(f"rendered in {time.perf_counter() - started:.0f} s", flush=True)
    for path in args.model or [shipped_path()]:
        rows = measure_factors(args.out / "chunks", args.samples, GestureModel.load(path))
        print(f"\nmodel {path}")
        print("\n".join(table(rows)), flush=True)


if __name__ == "__main__":
    main()
