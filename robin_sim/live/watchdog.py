"""The live step's watchdog: no step in which nothing valid can follow.

A live session must never loop nor strand its participant: after each instruction gesture the
robot acts, the participant judges, and the step ends when an action stands.
:class:`StepWatchdog` counts the robot's attempts and the simulated time since the
participant's last instruction gesture; past :attr:`WatchdogLimits.attempts` attempts or
:attr:`WatchdogLimits.seconds` s, the participant
(:class:`~robin_sim.live.participant.LiveParticipant`) hands the step back: the robot stops
trying, the page asks for a gesture, and the event is logged (``events.jsonl``, ``watchdog``).
It also counts the participant's gestures in a row that Robin could not act on (handed back):
at :attr:`WatchdogLimits.handed_back` the event is ``watchdog`` and the page says the way on
(the guide's gesture; on the next one Robin proposes an action itself, the loop's
``ask_after``). A state of Robin's in which no gesture the guide could ask for would be acted
on (a wrong move let stand, a drop) is re-grounded as the loop grounds it
(:func:`pil.task.grounding.ground`; event ``regrounded``), and :func:`no_way_on` checks the
guide's gesture against it.
"""

from __future__ import annotations

from collections.abc import Callable

from pil.task.scenario import HandoverType
from pil.types import Action, Hand, State
from pil.validity import why_invalid
from robin_sim.live.guide import step_for
from robin_sim.live.limits import WatchdogLimits


class StepWatchdog:
    """Counts attempts and simulated time (``clock``) since the last instruction gesture."""

    def __init__(self, limits: WatchdogLimits, clock: Callable[[], float]) -> None:
        self.limits, self._clock = limits, clock
        self.attempts = 0
        self._since = clock()
        self.handed_back = 0  # the participant's gestures in a row Robin could not act on

    def acted(self) -> None:
        """Robin acts: the gestures handed back in a row start again."""
        self.handed_back = 0

    def hand_back(self) -> str:
        """A gesture of the participant's goes back to them: why the watchdog steps in (""
        while within :attr:`WatchdogLimits.handed_back` in a row)."""
        self.handed_back += 1
        if self.handed_back < self.limits.handed_back:
            return ""
        return f"{self.handed_back} of your gestures in a row Robin could not act on"

    def gesture(self) -> None:
        """The participant made an instruction gesture: the count starts again."""
        self.attempts, self._since = 0, self._clock()

    def attempt(self) -> None:
        """The robot starts an action."""
        self.attempts += 1

    @property
    def seconds(self) -> float:
        """Simulated seconds since the last instruction gesture."""
        return self._clock() - self._since

    def tripped(self) -> str:
        """Why the robot must stop trying now ("" while within the limits)."""
        limits = self.limits
        if self.attempts >= limits.attempts:
            return f"{self.attempts} actions since your last gesture"
        if self.seconds >= limits.seconds:
            return f"{self.seconds:.0f} s since your last gesture"
        return ""


def no_way_on(kind: HandoverType, done: int, previous: Action, hand: Hand) -> str:
    """Why the gesture the guide asks for (:func:`robin_sim.live.guide.step_for`, ``done``
    steps of ``kind`` let stand) would not be acted on in Robin's state <``previous``,
    ``hand``>: the state it makes is invalid ("" when it is valid: the learner acts on every
    valid state, :meth:`pil.learner.Learner.decide`)."""
    step = kind.steps[step_for(kind, done, previous, hand)]
    why = why_invalid(State(step.gesture, previous, hand))
    if why is None:
        return ""
    return f"the guide's {step.gesture.value} in <{previous.value}, {hand.value}>: {why}"


def way_on(stuck: str) -> str:
    """What the page tells a participant whose gesture was handed back: to gesture again, or,
    when the watchdog stepped in (``stuck``: why), the way on that works."""
    if not stuck:
        return "Make a gesture again, or another one."
    return (
        f"That was {stuck}. Make the gesture the guide asks for; if Robin cannot act on your "
        "next gesture either, it proposes an action for your thumb."
    )
