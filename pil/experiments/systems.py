"""The study's systems (the paper's five, section IV-B, and baselines) and :func:`spec_row`.

* ``pil``: Proactive Incremental Learning from scratch, with correction, on the test tables.
* ``c1``: pre-trained at the test rate d, with correction.
* ``c2``: pre-trained at 100 %, with correction.
* ``c3``: pre-trained at d, manual repetition (the person repeats a misread gesture).
* ``c4``: pre-trained at 100 %, manual repetition.
* ``proactive`` (ours): ``pil`` that acts on the likely next state before its gesture
  (:mod:`pil.anticipation`); ``pil-halve`` (ours): a not-OK halves the refused count.
* ``bandit``, ``tamer``: the baselines of :mod:`pil.agents`, from scratch, same person, detector
  and counting (they act on the detected state as it is: no correction).

Pre-training is a PIL run (with correction) on ``training_tables`` tables (5 x 4 = 20
handovers, each handover type exactly twice). Its gestures and actions are reported apart
(``train_gestures``, ``train_actions``) and added to the totals, as the paper does. The learner
keeps learning during the test. A run's sub-seeds (handover order, detector, learner, person)
derive from ``seed`` alone, not from the system or the rate, so all systems of one repetition
face the same handover order and detector deck (common random numbers); c1 and c3 therefore
share one training run, and c2 and c4 another.
"""

from __future__ import annotations

from collections.abc import MutableMapping
from typing import Any

from pil.experiments.run_row import ROW_COLUMNS, run_row
from pil.task.assemble import Training, assemble
from pil.task.parts import DEFAULT_VALUES, derive_seeds, resolve_scenario
from pil.task.runner import RunStats
from pil.task.spec import RunSpec
from pil.task.systems import PAPER_SYSTEMS, SYSTEM_SPECS, SYSTEMS, SystemSpec, check_system

__all__ = [
    "DEFAULT_VALUES",
    "PAPER_SYSTEMS",
    "ROW_COLUMNS",
    "SYSTEMS",
    "SYSTEM_SPECS",
    "SystemSpec",
    "Training",
    "check_system",
    "derive_seeds",
    "resolve_scenario",
    "spec_row",
]


def spec_row(spec: RunSpec, cache: MutableMapping[Any, Any] | None = None) -> dict[str, Any]:
    """One learner-only run of ``spec`` as a flat CSV row (:data:`ROW_COLUMNS`).

    ``cache`` (a dict) lets a study reuse what the systems of one repetition share (training
    runs, the person's scripts); share it only between specs that differ in system and rate.
    Results are the same with or without it.
    """
    run = assemble(spec, cache=cache)
    stats = run.run()
    train = RunStats() if run.training is None else run.training.stats
    cells = {
        "system": spec.system,
        "rate": spec.rate,
        "seed": spec.seed,
        "scenario": spec.scenario.name,
    }
    return run_row(cells, stats, train, spec.effective().values())
