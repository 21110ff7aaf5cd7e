"""A learner-only run's CSV row: :data:`ROW_COLUMNS` names the cells, :func:`run_row` fills
them in that order (one source for both: a column without a value is a KeyError at once), and
:func:`spec_row` runs a :class:`~pil.task.spec.RunSpec` (any system of
:mod:`pil.task.systems`) to its row.

Counts come from the test run's :class:`~pil.task.counting.RunStats` by name, ``train_*`` ones
from the training run's; ``total_*`` add the two, as the paper does; then every parameter of
:data:`pil.task.parts.DEFAULT_VALUES` as the run used it.
"""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping
from typing import Any

from pil.task.assemble import assemble
from pil.task.counting import RunStats
from pil.task.parts import DEFAULT_VALUES
from pil.task.spec import RunSpec

TRAIN = "train_"  # prefix of the training run's counts
TOTAL = "total_"  # prefix of training + test counts

ROW_COLUMNS: tuple[str, ...] = (
    "system",
    "rate",
    "seed",
    "scenario",
    "legs",
    "handovers",
    "gestures",
    "actions",
    "train_gestures",
    "train_actions",
    "total_gestures",
    "total_actions",
    "corrections",
    "repeats",
    "misdetections",
    "discarded",
    "rejected",
    "exploited",
    "anticipated",
    "anticipated_ok",
    "scripted_gestures",
    "train_corrections",
    "train_repeats",
    "train_rejected",
    *DEFAULT_VALUES,
)


def run_row(
    run: Mapping[str, Any], test: RunStats, train: RunStats, params: Mapping[str, Any]
) -> dict[str, Any]:
    """The row of :data:`ROW_COLUMNS`: ``run`` gives system, rate, seed and scenario (name),
    ``params`` every parameter's value; the rest are counts of ``test`` and ``train``."""
    given = {**run, **params}

    def cell(column: str) -> Any:
        if column in given:
            return given[column]
        if column.startswith(TOTAL):
            name = column.removeprefix(TOTAL)
            return getattr(train, name) + getattr(test, name)
        if column.startswith(TRAIN):
            return getattr(train, column.removeprefix(TRAIN))
        return getattr(test, column)

    return {column: cell(column) for column in ROW_COLUMNS}


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
