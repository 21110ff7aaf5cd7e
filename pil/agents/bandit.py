"""An epsilon-greedy contextual bandit over PIL's states (a baseline).

Each state (detected gesture, last approved action, hand) is an independent bandit with five
arms (the arms refused in the current step are left out, see :class:`FeedbackAgent`). The
value of an arm is the mean reward it got (+1 OK, -1 not-OK); an arm never pulled is worth
``PRIOR`` = 0.5, above a refused arm and below an approved one, so every arm is tried before a
refused one is tried again and an approved one is kept. With probability ``epsilon`` the
agent draws an arm at random, otherwise it takes the best (ties at random). It knows nothing
of valid states, corrections or transitions.
"""

from __future__ import annotations

from pil.agents.base import FeedbackAgent
from pil.errors import check_rate
from pil.table import N_STATES, AssociationTable
from pil.types import ACTIONS

_N = len(ACTIONS)
PRIOR = 0.5  # the value of an arm never pulled


class BanditAgent(FeedbackAgent):
    """Epsilon-greedy with an optimistic prior (see the module docstring)."""

    name = "bandit"

    def __init__(
        self, seed: int = 0, *, epsilon: float = 0.1, table: AssociationTable | None = None
    ) -> None:
        super().__init__(seed, table=table)
        self.epsilon = check_rate(epsilon, "epsilon")
        self.values = [[PRIOR] * _N for _ in range(N_STATES)]
        self.pulls = [[0] * _N for _ in range(N_STATES)]

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        if self.epsilon and self._rng.random() < self.epsilon:
            return self._rng.choice(allowed), False, "explore (epsilon)"
        row = self.values[sid]
        top = max(row[i] for i in allowed)
        tops = [i for i in allowed if row[i] == top]
        exploited = top > PRIOR
        return self._rng.choice(tops), exploited, "greedy" if exploited else "untried arm"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        self.pulls[sid][index] += 1
        n = self.pulls[sid][index]
        value = self.values[sid][index] if n > 1 else 0.0  # the prior is dropped
        self.values[sid][index] = value + (reward - value) / n
