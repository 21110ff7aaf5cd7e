"""What this teacher's feedback means: P(heard | right action) and P(heard | wrong action).

The robot hears one of three things after an action: a thumb up (OK), a thumb down (not-OK)
or nothing (silence, which the paper counts as OK). :class:`TeacherModel` keeps, for each, the
probability of hearing it after a right action and after a wrong one, and turns them into the
weight of one such signal as evidence that the action was right, the log likelihood ratio
``log P(heard | right) / P(heard | wrong)``:

* For the two thumbs this is Policy Shaping's consistency (Griffith et al., NeurIPS 2013): with
  a teacher who labels an action right with probability C when it is right and wrong with C
  when it is wrong, delta = #OK - #not-OK gives P(right) = C^delta / (C^delta + (1-C)^delta),
  i.e. each thumb weighs log(C / (1 - C)). Here C is estimated, and may differ for OK and
  not-OK.
* For silence this is Strategy-Aware Bayesian Learning (Loftin et al., AAAI 2014; JAAMAS
  2016): whether silence after an action means OK (a "punishment-focused" trainer, who only
  speaks up at a mistake), not-OK (a "reward-focused" one) or nothing (a teacher who simply
  looks away) depends on the teacher, so its weight is learnt from the feedback seen.

The probabilities are fitted by expectation maximisation (I-SABL's inference of the trainer's
strategy): the learner's beliefs about which action is right in each state (the E-step,
:mod:`pil.robust.beliefs`) give the expected number of each signal after right and after
wrong actions, and :meth:`TeacherModel.fit` re-estimates the probabilities from them with a
Dirichlet prior (the M-step). The prior expects thumbs to be right (``THUMB_PRIOR``) and
says nothing about silence (the same share after right and wrong actions), so silence weighs
nothing until the feedback shows what it means.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from pil.types import Feedback

# The order of the signals in every triple below.
HEARD: tuple[Feedback, ...] = (Feedback.OK, Feedback.NOT_OK, Feedback.NONE)
HEARD_INDEX: dict[Feedback, int] = {f: i for i, f in enumerate(HEARD)}
# Dirichlet pseudo-counts of (OK, not-OK, silence) after a right and after a wrong action: a
# thumb is right 9 times in 10 (C = 0.9), and silence is as likely after either (weight 0).
PRIOR_RIGHT: tuple[float, float, float] = (9.0, 1.0, 2.0)
PRIOR_WRONG: tuple[float, float, float] = (1.0, 9.0, 2.0)
WEIGHT_LIMIT = 6.0  # no one signal weighs more than e^6 (about 400 to 1) either way


@dataclass(frozen=True, slots=True)
class Likelihoods:
    """P(heard | right) and P(heard | wrong), each a triple in :data:`HEARD` order."""

    right: tuple[float, float, float]
    wrong: tuple[float, float, float]

    def weight(self, heard: Feedback) -> float:
        """log P(heard | right) / P(heard | wrong): the evidence one signal gives."""
        i = HEARD_INDEX[heard]
        ratio = math.log(self.right[i] / self.wrong[i])
        return max(-WEIGHT_LIMIT, min(WEIGHT_LIMIT, ratio))

    @property
    def consistency(self) -> float:
        """Policy Shaping's C: the share of the thumbs that are right (OK after a right
        action, not-OK after a wrong one), averaged over the two."""
        up = self.right[0] / (self.right[0] + self.wrong[0])
        down = self.wrong[1] / (self.right[1] + self.wrong[1])
        return (up + down) / 2

    @property
    def silence_means(self) -> str:
        """What silence says about the action, in words."""
        w = self.weight(Feedback.NONE)
        if w >= SILENCE_SAYS:
            return "OK"
        if w <= -SILENCE_SAYS:
            return "not OK"
        return "nothing"


SILENCE_SAYS = math.log(3.0)  # silence "means" OK / not-OK once 3 times likelier after it


def _normalised(counts: Sequence[float]) -> tuple[float, float, float]:
    total = sum(counts)
    a, b, c = (x / total for x in counts)
    return a, b, c


class TeacherModel:
    """The teacher's feedback probabilities, re-estimated from expected counts (module doc)."""

    def __init__(
        self,
        prior_right: tuple[float, float, float] = PRIOR_RIGHT,
        prior_wrong: tuple[float, float, float] = PRIOR_WRONG,
    ) -> None:
        self.prior_right, self.prior_wrong = prior_right, prior_wrong
        self.likelihoods = Likelihoods(_normalised(prior_right), _normalised(prior_wrong))
        self.silences = 0.0  # silences heard (the evidence behind silence's weight)

    def weights(self) -> tuple[float, float, float]:
        """The weight of each signal, in :data:`HEARD` order."""
        return tuple(self.likelihoods.weight(f) for f in HEARD)  # type: ignore[return-value]

    def fit(self, after_right: Sequence[float], after_wrong: Sequence[float]) -> None:
        """The M-step: expected counts of each signal after right and wrong actions."""
        right = [p + n for p, n in zip(self.prior_right, after_right, strict=True)]
        wrong = [p + n for p, n in zip(self.prior_wrong, after_wrong, strict=True)]
        self.likelihoods = Likelihoods(_normalised(right), _normalised(wrong))
        self.silences = after_right[2] + after_wrong[2]

    def silence_is_ambiguous(self, min_silences: float) -> bool:
        """True once at least ``min_silences`` silences were heard and they still say too
        little either way (:data:`SILENCE_SAYS`): an answer the robot should ask for."""
        if self.silences < min_silences:
            return False
        return abs(self.likelihoods.weight(Feedback.NONE)) < SILENCE_SAYS
