"""The baseline table: bandit and TAMER, tuned on held-out seeds, against PIL under each rule.

:func:`run_baselines` runs every setting of :mod:`pil.experiments.baseline_grid` on the tuning
seeds, picks each learner's best (fewest mean total actions), then runs on the evaluation seeds
PIL under every exploration rule (within-step memory off and on) and each baseline at its tuned
setting and at the registry's defaults. :func:`baseline_tests` compares each baseline variant
with every PIL variant (:func:`pil.experiments.stats.compare`: paired t and Wilcoxon, pairing by
``rep`` within each rate), Holm over each test, measure and pair of variants (a declared
family, independent of what else ran); "as costly as" only where TOST
(:mod:`pil.experiments.equivalence`) shows it.
:func:`write_outputs` writes ``baselines.csv`` (the evaluation runs), ``tuning.csv``,
``tests.csv`` and ``summary.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from pil.errors import RobinPilError
from pil.experiments.baseline_grid import (
    BASELINES,
    LEARNERS,
    Score,
    Setting,
    choose_best,
    default_setting,
    grid,
    pil_references,
    score,
    split_seeds,
)
from pil.experiments.paper import PAPER_RATES, PAPER_REPS
from pil.experiments.run_row import ROW_COLUMNS, spec_row
from pil.experiments.stats import compare, measures, pair_family
from pil.task.params import RATE, REPS, SEED
from pil.task.runner import RunnerError
from pil.task.spec import RunSpec, parse_run_spec

RUN_COLUMNS: tuple[str, ...] = ("variant", "setting", "rep", *ROW_COLUMNS)
TUNING_COLUMNS: tuple[str, ...] = (
    "learner",
    "setting",
    "params",
    "runs",
    "stuck",
    "mean_total_actions",
    "sd_total_actions",
    "mean_total_gestures",
    "chosen",
)
METRICS = measures(("total_actions", "total_gestures"))
_TUNED = ("exploration", "step_memory", "epsilon", "epsilon_decay", "step_size")


@dataclass(frozen=True)
class BaselineConfig:
    """What to run: rates, repetitions (evaluation and tuning), master seed, run parameters."""

    rates: tuple[float, ...] = PAPER_RATES
    reps: int = PAPER_REPS
    tuning_reps: int = 10
    seed: int = 0
    params: Mapping[str, Any] | None = None  # e.g. {"tables": 2}
    # the names of the values in messages (e.g. {"reps": "--reps"} from the command line)
    labels: Mapping[str, str] = field(default_factory=dict, compare=False)
    # the runs' spec: params parsed once, here (the learner, rate and seed vary)
    base: RunSpec = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """The edge: rates, repetitions and seed, given as numbers or text, parsed once here."""
        label = self.labels.get
        rates = tuple(RATE.parse(r, label("rate", "detection rate")) for r in self.rates)
        if len(set(rates)) != len(rates) or not rates:
            where = label("rates", "rates")
            raise RobinPilError(f"{where}: give each rate once (at least one), got {self.rates!r}")
        object.__setattr__(self, "rates", rates)
        object.__setattr__(self, "reps", REPS.parse(self.reps, label("reps", "reps")))
        tuning = REPS.parse(self.tuning_reps, label("tuning_reps", "tuning reps"))
        object.__setattr__(self, "tuning_reps", tuning)
        object.__setattr__(self, "seed", SEED.parse(self.seed, label("seed", "seed")))
        for name in self.params or {}:
            if name in _TUNED:
                raise RobinPilError(
                    f"parameter {name!r} is set by the tuning grid and the "
                    f"table; give only others (e.g. tables, discard)"
                )
        base = parse_run_spec(params=self.params, labels=self.labels)
        object.__setattr__(self, "base", base)
        typed = base.values()  # the given parameters as parsed (for the summary)
        object.__setattr__(self, "params", {name: typed[name] for name in self.params or {}})

    def runs(self) -> int:
        """How many runs :func:`run_baselines` makes (at most: equal settings run once)."""
        tuning = sum(len(grid(learner)) for learner in LEARNERS) * self.tuning_reps
        evaluation = (len(pil_references()) + 2 * len(BASELINES)) * self.reps
        return (tuning + evaluation) * len(self.rates)


@dataclass(frozen=True)
class BaselineResult:
    """The evaluation rows, every tuning score, each learner's best, and the seeds."""

    rows: list[dict[str, Any]]
    scores: dict[str, list[Score]]
    best: dict[str, Score]
    tuning_seeds: list[int]
    seeds: list[int]


def _run(
    setting: Setting,
    seeds: Sequence[int],
    base: RunSpec,
    config: BaselineConfig,
    progress: Callable[[int], None] | None,
) -> tuple[list[dict[str, Any]], list[float]]:
    """``setting``'s runs at every rate and seed, and the cap of each stuck run; ``base``
    is the config's parameters, parsed once (the setting's own are typed constants)."""
    spec = base.changed(setting.params)
    rows: list[dict[str, Any]] = []
    caps: list[float] = []
    for rep, seed in enumerate(seeds):
        cache: dict[Any, Any] = {}  # the person's scripts of this seed (no training runs)
        for rate in config.rates:
            run_spec = spec.for_run(setting.learner, rate, seed)
            try:
                row = spec_row(run_spec, cache)
            except RunnerError:  # a step never ended (a memoryless greedy baseline)
                caps.append(_cap(run_spec, cache))
            else:
                rows.append({"setting": setting.describe(), "rep": rep, **row})
            if progress is not None:
                progress(1)
    return rows, caps


def _cap(spec: RunSpec, cache: dict[Any, Any]) -> float:
    """A stuck run's cost in the tuning mean: every scripted gesture (training included)
    times ``max_actions_per_gesture``, the most any run can cost."""
    from pil.task.assemble import assemble

    run = assemble(spec, cache=cache)
    scripted = len(run.person.script) + (
        0 if run.training is None else run.training.stats.scripted_gestures
    )
    return float(scripted * spec.learner.max_actions_per_gesture)


def run_baselines(
    config: BaselineConfig, progress: Callable[[int], None] | None = None
) -> BaselineResult:
    """Tune on the tuning seeds, then run the table on the evaluation seeds."""
    base = config.base  # parsed once, by the config: a bad one failed before any run
    tuning_seeds, seeds = split_seeds(config.seed, config.tuning_reps, config.reps)
    scores: dict[str, list[Score]] = {}
    for learner in LEARNERS:
        scores[learner] = [
            score(s, *_run(s, tuning_seeds, base, config, progress)) for s in grid(learner)
        ]
    best = {learner: choose_best(found) for learner, found in scores.items()}
    variants: list[tuple[str, Setting]] = [(f"pil:{s.name}", s) for s in pil_references()]
    for learner in BASELINES:
        variants += [
            (f"{learner}:tuned", best[learner].setting),
            (f"{learner}:default", default_setting(learner)),
        ]
    rows: list[dict[str, Any]] = []
    done: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for variant, setting in variants:
        key = (setting.learner, setting.describe())
        if key not in done:
            found, capped = _run(setting, seeds, base, config, progress)
            if capped:
                raise RunnerError(
                    f"{variant} ({setting.describe()}): {len(capped)} evaluation runs "
                    "had a step that never ended; the table needs every run"
                )
            done[key] = found
        rows += [{"variant": variant, **r} for r in done[key]]
    return BaselineResult(rows, scores, best, tuning_seeds, seeds)


def _family(result: Mapping[str, Any]) -> tuple[Any, ...]:
    """One test and measure of one pair of variants, over the rates (declared, not built
    from what ran)."""
    return (*pair_family(result), result["measure"])


def baseline_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Each baseline variant against every PIL variant, then PIL with the memory against
    PIL without it (same rule), and each baseline's tuned setting against its default, per
    rate and measure (paired by rep; ``mean_diff`` = baseline - PIL, with - without memory,
    tuned - default); Holm over each declared family, one test and measure of one pair of
    variants over the rates (:func:`pil.experiments.stats.pair_family`): what else ran never
    changes a comparison's p."""
    variants = list(dict.fromkeys(str(r["variant"]) for r in rows))
    pil = [v for v in variants if v.startswith("pil:")]
    results: list[dict[str, Any]] = []
    for variant in variants:
        if variant in pil:
            continue
        subset = [r for r in rows if r["variant"] in (variant, *pil)]
        results += compare(
            subset,
            variant,
            compare_by="variant",
            within=("rate",),
            metrics=METRICS,
            pair_by=("rep",),
            family=_family,
        )
    pairs = [(f"{v}+memory", v) for v in pil if f"{v}+memory" in pil]  # what the memory does
    pairs += [(f"{learner}:tuned", f"{learner}:default") for learner in BASELINES]
    for pair in pairs:
        subset = [r for r in rows if r["variant"] in pair]
        if {str(r["variant"]) for r in subset} == set(pair):
            results += compare(
                subset,
                pair[0],
                compare_by="variant",
                within=("rate",),
                metrics=METRICS,
                pair_by=("rep",),
                family=_family,
            )
    return results
