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

import csv
import io
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError
from pil.experiments.baseline_equivalence import EQUIVALENCE_COLUMNS as EQ_COLUMNS
from pil.experiments.baseline_equivalence import equivalence_markdown, equivalence_rows
from pil.experiments.baseline_grid import (
    BASELINES,
    CRITERION,
    LEARNERS,
    Score,
    Setting,
    at_edge,
    choose_best,
    default_setting,
    grid,
    pil_references,
    score,
    split_seeds,
)
from pil.experiments.equivalence import ACTION_MARGIN
from pil.experiments.paper import PAPER_RATES, PAPER_REPS
from pil.experiments.report import markdown_table, summary_markdown
from pil.experiments.run_row import ROW_COLUMNS, spec_row
from pil.experiments.stats import compare, csv_columns, describe_tests, measures, pair_family
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


def csv_text(rows: Sequence[Mapping[str, Any]], columns: Sequence[str]) -> str:
    """The rows as CSV text (fixed columns, ``\\n`` line ends: byte-reproducible)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()


def tuning_rows(result: BaselineResult) -> list[dict[str, Any]]:
    """One row per tuning setting: its means and whether it was chosen."""
    out = []
    for learner, found in result.scores.items():
        for s in found:
            out.append(
                {
                    "learner": learner,
                    "setting": s.setting.name,
                    "params": s.setting.describe(),
                    "runs": s.runs,
                    "stuck": s.stuck,
                    "mean_total_actions": round(s.actions, 3),
                    "sd_total_actions": round(s.actions_sd, 3),
                    "mean_total_gestures": round(s.gestures, 3),
                    "chosen": s is result.best[learner],
                }
            )
    return out


def _cell(r: Mapping[str, Any]) -> str:
    if math.isnan(r["p_holm"]):
        return f"{r['mean_diff']:+.1f} (no spread)"
    star = " *" if r["p_holm"] < 0.05 else ""
    return (
        f"{r['mean_diff']:+.1f} [{r['ci_low']:+.1f}, {r['ci_high']:+.1f}] p={r['p_holm']:.2g}{star}"
    )


def _matrix(tests: Sequence[Mapping[str, Any]], measure: str, rates: Sequence[float]) -> str:
    cells: dict[tuple[str, str], dict[float, str]] = {}
    for r in tests:
        if r["measure"] == measure and r["test"] == "paired t":
            cells.setdefault((r["system_a"], r["system_b"]), {})[float(r["rate"])] = _cell(r)
    body = [[a, b, *(row.get(rate, "") for rate in rates)] for (a, b), row in cells.items()]
    return markdown_table(["a", "b", *(f"{rate:g}" for rate in rates)], body)


def summary_text(result: BaselineResult, config: BaselineConfig, tests: Sequence[Any]) -> str:
    """``summary.md``: tuning, the table's means, and the paired tests against PIL."""
    rates = sorted({float(r["rate"]) for r in result.rows})
    tuning_body = [
        [
            r["learner"],
            r["setting"] + (" (chosen)" if r["chosen"] else ""),
            r["runs"],
            r["stuck"],
            f"{r['mean_total_actions']:.1f} ± {r['sd_total_actions']:.1f}",
            f"{r['mean_total_gestures']:.1f}",
        ]
        for r in tuning_rows(result)
    ]
    chosen = ", ".join(f"{k}: {v.setting.name}" for k, v in result.best.items())
    parts = [
        "# Baselines: tuned on held-out seeds, paired against PIL under every exploration rule",
        "",
        f"Rates {', '.join(f'{r:g}' for r in config.rates)}; master seed {config.seed}; "
        f"parameters {dict(config.params or {}) or 'the defaults'}. Tuning: every setting on "
        f"{config.tuning_reps} held-out repetitions (seed branch disjoint from the evaluation "
        f"seeds, checked); evaluation: {config.reps} repetitions, the seeds of "
        f"`robin-pil study --seed {config.seed}`. Best setting per learner = fewest mean "
        f"`{CRITERION}` over all tuning runs (ties: fewer gestures). Chosen: {chosen}.",
        "",
        "`+memory`: the within-step memory on (`step_memory=on`, `pil.step_memory`: a refused "
        "action is not tried again in the step until all five were refused). `default`: the "
        "registry's defaults (PIL memory off, the baselines' on).",
        "",
        "## Tuning (held-out seeds), mean ± sd over rates and repetitions",
        "",
        "`stuck`: runs with a step that found no approved action within "
        "`max_actions_per_gesture` actions (without the memory a greedy learner can keep "
        "choosing refused actions); each counts in the mean at the cap (every scripted "
        "gesture × `max_actions_per_gesture`): the means are over every run. " + _edges(result),
        "",
        markdown_table(
            ["learner", "setting", "runs", "stuck", "total actions", "total gestures"], tuning_body
        ),
        "",
        "## Evaluation seeds: mean ± sd per variant and rate",
        "",
        summary_markdown(result.rows, ("rate", "variant"), ("total_actions", "total_gestures")),
        "",
        "## Paired tests against PIL",
        "",
        describe_tests(tests)
        + " (In this table Holm's family is one test and measure of one pair over the "
        "rates, declared, so what else ran never changes it.) Cells: a − b (baseline − PIL, "
        "negative: the baseline needs "
        "fewer; the last rows: with − without the memory, tuned − default), 95 % CI, "
        "Holm-adjusted paired-t p; Wilcoxon in `tests.csv`.",
        "",
        "### Total actions",
        "",
        _matrix(tests, "total_actions", rates),
        "",
        "### Total gestures",
        "",
        _matrix(tests, "total_gestures", rates),
        "",
        f"## Equivalence (TOST, ±{ACTION_MARGIN:g} total actions)",
        "",
        "A non-significant difference is not equivalence. Two one-sided paired t-tests "
        "(`statsmodels` `ttost_paired`) per rate and averaged over the rates (each "
        "repetition's mean); `equivalent` when both reject at 0.05 (the 90 % CI inside the "
        'margin). Only those rows may be read as "as costly as" (`equivalence.csv`).',
        "",
        equivalence_markdown(equivalence_rows(result.rows)),
    ]
    return "\n".join(parts) + "\n"


def _edges(result: BaselineResult) -> str:
    """A sentence naming any chosen value at the edge of its grid."""
    notes = []
    for learner, best in result.best.items():
        edge = at_edge(best.setting, grid(learner))
        if edge:
            notes.append(f"{learner} ({', '.join(edge)})")
    if not notes:
        return "Every chosen value lies inside its grid."
    return (
        "Chosen values at the edge of their grid: "
        + "; ".join(notes)
        + " (epsilon = 0 and step size 1 are the ends of the valid ranges)."
    )


def write_outputs(result: BaselineResult, config: BaselineConfig, out: str | Path) -> list[Path]:
    """Write ``baselines.csv``, ``tuning.csv``, ``tests.csv`` and ``summary.md`` to ``out``."""
    out = Path(out)
    tests = baseline_tests(result.rows)
    return [
        write_text_atomic(out / "baselines.csv", csv_text(result.rows, RUN_COLUMNS)),
        write_text_atomic(out / "tuning.csv", csv_text(tuning_rows(result), TUNING_COLUMNS)),
        write_text_atomic(out / "tests.csv", csv_text(tests, csv_columns(("rate",)))),
        write_text_atomic(
            out / "equivalence.csv", csv_text(equivalence_rows(result.rows), EQ_COLUMNS)
        ),
        write_text_atomic(out / "summary.md", summary_text(result, config, tests)),
    ]
