"""``robin-pil study --seeds K``: K independent studies (master seeds seed .. seed+K-1, each
the whole configured study in ``OUT/seed_<n>/``) and their headlines over seeds.

``OUT/summary.md`` reports the paper's eight training figures as the mean over seeds with a
95 % interval (:func:`pil.experiments.stats.mean_ci`) beside the paper's value, how often the
paper's claim holds, every paired comparison's mean difference over seeds and, with ``pil``
and ``proactive``, the gestures saved and actions wasted. ``OUT/seeds.csv`` holds each seed's
eight figures, ``OUT/seeds_tests.csv`` the comparisons over seeds. A seed folder that already
holds a finished study with the same settings is read back, not re-run (resumable); an
unfinished one resumes from its finished repetitions (``reps.jsonl``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.experiments.over_seeds import (
    check_seed_count,
    check_seed_folders,
    interval,
    over_seeds_columns,
    over_seeds_markdown,
    run_seeds,
    seed_folder,
    tests_over_seeds,
)
from pil.experiments.paper import PAPER_TRAINING
from pil.experiments.paper_comparison import training_figures, worst_difference
from pil.experiments.proactive_report import proactive_figures
from pil.experiments.rep_journal import RepJournal
from pil.experiments.report import Row, load_rows, markdown_table
from pil.experiments.stats import mean_ci
from pil.experiments.study import (
    StudyConfig,
    csv_text,
    journal_settings,
    run_study,
    write_outputs,
)
from pil.experiments.study_tests import claim_rows, claim_verdicts, discard_reading
from pil.file_names import RUNS_NAME

SEEDS_COLUMNS: tuple[str, ...] = ("seed", "rate", "measure", "ours", "paper", "diff_percent")
FIGURES: tuple[str, ...] = ("gestures", "actions")


def settings(config: StudyConfig) -> dict[str, Any]:
    """What makes two seed folders the same study (all but the seed)."""
    values, scenario = config.base.values(), config.base.scenario
    return {
        "study": "study",
        "rates": list(config.rates),
        "reps": config.reps,
        "systems": list(config.systems),
        "scenario": scenario.name,
        "params": values,
    }


def seeds_of(config: StudyConfig, count: int) -> list[int]:
    """The master seeds of ``count`` studies from ``config.seed`` on."""
    return list(range(config.seed, config.seed + check_seed_count(count)))


def check_seeds(config: StudyConfig, count: int, out: Path) -> None:
    """Refuse a bad count or a seed folder of another study, before anything runs."""
    check_seed_folders(out, seeds_of(config, count), settings(config))


def figure_rows(seed: int, rows: Sequence[Row]) -> list[dict[str, Any]]:
    """The seed's rows of ``seeds.csv``: its eight training figures beside the paper's."""
    out = []
    for rate, fig in training_figures(rows).items():
        if rate not in PAPER_TRAINING:
            continue
        for i, name in enumerate(FIGURES):
            paper = PAPER_TRAINING[rate][i]
            diff = 100.0 * (fig[name] - paper) / paper
            out.append(
                {
                    "seed": seed,
                    "rate": rate,
                    "measure": name,
                    "ours": fig[name],
                    "paper": paper,
                    "diff_percent": diff,
                }
            )
    return out


def _figures_markdown(
    rows: Sequence[Mapping[str, Any]], by_seed: Mapping[int, Sequence[Row]]
) -> list[str]:
    body, means, inside = [], [], 0
    for rate in sorted({r["rate"] for r in rows}):
        for name in FIGURES:
            mine = [r for r in rows if r["rate"] == rate and r["measure"] == name]
            paper = mine[0]["paper"]
            ours = mean_ci([r["ours"] for r in mine])
            diff = mean_ci([r["diff_percent"] for r in mine])
            means.append(abs(diff[0]))
            inside += ours[1] <= paper <= ours[2]
            body.append(
                [
                    f"{rate * 100:.0f} %",
                    name,
                    interval(*ours),
                    paper,
                    interval(*diff, spec="+.1f") + " %",
                    f"{min(r['diff_percent'] for r in mine):+.1f} / "
                    f"{max(r['diff_percent'] for r in mine):+.1f} %",
                ]
            )
    worst = [worst_difference(training_figures(rows)) for rows in by_seed.values()]
    within = sum(1 for w in worst if w <= 5.0)
    header = [
        "rate",
        "figure",
        "ours: mean over seeds [95 % CI]",
        "paper",
        "difference [95 % CI]",
        "seeds' lowest / highest",
    ]
    return [
        markdown_table(header, body),
        "",
        f"Worst |difference| of a seed: {min(worst):.1f} to {max(worst):.1f} % (mean "
        f"{interval(*mean_ci(worst))} %); all eight within 5 % in {within} of {len(worst)} "
        f"seeds. Of the means over seeds the largest |difference| is {max(means):.1f} %; the "
        f"paper's value lies inside our 95 % interval for {inside} of {len(body)} figures.",
    ]


def _labelled(tests: Sequence[Row], discarded: str) -> list[Row]:
    """``tests`` with the study's own readings naming its discard reading, as the claim
    section of each seed's summary does."""
    return [
        {**t, "reading": f"{t['reading']}; discarded {discarded}"}
        if ";" not in str(t["reading"])
        else t
        for t in tests
    ]


def _claim_markdown(tests_by_seed: Mapping[int, Sequence[Row]], discarded: str) -> list[str]:
    tests_by_seed = {s: _labelled(t, discarded) for s, t in tests_by_seed.items()}
    over = tests_over_seeds({s: claim_rows(t) for s, t in tests_by_seed.items()})
    verdicts = {seed: claim_verdicts(tests) for seed, tests in tests_by_seed.items()}
    readings = sorted({r for v in verdicts.values() for r in v})
    if not readings:
        return []
    lines = [
        "| reading | seeds where it holds in full | comparisons held (all seeds) |",
        "|---|---|---|",
    ]
    for reading in readings:
        found = [v[reading] for v in verdicts.values() if reading in v]
        full = sum(1 for held, tried in found if held == tried)
        lines.append(
            f"| {reading} | {full} of {len(found)} | "
            f"{sum(h for h, _ in found)} of {sum(t for _, t in found)} |"
        )
    return [
        "",
        "## The paper's claim over seeds",
        "",
        "Per seed, a comparison holds when PIL needs more with Holm-adjusted p < 0.05 in "
        "both the paired t-test and the Wilcoxon test (each seed's summary.md).",
        "",
        *lines,
        "",
        over_seeds_markdown(over),
    ]


def _proactive_markdown(
    by_seed: Mapping[int, Sequence[Row]], tests_by_seed: Mapping[int, Sequence[Row]]
) -> list[str]:
    figures = {s: proactive_figures(rows, tests_by_seed[s]) for s, rows in by_seed.items()}
    if not all(figures.values()):
        return []
    body = []
    for i, entry in enumerate(next(iter(figures.values()))):
        per = [f[i] for f in figures.values()]
        cells = [f"{entry['rate']:g}"]
        for name in ("saved", "wasted", "pil_gestures", "gestures"):
            cells.append(interval(*mean_ci([e[f"{name}_mean"] for e in per])))
        cells.append(f"{sum(1 for e in per if e['p_gestures'] < 0.05)} of {len(per)}")
        cells.append(interval(*mean_ci([e["pil_actions_mean"] - e["actions_mean"] for e in per])))
        cells.append(f"{sum(1 for e in per if e['p_actions'] < 0.05)} of {len(per)}")
        body.append(cells)
    table = markdown_table(
        [
            "rate",
            "gestures saved",
            "actions wasted",
            "gestures pil",
            "gestures proactive",
            "seeds: gestures differ (Holm p < 0.05)",
            "actions pil − proactive",
            "seeds: actions differ",
        ],
        body,
    )
    return [
        "",
        "## Proactive vs reactive PIL over seeds",
        "",
        "Each seed's mean per run (test tables), then the mean over seeds [95 % CI].",
        "",
        table,
    ]


def run_study_seeds(
    config: StudyConfig,
    count: int,
    out: str | Path,
    progress: Callable[[int], None] | None = None,
) -> list[Path]:
    """Run (or resume) ``count`` studies and write the over-seeds outputs; their paths."""
    out = Path(out)
    seeds = seeds_of(config, count)

    def one(seed: int) -> StudyConfig:
        return config.for_seed(seed)

    by_seed = run_seeds(
        out,
        seeds,
        settings(config),
        RUNS_NAME,
        lambda seed: run_study(
            one(seed), progress, RepJournal(seed_folder(out, seed), journal_settings(one(seed)))
        ),
        lambda seed, rows, folder: write_outputs(rows, one(seed), folder),
        skipped=(lambda _seed: progress(config.runs())) if progress else None,
    )
    tests_by_seed: dict[int, Sequence[Row]] = {}
    for seed in seeds:
        path = seed_folder(out, seed) / "tests.csv"
        tests_by_seed[seed] = load_rows(path) if path.is_file() else []
    figures = [r for seed, rows in by_seed.items() for r in figure_rows(seed, rows)]
    over = tests_over_seeds(tests_by_seed)
    first, last = seeds[0], seeds[-1]
    discard = discard_reading(config.base.detector.repeat_discarded)
    parts = [
        f"# PIL study over {len(seeds)} seeds",
        "",
        f"Master seeds {first}-{last}, each the whole study (rates "
        f"{', '.join(f'{r:g}' for r in config.rates)}; {config.reps} repetitions; systems "
        f"{', '.join(config.systems)}; discarded gestures {discard}) in `seed_<n>/` with its "
        "own runs.csv, tests.csv and summary.md. Intervals: 95 % t-intervals over the seeds' "
        "means (the seeds are independent studies).",
    ]
    if figures:
        parts += [
            "",
            "## The paper's eight training figures over seeds",
            "",
            *_figures_markdown(figures, by_seed),
        ]
    parts += _claim_markdown(tests_by_seed, discard)
    parts += _proactive_markdown(by_seed, tests_by_seed)
    if over:
        parts += [
            "",
            "## Every paired comparison over seeds",
            "",
            "PIL against each other system; the seeds' paired-t mean differences.",
            "",
            over_seeds_markdown(over),
        ]
    written = []
    if figures:
        written.append(write_text_atomic(out / "seeds.csv", csv_text(figures, SEEDS_COLUMNS)))
    if over:
        written.append(
            write_text_atomic(out / "seeds_tests.csv", csv_text(over, over_seeds_columns()))
        )
    written.append(write_text_atomic(out / "summary.md", "\n".join(parts) + "\n"))
    return written
