"""Held-out eye-camera accuracy per place, light, skin and pose jitter, over seeds: one hand.

Run (from a checkout whose scene holds the hand to measure, with that hand's model):

    python bench/bench_vision_hands.py --hand articulated --seeds 0,1,2 --samples 336 \\
        --baseline bench/results/vision_hands/capsule.csv --out out/vision_hands

(``python bench/regenerate.py --only vision_hands`` runs it into ``bench/results``.)

Renders ``--samples`` samples of the held-out split (light never trained on; every skin tone,
pose jitter 0-2.5, the four kinds of place) per seed, or reuses chunks already rendered: with
``--cache DIR`` those under ``DIR`` of this checkout's render key (the same body, poses,
cameras and sample spec: :mod:`robin_sim.vision.render_key`), else those in ``--out``'s
``chunks`` (``--chunks SEED=DIR`` reuses a training run's held-out chunks of that seed), reads
them with ``--model`` (default: the shipped one) as an episode would (both eyes fused,
discarded below the threshold) and writes ``HAND.csv`` into ``--out``, one row per sample: the
class shown, whether it was read right (seven classes; a discard or no hand counts as wrong)
and the levels of what it was drawn with: its place (above a leg or spot, drawn back and
raised, at the handover point, in the working box), its light (dim 0.35-0.55 or bright 1.3-1.6
of the scene's light), its skin tone (nearest of 0-4) and its pose jitter (0-0.8, 0.8-1.6,
1.6-2.5). Written for the capsule-to-articulated comparison of issue 29: ``--baseline FILE``
copies the other hand's file (the capsule hand's, measured at ``f581bee``: this checkout's
scene no longer holds that hand) beside it and writes their paired ``table.md``
(``bench/vision_hands_table.py``, which also puts it into the docs); ``--previous FILE`` copies
the previous model's file of the same samples beside it as ``previous.csv`` and writes the
paired previous-against-this-model ``models.md``. It uses only interfaces both hands' code has.
"""

from __future__ import annotations

import argparse
import csv
import shutil
import time
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke
from vision_hands_table import MODELS, table

from robin_sim.vision.build import Job, run_jobs
from robin_sim.vision.classifier import CLASSES, GestureModel, shipped_path
from robin_sim.vision.dataset import (
    CHUNK,
    SPLIT_IDS,
    chunk_path,
    chunk_ready,
    chunks_for,
    load_split,
)
from robin_sim.vision.render_key import cache_folder
from robin_sim.vision.train import readings

PLACES = ("above a place", "drawn back, raised", "handover point", "working box")
JITTER_BINS = ((0.0, 0.8), (0.8, 1.6), (1.6, 2.5))
FIELDS = ("hand", "seed", "sample", "shown", "place", "light", "skin tone", "pose jitter", "right")


def place_kind(seed: int, index: int) -> str:
    """Where held-out sample ``index`` was drawn (the first draw of its spec's stream)."""
    where = np.random.default_rng([seed, SPLIT_IDS["heldout"], index]).random()
    return PLACES[min(int(where * 4), 3)]


def levels(seed: int, sample: int, condition: np.ndarray) -> dict[str, str]:
    """The factor levels of one sample (``condition``: skin, light, tilt, noise, jitter, lift)."""
    jitter = next(f"{lo:g}-{hi:g}" for lo, hi in JITTER_BINS if condition[4] <= hi + 1e-9)
    return {
        "place": place_kind(seed, sample),
        "light": "dim (0.35-0.55)" if condition[1] < 1.0 else "bright (1.3-1.6)",
        "skin tone": str(int(np.clip(np.rint(condition[0]), 0, 4))),
        "pose jitter": jitter,
    }


def measure(folder: Path, seed: int, samples: int, model: GestureModel) -> list[dict[str, object]]:
    """Rows of :data:`FIELDS` (less ``hand``), one per rendered held-out sample of one seed."""
    split = load_split(folder, "heldout", samples, seed)
    truth, reads = readings(model, split)
    rows: list[dict[str, object]] = []
    for sample, true, reading in zip(np.unique(split["sample"]), truth, reads, strict=True):
        condition = split["condition"][split["sample"] == sample][0]
        ok = reading.confidence >= model.threshold and CLASSES.index(reading.label) == true
        rows.append(
            {
                "seed": seed,
                "sample": int(sample),
                "shown": CLASSES[true],
                **levels(seed, int(sample), condition),
                "right": int(ok),
            }
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--hand", default="articulated", help="label of the hand measured")
    parser.add_argument("--seeds", default="0,1,2")
    parser.add_argument("--samples", type=int, default=336, help="held-out samples per seed")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--model", type=Path, default=None)
    parser.add_argument("--out", type=Path, default=Path("out/vision_hands"))
    parser.add_argument("--chunks", action="append", default=[], help="SEED=DIR to reuse")
    parser.add_argument("--cache", type=Path, default=None, help="render cache root")
    parser.add_argument("--baseline", type=Path, default=None, help="the other hand's CSV")
    parser.add_argument(
        "--previous", type=Path, default=None, help="the previous model's CSV (same samples)"
    )
    args = smoke.parse_args(parser, seeds="0", samples=CHUNK, workers=1)
    seeds = [int(s) for s in args.seeds.split(",")]
    reuse = {int(k): Path(v) for k, v in (c.split("=", 1) for c in args.chunks)}
    model = GestureModel.load(args.model or shipped_path())
    rows: list[dict[str, object]] = []
    for seed in seeds:
        own = args.out / "chunks" / f"seed{seed}"
        folder = reuse.get(seed, own if args.cache is None else cache_folder(args.cache, seed))
        jobs = [
            Job("heldout", k)
            for k in range(chunks_for(args.samples))
            if not chunk_ready(chunk_path(folder, "heldout", k), seed)
        ]
        started = time.perf_counter()
        run_jobs(jobs, folder, seed, args.workers)
        print(f"seed {seed}: {len(jobs) * CHUNK} rendered in {time.perf_counter() - started:.0f} s")
        rows += [{"hand": args.hand, **row} for row in measure(folder, seed, args.samples, model)]
    args.out.mkdir(parents=True, exist_ok=True)
    results = args.out / f"{args.hand}.csv"
    with results.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    right = sum(int(r["right"]) for r in rows)
    print(f"wrote {results}: {right} of {len(rows)} read right")
    if args.baseline is not None:
        other = args.out / args.baseline.name
        if other.resolve() != args.baseline.resolve():
            shutil.copyfile(args.baseline, other)
        pair = sorted([other, results], key=lambda p: p.name != "capsule.csv")
        (args.out / "table.md").write_text("\n".join(table(*pair)) + "\n")
        print(f"wrote {args.out / 'table.md'}")
    if args.previous is not None:
        previous = args.out / "previous.csv"
        if previous.resolve() != args.previous.resolve():
            shutil.copyfile(args.previous, previous)
        models = table(previous, results, MODELS)
        (args.out / "models.md").write_text("\n".join(models) + "\n")
        print(f"wrote {args.out / 'models.md'}")


if __name__ == "__main__":
    main()
