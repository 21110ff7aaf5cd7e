"""The give-me palm held out at the handover point, read with the arm where an episode has it.

A person asks for a leg ("give me") by holding the palm out at the handover point
(:meth:`robin_sim.person.body.PhysicalBody.perform`); Robin must read that hand as "give me"
whatever its arm is doing. :func:`palm_readings` walks a world through the arm states of
:func:`robin_sim.vision.arm_states.arm_states` (real actions run by physics), and in each of
``states`` has the person hold the palm out and Robin read it ``tries`` times (a new
performance each time: pose jitter, size, skin tone), in context as an episode reads an
instruction gesture: world, body and eyes are assembled as an episode's
(:func:`robin_sim.episode.physical_assembly.assemble_physical`, seeded by ``seed``). Used by
``bench/bench_palm_view.py`` and ``tests/test_vision_view.py``.
"""

from __future__ import annotations

from pil.task.spec import PHYSICAL, parse_run_spec
from pil.types import Gesture
from robin_sim.episode.physical_assembly import assemble_physical
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld
from robin_sim.vision.arm_states import arm_states
from robin_sim.vision.classifier import GestureModel
from robin_sim.vision.detector import VisionDetector

# the arm states in which the person may ask for a leg: at home (a new table), closed on a leg
# on the table, holding it over the palm (the palm already out), holding it over a spot
PALM_STATES = ("home", "close", "human", "location")


def palm_readings(
    tries: int = 6,
    states: tuple[str, ...] = PALM_STATES,
    gesture_model: GestureModel | None = None,
    seed: int = 0,
) -> dict[str, list[str]]:
    """Per arm state, what Robin read each of ``tries`` times the palm was held out (a gesture
    class of the four, or ``"discarded"``); the person's hand rests again afterwards unless a
    leg is held over the palm."""
    spec = parse_run_spec(seed=seed, params={"detector": "vision"}, world=PHYSICAL)
    run = assemble_physical(spec, gesture_model=gesture_model)  # as an episode is assembled
    world, body, detector = run.world, run.person.body, run.detector
    if not (
        isinstance(world, PhysicalWorld)
        and isinstance(body, PhysicalBody)
        and isinstance(detector, VisionDetector)
    ):
        raise TypeError(f"a vision run's parts, got {world!r}, {body!r}, {detector!r}")
    reads: dict[str, list[str]] = {}
    try:
        for state in arm_states(world, body):
            if state not in states:
                continue
            # the palm stays under a leg held over it (the way to rest would sweep into it)
            palm_was_out = world.palm_is_out() or body.leg_held_over_palm_place()
            body.perform(Gesture.GIVE_ME, None)
            reads[state] = []
            for _ in range(tries):
                detector.detect(Gesture.GIVE_ME)
                reads[state].append(detector.records[-1].read)
            if not palm_was_out:
                body.rest()
            if len(reads) == len(states):
                break  # the later states are not needed
    finally:
        detector.close()
    return reads


__all__ = ["PALM_STATES", "palm_readings"]
