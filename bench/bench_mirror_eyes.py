"""How Robin's eyes read the mirrored hand: the footage's readings through the live mirror.

Each stored tracker reading of the real footage (``tests/data/hands/landmarks.npz``) is applied
to the articulated person's hand by :class:`robin_sim.live.mirror.HandMirror` in a fresh scene
(Robin at home, the scripted body present as in a live session, the hand raised from rest to
where signs are read once the mirror drives it, :mod:`robin_sim.live.show_hand`), then both
eyes look at the palm and the shipped eye-camera model reads it
(:class:`robin_sim.live.eye_watch.EyeWatch`, the session's own reader). Prints a table per
footage sequence: readings, the share read as the sequence's gesture, and the classes
read. ``python bench/bench_mirror_eyes.py [--every N] [--at-palm]`` (every Nth reading;
default 1; ``--smoke``: every 15th; ``--at-palm``: the body first holds the palm out at the
handover point, as after a give me, and the readings are applied there).
"""

from __future__ import annotations

import argparse
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import smoke  # bench/smoke.py: --smoke
from hand_data import footage

from pil.types import Gesture
from robin_sim.live.eye_watch import EyeWatch
from robin_sim.live.hands.landmarks import HandInput
from robin_sim.live.mirror import HandMirror
from robin_sim.live.show_hand import ShowHand
from robin_sim.person.body import LIVE, PhysicalBody
from robin_sim.robot.world import PhysicalWorld

# the gesture each footage sequence is labelled with (tests/data/hands/make_data.py: the thumb
# down is the thumb-up clip flipped upside down, "open_up" the palm clip turned half round)
MEANT = {
    "thumb_up": "thumb_up",
    "palm": "give_me",
    "fist": "grasp",
    "open_up": "release",
    "thumb_down": "thumb_down",
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=1)
    parser.add_argument("--at-palm", action="store_true", help="the palm held out first")
    args = smoke.parse_args(parser, every=15)
    world = PhysicalWorld()
    body = PhysicalBody(world, tempo=LIVE)  # a session's body: its hand fit runs before renders
    mirror = HandMirror(world.model, world.data)
    world.sim.add_controller(mirror.tick)
    show = ShowHand(body.hand, mirror, body.tempo.hand_speed)  # as robin_sim.live.run wires it
    world.sim.add_controller(show.tick)
    if args.at_palm:
        body.perform(Gesture.GIVE_ME, None)  # the hand leaves rest: it is not raised
    eyes = EyeWatch(world.model, world.data, mirror)
    reads = footage()
    print("| sequence | readings | read as meant | classes read |")
    print("|---|---|---|---|")
    for sequence, meant in MEANT.items():
        labels: list[str] = []
        for i in np.flatnonzero(reads["sequence"] == sequence)[:: args.every]:
            points = reads["landmarks"][i].astype(float)
            if not np.isfinite(points).all() or not reads["handedness"][i]:
                continue
            hand = HandInput(points, str(reads["handedness"][i]), 0.95, float(reads["aspect"][i]))
            mirror.take(hand)
            world.run(0.04)
            while body.hand.busy(world.time):  # the first reading: the hand is raised first
                world.run(0.04)
            world.sim.prepare_view()
            labels.append(eyes.look(world.time).label)
        share = sum(label == meant for label in labels) / max(len(labels), 1)
        counts = ", ".join(f"{k} {v}" for k, v in Counter(labels).most_common())
        print(f"| {sequence} ({meant}) | {len(labels)} | {share:.2f} | {counts} |")
    eyes.close()


if __name__ == "__main__":
    main()
