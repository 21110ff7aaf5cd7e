"""I-SABL (Loftin et al., AAAI 2014; JAAMAS 2016): silence means what this trainer means by it.

SABL models a trainer who, for an action a in state s, first judges it right (a = lambda(s),
the action the trainer wants) or wrong, mistaking the judgement with probability epsilon, and
then gives a thumb or says nothing. A *strategy* (mu+, mu-) is how likely the trainer stays
silent after an action judged right (mu+) or judged wrong (mu-):

    P(OK | right)     = (1 - eps)(1 - mu+)      P(OK | wrong)     = eps (1 - mu+)
    P(not-OK | right) = eps (1 - mu-)           P(not-OK | wrong) = (1 - eps)(1 - mu-)
    P(silence | right) = (1 - eps) mu+ + eps mu-    P(silence | wrong) = (1 - eps) mu- + eps mu+

A reward-focused trainer (mu+ small, mu- large) says nothing after a wrong action, so silence
is a mild not-OK; a punishment-focused one (mu+ large, mu- small) says nothing after a right
one, so silence is a mild OK; balanced (both small) and inactive (both large) trainers make
silence carry little. I-SABL does not know the strategy: it infers it from the feedback seen.
The strategy is a hidden variable with a uniform prior over a grid of (mu+, mu-) (the centres
of ``levels`` x ``levels`` cells of the unit square), and Expectation-Maximisation finds the
maximum-likelihood policy: the E-step weighs each strategy by the likelihood of every thumb
and silence so far under the current policy, the M-step gives each state the action that
maximises the expected log-likelihood of that state's feedback, until the policy is stable.

This is the discrete case the papers treat (a policy is a table state -> action, so the M-step
is solved state by state); the agent follows the current maximum-likelihood policy, the
next-likeliest action after one refused in the step (the baselines' within-step memory), ties
broken at random. ``epsilon`` is tuned on the dev seeds like the other references' parameters.

The agent needs to tell silence from a thumb up: the step loop hands every learner the thumb
as read (:class:`pil.types.Feedback`, silence as ``NONE``); given a bool (an API caller's
verdict) it counts True as a thumb up.
"""

from __future__ import annotations

import numpy as np

from pil.agents.base import FeedbackAgent
from pil.table import N_STATES, AssociationTable
from pil.types import ACTIONS, Action, Feedback, State

FEEDBACK_KINDS: tuple[Feedback, ...] = (
    Feedback.OK,
    Feedback.NOT_OK,
    Feedback.NONE,
)  # count columns
ERROR_RATE = 0.05  # the default error rate (tuned on dev in the bench)
STRATEGY_LEVELS = 10  # strategy grid: the centres of a 10 x 10 partition of [0, 1]^2
MAX_ROUNDS = 50  # EM rounds at most (it stops as soon as the policy is stable)


def feedback_probabilities(epsilon: float, mu_plus: float, mu_minus: float) -> np.ndarray:
    """P(OK, not-OK, silence | right) and (| wrong) of the SABL trainer: a 2 x 3 array, row
    0 for a right action, row 1 for a wrong one (module docstring)."""
    e = epsilon
    return np.array(
        [
            [(1 - e) * (1 - mu_plus), e * (1 - mu_minus), (1 - e) * mu_plus + e * mu_minus],
            [e * (1 - mu_plus), (1 - e) * (1 - mu_minus), (1 - e) * mu_minus + e * mu_plus],
        ]
    )


class ISablAgent(FeedbackAgent):
    """I-SABL over the detected states (module docstring)."""

    name = "isabl"

    def __init__(
        self,
        seed: int = 0,
        *,
        epsilon: float = ERROR_RATE,
        levels: int = STRATEGY_LEVELS,
        table: AssociationTable | None = None,
    ) -> None:
        super().__init__(seed, table=table)
        self.epsilon = float(epsilon)
        centres = (np.arange(levels) + 0.5) / levels
        self.mu_plus, self.mu_minus = (g.ravel() for g in np.meshgrid(centres, centres))
        probs = np.array(
            [
                feedback_probabilities(self.epsilon, p, m)
                for p, m in zip(self.mu_plus, self.mu_minus, strict=True)
            ]
        )  # (strategies, right/wrong, kind)
        self._log_right, self._log_wrong = np.log(probs[:, 0, :]), np.log(probs[:, 1, :])
        self.counts = np.zeros(
            (N_STATES, len(ACTIONS), len(FEEDBACK_KINDS))
        )  # feedback per (state, action, kind)
        self.weights = np.full(len(centres) ** 2, 1.0 / len(centres) ** 2)  # P(strategy | h)
        self.policy = np.full(N_STATES, -1)  # lambda(s) as an action index (-1: no feedback)
        self.scores = np.zeros((N_STATES, len(ACTIONS)))  # expected log-likelihood of lambda(s) = a
        self.rounds = 0  # EM rounds of the last fit
        self.evidence: list[float] = []  # log P(h | lambda_i) after each E-step of the last fit
        self._kind = Feedback.OK

    # -- the feedback ---------------------------------------------------------------------
    def feedback(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """Count the thumb or the silence, refit, and keep the table and step memory."""
        if ok is True or ok is False:
            self._kind = Feedback.OK if ok else Feedback.NOT_OK
        else:
            self._kind = ok if isinstance(ok, Feedback) else Feedback.parse(ok)
        super().feedback(state, action, ok)

    def _learn(self, sid: int, index: int, reward: float) -> None:
        self.counts[sid, index, FEEDBACK_KINDS.index(self._kind)] += 1
        self.fit()

    # -- EM ---------------------------------------------------------------------------------
    def loglik(self) -> np.ndarray:
        """log P(feedback in s | lambda(s) = a, strategy g) for every (s, a, g)."""
        total = self.counts.sum(axis=1)  # (states, kinds): all feedback in each state
        wrong = total @ self._log_wrong.T  # every action in s taken as wrong
        gain = self.counts @ (self._log_right - self._log_wrong).T  # a taken as the right one
        return gain + wrong[:, None, :]

    def fit(self) -> None:
        """EM from the prior: alternate the strategy posterior and the policy until the
        policy no longer changes (or :data:`MAX_ROUNDS`)."""
        ll = self.loglik()
        seen = self.counts.sum(axis=(1, 2)) > 0
        weights = np.full(len(self.mu_plus), 1.0 / len(self.mu_plus))  # the uniform prior
        policy = np.full(N_STATES, -1)
        self.evidence = []
        for self.rounds in range(1, MAX_ROUNDS + 1):
            scores = ll @ weights  # M-step: expected log-likelihood of lambda(s) = a
            new = np.where(seen, np.argmax(scores, axis=1), -1)
            kept = policy >= 0  # a tie keeps the action the policy had (no needless change)
            same = scores[np.flatnonzero(kept), policy[kept]] >= scores.max(axis=1)[kept]
            new[np.flatnonzero(kept)[same]] = policy[kept][same]
            log_joint = ll[np.flatnonzero(seen), new[seen], :].sum(axis=0)  # E-step
            log_joint -= log_joint.max()
            weights = np.exp(log_joint) / np.exp(log_joint).sum()
            self.evidence.append(self._evidence(ll, seen, new))
            if np.array_equal(new, policy):
                break
            policy = new
        self.policy, self.weights, self.scores = policy, weights, ll @ weights

    def _evidence(self, ll: np.ndarray, seen: np.ndarray, policy: np.ndarray) -> float:
        """log P(h | policy), the strategy marginalised under its uniform prior."""
        joint = ll[np.flatnonzero(seen), policy[seen], :].sum(axis=0)
        top = joint.max() if joint.size else 0.0
        return float(top + np.log(np.exp(joint - top).mean())) if joint.size else 0.0

    def strategy(self) -> tuple[float, float]:
        """The posterior mean of (mu+, mu-): how often this trainer is silent after a right
        and after a wrong action."""
        return float(self.weights @ self.mu_plus), float(self.weights @ self.mu_minus)

    # -- acting -----------------------------------------------------------------------------
    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        row = self.scores[sid]
        top = max(row[i] for i in allowed)
        tops = [i for i in allowed if row[i] == top]
        index = self._rng.choice(tops)
        exploited = index == self.policy[sid]
        return index, exploited, "I-SABL: most likely wanted" if exploited else "I-SABL: explore"
