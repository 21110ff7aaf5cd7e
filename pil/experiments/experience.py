"""The paper's study at equal experience: the cost of each table against tables experienced.

The paper compares PIL's 10 test tables with the pre-trained conditions' 10 test tables
(*test tables only*) or with their 5 training tables added (*training included*). Neither
compares like with like: a condition's test table k is its (5 + k)-th table of experience,
PIL's is its k-th. Here every table a system meets is numbered by experience: PIL's tables
1-10 are experience 1-10; c1-c4's 5 training tables are experience 1-5 and their test tables
6-15. :func:`table_costs` counts gestures and actions per table (read from the step records
of the training and the test run, the same runs ``robin-pil study`` counts), and
:func:`window_rows` sums them over a window of experience, one row per run, so that
:func:`pil.experiments.stats.compare` pairs PIL and each condition by repetition:

* ``experience 6-10``: PIL's tables 6-10 against the condition's test tables 1-5: the same
  amount of experience behind every table;
* ``first 10 tables``: PIL's 10 tables against the condition's 5 training + 5 test tables;
* beside them the paper's two readings from the same per-table counts: ``training included``
  (every table each system met: PIL's 10 against a condition's 15) and ``test tables only``
  (PIL's 10 against a condition's 10 test tables, its 6-15 of experience).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from pil.task.records import StepRecord
from pil.task.spec import RunSpec

#: reading -> (experienced tables, 1-based inclusive, or None: all; phase, or None: both)
WINDOWS: dict[str, tuple[tuple[int, int] | None, str | None]] = {
    "training included": (None, None),  # the paper's wording: every table a system met
    "test tables only": (None, "test"),
    "experience 6-10": ((6, 10), None),  # PIL's tables 6-10, a condition's test tables 1-5
    "first 10 tables": ((1, 10), None),  # PIL's 10, a condition's 5 training + 5 test
}
EXPERIENCE_COLUMNS: tuple[str, ...] = (
    "rep",
    "seed",
    "rate",
    "system",
    "experienced",
    "phase",
    "scripted",
    "gestures",
    "actions",
    "extra_gestures",
    "extra_actions",
)
WINDOW_MEASURES: tuple[str, ...] = ("gestures", "actions", "extra_gestures", "extra_actions")


def per_table(records: Iterable[StepRecord], tables: int) -> list[tuple[int, int]]:
    """(gestures, actions) of each of ``tables`` tables from a run's step records."""
    ends = [(0, 0)] * tables
    for record in records:
        ends[record.table] = (record.gesture_count, record.t)
    out, last = [], (0, 0)
    for table in range(tables):
        end = ends[table] if ends[table] != (0, 0) else last
        end = (max(end[0], last[0]), max(end[1], last[1]))
        out.append((end[0] - last[0], end[1] - last[1]))
        last = end
    return out


def _scripted(script: Sequence[Any], tables: int) -> list[int]:
    counts = [0] * tables
    for item in script:
        counts[item.intent.table] += 1
    return counts


def _row(k: int, phase: str, scripted: int, cost: tuple[int, int]) -> dict[str, Any]:
    g, a = cost
    return {
        "experienced": k,
        "phase": phase,
        "scripted": scripted,
        "gestures": g,
        "actions": a,
        "extra_gestures": g - scripted,
        "extra_actions": a - scripted,
    }


def table_costs(spec: RunSpec) -> list[dict[str, Any]]:
    """One row per table ``spec``'s system meets, numbered by experience (training first):
    its scripted gestures (what it needs when all goes right), gestures and actions, and
    the extra over the script (``extra_*``: what misreadings and exploration cost; tables
    differ in how many gestures their handovers need, the extra does not depend on it)."""
    from pil.task.assemble import assemble, training_spec

    cache: dict[Any, Any] = {}
    rows: list[dict[str, Any]] = []
    trained = training_spec(spec)
    if trained is not None:
        run = assemble(trained, phase="train", cache=cache)
        tables = trained.scenario.training_tables
        scripted = _scripted(run.person.script, tables)
        for k, cost in enumerate(per_table(run.steps(), tables)):
            rows.append(_row(k + 1, "train", scripted[k], cost))
    test = assemble(spec, cache=cache)
    offset = len(rows)
    scripted = _scripted(test.person.script, spec.scenario.tables)
    for k, cost in enumerate(per_table(test.steps(), spec.scenario.tables)):
        rows.append(_row(offset + k + 1, "test", scripted[k], cost))
    head = {"seed": spec.seed, "rate": spec.rate, "system": spec.system}
    return [{**head, **r} for r in rows]


def experience_rows(
    base: RunSpec, systems: Sequence[str], rates: Sequence[float], seeds: Sequence[int]
) -> list[dict[str, Any]]:
    """:func:`table_costs` of every system, rate and repetition seed (rows of
    :data:`EXPERIENCE_COLUMNS`)."""
    out = []
    for rep, seed in enumerate(seeds):
        for rate in rates:
            for system in systems:
                out += [{"rep": rep, **r} for r in table_costs(base.for_run(system, rate, seed))]
    return out


def window_rows(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per run (rep, rate, system): gestures and actions summed over each reading of
    :data:`WINDOWS` (``<reading>|gestures`` columns; a run without the whole window of
    experience has none)."""
    runs: dict[tuple[Any, Any, Any], list[Mapping[str, Any]]] = {}
    for r in rows:
        runs.setdefault((r["rep"], r["rate"], r["system"]), []).append(r)
    out = []
    for (rep, rate, system), tables in runs.items():
        row: dict[str, Any] = {"rep": rep, "rate": rate, "system": system}
        by_k = {int(t["experienced"]): t for t in tables}
        for reading, (span, phase) in WINDOWS.items():
            if span is not None and not all(k in by_k for k in range(span[0], span[1] + 1)):
                continue
            chosen = [
                t
                for k, t in by_k.items()
                if (span is None or span[0] <= k <= span[1])
                and (phase is None or t["phase"] == phase)
            ]
            for measure in WINDOW_MEASURES:
                row[f"{reading}|{measure}"] = sum(float(t[measure]) for t in chosen)
        out.append(row)
    return out


def experience_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """PIL against every other system in every reading, per rate, on gestures, actions and
    their extra over the script (paired by ``rep``; Holm over each pair and reading: a
    declared family, whatever else ran)."""
    from pil.experiments.stats import Measure, compare

    windows = window_rows(rows)
    metrics = [
        Measure(f"{reading}|{m}", m, reading) for reading in WINDOWS for m in WINDOW_MEASURES
    ]
    present = [m for m in metrics if all(m.column in w for w in windows)]
    return compare(windows, "pil", within=("rate",), metrics=present, pair_by=("rep",))
