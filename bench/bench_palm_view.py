"""Is the give-me palm at the handover point read as "give me"? Per arm state, per model.

Run: ``python bench/bench_palm_view.py [--tries 6] [--model FILE ...]``. The arm is brought by
real actions to each state it is in when the person may ask for a leg
(:mod:`robin_sim.episode.palm_check`: home, closed on a leg, holding it over the palm, holding
a leg over a spot); there the person holds the palm out at the handover point and Robin reads
it ``--tries`` times (a new performance each time), in context as in an episode. Prints per
model and state the readings that were "give me" and what the others were. Default model: the
shipped one.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.episode.palm_check import PALM_STATES, palm_readings  # noqa: E402
from robin_sim.vision.classifier import GestureModel, shipped_path  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=6, help="readings per arm state")
    parser.add_argument("--model", type=Path, nargs="*", default=None)
    parser.add_argument("--seed", type=int, default=0, help="the readings' performances")
    args = smoke.parse_args(parser, tries=1)
    states = PALM_STATES[:1] if args.smoke else PALM_STATES
    print("| model | " + " | ".join(states) + " | all | other readings | wall s |")
    print("|---|" + "---|" * (len(states) + 3))
    for path in args.model or [shipped_path()]:
        started = time.perf_counter()
        reads = palm_readings(args.tries, states, GestureModel.load(path), args.seed)
        right = {s: sum(r == "give_me" for r in reads[s]) for s in states}
        other = Counter(r for s in states for r in reads[s] if r != "give_me")
        cells = " | ".join(f"{right[s]}/{len(reads[s])}" for s in states)
        total = sum(right.values())
        others = ", ".join(f"{k} {v}" for k, v in sorted(other.items())) or "-"
        wall = time.perf_counter() - started
        print(
            f"| {path} | {cells} | {total}/{args.tries * len(states)} | {others} | {wall:.0f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
