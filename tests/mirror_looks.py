"""Robin's eyes on the footage's hands, mirrored as a live session mirrors them.

Builds what :class:`robin_sim.live.run.LiveRun` builds around the mirrored hand (the world, the
scripted body at the live tempo, :class:`~robin_sim.live.mirror.HandMirror`,
:class:`~robin_sim.live.show_hand.ShowHand`, :class:`~robin_sim.live.eye_watch.EyeWatch`),
applies each stored tracker reading of the footage (``tests/data/hands/landmarks.npz``) and
lets the eyes look once per reading. Shared by ``tests/test_mirror_looks.py`` and
``bench/bench_mirror_eyes.py``.
"""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported

import numpy as np  # noqa: E402
from hand_data import footage, hand_input, usable  # noqa: E402

from pil.types import Gesture  # noqa: E402
from robin_sim.live.eye_watch import EyeWatch  # noqa: E402
from robin_sim.live.mirror import HandMirror  # noqa: E402
from robin_sim.live.show_hand import ShowHand  # noqa: E402
from robin_sim.person.body import LIVE, PhysicalBody  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402

# the gesture each footage sequence is labelled with (tests/data/hands/make_data.py: the thumb
# down is the thumb-up clip flipped upside down, "open_up" the palm clip turned half round)
MEANT = {
    "thumb_up": "thumb_up",
    "palm": "give_me",
    "fist": "grasp",
    "open_up": "release",
    "thumb_down": "thumb_down",
}
STEP = 0.04  # s of physics after each reading (and while the hand is raised)


def mirror_looks(every: int = 1, at_palm: bool = False) -> dict[str, list[str]]:
    """Per footage sequence, the class of all seven Robin's eyes read at each applied reading
    (every ``every``-th; those with no hand or non-finite landmarks are skipped). With
    ``at_palm`` the body first holds the palm out at the handover point (as after a give me),
    so the hand is not at rest and is not raised."""
    world = PhysicalWorld()
    body = PhysicalBody(world, tempo=LIVE)  # a session's body: its hand fit runs before renders
    mirror = HandMirror(world.model, world.data)
    world.sim.add_controller(mirror.tick)
    show = ShowHand(body.hand, mirror, body.tempo.hand_speed)  # as LiveRun wires it
    world.sim.add_controller(show.tick)
    if at_palm:
        body.perform(Gesture.GIVE_ME, None)
    eyes = EyeWatch(world.model, world.data, mirror)
    reads = footage()
    kept = set(usable(reads))
    looks: dict[str, list[str]] = {}
    try:
        for sequence in MEANT:
            labels = looks.setdefault(sequence, [])
            for i in np.flatnonzero(reads["sequence"] == sequence)[::every]:
                if int(i) not in kept:  # no hand, or landmarks not finite
                    continue
                mirror.take(hand_input(reads, int(i)))
                world.run(STEP)
                while body.hand.busy(world.time):  # the first reading: the hand is raised
                    world.run(STEP)
                world.sim.prepare_view()
                labels.append(eyes.look(world.time).label)
    finally:
        eyes.close()
    return looks
