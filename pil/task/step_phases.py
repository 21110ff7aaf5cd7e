"""The phases of one step of the loop (:func:`pil.task.runner.steps`), each its own method.

:class:`StepPhases` carries the loop's state from step to step (:class:`LoopState`) and runs
a step's phases: the proactive robot acting before the gesture (:meth:`StepPhases.anticipated`,
:func:`pil.task.proactive_step.anticipate_step`), the instruction's gesture performed and read
(:meth:`StepPhases.instruction`) and the robot's actions until the person approves
(:meth:`StepPhases.acting`); each action is one watched action
(:func:`pil.task.watched_action.watched_action`). The loop's constants and its error are here
too.
"""

from __future__ import annotations

from collections.abc import Generator, Iterator
from dataclasses import dataclass, replace

from pil.anticipation import Anticipation
from pil.errors import RobinPilError
from pil.learner import Decision, Learner
from pil.task.asking import ask_unreadable
from pil.task.detector import GestureReader
from pil.task.grounding import ground
from pil.task.person import Person
from pil.task.proactive_step import anticipate_step
from pil.task.records import StepObserver, StepRecord, item_record
from pil.task.script import ScriptStep
from pil.task.watched_action import StepParts, watched_action
from pil.task.world import World
from pil.types import START_ACTION, START_HAND, Action, Feedback, Hand, hand_after

# Random exploration has a geometric tail: 25 misses in a row at p = 3/4 happen about once a
# study, 100 about once in 1e10 studies.
MAX_ACTIONS_PER_GESTURE = 100
MAX_PERFORMANCES = 1000  # times one instruction gesture may be performed before giving up
# Repeat requests in a row (discarded or invalid gestures the correction could not mend) after
# which the robot stops asking for the gesture and proposes an action for the person to judge
# (pil.task.asking). At the study's lowest rate (0.4: 30 % discarded) ten discards in a row
# come about once in 170 000 gestures, so the paper's study is unchanged.
ASK_AFTER_REPEATS = 10
_NOT_OK = Feedback.NOT_OK


class RunnerError(RobinPilError):
    """The loop cannot go on (e.g. an instruction that never gets an approved action)."""


@dataclass(frozen=True, slots=True)
class StepOptions:
    """The loop's options (:func:`steps`)."""

    manual: bool
    repeat_discarded: bool
    max_actions_per_gesture: int
    ask_after: int = ASK_AFTER_REPEATS


@dataclass(slots=True)
class LoopState:
    """What the loop carries from step to step."""

    previous: Action = START_ACTION  # the last approved action (the state's)
    expected: Hand = START_HAND  # the hand the robot expects after it
    gestures: int = 0
    actions: int = 0
    legs: int = 0
    approved: bool = False  # the last action was approved: the robot may anticipate the next
    before: tuple[Action, Hand] | None = None  # previous and expected before the last approval
    repeats: int = 0  # repeat requests in a row since a gesture was last read and acted on
    asks: int = 0  # actions proposed for unreadable gestures since then

    def approve(self, action: Action, hand: Hand) -> None:
        """The robot takes ``action``, done with ``hand``, as approved."""
        self.before = self.previous, self.expected
        self.previous, self.expected = action, hand_after(action, hand)
        self.approved = True

    def ground(self, hand: Hand) -> str:
        """Ground the last action in ``hand``, the world's (:func:`pil.task.grounding.ground`);
        why it changed ("" when it did not)."""
        self.previous, why = ground(self.previous, self.expected, hand)
        self.expected = hand
        return why


@dataclass(slots=True)
class InstructionTally:
    """One instruction's count of actions and performances, and why it is made again."""

    spent: int = 0
    performed: int = 0
    again: str = ""


class StepPhases:
    """The phases of a step (:func:`steps`): the proactive robot acting before the gesture,
    the gesture's performances and reading, and the actions until the person approves."""

    def __init__(
        self,
        learner: Learner,
        person: Person,
        detector: GestureReader,
        world: World,
        observer: StepObserver | None,
    ) -> None:
        self.learner, self.person, self.detector, self.world = learner, person, detector, world
        self.parts = StepParts(learner, person, detector, world, observer)
        self.state = LoopState()
        self.note = ""  # why the state was last re-grounded, until a record says it

    def anticipated(
        self, item: ScriptStep, guess: Anticipation, hand: Hand
    ) -> Generator[StepRecord, None, bool]:
        """The proactive robot performs ``guess`` (:func:`anticipate_step`); True when the
        person is to make the instruction's gesture after all (they stopped it, the hand
        unchanged and the robot unaware)."""
        state = self.state
        record = anticipate_step(
            self.parts, item, guess, state.actions + 1, state.gestures, state.legs, state.previous
        )
        state.actions, state.legs = record.t, record.legs_delivered
        yield record
        if record.feedback_read is not _NOT_OK:  # the robot takes it as approved
            state.approve(guess.action, hand)
        if record.feedback is not _NOT_OK:  # and the person lets it stand
            self.person.completed(item, guess.action)
            return False
        # The stopped action changed the hand, or the robot saw the stop: the person re-plans
        # (a scripted person's next instruction is this one again; a live participant, asked
        # for it only now, makes the gesture).
        return self.world.hand() is hand and state.approved

    def grounded(self, hand: Hand) -> str:
        """Ground the robot's state in ``hand`` (a drop, or a wrong approval: see
        :mod:`pil.task.grounding`) and tell a learner that listens (``regrounded``); why the
        state changed ("" when it did not)."""
        state = self.state
        before, expected = state.previous, state.expected
        why = state.ground(hand)
        if why:
            self.note = why
            listener = getattr(self.learner, "regrounded", None)
            if listener is not None:
                listener(before, expected, hand)
        return why

    def take_back(self) -> str:
        """The person says the last approved action was wrong: the learner takes its approval
        back (``take_back``, where it has one) and the robot's state is the one before it,
        grounded in the hand the world reports now. What was taken back ("" when nothing
        was: no approval since the last take-back)."""
        state = self.state
        if state.before is None:
            return ""
        withdraw = getattr(self.learner, "take_back", None)
        taken = withdraw() if withdraw is not None else None
        undone = state.previous
        state.previous, state.expected = state.before
        state.before, state.approved = None, False
        self.grounded(self.world.hand())
        what = f"{undone.value} taken back"
        if taken is not None:
            what += f" (its approval in {taken[0].key()} withdrawn)"
        self.note = _joined(f"taken back: {what}", self.note)  # said on the next record
        return what

    def instruction(self, item: ScriptStep, options: StepOptions) -> Iterator[StepRecord]:
        """The instruction's gesture, performed and read until the robot acts on it and the
        person approves (or re-plans, or a live participant is asked anew)."""
        person, intent, state = self.person, item.intent, self.state
        true = intent.gesture
        steps = InstructionTally()
        while True:
            if steps.performed and not person.performs_again(steps.again):
                return  # a live participant is asked anew (next_step): nothing loops
            state.gestures += 1
            steps.performed += 1
            if steps.performed > MAX_PERFORMANCES:
                raise RunnerError(
                    f"gesture {true.value!r} was performed {MAX_PERFORMANCES} times without "
                    f"the robot acting on it (detection rate {self.detector.rate}); use a "
                    "higher rate"
                )
            person.perform(intent)
            detected = self.detector.detect(true)
            base = item_record(
                item, state.actions, state.gestures, state.legs, detected, intent.target
            )
            if (options.manual and detected is not true) or (
                options.repeat_discarded and detected is None
            ):
                what = "discarded" if detected is None else f"read as {detected.value}"
                steps.again = f"{what}; the person repeats it"
                yield base._replace(reason=steps.again)
                continue
            hand = self.world.hand()
            self.grounded(hand)
            grounded, self.note = self.note, ""  # said on this gesture's first record
            decision = self.learner.decide(detected, state.previous, hand)
            if decision.action is not None:
                state.repeats = state.asks = 0  # read and acted on
            elif state.repeats + 1 >= options.ask_after:
                decision = ask_unreadable(self.learner, decision, state.previous, hand, state.asks)
                state.asks += 1
            if grounded:
                decision = replace(decision, reason=_joined(grounded, decision.reason))
            if decision.state is None or decision.action is None:
                state.repeats += 1
                steps.again = decision.reason
                yield base._replace(reason=steps.again)
                continue
            acted = decision.state
            base = base._replace(
                corrected_gesture=acted.gesture if decision.corrected else None, state=acted
            )
            if (yield from self.acting(item, base, decision, hand, steps, options)):
                return  # approved, or the person re-plans

    def acting(
        self,
        item: ScriptStep,
        base: StepRecord,
        decision: Decision,
        hand: Hand,
        steps: InstructionTally,
        options: StepOptions,
    ) -> Generator[StepRecord, None, bool]:
        """The robot acts on ``decision`` and on each next choice while the person refuses;
        True when the instruction is over (approved, or the robot or the world moved on),
        False when the person performs the gesture again (out of patience)."""
        learner, person, world = self.learner, self.person, self.world
        intent, state = item.intent, self.state
        learnt = base.state
        assert learnt is not None and decision.action is not None
        action, exploited, reason = decision.action, decision.exploited, decision.reason
        confirm = decision.confirm
        rejections = 0
        while True:
            steps.spent += 1
            if steps.spent > options.max_actions_per_gesture:
                raise RunnerError(
                    f"no approved action after {options.max_actions_per_gesture} actions for "
                    f"gesture {intent.gesture.value!r} (step {item.step} of handover "
                    f"{intent.handover}, type {item.handover_type}); the world may keep "
                    "failing the wanted action"
                )
            state.actions += 1
            shown = base._replace(t=state.actions, action=action)
            record = watched_action(
                self.parts,
                intent,
                shown,
                hand,
                state.previous,
                exploited=exploited,
                reason=reason,
                confirm=confirm,
            )
            state.legs = record.legs_delivered
            ok, feedback = record.feedback_read is not _NOT_OK, record.feedback
            yield record
            if ok:  # the robot takes the step as approved
                state.approve(action, hand)
            if feedback is not _NOT_OK:  # the person does: on to their next instruction
                person.completed(item, action)
                return True
            if ok or world.hand() is not hand:
                return True  # the robot moved on, or the world changed: the person re-plans
            rejections += 1
            if person.loses_patience(rejections):
                steps.again = f"{rejections} actions rejected in a row"
                return False  # the person performs the gesture again
            action = learner.choose(learnt)
            exploited, reason = learner.last_exploited, learner.last_reason
            confirm = getattr(learner, "last_confirm", False)  # a learner that may ask


def _joined(first: str, second: str) -> str:
    return f"{first}; {second}" if first else second
