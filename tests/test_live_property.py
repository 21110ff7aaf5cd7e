"""Property: whatever a participant does, a live session never locks, loops or loses a step.

A hypothesis state machine over the real session engine (physics, the learner, the files): its
rules are a page's moves, at any moment and in any order (clicks on legs or anywhere, the
gesture keys, early, late and random thumbs, wrong moves let stand, "That was wrong", idle
periods, junk), chosen by hypothesis and shrunk to a smallest failing sequence if an invariant
breaks. After every move the robot's turn must not have stood still for longer than any step
can last; at the end :class:`live_monkey.Audit` checks the log against physics and the inputs:
steps numbered 1, 2, 3, ... once each, every executed action logged, no gesture performed that
the participant did not make, no more actions on one gesture than the watchdog allows, no
more gestures in a row handed back than it lets go back, no gesture the guide asked for handed
back, every take-back of a step that stood and counted in the summary.
``tests/live_soak.py`` runs whole sessions of the same participants (also with webcam
readings of the real footage).
"""

from __future__ import annotations

import random
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule
from live_monkey import STALL_S, Audit, Monkey

from robin_sim.live.session import LiveConfig, LiveSession

pytestmark = pytest.mark.slow
MAX_ATTEMPTS = 6
THEN = st.floats(0.0, 3.0)


class LiveParticipantMachine(RuleBasedStateMachine):
    """One session per example; hypothesis drives the participant's moves."""

    session: LiveSession | None = None

    @initialize(seed=st.integers(0, 2**16), feedback=st.sampled_from([1.0, 2.0]))
    def start(self, seed: int, feedback: float) -> None:
        folder = Path(tempfile.mkdtemp(prefix="live-property-"))
        config = LiveConfig(
            out_root=folder,
            seed=seed,
            video=False,
            speed=10.0,
            fps=2.0,
            feedback_window=feedback,
            max_attempts=MAX_ATTEMPTS,
        )
        self.session = LiveSession(config)
        self.session.start()
        self.monkey = Monkey(self.session, random.Random(seed))
        self.monkey.wait_turn()  # the scene is up and the participant asked

    # every move is followed by ``then`` s of sim time (a person's pace varies): the robot acts
    @rule(leg=st.integers(0, 3), then=THEN)
    def click_a_leg(self, leg: int, then: float) -> None:
        self.monkey.click_leg(leg)
        self.monkey.idle(then)

    @rule(then=THEN)
    def follow_the_guide(self, then: float) -> None:
        self.monkey.follow()
        self.monkey.idle(then)

    @rule(then=THEN)
    def click_anywhere(self, then: float) -> None:
        self.monkey.click_anywhere()
        self.monkey.idle(then)

    @rule(name=st.sampled_from(["give_me", "grasp", "release"]), then=THEN)
    def gesture(self, name: str, then: float) -> None:
        self.monkey.gesture(name)
        self.monkey.idle(then)

    @rule(value=st.sampled_from(["up", "down"]), then=THEN)
    def thumb(self, value: str, then: float) -> None:
        self.monkey.thumb(value)
        self.monkey.idle(then)

    @rule(then=THEN)
    def let_a_wrong_move_stand(self, then: float) -> None:
        self.monkey.let_wrong_stand()
        self.monkey.idle(then)

    @rule()
    def late_thumb(self) -> None:
        self.monkey.late_thumb()

    @rule(then=THEN)
    def that_was_wrong(self, then: float) -> None:
        self.monkey.take_back()
        self.monkey.idle(then)

    @rule(seconds=st.floats(2.0, 10.0))
    def idle(self, seconds: float) -> None:
        self.monkey.idle(seconds)

    @rule()
    def junk(self) -> None:
        self.monkey.junk()

    @invariant()
    def the_robots_turn_never_stands_still(self) -> None:
        if self.session is not None:
            self.monkey.look()
            assert self.monkey.stall_s <= STALL_S, self.session.status()
            assert self.session.status()["status"] != "failed", self.session.status()

    def teardown(self) -> None:
        session = self.session
        if session is None:
            return
        self.monkey.idle(3.0)  # what runs now comes back to the participant by itself
        session.stop("ended")
        audit = Audit.of(session, self.monkey, MAX_ATTEMPTS)
        assert audit.problems == [], audit


LiveParticipantMachine.TestCase.settings = settings(
    max_examples=8,
    stateful_step_count=25,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,  # the same sequences on every run (CI included)
)
test_live_participants = LiveParticipantMachine.TestCase
