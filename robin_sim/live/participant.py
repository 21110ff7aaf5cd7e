"""A real participant in the scripted person's place (:class:`pil.task.person.Person`).

:class:`LiveParticipant` is driven by the step loop (:func:`pil.task.runner.steps`) in the
physics thread and by the participant's messages from any thread (:meth:`offer`; the session
checks them first). While it waits for the participant, physics keeps running (paced, frames
streaming): every wait is a loop of control ticks, and the session's tick hook hands the
messages that arrived to :meth:`poll`.

* :meth:`next_step` waits for the next instruction gesture (a click resolved to a leg or spot,
  or give me / grasp / release) and returns it as a :class:`~pil.task.person.ScriptStep`: the
  handover is the next undelivered leg, and as intended action (for the record only: the robot
  never sees it) the correct action of the state the gesture makes under the block's handover
  types, which have exactly one correct action per state.
* :meth:`watch` returns a watcher that stops the robot once a thumb down arrived during its move;
  :meth:`judge` is the participant's thumb (up during or after the move: OK; down: not OK; none
  within ``feedback_window`` s of simulated time, or a next gesture instead: silence, OK).
* The simulated hand (:class:`~robin_sim.person.body.PhysicalBody`) makes every act visible: it
  points at what was clicked, shapes the gesture, shows the thumb, holds out the palm and
  carries delivered legs to the bin.
* "That was wrong" (:mod:`robin_sim.live.take_back`): while the participant's gesture is
  awaited, a take-back asked for ends the wait; the loop asks :meth:`takes_back` at its safe
  point, takes the approval back and tells :meth:`taken_back`, which restores the participant's
  step: the guide asks for the instruction again.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable, Sequence
from typing import Any

from pil.task.records import StepRecord
from pil.task.scenario import HandoverType
from pil.task.script import LegsSeen, ScriptStep
from pil.task.world import Intent, Outcome
from pil.types import Action, Feedback, Gesture, Hand, State
from robin_sim.live.guide import cannot_act, guide, leg_now, legend, meant_action, step_for
from robin_sim.live.limits import WatchdogLimits
from robin_sim.live.robin_seen import RobinSeen
from robin_sim.live.take_back import Stood, TakeBacks
from robin_sim.live.thumbs import Gesturing, ThumbWatcher
from robin_sim.live.watchdog import StepWatchdog, no_way_on, way_on
from robin_sim.person.body import PhysicalBody

PHASES = ("waiting_for_gesture", "robot_acting", "waiting_for_thumb", "instructions", "done")
EventSink = Callable[[str, dict[str, Any]], None]


class LiveParticipant:
    """The person of a live session (see the module doc)."""

    def __init__(
        self,
        body: PhysicalBody,
        types: Sequence[HandoverType],
        legs_per_table: int,
        feedback_window: float,
        robot_anticipates: Callable[[Action, Hand], bool] | None = None,
        limits: WatchdogLimits | None = None,
        on_event: EventSink | None = None,
    ) -> None:
        self.body, self.types = body, tuple(types)
        self.legs_per_table, self.feedback_window = legs_per_table, feedback_window
        self.legs_total = len(self.types)
        self.correct = {step.state: step.action for t in self.types for step in t.steps}
        self._lock = threading.Lock()
        self._inbox: deque[Gesturing | Feedback | str] = deque()
        self.phase = "robot_acting"  # until the loop asks for the first gesture
        self.message = "The robot gets ready."
        self.legs_delivered = 0
        self.thumb: Feedback | None = None  # the thumb given since the current action began
        self.ended = False
        self.judging = False  # an action is watched or awaits its thumb: a thumb is taken
        self.verdict_pending = False  # judged, not yet received by the learner (session clears)
        self.interventions = 0
        self.actions_started = 0  # robot actions begun in the session (a block's cap)
        self._gesture: Gesturing | None = None
        self.robin = RobinSeen()  # Robin's state as the loop takes it (robin_sim.live.robin_seen)
        self._legs = LegsSeen()
        self._delivered_legs: set[int] = set()  # of the table now laid out
        self._laid: set[int] = set()  # the tables laid out
        self._handover, self._step = -1, 0  # the handover and its approved instructions
        # A proactive robot acts before the next gesture after an approved action, when its
        # learnt transitions make one next state likely (pil.anticipation): then the loop gets
        # the participant's next instruction at once, without waiting for a gesture.
        self.robot_anticipates = robot_anticipates
        # The participant's gesture of the step now running: the webcam learns from its verdict.
        self.step_gesture: Gesture | None = None  # None: the robot went first
        self.step_reading: int | None = None
        self.step_key: tuple[int, int] = (0, 0)
        # What the page must say until the participant's next input (a silent approval, a
        # step handed back), and when the feedback window now open ends (sim time).
        self.notice = ""
        self.window_until: float | None = None
        self.watchdog = StepWatchdog(limits or WatchdogLimits(), lambda: body.world.time)
        self._tripped = ""  # why the watchdog stopped the robot in this step ("" not)
        self.on_event = on_event
        self.take_backs = TakeBacks()  # "That was wrong" (robin_sim.live.take_back)
        self._received: tuple[int, bool] = (0, False)  # the last step's t, and if it delivered
        self._held: int | None = None  # the leg Robin held when its current action began
        self.went_first = False  # next_step let the robot act before the gesture

    # --- from the session (any thread, then the physics thread) ---------------------------------
    def offer(self, item: Gesturing | Feedback | str) -> None:
        """A checked gesture, thumb or "end" from the participant (thread-safe)."""
        with self._lock:
            self._inbox.append(item)

    def poll(self) -> None:
        """Take the messages that arrived (physics thread, between ticks)."""
        with self._lock:
            items, self._inbox = list(self._inbox), deque()
        for item in items:
            if isinstance(item, Gesturing):
                self._gesture, self.notice = item, ""
            elif isinstance(item, Feedback):
                if self.judging and self.thumb is None:
                    self.thumb, self.notice = item, ""
            elif item == "take_back":  # waits for the loop's safe point (or came too late)
                self.notice = self.take_backs.ask(self.phase == "waiting_for_gesture")
                if self.notice:
                    self._event("take_back", done=False, why=self.notice)
            else:
                self.ended = True

    @property
    def instruction(self) -> tuple[int, int]:
        """(handover, step): the leg being handed over and its instructions let stand so far."""
        return self.legs_delivered, self._step if self._handover == self.legs_delivered else 0

    def task(self) -> dict[str, object]:
        """The handover now asked for: its index, type and the type's steps (for the page)."""
        handover = min(self.legs_delivered, self.legs_total - 1)
        kind = self.types[handover]
        steps = [f"{s.gesture.value} -> {s.action.value}" for s in kind.steps]
        return {"handover": handover, "handover_type": kind.name, "handover_steps": steps}

    def guide(self) -> dict[str, object]:
        """The page's plain-words guide to the handover now asked for
        (:func:`robin_sim.live.guide.guide`), with the table's legs and spots for its legend."""
        handover = min(self.legs_delivered, self.legs_total - 1)
        done = self._step if self._handover == self.legs_delivered else 0
        leg = leg_now(self._legs, self._delivered_legs, self.legs_per_table)
        shown = guide(self.types[handover], done, leg, handover, self.legs_total)
        spots = len(self.body.world.layout.spots)
        return {**shown, **legend(self.legs_per_table, self._delivered_legs, spots)}

    def acting(self, record: StepRecord) -> None:
        """The robot starts ``record``'s action now: logged (``acts``), the moment a bench
        measures from the participant's input."""
        self.actions_started += 1
        self.take_backs.gone()  # Robin acts again: the thumb judges this one
        self.watchdog.acted()
        action = None if record.action is None else record.action.value
        self._event("acts", t=record.t, action=action, proactive=record.proactive)

    def received(self, record: StepRecord) -> None:
        """The learner has ``record``: a delivered leg is off the table from now on."""
        self.verdict_pending = False
        self._received = (record.t, record.delivered)
        leg = self._legs.holding if self._held is None else self._held
        if record.delivered and leg is not None:
            self._delivered_legs.add(leg)

    def window_left(self) -> float | None:
        """Sim seconds left of the feedback window now open (None: none is open)."""
        until = self.window_until
        return None if until is None else max(0.0, until - self.body.world.time)

    def take_back_left(self) -> float | None:
        """Sim seconds left to take back the action that stood last (None: nothing now)."""
        if self.phase != "waiting_for_gesture":
            return None
        return self.take_backs.left(self.body.world.time)

    @property
    def gesture_pending(self) -> bool:
        """A gesture has arrived that the loop has not taken yet."""
        return self._gesture is not None

    def _tick(self) -> None:
        self.body.world.sim.tick()

    # --- the Person protocol -------------------------------------------------------------------
    def next_step(self, hand: Hand) -> ScriptStep | None:
        """The participant's next instruction (None: all legs delivered, or the session ended)."""
        if self.legs_delivered >= self.legs_total or self.ended:
            return None
        if self._legs.holding is not None and hand is Hand.FREE:  # the robot dropped the leg
            leg = self._legs.lost()
            assert leg is not None
            self.interventions += self.body.recover(leg)
        self.interventions += self.body.put_back_strays(self._delivered_legs)
        self.thumb = None
        handover = self.legs_delivered
        if handover != self._handover:
            self._handover, self._step = handover, 0
        table, leg = divmod(handover, self.legs_per_table)
        if leg == 0 and self._step == 0 and table not in self._laid:
            # a new table is laid out before the participant is asked, not after their
            # gesture (that took a second and more between the input and Robin's motion)
            self._laid.add(table)
            self.start_table(table)
            self.body.world.start_table(table)
        kind = self.types[handover]
        regrounded = self._ground(kind, hand)
        previous = self.robin.previous
        # for the record, the type's next instruction: the robot goes first, or the loop
        # takes an approval back first (a gesture made meanwhile stays pending)
        step = kind.steps[min(self._step, len(kind.steps) - 1)]
        planned = ScriptStep(
            Intent(step.gesture, step.action, None, handover, table), kind.name, self._step, False
        )
        self.went_first = self._robot_goes_first(hand, regrounded)
        if self.went_first:
            self.set_phase("robot_acting", "The robot anticipates your next instruction.")
            self.step_gesture, self.step_reading = None, None
            return planned
        self.set_phase(
            "waiting_for_gesture", "Your turn: click a leg or a spot, or make a gesture."
        )
        while self._gesture is None and not self.take_backs.asked:
            if self.ended:
                return None
            self._tick()
        if self.take_backs.asked:
            return planned
        gesturing, self._gesture = self._gesture, None
        assert gesturing is not None  # the wait ended on it
        self.watchdog.gesture()
        self._tripped = ""
        self.step_gesture, self.step_reading = gesturing.gesture, gesturing.reading
        self.step_key = (handover, self._step)
        state = State(gesturing.gesture, previous, hand)
        action = self.correct.get(state) or meant_action(state, gesturing.target)
        intent = Intent(gesturing.gesture, action, gesturing.target, handover, table)
        self.set_phase("robot_acting", "The robot reads your gesture.")
        return ScriptStep(intent, kind.name, self._step, False)  # the table is laid out

    def _robot_goes_first(self, hand: Hand, regrounded: str) -> bool:
        """Whether the robot will act before the next gesture (the loop's own condition: not
        after a re-grounding), unless the watchdog says it has done enough on the last
        gesture."""
        anticipates = self.robot_anticipates
        if anticipates is None or not self.robin.approved or regrounded:
            return False
        if not anticipates(self.robin.previous, hand):
            return False
        tripped = self.watchdog.tripped()
        if tripped:
            self._event("watchdog", reason=tripped, withheld="anticipation")
            self.notice = f"Robin waits for your gesture ({tripped})."
            return False
        return True

    def _ground(self, kind: HandoverType, hand: Hand) -> str:
        """Robin's state grounded in ``hand`` as the loop grounds it at this safe point
        (:class:`RobinSeen`; logged, ``regrounded``) and the guide's step in it, which the
        watchdog checks (:func:`no_way_on`); why the state changed ("" when it did not)."""
        why = self.robin.ground(hand)
        if why:
            self._event("regrounded", reason=why)
        previous = self.robin.previous
        self._step = step_for(kind, self._step, previous, hand)  # never an invalid gesture
        stuck = no_way_on(kind, self._step, previous, hand)  # the grounding rules it out
        if stuck:
            self._event("watchdog", reason=stuck)
        return why

    def completed(self, item: ScriptStep, action: Action) -> None:
        """The participant let ``action`` stand for ``item`` (it may be taken back)."""
        legs = LegsSeen(self._legs.holding, self._legs.pointed)
        before = (self.robin.approve(action), self._step, legs)
        self._step += 1
        self._legs.approved(action, item.intent.target)
        t, delivered = self._received
        self.take_backs.stood(Stood(action, t, self.body.world.time, delivered, before))

    def lets_robot_go_first(self) -> bool:
        """Only when :meth:`next_step` let it (the loop's own condition, unless the watchdog
        held the robot back): a gesture the participant made is always performed."""
        return self.went_first

    def takes_back(self, stood: bool) -> bool:
        """The loop's safe point: True when the participant asked to take back the last
        action that stood ("That was wrong", checked against its window when it came)."""
        return self.take_backs.asked

    def taken_back(self, what: str) -> None:
        """The loop took the approval back (``what``; "" when none stood): the participant's
        step is the one before it, so the guide asks for that instruction again; logged."""
        taken, self.notice = self.take_backs.taken(what)
        if taken is None:
            return
        if what:
            robin, self._step, self._legs = taken.before
            self.robin.restore(robin)
        self._event("take_back", done=bool(what), t=taken.t, action=taken.action.value, loop=what)

    def start_table(self, table: int) -> None:
        """A new table's legs are laid out: the hand rests first."""
        self._delivered_legs.clear()
        self.body.start_table(table)

    def perform(self, intent: Intent) -> None:
        """The simulated hand makes the participant's gesture (pointing at what was clicked)."""
        self.body.perform(intent.gesture, intent.target)

    def watch(self, intent: Intent) -> ThumbWatcher:
        """Watch the robot's next action: a thumb down from now on stops it."""
        self.watchdog.attempt()
        self.window_until = None
        self.thumb, self.judging = None, True
        self.robin.acts(self.body.world.hand())
        self._held = self.body.world.held_leg()  # the leg an open now delivers, by physics
        self.set_phase("robot_acting", "The robot acts: thumb down stops it, thumb up approves.")
        return ThumbWatcher(self)

    def judge(self, intent: Intent, action: Action, outcome: Outcome) -> Feedback:
        """The participant's thumb, given during the move or in the feedback window the world
        waited after it (:meth:`ThumbWatcher.result_window`); a thumb down took the action
        back (``outcome.interrupted``); none, or a next gesture instead, is silence (OK)."""
        self.verdict_pending = True
        self.window_until = None
        if outcome.interrupted:
            return Feedback.NOT_OK
        if self.thumb is not None:
            return self.thumb
        # Silence: the participant had the feedback window (or gestured on instead).
        why = "your next gesture came first" if self.gesture_pending else "no thumb in time"
        self.notice = f"No thumb: Robin takes '{action.value}' as OK ({why})."
        self._event("silence", action=action.value, why=why)
        return Feedback.NONE

    def show_feedback(self, feedback: Feedback) -> None:
        """The simulated hand shows the thumb (nothing for silence)."""
        self.judging = False
        self.set_phase("robot_acting", "Thank you: the robot takes in your thumb.")
        self.body.show_feedback(feedback)

    def after_feedback(self, feedback: Feedback) -> None:
        """After an approval, a leg on the palm goes to the bin."""
        self.body.after_feedback(feedback)

    def loses_patience(self, rejections: int) -> bool:
        """When the watchdog trips (:mod:`robin_sim.live.watchdog`): the robot stops trying
        and the step goes back to the participant; else never (they gesture again when they
        want to)."""
        self._tripped = self.watchdog.tripped()
        return bool(self._tripped)

    def performs_again(self, reason: str) -> bool:
        """Never at once: the robot could not act on the gesture (or the watchdog stopped
        it), so the step goes back to the participant with a plain message, and is logged."""
        gesture = self.step_gesture or Gesture.POINTING
        tripped, self._tripped = self._tripped, ""
        stuck = "" if tripped else self.watchdog.hand_back()
        why = tripped or reason
        self.notice = f"{cannot_act(gesture, why)} {way_on(stuck)}"
        kind = "watchdog" if tripped or stuck else "handed_back"
        self._event(kind, reason=why, gesture=gesture.value, **({"stuck": stuck} if stuck else {}))
        return False

    def _event(self, kind: str, **fields: Any) -> None:
        if self.on_event is not None:
            self.on_event(kind, {"sim_time": round(self.body.world.time, 4), **fields})

    # --- what the session shows ----------------------------------------------------------------
    def set_phase(self, phase: str, message: str) -> None:
        self.phase, self.message = phase, message
