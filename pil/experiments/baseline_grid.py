"""The settings a baseline table tunes over, the held-out seeds, and the choice of the best.

Each learner (``pil``, ``bandit``, ``tamer``: study systems of
:mod:`pil.task.systems`) has a small grid of :class:`Setting` objects, each with the
within-step memory (:mod:`pil.step_memory`) off and on:

* ``pil``: every exploration rule of :mod:`pil.exploration`;
* ``bandit``: epsilon 0, 0.02, 0.05, 0.1, each with the optimistic start (the value of an arm
  never pulled, ``bandit_prior``) -1.5, -0.9, -0.5, 0, 0.5, 0.9 and 1.5, and a decaying epsilon,
  epsilon_t = 0.1 / (1 + t / 5) after t feedbacks in the state (:data:`DECAY_TAU`);
* ``tamer``: step size 0.02, 0.05, 0.1, 0.25, 0.5 and 1.

The grids reach past their optima where the range allows it: :func:`at_edge` names a chosen
value that is the smallest or largest of its grid (epsilon = 0 and step size 1 are the ends
of the valid ranges, nothing lies beyond them).

The grid is run on *tuning* seeds, the table on *evaluation* seeds. The evaluation seeds are the
repetition seeds of ``robin-pil study --seed S`` (children ``(i,)`` of
``numpy.random.SeedSequence(S)``); the tuning seeds are children of a branch of the same root
(spawn key ``(TUNING_BRANCH, i)``), a key no study repetition has, so the two never share a
stream; :func:`split_seeds` also checks that no seed is in both. :func:`choose_best` picks,
per learner, the setting with the fewest total actions on average over every tuning run (all
rates and repetitions); ties go to fewer gestures, then to the earlier setting of the grid.
A *stuck* run (a step with no approved action within ``max_actions_per_gesture`` actions:
without the memory a greedy baseline can keep choosing refused actions and never try the
wanted one) counts in the mean at the cap, every scripted gesture times
``max_actions_per_gesture`` actions (:func:`score`): the means are over every run, never over
the survivors only.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pil.agents.bandit import EPSILON
from pil.errors import RobinPilError
from pil.exploration import RULES

LEARNERS: tuple[str, ...] = ("pil", "bandit", "tamer")
BASELINES: tuple[str, ...] = ("bandit", "tamer")
MEMORY: tuple[str, ...] = ("off", "on")
EPSILONS: tuple[float, ...] = (0.0, 0.02, 0.05, 0.1)
PRIORS: tuple[float, ...] = (-1.5, -0.9, -0.5, 0.0, 0.5, 0.9, 1.5)  # the optimistic start
DECAY_EPSILON = EPSILON  # the decaying setting starts at the default rate ...
DECAY_TAU = 5.0  # ... and halves after 5 feedbacks in a state
STEP_SIZES: tuple[float, ...] = (0.02, 0.05, 0.1, 0.25, 0.5, 1.0)
TUNING_BRANCH = 2**31  # spawn key of the tuning seeds' branch (no study has this many reps)
CRITERION = "total_actions"  # the mean the best setting minimises (then total_gestures)


@dataclass(frozen=True)
class Setting:
    """One learner's parameters (run parameters of :mod:`pil.task.params`) and its name."""

    learner: str
    name: str
    params: Mapping[str, Any] = field(default_factory=dict)

    def describe(self) -> str:
        """The parameters as ``key=value`` text (``defaults`` when none are set)."""
        return (
            " ".join(
                f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in self.params.items()
            )
            or "defaults"
        )


def _memory_name(memory: str) -> str:
    return "" if memory == "off" else "+memory"


def grid(learner: str) -> tuple[Setting, ...]:
    """The tuning grid of ``learner`` (see the module docstring)."""
    if learner not in LEARNERS:
        from pil.errors import InvalidChoiceError

        raise InvalidChoiceError("learner", learner, LEARNERS)
    out: list[Setting] = []
    for memory in MEMORY:
        tag = _memory_name(memory)
        if learner == "pil":
            out += [
                Setting("pil", f"{rule}{tag}", {"exploration": rule, "step_memory": memory})
                for rule in RULES
            ]
        elif learner == "bandit":
            out += [
                Setting(
                    "bandit",
                    f"eps={e:g},prior={p:g}{tag}",
                    {"epsilon": e, "bandit_prior": p, "step_memory": memory},
                )
                for e in EPSILONS
                for p in PRIORS
            ]
            decay = {"epsilon": DECAY_EPSILON, "epsilon_decay": DECAY_TAU, "step_memory": memory}
            out.append(Setting("bandit", f"eps={DECAY_EPSILON:g}/(1+t/{DECAY_TAU:g}){tag}", decay))
        else:
            out += [
                Setting("tamer", f"step={s:g}{tag}", {"step_size": s, "step_memory": memory})
                for s in STEP_SIZES
            ]
    return tuple(out)


def default_setting(learner: str) -> Setting:
    """The registry's defaults (what ``robin-pil study --systems LEARNER`` runs)."""
    return Setting(learner, "default", {})


# With the memory on, two rules become others: untried-first never repeats a refusal anyway,
# and with-replacement draws, like avoid-last, among the actions not refused in this step.
SAME_WITH_MEMORY: dict[str, str] = {
    "untried-first+memory": "untried-first",
    "with-replacement+memory": "avoid-last+memory",
}


def pil_references() -> tuple[Setting, ...]:
    """PIL under every exploration rule, without and with the within-step memory (less the
    settings of :data:`SAME_WITH_MEMORY`, which make the same decisions as another)."""
    return tuple(s for s in grid("pil") if s.name not in SAME_WITH_MEMORY)


def _seeds(root: np.random.SeedSequence, n: int) -> list[int]:
    """``n`` repetition seeds from ``root``'s children (as :func:`study.rep_seeds` makes them)."""
    return [int(child.generate_state(1, np.uint64)[0] >> 1) for child in root.spawn(n)]


def split_seeds(seed: int, tuning_reps: int, reps: int) -> tuple[list[int], list[int]]:
    """(tuning seeds, evaluation seeds) from the master ``seed``, disjoint (checked)."""
    evaluation = _seeds(np.random.SeedSequence(seed), reps)
    tuning = _seeds(np.random.SeedSequence(seed, spawn_key=(TUNING_BRANCH,)), tuning_reps)
    shared = set(tuning) & set(evaluation)
    if shared:  # never seen: the streams differ by construction
        raise RobinPilError(f"tuning and evaluation seeds overlap: {sorted(shared)}")
    return tuning, evaluation


@dataclass(frozen=True)
class Score:
    """A setting's means over its tuning runs."""

    setting: Setting
    runs: int  # runs that ended
    stuck: int  # runs with a step that never ended (in the action mean at the cap)
    actions: float
    actions_sd: float
    gestures: float


def score(setting: Setting, rows: Sequence[Mapping[str, Any]], caps: Sequence[float] = ()) -> Score:
    """The means of ``setting``'s tuning ``rows`` and its stuck runs, each counted at its cap
    of actions (``caps``: one per run that never ended); gestures: the finished runs'."""
    actions = [float(r[CRITERION]) for r in rows] + [float(c) for c in caps]
    gestures = [float(r["total_gestures"]) for r in rows]
    sd = statistics.stdev(actions) if len(actions) > 1 else 0.0
    mean = statistics.fmean(actions) if actions else math.nan
    return Score(
        setting,
        len(rows),
        len(caps),
        mean,
        sd,
        statistics.fmean(gestures) if gestures else math.nan,
    )


def choose_best(scores: Sequence[Score]) -> Score:
    """The fewest mean total actions over every run (stuck ones at their cap), then the
    fewest gestures, then the earliest."""
    eligible = [i for i, s in enumerate(scores) if s.runs]
    if not eligible:
        raise RobinPilError("no setting of the grid finished any of its tuning runs")
    best = min(eligible, key=lambda i: (scores[i].actions, scores[i].gestures, i))
    return scores[best]


def at_edge(chosen: Setting, settings: Sequence[Setting]) -> list[str]:
    """The numeric parameters of ``chosen`` whose value is the smallest or largest that
    the grid's settings of the same learner give them (``name=value`` texts)."""
    out = []
    for name, value in chosen.params.items():
        if isinstance(value, bool) or not isinstance(value, int | float):
            continue
        values = {
            s.params[name]
            for s in settings
            if s.learner == chosen.learner and isinstance(s.params.get(name), int | float)
        }
        if len(values) > 1 and value in (min(values), max(values)):
            out.append(f"{name}={value:g}")
    return out
