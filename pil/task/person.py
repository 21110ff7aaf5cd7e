"""The scripted person: performs each handover type's gestures and judges the robot's actions.

One :class:`ScriptedPerson` owns everything the person does, in the order a person does it:
:meth:`~ScriptedPerson.perform` the gesture, :meth:`~ScriptedPerson.watch` the robot act (and
stop it with a thumb down when it does something else), :meth:`~ScriptedPerson.judge` the
result and :meth:`~ScriptedPerson.show_feedback` with a thumb; only then does the learner
receive the feedback. The same person serves the symbolic study (no body: the action is seen at
once, nothing is shown) and the physical episode, whose :class:`PersonBody` perceives the
robot's motion, reacts after a reaction time, makes the gestures and thumbs visible, holds out
the palm and carries delivered legs away.

The person's next instruction follows the world (:meth:`~ScriptedPerson.next_step`): when a leg
the robot held has left its hand (a drop), the person first has it picked up again, pointing at
the leg where it lies (or, when it left the robot's reach, putting it back on the table: a
person intervention), then goes on with the script. A leg the person is about to point at
that lies off the table top (knocked to the floor by a motion) is put back the same way.

The person knows the correct association T_c: for every gesture of the script they want one
action (the step's action). They approve an action exactly when it is the wanted one *and* the
world reports that it worked; otherwise they give not-OK. With probability ``silent_ok`` they
approve by giving no feedback at all (the learner counts that as OK, eq. 1), except when the
robot asked for a thumb on the action (:meth:`~ScriptedPerson.confirm_requested`): then they
always show one.

``patience`` (0 = off) models a person who, after that many rejected actions in a row for
one gesture, performs the gesture again instead of waiting for the robot to find the action.

``take_back`` (0 = off) models a person who says "that was wrong" when the robot let a wrong
move stand (their thumb down missed, misread or late, so the robot took the move as approved):
with that probability per such move, after watching ``take_back_delay`` more robot actions, at
the loop's next safe point, before an instruction (:meth:`~ScriptedPerson.takes_back`; 0: before
the next gesture). The robot then takes back its *last* approval
(:meth:`pil.task.step_phases.StepPhases.take_back`): with a delay, that may be a later, right
one, as a late thumb lands on the next action. The person's own script is unchanged (they
never counted the wrong move as done).
"""

from __future__ import annotations

import random
from collections import deque
from collections.abc import Sequence
from typing import Protocol

from pil.task.scenario import HandoverType, Scenario
from pil.task.script import LegsSeen, ScriptStep, plan_script
from pil.task.watching import InstantWatcher, ReactionTime
from pil.task.world import Intent, Outcome, Target, Watcher
from pil.types import Action, Feedback, Gesture, Hand


class PersonBody(Protocol):
    """What the person's body does in a world where it can be seen (a physical episode)."""

    def start_table(self, table: int) -> None:
        """Before a new table's legs are laid out: the hand goes back to rest."""
        ...

    def perform(self, gesture: Gesture, target: Target | None) -> None:
        """Make ``gesture`` visibly (pointing at ``target``), hold it, and make room."""
        ...

    def watch(self, intent: Intent, reaction: float) -> Watcher:
        """Watch the robot's next action, meaning ``intent``: recognise from the motion when it
        is another action, then show thumb down ``reaction`` s later."""
        ...

    def show_feedback(self, feedback: Feedback) -> None:
        """Show the thumb (or nothing for silence) and hold it."""
        ...

    def after_feedback(self, feedback: Feedback) -> None:
        """What follows the thumb, e.g. carry a leg that now lies on the palm to the bin."""
        ...

    def recover(self, leg: int) -> bool:
        """Make leg ``leg`` (dropped by the robot) graspable again: True when the person had to
        put it back on the table themselves (a person intervention)."""
        ...

    def put_back_off_table(self, leg: int) -> bool:
        """Before pointing at leg ``leg``: put it back at its place on the table when it lies
        off the table top (e.g. knocked to the floor, where the robot cannot reach it) and the
        robot does not hold it; True when the person did (a person intervention)."""
        ...


class Person(Protocol):
    """What the step loop (:func:`pil.task.runner.steps`) needs of the person: a
    :class:`ScriptedPerson`, or a live participant (``robin_sim.live.participant``)."""

    def next_step(self, hand: Hand) -> ScriptStep | None:
        """The next instruction given the robot's ``hand`` (None: done)."""
        ...

    def completed(self, item: ScriptStep, action: Action) -> None:
        """``item``'s instruction got an approved ``action``."""
        ...

    def start_table(self, table: int) -> None:
        """A new table begins."""
        ...

    def perform(self, intent: Intent) -> None:
        """Perform ``intent``'s gesture."""
        ...

    def watch(self, intent: Intent) -> Watcher:
        """How the person watches the robot's next action."""
        ...

    def judge(self, intent: Intent, action: Action, outcome: Outcome) -> Feedback:
        """The person's verdict on the action."""
        ...

    def show_feedback(self, feedback: Feedback) -> None:
        """Give the thumb before the learner receives it."""
        ...

    def after_feedback(self, feedback: Feedback) -> None:
        """What follows the thumb."""
        ...

    def loses_patience(self, rejections: int) -> bool:
        """True when ``rejections`` in a row make the person perform the gesture again."""
        ...

    def performs_again(self, reason: str) -> bool:
        """The robot wants the instruction's gesture again (``reason``: a discarded or invalid
        reading, or the person's lost patience). True: the person makes it again at once (a
        scripted person); False: the loop asks :meth:`next_step` anew (a live participant,
        who decides what to do next)."""
        ...

    def lets_robot_go_first(self) -> bool:
        """Asked before a proactive robot anticipates the instruction ``next_step`` returned:
        False when the person made its gesture first (a live participant whose watchdog held
        the robot back), so that gesture is performed, never dropped."""
        ...

    def takes_back(self, stood: bool) -> bool:
        """Asked at the loop's safe point, before each instruction: True when the person says
        "that was wrong" now, of the robot's last approved action. ``stood``: the robot took
        its last action (since it last asked) as approved."""
        ...

    def taken_back(self, what: str) -> None:
        """The robot took its last approval back (``what`` says which; "" when none stood)."""
        ...


class ScriptedPerson:
    """Performs a script, watches the robot and gives feedback (own seeded RNGs).

    ``body``, when given, makes what the person does visible in a physical world;
    ``reaction_time`` is the mean and spread (s) of the delay between recognising an unwanted
    action and the thumb down. ``silent_ok``, ``patience``, ``take_back`` and
    ``take_back_delay`` are run parameters, checked once where they enter
    (:func:`pil.task.spec.parse_run_spec`) and taken here as given.
    """

    def __init__(
        self,
        script: Sequence[ScriptStep],
        seed: int = 0,
        *,
        silent_ok: float = 0.0,
        patience: int = 0,
        take_back: float = 0.0,
        take_back_delay: int = 0,
        reaction_time: ReactionTime | None = None,
        body: PersonBody | None = None,
    ) -> None:
        self.script = tuple(script)
        self.body = body
        self.silent_ok = float(silent_ok)
        self.patience = patience
        self.take_back, self.take_back_delay = float(take_back), take_back_delay
        self._take_back_rng = random.Random(f"take_back:{seed}")  # apart: off draws nothing
        self._verdict: Feedback | None = None  # the person's thumb on the last action
        self._watched = 0  # robot actions watched
        self._due: int | None = None  # say "that was wrong" once this many were watched
        self.taken_back_count = 0  # approvals the robot took back when the person said so
        self.reaction_time = reaction_time or ReactionTime()
        self._rng = random.Random(seed)
        self._reaction_rng = random.Random(f"reaction:{seed}")  # apart: the study draws none
        self._todo: deque[ScriptStep] = deque(self.script)
        self._legs = LegsSeen()
        self.interventions = 0  # legs the person put back on the table themselves
        self._asked = False  # the robot asked for a thumb on the action now shown

    @classmethod
    def for_types(
        cls, scenario: Scenario, types: Sequence[HandoverType], seed: int = 0, **options: float
    ) -> ScriptedPerson:
        """A person performing ``types`` with the scenario's legs per table and spots."""
        script = plan_script(types, scenario.legs_per_table, scenario.spots)
        return cls(script, seed, **options)  # type: ignore[arg-type]

    # --- what to do next -----------------------------------------------------------------------
    def next_step(self, hand: Hand) -> ScriptStep | None:
        """The next instruction given the robot's ``hand`` as the person sees it (None: done).

        A leg the robot held but no longer holds is first picked up again; a leg the robot
        caught although its close was rejected counts as grasped (see module doc)."""
        if not self._todo:
            return None
        head = self._todo[0]
        if self._legs.holding is not None and hand is Hand.FREE:
            leg = self._legs.lost()
            assert leg is not None  # held a moment ago
            if self.body is not None and self.body.recover(leg):
                self.interventions += 1
            where = head.intent
            point = Intent(
                Gesture.POINTING, Action.OBJECT, Target("leg", leg), where.handover, where.table
            )
            grasp = Intent(Gesture.GRASP, Action.CLOSE, None, where.handover, where.table)
            for intent in (grasp, point):
                recovery = ScriptStep(intent, head.handover_type, head.step, False, recovery=True)
                self._todo.appendleft(recovery)
            head = self._todo[0]
        elif (
            self._legs.holding is None
            and hand is Hand.OCCUPIED
            and head.intent.action is Action.CLOSE
        ):
            self.completed(head, Action.CLOSE)  # the leg is in the hand already
            return self.next_step(hand)
        return head

    def completed(self, item: ScriptStep, action: Action) -> None:
        """``item``'s instruction got an approved ``action``: on to the next one."""
        if self._todo and self._todo[0] is item:
            self._todo.popleft()
        self._legs.approved(action, item.intent.target)

    # --- one action ----------------------------------------------------------------------------
    def start_table(self, table: int) -> None:
        """A new table begins: the body (if any) rests its hand."""
        if self.body is not None:
            self.body.start_table(table)

    def perform(self, intent: Intent) -> None:
        """Perform ``intent``'s gesture (visibly, with a body). Pointing at a leg that lies off
        the table top (e.g. on the floor), the person first puts it back at its place (an
        intervention: the robot reaches for a leg on the table, so pointing at it there asked
        for an action that could not succeed, again and again)."""
        if self.body is None:
            return
        target = intent.target
        if intent.gesture is Gesture.POINTING and target is not None and target.kind == "leg":
            self.interventions += self.body.put_back_off_table(target.index)
        self.body.perform(intent.gesture, intent.target)

    def watch(self, intent: Intent) -> Watcher:
        """How the person watches the robot's next action (instantly, without a body)."""
        self._watched += 1
        if self.body is None:
            return InstantWatcher(intent)
        return self.body.watch(intent, self.reaction_time.draw(self._reaction_rng))

    def judge(self, intent: Intent, action: Action, outcome: Outcome) -> Feedback:
        """OK (or silence) for the wanted action when it worked, else not-OK (a stopped action
        got its thumb down already)."""
        asked, self._asked = self._asked, False
        self._verdict = Feedback.NOT_OK
        if outcome.interrupted or action is not intent.action or not outcome.succeeded:
            return Feedback.NOT_OK
        self._verdict = Feedback.OK
        # the draw is made when asked too, so asking changes no later draw
        if self.silent_ok and self._rng.random() < self.silent_ok and not asked:
            return Feedback.NONE
        return Feedback.OK

    def confirm_requested(self) -> None:
        """The robot asks for an explicit thumb on the action it is about to show: the person
        answers it with a thumb, never with silence (:meth:`judge`)."""
        self._asked = True

    def show_feedback(self, feedback: Feedback) -> None:
        """Give the thumb ``feedback`` (visibly, with a body), before the learner receives it."""
        if self.body is not None:
            self.body.show_feedback(feedback)

    def after_feedback(self, feedback: Feedback) -> None:
        """Once the robot has seen the thumb: what follows it (with a body)."""
        if self.body is not None:
            self.body.after_feedback(feedback)

    def loses_patience(self, rejections: int) -> bool:
        """True when ``rejections`` in a row make the person perform the gesture again."""
        return self.patience > 0 and rejections >= self.patience

    def performs_again(self, reason: str) -> bool:
        """Always: the scripted person repeats the instruction's gesture at once."""
        return True

    def lets_robot_go_first(self) -> bool:
        """Always: the scripted person performs a gesture only when the robot did not act."""
        return True

    def takes_back(self, stood: bool) -> bool:
        """True when the person says "that was wrong" now (see the module doc): a wrong move
        the robot let stand (``stood`` against their thumb down) is taken back with probability
        ``take_back``, once ``take_back_delay`` more robot actions were watched."""
        wrong = stood and self._verdict is Feedback.NOT_OK
        if wrong and self.take_back and self._take_back_rng.random() < self.take_back:
            self._due = self._watched + self.take_back_delay
        if self._due is None or self._watched < self._due:
            return False
        self._due = None
        return True

    def taken_back(self, what: str) -> None:
        """The robot took an approval back: counted (the script is unchanged)."""
        self.taken_back_count += bool(what)
