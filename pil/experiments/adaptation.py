"""The adaptation study: the person changes what a gesture means in the middle of the task.

A change file (``scenarios/mapping_change.yaml``) names a base assembly and the change, e.g.
"from table 6 on, give me means location". The change lives in the person's script: the
handover types of the later tables are rewritten (each step of that gesture now means the new
action) before :func:`pil.task.person.plan_script` plans them; the runner and the learners are
the study's. Each run is paired with a control run without the change (same seeds), and
measures what the change cost: extra gestures and actions; the old habit at the change (the
count of the old action in the gesture's state where it is largest, the *habit state*); the
instructions acted on in the habit state until the robot exploits the new action there; and
the rejections on instructions with the gesture until then.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, MutableMapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.experiments.paper import PAPER_REPS
from pil.experiments.study import rep_seeds
from pil.experiments.study_files import read_study_file
from pil.task.assemble import assemble, pretraining
from pil.task.scenario import SCENARIOS_DIR, HandoverType, Scenario, ScenarioError, build_type
from pil.task.script import ScriptStep, plan_script
from pil.task.spec import RunSpec, parse_run_spec
from pil.types import Action, Feedback, Gesture

DEFAULT_CHANGE = SCENARIOS_DIR / "mapping_change.yaml"
ADAPT_SYSTEMS: tuple[str, ...] = ("pil", "pil-halve", "c1", "c2", "c3", "c4", "bandit", "tamer")
ADAPT_RATES: tuple[float, ...] = (0.8, 1.0)  # robin-pil adapt's default detection rates
_KEYS = ("name", "description", "scenario", "change")
_CHANGE_KEYS = ("from_table", "gesture", "action")


@dataclass(frozen=True, slots=True)
class MappingChange:
    """From test table ``from_table`` (1-based) on, ``gesture`` means ``action``."""

    scenario: Scenario
    from_table: int
    gesture: Gesture
    action: Action
    name: str = "mapping_change"


def load_change(path: str | Path = DEFAULT_CHANGE) -> MappingChange:
    """Read a change file; anything malformed raises :class:`ScenarioError` naming it."""
    path, raw, scenario = read_study_file(path, _KEYS, "mapping change")
    change = raw.get("change")
    if not isinstance(change, Mapping) or set(change) != set(_CHANGE_KEYS):
        raise ScenarioError(f"{path}: change: expected the keys {', '.join(_CHANGE_KEYS)}")
    first = change["from_table"]
    if isinstance(first, bool) or not isinstance(first, int) or not 2 <= first <= scenario.tables:
        raise ScenarioError(
            f"{path}: change.from_table: expected a whole number from 2 to "
            f"{scenario.tables} (the test tables), got {first!r}"
        )
    try:
        gesture, action = Gesture.parse(change["gesture"]), Action.parse(change["action"])
    except ValueError as error:
        raise ScenarioError(f"{path}: change: {error}") from None
    return MappingChange(scenario, first, gesture, action, str(raw.get("name", path.stem)))


def remap(handover_type: HandoverType, gesture: Gesture, action: Action) -> HandoverType:
    """``handover_type`` with every step of ``gesture`` meaning ``action`` (states recomputed)."""
    texts = [
        f"{s.gesture.value} -> {(action if s.gesture is gesture else s.action).value}"
        for s in handover_type.steps
    ]
    raw = {
        "steps": texts,
        "description": f"{handover_type.description} ({gesture.value} -> {action.value})",
    }
    return build_type(handover_type.name, raw, "mapping change")


def changed_script(
    scenario: Scenario, change: MappingChange, draw_seed: int
) -> tuple[ScriptStep, ...]:
    """The test script with the change applied from ``change.from_table`` on."""
    types = scenario.draw_types(scenario.tables * scenario.legs_per_table, draw_seed)
    first = (change.from_table - 1) * scenario.legs_per_table
    later = [remap(t, change.gesture, change.action) for t in types[first:]]
    return plan_script([*types[:first], *later], scenario.legs_per_table, scenario.spots)


def run_adaptation(
    spec: RunSpec, change: MappingChange, cache: MutableMapping[Any, Any] | None = None
) -> dict[str, Any]:
    """One paired run of ``spec`` (its scenario: the change's): with the change and without
    it (same seeds), both assembled from the spec (:func:`pil.task.assemble.assemble`)."""
    system, rate, seed, scenario = spec.system, spec.rate, spec.seed, spec.scenario
    training = pretraining(spec, cache)
    base = assemble(spec, cache=cache, training=training).run()
    script = changed_script(scenario, change, spec.seeds.phase("test").draw)
    parts = assemble(spec, cache=cache, training=training, script=script)
    changed_from = change.from_table - 1
    habit, main = math.nan, None
    seen: set[tuple[int, int]] = set()
    instructions = rejections = 0
    adapted_after = math.nan
    last = None
    for record in parts.steps():
        last = record
        if record.table < changed_from:
            continue
        if main is None:  # at the change: the gesture's state with the strongest old habit
            table = parts.learner.table
            habit, main = max(
                ((table.count(st, old), st) for st, old in _old_states(scenario, change.gesture)),
                key=lambda pair: pair[0],
            )
        if record.true_gesture is not change.gesture or record.action is None:
            continue
        if adapted_after == adapted_after:
            continue
        key = (record.handover, record.step)
        if key not in seen and record.state == main:  # an instruction's first action there
            seen.add(key)
            instructions += 1
            if record.exploited and record.action is change.action:
                adapted_after = instructions
                continue
        seen.add(key)
        rejections += record.feedback is Feedback.NOT_OK
    assert last is not None
    return {
        "system": system,
        "rate": rate,
        "seed": int(seed),
        "gestures": last.gesture_count,
        "actions": last.t,
        "control_gestures": base.gestures,
        "control_actions": base.actions,
        "extra_gestures": last.gesture_count - base.gestures,
        "extra_actions": last.t - base.actions,
        "habit": habit,
        "habit_state": "" if main is None else main.key(),
        "adapted": adapted_after == adapted_after,
        "instructions_to_adapt": adapted_after,
        "lost_rejections": rejections,
        "from_table": change.from_table,
        "gesture": change.gesture.value,
        "action": change.action.value,
    }


def _old_states(scenario: Scenario, gesture: Gesture) -> list[tuple[Any, Action]]:
    """The states in which ``gesture`` is performed before the change, with its action then."""
    return sorted(
        {(s.state, s.action) for t in scenario.types for s in t.steps if s.gesture is gesture},
        key=lambda pair: pair[0].key(),
    )


def run_adaptation_study(
    change: MappingChange,
    systems: Sequence[str] = ADAPT_SYSTEMS,
    rates: Sequence[float] = ADAPT_RATES,
    reps: int = PAPER_REPS,
    seed: int = 0,
    params: Mapping[str, Any] | None = None,
    progress: Any = None,
) -> list[dict[str, Any]]:
    """Every system at every rate, ``reps`` paired runs each (common random numbers).
    ``systems`` and ``rates`` are taken as checked by the edge (``robin-pil adapt``'s
    ``run_options``); the scenario and ``params`` are parsed here, once."""
    base = parse_run_spec(scenario=change.scenario, params=params)
    rows = []
    for rep, run_seed in enumerate(rep_seeds(seed, reps)):
        cache: dict[Any, Any] = {}
        for rate in rates:
            for system in systems:
                row = run_adaptation(base.for_run(system, rate, run_seed), change, cache)
                rows.append({"rep": rep, **row})
                if progress is not None:
                    progress(1)
    from pil.experiments.outputs import sort_runs  # with the other outputs: loaded late

    return sort_runs(rows, systems)


def adapted_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """Per rate and system: the share of runs that adapted, and the instructions it took."""
    from pil.experiments.report import group_rows, markdown_table, mean_sd, number

    body = []
    for (rate, system), members in group_rows(rows, ["rate", "system"]).items():
        took = [number(r["instructions_to_adapt"]) for r in members if str(r["adapted"]) == "True"]
        habit = mean_sd([number(r["habit"]) for r in members])
        mean, sd = mean_sd(took)
        body.append(
            [
                rate,
                system,
                f"{len(took)} of {len(members)}",
                "n/a" if not took else f"{mean:.1f} ± {sd:.1f}",
                f"{habit[0]:.1f} ± {habit[1]:.1f}",
            ]
        )
    return "## Adapted within the run\n\n" + markdown_table(
        [
            "rate",
            "system",
            "adapted",
            "instructions in the habit state until exploited",
            "old habit (count at the change)",
        ],
        body,
    )


def write_adaptation(rows: Sequence[Mapping[str, Any]], change: MappingChange, out: Any) -> list:
    """``adaptation.csv``, ``adaptation.md`` and ``adaptation.png`` under ``out``."""
    from pil.experiments.outputs import write_small_study

    intro = (
        f"From test table {change.from_table} on, {change.gesture.value!r} means "
        f"{change.action.value!r}. `extra_*`: the cost against the same run without the "
        "change (same seeds); `lost_rejections`: not-OKs on instructions with the gesture "
        "until the new action is exploited (or to the end); `habit`: the old action's count "
        "in the gesture's states at the change."
    )
    return write_small_study(
        rows,
        out,
        "adaptation",
        title="Adaptation to a changed mapping",
        intro=intro,
        group_by=("rate", "system"),
        metrics=("extra_actions", "extra_gestures", "lost_rejections", "habit"),
        figure_metric="extra_actions",
        baseline="pil",
        compare_by="system",
        ylabel="extra robot actions caused by the change",
        extra=adapted_markdown(rows),
    )
