"""Held-out accuracy per factor of a performance: pose jitter, hand height, skin tone.

Each level of each factor (:data:`FACTORS`) renders ``samples`` samples of the held-out split
(light never trained on) with that one field of the sample fixed (e.g. every hand 12 cm
higher than its place) and the others drawn as usual; the gesture model reads them as an
episode would (both eyes fused, discarded below the threshold). Per level: hands found
(either eye), seven-class accuracy (a discard or no hand counts as wrong) with its 95 %
Wilson interval, and instruction gestures read right in context (d). Used by
``bench/bench_vision_factors.py``; the chunks are kept, so a second model is measured on the
same renders without rendering again.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
from statsmodels.stats.proportion import proportion_confint

from robin_sim.vision.build import Job, run_jobs
from robin_sim.vision.classifier import GestureModel
from robin_sim.vision.dataset import CHUNK, chunks_for, load_split
from robin_sim.vision.train import evaluate

# factor -> (the SampleSpec field it fixes, its levels); 1.0 jitter is a performance's usual
# spread, 2.0 twice that; lift in m above the hand's place; skin on the five-tone scale
FACTORS: dict[str, tuple[str, tuple[float, ...]]] = {
    "pose jitter": ("jitter", (0.0, 1.0, 2.0)),
    "hand height": ("lift", (0.0, 0.06, 0.12)),
    "skin tone": ("skin", (0.0, 1.0, 2.0, 3.0, 4.0)),
}


def chunk_name(field: str, level: float) -> str:
    """File name stem of a level's chunks, e.g. ``factor-lift-0.12``."""
    return f"factor-{field}-{level:g}"


def render_factors(
    folder: Path, seed: int, samples: int, workers: int, progress: Callable[[int], None]
) -> int:
    """Render every level's held-out samples into ``folder`` (existing chunks are kept)."""
    jobs = []
    for field, levels in FACTORS.values():
        for level in levels:
            for k in range(chunks_for(samples)):
                name = chunk_name(field, level)
                if not (folder / f"{name}-{k:04d}.npz").exists():
                    jobs.append(Job("heldout", k, ((field, level),), name))
    progress(CHUNK * (sum(len(v) for _, v in FACTORS.values()) * chunks_for(samples) - len(jobs)))
    return run_jobs(jobs, folder, seed, workers, progress)


def measure_factors(
    folder: Path, samples: int, model: GestureModel
) -> list[dict[str, float | str]]:
    """One row per factor level (see the module doc)."""
    rows: list[dict[str, float | str]] = []
    for factor, (field, levels) in FACTORS.items():
        for level in levels:
            split = load_split(folder, chunk_name(field, level), samples)
            evaluation = evaluate(model, split)
            right = int(np.trace(evaluation.confusion[:, :-1]))
            low, high = proportion_confint(right, evaluation.samples, method="wilson")
            found = np.zeros(samples, bool)
            np.logical_or.at(found, split["sample"], split["found"])
            rows.append(
                {
                    "factor": factor,
                    "level": level,
                    "samples": evaluation.samples,
                    "hands_found": float(found.mean()),
                    "accuracy": evaluation.accuracy,
                    "ci_low": float(low),
                    "ci_high": float(high),
                    "in_context": evaluation.detection_rate(),
                }
            )
    return rows


def table(rows: list[dict[str, float | str]]) -> list[str]:
    """Markdown lines of :func:`measure_factors`' rows."""
    lines = [
        "| factor | level | samples | hands found | accuracy (7 classes) [95 % CI] | "
        "in context (d) |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['factor']} | {r['level']:g} | {r['samples']} | {r['hands_found']:.1%} | "
            f"{r['accuracy']:.1%} [{r['ci_low']:.1%}, {r['ci_high']:.1%}] | "
            f"{r['in_context']:.1%} |"
        )
    return lines
