"""Cost of the person watching every control tick (issue 9's closed loop).

Run: ``python bench/bench_watching.py [--repeats 5]``. One type-A handover of leg 0 (object,
close, human, open, each the meant action, so nothing is stopped and both variants follow the
same trajectory) is run with the person's :class:`~robin_sim.person.watcher.PhysicalWatcher`
asked at every tick, and with nobody watching (the baseline, measured in the same run,
interleaved). Prints the median wall time and real-time factor of each and their ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time

import smoke  # bench/smoke.py: --smoke

from pil.task.world import Intent, Target
from pil.types import Action, Feedback, Gesture
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

STEPS = (
    (Action.OBJECT, Gesture.POINTING, Target("leg", 0)),
    (Action.CLOSE, Gesture.GRASP, None),
    (Action.HUMAN, Gesture.GIVE_ME, None),
    (Action.OPEN, Gesture.RELEASE, None),
)


def handover(watching: bool) -> tuple[float, float]:
    """Wall seconds spent in ``execute`` and simulated seconds of those calls."""
    world = PhysicalWorld()
    body = PhysicalBody(world, seed=0)
    wall = sim = 0.0
    for action, gesture, target in STEPS:
        intent = Intent(gesture, action, target, handover=0, table=0)
        body.perform(gesture, target)
        watcher = body.watch(intent, 0.5) if watching else None
        began, sim_began = time.perf_counter(), world.time
        outcome = world.execute(action, target, watcher)
        wall += time.perf_counter() - began
        sim += world.time - sim_began
        assert outcome.succeeded and not outcome.interrupted, outcome.detail
        body.show_feedback(Feedback.OK)
        body.after_feedback(Feedback.OK)
    return wall, sim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs per variant (median)")
    args = smoke.parse_args(parser, repeats=1)
    runs: dict[bool, list[tuple[float, float]]] = {True: [], False: []}
    for _ in range(args.repeats):  # interleaved, so load from other processes hits both
        for watching in (False, True):
            runs[watching].append(handover(watching))
    print("| variant | median wall s | sim s | real-time factor |")
    print("|---|---|---|---|")
    medians = {}
    for watching, label in ((False, "nobody watching (baseline)"), (True, "person watches")):
        wall = statistics.median(w for w, _ in runs[watching])
        sim = runs[watching][0][1]
        medians[watching] = wall
        print(f"| {label} | {wall:.2f} | {sim:.1f} | {sim / wall:.1f}x |")
    print(f"ratio watching / baseline: {medians[True] / medians[False]:.3f}")


if __name__ == "__main__":
    main()
