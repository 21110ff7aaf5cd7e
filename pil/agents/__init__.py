"""Agents that learn gesture -> action associations, behind one protocol.

:class:`Agent` is what the step loop (:func:`pil.task.runner.steps`), the study and the
environment use. :class:`pil.learner.Learner` (PIL) implements it; :mod:`pil.agents.bandit` and
:mod:`pil.agents.tamer` are baselines over the same states. :data:`AGENTS` maps a name to a
factory ``(seed, table, params) -> Agent``; add an entry to make a new agent selectable.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from pil.agents.bandit import BanditAgent
from pil.agents.base import Agent, FeedbackAgent
from pil.agents.tamer import TamerAgent
from pil.learner import Learner
from pil.table import AssociationTable

AgentFactory = Callable[[int, AssociationTable | None, Mapping[str, Any]], Agent]


def _pil(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return Learner(seed, table=table, correction=bool(params.get("correction", True)),
                   exploration=str(params.get("exploration", "next-best")))  # fmt: skip


def _bandit(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return BanditAgent(seed, epsilon=float(params.get("epsilon", 0.1)), table=table)


def _tamer(seed: int, table: AssociationTable | None, params: Mapping[str, Any]) -> Agent:
    return TamerAgent(seed, step_size=float(params.get("step_size", 0.5)), table=table)


AGENTS: dict[str, AgentFactory] = {"pil": _pil, "bandit": _bandit, "tamer": _tamer}

__all__ = ["AGENTS", "Agent", "AgentFactory", "BanditAgent", "FeedbackAgent", "TamerAgent"]
