"""How the person watches the robot: the reaction time, and the instant watcher of the study.

A person who sees the robot start something they did not mean recognises it once the motion
makes it clear, then needs a reaction time to show thumb down. :class:`ReactionTime` draws that
delay: normal with mean ``mean`` and standard deviation ``spread``, cut at ``floor``. The default
mean of 0.5 s is a choice reaction time: a simple visual reaction takes about 0.2 s, and the
time grows with the number of possible answers (the Hick-Hyman law; Hick 1952, Hyman 1953);
choosing between approving and rejecting one of several robot actions takes 0.4-0.6 s in
the classic choice-reaction studies summarised by Welford (*Reaction Times*, 1980).

:class:`InstantWatcher` is the symbolic study's person: the world shows the action outright and
the person stops an unwanted one at once.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

from pil.task.world import Intent
from pil.types import Action

DEFAULT_REACTION_MEAN = 0.5  # s, choice reaction time (see module doc)
DEFAULT_REACTION_SPREAD = 0.1  # s, standard deviation between reactions
REACTION_FLOOR = 0.15  # s: no one reacts faster than a simple visual reaction allows


@dataclass(frozen=True, slots=True)
class ReactionTime:
    """The delay (s) from recognising an unwanted action to the thumb down. The values are
    taken as given: the edge checked them once (``reaction_time`` and ``reaction_spread`` of
    the registry, :mod:`pil.task.params`)."""

    mean: float = DEFAULT_REACTION_MEAN
    spread: float = DEFAULT_REACTION_SPREAD
    floor: float = REACTION_FLOOR

    def draw(self, rng: random.Random) -> float:
        """One reaction time: normal(mean, spread), at least ``floor`` (and at most 3 sd up)."""
        if self.spread == 0.0:
            return max(self.floor, self.mean)
        value = rng.gauss(self.mean, self.spread)
        return min(max(self.floor, value), self.mean + 3 * self.spread)


class InstantWatcher:
    """The study's person: sees the shown action at once; stops it unless it is meant."""

    def __init__(self, intent: Intent) -> None:
        self.intent = intent

    def stop_now(self, shown: Action | None) -> bool:
        """True as soon as ``shown`` is another action than the meant one."""
        return shown is not None and shown is not self.intent.action

    def result_window(self, shown: Action | None, *, undone: bool = False) -> float:
        """Nothing left to judge: an unwanted action was stopped at once."""
        return 0.0

    def settled(self) -> bool:
        """Never asked: there is no result window."""
        return False
