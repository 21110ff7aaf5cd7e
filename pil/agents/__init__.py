"""Agents that learn gesture -> action associations, behind one protocol.

:class:`Agent` is what the step loop (:func:`pil.task.runner.steps`), the study and the
environment use. :class:`pil.learner.Learner` (PIL) implements it; :mod:`pil.agents.bandit` and
:mod:`pil.agents.tamer` are baselines over the same states. :data:`AGENTS` maps a name to a
factory ``(seed, table, params) -> Agent``; add an entry to make a new agent selectable.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from pil.agents.bandit import EPSILON, EPSILON_DECAY, PRIOR, BanditAgent
from pil.agents.base import Agent, FeedbackAgent
from pil.agents.tamer import STEP_SIZE, TamerAgent
from pil.exploration import DEFAULT_RULE
from pil.learner import Learner
from pil.step_memory import DEFAULT_STEP_MEMORY, step_memory_on
from pil.table import AssociationTable

AgentFactory = Callable[[int, AssociationTable | None, Mapping[str, Any]], Agent]


def _memory(params: Mapping[str, Any], own: bool) -> bool:
    return step_memory_on(str(params.get("step_memory", DEFAULT_STEP_MEMORY)), own)


def _pil(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return Learner(
        seed,
        table=table,
        correction=bool(params.get("correction", True)),
        exploration=str(params.get("exploration", DEFAULT_RULE)),
        step_memory=_memory(params, Learner.STEP_MEMORY_OWN),
    )


def _bandit(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return BanditAgent(
        seed,
        epsilon=params.get("epsilon", EPSILON),
        epsilon_decay=params.get("epsilon_decay", EPSILON_DECAY),
        prior=params.get("bandit_prior", PRIOR),
        table=table,
        step_memory=_memory(params, BanditAgent.STEP_MEMORY_OWN),
    )


def _tamer(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return TamerAgent(
        seed,
        step_size=params.get("step_size", STEP_SIZE),
        table=table,
        step_memory=_memory(params, TamerAgent.STEP_MEMORY_OWN),
    )


AGENTS: dict[str, AgentFactory] = {"pil": _pil, "bandit": _bandit, "tamer": _tamer}

__all__ = ["AGENTS", "Agent", "AgentFactory", "BanditAgent", "FeedbackAgent", "TamerAgent"]
