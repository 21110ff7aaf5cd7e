"""The transfer study: a second task (tidying legs onto spots) from scratch or from the
associations saved after the assembly.

Per repetition and rate, a PIL run assembles the 10 tables (``scenarios/assembly.yaml``) and
its table is kept, unless a saved table is given (``--table FILE``: every run starts from
it). Then the same person and detector seeds tidy 10 rounds (``scenarios/tidy.yaml``) twice:
from an empty table and from a copy of the transferred one. The tidy task shares most of its
states with the assembly, with the same meaning, but in one handover type "give me" means
location, where the assembly taught human.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from pil.experiments.paper import PAPER_REPS
from pil.experiments.study import rep_seeds
from pil.table import AssociationTable
from pil.table_io import load_table, save_table
from pil.task.assemble import assemble
from pil.task.scenario import SCENARIOS_DIR, load_scenario
from pil.task.spec import RunSpec, parse_run_spec

TIDY = SCENARIOS_DIR / "tidy.yaml"
STARTS: tuple[str, ...] = ("scratch", "table")
TRANSFER_SYSTEMS: tuple[str, ...] = ("pil", "pil-halve")
TRANSFER_RATES: tuple[float, ...] = (0.6, 0.8, 1.0)  # robin-pil transfer's default rates


def assembly_table(spec: RunSpec) -> AssociationTable:
    """The table a PIL run of ``spec`` (its system's parameters applied) leaves after
    assembling its scenario's test tables."""
    run = assemble(spec)
    run.run()
    return run.learner.table


def run_transfer(spec: RunSpec, start: str, table: AssociationTable | None) -> dict[str, Any]:
    """One run of ``spec``'s task (its scenario: the second task) from ``start`` ("scratch"
    or "table")."""
    used = None if start == "scratch" else table.copy()  # type: ignore[union-attr]
    stats = assemble(spec, table=used).run()
    return {
        "system": spec.system,
        "start": start,
        "run": f"{spec.system} from {start}",
        "rate": spec.rate,
        "seed": int(spec.seed),
        "task": spec.scenario.name,
        "gestures": stats.gestures,
        "actions": stats.actions,
        "rejected": stats.rejected,
        "corrections": stats.corrections,
        "repeats": stats.repeats,
        "transferred_approvals": 0 if used is None else table.total(),  # type: ignore[union-attr]
    }


def run_transfer_study(
    systems: Sequence[str] = TRANSFER_SYSTEMS,
    rates: Sequence[float] = TRANSFER_RATES,
    reps: int = PAPER_REPS,
    seed: int = 0,
    *,
    table_file: str | Path | None = None,
    save_first: str | Path | None = None,
    params: Mapping[str, Any] | None = None,
    progress: Any = None,
) -> list[dict[str, Any]]:
    """Paired runs (scratch vs table) of every system, rate and repetition.

    ``table_file``: start every "table" run from this saved table instead of each
    repetition's own assembly; ``save_first``: save the first repetition's assembly table
    at the first rate there (to reuse with ``table_file``). ``systems`` (PIL learners from
    scratch) and ``rates`` are taken as checked by the edge (``robin-pil transfer``'s
    ``run_options``).
    """
    assembly = parse_run_spec(params=params)  # parsed once, here (the first task's)
    task = replace(assembly, scenario=load_scenario(TIDY))  # the second task: as shipped
    given = None if table_file is None else load_table(table_file)
    rows = []
    for rep, run_seed in enumerate(rep_seeds(seed, reps)):
        for rate in rates:
            for system in systems:
                table = given
                if table is None:
                    table = assembly_table(assembly.for_run(system, rate, run_seed))
                    if save_first is not None and rep == 0 and rate == rates[0]:
                        save_table(table, save_first)
                for start in STARTS:
                    row = run_transfer(task.for_run(system, rate, run_seed), start, table)
                    rows.append({"rep": rep, **row})
                if progress is not None:
                    progress(1)
    from pil.experiments.outputs import sort_runs  # with the other outputs: loaded late

    return sort_runs(rows, systems, "start", STARTS)


def write_transfer(rows: Sequence[Mapping[str, Any]], out: Any, source: str) -> list:
    """``transfer.csv``, ``transfer.md`` and ``transfer.png`` under ``out``."""
    from pil.experiments.outputs import write_small_study

    intro = (
        "The second task (tidying 10 rounds of 4 legs onto spots) from an empty table "
        f"(`scratch`) and from {source} (`table`); same seeds in both."
    )
    return write_small_study(
        rows,
        out,
        "transfer",
        title="Transfer to a second task",
        intro=intro,
        group_by=("rate", "system", "start"),
        metrics=("actions", "gestures", "rejected"),
        figure_group_by=("rate", "run"),
        figure_metric="actions",
        baseline="scratch",
        compare_by="start",
        within=("rate", "system"),
        ylabel="robot actions to tidy 10 rounds",
    )
