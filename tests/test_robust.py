"""The robust PIL rule (pil.robust): PIL's strengths kept, and what it adds for real teachers.

Each test feeds the learner through its public API (decide, choose, feedback, take_back,
regrounded) or the real step loop, and checks a behaviour the design claims
(docs/learner.md, "The robust rule"); each fails when that part of the design is switched off
or broken (the comments say how).
"""

from __future__ import annotations

import random
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from pil.bench.entrants import REFERENCE
from pil.bench.noise import FeedbackChannel
from pil.bench.suite import load_suite
from pil.bench.tracks import run_track
from pil.errors import RobinPilError
from pil.learner import Learner
from pil.robust import RobustLearner
from pil.robust.asking import TRIAL
from pil.robust.learner import CAP, DECAY
from pil.table import action_index, state_id
from pil.task.detector import Detector
from pil.task.person import ScriptedPerson
from pil.task.records import StepRecord
from pil.task.runner import steps
from pil.task.scenario import load_scenario
from pil.task.spec import parse_run_spec
from pil.task.world import SymbolicWorld
from pil.types import Action, Feedback, Gesture, Hand, State
from pil.validity import VALID_STATES

sys.path.insert(0, str(Path(__file__).parent))
from test_table_one import _replay

# The assembly's right action in each valid state (each state has exactly one).
RIGHT = {
    state: {
        Gesture.POINTING: Action.OBJECT if state.hand is Hand.FREE else Action.LOCATION,
        Gesture.GRASP: Action.CLOSE,
        Gesture.GIVE_ME: Action.HUMAN,
        Gesture.RELEASE: Action.OPEN,
    }[state.gesture]
    for state in VALID_STATES
}
Teacher = Callable[[bool, random.Random], Feedback]


def reward_focused(right: bool, rng: random.Random) -> Feedback:
    """Says OK to a right action, nothing to a wrong one (Loftin et al.'s reward-focused)."""
    return Feedback.OK if right else Feedback.NONE


def punishment_focused(right: bool, rng: random.Random) -> Feedback:
    """Says nothing to a right action, not-OK to a wrong one (the paper's assumed teacher)."""
    return Feedback.NONE if right else Feedback.NOT_OK


def looks_away(right: bool, rng: random.Random) -> Feedback:
    """Gives the right thumb, but half the time none at all, whatever the action."""
    if rng.random() < 0.5:
        return Feedback.NONE
    return Feedback.OK if right else Feedback.NOT_OK


def flips(share: float) -> Teacher:
    """Gives the right thumb, flipped with probability ``share`` (never silent)."""

    def teacher(right: bool, rng: random.Random) -> Feedback:
        honest = right != (rng.random() < share)
        return Feedback.OK if honest else Feedback.NOT_OK

    return teacher


def teach(
    learner: RobustLearner,
    teacher: Teacher,
    rounds: int,
    seed: int = 0,
    states: tuple[State, ...] = VALID_STATES,
) -> int:
    """Each of ``states`` ``rounds`` times, in turn: the learner acts until the teacher says
    OK (at most 5 actions a round); the wrong actions it took."""
    rng = random.Random(seed)
    wrong = 0
    for _ in range(rounds):
        for state in states:
            for _try in range(5):
                action = learner.choose(state)
                heard = teacher(action is RIGHT[state], rng)
                learner.feedback(state, action, heard)
                wrong += action is not RIGHT[state]
                if heard is Feedback.OK:
                    break
    return wrong


# -- PIL's strengths --------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
def test_one_ok_is_enough_to_exploit_the_action_next_time(seed: int) -> None:
    """One-shot learning with right thumbs: refused actions, one OK; the next time the state
    comes the robot exploits that action. (Fails if an OK weighed too little to make the
    action the most probable: e.g. a prior consistency of 0.5.)"""
    learner = RobustLearner(seed)
    state = State(Gesture.GRASP, Action.OBJECT, Hand.FREE)
    while (action := learner.decide("grasp", "object", "free").action) is not Action.CLOSE:
        assert action is not None
        learner.feedback(state, action, False)
    learner.feedback(state, Action.CLOSE, True)
    again = learner.decide("grasp", "object", "free")
    assert again.action is Action.CLOSE and again.exploited


@pytest.mark.parametrize("seed", range(5))
def test_table_one_misread_at_step_21_is_corrected_to_release(seed: int) -> None:
    """Section III-B: pointing misread as grasp while holding (t = 21) is corrected from the
    learnt transitions to release, and the robot opens. (Fails with correction=False.)"""
    learner = RobustLearner(seed)
    _replay(learner, until=21)
    decision = learner.decide("grasp", "human", "occupied")
    assert decision.corrected and decision.state == State("release", "human", "occupied")
    assert decision.action is Action.OPEN
    off = RobustLearner(seed, correction=False)
    _replay(off, until=21)
    assert off.decide("grasp", "human", "occupied").action is None


def test_after_a_refusal_what_another_gesture_means_comes_next() -> None:
    """A valid misread (grasp read as pointing at the leg): the pointing's action is refused,
    and the robot next does what grasp means there, not a random action. (Fails with a
    misread prior of 0: only the reading's own state would count.)"""
    for seed in range(10):
        learner = RobustLearner(seed)
        teach(learner, flips(0.0), rounds=2)
        pointing = State(Gesture.POINTING, Action.OBJECT, Hand.FREE)
        assert learner.choose(pointing) is Action.OBJECT
        learner.feedback(pointing, Action.OBJECT, False)
        assert learner.choose(pointing) is Action.CLOSE


def test_a_shared_prior_exploits_an_unseen_state_from_its_gesture_and_hand() -> None:
    """Table I, t = 17: <pointing, object, free> never seen; the paper's learner explores at
    random, the robust one acts on what pointing with a free hand meant (object). (Fails with
    share=0.)"""
    learner = RobustLearner(0)
    _replay(learner, until=17)
    decision = learner.decide("pointing", "object", "free")
    assert decision.action is Action.OBJECT and decision.exploited
    flat = RobustLearner(0, share=0.0)
    _replay(flat, until=17)
    assert not flat.decide("pointing", "object", "free").exploited


# -- what silence means is learnt ---------------------------------------------------------------
@pytest.mark.parametrize(
    ("teacher", "meaning"),
    [(reward_focused, "not OK"), (punishment_focused, "OK"), (looks_away, "nothing")],
)
def test_what_silence_means_is_learnt_from_the_teacher(teacher: Teacher, meaning: str) -> None:
    """SABL: the same silence means not-OK from a reward-focused teacher, OK from a
    punishment-focused one, nothing from one who looks away; the robot learns the right
    actions from each. (Fails without the EM refit: silence keeps its prior weight, 0.)"""
    learner = RobustLearner(0)
    teach(learner, teacher, rounds=6)
    assert learner.beliefs.teacher.likelihoods.silence_means == meaning
    learnt = sum(learner.choose(s) is RIGHT[s] for s in VALID_STATES)
    assert learnt == len(VALID_STATES)


def test_the_teachers_consistency_is_estimated() -> None:
    """Policy Shaping's C: a teacher whose thumbs are flipped 20 % of the time is estimated
    near 0.8, a consistent one above 0.93. (Fails with fixed likelihoods: 0.9 for both.)"""
    sloppy, careful = RobustLearner(0), RobustLearner(0)
    teach(sloppy, flips(0.2), rounds=30, seed=1)
    teach(careful, flips(0.0), rounds=30, seed=1)
    assert abs(sloppy.beliefs.teacher.likelihoods.consistency - 0.8) < 0.05
    assert careful.beliefs.teacher.likelihoods.consistency > 0.93


# -- take-back and decay ----------------------------------------------------------------------
def test_an_approval_the_world_contradicts_is_taken_back() -> None:
    """An empty hand approved at the person (a wrong approval): the loop re-grounds and calls
    ``regrounded``; the robot no longer believes human is meant by pointing there. (Fails if
    the take-back did not count against the action.)"""
    learner = RobustLearner(0)
    state = State(Gesture.POINTING, Action.OPEN, Hand.FREE)
    learner.feedback(state, Action.HUMAN, Feedback.NONE)  # silence: taken as approved
    learner.feedback(state, Action.HUMAN, Feedback.OK)  # and a (misread) OK on top
    assert learner.choose(state) is Action.HUMAN
    learner.regrounded(Action.HUMAN, Hand.FREE, Hand.FREE)
    assert learner.taken_back == 1
    assert learner.choose(state) is not Action.HUMAN
    assert learner.beliefs.posterior(state_id(state))[action_index(Action.HUMAN)] < 0.05


def test_the_person_takes_an_approval_back() -> None:
    """``take_back`` (the person's "that was wrong"): the action counts against its state,
    and the approved state before it is the last one again."""
    learner = RobustLearner(0)
    first = State(Gesture.POINTING, Action.OPEN, Hand.FREE)
    learner.feedback(first, Action.OBJECT, True)
    grasp = State(Gesture.GRASP, Action.OBJECT, Hand.FREE)
    learner.feedback(grasp, Action.OPEN, True)
    assert learner.take_back() == (grasp, Action.OPEN)
    assert learner.last_ok_state == first
    assert learner.choose(grasp) is not Action.OPEN
    assert learner.take_back() is None  # nothing more to take back


def test_a_refused_trusted_association_decays_and_evidence_is_bounded() -> None:
    """A mistaken association fades: however many OKs it got, its evidence stays at most
    CAP, and a refusal of it while trusted keeps DECAY of it before the refusal counts, so
    it falls below CAP * DECAY and well below where the refusal alone takes it. (Fails with
    cap or decay switched off.)"""
    state = State(Gesture.GIVE_ME, Action.CLOSE, Hand.OCCUPIED)
    sid, human = state_id(state), action_index(Action.HUMAN)

    def after_a_refusal(decay: float) -> float:
        learner = RobustLearner(0, decay=decay)
        for _ in range(20):
            learner.feedback(state, Action.HUMAN, True)
        assert learner.beliefs.evidence(sid)[human] == pytest.approx(CAP)
        learner.feedback(state, Action.HUMAN, False)
        return learner.beliefs.evidence(sid)[human]

    decayed, kept = after_a_refusal(DECAY), after_a_refusal(1.0)
    assert decayed < CAP * DECAY and decayed < kept - 1.0


@pytest.mark.parametrize(
    ("decay", "cap", "within"), [(DECAY, CAP, 1), (1.0, CAP, 2), (DECAY, 1e9, 4), (1.0, 1e9, 8)]
)
def test_a_changed_meaning_is_taken_up_within_a_few_instructions(
    decay: float, cap: float, within: int
) -> None:
    """After 20 approvals of human for give me, the person means location: with decay and
    the cap the robot exploits location after one instruction; with the cap alone after two,
    with the decay alone after four, with neither after eight (measured; each part counts)."""
    learner = RobustLearner(0, decay=decay, cap=cap)
    state = State(Gesture.GIVE_ME, Action.CLOSE, Hand.OCCUPIED)
    for _ in range(20):
        learner.feedback(state, Action.HUMAN, True)
    instructions = 0
    while instructions < 50:
        instructions += 1
        while (action := learner.choose(state)) is not Action.LOCATION:
            learner.feedback(state, action, False)
        learner.feedback(state, Action.LOCATION, True)
        if learner.choose(state) is Action.LOCATION:
            break
    assert instructions == within


# -- asking ---------------------------------------------------------------------------------------
def test_asks_for_a_thumb_when_silence_says_nothing_and_it_is_unsure() -> None:
    """With a teacher who looks away half the time, an unsure choice carries ``confirm``
    (the robot asks); a sure one does not; ``ask=False`` never asks; and with a teacher
    who is always clear silence is never heard, so the robot never asks."""
    free = tuple(s for s in VALID_STATES if s.hand is Hand.FREE)  # taught; the rest unseen
    unseen = State(Gesture.GIVE_ME, Action.LOCATION, Hand.OCCUPIED)
    learner = RobustLearner(0)
    teach(learner, looks_away, rounds=2, states=free)
    assert learner.beliefs.teacher.silence_is_ambiguous(3.0)
    decision = learner.decide("give me", "location", "occupied")
    assert decision.state == unseen and decision.confirm and learner.last_p < 0.7
    teach(learner, flips(0.0), rounds=3)
    assert not learner.decide("give me", "location", "occupied").confirm  # sure now
    quiet = RobustLearner(0, ask=False)
    teach(quiet, looks_away, rounds=2, states=free)
    assert not quiet.decide("give me", "location", "occupied").confirm
    clear = RobustLearner(0)
    teach(clear, flips(0.0), rounds=2, states=free)
    assert not clear.decide("give me", "location", "occupied").confirm


def test_asking_stops_when_asking_gets_no_answer() -> None:
    """A thumb the cameras cannot read stays silent however often the robot asks: after
    TRIAL asks answered by silence as often as unasked actions, the robot stops asking."""
    learner = RobustLearner(0)
    for _ in range(TRIAL + 5):
        learner.answers.heard(Feedback.NONE, asked=True)
        learner.answers.heard(Feedback.NONE, asked=False)
    assert not learner.answers.helps()


def test_the_request_reaches_the_person_and_the_feedback_channel() -> None:
    """The loop turns ``confirm`` into a request: the decided record says so (for a page),
    a person who approves by silence half the time answers with a thumb, and the bench's
    channel, which silences half the thumbs, lets that thumb through. (Fails when the loop
    does not pass the request on: asked actions would be answered by silence too.)"""
    scenario = load_scenario()
    person = ScriptedPerson.for_types(scenario, scenario.draw_types(8, 0), 0, silent_ok=0.5)
    learner = RobustLearner(0)
    decided: list[StepRecord] = []

    class Observer:
        def decided(self, record: StepRecord) -> None:
            decided.append(record)

        def answered(self, record: StepRecord) -> None: ...
        def received(self, record: StepRecord) -> None: ...

    detector = Detector(1.0, 0, deck_size=len(person.script))
    reader = FeedbackChannel(detector, {"silence": 0.5}, 0)
    records = list(steps(learner, person, reader, SymbolicWorld(), observer=Observer()))
    asked = [r for r in records if r.confirm]
    assert len(asked) >= 5
    assert all(r.feedback is not Feedback.NONE for r in asked)
    assert all(r.feedback_read is not Feedback.NONE for r in asked if not r.interrupted)
    assert [r.confirm for r in decided] == [r.confirm for r in records if r.action is not None]
    unasked = [r for r in records if r.action is not None and not r.confirm]
    assert any(r.feedback_read is Feedback.NONE for r in unasked)
    channel = FeedbackChannel(detector, {"silence": 1.0}, 0)
    assert channel.read_feedback(Feedback.OK) is Feedback.NONE
    channel.confirm_requested()
    assert channel.read_feedback(Feedback.OK) is Feedback.OK


# -- registration and determinism ----------------------------------------------------------------
def test_registered_and_selectable() -> None:
    """``pil-robust`` is a bench reference agent; ``learner=robust`` and the system
    ``pil-robust`` select it in a run; a bad name says the valid ones."""
    assert isinstance(REFERENCE["pil-robust"](3, {}), RobustLearner)
    from pil.task.assemble import assemble

    assert isinstance(assemble(parse_run_spec(params={"learner": "robust"})).learner, RobustLearner)
    assert isinstance(assemble(parse_run_spec(system="pil-robust")).learner, RobustLearner)
    assert not isinstance(assemble(parse_run_spec()).learner, RobustLearner)
    assert isinstance(assemble(parse_run_spec()).learner, Learner)
    with pytest.raises(RobinPilError, match="'pil', 'robust'"):
        parse_run_spec(params={"learner": "robot"})


def test_same_seed_same_run() -> None:
    """Determinism: one seed, one bench run, twice, under the noisiest teacher."""
    suite = load_suite()
    track = suite.track("assembly")
    seed = suite.seeds("dev", quick=True)[0]
    make = REFERENCE["pil-robust"]
    first = run_track(suite, track, "teacher", seed, lambda s: make(s, {}), True)
    again = run_track(suite, track, "teacher", seed, lambda s: make(s, {}), True)
    assert first == again and not first["failed"]
