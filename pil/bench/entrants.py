"""Who can be entered in the benchmark: the reference agents by name, any agent by module path.

An entrant is a *factory* called once per run as ``factory(seed)``; it returns either

* an :class:`pil.agents.Agent` (``decide``, ``choose``, ``feedback``, ``correct``, ``save``,
  ``table``...): used as the study uses PIL and the baselines, or
* an *actor* of :class:`pil.env.AssemblyEnv`'s observations, with
  ``select_action(observation) -> int`` and ``observe(action, reward)``: wrapped by
  :class:`ActorAgent`, which shows it each reading as the environment's integer observation
  (``gesture``, ``previous_action``, ``hand``) and passes the verdict as the reward (+1 / -1).

``--agent pkg.module:factory`` imports ``pkg.module`` (the working folder is on the path) or,
for ``path/to/file.py:factory``, loads the file. :func:`reference` builds a reference agent
(names in :data:`REFERENCE`) with its parameters.
"""

from __future__ import annotations

import importlib
import importlib.util
import operator
import os
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from pil.agents import Agent, TamerAgent
from pil.agents.base import FeedbackAgent
from pil.bench.agents import (
    CoachAgent,
    EpsilonGreedyAgent,
    OracleAgent,
    PolicyShapingAgent,
    RandomAgent,
    ThompsonAgent,
)
from pil.bench.isabl import ISablAgent
from pil.errors import RobinPilError, quote
from pil.learner import Learner
from pil.robust import RobustLearner
from pil.types import ACTIONS, GESTURES, Hand

Factory = Callable[[int], Any]


class EntrantError(RobinPilError):
    """An entrant that cannot be loaded or does not meet the agent protocol."""


def _pil(rule: str) -> Callable[[int, Mapping[str, Any]], Any]:
    return lambda seed, params: Learner(seed, exploration=rule)


REFERENCE: dict[str, Callable[[int, Mapping[str, Any]], Any]] = {
    "random": lambda seed, params: RandomAgent(seed),
    "oracle": lambda seed, params: OracleAgent(seed),
    "pil-paper": _pil("avoid-last"),  # Algorithm 1, lines 8-13: argmax if unique, else random
    "pil-next-best": _pil("next-best"),
    "pil-robust": lambda seed, params: RobustLearner(seed, **params),
    "tamer": lambda seed, params: TamerAgent(seed, **params),
    "egreedy": lambda seed, params: EpsilonGreedyAgent(seed, **params),
    "thompson": lambda seed, params: ThompsonAgent(seed, **params),
    "coach": lambda seed, params: CoachAgent(seed, **params),
    "policy-shaping": lambda seed, params: PolicyShapingAgent(seed, **params),
    "isabl": lambda seed, params: ISablAgent(seed, **params),
}


def reference(name: str, params: Mapping[str, Any] | None = None) -> Factory:
    """The factory of reference agent ``name`` with ``params`` (its tuned values)."""
    if name not in REFERENCE:
        raise EntrantError(f"unknown agent {quote(name)}; valid choices: " + ", ".join(REFERENCE))
    make, given = REFERENCE[name], dict(params or {})
    return lambda seed: make(seed, given)


class ActorAgent(FeedbackAgent):
    """An actor of the environment's observations behind the agent protocol (module doc)."""

    name = "actor"

    def __init__(self, actor: Any, seed: int = 0) -> None:
        super().__init__(seed, step_memory=False)
        self.actor = actor

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        from pil.validity import ALL_STATES

        state = ALL_STATES[sid]
        observation = {
            "gesture": np.asarray(GESTURES.index(state.gesture), dtype=np.int64),
            "previous_action": np.asarray(ACTIONS.index(state.previous_action), dtype=np.int64),
            "hand": np.asarray((Hand.FREE, Hand.OCCUPIED).index(state.hand), dtype=np.int64),
        }
        return actor_action(self.actor.select_action(observation)), False, "actor"

    def _learn(self, sid: int, index: int, reward: float) -> None:
        self.actor.observe(index, reward)


def actor_action(value: Any) -> int:
    """``select_action``'s answer as an action index; :class:`EntrantError` saying what it
    returned when it is not a whole number from 0 to 4."""
    try:
        index = None if isinstance(value, bool) else operator.index(value)
    except TypeError:
        index = None
    if index is None or not 0 <= index < len(ACTIONS):
        names = ", ".join(f"{i} {a.value}" for i, a in enumerate(ACTIONS))
        raise EntrantError(
            f"select_action returned {quote(value)}, not an action index (valid: {names})"
        )
    return index


def as_agent(made: Any, seed: int, where: str) -> Agent:
    """``made`` as an agent: itself if it meets the protocol, an actor wrapped, else an error."""
    if isinstance(made, Agent):
        return made
    if callable(getattr(made, "select_action", None)) and callable(getattr(made, "observe", None)):
        return ActorAgent(made, seed)
    raise EntrantError(
        f"{where} returned {type(made).__name__}, which is neither an agent (decide, choose, "
        "feedback, correct, save, table, last_exploited, last_reason: pil.agents.Agent) nor an "
        "actor (select_action, observe); see docs/bench.md"
    )


def load_factory(spec: str) -> Factory:
    """The factory named by ``pkg.module:factory`` or ``path/file.py:factory``."""
    module_name, sep, attribute = str(spec).rpartition(":")
    if not sep or not module_name or not attribute:
        raise EntrantError(f"--agent {quote(spec)}: expected pkg.module:factory or file.py:factory")
    try:
        if module_name.endswith(".py") or os.sep in module_name:
            path = Path(module_name)
            if not path.is_file():
                raise EntrantError(f"--agent {quote(spec)}: no such file {path}")
            loader = importlib.util.spec_from_file_location(f"bench_entrant_{path.stem}", path)
            assert loader is not None and loader.loader is not None
            module = importlib.util.module_from_spec(loader)
            sys.modules[loader.name] = module
            loader.loader.exec_module(module)
        else:
            if os.getcwd() not in sys.path:
                sys.path.insert(0, os.getcwd())
            module = importlib.import_module(module_name)
    except EntrantError:
        raise
    except (Exception, SystemExit) as error:  # an entrant's own import problem, said once
        raise EntrantError(
            f"--agent {quote(spec)}: cannot import {module_name}: {type(error).__name__}: {error}"
        ) from None
    factory = getattr(module, attribute, None)
    if not callable(factory):
        raise EntrantError(f"--agent {quote(spec)}: {module_name} has no callable {attribute!r}")
    return factory
