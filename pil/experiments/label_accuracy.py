"""How right the labels are that an adapting gesture reader gets from the robot's feedback.

An adapting reader (:class:`pil.task.detector.LearnsFromFeedback`, Robin's eye cameras with
``adapt``) is told after each approved action the gesture that action means by what PIL has
learnt (:func:`pil.gesture_evidence.meant_gesture`), or nothing where the table has no such
evidence yet. This runs the learner-only loop with the paper's dice (a reader that records
what it is told) and counts, per seed: approvals, approvals labelled, labels equal to the
person's true gesture, and labelled readings acted on that were read right. ``python -m
pil.experiments.label_accuracy --out bench/results/label_accuracy`` writes ``labels.csv``
(a row per seed and one ``all`` row) and ``labels.md``.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.experiments.report import csv_text, markdown_table
from pil.task.detector import Detector
from pil.types import Gesture

LABEL_COLUMNS: tuple[str, ...] = (
    "seed",
    "approvals",
    "labelled",
    "labelled_right",
    "read_right",
    "unlabelled",
    "unlabelled_share",
)
LABEL_SEEDS: tuple[int, ...] = tuple(range(10))
LABEL_RATE = 0.6
LABEL_TABLES = 10


class RecordingDetector(Detector):
    """The paper's dice detector, recording the verdicts the loop tells it."""

    def __init__(self, rate: float, seed: int, deck_size: int) -> None:
        super().__init__(rate, seed, deck_size=deck_size)
        self.verdicts: list[tuple[Gesture | None, bool]] = []

    def verdict(self, meant: Gesture | None, approved: bool) -> None:
        """Keep what the loop told the reader."""
        self.verdicts.append((meant, approved))


def seed_row(seed: int, rate: float = LABEL_RATE, tables: int = LABEL_TABLES) -> dict[str, Any]:
    """The counts of one seed's run (learner-only, PIL, the dice at ``rate``)."""
    from pil.task.assemble import assemble
    from pil.task.runner import steps
    from pil.task.spec import parse_run_spec

    spec = parse_run_spec(system="pil", rate=rate, seed=seed, params={"tables": tables})
    built = assemble(spec)
    detector = RecordingDetector(rate, seed=seed + 1, deck_size=64)
    records = list(steps(built.learner, built.person, detector, built.world, **built.options))
    acted = [r for r in records if r.action is not None and not r.proactive]
    approved = [(m, r) for (m, ok), r in zip(detector.verdicts, acted, strict=True) if ok]
    labelled = [(m, r) for m, r in approved if m is not None]
    return _row(
        seed,
        len(approved),
        len(labelled),
        sum(m is r.true_gesture for m, r in labelled),
        sum(r.state is not None and r.state.gesture is r.true_gesture for _, r in labelled),
    )


def _row(seed: Any, approvals: int, labelled: int, right: int, read_right: int) -> dict[str, Any]:
    return {
        "seed": seed,
        "approvals": approvals,
        "labelled": labelled,
        "labelled_right": right,
        "read_right": read_right,
        "unlabelled": approvals - labelled,
        "unlabelled_share": round((approvals - labelled) / approvals, 4) if approvals else 0.0,
    }


def label_rows(seeds: Sequence[int] = LABEL_SEEDS) -> list[dict[str, Any]]:
    """A row per seed and the ``all`` row (sums)."""
    rows = [seed_row(s) for s in seeds]

    def total(key: str) -> int:
        return sum(int(r[key]) for r in rows)

    every = _row(
        "all", total("approvals"), total("labelled"), total("labelled_right"), total("read_right")
    )
    return [*rows, every]


def write(out: str | Path, seeds: Sequence[int] = LABEL_SEEDS) -> list[Path]:
    """``labels.csv`` and ``labels.md`` in ``out``."""
    rows = label_rows(seeds)
    body = [
        [
            r["seed"],
            r["approvals"],
            r["labelled"],
            f"{r['labelled_right']}/{r['labelled']}",
            f"{r['read_right']}/{r['labelled']}",
            f"{100 * r['unlabelled_share']:.1f} %",
        ]
        for r in rows
    ]
    header = ["seed", "approvals", "labelled", "label right", "reading right", "unlabelled"]
    text = (
        "# Labels an adapting reader gets from the robot's feedback\n\n"
        f"PIL, learner only, the paper's dice at d = {LABEL_RATE:g}, {LABEL_TABLES} tables, seeds "
        f"{seeds[0]}-{seeds[-1]}.\n\n" + markdown_table(header, body) + "\n"
    )
    out = Path(out)
    return [
        write_text_atomic(out / "labels.csv", csv_text(rows, LABEL_COLUMNS)),
        write_text_atomic(out / "labels.md", text),
    ]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m pil.experiments.label_accuracy --out DIR``."""
    parser = argparse.ArgumentParser(prog="python -m pil.experiments.label_accuracy")
    parser.add_argument("--out", default="bench/results/label_accuracy")
    args = parser.parse_args(argv)
    for path in write(args.out):
        print(path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
