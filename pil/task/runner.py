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
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any, NamedTuple

from pil.errors import RobinPilError
from pil.learner import Learner
from pil.task.detector import Detector
from pil.task.person import ScriptedPerson
from pil.task.world import Target, World
from pil.types import START_ACTION, Action, Feedback, Gesture, Hand, State

# Random exploration has a geometric tail: 25 misses in a row at p = 3/4 happen about once a
# study, 100 about once in 1e10 studies.
MAX_ACTIONS_PER_GESTURE = 100
MAX_PERFORMANCES = 1000  # times one instruction gesture may be performed before giving up
_DELIVERY_FROM = (Action.HUMAN, Action.LOCATION)
_NOT_OK, _OPEN, _OCCUPIED = Feedback.NOT_OK, Action.OPEN, Hand.OCCUPIED


class RunnerError(RobinPilError):
    """The loop cannot go on (e.g. an instruction that never gets an approved action)."""


class StepRecord(NamedTuple):
    """One event of the loop (immutable). ``action`` None: the robot asks for a repeat."""

    t: int  # robot actions so far, this one included (Table I's step t)
    gesture_count: int  # instruction gestures performed so far, this one included
    table: int  # 0-based table
    handover: int  # 0-based handover (leg) in the whole run
    handover_type: str
    step: int  # 0-based gesture index within the handover
    true_gesture: Gesture
    detected_gesture: Gesture | None  # None: discarded as low-confidence
    corrected_gesture: Gesture | None  # set when the learner corrected the state
    state: State | None  # the state acted on (None for a repeat request)
    action: Action | None
    intended_action: Action
    feedback: Feedback | None
    succeeded: bool | None  # what the world reported (None: no action)
    detail: str
    delivered: bool  # Algorithm 1, line 19: this approved open delivered a leg
    legs_delivered: int
    exploited: bool
    reason: str
    target: Target | None = None  # the leg or spot the person indicates (None: nothing)

    @property
    def state_key(self) -> str | None:
        """The acted-on state as its text key, e.g. ``"pointing|open|free"``."""
        return None if self.state is None else self.state.key()

    @property
    def is_repeat(self) -> bool:
        """True for a repeat request (no action executed)."""
        return self.action is None

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready values (enums as the paper's names, the state as its key)."""
        out = self._asdict()
        out["state"] = self.state_key
        target = self.target
        out["target"] = None if target is None else {"kind": target.kind, "index": target.index}
        for key, value in out.items():
            if isinstance(value, (Gesture, Action, Feedback)):
                out[key] = value.value
        return out


@dataclass(slots=True)
class RunStats:
    """What a run cost and achieved (the study's counts)."""

    gestures: int = 0  # instruction gestures performed, repeats included
    actions: int = 0  # robot actions executed, rejected ones included
    rejected: int = 0  # actions that got not-OK
    corrections: int = 0  # states corrected by the learner (section III-B)
    repeats: int = 0  # gestures performed again (robot asked, manual repetition, patience)
    misdetections: int = 0  # gestures read wrong or discarded
    discarded: int = 0
    exploited: int = 0  # actions chosen as the unique best (eq. 4)
    legs: int = 0  # legs delivered
    handovers: int = 0  # handovers in the script
    scripted_gestures: int = 0  # gestures the script needs when every one is read right

    def as_dict(self) -> dict[str, int]:
        """The counts by name."""
        return {name: getattr(self, name) for name in self.__slots__}


def steps(
    learner: Learner,
    person: ScriptedPerson,
    detector: Detector,
    world: World,
    *,
    manual: bool = False,
    repeat_discarded: bool = False,
    max_actions_per_gesture: int = MAX_ACTIONS_PER_GESTURE,
    before_action: Callable[[StepRecord], None] | None = None,
) -> Iterator[StepRecord]:
    """Run ``person``'s script to the end, yielding a record per action or repeat request.

    ``before_action``, if given, is called with a preliminary record (no feedback or outcome
    yet) just before the world executes each action, e.g. to show the decision on a video.
    """
    previous = START_ACTION
    gestures = actions = legs = 0
    for item in person.script:
        intent = item.intent
        true = intent.gesture
        wanted_action = intent.action
        if item.first_of_table:
            world.start_table(intent.table)
        spent = performed = 0  # actions and performances for this instruction
        done = False
        while not done:
            gestures += 1
            performed += 1
            if performed > MAX_PERFORMANCES:
                raise RunnerError(
                    f"gesture {true.value!r} was performed {MAX_PERFORMANCES} times without "
                    f"the robot acting on it (detection rate {detector.rate}); use a higher rate"
                )
            detected = detector.detect(true)
            if (manual and detected is not true) or (repeat_discarded and detected is None):
                what = "discarded" if detected is None else f"read as {detected.value}"
                yield StepRecord(
                    actions, gestures, intent.table, intent.handover, item.handover_type,
                    item.step, true, detected, None, None, None, wanted_action, None, None,
                    "", False, legs, False, f"{what}; the person repeats it", intent.target,
                )  # fmt: skip
                continue
            decision = learner.decide(detected, previous, world.hand())
            state = decision.state
            if state is None or decision.action is None:
                yield StepRecord(
                    actions, gestures, intent.table, intent.handover, item.handover_type,
                    item.step, true, detected, None, None, None, wanted_action, None, None,
                    "", False, legs, False, decision.reason, intent.target,
                )  # fmt: skip
                continue
            corrected = state.gesture if decision.corrected else None
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
                hand = world.hand()
                if before_action is not None:
                    before_action(StepRecord(
                        actions + 1, gestures, intent.table, intent.handover,
                        item.handover_type, item.step, true, detected, corrected, state, action,
                        wanted_action, None, None, "", False, legs, exploited, reason,
                        intent.target,
                    ))  # fmt: skip
                outcome = world.execute(action, intent, action is wanted_action)
                actions += 1
                feedback = person.feedback(intent, action, outcome)
                ok = feedback is not _NOT_OK  # no feedback counts as OK (eq. 1)
                learner.feedback(state, action, ok)
                delivered = (
                    ok and action is _OPEN and previous in _DELIVERY_FROM and hand is _OCCUPIED
                )
                legs += delivered
                yield StepRecord(
                    actions, gestures, intent.table, intent.handover, item.handover_type,
                    item.step, true, detected, corrected, state, action, wanted_action,
                    feedback, outcome.succeeded, outcome.detail, delivered, legs, exploited,
                    reason, intent.target,
                )  # fmt: skip
                if ok:
                    previous = action
                    done = True
                    break
                rejections += 1
                if person.loses_patience(rejections):
                    break  # the person performs the gesture again
                action = learner.choose(state)
                exploited, reason = learner.last_exploited, learner.last_reason


def run(
    learner: Learner,
    person: ScriptedPerson,
    detector: Detector,
    world: World,
    **options: Any,
) -> RunStats:
    """Run the loop to the end and count (:class:`RunStats`); ``options`` go to :func:`steps`."""
    stats = RunStats(scripted_gestures=len(person.script))
    stats.handovers = len({item.intent.handover for item in person.script})
    last: StepRecord | None = None
    last_gesture = 0
    for record in steps(learner, person, detector, world, **options):
        if record.gesture_count != last_gesture:
            last_gesture = record.gesture_count
            if record.detected_gesture is not record.true_gesture:
                stats.misdetections += 1
                stats.discarded += record.detected_gesture is None
            if record.corrected_gesture is not None:
                stats.corrections += 1
        last = record
        if record.action is None:
            continue
        if record.feedback is Feedback.NOT_OK:
            stats.rejected += 1
        stats.exploited += record.exploited
    if last is not None:
        stats.gestures, stats.actions, stats.legs = last.gesture_count, last.t, last.legs_delivered
    stats.repeats = stats.gestures - stats.scripted_gestures
    return stats
