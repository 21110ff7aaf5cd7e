"""The robust learner's beliefs: which action is right in each state, from weighed evidence.

Every state has one right action (as in the paper's task). :class:`Beliefs` keeps, per state
and action, how often each signal was heard after it (OK, not-OK, silence: fractional counts,
since old evidence fades) and how often the world or the person contradicted an approval of
it. The evidence that action a is the right one in state s is the sum of the signals'
weights (:class:`pil.robust.teacher.TeacherModel`: log likelihood ratios); the posterior is

    P(a right in s) ∝ prior_s(a) · exp(evidence(s, a)).

The prior is shared among the states with the same gesture and hand (a back-off, as TAMER's
features share what is learnt among states): with probability ``share`` the state means what
its group's other states mean (a softmax of their summed evidence), otherwise any action
(uniform). A state never seen thus starts from what the gesture meant with this hand in
other contexts, and its own evidence outweighs the prior as it comes.

A mistaken association decays: the evidence of what was heard about an action is bounded
(``cap``: however many thumbs agreed, the robot stays ready to learn otherwise, as a model
with a small chance of a changed meaning would), and :meth:`Beliefs.scale` shrinks it (the
learner halves it when a trusted association is refused). An approval the world or the person
contradicts (:meth:`Beliefs.contradict`) counts against the action with
:data:`AGAINST_WEIGHT`. :meth:`Beliefs.refit` runs one EM iteration of the teacher model over
all the evidence (the E-step is :meth:`Beliefs.posterior`), so a signal heard after an action
the world later contradicted teaches what such signals mean.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from pil.robust.teacher import HEARD, HEARD_INDEX, TeacherModel
from pil.table import N_STATES
from pil.types import ACTIONS, Feedback
from pil.validity import ALL_STATES

N_ACTIONS = len(ACTIONS)
UNIFORM = 1.0 / N_ACTIONS
AGAINST_WEIGHT = -4.0  # a contradicted approval: as strong as a trusted thumb down or more
# The states sharing a gesture and a hand (the prior's groups), by state id.
GROUP: tuple[tuple[int, ...], ...] = tuple(
    tuple(
        j
        for j, other in enumerate(ALL_STATES)
        if j != i and (other.gesture, other.hand) == (state.gesture, state.hand)
    )
    for i, state in enumerate(ALL_STATES)
)


def softmax(values: list[float]) -> list[float]:
    """exp(v) normalised (stable)."""
    top = max(values)
    weights = [math.exp(v - top) for v in values]
    total = sum(weights)
    return [w / total for w in weights]


class Beliefs:
    """Evidence per state and action, the posteriors it gives, the teacher model it fits."""

    def __init__(self, share: float, cap: float, teacher: TeacherModel | None = None) -> None:
        self.share = float(share)
        self.cap = float(cap)
        self.teacher = TeacherModel() if teacher is None else teacher
        self._heard = [[[0.0] * len(HEARD) for _ in ACTIONS] for _ in range(N_STATES)]
        self._against = [[0.0] * N_ACTIONS for _ in range(N_STATES)]
        self._evidence: list[list[float] | None] = [None] * N_STATES  # None: no evidence
        self._weights = self.teacher.weights()

    # -- evidence -----------------------------------------------------------------------
    def add(self, sid: int, index: int, heard: Feedback, amount: float = 1.0) -> None:
        """``heard`` after action ``index`` in state ``sid`` (``amount`` < 1: a share); what
        was heard about the action is scaled back to the cap when it passes it (a saturating
        tally: agreeing signals past the cap are not stored)."""
        cell = self._heard[sid][index]
        cell[HEARD_INDEX[heard]] += amount
        raw = self._raw(cell)
        if abs(raw) > self.cap:
            self._scale_cell(cell, self.cap / abs(raw))
        self._evidence[sid] = self._score(sid)

    def contradict(self, sid: int, index: int, amount: float = 1.0) -> None:
        """The world or the person contradicted an approval of action ``index`` in ``sid``."""
        self._against[sid][index] += amount
        self._evidence[sid] = self._score(sid)

    def scale(self, sid: int, index: int, factor: float) -> None:
        """Scale what was heard about action ``index`` in ``sid`` by ``factor`` (a mistaken
        association decays)."""
        self._scale_cell(self._heard[sid][index], factor)
        if self._evidence[sid] is not None:
            self._evidence[sid] = self._score(sid)

    @staticmethod
    def _scale_cell(cell: list[float], factor: float) -> None:
        for i, n in enumerate(cell):
            cell[i] = n * factor

    def _raw(self, cell: list[float]) -> float:
        """The evidence of what was heard about one action (the weighed sum)."""
        return sum(n * w for n, w in zip(cell, self._weights, strict=True))

    def _score(self, sid: int) -> list[float]:
        cap = self.cap  # what was heard is bounded (the teacher model may re-weigh it)
        return [
            max(-cap, min(cap, self._raw(cell))) + AGAINST_WEIGHT * against
            for cell, against in zip(self._heard[sid], self._against[sid], strict=True)
        ]

    def evidence(self, sid: int) -> tuple[float, ...]:
        """The evidence for each action in ``sid`` (zeros when nothing was heard there)."""
        found = self._evidence[sid]
        return (0.0,) * N_ACTIONS if found is None else tuple(found)

    def has_evidence(self, sid: int) -> bool:
        """True once anything was heard about ``sid``."""
        return self._evidence[sid] is not None

    # -- posteriors (the E-step) --------------------------------------------------------
    def prior(self, sid: int) -> list[float]:
        """prior_s: the group's meaning with probability ``share``, else uniform."""
        others = [e for j in GROUP[sid] if (e := self._evidence[j]) is not None]
        if not others or not self.share:
            return [UNIFORM] * N_ACTIONS
        pooled = softmax([sum(column) for column in zip(*others, strict=True)])
        return [self.share * p + (1.0 - self.share) * UNIFORM for p in pooled]

    def posterior(self, sid: int) -> list[float]:
        """P(each action is the right one in ``sid``)."""
        evidence = self._evidence[sid]
        prior = self.prior(sid)
        if evidence is None:
            return prior
        return softmax([math.log(p) + e for p, e in zip(prior, evidence, strict=True)])

    def mixed(self, weights: Mapping[int, float]) -> list[float]:
        """P(each action is the one wanted) when the person's state is ``sid`` with
        probability ``weights[sid]`` (the weights sum to 1)."""
        out = [0.0] * N_ACTIONS
        for sid, weight in weights.items():
            for i, p in enumerate(self.posterior(sid)):
                out[i] += weight * p
        return out

    # -- the teacher model (the M-step) -------------------------------------------------
    def refit(self) -> None:
        """One EM iteration: expected signals after right and wrong actions under the
        current posteriors, the teacher model re-estimated, the evidence re-weighed."""
        right = [0.0] * len(HEARD)
        wrong = [0.0] * len(HEARD)
        for sid in range(N_STATES):
            if self._evidence[sid] is None:
                continue
            for p, cell in zip(self.posterior(sid), self._heard[sid], strict=True):
                for i, n in enumerate(cell):
                    right[i] += n * p
                    wrong[i] += n * (1.0 - p)
        self.teacher.fit(right, wrong)
        self._weights = self.teacher.weights()
        for sid in range(N_STATES):
            if self._evidence[sid] is not None:
                self._evidence[sid] = self._score(sid)
