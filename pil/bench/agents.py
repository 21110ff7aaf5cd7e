"""The benchmark's reference agents that :mod:`pil.agents` does not have.

All act on the detected state as it is (no correction), ask for a repeat of a discarded
gesture and keep the within-step memory of :class:`pil.agents.base.FeedbackAgent` (an action
refused in this step is not tried again until all five were). Feedback h is +1 (OK or
silence) or -1 (not-OK).

* :class:`RandomAgent`: uniformly at random among the allowed actions (the floor).
* :class:`OracleAgent`: knows the mapping in force (state -> wanted action, told by the bench
  at each table), not the gesture really made: it acts on the reading, then on the other
  actions of the mapping in the same context, then on the rest.
* :class:`EpsilonGreedyAgent`: :class:`pil.agents.bandit.BanditAgent` with the value of an
  untried arm (``prior``) as a parameter.
* :class:`ThompsonAgent`: Beta-Bernoulli Thompson sampling per state and action, prior
  Beta(``prior``, ``prior``).
* :class:`CoachAgent`: COACH (MacGlashan et al., 2017): a softmax policy over preferences
  theta(s, .); the feedback is the advantage, theta += ``learning_rate`` * h * grad log pi(a|s).
* :class:`PolicyShapingAgent`: Policy Shaping (Griffith et al., 2013): with
  delta(s, a) = #OK - #not-OK and assumed consistency C, the probability that a is the
  wanted action is C^delta / (C^delta + (1 - C)^delta); the agent samples by it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from pil.agents.bandit import BanditAgent
from pil.agents.base import FeedbackAgent
from pil.table import N_STATES, AssociationTable, state_id
from pil.types import ACTIONS, Action, State
from pil.validity import ALL_STATES

_ACTION_COUNT = len(ACTIONS)


class RandomAgent(FeedbackAgent):
    """Uniformly at random among the actions allowed in the step."""

    name = "random"

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        return self._rng.choice(allowed), False, "random"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        return None


class OracleAgent(FeedbackAgent):
    """Knows the mapping in force (module docstring); :meth:`set_mapping` at each table."""

    name = "oracle"

    def __init__(self, seed: int = 0, *, table: AssociationTable | None = None) -> None:
        super().__init__(seed, table=table)
        self._wanted: dict[int, int] = {}

    def set_mapping(self, mapping: Mapping[State, Action]) -> None:
        """The person's mapping from now on (state -> wanted action)."""
        self._wanted = {state_id(s): ACTIONS.index(a) for s, a in mapping.items()}

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        here = ALL_STATES[sid]
        order = [self._wanted[sid]] if sid in self._wanted else []
        order += [
            a
            for s, a in self._wanted.items()
            if (ALL_STATES[s].previous_action, ALL_STATES[s].hand)
            == (here.previous_action, here.hand)
        ]
        order += list(range(_ACTION_COUNT))
        index = next(i for i in order if i in allowed)
        return index, sid in self._wanted and index == self._wanted[sid], "the mapping"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        return None


class EpsilonGreedyAgent(BanditAgent):
    """Epsilon-greedy whose untried arms are worth ``prior`` (tuned, not fixed at 0.5)."""

    name = "egreedy"

    def __init__(self, seed: int = 0, *, epsilon: float = 0.1, prior: float = 0.5) -> None:
        super().__init__(seed, epsilon=epsilon)
        self.values = [[float(prior)] * _ACTION_COUNT for _ in range(N_STATES)]


class ThompsonAgent(FeedbackAgent):
    """Beta-Bernoulli Thompson sampling (module docstring)."""

    name = "thompson"

    def __init__(self, seed: int = 0, *, prior: float = 1.0) -> None:
        super().__init__(seed)
        self.prior = float(prior)
        self.wins = [[0] * _ACTION_COUNT for _ in range(N_STATES)]
        self.losses = [[0] * _ACTION_COUNT for _ in range(N_STATES)]

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        a0 = self.prior
        draws = {
            i: self._rng.betavariate(a0 + self.wins[sid][i], a0 + self.losses[sid][i])
            for i in allowed
        }
        best = max(draws, key=lambda i: (draws[i], -i))
        return best, self.wins[sid][best] > 0, "thompson draw"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        (self.wins if reward > 0 else self.losses)[sid][index] += 1


class CoachAgent(FeedbackAgent):
    """COACH: the feedback as the advantage of a softmax policy (module docstring)."""

    name = "coach"

    def __init__(self, seed: int = 0, *, learning_rate: float = 1.0) -> None:
        super().__init__(seed)
        self.learning_rate = float(learning_rate)
        self.theta = [[0.0] * _ACTION_COUNT for _ in range(N_STATES)]

    def policy(self, sid: int, allowed: list[int]) -> dict[int, float]:
        """pi(a | s) over the allowed actions."""
        row = self.theta[sid]
        top = max(row[i] for i in allowed)
        weights = {i: math.exp(row[i] - top) for i in allowed}
        total = sum(weights.values())
        return {i: w / total for i, w in weights.items()}

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        pi = self.policy(sid, allowed)
        draw, acc = self._rng.random(), 0.0
        for i, p in pi.items():
            acc += p
            if draw < acc:
                return i, p > 0.5, "softmax draw"
        return allowed[-1], False, "softmax draw"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        pi = self.policy(sid, list(range(_ACTION_COUNT)))
        for i in range(_ACTION_COUNT):  # grad log pi(a|s) = 1[i = a] - pi(i|s)
            self.theta[sid][i] += self.learning_rate * reward * ((i == index) - pi[i])


class PolicyShapingAgent(FeedbackAgent):
    """Policy Shaping with an assumed feedback consistency C (module docstring)."""

    name = "policy-shaping"

    def __init__(self, seed: int = 0, *, consistency: float = 0.8) -> None:
        super().__init__(seed)
        self.consistency = float(consistency)
        self.delta = [[0] * _ACTION_COUNT for _ in range(N_STATES)]

    def optimal(self, sid: int, index: int) -> float:
        """P(action ``index`` is the wanted one in ``sid`` | the feedback so far)."""
        c, d = self.consistency, self.delta[sid][index]
        return c**d / (c**d + (1.0 - c) ** d)

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        weights = [self.optimal(sid, i) for i in allowed]
        index = self._rng.choices(allowed, weights=weights)[0]
        return index, self.delta[sid][index] > 0, "policy shaping draw"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        self.delta[sid][index] += 1 if reward > 0 else -1
