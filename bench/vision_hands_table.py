"""The capsule-hand against articulated-hand eye-camera table, from two results files.

Run: ``python bench/vision_hands_table.py [--results bench/results/vision_hands]``. Reads
``capsule.csv`` and ``articulated.csv`` (``bench/bench_vision_hands.py``, one row per
held-out sample), pairs the samples (same seed and index: the same place, light, skin, class
and camera; only the hand differs), and writes ``table.md`` beside them and into
``docs/vision.md`` between its ``vision-hands`` markers: per factor level (the gesture shown,
the place, light, skin tone and pose jitter) the samples, each hand's seven-class accuracy
(pooled over the seeds; in brackets the lowest and highest seed), the paired difference with
its 95 % interval, and McNemar's exact test (statsmodels), Holm adjusted within each factor.
Where ``previous.csv`` is there too (the articulated hand read by the model shipped before,
on the same samples), the same table of the previous model against ``articulated.csv``'s is
written to ``models.md`` and between the docs' ``vision-models`` markers.
"""

from __future__ import annotations

import argparse
import csv
from collections import defaultdict
from pathlib import Path

import numpy as np
from statsmodels.stats.contingency_tables import mcnemar
from statsmodels.stats.multitest import multipletests

FACTORS = ("all", "shown", "place", "light", "skin tone", "pose jitter")
BEGIN, END = "<!-- vision-hands table: begin -->", "<!-- vision-hands table: end -->"
MODELS_BEGIN = "<!-- vision-models table: begin -->"
MODELS_END = "<!-- vision-models table: end -->"
HANDS = ("capsule hand", "articulated hand")
MODELS = ("previous model", "this model")
DOCS = Path(__file__).resolve().parents[1] / "docs" / "vision.md"


def load(path: Path) -> dict[tuple[int, int], dict[str, str]]:
    """Rows by (seed, sample)."""
    with path.open() as handle:
        return {(int(r["seed"]), int(r["sample"])): r for r in csv.DictReader(handle)}


def _per_seed(rows: list[tuple[dict[str, str], dict[str, str]]], side: int) -> str:
    by_seed: dict[str, list[int]] = defaultdict(list)
    for pair in rows:
        by_seed[pair[side]["seed"]].append(int(pair[side]["right"]))
    rates = [float(np.mean(v)) for v in by_seed.values()]
    return f"{min(rates):.0%}-{max(rates):.0%}"


def table(capsule: Path, articulated: Path, sides: tuple[str, str] = HANDS) -> list[str]:
    """Markdown lines (see the module doc); ``sides`` names the two files' columns."""
    a, b = load(capsule), load(articulated)
    keys = sorted(set(a) & set(b))
    seeds = sorted({k[0] for k in keys})
    lines = [
        f"Held-out split (light never trained on), seeds {', '.join(map(str, seeds))}, "
        f"{len(keys)} paired samples; a discard or a missed hand counts as wrong.",
        "",
        f"| factor | level | samples | {sides[0]} [seeds] | {sides[1]} [seeds] | "
        "difference [95 % CI] | McNemar p (Holm) |",
        "|---|---|---|---|---|---|---|",
    ]
    for factor in FACTORS:
        groups: dict[str, list[tuple[dict[str, str], dict[str, str]]]] = defaultdict(list)
        for k in keys:
            level = "all" if factor == "all" else a[k][factor]
            groups[level].append((a[k], b[k]))
        cells, pvalues = [], []
        for level in sorted(groups):
            pairs = groups[level]
            x = np.array([int(p[0]["right"]) for p in pairs])
            y = np.array([int(p[1]["right"]) for p in pairs])
            n = len(pairs)
            only_a, only_b = int(np.sum((x == 1) & (y == 0))), int(np.sum((x == 0) & (y == 1)))
            both = int(np.sum((x == 1) & (y == 1)))
            test = mcnemar([[both, only_a], [only_b, n - both - only_a - only_b]], exact=True)
            diff = (only_b - only_a) / n
            se = np.sqrt(max(only_a + only_b - (only_b - only_a) ** 2 / n, 0.0)) / n
            cells.append((level, n, x.mean(), y.mean(), diff, se, pairs))
            pvalues.append(float(test.pvalue))
        adjusted = multipletests(pvalues, method="holm")[1] if len(pvalues) > 1 else pvalues
        for (level, n, pa, pb, diff, se, pairs), p in zip(cells, adjusted, strict=True):
            lines.append(
                f"| {factor} | {level} | {n} | {pa:.1%} [{_per_seed(pairs, 0)}] | "
                f"{pb:.1%} [{_per_seed(pairs, 1)}] | {diff:+.1%} "
                f"[{diff - 1.96 * se:+.1%}, {diff + 1.96 * se:+.1%}] | {p:.3g} |"
            )
    return lines


def put(docs: Path, begin: str, end: str, text: str) -> None:
    """Replace what lies between the markers ``begin`` and ``end`` in ``docs`` with ``text``."""
    page = docs.read_text()
    if begin in page and end in page:
        head, rest = page.split(begin, 1)
        docs.write_text(head + begin + "\n" + text + end + rest.split(end, 1)[1])


def write(results: Path, docs: Path) -> list[Path]:
    """Write ``table.md`` (and ``models.md`` where ``previous.csv`` is there) and the docs."""
    articulated = results / "articulated.csv"
    text = "\n".join(table(results / "capsule.csv", articulated)) + "\n"
    (results / "table.md").write_text(text)
    put(docs, BEGIN, END, text)
    written = [results / "table.md"]
    if (results / "previous.csv").exists():
        models = "\n".join(table(results / "previous.csv", articulated, MODELS)) + "\n"
        (results / "models.md").write_text(models)
        put(docs, MODELS_BEGIN, MODELS_END, models)
        written.append(results / "models.md")
    return written


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, default=Path("bench/results/vision_hands"))
    parser.add_argument("--docs", type=Path, default=DOCS)
    args = parser.parse_args()
    for path in write(args.results, args.docs):
        print(path.read_text())


if __name__ == "__main__":
    main()
