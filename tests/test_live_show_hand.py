"""The mirrored hand is held up where Robin reads signs (robin_sim.live.show_hand).

Real MuJoCo physics: the world, the live session's scripted body (its tempo), the mirror fed
the footage's fist reading, and :class:`ShowHand` wired as :class:`robin_sim.live.run.LiveRun`
wires it. Positions are the mocap hand's, from the simulation.
"""

from __future__ import annotations

import numpy as np
from hand_data import footage, hand_input, usable

from pil.types import Gesture
from robin_sim.live.hands.landmarks import HandInput
from robin_sim.live.mirror import HandMirror
from robin_sim.live.show_hand import ShowHand
from robin_sim.person.body import LIVE, PhysicalBody
from robin_sim.robot.world import PhysicalWorld
from robin_sim.vision.dataset import drawn_back

TOLERANCE = 1e-3  # m: the hand arrives where its path ends
STEP = 0.04  # s of physics between checks


def _fist() -> HandInput:
    reads = footage()
    return hand_input(reads, usable(reads, "fist")[0])


def _settle(world: PhysicalWorld, body: PhysicalBody) -> None:
    world.run(STEP)
    while body.hand.busy(world.time):
        world.run(STEP)


def test_the_mirrored_hand_is_raised_from_rest_and_only_from_rest() -> None:
    world = PhysicalWorld()
    body = PhysicalBody(world, tempo=LIVE)
    mirror = HandMirror(world.model, world.data)
    world.sim.add_controller(mirror.tick)
    show = ShowHand(body.hand, mirror, body.tempo.hand_speed)
    world.sim.add_controller(show.tick)
    rest = body.hand.rest_pose.translation()
    place = drawn_back(rest)
    # no participant's reading yet: the hand stays at rest
    world.run(0.5)
    assert show.raised == 0
    np.testing.assert_allclose(body.hand.pose().translation(), rest, atol=TOLERANCE)
    # a reading drives the hand: it is raised, and Robin's view of it is "drawn back, raised"
    mirror.take(_fist())
    _settle(world, body)
    assert show.raised == 1
    np.testing.assert_allclose(body.hand.pose().translation(), place, atol=TOLERANCE)
    assert place[2] - rest[2] > 0.15 and place[0] < rest[0]
    # the body's own move (the palm held out) starts from there and is not undone
    body.perform(Gesture.GIVE_ME, None)
    _settle(world, body)
    assert world.palm_is_out() and show.raised == 1
    # brought back to rest while the mirror drives it, the hand is raised again
    body.rest()
    _settle(world, body)
    assert show.raised == 2
    np.testing.assert_allclose(body.hand.pose().translation(), place, atol=TOLERANCE)
    assert world.person_contacts.events == 0
