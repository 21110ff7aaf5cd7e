"""Tests of the sweep grid: ids, seeds, expansion and validation of every input."""

from __future__ import annotations

import pytest

from pil.errors import InvalidChoiceError, RobinPilError
from pil.experiments.sweep_grid import (
    SweepGridError,
    build_grid,
    derive_seed,
    parse_param,
    split_list,
)
from pil.experiments.sweep_kinds import LEARNER_RUNS, load_kind
from pil.task.params import ParamError
from pil.task.parts import DEFAULT_VALUES
from pil.task.systems import SYSTEMS


@pytest.fixture(scope="module")
def learner():
    return load_kind("learner")


def test_learner_kind_lists_its_params_and_systems(learner) -> None:
    assert learner is LEARNER_RUNS
    assert learner.function == "pil.experiments.systems:run_one"  # what sweep.json names
    assert learner.systems == tuple(SYSTEMS)
    assert set(DEFAULT_VALUES) <= set(learner.params)
    assert "scenario" in learner.params  # the run option besides the run parameters
    assert not {"system", "rate", "seed", "rep"} & set(learner.params)


def test_grid_expands_every_combination_sorted_by_unique_id(learner) -> None:
    grid = build_grid(
        learner, systems=["pil", "c1"], rates=[0.4, 1.0], reps=3, params=["discard=0,0.3"]
    )
    runs = grid.runs()
    assert len(runs) == 2 * 2 * 2 * 3
    ids = [run.run_id for run in runs]
    assert ids == sorted(ids) and len(set(ids)) == len(ids)
    assert "pil|rate=0.4|tables=10|discard=0.0|rep=0002" in ids
    assert {run.params for run in runs} == {
        (("tables", 10), ("discard", 0.0)),
        (("tables", 10), ("discard", 0.3)),
    }
    assert grid.swept == ("system", "rate", "discard")


def test_seeds_depend_on_parameters_only(learner) -> None:
    one = build_grid(learner, systems=["pil", "c1"], rates=[0.4, 0.6], reps=4, base_seed=7)
    two = build_grid(learner, systems=["c1", "pil"], rates=[0.6, 0.4], reps=4, base_seed=7)
    seeds_one = {run.run_id: run.seed for run in one.runs()}
    assert seeds_one == {run.run_id: run.seed for run in two.runs()}
    # systems of one cell share the seed (common random numbers); reps and rates differ
    assert (
        seeds_one["pil|rate=0.4|tables=10|rep=0001"] == seeds_one["c1|rate=0.4|tables=10|rep=0001"]
    )
    cells = {seed for run_id, seed in seeds_one.items() if run_id.startswith("pil|")}
    assert len(cells) == 2 * 4
    other = build_grid(learner, systems=["pil"], rates=[0.4], reps=1, base_seed=8).runs()[0]
    assert other.seed != seeds_one["pil|rate=0.4|tables=10|rep=0000"]
    assert derive_seed(7, "rate=0.4|tables=10|rep=0000") == seeds_one[other.run_id]
    assert all(0 <= seed < 2**32 for seed in seeds_one.values())


def test_param_values_take_the_type_of_the_default(learner) -> None:
    assert parse_param("discard=0,0.3", learner) == ("discard", (0.0, 0.3))
    assert parse_param("patience=0,3", learner) == ("patience", (0, 3))
    assert parse_param("repeat_discarded=true,no", learner) == ("repeat_discarded", (True, False))
    assert parse_param("detector=exact,independent", learner)[1] == ("exact", "independent")
    with pytest.raises(
        ParamError, match="--param patience must be a whole number from 0 to 1000, got 'two'"
    ):
        parse_param("patience=two", learner)
    with pytest.raises(
        ParamError, match="--param repeat_discarded must be true or false, got 'maybe'"
    ):
        parse_param("repeat_discarded=maybe", learner)


def test_unknown_parameter_lists_the_valid_ones(learner) -> None:
    with pytest.raises(InvalidChoiceError) as caught:
        parse_param("dicsard=0.3", learner)
    message = str(caught.value)
    assert "'dicsard'" in message
    assert all(f"'{name}'" in message for name in DEFAULT_VALUES)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"systems": ["pil", "c9"]}, "unknown system 'c9'; valid choices: 'pil', 'c1'"),
        ({"rates": [0.4, 1.5]}, r"--rates must be a number in \(0, 1\], got 1.5"),
        ({"rates": [-0.1]}, r"--rates must be a number in \(0, 1\]"),
        ({"rates": [0.0]}, r"--rates must be a number in \(0, 1\], got 0.0 \(at rate 0"),
        ({"rates": []}, "empty grid: no detection rates"),
        ({"systems": []}, "empty grid: no systems"),
        ({"reps": 0}, "--reps must be a whole number from 1 to 100000, got 0"),
        ({"params": ["discard="]}, "empty grid: --param discard has no values"),
        ({"params": ["discard"]}, "write it as NAME=V1,V2"),
        ({"params": ["discard=0.1,0.1"]}, "0.1 given more than once"),
        ({"params": ["discard=0.1", "discard=0.2"]}, "--param discard given more than once"),
        ({"params": ["tables=2,4"]}, "either with --tables or --param tables"),
        ({"params": ["rate=0.5"]}, "not a parameter; use --rates"),
        ({"rates": [0.4, 0.4]}, "given twice"),
        ({"tables": 0}, "--tables must be a whole number from 1 to 1000"),
    ],
)
def test_bad_grids_raise_one_clear_error(learner, changes, message) -> None:
    arguments = {"systems": ["pil"], "rates": [0.5], "reps": 1, **changes}
    with pytest.raises(RobinPilError, match=message):
        build_grid(learner, **arguments)


def test_tables_can_be_swept_as_a_parameter(learner) -> None:
    grid = build_grid(
        learner, systems=["pil"], rates=[1.0], reps=1, params=["tables=1,2"], tables=None
    )
    assert [dict(run.params)["tables"] for run in grid.runs()] == [1, 2]


def test_split_list_rejects_empty_items_and_repeats() -> None:
    assert split_list(" pil, c1 ", "--systems") == ["pil", "c1"]
    assert split_list("", "--systems") == []
    with pytest.raises(SweepGridError, match="empty item"):
        split_list("pil,,c1", "--systems")
    with pytest.raises(SweepGridError, match="pil given more than once"):
        split_list("pil,c1,pil", "--systems")


def test_unknown_kind_and_missing_function_are_clear() -> None:
    with pytest.raises(
        InvalidChoiceError, match="unknown run kind 'fast'; valid choices: 'learner'"
    ):
        load_kind("fast")
    with pytest.raises(SweepGridError, match="has no 'nope'"):
        load_kind("custom", "pil.task.systems:nope")
    with pytest.raises(SweepGridError, match=r"must be written 'package\.module:function'"):
        load_kind("custom", "pil.task.systems.check_system")


def test_custom_function_declares_its_own_params() -> None:
    target = load_kind("custom", "sweep_test_runs:paced_run")
    assert {"delay", "die", "discard", "tables"} <= set(target.params)
    assert target.systems == tuple(SYSTEMS)
    assert parse_param("delay=0.01", target) == ("delay", (0.01,))


def test_physical_runs_start_longest_expected_first() -> None:
    from pil.experiments.sweep_grid import longest_first
    from robin_sim.episode.physical_run import physical_cost

    target = load_kind("physical")
    grid = build_grid(
        target, systems=["pil"], rates=[0.6, 1.0], reps=4, tables=1, params=["legs_per_table=1"]
    )
    runs = grid.runs()
    ordered = longest_first(runs, target)
    assert sorted(r.run_id for r in ordered) == [r.run_id for r in runs]
    costs = [physical_cost(r.spec) for r in ordered]
    assert costs == sorted(costs, reverse=True) and costs[0] > costs[-1]
    # the learner-only twin's counts: a run at 60 % costs more than the same seed at 100 %
    low = {r.seed: c for r, c in zip(ordered, costs, strict=True) if r.rate == 0.6}
    high = {r.seed: c for r, c in zip(ordered, costs, strict=True) if r.rate == 1.0}
    assert sum(low.values()) > sum(high.values())
    learner = load_kind("learner")
    assert longest_first(runs, learner) == runs  # learner-only: the grid's order
