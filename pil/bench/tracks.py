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
repeat). :func:`run_track` returns a flat row (the journal's).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from pil.bench.entrants import Factory, as_agent
from pil.bench.noise import make_reader
from pil.bench.suite import Suite, Track
from pil.task.person import ScriptedPerson, ScriptStep, plan_script
from pil.task.records import StepRecord
from pil.task.runner import RunnerError, steps
from pil.task.scenario import load_scenario, states_along
from pil.task.seeds import sub_seeds
from pil.task.world import Outcome, SymbolicWorld, Target, Watcher
from pil.types import Action, Feedback, State, hand_after


class _CappedError(Exception):
    """The run passed its cap of actions."""


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


@dataclass
class Played:
    """What one script cost: totals, per-table actions, and the records' key facts."""

    actions: int = 0
    gestures: int = 0
    rejected: int = 0
    failed: str = ""
    per_table: dict[int, int] = field(default_factory=dict)
    # (table, handover, step, gesture, first action of the instruction approved?) per action
    events: list[tuple[int, int, int, str, bool, int]] = field(default_factory=list)


def play(
    agent: Any,
    script: Sequence[ScriptStep],
    reader: Any,
    person_seed: int,
    cap: float,
    people: int = 1,
) -> Played:
    """Run ``agent`` through ``script`` with ``reader``; stop (failed) past the cap."""
    mappings = table_mappings(script)

    def on_table(table: int) -> None:
        if hasattr(agent, "set_mapping"):
            agent.set_mapping(mappings.get(table, {}))
        if hasattr(reader, "set_person"):
            reader.set_person(table % people)

    person = ScriptedPerson(script, person_seed)
    records = steps(agent, person, reader, TableWorld(on_table, reader))
    return count(records, cap * len(script))


def count(records: Iterable[StepRecord], limit: float) -> Played:
    """What a run's records cost; stop (failed) when actions or gestures pass ``limit``."""
    out = Played()
    seen: set[tuple[int, int, bool]] = set()
    try:
        for record in records:
            out.gestures = record.gesture_count
            if record.gesture_count > limit:
                raise _CappedError
            if record.action is None:
                continue
            out.actions = record.t
            out.per_table[record.table] = out.per_table.get(record.table, 0) + 1
            out.rejected += record.feedback is Feedback.NOT_OK
            key = (record.handover, record.step, record.recovery)
            first = key not in seen
            seen.add(key)
            ok = record.feedback is not Feedback.NOT_OK
            out.events.append(
                (
                    record.table,
                    record.handover,
                    record.step,
                    record.true_gesture.value,
                    first and ok,
                    record.t,
                )
            )
            if record.t > limit:
                raise _CappedError
    except _CappedError:
        out.failed = f"passed the cap of {limit:g} actions or gestures"
    except RunnerError as error:
        out.failed = str(error)
    return out


def curve_of(played: Played, tables: int) -> list[int]:
    """Actions per table (0 for a table the run never reached)."""
    return [played.per_table.get(k, 0) for k in range(tables)]


def curve_area(curve: Sequence[float]) -> float:
    """The trapezoid area under the per-table actions curve over the unit interval (its mean
    height, in actions per table, whatever the number of tables)."""
    if len(curve) < 2:
        return float(curve[0]) if curve else math.nan
    return sum((a + b) / 2 for a, b in itertools.pairwise(curve)) / (len(curve) - 1)


def recovery(played: Played, from_table: int, gesture: str, criterion: int) -> float:
    """Actions from the change until ``criterion`` instructions with ``gesture`` in a row had
    their first action approved (NaN: never)."""
    start, streak, seen = None, 0, set()
    for table, handover, step, true, first_ok, t in played.events:
        if table < from_table:
            continue
        if start is None:
            start = t - 1
        if true != gesture or (handover, step) in seen:
            continue
        seen.add((handover, step))
        streak = streak + 1 if first_ok else 0
        if streak >= criterion:
            return float(t - start)
    return math.nan


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
    played = play(agent, script, reader, seeds.person, cap, parts.get("people", 1))
    tables = 1 + max((i.intent.table for i in script), default=0)
    curve = curve_of(played, tables)
    row: dict[str, Any] = {
        "actions": played.actions,
        "gestures": played.gestures,
        "rejected": played.rejected,
        "curve": curve,
        "curve_area": curve_area(curve),
        "failed": played.failed,
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
        after = play(
            agent, second, make_reader(spec, seeds.detector, len(second)), seeds.person, cap
        )
        fresh = as_agent(factory(seeds.learner), seeds.learner, "the agent factory")
        scratch = play(
            fresh, second, make_reader(spec, seeds.detector, len(second)), seeds.person, cap
        )
        failed = played.failed or after.failed or scratch.failed
        row.update(
            first_actions=played.actions,
            actions=after.actions,
            gestures=after.gestures,
            rejected=after.rejected,
            scratch_actions=scratch.actions,
            scripted=len(second),
            savings=scratch.actions - after.actions,
            failed=failed,
        )
    if row["failed"]:
        for key in ("actions", "gestures", "rejected", "curve_area", "recovery", "savings"):
            if key in row:
                row[key] = math.nan
    return row
