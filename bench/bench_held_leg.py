"""Robin's eyes on the hand under a leg it holds above the palm: two gesture models, same views.

Run: ``python bench/bench_held_leg.py [--seeds 0,1,2,3,4] [--tries 20] [--other FILE]
[--other-name NAME] [--out out/held_leg]`` (``python bench/regenerate.py --only held_leg`` runs
it into ``bench/results``).

In an episode the person shows "release" (and, when Robin already holds the leg there, "give
me") with the palm slid under the leg Robin holds above it; Robin's fingers and the leg then
frame and hide parts of the hand. Per seed a fresh world is brought there by real actions
(:func:`robin_sim.vision.arm_states.arm_states`, state ``human``), the person slides the hand
under the leg, and shows each of the two gestures ``--tries`` times (a new performance each
time, drawn from the seed), read as the robot reads an instruction: among the four gestures,
discarded below the threshold. Each view is read by the shipped model and by ``--other`` (a
candidate model file, named ``--other-name`` in the table; default: none, then only the
shipped model's column), so the two columns are paired: the same views; the other model is
copied beside the figures as ``other_model.npz``. Writes ``held_leg.csv`` (one row per reading)
and ``table.md`` (per gesture: the readings, each model's share read right, the paired
difference (other less shipped) with its 95 % interval and McNemar's exact p, Holm over the
gestures).
"""

from __future__ import annotations

import argparse
import csv
import shutil
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke
from scipy.stats import norm
from statsmodels.stats.contingency_tables import mcnemar
from statsmodels.stats.multitest import multipletests

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from pil.types import Gesture  # noqa: E402
from robin_sim.person.body import PhysicalBody  # noqa: E402
from robin_sim.person.gestures import pose_for  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402
from robin_sim.vision.arm_states import reach_held_leg  # noqa: E402
from robin_sim.vision.classifier import NO_GESTURE, GestureModel, load_shipped  # noqa: E402
from robin_sim.vision.detector import VisionDetector  # noqa: E402
from robin_sim.vision.reader import EyeReading, fuse  # noqa: E402
from robin_sim.vision.train import GESTURE_CLASSES  # noqa: E402

GESTURES = (Gesture.RELEASE, Gesture.GIVE_ME)  # what a person shows under the held leg
FIELDS = ("seed", "try", "shown", "shipped", "other")
Z95 = float(norm.ppf(0.975))  # two-sided 95 % normal quantile (the difference's interval)


def in_context(model: GestureModel, reading: EyeReading) -> str:
    """What ``model`` reads in ``reading``'s views as an instruction ("" when discarded)."""
    if reading.features is None:
        return ""
    p = fuse(model.probabilities(reading.features))
    label, confidence = EyeReading(p, reading.boxes, model.threshold).among(GESTURE_CLASSES)
    return label if label != NO_GESTURE and confidence >= model.threshold else ""


def measure(seed: int, tries: int, other: GestureModel | None) -> list[dict[str, object]]:
    """Readings of one seed's world (see the module doc)."""
    world = PhysicalWorld()
    body = PhysicalBody(world)
    detector = VisionDetector(world.sim, display=body.display, seed=seed)
    rows: list[dict[str, object]] = []
    try:
        reach_held_leg(world, body)  # the palm slid under the held leg
        for k in range(tries):
            for gesture in GESTURES:
                read = detector.detect(gesture)
                reading = detector.last_reading
                assert reading is not None
                rows.append(
                    {
                        "seed": seed,
                        "try": k,
                        "shown": pose_for(gesture),
                        "shipped": "" if read is None else pose_for(read),
                        "other": "" if other is None else in_context(other, reading),
                    }
                )
    finally:
        detector.close()
    return rows


def table(rows: list[dict[str, object]], other: str | None) -> list[str]:
    """The per-gesture table (see the module doc); ``other``: the other model's name."""
    paired = other is not None
    lines = [
        f"| shown | readings | shipped model | {other or '-'} | difference [95 % CI] | "
        "McNemar p (Holm) |",
        "|---|---|---|---|---|---|",
    ]
    cells, pvalues = [], []
    for gesture in GESTURES:
        shown = pose_for(gesture)  # the class names the models read
        mine = [r for r in rows if r["shown"] == shown]
        a = np.array([r["shipped"] == shown for r in mine])
        b = np.array([r["other"] == shown for r in mine])
        d = b.astype(float) - a.astype(float)
        half = Z95 * d.std(ddof=1) / np.sqrt(len(d)) if len(d) > 1 else 0.0
        both = [[np.sum(a & b), np.sum(a & ~b)], [np.sum(~a & b), np.sum(~a & ~b)]]
        pvalues.append(float(mcnemar(both, exact=True).pvalue) if paired else 1.0)
        cells.append((shown, len(mine), a.mean(), b.mean(), d.mean(), half))
    adjusted = multipletests(pvalues, method="holm")[1]
    for (name, n, pa, pb, diff, half), p in zip(cells, adjusted, strict=True):
        change = f"{diff:+.1%} [{diff - half:+.1%}, {diff + half:+.1%}]"
        lines.append(
            f"| {name} | {n} | {pa:.1%} | {pb:.1%} | {change} | {p:.3g} |"
            if paired
            else f"| {name} | {n} | {pa:.1%} | - | - | - |"
        )
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0,1,2,3,4")
    parser.add_argument("--tries", type=int, default=20)
    parser.add_argument("--other", type=Path, default=None, help="a gesture model file")
    parser.add_argument("--other-name", default="other model", help="its column's name")
    parser.add_argument("--out", type=Path, default=Path("out/held_leg"))
    args = smoke.parse_args(parser, seeds="0", tries=1)
    other = None if args.other is None else GestureModel.load(args.other)
    shipped = load_shipped()
    if other is not None and np.array_equal(other.weights[0], shipped.weights[0]):
        print("note: --other is the shipped model itself")
    rows = [
        row
        for seed in (int(s) for s in args.seeds.split(","))
        for row in measure(seed, args.tries, other)
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    if args.other is not None:  # kept beside the figures, so a regeneration finds it there
        kept = args.out / "other_model.npz"
        if args.other.resolve() != kept.resolve():
            shutil.copyfile(args.other, kept)
    with (args.out / "held_leg.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    lines = table(rows, None if other is None else args.other_name)
    (args.out / "table.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
