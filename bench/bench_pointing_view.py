"""Can Robin see the pointing hand? Pointing read right per leg and spot, per arm state.

Run: ``python bench/bench_pointing_view.py [--tries 5] [--states home,open] [--raise 0.2]
[--heldout 336]``. The arm is brought by real actions to each state it is in when the person
points during an episode (:mod:`robin_sim.vision.arm_states`: home, at a leg, closed on it,
holding it over the palm, after the open over the palm, holding a leg over a spot, after the
open over the spot); there the person points ``--tries`` times at each leg on the table and each
spot (a new performance each time), Robin reads the gesture with its eye cameras, and the table
prints how often it read "pointing", how often both eyes found the hand and the smallest hand
box (pixels tall; Robin's own hand in the way cuts the box short). ``--raise`` sets how far
the drawn-back pointing hand is raised (``POINT_RAISE``, m; a comma list).

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

from dataclasses import dataclass, field, replace  # noqa: E402

import numpy as np  # noqa: E402

import robin_sim.person.body as body_module  # noqa: E402
from pil.task.world import Target  # noqa: E402
from pil.types import Gesture  # noqa: E402
from robin_sim.model.robot_spec import POINT_OFFSET  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402
from robin_sim.vision.arm_states import ARM_STATES, arm_states, on_table  # noqa: E402
from robin_sim.vision.classifier import load_shipped  # noqa: E402
from robin_sim.vision.dataset import PLACES, sample_spec, split_of_views  # noqa: E402
from robin_sim.vision.detector import VisionDetector  # noqa: E402
from robin_sim.vision.render_set import SampleRenderer  # noqa: E402
from robin_sim.vision.train import evaluate  # noqa: E402

TARGETS = [Target("leg", k) for k in range(4)] + [Target("spot", k) for k in range(4)]


@dataclass
class StateRow:
    """One arm state's counts: per target (read right, tries), both eyes found, box heights."""

    state: str
    right: dict[str, int] = field(default_factory=dict)
    tries: dict[str, int] = field(default_factory=dict)
    both: int = 0
    heights: list[int] = field(default_factory=list)


def measure(raise_by: float, tries: int, states: set[str]) -> tuple[list[StateRow], int]:
    """Per arm state the counts of :class:`StateRow`, and the person's contacts with the robot."""
    body_module.POINT_RAISE = raise_by  # the body reads it at each pointing
    world = PhysicalWorld()
    body = body_module.PhysicalBody(world)
    detector = VisionDetector(world.sim, display=body.display, seed=1)
    rows = []
    try:
        for state in arm_states(world, body):
            if state not in states:
                continue
            row = StateRow(state)
            for target in TARGETS:
                if not on_table(world, target):
                    continue
                name = f"{target.kind} {target.index}"
                row.right[name], row.tries[name] = 0, tries
                for _ in range(tries):
                    body.perform(Gesture.POINTING, target)
                    row.right[name] += detector.detect(Gesture.POINTING) is Gesture.POINTING
                    boxes = detector.records[-1].boxes
                    row.both += all(box is not None for box in boxes)
                    row.heights.append(min((b[3] for b in boxes if b is not None), default=0))
                    body.rest()
            rows.append(row)
    finally:
        detector.close()
    return rows, world.person_contacts.events


def heldout(samples: int, moved: bool) -> tuple[float, float, float]:
    """(hands found, seven-class accuracy, in-context accuracy of the instruction gestures and
    thumbs) on held-out samples, read as the data set's report reads them."""
    renderer, model = SampleRenderer(), load_shipped()
    views = []
    for index in range(samples):
        spec = sample_spec(0, "heldout", index)
        if moved:  # the same sample, the hand drawn back and raised above a leg or spot
            rng = np.random.default_rng([1, index])
            place = PLACES[rng.integers(len(PLACES))] + POINT_OFFSET
            drawn_back = (body_module.PERSON_CLEAR_X, place[1], place[2] + body_module.POINT_RAISE)
            spec = replace(spec, hand=np.array(drawn_back) + rng.normal(0.0, 0.02, 3))
        views.append((index, spec.label, renderer.render(spec)[0]))
    split = split_of_views(views)
    found = np.mean([any(c is not None for c in crops) for _, _, crops in views])
    figures = evaluate(model, split)
    in_context = np.trace(figures.gestures[:, :-1]) + np.trace(figures.feedback[:, :-1])
    expected = figures.gestures.sum() + figures.feedback.sum()
    return float(found), figures.accuracy, float(in_context / max(expected, 1))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tries", type=int, default=5)
    parser.add_argument("--states", default=",".join(ARM_STATES), help="arm states, comma list")
    parser.add_argument("--raise", dest="heights", default="0.2", help="m, comma list")
    parser.add_argument("--heldout", type=int, default=0, help="held-out samples (0: skip)")
    args = smoke.parse_args(parser, tries=1, heights="0", heldout=0)
    if args.heldout:
        print("| held-out samples' hand | hands found | accuracy (7 classes) | in context |")
        print("|---|---|---|---|")
        for moved, where in ((False, "as in the data set"), (True, "drawn back and raised")):
            found, right, in_context = heldout(args.heldout, moved)
            print(f"| {where} | {found:.1%} | {right:.1%} | {in_context:.1%} |", flush=True)
    names = [f"{t.kind} {t.index}" for t in TARGETS]
    for text in args.heights.split(","):
        started = time.perf_counter()
        rows, contacts = measure(float(text), args.tries, set(args.states.split(",")))
        print(f"\ndrawn-back hand raised {float(text):g} m, {args.tries} tries per cell")
        head = " | ".join(names) + " | all | both eyes found | smallest box (px) |"
        print("| arm state | " + head)
        print("|---" * (len(names) + 4) + "|")
        for row in rows:
            cells = " | ".join(
                f"{row.right[n]}/{row.tries[n]}" if n in row.right else "-" for n in names
            )
            total = sum(row.tries.values())
            print(
                f"| {row.state} | {cells} | {sum(row.right.values())}/{total} "
                f"| {row.both}/{total} | {min(row.heights)} |",
                flush=True,
            )
        print(f"person contacts: {contacts}  ({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
