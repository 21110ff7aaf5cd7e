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

With ``--away`` (and ``--readings``) every sample is shown again with Robin's active arm swung
back out of its eyes' view (:func:`robin_sim.vision.arm_states.away_qpos`, a what-if no episode
reaches; the same spec otherwise) and the shipped model reads it as ``bench_vision_hands`` reads
the paired samples: ``away.csv`` (its rows), ``away_hidden.md`` (the table above for these
views) and ``away.md``, the readings with the arm at home against these, paired by sample
(``vision_hands_table.table``: McNemar, Holm within each factor).
"""

from __future__ import annotations

import argparse
import csv
from dataclasses import replace
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke
from bench_vision_hands import FIELDS as READ_FIELDS
from bench_vision_hands import PLACES, levels, place_kind
from vision_hands_table import table as paired_table

from robin_sim.vision.classifier import CLASSES, GestureModel, shipped_path
from robin_sim.vision.dataset import sample_spec, split_of_views
from robin_sim.vision.render_set import POSE_OF, SampleRenderer
from robin_sim.vision.segment import MIN_PIXELS
from robin_sim.vision.train import readings

FIELDS = ("seed", "sample", "place", "left_pixels", "right_pixels")
SEEN = ("neither eye", "one eye", "both eyes")
SIDES = ("arm at home", "arm away")  # the paired table's two columns


def hand_pixels(renderer: SampleRenderer, seed: int, sample: int) -> tuple[int, int]:
    """True hand pixels in the left and right eye of held-out sample ``sample`` of ``seed``."""
    spec = sample_spec(seed, "heldout", sample)
    renderer.render(spec)  # shows the pose, aims the head, as the data set does
    pose = POSE_OF[CLASSES[spec.label]]
    left, right = (int(renderer.truth_mask(pose, eye).sum()) for eye in (0, 1))
    return left, right


def read_away(
    renderer: SampleRenderer, model: GestureModel, seed: int, sample: int
) -> tuple[dict[str, object], tuple[int, int]]:
    """Held-out sample ``sample`` of ``seed`` shown with Robin's arm away and read by ``model``
    (both eyes fused, as ``bench_vision_hands`` reads it): a row of its CSV, and the true hand
    pixels in the left and right eye."""
    spec = replace(sample_spec(seed, "heldout", sample), arm="away")
    crops, _ = renderer.render(spec)
    pose = POSE_OF[CLASSES[spec.label]]
    pixels = (int(renderer.truth_mask(pose, 0).sum()), int(renderer.truth_mask(pose, 1).sum()))
    split = split_of_views([(sample, spec.label, crops)])
    _, (reading,) = readings(model, split)
    condition = np.array([spec.skin, spec.lighting, spec.light_tilt, spec.camera_noise])
    condition = np.append(condition, [spec.jitter, spec.lift])
    right = reading.confidence >= model.threshold and CLASSES.index(reading.label) == spec.label
    row = {
        "hand": SIDES[1],
        "seed": seed,
        "sample": sample,
        "shown": CLASSES[spec.label],
        **levels(seed, sample, condition),
        "right": int(right),
    }
    return row, pixels


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


def load_readings(path: Path, rows: list[dict[str, object]]) -> dict[tuple[int, int], bool]:
    """Whether each sample of ``rows`` was read right, from a ``bench_vision_hands`` CSV;
    raises ``ValueError`` naming a sample the file lacks."""
    with path.open(newline="") as handle:
        read = {
            (int(r["seed"]), int(r["sample"])): r["right"] == "1" for r in csv.DictReader(handle)
        }
    missing = [(r["seed"], r["sample"]) for r in rows if (r["seed"], r["sample"]) not in read]
    if missing:
        raise ValueError(f"{path} has no reading of {len(missing)} samples, e.g. {missing[0]}")
    return read


def write_csv(path: Path, fields: tuple[str, ...], rows: list[dict[str, object]]) -> None:
    """``rows`` as a CSV with the columns ``fields``."""
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fields)
        writer.writeheader()
        writer.writerows(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0,1,2")
    parser.add_argument("--samples", type=int, default=336, help="held-out samples per seed")
    parser.add_argument("--readings", type=Path, default=None, help="bench_vision_hands CSV")
    parser.add_argument("--away", action="store_true", help="read each sample with the arm away")
    parser.add_argument("--out", type=Path, default=Path("out/hand_hidden"))
    shipped = Path(__file__).resolve().parent / "results" / "vision_hands" / "articulated.csv"
    args = smoke.parse_args(parser, seeds="0", samples=8, readings=shipped, away=True)
    seeds = [int(s) for s in args.seeds.split(",")]
    keys = [(seed, sample) for seed in seeds for sample in range(args.samples)]
    if args.away and args.readings is None:
        parser.error("--away compares with the arm at home: give that reading's --readings CSV")
    right_of: dict[tuple[int, int], bool] | None = None
    if args.readings is not None:  # checked before anything is rendered
        try:
            right_of = load_readings(args.readings, [{"seed": k[0], "sample": k[1]} for k in keys])
        except (OSError, ValueError, KeyError) as error:
            parser.error(f"--readings: {error}")
    renderer = SampleRenderer()
    model = GestureModel.load(shipped_path()) if args.away else None
    rows: list[dict[str, object]] = []
    away_rows: list[dict[str, object]] = []
    away_pixels: list[dict[str, object]] = []
    for seed, sample in keys:
        place = place_kind(seed, sample)
        left, right = hand_pixels(renderer, seed, sample)
        rows.append(dict(zip(FIELDS, (seed, sample, place, left, right), strict=True)))
        if model is not None:
            row, (left, right) = read_away(renderer, model, seed, sample)
            away_rows.append(row)
            away_pixels.append(dict(zip(FIELDS, (seed, sample, place, left, right), strict=True)))
    args.out.mkdir(parents=True, exist_ok=True)
    write_csv(args.out / "hidden.csv", FIELDS, rows)
    lines = table(rows, right_of)
    (args.out / "table.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    hidden = [seen_by(r) == SEEN[0] for r in rows]
    share = f"{np.mean(hidden):.1%}"
    print(f"{sum(hidden)} of {len(rows)} samples show the hand to neither eye ({share})")
    if args.readings is not None and away_rows:
        write_csv(args.out / "away.csv", READ_FIELDS, away_rows)
        right_away = {
            (int(str(r["seed"])), int(str(r["sample"]))): r["right"] == 1 for r in away_rows
        }
        hidden_lines = table(away_pixels, right_away)
        (args.out / "away_hidden.md").write_text("\n".join(hidden_lines) + "\n")
        paired = paired_table(args.readings, args.out / "away.csv", SIDES)
        (args.out / "away.md").write_text("\n".join(paired) + "\n")
        print("\n".join(["", "With the arm away:", *hidden_lines, "", *paired]))


if __name__ == "__main__":
    main()
