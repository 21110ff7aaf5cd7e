"""``pil-robust``: PIL for the teachers it will meet (silent, late, inconsistent thumbs).

:class:`RobustLearner` is :class:`pil.learner.Learner` (Algorithm 1: act on the best action,
correct an invalid or discarded gesture from the learnt transitions, section III-B; its state
grounded in the hand by the loop; approvals taken back) with another way to weigh the
feedback and to choose, designed from the literature on learning from human feedback
(docs/learner.md, "The robust rule"):

* **Weighed feedback** (:mod:`pil.robust.beliefs`, :mod:`pil.robust.teacher`): each signal
  heard after an action is evidence, weighed by what it means for this teacher: the thumbs by
  the teacher's estimated consistency (Policy Shaping), silence by what it turned out to mean
  (Strategy-Aware Bayesian Learning: EM over P(silence | right) and P(silence | wrong)). The
  robot acts on the action most probably wanted; one OK in a state makes its action the
  most probable there (PIL's one-shot learning).
* **Shared evidence**: a state's prior is what its gesture meant with the same hand in other
  contexts (what makes TAMER's linear features fast, as a back-off).
* **Misread gestures** (:mod:`pil.robust.readings`): what the person wants is a mixture over
  the context's states, weighed by the learnt transitions (the correction's P(s' | s_{t-1}))
  and a misread rate (``misread``); after a refusal, what the context's other gestures mean
  comes before a random action. A corrected gesture is acted on only when more probably
  right than not (``correct_above``); otherwise the robot asks for the gesture again.
* **Take-back and decay**: an approval the world contradicts (:meth:`Learner.regrounded`) or
  the person takes back (:meth:`Learner.take_back`) counts against the action; a trusted
  association that is refused loses ``decay`` of its evidence, and no evidence grows beyond
  ``cap``, so a mistaken or outdated association fades.
* **Asking** (:mod:`pil.robust.asking`): when silence says nothing for this teacher and the
  robot is unsure of its action (P below ``ask_below``), the decision carries ``confirm``:
  the robot asks for an explicit thumb (:func:`pil.task.watched_action.ask`), as long as
  asking does get answers.
"""

from __future__ import annotations

from dataclasses import replace

from pil.anticipation import DEFAULT_MIN_COUNT, DEFAULT_THRESHOLD
from pil.learner import Decision, Learner
from pil.robust.asking import Answers
from pil.robust.beliefs import Beliefs
from pil.robust.readings import Readings
from pil.table import N_STATES, START, AssociationTable, action_index, state_id
from pil.types import ACTIONS, Action, Feedback, Gesture, Hand, State

SHARE = 0.9  # prior: the chance that a state means what its gesture-and-hand group does
MISREAD = 0.1  # the chance that a valid reading is another gesture of the context
CORRECT_ABOVE = 0.5  # act on a corrected gesture only when more probably right than not
DECAY = 0.7  # a refused trusted association keeps this share of its evidence
CAP = 6.0  # no action's evidence in a state beyond this (odds of e^6, about 400 to 1)
ASK_BELOW = 0.7  # ask for a thumb when P(the action is wanted) is below this ...
MIN_SILENCES = 3.0  # ... once at least this many silences were heard and said too little
EXPLOIT_AT = 0.5  # an action more probably wanted than not is an exploit (the log's word)


def heard_of(ok: bool | Feedback | str) -> Feedback:
    """The signal the robot heard: True is OK, False not-OK, a Feedback (or its name) itself."""
    if ok is True:
        return Feedback.OK
    if ok is False:
        return Feedback.NOT_OK
    return ok if isinstance(ok, Feedback) else Feedback.parse(ok)


class RobustLearner(Learner):
    """PIL with weighed feedback, shared evidence, take-back, decay and asking (module doc).

    The knobs and their defaults: ``share`` (:data:`SHARE`), ``misread`` (:data:`MISREAD`),
    ``correct_above`` (:data:`CORRECT_ABOVE`),
    ``decay`` (:data:`DECAY`), ``cap`` (:data:`CAP`), ``ask`` (on) and ``ask_below``
    (:data:`ASK_BELOW`). ``seed`` seeds the tie breaks: same seed and calls, same decisions.
    ``table``, ``correction``, ``proactive*`` and ``step_memory`` are :class:`Learner`'s; a
    given table (a pre-trained or loaded one) is also taken as evidence: each approval as an
    OK, each recorded refusal as one not-OK (the table keeps no silences).
    """

    STEP_MEMORY_OWN = True  # never repeat an action refused in this step (until all five were)

    def __init__(
        self,
        seed: int = 0,
        *,
        table: AssociationTable | None = None,
        correction: bool = True,
        share: float = SHARE,
        misread: float = MISREAD,
        correct_above: float = CORRECT_ABOVE,
        decay: float = DECAY,
        cap: float = CAP,
        ask: bool = True,
        ask_below: float = ASK_BELOW,
        proactive: bool = False,
        proactive_threshold: float = DEFAULT_THRESHOLD,
        proactive_min_count: int = DEFAULT_MIN_COUNT,
        step_memory: bool = STEP_MEMORY_OWN,
    ) -> None:
        super().__init__(
            seed,
            table=table,
            correction=correction,
            proactive=proactive,
            proactive_threshold=proactive_threshold,
            proactive_min_count=proactive_min_count,
            step_memory=step_memory,
        )
        self.beliefs = Beliefs(share, cap)
        self.readings = Readings(misread)
        self.answers = Answers()
        self.correct_above, self.decay = float(correct_above), float(decay)
        self.ask, self.ask_below = bool(ask), float(ask_below)
        self.last_confirm = False  # the last chosen action asks for a thumb
        self.last_p = 0.0  # P(the last chosen action is the one wanted)
        self.asked = 0  # actions on which the robot asked for a thumb
        self._repairing = False  # choosing for a corrected state: the reading says nothing
        self._corrected = -1  # the corrected state acted on in this step (-1: none)
        self._absorb(self.table)

    def _absorb(self, table: AssociationTable) -> None:
        """Take a given table's approvals and refusals as evidence (class docstring)."""
        if table.is_empty() and not table.rejected_states():
            return
        for sid in range(N_STATES):
            row, refused = table.row(sid), table.rejected_mask(sid)
            for index in range(len(ACTIONS)):
                if row is not None and row[index]:
                    self.beliefs.add(sid, index, Feedback.OK, row[index])
                if refused >> index & 1:
                    self.beliefs.add(sid, index, Feedback.NOT_OK)
        self.beliefs.refit()

    # -- choosing -------------------------------------------------------------------------
    def _choose(self, sid: int) -> Action:
        _refused, allowed = self._memory.masks(sid)
        read = not self._repairing and sid != self._corrected
        weights = self.readings.weigh(sid, self.table.followers(self._last_ok), read)
        wanted = self.beliefs.mixed(weights)
        candidates = [i for i in range(len(ACTIONS)) if allowed >> i & 1]
        top = max(wanted[i] for i in candidates)
        tops = [i for i in candidates if wanted[i] >= top * (1.0 - 1e-9)]
        index = tops[0] if len(tops) == 1 else self._rng.choice(tops)
        p = self.last_p = wanted[index]
        self.last_exploited = p >= EXPLOIT_AT
        self.last_confirm = (
            self.ask
            and p < self.ask_below
            and self.beliefs.teacher.silence_is_ambiguous(MIN_SILENCES)
            and self.answers.helps()
        )
        how = "most probably wanted" if len(tops) == 1 else "a tie, drawn"
        ask = "; asks for a thumb" if self.last_confirm else ""
        self.last_reason = f"{how} (P={p:.2f}){ask}"
        return ACTIONS[index]

    def decide(
        self, detected: Gesture | str | None, previous_action: Action | str, hand: Hand | str
    ) -> Decision:
        """Algorithm 1 for one reading (:meth:`Learner.decide`); ``confirm`` set when the
        robot asks for an explicit thumb."""
        self._corrected = -1
        decision = super().decide(detected, previous_action, hand)
        if decision.action is None:
            return decision
        if decision.corrected and decision.state is not None:
            self._corrected = state_id(decision.state)
        return replace(decision, confirm=self.last_confirm)

    def _repair(
        self, detected_state: State | None, previous_action: Action, hand: Hand
    ) -> Decision:
        """The paper's correction, acted on only when more probably right than not."""
        self._repairing = True
        try:
            decision = super()._repair(detected_state, previous_action, hand)
        finally:
            self._repairing = False
        if decision.corrected and decision.action is not None and self.last_p < self.correct_above:
            why = f"{decision.reason}; too unsure to act (repeat)"
            return replace(decision, state=None, action=None, corrected=False, reason=why)
        return decision

    # -- feedback ---------------------------------------------------------------------------
    def feedback(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """The signal heard after ``action`` in ``state`` (True / False, or the Feedback as
        read: silence is :data:`Feedback.NONE`): the table as PIL keeps it (silence counts as
        approved there, as the loop takes it) and the weighed evidence."""
        heard = heard_of(ok)
        sid, index = state_id(state), action_index(action)
        self.asked += self.last_confirm
        self.answers.heard(heard, asked=self.last_confirm)
        approved = heard is not Feedback.NOT_OK
        if not approved and self.beliefs.posterior(sid)[index] >= EXPLOIT_AT:
            self.beliefs.scale(sid, index, self.decay)  # a trusted association refused
        self.beliefs.add(sid, index, heard)
        self.beliefs.refit()
        super().feedback(state, action, heard)
        if approved:
            self._corrected = -1

    def _withdraw(self) -> None:
        """The last approval is taken back: the action counts as contradicted in its state
        (then as :meth:`Learner._withdraw`)."""
        if self._last_approved >= 0 and self._last_ok != START:
            self.beliefs.contradict(self._last_ok, self._last_approved)
            self.beliefs.refit()
        super()._withdraw()

    def restart(self) -> None:
        """Back at the start pose (what was learnt stays)."""
        super().restart()
        self._corrected = -1
