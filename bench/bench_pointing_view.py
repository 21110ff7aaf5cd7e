"""Can Robin see the pointing hand? Pointing read right per leg and spot, per hand height.

Run: ``python bench/bench_pointing_view.py [--tries 10] [--raise 0,0.15,0.2]``.
For each height the drawn-back pointing hand is raised to (``POINT_RAISE``, m), the person
points ``--tries`` times at each of the default table's four legs and four spots (a new
performance each time, arm at home), Robin reads the gesture with its eye cameras, and the
table prints how often it read "pointing" and how often both eyes found the hand. The robot's
own left upper arm hides a hand held low above the left legs and spots.
"""

from __future__ import annotations

import argparse
import time

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

import robin_sim.person.body as body_module  # noqa: E402
from pil.task.world import Target  # noqa: E402
from pil.types import Gesture  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402
from robin_sim.vision.detector import VisionDetector  # noqa: E402

TARGETS = [Target("leg", k) for k in range(4)] + [Target("spot", k) for k in range(4)]


def measure(raise_by: float, tries: int) -> tuple[list[int], list[int], int]:
    """(read right, both eyes found) per target, and the person's contacts with the robot."""
    body_module.POINT_RAISE = raise_by  # the body reads it at each pointing
    world = PhysicalWorld()
    world.start_table(0)
    body = body_module.PhysicalBody(world)
    detector = VisionDetector(world.sim, display=body.display, seed=1)
    right, found = [], []
    for target in TARGETS:
        ok = both = 0
        for _ in range(tries):
            body.perform(Gesture.POINTING, target)
            ok += detector.detect(Gesture.POINTING) is Gesture.POINTING
            both += all(box is not None for box in detector.records[-1].boxes)
            body.rest()
        right.append(ok)
        found.append(both)
    detector.close()
    return right, found, world.person_contacts.events


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=10)
    parser.add_argument("--raise", dest="heights", default="0,0.15,0.2", help="m, comma list")
    args = parser.parse_args()
    names = [f"{t.kind} {t.index}" for t in TARGETS]
    print("| raised (m) | " + " | ".join(names) + " | all | both eyes found | contacts |")
    print("|---" * (len(names) + 4) + "|")
    for text in args.heights.split(","):
        started = time.perf_counter()
        right, found, contacts = measure(float(text), args.tries)
        cells = " | ".join(f"{r}/{args.tries}" for r in right)
        total = len(TARGETS) * args.tries
        print(
            f"| {float(text):g} | {cells} | {sum(right)}/{total} | {sum(found)}/{total} "
            f"| {contacts} |  ({time.perf_counter() - started:.0f} s)",
            flush=True,
        )


if __name__ == "__main__":
    main()
