"""The PIL agent: Algorithm 1 (lines 3-18) with the feedback learning and gesture correction.

One *step* is one instruction: the robot acts on a state until the person approves an action
(OK or no feedback). :meth:`Learner.choose` exploits the unique best action of eq. 4 and
otherwise explores by the learner's exploration rule (:mod:`pil.exploration`: ``next-best``
by default, ``avoid-last``, ``with-replacement`` or ``untried-first``).

:meth:`Learner.decide` runs Algorithm 1 for one detected gesture: explore on an empty table,
choose on a valid state, otherwise correct the gesture (section III-B) or ask for a repeat.
"""

from __future__ import annotations

import os
import random
from dataclasses import dataclass, replace
from pathlib import Path

from pil.anticipation import DEFAULT_MIN_COUNT, DEFAULT_THRESHOLD, Anticipation
from pil.anticipation import anticipate as _anticipate
from pil.errors import RobinPilError
from pil.exploration import DEFAULT_RULE, RULES
from pil.step_memory import StepMemory
from pil.table import (
    ACTION_INDEX,
    START,
    STATE_ID_BY_OBJECT,
    AssociationTable,
    action_index,
    approves,
    state_id,
)
from pil.table_io import load_table, save_table
from pil.types import ACTIONS, Action, Feedback, Gesture, Hand, State
from pil.validity import (
    ALL_STATES,
    GROUNDED_ACTION,
    REACHABLE_CONTEXTS,
    broken_rules,
    is_valid,
)

# "none": eq. 2 (counts only grow); "halve": ours, a not-OK halves the refused action's count
ADAPTATIONS: dict[str, str] = {
    "none": "eq. 2: a not-OK leaves the counts unchanged",
    "halve": "a not-OK halves the refused action's count (rounded down), so old habits fade",
}
_ID_OF_PARTS: dict[tuple[Gesture, Action, Hand], int] = {
    (s.gesture, s.previous_action, s.hand): i for i, s in enumerate(ALL_STATES)
}
# Whether each state (by id) is valid; the valid states grouped by (previous action, hand): the
# candidates of a correction (and of pil.robust's reading of a gesture).
VALID_BY_ID: tuple[bool, ...] = tuple(is_valid(s) for s in ALL_STATES)
SAME_CONTEXT: dict[tuple[Action, Hand], frozenset[int]] = {
    (a, h): frozenset(
        i
        for i, s in enumerate(ALL_STATES)
        if VALID_BY_ID[i] and (s.previous_action, s.hand) == (a, h)
    )
    for a in ACTIONS
    for h in Hand
}


@dataclass(frozen=True, slots=True)
class Decision:
    """What the learner decided for one detected gesture.

    ``state`` is the state acted on (the corrected one after a correction), ``action`` None
    means no action: the person has to repeat the gesture. ``confirm``: the robot is unsure
    and asks the person for an explicit thumb on this action (silence is no answer); the
    paper's learner never asks (:mod:`pil.robust` does).
    """

    state: State | None
    detected_state: State | None
    action: Action | None
    corrected: bool
    exploited: bool
    reason: str
    confirm: bool = False


def _id_of_parts(gesture: Gesture | str, previous_action: Action | str, hand: Hand | str) -> int:
    """The state id for the three parts (enum members or the paper's names)."""
    found = _ID_OF_PARTS.get((gesture, previous_action, hand))  # type: ignore[arg-type]
    if found is None:  # other spellings ("Give_Me") or bad names (which raise here)
        return state_id(State(gesture, previous_action, hand))  # type: ignore[arg-type]
    return found


class Learner:
    """Learns on the fly which action each state asks for (Proactive Incremental Learning).

    ``seed`` seeds the learner's own ``random.Random`` (exploration and tie breaks), so the same
    seed and the same calls give the same decisions. ``exploration`` names the rule of
    :data:`pil.exploration.RULES` that picks the next action after a not-OK. ``table`` is
    updated in place (pass ``table.copy()`` to keep a pre-trained table unchanged);
    ``correction`` False makes an invalid or discarded gesture always ask the person to repeat
    it. ``adaptation`` (:data:`ADAPTATIONS`): "none" is eq. 2; "halve", our option, lets a
    not-OK halve the refused action's count so a changed mapping is taken up sooner.
    ``proactive`` (ours, the follow-up work): :meth:`anticipate` offers the likely next state's
    action after an approval (:mod:`pil.anticipation`, ``proactive_threshold`` and
    ``proactive_min_count``); off, it offers nothing. ``step_memory`` (:mod:`pil.step_memory`,
    off by default: :data:`STEP_MEMORY_OWN`) keeps every exploration draw off the actions
    refused in this step, as the baselines do.
    """

    STEP_MEMORY_OWN = False  # PIL's own within-step memory setting (the paper's learner)

    def __init__(
        self,
        seed: int = 0,
        *,
        table: AssociationTable | None = None,
        correction: bool = True,
        exploration: str = DEFAULT_RULE,
        adaptation: str = "none",
        proactive: bool = False,
        proactive_threshold: float = DEFAULT_THRESHOLD,
        proactive_min_count: int = DEFAULT_MIN_COUNT,
        step_memory: bool = STEP_MEMORY_OWN,
    ) -> None:
        self.seed = seed
        if table is not None and not isinstance(table, AssociationTable):
            raise RobinPilError(
                f"table must be an AssociationTable (or None for an empty one), got "
                f"{type(table).__name__} {table!r}; load a saved one with pil.load_table(path)"
            )
        self.table = AssociationTable() if table is None else table
        self.correction = correction
        # run parameters, checked once where they enter (pil.task.spec.parse_run_spec)
        self.exploration = exploration
        self._rule = RULES[exploration]
        self.adaptation = adaptation
        self._halve = adaptation == "halve"
        self.proactive = bool(proactive)
        self.proactive_threshold = float(proactive_threshold)
        self.proactive_min_count = proactive_min_count
        self._rng = random.Random(seed)
        self._memory = StepMemory(step_memory)  # actions tried (refused) in this step
        self._last_rejected: dict[int, int] = {}  # state id -> action just rejected, this step
        self._last_ok = START  # id of the last approved state; START at the task start
        self._last_approved = -1  # index of the action approved there (-1: none yet)
        self._ok_before = START  # the last approved state before that one
        self.taken_back = 0  # approvals taken back because the world contradicted them
        self.last_exploited = False
        self.last_reason = ""

    # -- state of the learner -------------------------------------------------------------
    @property
    def last_ok_state(self) -> State | None:
        """The last state whose action got OK (None at the start of the task)."""
        return None if self._last_ok == START else ALL_STATES[self._last_ok]

    def tried_in_step(self, state: State) -> frozenset[Action]:
        """The actions tried in ``state`` since the last OK."""
        mask = self._memory.refused(state_id(state))
        return frozenset(a for i, a in enumerate(ACTIONS) if mask >> i & 1)

    def restart(self) -> None:
        """The robot is back at its start pose: forget the step and the previous OK state."""
        self._memory.clear()
        self._last_rejected.clear()
        self._last_ok, self._last_approved, self._ok_before = START, -1, START

    @property
    def step_memory(self) -> bool:
        """Whether the within-step memory is on (:mod:`pil.step_memory`)."""
        return self._memory.on

    # -- section III-A ----------------------------------------------------------------------
    def choose(self, state: State) -> Action:
        """The next action to try in ``state`` within the current step (by the exploration rule)."""
        sid = STATE_ID_BY_OBJECT.get(id(state))
        return self._choose(state_id(state) if sid is None else sid)

    def _choose(self, sid: int) -> Action:
        tried, allowed = self._memory.masks(sid)  # all five rejected: the step starts over
        last = self._last_rejected.get(sid, -1)
        index, self.last_exploited, self.last_reason = self._rule(
            self.table, sid, tried, last, self._rng, allowed
        )
        return ACTIONS[index]

    def feedback(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """Apply the person's feedback on ``action`` in ``state`` (eq. 1 and 2).

        Not-OK: the action counts as tried in this step and as rejected in ``state``. OK or no
        feedback: the step ends, the transition from the previous OK state is counted and
        ``state`` becomes the previous OK state.
        """
        sid = STATE_ID_BY_OBJECT.get(id(state))
        if sid is None:
            sid = state_id(state)
        index = ACTION_INDEX.get(action)  # "object" hits too
        if index is None:
            index = action_index(action)
        if ok is True or (ok is not False and approves(ok)):
            self.table.approve_id(sid, index)
            self.table.follow_id(self._last_ok, sid)
            self._memory.clear()
            self._last_rejected.clear()
            self._ok_before, self._last_ok, self._last_approved = self._last_ok, sid, index
        else:
            self.table.reject_id(sid, index)
            if self._halve:  # ours, outside eq. 2: a refusal halves the refused count
                row = self.table.row(sid)
                if row is not None and row[index]:
                    self.table.forget_id(sid, index, row[index] - row[index] // 2)
            self._memory.refuse(sid, index)
            self._last_rejected[sid] = index

    def regrounded(self, previous: Action, expected: Hand, hand: Hand) -> None:
        """The loop re-grounded the robot's state in its hand (:mod:`pil.task.grounding`).

        When the last approved action itself left a context no right approval reaches (an
        empty hand approved at the person, a full one at a leg), that approval was wrong: its
        count is taken back and the action is recorded as refused there. A hand that physics
        changed after a right approval (a drop) takes nothing back. With right thumbs it never
        happens, so the paper's learner is unchanged there.
        """
        if self._last_approved < 0 or (previous, expected) in REACHABLE_CONTEXTS:
            return
        if ACTIONS[self._last_approved] is previous:  # that approval left this context
            self._withdraw()

    def take_back(self) -> tuple[State, Action] | None:
        """The person says the last approved action was wrong ("that was wrong"): its count
        is taken back, it counts as refused in its state, and the approved state before it is
        the last OK one again. The state and action taken back (None: nothing to take back,
        e.g. twice in a row or before any approval)."""
        if self._last_approved < 0:
            return None
        taken = ALL_STATES[self._last_ok], ACTIONS[self._last_approved]
        self._withdraw()
        self._last_ok = self._ok_before
        return taken

    def _withdraw(self) -> None:
        """Take back the last approval (count and refusal; eq. 2 only ever adds)."""
        self.table.forget_id(self._last_ok, self._last_approved)
        self.table.reject_id(self._last_ok, self._last_approved)
        self._last_approved = -1
        self.taken_back += 1

    # -- the proactive robot (ours) -----------------------------------------------------------
    def anticipate(self, previous_action: Action, hand: Hand) -> Anticipation | None:
        """The action to perform before the next gesture (None: wait for it; always None
        unless ``proactive``); the robot's previous action and hand are ``previous_action`` and
        ``hand``."""
        if not self.proactive:
            return None
        candidates = SAME_CONTEXT.get((previous_action, hand), frozenset())
        return _anticipate(
            self.table,
            self._last_ok,
            candidates,
            self.proactive_threshold,
            self.proactive_min_count,
        )

    # -- section III-B ----------------------------------------------------------------------
    def correct(self, state: State, previous_state: State | None) -> State | None:
        """The most frequent valid state that followed ``previous_state`` with OK and shares
        ``state``'s previous action and hand (ties at random), or None if there is none.

        ``previous_state`` None means the start of the task.
        """
        state = ALL_STATES[state_id(state)]
        source = START if previous_state is None else state_id(previous_state)
        return self._correct(state.previous_action, state.hand, source)

    def _correct(self, previous_action: Action, hand: Hand, source: int) -> State | None:
        followers = self.table.followers(source)
        candidates = SAME_CONTEXT.get((previous_action, hand), frozenset())
        top = 0
        tops: list[int] = []
        for sid in sorted(followers):  # a fixed order, whatever order the counts came in
            if sid in candidates:
                count = followers[sid]
                if count > top:
                    top, tops = count, [sid]
                elif count == top:
                    tops.append(sid)
        if not tops:
            return None
        return ALL_STATES[tops[0] if len(tops) == 1 else self._rng.choice(tops)]

    # -- Algorithm 1, lines 3-18 ------------------------------------------------------------
    def decide(
        self, detected: Gesture | str | None, previous_action: Action | str, hand: Hand | str
    ) -> Decision:
        """Decide what to do for one detected gesture (None: the detector discarded it)."""
        if detected is None:
            detected_state = None
        else:
            sid = _id_of_parts(detected, previous_action, hand)
            detected_state = ALL_STATES[sid]
            if self.table.is_empty():  # T is empty: explore without a validity check
                action = self._choose(sid)
                reason = f"explore (nothing learnt yet); {self.last_reason}"
                return Decision(detected_state, detected_state, action, False, False, reason)
            if VALID_BY_ID[sid]:
                action = self._choose(sid)
                return Decision(
                    detected_state,
                    detected_state,
                    action,
                    False,
                    self.last_exploited,
                    self.last_reason,
                )
        if previous_action.__class__ is not Action:
            previous_action = Action.parse(previous_action)
        if hand.__class__ is not Hand:
            hand = Hand.parse(hand)
        return self._repair(detected_state, previous_action, hand)

    def _repair(
        self, detected_state: State | None, previous_action: Action, hand: Hand
    ) -> Decision:
        """An invalid or discarded gesture: correct it (section III-B) or ask for a repeat."""
        if detected_state is None:
            why, was = "discarded", "none"
        else:
            why = f"invalid: {broken_rules(detected_state)[0].name}"
            was = detected_state.gesture.value
        if self.table.is_empty():
            return Decision(None, detected_state, None, False, False, f"{why}; nothing learnt yet")
        if not self.correction:
            reason = f"{why}; no correction (manual repetition)"
            return Decision(None, detected_state, None, False, False, reason)
        if not SAME_CONTEXT[(previous_action, hand)]:
            # no right approval reaches this context: one was wrong (pil.task.grounding)
            note = f"<{previous_action.value}, {hand.value}> unreachable, re-grounded"
            previous_action = GROUNDED_ACTION[hand]
            if detected_state is not None:
                grounded = self.decide(detected_state.gesture, previous_action, hand)
                return replace(grounded, reason=f"{note}; {grounded.reason}")
        corrected = self._correct(previous_action, hand, self._last_ok)
        if corrected is None:
            reason = f"{why}; nothing to correct from (repeat)"
            return Decision(None, detected_state, None, False, False, reason)
        action = self.choose(corrected)
        return Decision(
            corrected,
            detected_state,
            action,
            True,
            self.last_exploited,
            f"corrected {was}->{corrected.gesture.value}; {self.last_reason}",
        )

    # -- files ------------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str]) -> Path:
        """Save the table (counts, rejections, transitions) with :func:`pil.save_table`."""
        return save_table(self.table, path)

    @classmethod
    def load(
        cls,
        path: str | os.PathLike[str],
        seed: int = 0,
        *,
        correction: bool = True,
        exploration: str = DEFAULT_RULE,
    ) -> Learner:
        """A learner at the task start whose table is read from ``path``."""
        return cls(seed, table=load_table(path), correction=correction, exploration=exploration)
