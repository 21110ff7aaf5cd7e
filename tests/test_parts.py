"""assemble(parse_run_spec(...)): one run's learner, person and detector from a seed, shared with
episodes."""

from __future__ import annotations

from dataclasses import replace

import pytest
from learner_rows import learner_row

from pil.errors import InvalidChoiceError
from pil.task.assemble import assemble
from pil.task.parts import DEFAULT_VALUES, SEED_NAMES, derive_seeds, phase_script
from pil.task.runner import run, steps
from pil.task.scenario import load_scenario
from pil.task.spec import parse_run_spec
from pil.task.world import Outcome, SymbolicWorld, Target, Watcher
from pil.types import Action


class MeasuringWorld(SymbolicWorld):
    """Like a physical world whose actions all succeed: same effects, its own details."""

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        result = super().execute(action, target, watcher)
        return replace(result, detail=f"moved for {target}")


def test_parts_reproduce_learner_row() -> None:
    parts = assemble(parse_run_spec(rate=0.6, seed=4, params={"tables": 2}))
    stats = run(parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options)
    row = learner_row("pil", 0.6, 4, tables=2)
    assert (stats.gestures, stats.actions, stats.legs) == (row["gestures"], row["actions"], 8)


def test_same_seed_same_decisions_in_another_world() -> None:
    spec = parse_run_spec(rate=0.6, seed=8, params={"tables": 1})
    first, second = assemble(spec), assemble(spec)
    symbolic = list(
        steps(first.learner, first.person, first.detector, SymbolicWorld(), **first.options)
    )
    measured = list(
        steps(second.learner, second.person, second.detector, MeasuringWorld(), **second.options)
    )
    assert [r._replace(detail="") for r in measured] == [r._replace(detail="") for r in symbolic]
    assert any(r.detail.startswith("moved for Target") for r in measured)


def test_seeds_and_scripts() -> None:
    seeds = derive_seeds(3)
    assert set(seeds) == set(SEED_NAMES) and len(set(seeds.values())) == len(SEED_NAMES)
    scenario = load_scenario()
    cache: dict = {}
    script = phase_script(scenario, "train", seeds, cache)
    assert len(script) == 110 and phase_script(scenario, "train", seeds, cache) is script
    assert len(phase_script(scenario, "test", seeds)) == 220
    with pytest.raises(InvalidChoiceError, match="'train', 'test'"):
        phase_script(scenario, "warmup", seeds)
    with pytest.raises(InvalidChoiceError, match="unknown parameter 'discrad'"):
        parse_run_spec(rate=0.5, seed=1, params={"discrad": 0.2})
    assert DEFAULT_VALUES["discard"] == 0.5 and DEFAULT_VALUES["repeat_discarded"] is True


def test_parameter_values_from_text_are_converted() -> None:
    from pil.errors import RobinPilError

    def checked(params: dict) -> dict:
        return parse_run_spec(params=params).values()

    values = checked(
        {"discard": "0.3", "repeat_discarded": "false", "patience": "2", "legs_per_table": 3.0}
    )
    assert values["discard"] == 0.3 and values["repeat_discarded"] is False
    assert values["patience"] == 2 and values["legs_per_table"] == 3
    with pytest.raises(
        RobinPilError, match=r"'patience' must be a whole number from 0 to 1000, got '2.5'"
    ):
        checked({"patience": "2.5"})
    with pytest.raises(
        RobinPilError, match="'repeat_discarded' must be true or false, got 'maybe'"
    ):
        checked({"repeat_discarded": "maybe"})
    with pytest.raises(
        RobinPilError,
        match=r"'tables' must be a whole number from 1 to 1000 "
        r"\(or empty: the scenario's\), got True",
    ):
        checked({"tables": True})
