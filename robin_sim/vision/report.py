"""The ``train-gestures`` report: held-out accuracy and confusion (Markdown and PNG), and the
measured error model file for ``robin-pil study --detector measured:FILE``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pil.file_names import MEASURED_NAME
from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.vision.classifier import CLASSES
from robin_sim.vision.dataset import SPLITS
from robin_sim.vision.train import DISCARDED, FEEDBACK_CLASSES, GESTURE_CLASSES, Evaluation

if TYPE_CHECKING:
    from robin_sim.vision.build_config import BuildConfig

# the pil names of the classes (measured files speak the learner's language)
PIL_NAMES = {
    **{SIGN_OF[gesture]: gesture.value for gesture in Gesture},
    SIGN_OF[Feedback.OK]: "OK",
    SIGN_OF[Feedback.NOT_OK]: "not OK",
}


def _rows(counts: np.ndarray) -> np.ndarray:
    return counts / np.maximum(counts.sum(axis=1, keepdims=True), 1)


def measured(evaluation: Evaluation, condition: str) -> dict[str, object]:
    """The in-context error model: rows true class, columns readings then "discarded"."""
    return {
        "format": 1,
        "source": f"robin-pil train-gestures, held-out split ({condition})",
        "gestures": [PIL_NAMES[c] for c in GESTURE_CLASSES],
        "confusion": _rows(evaluation.gestures).round(6).tolist(),
        "feedback": [PIL_NAMES[c] for c in FEEDBACK_CLASSES],
        "feedback_confusion": _rows(evaluation.feedback).round(6).tolist(),
        "samples": int(evaluation.gestures.sum()),
    }


def _table(counts: np.ndarray, rows: tuple[str, ...], columns: tuple[str, ...]) -> list[str]:
    lines = ["| true \\ read | " + " | ".join(columns) + " |"]
    lines.append("|---" * (len(columns) + 1) + "|")
    for name, row in zip(rows, counts, strict=True):
        lines.append(f"| {name} | " + " | ".join(str(int(v)) for v in row) + " |")
    return lines


def _figure(evaluation: Evaluation, path: Path) -> None:
    from pil.experiments.plotting import pyplot

    plt = pyplot()
    share = _rows(evaluation.confusion)
    fig, ax = plt.subplots(figsize=(7, 5.2))
    ax.imshow(share, cmap="Blues", vmin=0, vmax=1)
    columns = [*CLASSES, DISCARDED]
    ax.set_xticks(range(len(columns)), columns, rotation=40, ha="right")
    ax.set_yticks(range(len(CLASSES)), CLASSES)
    for i in range(share.shape[0]):
        for j in range(share.shape[1]):
            ax.text(
                j,
                i,
                f"{share[i, j]:.2f}",
                ha="center",
                va="center",
                fontsize=7,
                color="white" if share[i, j] > 0.5 else "black",
            )
    ax.set_xlabel("reading")
    ax.set_ylabel("true pose")
    ax.set_title(f"held-out (light never trained on): accuracy {evaluation.accuracy:.1%}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _no_hand_share(split: dict[str, np.ndarray]) -> float:
    """Share of samples in which neither eye found a hand."""
    samples = np.unique(split["sample"])
    found = np.zeros(samples.size, bool)
    np.logical_or.at(found, np.searchsorted(samples, split["sample"]), split["found"])
    return float(1.0 - found.mean())


def write_report(
    config: BuildConfig,
    model_path: Path,
    threshold: float,
    heldout: Evaluation,
    training: Evaluation,
    heldout_split: dict[str, np.ndarray],
    train_split: dict[str, np.ndarray],
) -> list[Path]:
    """Write report.md, confusion.png and measured.json under ``config.out``."""
    out = config.out
    ranges = {name: r for name, r in SPLITS.items()}
    condition = (
        f"light scale {ranges['heldout'].lighting}, light tilt {ranges['heldout'].light_tilt} rad"
    )
    train = ranges["train"]
    no_hand = _no_hand_share(heldout_split)
    lines = [
        "# Gesture recognition: train-gestures report",
        "",
        f"Seed {config.seed}; {config.samples} training samples, {config.heldout} held-out "
        f"samples (two eyes each); model `{model_path.name}` "
        f"({model_path.stat().st_size / 1024:.0f} KiB), confidence threshold "
        f"{threshold:.2f}.",
        "",
        f"- both splits: skin tones {train.skin}, pose jitter scale {train.jitter}, hand held "
        f"{train.lift} m above its place; a quarter each above a place, drawn back and raised, "
        "at the handover point, in the working box",
        f"- training light: scale {train.lighting}, tilt {train.light_tilt} rad",
        f"- held-out light (never trained on): {condition}",
        "",
        "| split | accuracy (7 classes) | discarded | accuracy of kept readings | "
        "instruction gestures read right in context (d) |",
        "|---|---|---|---|---|",
    ]
    for name, e in (("held-out", heldout), ("training", training)):
        lines.append(
            f"| {name} | {e.accuracy:.1%} | {e.discard_rate:.1%} | {e.accepted_accuracy:.1%} | "
            f"{e.detection_rate():.1%} |"
        )
    iou_heldout, iou_train = heldout_split["iou"][::2].mean(), train_split["iou"][::2].mean()
    lines += [
        "",
        f"Hand segmentation (left eye, IoU with the renderer's ground truth): held-out mean "
        f"{iou_heldout:.2f}, training mean {iou_train:.2f}; "
        f"an eye found a hand in {heldout_split['found'].mean():.1%} of held-out views; "
        f"neither eye found one in {no_hand:.1%} of held-out samples (no hand: discarded).",
        "",
        "## Held-out confusion (counts; rows: the pose shown)",
        "",
        *_table(heldout.confusion, CLASSES, (*CLASSES, DISCARDED)),
        "",
        "## In context (what `--detector measured:FILE` uses)",
        "",
        *_table(heldout.gestures, GESTURE_CLASSES, (*GESTURE_CLASSES, DISCARDED)),
        "",
        *_table(heldout.feedback, FEEDBACK_CLASSES, (*FEEDBACK_CLASSES, DISCARDED)),
        "",
    ]
    report = out / "report.md"
    report.write_text("\n".join(lines))
    figure = out / "confusion.png"
    _figure(heldout, figure)
    measured_path = out / MEASURED_NAME
    measured_path.write_text(json.dumps(measured(heldout, condition), indent=2) + "\n")
    return [report, figure, measured_path]
