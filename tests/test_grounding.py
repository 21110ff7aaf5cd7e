"""The robot's state grounded in its hand: a context right approvals cannot reach stalls nothing."""

from __future__ import annotations

import pytest

from pil.learner import Learner
from pil.task.detector import Detector
from pil.task.grounding import ground, is_reachable
from pil.task.person import ScriptedPerson
from pil.task.runner import ASK_AFTER_REPEATS, steps
from pil.task.scenario import load_scenario
from pil.task.watching import InstantWatcher
from pil.task.world import Intent, Outcome, SymbolicWorld, Watcher
from pil.types import ACTIONS, Action, Feedback, Hand
from pil.validity import REACHABLE_CONTEXTS, VALID_STATES


def test_every_context_grounds_to_one_with_a_valid_state_for_each_hand() -> None:
    for action in ACTIONS:
        for hand in Hand:
            grounded, why = ground(action, hand, hand)
            assert is_reachable(grounded, hand)
            assert bool(why) is (not is_reachable(action, hand))
            assert any((s.previous_action, s.hand) == (grounded, hand) for s in VALID_STATES)


def test_unreachable_contexts_are_the_four_the_rules_name() -> None:
    unreachable = {(a, h) for a in ACTIONS for h in Hand} - REACHABLE_CONTEXTS
    assert unreachable == {
        (Action.OPEN, Hand.OCCUPIED),
        (Action.CLOSE, Hand.FREE),
        (Action.HUMAN, Hand.FREE),
        (Action.LOCATION, Hand.FREE),
        (Action.OBJECT, Hand.OCCUPIED),
    }


EMPTY_HANDED = (Action.OBJECT, Action.CLOSE)  # what the person wants while the hand is empty


class LetsItRun(InstantWatcher):
    """Watches without stopping ``allowed`` (the person looks away)."""

    def __init__(self, intent: Intent, allowed: Action) -> None:
        super().__init__(intent)
        self.allowed = allowed

    def stop_now(self, shown: Action | None) -> bool:
        return shown is not self.allowed and super().stop_now(shown)


class LetsWrongMovesStand(ScriptedPerson):
    """A person who lets one chosen wrong action run and stand once, without a thumb (silence
    counts as OK, eq. 1)."""

    def __init__(self, *args: object, silent_on: Action = Action.HUMAN, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.silent_on = silent_on
        self.stood = 0

    def watch(self, intent: Intent) -> Watcher:
        if self.stood or intent.action not in EMPTY_HANDED:
            return super().watch(intent)
        return LetsItRun(intent, self.silent_on)

    def judge(self, intent: Intent, action: Action, outcome: Outcome) -> Feedback:
        if action is self.silent_on and intent.action in EMPTY_HANDED and not self.stood:
            self.stood += 1
            return Feedback.NONE
        return super().judge(intent, action, outcome)


@pytest.mark.parametrize("silent_on", [Action.HUMAN, Action.LOCATION])
@pytest.mark.parametrize("exploration", ["next-best", "avoid-last"])
def test_an_empty_hand_moved_to_the_person_and_let_stand_is_no_dead_end(
    silent_on: Action, exploration: str
) -> None:
    """The live lock-up of issue 38: the empty hand goes to the person (or a spot), nobody
    objects; before the grounding every later gesture was invalid and asked for again."""
    scenario = load_scenario()
    types = scenario.draw_types(4, 0)
    for seed in range(6):
        person = LetsWrongMovesStand.for_types(scenario, types, seed)
        person.silent_on = silent_on
        person.stood = 0
        learner = Learner(seed, exploration=exploration)
        records = list(steps(learner, person, Detector(1.0, seed), SymbolicWorld()))
        assert person.next_step(Hand.FREE) is None  # the person's whole script was done
        assert records[-1].handover == 3
        if not person.stood:
            continue  # the robot never tried the wrong move with an empty hand on this seed
        # right after the wrong move stood the robot acts on the next gesture: no repeat
        stood_at = next(
            i
            for i, r in enumerate(records)
            if r.action is silent_on and r.feedback is Feedback.NONE
        )
        after = records[stood_at + 1 :]
        assert "re-grounded" in after[0].reason
        assert learner.taken_back >= 1  # the approval the world contradicts is withdrawn
        # the person's script goes on (they think the robot is at the leg): its next gesture
        # may not fit, but the robot acts within ASK_AFTER_REPEATS performances, never stalls
        in_a_row = 0
        for record in after:
            in_a_row = in_a_row + 1 if record.action is None else 0
            assert in_a_row < ASK_AFTER_REPEATS


def test_pointing_at_the_leg_after_the_empty_hand_stood_is_acted_on() -> None:
    """The live reproduction: after the empty-hand move stood, pointing at the leg works."""
    for exploration in ("next-best", "avoid-last"):
        learner = Learner(0, exploration=exploration)
        learner.feedback(learner.decide("pointing", "open", "free").state, "object", True)
        learner.feedback(learner.decide("grasp", "object", "free").state, "close", True)
        learner.feedback(learner.decide("give me", "close", "occupied").state, "human", True)
        learner.feedback(learner.decide("release", "human", "occupied").state, "open", True)
        decision = learner.decide("pointing", "open", "free")
        learner.feedback(decision.state, "human", True)  # wrong, and let stand
        again = learner.decide("pointing", "human", "free")  # the learner alone grounds it
        assert again.action is not None and again.state is not None
        assert again.state.previous_action is Action.OPEN and "re-grounded" in again.reason
        learner.regrounded(Action.HUMAN, Hand.FREE, Hand.FREE)  # as the step loop tells it
        assert learner.taken_back == 1
        again = learner.decide("pointing", "human", "free")
        assert again.action is Action.OBJECT and again.exploited
