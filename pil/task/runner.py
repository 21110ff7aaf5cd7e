"""The step loop shared by the learner-only study and the physical episode.

:func:`steps` drives a learner, a scripted person, a detector and a :class:`pil.task.world.World`
through a script and yields one :class:`StepRecord` per event: an executed action, or a
request to the person to repeat the gesture (``action`` None). Callers log, render or count
the records and may stop at any time. :func:`run` consumes the loop and returns
:class:`RunStats`.

Per instruction gesture (Algorithm 1): the detector reads the gesture; with ``manual`` set
(conditions 3 and 4) the person repeats it until it is read right. The learner decides on
the state <detected gesture, last approved action, ``world.hand()``>, correcting or asking for
a repeat when it is invalid. The robot acts; on not-OK it tries the next action for the same
state (a rejected action leaves the last approved action unchanged), until the person
approves. The decisions depend only on the seeds of the learner, detector and person.

A proactive learner (``Learner(proactive=True)``) may act before an instruction's gesture
(:func:`_anticipate`): after an approved action, when the learnt transitions make one next
state likely enough (:mod:`pil.anticipation`), the robot performs that state's best action
while the person watches. Let happen, it counts as OK and the person moves on without
performing the gesture; stopped, it counts as not-OK for the anticipated state and the person
performs the gesture as usual.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any, Protocol

from pil.anticipation import Anticipation
from pil.errors import RobinPilError
from pil.gesture_evidence import meant_gesture
from pil.learner import Learner
from pil.table import AssociationTable
from pil.task.counting import RunStats
from pil.task.detector import GestureReader, LearnsFromFeedback
from pil.task.person import Person, ScriptedPerson, ScriptStep
from pil.task.records import StepRecord
from pil.task.world import World
from pil.types import START_ACTION, START_HAND, Action, Feedback, Gesture, Hand, State, hand_after

# Random exploration has a geometric tail: 25 misses in a row at p = 3/4 happen about once a
# study, 100 about once in 1e10 studies.
MAX_ACTIONS_PER_GESTURE = 100
MAX_PERFORMANCES = 1000  # times one instruction gesture may be performed before giving up
_DELIVERY_FROM = (Action.HUMAN, Action.LOCATION)
_NOT_OK, _OPEN, _OCCUPIED = Feedback.NOT_OK, Action.OPEN, Hand.OCCUPIED
# The last action the state takes when physics changed the hand without an approved action: a
# hand that lost its leg is open and empty, as at the start; one that caught a leg has closed.
AFTER_DROP: dict[Hand, Action] = {Hand.FREE: Action.OPEN, Hand.OCCUPIED: Action.CLOSE}


class RunnerError(RobinPilError):
    """The loop cannot go on (e.g. an instruction that never gets an approved action)."""


class StepObserver(Protocol):
    """Presentation of the loop (e.g. a video overlay); it must not act in the world."""

    def decided(self, record: StepRecord) -> None:
        """The robot is about to act on ``record`` (no feedback or outcome yet)."""
        ...

    def answered(self, record: StepRecord) -> None:
        """The person is about to show ``record.feedback``."""
        ...

    def received(self, record: StepRecord) -> None:
        """The learner has received ``record``'s feedback (the step is complete; a delivered
        leg is in the person's hand, before they carry it away)."""
        ...


def steps(
    learner: Learner,
    person: Person,
    detector: GestureReader,
    world: World,
    *,
    manual: bool = False,
    repeat_discarded: bool = False,
    max_actions_per_gesture: int = MAX_ACTIONS_PER_GESTURE,
    observer: StepObserver | None = None,
) -> Iterator[StepRecord]:
    """Run ``person``'s script to the end, yielding a record per action or repeat request.

    Per performance of a gesture, in the order things happen: the person performs it, the
    detector reads it, the learner decides; per action the robot acts, the person judges it and
    shows the thumb, and only then the learner receives the feedback; then the person does what
    follows the thumb (e.g. carries a delivered leg away) and the record is yielded.
    ``observer`` is told of each decision, answer and received feedback (before that carry:
    a live session logs the step there, so ending during the carry loses nothing).
    """
    previous, expected = START_ACTION, START_HAND
    gestures = actions = legs = 0
    laid: set[int] = set()
    anticipate = getattr(learner, "anticipate", None)  # the baselines of pil.agents have none
    approved = False  # the last action was approved: the robot may anticipate the next one
    while (item := person.next_step(world.hand())) is not None:
        intent = item.intent
        true = intent.gesture
        if item.first_of_table and intent.table not in laid:
            laid.add(intent.table)
            person.start_table(intent.table)
            world.start_table(intent.table)
        # --- the proactive robot: act before the gesture (see _anticipate) ---------------------
        hand = world.hand()
        guess = anticipate(previous, hand) if approved and anticipate and hand is expected else None
        approved = False
        if guess is not None:
            record = _anticipate(
                learner,
                person,
                detector,
                world,
                item,
                guess,
                actions + 1,
                gestures,
                legs,
                previous,
                observer,
            )
            actions, legs = record.t, record.legs_delivered
            yield record
            if record.feedback_read is not _NOT_OK:  # the robot takes it as approved
                previous, expected = guess.action, hand_after(guess.action, hand)
                approved = True
            if record.feedback is not _NOT_OK:  # and the person lets it stand
                person.completed(item, guess.action)
                continue  # no gesture for this instruction
            if world.hand() is not hand or not approved:
                # The stopped action changed the hand, or the robot saw the stop: the person
                # re-plans (a scripted person's next instruction is this one again; a live
                # participant, asked for it only now, makes the gesture).
                continue
        # --- the instruction's gesture ---------------------------------------------------------
        spent = performed = 0  # actions and performances for this instruction
        done = changed = False
        again = ""  # why the gesture is to be made again (the repeat request's reason)
        while not (done or changed):
            if performed and not person.performs_again(again):
                break  # a live participant is asked anew (next_step): nothing loops
            gestures += 1
            performed += 1
            if performed > MAX_PERFORMANCES:
                raise RunnerError(
                    f"gesture {true.value!r} was performed {MAX_PERFORMANCES} times without "
                    f"the robot acting on it (detection rate {detector.rate}); use a higher rate"
                )
            person.perform(intent)
            detected = detector.detect(true)
            base = StepRecord(
                t=actions,
                gesture_count=gestures,
                table=intent.table,
                handover=intent.handover,
                handover_type=item.handover_type,
                step=item.step,
                true_gesture=true,
                detected_gesture=detected,
                intended_action=intent.action,
                legs_delivered=legs,
                target=intent.target,
                recovery=item.recovery,
            )
            if (manual and detected is not true) or (repeat_discarded and detected is None):
                what = "discarded" if detected is None else f"read as {detected.value}"
                again = f"{what}; the person repeats it"
                yield base._replace(reason=again)
                continue
            hand = world.hand()
            if hand is not expected:  # physics changed the hand (a drop): the robot's hand is
                previous, expected = AFTER_DROP[hand], hand  # open and empty, as at the start
            decision = learner.decide(detected, previous, hand)
            state = decision.state
            if state is None or decision.action is None:
                again = decision.reason
                yield base._replace(reason=again)
                continue
            base = base._replace(
                corrected_gesture=state.gesture if decision.corrected else None, state=state
            )
            action, exploited, reason = decision.action, decision.exploited, decision.reason
            rejections = 0
            while True:
                spent += 1
                if spent > max_actions_per_gesture:
                    raise RunnerError(
                        f"no approved action after {max_actions_per_gesture} actions for "
                        f"gesture {true.value!r} (step {item.step} of handover "
                        f"{intent.handover}, type {item.handover_type}); the world may keep "
                        "failing the wanted action"
                    )
                actions += 1
                if observer is not None:
                    observer.decided(
                        base._replace(t=actions, action=action, exploited=exploited, reason=reason)
                    )
                outcome = world.execute(action, intent.target, person.watch(intent))
                feedback = person.judge(intent, action, outcome)
                if observer is not None:
                    observer.answered(base._replace(t=actions, action=action, feedback=feedback))
                person.show_feedback(feedback)
                # What the robot sees of the thumb: it stopped a stopped action because it saw
                # the thumb go down; the thumb after an action that ran to its end is read.
                heard = _NOT_OK if outcome.interrupted else detector.read_feedback(feedback)
                ok = heard is not _NOT_OK  # no feedback counts as OK (eq. 1)
                delivered = (
                    ok and action is _OPEN and previous in _DELIVERY_FROM and hand is _OCCUPIED
                )
                legs += delivered
                record = base._replace(
                    t=actions,
                    action=action,
                    exploited=exploited,
                    reason=reason,
                    feedback=feedback,
                    succeeded=outcome.succeeded,
                    detail=outcome.detail,
                    delivered=delivered,
                    legs_delivered=legs,
                    interrupted=outcome.interrupted,
                    dropped=outcome.dropped,
                    feedback_read=heard,
                )
                learner.feedback(state, action, ok)
                if isinstance(detector, LearnsFromFeedback):  # what the learner just received
                    detector.verdict(_meant(learner, action, state) if ok else None, ok)
                if observer is not None:
                    observer.received(record)
                person.after_feedback(feedback)  # e.g. a delivered leg carried to the bin
                yield record
                if ok:  # the robot takes the step as approved
                    previous, expected = action, hand_after(action, hand)
                    approved = True
                if feedback is not _NOT_OK:  # the person does: on to their next instruction
                    person.completed(item, action)
                    done = True
                    break
                if ok or world.hand() is not hand:
                    changed = True  # the robot moved on, or the world changed: the person re-plans
                    break
                rejections += 1
                if person.loses_patience(rejections):
                    again = f"{rejections} actions rejected in a row"
                    break  # the person performs the gesture again
                action = learner.choose(state)
                exploited, reason = learner.last_exploited, learner.last_reason


def _anticipate(
    learner: Learner,
    person: Person,
    detector: GestureReader,
    world: World,
    item: ScriptStep,
    guess: Anticipation,
    t: int,
    gestures: int,
    legs: int,
    previous: Action,
    observer: StepObserver | None,
) -> StepRecord:
    """Perform ``guess`` before ``item``'s gesture while the person watches; its record.

    Nothing is pointed at (the world gets no target; :mod:`pil.anticipation` offers only a close
    or an open on a spot, done where the hand is); the person watches it as any action, meaning
    ``item``'s instruction, and stops it when it is not. The learner receives the feedback
    after the thumb, for the anticipated state; no gesture is performed or counted
    (``gesture_count`` stays).
    """
    intent, action, hand = item.intent, guess.action, world.hand()
    base = StepRecord(
        t=t,
        gesture_count=gestures,
        table=intent.table,
        handover=intent.handover,
        handover_type=item.handover_type,
        step=item.step,
        true_gesture=intent.gesture,
        detected_gesture=None,
        intended_action=intent.action,
        legs_delivered=legs,
        recovery=item.recovery,
        state=guess.state,
        action=action,
        exploited=True,
        reason=guess.reason,
        proactive=True,
    )
    if observer is not None:
        observer.decided(base)
    outcome = world.execute(action, None, person.watch(intent))
    feedback = person.judge(intent, action, outcome)
    if observer is not None:
        observer.answered(base._replace(feedback=feedback))
    person.show_feedback(feedback)
    heard = _NOT_OK if outcome.interrupted else detector.read_feedback(feedback)
    ok = heard is not _NOT_OK
    delivered = ok and action is _OPEN and previous in _DELIVERY_FROM and hand is _OCCUPIED
    record = base._replace(
        feedback=feedback,
        succeeded=outcome.succeeded,
        detail=outcome.detail,
        delivered=delivered,
        legs_delivered=legs + delivered,
        interrupted=outcome.interrupted,
        dropped=outcome.dropped,
        feedback_read=heard,
    )
    learner.feedback(guess.state, action, ok)
    if observer is not None:
        observer.received(record)
    person.after_feedback(feedback)
    return record


def _meant(learner: Learner, action: Action, state: State) -> Gesture | None:
    """The gesture an approved ``action`` means by the learner's table (None: a learner
    without one, or no evidence yet)."""
    table = getattr(learner, "table", None)
    if not isinstance(table, AssociationTable):
        return None
    return meant_gesture(table, action, state.previous_action, state.hand)


def run(
    learner: Learner,
    person: ScriptedPerson,
    detector: GestureReader,
    world: World,
    **options: Any,
) -> RunStats:
    """Run the loop to the end and count (:class:`RunStats`); ``options`` go to :func:`steps`."""
    stats = RunStats.for_script(person.script)
    for record in steps(learner, person, detector, world, **options):
        stats.add(record)
    return stats
