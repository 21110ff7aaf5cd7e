"""The appearance study, start to end: check and plan it (nothing runs), run what is left,
write the files."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

from pil.errors import RobinPilError
from pil.task.params import ASSEMBLY, REPS, SEED
from robin_sim.appearance.people import AppearancePeople
from robin_sim.appearance.report import write_appearance
from robin_sim.appearance.runs import AppearanceRun, plan_runs, run_all


@dataclass(frozen=True, slots=True)
class AppearancePlan:
    """A checked study: its people, repetitions and every run."""

    people: AppearancePeople
    reps: int
    runs: tuple[AppearanceRun, ...]


def plan_study(
    people: AppearancePeople,
    *,
    reps: int,
    seed: int,
    tables: int | None = None,
    persons: list[str] | None = None,
) -> AppearancePlan:
    """Check the options (``tables`` / ``persons`` override the people file's) and list every
    run; bad input raises one :class:`RobinPilError` naming it."""
    from pil.experiments.study import rep_seeds

    reps = REPS.parse(reps, "--reps")
    seed = SEED.parse(seed, "--seed")
    if persons:
        people = people.only(persons)
    if tables is not None:
        people = replace(people, tables=ASSEMBLY["tables"].required().parse(tables, "--tables"))
    if not people.people:
        raise RobinPilError("the appearance study has no people")
    return AppearancePlan(people, reps, tuple(plan_runs(people, reps, rep_seeds(seed, reps))))


def run_study(
    plan: AppearancePlan,
    out: Path,
    *,
    workers: int = 2,
    progress: Callable[[int], object] = lambda n: None,
) -> list[Path]:
    """Run what is left of ``plan`` into ``out`` (resumable) and write the study's files."""
    results = run_all(list(plan.runs), out, workers, progress)
    return write_appearance(results, out, plan.reps, plan.people.tables)
