"""How much of the person's hand each eye can see in the paired vision table's samples, per place.

Run:

    python bench/bench_hand_hidden.py --seeds 0,1,2 --samples 336 \\
        --readings bench/results/vision_hands/articulated.csv --out out/hand_hidden

(``python bench/regenerate.py --only hand_hidden`` runs it into ``bench/results``.)

Shows each held-out sample of the paired table (``bench/bench_vision_hands.py``: the same specs,
seeds and samples) as the data set does and counts, by the segmentation renderer (ground truth,
never used to read), the pixels of the true hand in each eye. A hand with fewer than the
segmentation's least hand (``segment.MIN_PIXELS``) in an eye is hidden from that eye: by
Robin's own arm at home, or out of the eye's narrow view. Writes ``hidden.csv`` (one row per
sample: seed, sample, place, pixels per eye) and ``table.md``: per place the samples hidden
from both eyes, from one, from none, and, with ``--readings`` (a ``bench_vision_hands`` CSV of
the same samples), how many of each the model read right: no reading can be right where no eye
sees the hand, so a place's accuracy cannot pass the share of its samples some eye sees.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke
from bench_vision_hands import PLACES, place_kind

from robin_sim.vision.classifier import CLASSES
from robin_sim.vision.dataset import sample_spec
from robin_sim.vision.render_set import POSE_OF, SampleRenderer
from robin_sim.vision.segment import MIN_PIXELS

FIELDS = ("seed", "sample", "place", "left_pixels", "right_pixels")
SEEN = ("neither eye", "one eye", "both eyes")


def hand_pixels(renderer: SampleRenderer, seed: int, sample: int) -> tuple[int, int]:
    """True hand pixels in the left and right eye of held-out sample ``sample`` of ``seed``."""
    spec = sample_spec(seed, "heldout", sample)
    renderer.render(spec)  # shows the pose, aims the head, as the data set does
    pose = POSE_OF[CLASSES[spec.label]]
    left, right = (int(renderer.truth_mask(pose, eye).sum()) for eye in (0, 1))
    return left, right


def seen_by(row: dict[str, object]) -> str:
    """Which eyes see the hand of ``row`` (at least :data:`MIN_PIXELS` true hand pixels)."""
    return SEEN[sum(int(str(row[k])) >= MIN_PIXELS for k in ("left_pixels", "right_pixels"))]


def table(rows: list[dict[str, object]], right: dict[tuple[int, int], bool] | None) -> list[str]:
    """Markdown lines: per place, the samples each number of eyes sees (and read right)."""
    cells = "samples read right / samples" if right is not None else "samples"
    lines = [
        f"Held-out samples of the paired vision table; cells: {cells}; an eye sees the hand "
        f"when at least {MIN_PIXELS} of its pixels are the true hand's.",
        "",
        "| place | samples | " + " | ".join(f"seen by {s}" for s in SEEN) + " |",
        "|---|---|" + "---|" * len(SEEN),
    ]
    for place in (*PLACES, "all"):
        mine = [r for r in rows if place in ("all", r["place"])]
        out = []
        for seen in SEEN:
            group = [r for r in mine if seen_by(r) == seen]
            if right is None:
                out.append(str(len(group)))
            else:
                good = sum(right[(int(str(r["seed"])), int(str(r["sample"])))] for r in group)
                out.append(f"{good}/{len(group)}")
        lines.append(f"| {place} | {len(mine)} | " + " | ".join(out) + " |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0,1,2")
    parser.add_argument("--samples", type=int, default=336, help="held-out samples per seed")
    parser.add_argument("--readings", type=Path, default=None, help="bench_vision_hands CSV")
    parser.add_argument("--out", type=Path, default=Path("out/hand_hidden"))
    args = smoke.parse_args(parser, seeds="0", samples=8)
    renderer = SampleRenderer()
    rows: list[dict[str, object]] = []
    for seed in (int(s) for s in args.seeds.split(",")):
        for sample in range(args.samples):
            left, right = hand_pixels(renderer, seed, sample)
            place = place_kind(seed, sample)
            rows.append(dict(zip(FIELDS, (seed, sample, place, left, right), strict=True)))
    right_of: dict[tuple[int, int], bool] | None = None
    if args.readings is not None:
        with args.readings.open(newline="") as handle:
            read = {
                (int(r["seed"]), int(r["sample"])): r["right"] == "1"
                for r in csv.DictReader(handle)
            }
        missing = [(r["seed"], r["sample"]) for r in rows if (r["seed"], r["sample"]) not in read]
        if missing:
            parser.error(
                f"{args.readings} has no reading of {len(missing)} samples, e.g. {missing[0]}"
            )
        right_of = read
    args.out.mkdir(parents=True, exist_ok=True)
    with (args.out / "hidden.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    lines = table(rows, right_of)
    (args.out / "table.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    hidden = [seen_by(r) == SEEN[0] for r in rows]
    share = f"{np.mean(hidden):.1%}"
    print(f"{sum(hidden)} of {len(rows)} samples show the hand to neither eye ({share})")


if __name__ == "__main__":
    main()
