"""Measured detection rate per camera condition, and what it costs PIL.

For each condition of a grid (light scale x pixel noise) the data-set renderer renders
``samples`` performances (every skin tone, the hand wherever gestures are made) under exactly
that condition; the shipped gesture model reads them in context, which gives the condition's
measured error model (``measured-<tag>.json``: the detection rate d, discards, misreadings, and
the thumbs' confusion). The learner-only study then runs PIL with each measured error model
(``measured:FILE``) and, as the reference, with the paper's dice at d = 0.4 .. 1.0. Outputs:
``conditions.csv``, ``conditions.md`` and ``conditions.png`` (PIL's gestures and actions
against d: the dice curve and the measured conditions), ``conditions_runs.csv`` (PIL's run
per measured condition and repetition) and ``tests.csv``: each condition against the first one
studied (the brightest, noiseless by default) on PIL's gestures and actions, paired by
repetition (every condition's study uses the same master seed, so repetition ``r`` has the same
handover order; paired t and Wilcoxon with Holm, :mod:`pil.experiments.stats`).
"""

from __future__ import annotations

import csv
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pil.task.detector import EXACT
from robin_sim.vision.build import Job, run_jobs
from robin_sim.vision.classifier import GestureModel, load_shipped
from robin_sim.vision.dataset import CHUNK, chunk_ready, chunks_for, load_split
from robin_sim.vision.report import measured
from robin_sim.vision.train import evaluate

LIGHTING: tuple[float, ...] = (1.0, 0.5, 0.25, 0.12)
NOISE: tuple[float, ...] = (0.0, 12.0, 24.0)
DICE_RATES: tuple[float, ...] = (0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
MIN_STUDY_RATE = 0.25  # below it the study is not run for a condition


def tag(lighting: float, noise: float) -> str:
    """File tag of a condition, e.g. ``l0.25-n12``."""
    return f"l{lighting:g}-n{noise:g}"


def render_conditions(
    out: Path,
    seed: int,
    samples: int,
    workers: int,
    conditions: list[tuple[float, float]],
    progress: Callable[[int], None] = lambda n: None,
) -> None:
    """Render each condition's samples (resumable: existing chunk files are kept)."""
    folder = out / "chunks"
    jobs = []
    for lighting, noise in conditions:
        for k in range(chunks_for(samples)):
            name = f"sweep-{tag(lighting, noise)}"
            if chunk_ready(folder / f"{name}-{k:04d}.npz", seed):
                progress(CHUNK)
                continue
            overrides = (("lighting", lighting), ("camera_noise", noise))
            jobs.append(Job("sweep", k, overrides, name))
    run_jobs(jobs, folder, seed, workers, progress)


def measure(
    out: Path, samples: int, conditions: list[tuple[float, float]], model: GestureModel
) -> list[dict[str, object]]:
    """Per condition: its measured error model file and headline figures."""
    rows = []
    for lighting, noise in conditions:
        split = load_split(out / "chunks", f"sweep-{tag(lighting, noise)}", samples)
        evaluation = evaluate(model, split)
        path = out / f"measured-{tag(lighting, noise)}.json"
        errors = measured(evaluation, f"lighting {lighting:g}, camera noise {noise:g}")
        path.write_text(json.dumps(errors, indent=2) + "\n")
        thumbs, gestures = evaluation.feedback, evaluation.gestures
        discarded = float(gestures[:, -1].sum() / gestures.sum())
        misread_thumbs = float((thumbs[0, 1] + thumbs[1, 0]) / max(thumbs.sum(), 1))
        rows.append(
            {
                "lighting": lighting,
                "camera_noise": noise,
                "detection_rate": round(evaluation.detection_rate(), 4),
                "discarded": round(discarded, 4),
                "feedback_misread": round(misread_thumbs, 4),
                "hands_found": round(float(split["found"].mean()), 4),
                "measured_file": str(path),
            }
        )
    return rows


def study_costs(
    rows: list[dict[str, object]], reps: int, seed: int
) -> tuple[list[dict[str, object]], list[dict[str, float]], list[dict[str, object]]]:
    """PIL's mean gestures and actions per measured condition and along the dice curve, and
    the measured conditions' runs (a ``condition`` column added)."""
    from pil.experiments.study import StudyConfig, run_study

    measured_runs: list[dict[str, object]] = []

    def pil_means(
        rate: float, detector: str, condition: str = ""
    ) -> tuple[float, float, float, float]:
        config = StudyConfig(
            rates=(rate,), reps=reps, seed=seed, systems=("pil",), params={"detector": detector}
        )
        runs = run_study(config)
        if condition:
            measured_runs.extend({"condition": condition, **r} for r in runs)
        g = [float(r["gestures"]) for r in runs]
        a = [float(r["actions"]) for r in runs]
        return (
            float(np.mean(g)),
            float(np.std(g, ddof=1)),
            float(np.mean(a)),
            float(np.std(a, ddof=1)),
        )

    for row in rows:
        d = _number(row["detection_rate"])
        if d < MIN_STUDY_RATE:  # the person would repeat gestures forever
            row.update(
                pil_gestures=None, pil_gestures_sd=None, pil_actions=None, pil_actions_sd=None
            )
            continue
        g, gs, a, asd = pil_means(
            round(d, 4),
            f"measured:{row['measured_file']}",
            tag(_number(row["lighting"]), _number(row["camera_noise"])),
        )
        row.update(
            pil_gestures=round(g, 1),
            pil_gestures_sd=round(gs, 1),
            pil_actions=round(a, 1),
            pil_actions_sd=round(asd, 1),
        )
    dice = []
    for rate in DICE_RATES:
        g, gs, a, asd = pil_means(rate, EXACT)
        dice.append(
            {"rate": rate, "gestures": g, "gestures_sd": gs, "actions": a, "actions_sd": asd}
        )
    return rows, dice, measured_runs


def condition_tests(runs: list[dict[str, object]]) -> list[dict[str, object]]:
    """Each measured condition against the first one, paired by repetition (``tests.csv``)."""
    from pil.experiments.stats import compare

    if len({r["condition"] for r in runs}) < 2:
        return []
    return compare(
        runs,
        str(runs[0]["condition"]),
        compare_by="condition",
        within=(),
        metrics=("gestures", "actions"),
        pair_by=("rep", "seed"),
    )


def _number(value: object) -> float:
    """A row's numeric cell (a number, or its text) as a float."""
    if not isinstance(value, int | float | str):
        raise TypeError(f"expected a number, got {value!r}")
    return float(value)


def _cost(row: dict[str, object], key: str) -> str:
    mean = row[f"pil_{key}"]
    return "not run (d too low)" if mean is None else f"{mean} ± {row[f'pil_{key}_sd']}"


def write_outputs(
    out: Path,
    rows: list[dict[str, object]],
    dice: list[dict[str, float]],
    reps: int,
    runs: list[dict[str, object]] | None = None,
) -> list[Path]:
    """conditions.csv, conditions.md and conditions.png; with ``runs`` (the measured
    conditions' runs of :func:`study_costs`) also conditions_runs.csv and tests.csv."""
    from pil.experiments.plotting import pyplot
    from pil.experiments.stats import csv_columns, describe_tests, tests_markdown
    from pil.experiments.study import csv_text

    plt = pyplot()

    table = out / "conditions.csv"
    with table.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "# Measured detection rate per camera condition, and PIL's costs",
        "",
        f"PIL, learner only, 10 tables, {reps} repetitions per point (mean ± sd).",
        "",
        "| lighting | camera noise | hands found | d (measured) | discarded | thumbs misread | "
        "PIL gestures | PIL actions |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['lighting']:g} | {r['camera_noise']:g} | {r['hands_found']:.1%} | "
            f"{r['detection_rate']:.1%} | {r['discarded']:.1%} | {r['feedback_misread']:.1%} | "
            f"{_cost(r, 'gestures')} | {_cost(r, 'actions')} |"
        )
    lines += [
        "",
        "Dice (the paper's exact detector) at the same number of repetitions:",
        "",
        "| d | PIL gestures | PIL actions |",
        "|---|---|---|",
    ]
    for point in dice:
        lines.append(
            f"| {point['rate']:g} | {point['gestures']:.1f} ± {point['gestures_sd']:.1f} | "
            f"{point['actions']:.1f} ± {point['actions_sd']:.1f} |"
        )
    extra: list[Path] = []
    tests = condition_tests(runs or [])
    if runs:
        extra.append(out / "conditions_runs.csv")
        extra[-1].write_text(csv_text(runs, list(runs[0])))
    if tests:
        extra.append(out / "tests.csv")
        extra[-1].write_text(csv_text(tests, csv_columns(())))
        lines += [
            "",
            f"## Each condition against {tests[0]['system_a']} (PIL, test tables)",
            "",
            describe_tests(tests) + " All rows in `tests.csv`.",
            "",
            tests_markdown(tests, ()),
        ]
    report = out / "conditions.md"
    report.write_text("\n".join(lines) + "\n")
    figure = out / "conditions.png"
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, key in zip(axes, ("gestures", "actions"), strict=True):
        ax.errorbar(
            [r["rate"] for r in dice],
            [r[key] for r in dice],
            yerr=[r[f"{key}_sd"] for r in dice],
            color="grey",
            marker="o",
            label="dice (paper's detector)",
        )
        for lighting in sorted({_number(r["lighting"]) for r in rows}, reverse=True):
            sel = [r for r in rows if r["lighting"] == lighting and r["pil_gestures"] is not None]
            ax.errorbar(
                [r["detection_rate"] for r in sel],
                [r[f"pil_{key}"] for r in sel],
                yerr=[r[f"pil_{key}_sd"] for r in sel],
                marker="s",
                linestyle="none",
                label=f"cameras, light x{lighting:g}",
            )
            for r in sel:
                ax.annotate(
                    f"n{r['camera_noise']:g}",
                    (r["detection_rate"], r[f"pil_{key}"]),
                    fontsize=7,
                    xytext=(3, 3),
                    textcoords="offset points",
                )
        ax.set_xlabel("gesture detection rate d")
        ax.set_ylabel(f"PIL {key} (10 tables)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("PIL's costs against the detection rate: dice vs measured camera conditions")
    fig.tight_layout()
    fig.savefig(figure, dpi=110)
    plt.close(fig)
    return [table, report, figure, *extra]


def run_conditions(
    out: Path,
    *,
    seed: int = 0,
    samples: int = 336,
    reps: int = 10,
    workers: int = 2,
    lighting: tuple[float, ...] = LIGHTING,
    noise: tuple[float, ...] = NOISE,
    progress: Callable[[int], None] = lambda n: None,
) -> list[Path]:
    """The whole sweep (see the module doc)."""
    conditions = [(lit, n) for lit in lighting for n in noise]
    render_conditions(out, seed, samples, workers, conditions, progress)
    rows = measure(out, samples, conditions, load_shipped())
    rows, dice, runs = study_costs(rows, reps, seed)
    return write_outputs(out, rows, dice, reps, runs)
