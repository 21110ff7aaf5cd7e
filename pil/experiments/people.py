"""The personal-mappings study: two people who mean different actions by the same gesture.

A people file (``scenarios/two_people.yaml``) names a base assembly and, per person, the
gestures they mean differently (``give me -> location``). The people take turns, one table
each (person ``k % n`` assembles test table ``k``). Two ways to learn:

* ``shared``: one learner over the whole assembly, as if the robot could not tell the people
  apart;
* ``per-person``: the robot knows who is there and keeps a table per person (each learner
  sees only its person's tables).

Both get the same detection rate; costs are summed over both people.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.experiments.adaptation import remap
from pil.experiments.paper import PAPER_REPS
from pil.experiments.rep_journal import RepJournal
from pil.experiments.study import rep_seeds
from pil.experiments.study_files import read_study_file
from pil.task.assemble import assemble
from pil.task.scenario import SCENARIOS_DIR, HandoverType, Scenario, ScenarioError, parse_step
from pil.task.script import plan_script
from pil.task.seeds import person_seed, sub_seeds
from pil.task.spec import RunSpec, parse_run_spec
from pil.types import Action, Gesture

DEFAULT_PEOPLE = SCENARIOS_DIR / "two_people.yaml"
MODES: tuple[str, ...] = ("shared", "per-person")
PEOPLE_SYSTEMS: tuple[str, ...] = ("pil", "pil-halve")
PEOPLE_RATES: tuple[float, ...] = (0.8, 1.0)  # robin-pil people's default detection rates
_KEYS = ("name", "description", "scenario", "people")


@dataclass(frozen=True, slots=True)
class People:
    """The base assembly and each person's overrides (gesture -> action)."""

    scenario: Scenario
    overrides: Mapping[str, tuple[tuple[Gesture, Action], ...]]


def load_people(path: str | Path = DEFAULT_PEOPLE) -> People:
    """Read a people file; anything malformed raises :class:`ScenarioError` naming it."""
    path, raw, scenario = read_study_file(path, _KEYS, "people file")
    people = raw.get("people")
    if not isinstance(people, Mapping) or len(people) < 2:
        raise ScenarioError(f"{path}: people: expected at least two people (name: [overrides])")
    overrides = {}
    for name, steps in people.items():
        if not isinstance(steps, list):
            raise ScenarioError(f"{path}: people.{name}: expected a list of 'gesture -> action'")
        overrides[str(name)] = tuple(parse_step(text, f"{path}: people.{name}") for text in steps)
    return People(scenario, overrides)


def person_types(people: People, name: str, types: Sequence[HandoverType]) -> list[HandoverType]:
    """``types`` as person ``name`` performs them (their overrides applied)."""
    out = list(types)
    for gesture, action in people.overrides[name]:
        out = [remap(t, gesture, action) for t in out]
    return out


def run_people(spec: RunSpec, mode: str, people: People) -> dict[str, Any]:
    """One run of the whole assembly by the people taking turns, in ``mode``; each learner's
    run is assembled from ``spec`` (its system's parameters applied) with the people's
    script (:func:`pil.task.assemble.assemble`)."""
    scenario, names = people.scenario, list(people.overrides)
    legs = scenario.legs_per_table
    seeds = spec.seeds.phase("test")
    types = scenario.draw_types(scenario.tables * legs, seeds.draw)
    by_table = [
        person_types(people, names[k % len(names)], types[k * legs : (k + 1) * legs])
        for k in range(scenario.tables)
    ]
    if mode == "shared":
        script = plan_script([t for table in by_table for t in table], legs, scenario.spots)
        parts = [assemble(spec, seeds=seeds, script=script).run()]
    else:
        parts = []
        for i in range(len(names)):
            own = [t for k, table in enumerate(by_table) if k % len(names) == i for t in table]
            if not own:  # fewer tables than people: this person builds none and costs nothing
                continue
            script = plan_script(own, legs, scenario.spots)
            own_seeds = sub_seeds(person_seed(spec.seed, i)).phase("test")
            run = assemble(spec, seeds=own_seeds, script=script)
            parts.append(run.run())
    return {
        "system": spec.system,
        "mode": mode,
        "run": f"{spec.system} {mode}",
        "rate": spec.rate,
        "seed": int(spec.seed),
        "people": len(names),
        "tables": scenario.tables,
        "gestures": sum(p.gestures for p in parts),
        "actions": sum(p.actions for p in parts),
        "rejected": sum(p.rejected for p in parts),
        "legs": sum(p.legs for p in parts),
    }


def journal_settings(
    people: People, systems: Sequence[str], rates: Sequence[float], seed: int
) -> dict[str, Any]:
    """What makes two people studies' repetitions the same (:class:`RepJournal`'s key)."""
    return {
        "study": "people",
        "scenario": repr(people.scenario),
        "overrides": repr(people.overrides),
        "systems": list(systems),
        "rates": list(rates),
        "seed": seed,
    }


def run_people_study(
    people: People,
    systems: Sequence[str] = PEOPLE_SYSTEMS,
    rates: Sequence[float] = PEOPLE_RATES,
    reps: int = PAPER_REPS,
    seed: int = 0,
    progress: Any = None,
    journal: RepJournal | None = None,
) -> list[dict[str, Any]]:
    """Both modes for every system, rate and repetition (same handover order per seed).
    ``systems`` (PIL learners from scratch) and ``rates`` are taken as checked by the edge
    (``robin-pil people``'s ``run_options``); the scenario is parsed here, once. With a
    ``journal`` (of :func:`journal_settings`) each finished repetition is kept as it ends and
    one kept already is read back, not run again."""
    base = parse_run_spec(scenario=people.scenario)
    rows: list[dict[str, Any]] = []
    for rep, run_seed in enumerate(rep_seeds(seed, reps)):
        kept = None if journal is None else journal.finished(rep, run_seed)
        if kept is not None:
            rows += kept
            if progress is not None:
                progress(len(rates) * len(systems))
            continue
        these = []
        for rate in rates:
            for system in systems:
                for mode in MODES:
                    row = run_people(base.for_run(system, rate, run_seed), mode, people)
                    these.append({"rep": rep, **row})
                if progress is not None:
                    progress(1)
        rows += these if journal is None else journal.add(rep, run_seed, these)
    from pil.experiments.outputs import sort_runs  # with the other outputs: loaded late

    return sort_runs(rows, systems, "mode", MODES)


def write_people(rows: Sequence[Mapping[str, Any]], out: Any) -> list:
    """``people.csv``, ``people.md`` and ``people.png`` under ``out``."""
    from pil.experiments.outputs import write_small_study

    tables = rows[0]["tables"] if rows else "?"
    intro = (
        f"Two people take turns over {tables} tables, one table each; B means location by "
        "give me, A human. "
        "`shared`: one table for both; `per-person`: one table each. Costs summed over "
        "both people."
    )
    return write_small_study(
        rows,
        out,
        "people",
        title="Personal mappings: one shared table vs one per person",
        intro=intro,
        group_by=("rate", "system", "mode"),
        metrics=("actions", "gestures", "rejected"),
        figure_metric="actions",
        baseline="shared",
        compare_by="mode",
        within=("rate", "system"),
        ylabel=f"robot actions for {tables} tables",
        figure_group_by=("rate", "run"),
    )
