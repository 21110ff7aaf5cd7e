"""The thumb at the handover point must be seen: after Robin brought a leg over the palm, and
with the delivered leg lying on it, the person draws the hand back and up into Robin's view
before showing the thumb, and Robin reads it with its eye cameras.

Real MuJoCo physics (the arm brought to its states by real actions), EGL renders of the eye
cameras, the installed gesture model.
"""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pil.task.world import Target  # noqa: E402
from pil.types import Action, Feedback, Gesture  # noqa: E402
from robin_sim.person.body import PERSON_CLEAR_X, POINT_RAISE, THUMB_ASIDE, PhysicalBody  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402
from robin_sim.vision.arm_states import PALM_LEG, _act  # noqa: E402
from robin_sim.vision.detector import VisionDetector  # noqa: E402

TRIES = 18  # readings of each thumb per detector seed, a new performance each time
DETECTOR_SEEDS = (0, 1, 2)  # one seed's 18 readings are too few to bound a rate (issue 41)
# Of the 54 readings of each thumb at least RIGHT are right and at most FLIPPED read as the
# other thumb; a discard is asked again. Measured in this scene with the shipped model over
# detector seeds 0-9 (180 readings of each): the thumb up after `human` and after the bin
# 180/180 right; the thumb down 135 right, 44 read as up (24 %: a thumb down shown beside the
# held leg is flipped about one time in four), 1 discarded. The bounds are the 0.1 % and
# 99.9 % binomial quantiles of 54 readings at those rates (scipy.stats.binom). With the
# model before (16 128 samples, no held-leg samples) the thumb down was 89 right and 42
# flipped of 180: it held the old bound (at most 3 of 18 flipped, detector seed 0 alone) by
# that seed's luck, as more than 3 of 18 were flipped in five of the ten seeds.
RIGHT = 30
FLIPPED = 24
TOLERANCE = 0.01  # m: the hand drawn back and raised as meant; the held leg where it was
SHOWN = {Feedback.OK: "thumb_up", Feedback.NOT_OK: "thumb_down"}
BIN_HALF, BIN_RIM = 0.18, 0.25  # m: the bin's inner half-side and its rim's height


def _read(detectors: list[VisionDetector], feedback: Feedback) -> int:
    """How many of the readings of ``feedback`` (:data:`TRIES` per detector) are right; at most
    :data:`FLIPPED` may be read as the other thumb (a discard is asked again or taken as no
    feedback; a flipped thumb misleads the learner, which the robust rule of issue 38 must then
    survive)."""
    reads = []
    for detector in detectors:
        for _ in range(TRIES):
            detector.read_feedback(feedback)
        reads += [r.read for r in detector.records[-TRIES:]]
    other = next(v for k, v in SHOWN.items() if k is not feedback)
    assert reads.count(other) <= FLIPPED, f"{feedback.value} read as {other}: {reads}"
    return sum(r == SHOWN[feedback] for r in reads)


@pytest.mark.slow
def test_a_thumb_at_the_palm_is_shown_in_robins_view_and_read() -> None:
    """After ``human`` (Robin's hand and the held leg just above the palm) a thumb up and a
    thumb down are each shown drawn back, raised and aside, clear of the held leg and of
    Robin's arm, and read right;
    after the open over the palm the person puts the leg into the bin, then shows the thumb up
    with the free hand, and it is read. No person contact throughout."""
    world = PhysicalWorld()
    body = PhysicalBody(world)
    detectors = [VisionDetector(world.sim, display=body.display, seed=s) for s in DETECTOR_SEEDS]
    try:
        world.start_table(0)
        _act(world, body, Gesture.POINTING, Action.OBJECT, Target("leg", PALM_LEG))
        _act(world, body, Gesture.GRASP, Action.CLOSE)
        for i, feedback in enumerate((Feedback.OK, Feedback.NOT_OK)):
            body.perform(Gesture.GIVE_ME, None)  # the second time: slid back under the leg
            if i == 0:
                assert world.execute(Action.HUMAN, None).succeeded
            assert world.palm_is_out() and body.thumb_hidden_at_palm()
            held = world.legs.position(PALM_LEG)
            out = body.hand.pose().translation()
            body.show_feedback(feedback)
            here = body.hand.pose().translation()  # drawn back and raised into view
            assert here[0] == pytest.approx(PERSON_CLEAR_X, abs=TOLERANCE), here
            aside = out + np.array([0.0, THUMB_ASIDE, POINT_RAISE])
            assert here[1:] == pytest.approx(aside[1:], abs=TOLERANCE), here
            assert world.held_leg() == PALM_LEG
            assert np.linalg.norm(world.legs.position(PALM_LEG) - held) < TOLERANCE
            right = _read(detectors, feedback)
            assert right >= RIGHT, f"{feedback.value} after human: {right} read right"
        body.perform(Gesture.RELEASE, None)  # slid under the held leg
        assert world.execute(Action.OPEN, None).succeeded
        assert body.leg_on_palm() == PALM_LEG and body.thumb_hidden_at_palm()
        body.show_feedback(Feedback.OK)  # the leg into the bin first, then the free hand's thumb
        bin_x, bin_y = world.layout.bin
        leg = world.legs.position(PALM_LEG)
        # the leg lies in the bin (inner half-side 0.18 m; below its 0.25 m rim), by physics
        assert abs(leg[0] - bin_x) < BIN_HALF and abs(leg[1] - bin_y) < BIN_HALF, leg
        assert leg[2] < BIN_RIM, leg
        assert body.leg_on_palm() is None and not body.thumb_hidden_at_palm()
        right = _read(detectors, Feedback.OK)
        assert right >= RIGHT, f"ok after taking the leg: {right} read right"
        body.after_feedback(Feedback.OK)  # nothing left to carry
        assert PALM_LEG in world.delivered and body.leg_on_palm() is None
        assert world.person_contacts.events == 0
    finally:
        for detector in detectors:
            detector.close()
