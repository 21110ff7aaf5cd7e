"""Property: whatever the participant's readings and the body's moves, the mirrored hand is
raised only from rest, only while mirrored, and never into anything (robin_sim.live.show_hand).

A hypothesis state machine over real MuJoCo physics: the world, the live tempo's scripted body,
the mirror and :class:`ShowHand` wired as :class:`robin_sim.live.run.LiveRun` wires them. Its
rules are footage readings (any sequence, any frame), the body's own moves (a give me, a
pointing at any leg or spot, a rest) and idle time, in any order; hypothesis shrinks a failing
sequence. After every rule: a raise began only from rest (within ``AT_REST``) with a reading
driving the hand, an idle hand at rest is never left there while mirrored, and no person contact.
"""

from __future__ import annotations

import numpy as np
import pytest
from hand_data import footage, hand_input, usable
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from pil.task.world import Target
from pil.types import Gesture
from robin_sim.control.human_hand import HumanHand
from robin_sim.control.simulator import Simulator
from robin_sim.live.mirror import HandMirror
from robin_sim.live.show_hand import AT_REST, ShowHand
from robin_sim.person.body import LIVE, PhysicalBody
from robin_sim.robot.world import PhysicalWorld

pytestmark = pytest.mark.slow
READS = footage()
USABLE = usable(READS)
STEP = 0.04  # s of physics per check while the hand moves
MOTION_S = 10.0  # s: every move of the body or raise ends well within this


class Watched(ShowHand):
    """:class:`ShowHand`, recording where the hand was each time a raise began."""

    def __init__(self, hand: HumanHand, mirror: HandMirror, speed: float) -> None:
        super().__init__(hand, mirror, speed)
        self.raised_from: list[tuple[np.ndarray, bool]] = []

    def tick(self, sim: Simulator) -> None:
        before = self.raised
        here = self.hand.pose().translation().copy()
        active = self.mirror.active
        super().tick(sim)
        if self.raised > before:
            self.raised_from.append((here, active))


class ShowHandMachine(RuleBasedStateMachine):
    """One world per example; hypothesis picks the readings and the body's moves."""

    @initialize()
    def build(self) -> None:
        self.world = PhysicalWorld()
        self.body = PhysicalBody(self.world, tempo=LIVE)
        self.mirror = HandMirror(self.world.model, self.world.data)
        self.world.sim.add_controller(self.mirror.tick)
        self.show = Watched(self.body.hand, self.mirror, self.body.tempo.hand_speed)
        self.world.sim.add_controller(self.show.tick)

    def _settle(self) -> None:
        """Run until the hand's motion ends (a raise may begin a tick later), at most
        :data:`MOTION_S` of simulated time: a hand that never comes to rest fails."""
        end = self.world.time + MOTION_S
        self.world.run(STEP)
        while self.body.hand.busy(self.world.time):
            assert self.world.time < end, "the hand kept moving"
            self.world.run(STEP)
        self.world.run(STEP)

    @rule(k=st.integers(0, len(USABLE) - 1))
    def a_reading(self, k: int) -> None:
        self.mirror.take(hand_input(READS, USABLE[k]))
        self._settle()

    @rule()
    def give_me(self) -> None:
        self.body.perform(Gesture.GIVE_ME, None)
        self._settle()

    @rule(kind=st.sampled_from(["leg", "spot"]), index=st.integers(0, 3))
    def pointing(self, kind: str, index: int) -> None:
        self.body.perform(Gesture.POINTING, Target(kind, index))
        self._settle()

    @rule()
    def rest(self) -> None:
        self.body.rest()
        self._settle()

    @rule(seconds=st.floats(0.0, 1.0))
    def idle(self, seconds: float) -> None:
        self.world.run(seconds)

    @invariant()
    def raised_only_from_rest_while_mirrored(self) -> None:
        for here, active in self.show.raised_from:
            assert active
            assert float(np.linalg.norm(here - self.show.rest)) <= AT_REST

    @invariant()
    def a_mirrored_idle_hand_is_not_left_at_rest(self) -> None:
        hand = self.body.hand
        at_rest = float(np.linalg.norm(hand.pose().translation() - self.show.rest)) <= AT_REST
        if self.mirror.active and at_rest:
            assert hand.busy(self.world.time + self.world.sim.control_dt)

    @invariant()
    def nothing_is_touched(self) -> None:
        assert self.world.person_contacts.events == 0


ShowHandMachine.TestCase.settings = settings(
    max_examples=30,
    stateful_step_count=10,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
test_show_hand_machine = ShowHandMachine.TestCase
