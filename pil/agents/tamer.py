"""A TAMER-style learner: it regresses the person's feedback and acts greedily on it.

TAMER (Knox and Stone) models the human's reinforcement H(s, a) and picks argmax_a H(s, a).
Here one verdict follows each action, so the credit goes to that action alone. H is linear in
features of the state: one-hot detected gesture (4), last approved action (5) and hand (2),
plus a bias, with one weight vector per action, so what is learnt in one state carries over
to states that share a gesture, a previous action or a hand. Each verdict h (+1 OK, -1
not-OK) moves H(s, a) a fraction ``step_size`` of the way to h (normalised least mean
squares); ``step_size`` lies in [0, 1] (above 1, H would overshoot the verdict). Ties are
broken at random; with the within-step memory on, actions refused in the current step are left
out (:class:`pil.agents.base.FeedbackAgent`).

:data:`STEP_SIZE` and :data:`STEP_SIZE_RANGE` are the one source of the default and the valid
values (the run parameter ``step_size`` of :mod:`pil.task.params` reads them).
"""

from __future__ import annotations

from pil.agents.base import FeedbackAgent
from pil.table import AssociationTable
from pil.types import ACTIONS, GESTURES, Hand
from pil.validity import ALL_STATES

_GESTURE = {g: i for i, g in enumerate(GESTURES)}
_ACTION = {a: len(GESTURES) + i for i, a in enumerate(ACTIONS)}
_HAND = {h: len(GESTURES) + len(ACTIONS) + i for i, h in enumerate(Hand)}
_BIAS = len(GESTURES) + len(ACTIONS) + len(Hand)
N_FEATURES = _BIAS + 1
STEP_SIZE = 0.5  # the default: H moves half way to each verdict
STEP_SIZE_RANGE = (0.0, 1.0)  # a fraction of the way to the verdict
# The active features of every state id (each state has exactly 4 ones).
_FEATURES: tuple[tuple[int, ...], ...] = tuple(
    (_GESTURE[s.gesture], _ACTION[s.previous_action], _HAND[s.hand], _BIAS) for s in ALL_STATES
)


class TamerAgent(FeedbackAgent):
    """Greedy on a linear model of the person's feedback (see the module docstring)."""

    name = "tamer"

    def __init__(
        self,
        seed: int = 0,
        *,
        step_size: float = STEP_SIZE,
        table: AssociationTable | None = None,
        step_memory: bool = FeedbackAgent.STEP_MEMORY_OWN,
    ) -> None:
        super().__init__(seed, table=table, step_memory=step_memory)
        self.step_size = float(step_size)  # checked once where it enters (the registry)
        self.weights = [[0.0] * N_FEATURES for _ in ACTIONS]

    def predict(self, sid: int, index: int) -> float:
        """H(s, a) for state id ``sid`` and action index ``index``."""
        w = self.weights[index]
        return sum(w[f] for f in _FEATURES[sid])

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        values = {i: self.predict(sid, i) for i in allowed}
        top = max(values.values())
        tops = [i for i, v in values.items() if v == top]
        exploited = top > 0
        return self._rng.choice(tops), exploited, "greedy on H" if exploited else "explore (H <= 0)"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        features = _FEATURES[sid]
        error = reward - self.predict(sid, index)
        w = self.weights[index]
        for f in features:  # NLMS: H(s, a) moves step_size of the way to the reward
            w[f] += self.step_size * error / len(features)
