"""An epsilon-greedy contextual bandit over PIL's states (a baseline).

Each state (detected gesture, last approved action, hand) is an independent bandit with five
arms (with the within-step memory on, the arms refused in the current step are left out, see
:class:`FeedbackAgent`). The value of an arm is the mean reward it got (+1 OK, -1 not-OK); an
arm never pulled is worth ``prior`` (default :data:`PRIOR` = 0.5, run parameter
``bandit_prior``), above a refused arm and below an approved one, so every arm is tried
before a refused one is tried again and an approved one is kept. With
probability epsilon the agent draws an arm at random, otherwise it takes the best (ties at
random). ``epsilon_decay`` tau > 0 makes the rate decay in each state: after t feedbacks in
the state, epsilon_t = epsilon / (1 + t / tau) (0: a constant epsilon). It knows nothing of
valid states, corrections or transitions.

:data:`EPSILON`, :data:`EPSILON_DECAY` and their ranges are the one source of the defaults
and valid values (the run parameters of :mod:`pil.task.params` read them).
"""

from __future__ import annotations

from pil.agents.base import FeedbackAgent
from pil.table import N_STATES, AssociationTable
from pil.types import ACTIONS

_N = len(ACTIONS)
PRIOR = 0.5  # the default value of an arm never pulled (the optimistic start)
PRIOR_RANGE = (-2.0, 2.0)  # from below every reward to above every reward
EPSILON = 0.1  # the default exploration rate
EPSILON_RANGE = (0.0, 1.0)
EPSILON_DECAY = 0.0  # the default tau: no decay
EPSILON_DECAY_RANGE = (0.0, 1e6)  # in feedbacks per state


class BanditAgent(FeedbackAgent):
    """Epsilon-greedy with an optimistic prior (see the module docstring)."""

    name = "bandit"

    def __init__(
        self,
        seed: int = 0,
        *,
        epsilon: float = EPSILON,
        epsilon_decay: float = EPSILON_DECAY,
        prior: float = PRIOR,
        table: AssociationTable | None = None,
        step_memory: bool = FeedbackAgent.STEP_MEMORY_OWN,
    ) -> None:
        super().__init__(seed, table=table, step_memory=step_memory)
        self.epsilon = float(epsilon)  # checked once where they enter (the registry)
        self.epsilon_decay = float(epsilon_decay)
        self.prior = float(prior)
        self.values = [[self.prior] * _N for _ in range(N_STATES)]
        self.pulls = [[0] * _N for _ in range(N_STATES)]

    def epsilon_in(self, sid: int) -> float:
        """The exploration rate in state id ``sid`` now (decayed by its feedbacks so far)."""
        if not self.epsilon_decay:
            return self.epsilon
        return self.epsilon / (1.0 + sum(self.pulls[sid]) / self.epsilon_decay)

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        if self.epsilon and self._rng.random() < self.epsilon_in(sid):
            return self._rng.choice(allowed), False, "explore (epsilon)"
        row = self.values[sid]
        top = max(row[i] for i in allowed)
        tops = [i for i in allowed if row[i] == top]
        exploited = top > self.prior
        return self._rng.choice(tops), exploited, "greedy" if exploited else "untried arm"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        self.pulls[sid][index] += 1
        n = self.pulls[sid][index]
        value = self.values[sid][index] if n > 1 else 0.0  # the prior is dropped
        self.values[sid][index] = value + (reward - value) / n
