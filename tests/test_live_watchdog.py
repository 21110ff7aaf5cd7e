"""The live watchdog and guide, without a session: no state of Robin's strands a participant.

Whatever the learner has learnt and whatever approvals stood (right or wrong, a drop, a
take-back), the guide's gesture in Robin's state grounded as the loop grounds it is one the
learner acts on (a valid state: :meth:`pil.learner.Learner.decide` acts on every one), and
:func:`robin_sim.live.watchdog.no_way_on` says so; in the state the participant's page used to
keep (the issue's empty hand let stand at the person, not grounded) it catches the dead end.
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from pil.learner import Learner
from pil.task.grounding import ground
from pil.task.scenario import load_scenario
from pil.types import ACTIONS, HANDS, Action, Hand, State
from pil.validity import VALID_STATES
from robin_sim.live.guide import step_for
from robin_sim.live.limits import WatchdogLimits
from robin_sim.live.watchdog import StepWatchdog, no_way_on, way_on

TYPES = load_scenario().types

feedbacks = st.lists(
    st.tuples(st.sampled_from(VALID_STATES), st.sampled_from(ACTIONS), st.booleans()),
    max_size=40,
)


@settings(max_examples=200, deadline=None)
@given(
    history=feedbacks,
    kind=st.sampled_from(TYPES),
    done=st.integers(0, 6),
    previous=st.sampled_from(ACTIONS),
    expected=st.sampled_from(HANDS),
    hand=st.sampled_from(HANDS),
    seed=st.integers(0, 1000),
)
def test_the_guides_gesture_is_acted_on_in_every_grounded_state(
    history: list[tuple[State, Action, bool]],
    kind: object,
    done: int,
    previous: Action,
    expected: Hand,
    hand: Hand,
    seed: int,
) -> None:
    learner = Learner(seed)
    for state, action, ok in history:  # any teacher: right, wrong, silent
        learner.feedback(state, action, ok)
    grounded, _ = ground(previous, expected, hand)
    assert no_way_on(kind, done, grounded, hand) == ""  # type: ignore[arg-type]
    step = kind.steps[step_for(kind, done, grounded, hand)]  # type: ignore[attr-defined]
    decision = learner.decide(step.gesture, grounded, hand)
    assert decision.action is not None, (step, grounded, hand, decision.reason)


def test_the_issues_empty_hand_at_the_person_is_a_dead_end_unless_grounded() -> None:
    """The context an empty hand moved to the person and let stand leaves: no step of any
    type has a gesture valid there (the old page asked for one anyway); grounded, it has."""
    for kind in TYPES:
        for done in range(len(kind.steps)):
            assert no_way_on(kind, done, Action.HUMAN, Hand.FREE).startswith("the guide's")
            grounded, why = ground(Action.HUMAN, Hand.FREE, Hand.FREE)
            assert grounded is Action.OPEN and why.startswith("re-grounded")
            assert no_way_on(kind, done, grounded, Hand.FREE) == ""


def test_gestures_handed_back_in_a_row_wake_the_watchdog() -> None:
    clock = [0.0]
    watchdog = StepWatchdog(WatchdogLimits(handed_back=3), lambda: clock[0])
    assert watchdog.hand_back() == "" and watchdog.hand_back() == ""
    stuck = watchdog.hand_back()
    assert stuck == "3 of your gestures in a row Robin could not act on"
    assert "proposes an action for your thumb" in way_on(stuck)
    watchdog.acted()  # Robin acts: the count starts again
    assert watchdog.hand_back() == ""
    assert way_on("") == "Make a gesture again, or another one."


def test_a_second_take_back_before_the_first_is_seen_is_refused() -> None:
    """Two "That was wrong" in one tick (seen in the soak: both accepted, one done): the page's
    thread marks the first at once, so the second is refused, not merged."""
    from pil.types import Action
    from robin_sim.live.take_back import Stood, TakeBacks

    backs = TakeBacks()
    backs.stood(Stood(Action.OBJECT, 3, 10.0, False, None))
    assert backs.refusal(11.0, your_turn=True) == ""
    backs.request()
    assert "no action of Robin's to take back" in backs.refusal(11.0, your_turn=True)
    assert backs.left(11.0) is None
    assert backs.ask(your_turn=True) == "" and backs.asked
    taken, notice = backs.taken("object taken back")
    assert taken is not None and taken.t == 3 and notice.startswith("Robin took back its 'object'")
    assert backs.count == 1 and backs.last is None
