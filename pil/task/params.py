"""The parameters: the one place that knows each option's type, range and default.

Every parameter is a :class:`~pil.task.param_spec.ParamSpec`, which turns a value given as text
(a command line, a sweep's ``--param``, a CSV cell) or already typed (a YAML scenario, a Python
call) into the typed value, or raises :class:`ParamError` naming the parameter, the valid range
or choices, and what it got. The run parameters (:data:`PARAMS`), the scenario file's assembly
keys, the sweep grid and the CLI options all validate through these specs::

    PARAMS["discard"].parse("0.3")        # 0.3
    PARAMS["discard"].parse("1.5")        # ParamError: parameter 'discard' must be a number
                                          #   in [0, 1], got '1.5'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

from pil.agents import DEFAULT_LEARNER, PIL_LEARNERS
from pil.agents.bandit import (
    EPSILON,
    EPSILON_DECAY,
    EPSILON_DECAY_RANGE,
    EPSILON_RANGE,
    PRIOR,
    PRIOR_RANGE,
)
from pil.agents.tamer import STEP_SIZE, STEP_SIZE_RANGE
from pil.anticipation import DEFAULT_MIN_COUNT, DEFAULT_THRESHOLD
from pil.errors import NEVER_DETECTED, InvalidChoiceError
from pil.exploration import DEFAULT_RULE, RULES
from pil.learner import ADAPTATIONS
from pil.step_memory import DEFAULT_STEP_MEMORY, STEP_MEMORY
from pil.task.detector import DEFAULT_DISCARD, EXACT, MODELS
from pil.task.param_spec import MAX_TEXT, ParamError, ParamSpec, spec_for
from pil.task.watching import DEFAULT_REACTION_MEAN, DEFAULT_REACTION_SPREAD

__all__ = [  # the spec type is re-exported: callers import parameters from here only
    "ASSEMBLY",
    "ASSEMBLY_DEFAULTS",
    "DRAWS",
    "MAX_COUNT",
    "MAX_LEGS",
    "MAX_SEED",
    "MAX_TABLES",
    "MAX_TEXT",
    "PARAMS",
    "RATE",
    "REPS",
    "RUN_OPTIONS",
    "SCENARIO",
    "SEED",
    "STEP_RATE",
    "ParamError",
    "ParamSpec",
    "parse_all",
    "spec_for",
]

MAX_TABLES = 1000  # tables of one run: 4000 handovers, a few seconds learner-only
MAX_LEGS = 12  # legs of one table (and table spots)
MAX_COUNT = 1000  # patience, actions per gesture
MAX_SEED = 2**63 - 1
DRAWS: tuple[str, ...] = ("balanced", "cycle", "random")


def _specs(*specs: ParamSpec) -> dict[str, ParamSpec]:
    return {spec.name: spec for spec in specs}


# The assembly's own settings: None (the default) keeps the scenario file's value; the
# scenario file's keys are checked by the same specs, with ASSEMBLY_DEFAULTS for missing keys.
ASSEMBLY: dict[str, ParamSpec] = _specs(
    ParamSpec("tables", "int", None, "test tables", 1, MAX_TABLES, optional=True),
    ParamSpec("legs_per_table", "int", None, "legs of each table", 1, MAX_LEGS, optional=True),
    ParamSpec(
        "training_tables", "int", None, "pre-training tables (c1-c4)", 0, MAX_TABLES, optional=True
    ),
    ParamSpec("draw", "choice", None, "order of the handover types", choices=DRAWS, optional=True),
    ParamSpec("spots", "int", None, "table spots for 'location'", 1, MAX_LEGS, optional=True),
)
ASSEMBLY_DEFAULTS: dict[str, Any] = {
    "tables": 10,
    "legs_per_table": 4,
    "training_tables": 5,
    "draw": "balanced",
    "spots": 4,
}
PARAMS: dict[str, ParamSpec] = {
    **ASSEMBLY,
    **_specs(
        ParamSpec("detector", "detector", EXACT, "detection model", choices=MODELS),
        ParamSpec("discard", "float", DEFAULT_DISCARD, "share of misses discarded", 0.0, 1.0),
        ParamSpec(
            "confusion",
            "matrix",
            None,
            "how a miss of each gesture is misread",
            optional=True,
            empty="uniform",
        ),
        ParamSpec("repeat_discarded", "bool", True, "ask for a repeat of a discarded gesture"),
        ParamSpec("silent_ok", "float", 0.0, "chance of approving by saying nothing", 0.0, 1.0),
        ParamSpec("patience", "int", 0, "rejections before a repeat (0: off)", 0, MAX_COUNT),
        ParamSpec(
            "take_back",
            "float",
            0.0,
            "chance of taking back a wrong move the robot let stand",
            0.0,
            1.0,
        ),
        ParamSpec(
            "take_back_delay",
            "int",
            0,
            "robot actions watched before taking it back (0: before the next gesture)",
            0,
            MAX_COUNT,
        ),
        ParamSpec("max_actions_per_gesture", "int", 100, "actions before giving up", 1, MAX_COUNT),
        ParamSpec(
            "reaction_time",
            "float",
            DEFAULT_REACTION_MEAN,
            "s, the person's mean reaction to an unwanted action",
            0.0,
            10.0,
        ),
        ParamSpec(
            "reaction_spread",
            "float",
            DEFAULT_REACTION_SPREAD,
            "s, standard deviation of the reaction time",
            0.0,
            5.0,
        ),
        ParamSpec(
            "handover_timeout",
            "float",
            180.0,
            "s from a handover's first gesture (physical episodes)",
            1.0,
            1e6,
        ),
        ParamSpec(
            "learner",
            "choice",
            DEFAULT_LEARNER,
            "the PIL rule: the paper's or the robust one (docs/learner.md)",
            choices=tuple(PIL_LEARNERS),
        ),
        ParamSpec(
            "exploration",
            "choice",
            DEFAULT_RULE,
            "the learner's rule after a not-OK (learner=pil)",
            choices=tuple(RULES),
        ),
        ParamSpec(
            "adaptation",
            "choice",
            "none",
            "how a not-OK changes counts (learner=pil)",
            choices=tuple(ADAPTATIONS),
        ),
        ParamSpec("proactive", "bool", False, "act on the likely next state before its gesture"),
        ParamSpec(
            "proactive_threshold",
            "float",
            DEFAULT_THRESHOLD,
            "P(next state | state) needed to act unasked",
            0.0,
            1.0,
            low_open=True,
        ),
        ParamSpec(
            "proactive_min_count",
            "int",
            DEFAULT_MIN_COUNT,
            "transitions seen before that share counts",
            1,
            MAX_COUNT,
        ),
        ParamSpec(
            "epsilon", "float", EPSILON, "the bandit baseline's exploration rate", *EPSILON_RANGE
        ),
        ParamSpec(
            "epsilon_decay",
            "float",
            EPSILON_DECAY,
            "bandit: epsilon / (1 + t / tau) after t feedbacks in a state (0: constant)",
            *EPSILON_DECAY_RANGE,
        ),
        ParamSpec(
            "bandit_prior",
            "float",
            PRIOR,
            "bandit: the value of an arm never pulled (its optimistic start)",
            *PRIOR_RANGE,
        ),
        ParamSpec(
            "step_size",
            "float",
            STEP_SIZE,
            "the TAMER baseline's regression step",
            *STEP_SIZE_RANGE,
        ),
        ParamSpec(
            "step_memory",
            "choice",
            DEFAULT_STEP_MEMORY,
            "never repeat an action refused in this step (every learner; pil.step_memory)",
            choices=tuple(STEP_MEMORY),
        ),
    ),
}
SCENARIO = ParamSpec(
    "scenario",
    "text",
    None,
    "an assembly YAML or a shipped scenario's name",
    optional=True,
    empty="scenarios/assembly.yaml",
)
RUN_OPTIONS: dict[str, ParamSpec] = {"scenario": SCENARIO}  # a run's option besides PARAMS
# The smallest detection rate. A gesture repeated until it is read right (conditions 3 and 4,
# manual repetition) is read within the loop's MAX_PERFORMANCES (1000) performances but with
# probability (1 - 0.05) ** 1000 = 5e-23 (at 0.001 the runs failed: 0.999 ** 1000 = 0.37).
MIN_RATE = 0.05
RATE = ParamSpec(
    "rate",
    "float",
    1.0,
    "gesture detection rate",
    0.0,
    1.0,
    low_open=True,
    why_low=NEVER_DETECTED,
    smallest=MIN_RATE,
)
# a step-level environment (pil.env) may miss every gesture: rate 0 is valid there
STEP_RATE = replace(RATE, low_open=False, why_low="", doc="gesture detection rate (0: all missed)")
SEED = ParamSpec("seed", "int", 0, "seed of every random choice", 0, MAX_SEED)
REPS = ParamSpec("reps", "int", 20, "repetitions", 1, 100_000)  # the paper's 20


def parse_all(
    specs: Mapping[str, ParamSpec], values: Mapping[str, Any], what: str = "parameter"
) -> dict[str, Any]:
    """Every spec's value: ``values`` parsed, defaults for the others; unknown names raise."""
    for name in values:
        if name not in specs:
            raise InvalidChoiceError(what, name, specs)
    return {
        name: spec.parse(values[name]) if name in values else spec.default
        for name, spec in specs.items()
    }
