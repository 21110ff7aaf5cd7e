"""What the live page shows: the phase, whose turn it is, what the robot does, counts, P(a|s).

:class:`LiveStatus` is the step loop's :class:`~pil.task.runner.StepObserver` (it only records
what it is told) and builds :meth:`~robin_sim.live.session.LiveSession.status`'s dict from it
and from the participant's phase.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any

from pil.task.records import StepRecord
from pil.task.world import Target
from pil.types import Hand
from robin_sim.episode.summary import EpisodeTotals
from robin_sim.live.config import LiveConfig
from robin_sim.live.guide import target_name

if TYPE_CHECKING:
    from robin_sim.live.participant import LiveParticipant

DOING = {
    "object": "moving to {target}",
    "location": "moving to {target}",
    "human": "bringing the leg to your hand",
    "close": "closing the hand",
    "open": "opening the hand",
}
EMPTY_HAND_TO_PERSON = "moving its empty hand to yours"  # "human" holding nothing
# the robust rule (pil.robust) asks for an explicit thumb when it is unsure (StepRecord.confirm)
ASKS_FOR_A_THUMB = "; Robin is unsure and asks: is this what you meant? Show a thumb"
TURN = {"waiting_for_gesture": "participant", "waiting_for_thumb": "participant"}


def _target_text(record: StepRecord) -> str:
    target = record.target
    if target is None:
        return (
            "the nearest leg"
            if record.action is not None and record.action.value == "object"
            else "the nearest spot"
        )
    return target_name(target)


def _doing(record: StepRecord) -> str:
    """What the robot does, in the page's words."""
    action = "" if record.action is None else record.action.value
    if action == "human" and record.state is not None and record.state.hand is Hand.FREE:
        return EMPTY_HAND_TO_PERSON
    return DOING.get(action, action).format(target=_target_text(record))


class LiveStatus:
    """The session's status, kept current from the step loop (thread-safe)."""

    def __init__(self, config: LiveConfig) -> None:
        self.config = config
        self.table: Any = None  # the learner's association table, once built
        self._lock = threading.Lock()
        self._doing = ""
        self._action: str | None = None
        self._last: str | None = None  # the action last decided (the one being judged)
        self._policy: dict[str, Any] | None = None
        self._tally = {"gestures": 0, "actions": 0, "rejected": 0, "legs_delivered": 0}
        self.session = ""
        self._clicked: dict[str, Any] | None = None  # the leg or spot clicked last

    # --- the StepObserver protocol -------------------------------------------------------------
    def decided(self, record: StepRecord) -> None:
        """The robot is about to act on ``record``."""
        action = "" if record.action is None else record.action.value
        doing = _doing(record)
        if record.proactive:
            doing += " (anticipating)"
        if record.confirm:
            doing += ASKS_FOR_A_THUMB
        policy = self._policy_of(record)
        with self._lock:
            self._doing, self._action = doing, action or None
            self._last = self._action
            if policy is not None:
                self._policy = policy

    def answered(self, record: StepRecord) -> None:
        """The participant's verdict is in."""
        with self._lock:
            self._doing, self._action = "", None

    def finished(self, record: StepRecord, totals: EpisodeTotals) -> None:
        """A step is logged (the learner has its feedback): the counts and P(a|s) now."""
        counts = totals.counts
        policy = self._policy_of(record)
        with self._lock:
            if policy is not None:
                self._policy = policy
            self._tally = {
                "gestures": counts.gestures,
                "actions": counts.actions,
                "rejected": counts.rejected,
                "legs_delivered": counts.legs,
            }

    def clicked(self, target: Target, x: float, y: float) -> None:
        """The participant clicked ``target`` at frame pixel (x, y) (the page marks it)."""
        with self._lock:
            self._clicked = {
                "kind": target.kind,
                "index": target.index,
                "number": target.index + 1,
                "name": target_name(target),
                "x": round(x, 1),
                "y": round(y, 1),
            }

    def _policy_of(self, record: StepRecord) -> dict[str, Any] | None:
        """P(a|s) of the learner's table for the record's state (None without either)."""
        state = record.state
        if self.table is None or state is None:
            return None
        p = self.table.probabilities(state)
        return {
            "state": f"{state.gesture.value} / {state.previous_action.value} / {state.hand.value}",
            "actions": {a.value: round(float(v), 4) for a, v in p.items()},
        }

    # --- the page's view -----------------------------------------------------------------------
    def status(self, participant: LiveParticipant | None, final: str | None) -> dict[str, Any]:
        """The contract's status dict."""
        with self._lock:
            counts, doing, policy = dict(self._tally), self._doing, self._policy
            action, last, clicked = self._action, self._last, self._clicked
        if final is not None:
            phase, message = "done", f"The session is over ({final})."
        elif participant is None:
            phase, message = "robot_acting", "The scene is being set up."
        else:
            phase, message = participant.phase, participant.message
        if phase != "robot_acting":
            doing, action = "", None
        elif participant is not None and not participant.judging:
            action = None  # its thumb is taken (or it is being taken back): nothing to judge
        if phase == "robot_acting" and not doing:
            doing = "watching you" if participant is not None else "setting up"
        world = None if participant is None else participant.body.world
        return {
            "phase": phase,
            "turn": TURN.get(phase, "robot"),
            "robot_doing": doing,
            "action": action,  # the action the robot runs now (None: none)
            "last_action": last,  # the action last decided: the one a thumb judges
            "message": message,
            **counts,
            "legs_total": None if participant is None else participant.legs_total,
            # the handover now asked for, e.g. {"handover": 0, "handover_type": "A",
            # "handover_steps": ["pointing -> object", ...]} (None before the scene is built)
            "task": None if participant is None else participant.task(),
            # the same in plain words: goal, next instruction, checklist, legs and spots
            "guide": None if participant is None else participant.guide(),
            "clicked": clicked,  # the leg or spot clicked last (None: none yet)
            "sim_time": None if world is None else round(world.time, 3),
            "system": self.config.system,
            "participant": self.config.participant,
            "session": self.session,
            "block": self.config.block,
            "policy": policy,
            "status": final or "running",
        }
