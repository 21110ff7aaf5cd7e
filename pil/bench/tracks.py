"""One benchmark run: an entrant on a track, under a condition, for one run seed.

Every track drives the study's step loop (:func:`pil.task.runner.steps`) with the scripted
person, the condition's reader (:mod:`pil.bench.noise`) and a symbolic world, so actions and
gestures are counted as the study counts them. The run seed's sub-seeds
(:func:`pil.task.seeds.sub_seeds`) fix the handover order, the reader's draws and the
person's, so every agent faces the same script and readings on a seed (common random numbers).

* ``assembly``: the tables of the scenario from scratch.
* ``meaning-change``: the assembly with a gesture's meaning changed from a table on;
  ``recovery`` = actions from the change until ``criterion`` instructions with that gesture in
  a row got their first action approved (NaN: never).
* ``transfer``: the assembly, then the second task by the same agent (``actions``) and by a
  fresh one (``scratch_actions``); ``savings`` = scratch - after.
* ``two-people``: the people take turns a table each (one agent for both).

A run stops as failed when a gesture never gets an approved action or the actions pass
``cap`` x the scripted gestures (or the gestures do: a robot that keeps asking for a
repeat); apart from that it is *stalled* when the robot did not act for the suite's
``stalled`` (K) gestures in a row (:mod:`pil.bench.counting`). :func:`run_track` returns a
flat row (the journal's).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from pil.bench.counting import Played, count, curve_area, curve_of, recovery
from pil.bench.entrants import Factory, as_agent
from pil.bench.noise import make_reader
from pil.bench.suite import Suite, Track
from pil.task.person import ScriptedPerson
from pil.task.runner import steps
from pil.task.scenario import load_scenario, states_along
from pil.task.script import ScriptStep, plan_script
from pil.task.seeds import sub_seeds
from pil.task.world import Outcome, SymbolicWorld, Target, Watcher
from pil.types import Action, Feedback, State, hand_after

__all__ = ["TableWorld", "count", "curve_area", "curve_of", "play", "run_track"]


class TableWorld(SymbolicWorld):
    """The symbolic world, telling ``on_table`` of each new table. The thumb down that stops
    a wrong action is read by ``reader`` when it can (:meth:`FeedbackChannel.read_stop`): a
    stop the robot does not get lets the action run on, as a real robot would."""

    def __init__(self, on_table: Callable[[int], None], reader: Any = None) -> None:
        super().__init__()
        self._on_table = on_table
        self._read_stop = getattr(reader, "read_stop", None)

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        """As the symbolic world, but the stop passes through the reader's thumb noise."""
        if (
            watcher is not None
            and (watcher.stop_now(action) or watcher.result_window(action) > 0.0)
            and (self._read_stop is None or self._read_stop() is Feedback.NOT_OK)
        ):
            return Outcome(False, "stopped by the person", undone=True, interrupted=True)
        self._hand = hand_after(action, self._hand)
        return Outcome(succeeded=True)

    def start_table(self, table: int) -> None:
        """Tell the bench (the oracle's mapping, the person now gesturing)."""
        self._on_table(table)


def table_mappings(script: Sequence[ScriptStep]) -> dict[int, dict[State, Action]]:
    """Per table, the mapping its handovers follow (state -> wanted action)."""
    handovers: dict[int, list[ScriptStep]] = {}
    for item in script:
        handovers.setdefault(item.intent.handover, []).append(item)
    out: dict[int, dict[State, Action]] = {}
    for items in handovers.values():
        pairs = [(i.intent.gesture, i.intent.action) for i in items]
        mapping = out.setdefault(items[0].intent.table, {})
        for state, (_g, action) in zip(states_along(pairs), pairs, strict=True):
            mapping[state] = action
    return out


def play(
    agent: Any,
    script: Sequence[ScriptStep],
    reader: Any,
    person_seed: int,
    cap: float,
    people: int = 1,
    stall_after: int | None = None,
) -> Played:
    """Run ``agent`` through ``script`` with ``reader``; stop (failed) past the cap; a wait of
    ``stall_after`` gestures without an action marks it stalled."""
    mappings = table_mappings(script)

    def on_table(table: int) -> None:
        if hasattr(agent, "set_mapping"):
            agent.set_mapping(mappings.get(table, {}))
        if hasattr(reader, "set_person"):
            reader.set_person(table % people)

    person = ScriptedPerson(script, person_seed)
    records = steps(agent, person, reader, TableWorld(on_table, reader))
    return count(records, cap * len(script), stall_after)


def _scripts(track: Track, quick: bool, draw: int) -> dict[str, Any]:
    """The track's script(s) and what its metrics need."""
    opts, kind = track.options, track.kind
    tables = track.quick.get("tables") if quick else None
    if kind == "meaning-change":
        from dataclasses import replace

        from pil.experiments.adaptation import changed_script, load_change

        change = load_change(_shipped(opts["change"]))
        first = track.quick.get("from_table", change.from_table) if quick else change.from_table
        scenario = change.scenario.with_changes(tables=tables or change.scenario.tables)
        change = replace(change, scenario=scenario, from_table=first)
        script = changed_script(scenario, change, draw)
        return {"script": script, "change": change}
    if kind == "two-people":
        from pil.experiments.people import load_people, person_types

        people = load_people(_shipped(opts["people"]))
        scenario = people.scenario.with_changes(tables=tables or people.scenario.tables)
        names, legs = list(people.overrides), scenario.legs_per_table
        types = scenario.draw_types(scenario.tables * legs, draw)
        ordered = [
            t
            for k in range(scenario.tables)
            for t in person_types(people, names[k % len(names)], types[k * legs : (k + 1) * legs])
        ]
        return {"script": plan_script(ordered, legs, scenario.spots), "people": len(names)}
    scenario = load_scenario(opts.get("scenario", "assembly"))
    scenario = scenario.with_changes(tables=tables or scenario.tables)
    legs = scenario.legs_per_table
    types = scenario.draw_types(scenario.tables * legs, draw)
    out: dict[str, Any] = {"script": plan_script(types, legs, scenario.spots)}
    if kind == "transfer":
        second = load_scenario(opts["second"])
        second = second.with_changes(tables=tables or second.tables)
        more = second.draw_types(second.tables * second.legs_per_table, draw)
        out["second"] = plan_script(more, second.legs_per_table, second.spots)
    return out


def _shipped(name: str) -> str:
    from pil.task.scenario import SCENARIOS_DIR

    return str(SCENARIOS_DIR / f"{name}.yaml")


def run_track(
    suite: Suite, track: Track, condition: str, seed: int, factory: Factory, quick: bool
) -> dict[str, Any]:
    """One run of ``factory``'s agent: a flat row of the metrics (see the module docstring)."""
    seeds = sub_seeds(seed).phase("test")
    parts = _scripts(track, quick, seeds.draw)
    script = parts["script"]
    spec = suite.conditions[condition]
    agent = as_agent(factory(seeds.learner), seeds.learner, "the agent factory")
    reader = make_reader(spec, seeds.detector, len(script))
    cap = suite.cap_of(track.name)
    stall = suite.stall_after
    played = play(agent, script, reader, seeds.person, cap, parts.get("people", 1), stall)
    tables = 1 + max((i.intent.table for i in script), default=0)
    curve = curve_of(played, tables)
    row: dict[str, Any] = {
        "actions": played.actions,
        "gestures": played.gestures,
        "rejected": played.rejected,
        "curve": curve,
        "curve_area": curve_area(curve),
        "failed": played.failed,
        "stalled": played.stalled,
        "longest_wait": played.longest_wait,
        "scripted": len(script),
    }
    if track.kind == "meaning-change":
        change = parts["change"]
        criterion = int(track.options.get("criterion", 3))
        row["recovery"] = recovery(played, change.from_table - 1, change.gesture.value, criterion)
    if track.kind == "transfer":
        second = parts["second"]
        if hasattr(agent, "restart"):
            agent.restart()  # back at the start pose; what it learnt stays

        def tidy(by: Any) -> Played:  # the second task, the same readings and person
            reader = make_reader(spec, seeds.detector, len(second))
            return play(by, second, reader, seeds.person, cap, stall_after=stall)

        after = tidy(agent)
        scratch = tidy(as_agent(factory(seeds.learner), seeds.learner, "the agent factory"))
        failed = played.failed or after.failed or scratch.failed
        every = (played, after, scratch)
        row.update(
            first_actions=played.actions,
            actions=after.actions,
            gestures=after.gestures,
            rejected=after.rejected,
            scratch_actions=scratch.actions,
            scripted=len(second),
            savings=scratch.actions - after.actions,
            failed=failed,
            stalled=any(p.stalled for p in every),
            longest_wait=max(p.longest_wait for p in every),
        )
    if row["failed"]:
        for key in ("actions", "gestures", "rejected", "curve_area", "recovery", "savings"):
            if key in row:
                row[key] = math.nan
    return row
