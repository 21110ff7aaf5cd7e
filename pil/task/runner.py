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
from typing import Any

from pil.learner import Learner
from pil.task.counting import RunStats
from pil.task.detector import GestureReader
from pil.task.grounding import AFTER_DROP
from pil.task.person import Person, ScriptedPerson
from pil.task.records import StepObserver, StepRecord
from pil.task.step_phases import (
    ASK_AFTER_REPEATS,
    MAX_ACTIONS_PER_GESTURE,
    MAX_PERFORMANCES,
    RunnerError,
    StepOptions,
    StepPhases,
)
from pil.task.world import World

__all__ = [
    "AFTER_DROP",
    "ASK_AFTER_REPEATS",
    "MAX_ACTIONS_PER_GESTURE",
    "MAX_PERFORMANCES",
    "RunnerError",
    "StepObserver",
    "StepRecord",
    "run",
    "steps",
]


def steps(
    learner: Learner,
    person: Person,
    detector: GestureReader,
    world: World,
    *,
    manual: bool = False,
    repeat_discarded: bool = False,
    max_actions_per_gesture: int = MAX_ACTIONS_PER_GESTURE,
    ask_after: int = ASK_AFTER_REPEATS,
    observer: StepObserver | None = None,
) -> Iterator[StepRecord]:
    """Run ``person``'s script to the end, yielding a record per action or repeat request.

    Per performance of a gesture, in the order things happen: the person performs it, the
    detector reads it, the learner decides; per action the robot acts, the person judges it and
    shows the thumb, and only then the learner receives the feedback; then the person does what
    follows the thumb (e.g. carries a delivered leg away) and the record is yielded.
    A robot whose state no right approval reaches re-grounds it in its hand
    (:mod:`pil.task.grounding`); after ``ask_after`` repeat requests in a row it proposes an
    action instead of asking again (:mod:`pil.task.asking`). Before each instruction the
    person may say the robot's last approved action was wrong (``person.takes_back``): the loop
    takes that approval back (:meth:`StepPhases.take_back`; the next record's ``reason`` starts
    "taken back: ...") and asks the person for their next instruction. ``observer`` is told of each
    decision, answer and received feedback (before that carry: a live session logs the step
    there, so ending during the carry loses nothing).
    """
    loop = StepPhases(learner, person, detector, world, observer)
    options = StepOptions(manual, repeat_discarded, max_actions_per_gesture, ask_after)
    laid: set[int] = set()
    anticipate = getattr(learner, "anticipate", None)  # the baselines of pil.agents have none
    while (item := person.next_step(world.hand())) is not None:
        # the safe point between instructions: the person may take the last approval back
        if person.takes_back(loop.state.approved):
            person.taken_back(loop.take_back())
            continue  # the person's next instruction, in the state before that approval
        intent = item.intent
        if item.first_of_table and intent.table not in laid:
            laid.add(intent.table)
            person.start_table(intent.table)
            world.start_table(intent.table)
        hand = world.hand()
        state = loop.state
        guess = None
        regrounded = loop.grounded(hand)  # a drop or a wrong approval: no anticipation
        if state.approved and anticipate and not regrounded and person.lets_robot_go_first():
            guess = anticipate(state.previous, hand)
        state.approved = False
        if guess is not None and not (yield from loop.anticipated(item, guess, hand)):
            continue  # the robot acted before the gesture: no gesture for this instruction
        yield from loop.instruction(item, options)


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
