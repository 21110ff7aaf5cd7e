"""Can Robin see the pointing hand? Pointing read right per leg and spot, per hand height.

Run: ``python bench/bench_pointing_view.py [--tries 10] [--raise 0,0.15,0.2] [--heldout 336]``.
For each height the drawn-back pointing hand is raised to (``POINT_RAISE``, m), the person
points ``--tries`` times at each of the default table's four legs and four spots (a new
performance each time, arm at home), Robin reads the gesture with its eye cameras, and the
table prints how often it read "pointing" and how often both eyes found the hand. The robot's
own left upper arm hides a hand held low above the left legs and spots.

``--heldout N``: the shipped model on the first N samples of the held-out split (skin tones and
light never trained on, all seven classes) rendered where the data set put them and again with
the hand moved to the drawn-back, raised pointing place (where Robin now reads a pointing and
the thumbs that follow it): hands found, seven-class accuracy (kept readings) and in context.
"""

from __future__ import annotations

import argparse
import time

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from dataclasses import replace  # noqa: E402

import numpy as np  # noqa: E402

import robin_sim.person.body as body_module  # noqa: E402
from pil.task.world import Target  # noqa: E402
from pil.types import Gesture  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402
from robin_sim.vision.classifier import CLASSES, NO_GESTURE, load_shipped  # noqa: E402
from robin_sim.vision.dataset import PLACES, POINT_OFFSET, sample_spec  # noqa: E402
from robin_sim.vision.detector import VisionDetector  # noqa: E402
from robin_sim.vision.render_set import SampleRenderer  # noqa: E402
from robin_sim.vision.train import FEEDBACK_CLASSES, GESTURE_CLASSES  # noqa: E402

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


def heldout(samples: int, moved: bool) -> tuple[float, float, float]:
    """(hands found, seven-class accuracy, in-context accuracy) on held-out samples."""
    renderer, model = SampleRenderer(), load_shipped()
    found = right = in_context = expected = 0
    for index in range(samples):
        spec = sample_spec(0, "heldout", index)
        if moved:  # the same sample, the hand drawn back and raised above a leg or spot
            rng = np.random.default_rng([1, index])
            place = PLACES[rng.integers(len(PLACES))] + POINT_OFFSET
            drawn_back = (body_module.PERSON_CLEAR_X, place[1], place[2] + body_module.POINT_RAISE)
            spec = replace(spec, hand=np.array(drawn_back) + rng.normal(0.0, 0.02, 3))
        rows = [f for f in renderer.render(spec)[0] if f is not None]
        found += bool(rows)
        p = np.zeros(len(CLASSES))
        p[CLASSES.index(NO_GESTURE)] = 1.0
        if rows:
            p = model.probabilities(np.stack(rows)).mean(axis=0)
        label = CLASSES[spec.label]
        right += CLASSES[int(np.argmax(p))] == label and p.max() >= model.threshold
        for classes in (GESTURE_CLASSES, FEEDBACK_CLASSES):
            if label in classes:  # as the robot reads it: only what it expects, or nothing
                keep = [CLASSES.index(c) for c in (*classes, NO_GESTURE)]
                best = keep[int(np.argmax(p[keep]))]
                sure = p[best] / p[keep].sum() >= model.threshold
                in_context += CLASSES[best] == label and sure
                expected += 1
    return found / samples, right / samples, in_context / max(expected, 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=10)
    parser.add_argument("--raise", dest="heights", default="0,0.15,0.2", help="m, comma list")
    parser.add_argument("--heldout", type=int, default=0, help="held-out samples (0: skip)")
    args = smoke.parse_args(parser, tries=1, heights="0", heldout=0)
    if args.heldout:
        print("| held-out samples' hand | hands found | accuracy (7 classes) | in context |")
        print("|---|---|---|---|")
        for moved, where in ((False, "as in the data set"), (True, "drawn back and raised")):
            found, right, in_context = heldout(args.heldout, moved)
            print(f"| {where} | {found:.1%} | {right:.1%} | {in_context:.1%} |", flush=True)
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
