"""Agents that learn gesture -> action associations, behind one protocol.

:class:`Agent` is what the step loop (:func:`pil.task.runner.steps`), the study and the
environment use. :class:`pil.learner.Learner` (PIL) implements it, and so does its robust
rule :class:`pil.robust.RobustLearner`; :mod:`pil.agents.bandit` and :mod:`pil.agents.tamer`
are baselines over the same states. :data:`AGENTS` maps a name to a factory
``(seed, table, settings) -> Agent``; add an entry to make a new agent selectable. The PIL
agent's rule is the run parameter ``learner`` (:data:`PIL_LEARNERS`). The
settings are typed and checked (:class:`AgentSettings`, e.g. a run spec's
``pil.task.spec.LearnerSettings``): a factory reads them as they are, re-defaults nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from pil.agents.bandit import BanditAgent
from pil.agents.base import Agent, FeedbackAgent
from pil.agents.tamer import TamerAgent
from pil.learner import Learner
from pil.robust import RobustLearner
from pil.step_memory import step_memory_on
from pil.table import AssociationTable

# The PIL rules (the run parameter ``learner``): name -> what it is.
PIL_LEARNERS: dict[str, str] = {
    "pil": "the paper's PIL (pil.learner.Learner; `exploration` picks its rule after a not-OK)",
    "robust": "the robust PIL rule (pil.robust.RobustLearner, docs/learner.md)",
}
DEFAULT_LEARNER = "pil"


class AgentSettings(Protocol):
    """What the agents read of a run's learner settings (typed and checked by the edge)."""

    @property
    def learner(self) -> str: ...
    @property
    def exploration(self) -> str: ...
    @property
    def step_memory(self) -> str: ...
    @property
    def epsilon(self) -> float: ...
    @property
    def epsilon_decay(self) -> float: ...
    @property
    def bandit_prior(self) -> float: ...
    @property
    def step_size(self) -> float: ...


AgentFactory = Callable[[int, AssociationTable | None, AgentSettings], Agent]


def _pil(seed: int, table: AssociationTable | None, settings: AgentSettings) -> Agent:
    if settings.learner == "robust":
        return RobustLearner(
            seed,
            table=table,
            step_memory=step_memory_on(settings.step_memory, RobustLearner.STEP_MEMORY_OWN),
        )
    return Learner(
        seed,
        table=table,
        exploration=settings.exploration,
        step_memory=step_memory_on(settings.step_memory, Learner.STEP_MEMORY_OWN),
    )


def _bandit(seed: int, table: AssociationTable | None, settings: AgentSettings) -> Agent:
    return BanditAgent(
        seed,
        epsilon=settings.epsilon,
        epsilon_decay=settings.epsilon_decay,
        prior=settings.bandit_prior,
        table=table,
        step_memory=step_memory_on(settings.step_memory, BanditAgent.STEP_MEMORY_OWN),
    )


def _tamer(seed: int, table: AssociationTable | None, settings: AgentSettings) -> Agent:
    return TamerAgent(
        seed,
        step_size=settings.step_size,
        table=table,
        step_memory=step_memory_on(settings.step_memory, TamerAgent.STEP_MEMORY_OWN),
    )


AGENTS: dict[str, AgentFactory] = {"pil": _pil, "bandit": _bandit, "tamer": _tamer}

__all__ = [
    "AGENTS",
    "DEFAULT_LEARNER",
    "PIL_LEARNERS",
    "Agent",
    "AgentFactory",
    "AgentSettings",
    "BanditAgent",
    "FeedbackAgent",
    "RobustLearner",
    "TamerAgent",
]
