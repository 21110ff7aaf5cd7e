"""Train the gesture model on the rendered data set and measure it on the held-out split.

:func:`fit` standardises the training split's per-eye feature rows and fits scikit-learn's
``MLPClassifier`` (one hidden layer of :data:`HIDDEN` ReLU units, L2 penalty :data:`PENALTY`,
Adam, its random state the seed: deterministic). On the default data set it reads held-out
samples about 3 points better than a multinomial logistic regression. :func:`evaluate` reads
every held-out sample as an episode would: both eyes' probabilities fused, "no gesture"
when neither eye finds a hand, discarded below the confidence threshold; it returns the
confusion counts (true class x reading, discards as the last column) and the restricted
readings the robot makes in context (instruction gestures among the four gestures, feedback
among the two thumbs) that ``--detector measured:FILE`` uses.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from pil.types import SIGN_OF, Feedback
from robin_sim.vision.classifier import CLASSES, NO_GESTURE, GestureModel
from robin_sim.vision.reader import EyeReading, fuse

DEFAULT_THRESHOLD = 0.5
HIDDEN = 256  # hidden units
PENALTY = 1e-2  # scikit-learn's alpha (L2)
MAX_ITER = 80  # epochs (400 before issue 41; fewer, so that a retraining fits in a session)
GESTURE_CLASSES = CLASSES[:4]
FEEDBACK_CLASSES = (SIGN_OF[Feedback.OK], SIGN_OF[Feedback.NOT_OK])
DISCARDED = "discarded"


def fit(
    split: dict[str, np.ndarray], *, seed: int, threshold: float = DEFAULT_THRESHOLD
) -> GestureModel:
    """The gesture model trained on the rows of ``split`` where a hand was found."""
    from sklearn.neural_network import MLPClassifier

    rows = split["found"]
    x = split["features"][rows].astype(np.float64)
    y = split["label"][rows]
    mean = x.mean(axis=0)
    scale = x.std(axis=0) + 1e-6
    classifier = MLPClassifier(
        (HIDDEN,), alpha=PENALTY, max_iter=MAX_ITER, random_state=seed, early_stopping=False
    )
    with warnings.catch_warnings():  # a small N stops at MAX_ITER; that is fine
        warnings.simplefilter("ignore", category=UserWarning)
        classifier.fit((x - mean) / scale, y)
    if list(classifier.classes_) != list(range(len(CLASSES))):
        raise ValueError(f"training split lacks classes: has {classifier.classes_.tolist()}")
    return GestureModel(
        mean=mean,
        scale=scale,
        weights=tuple(classifier.coefs_),
        biases=tuple(classifier.intercepts_),
        threshold=threshold,
        seed=seed,
        samples=len(np.unique(split["sample"])),
    )


def readings(model: GestureModel, split: dict[str, np.ndarray]) -> tuple[np.ndarray, list]:
    """Per sample: the true class index and its fused :class:`EyeReading`."""
    samples = np.unique(split["sample"])
    truth, out = [], []
    for sample in samples:
        rows = (split["sample"] == sample) & split["found"]
        if rows.any():
            p = fuse(model.probabilities(split["features"][rows]))
        else:
            p = np.zeros(len(CLASSES))
            p[CLASSES.index(NO_GESTURE)] = 1.0
        truth.append(int(split["label"][split["sample"] == sample][0]))
        out.append(EyeReading(p, (), model.threshold))
    return np.array(truth), out


@dataclass(frozen=True)
class Evaluation:
    """Held-out figures: 7-class confusion (+ discards) and the in-context confusions."""

    confusion: np.ndarray  # (7, 8) counts
    gestures: np.ndarray  # (4, 5) counts: true gesture x (4 gestures, discarded)
    feedback: np.ndarray  # (2, 3) counts: true thumb x (2 thumbs, discarded)
    samples: int

    @property
    def accuracy(self) -> float:
        """Share of samples read as their class (discards count as wrong)."""
        return float(np.trace(self.confusion[:, :-1]) / self.confusion.sum())

    @property
    def discard_rate(self) -> float:
        """Share of samples discarded (below the threshold)."""
        return float(self.confusion[:, -1].sum() / self.confusion.sum())

    @property
    def accepted_accuracy(self) -> float:
        """Accuracy among the readings kept."""
        kept = self.confusion[:, :-1].sum()
        return float(np.trace(self.confusion[:, :-1]) / kept) if kept else 0.0

    def detection_rate(self) -> float:
        """Share of instruction gestures read right in context (the paper's d)."""
        return float(np.trace(self.gestures[:, :-1]) / max(self.gestures.sum(), 1))


def _in_context(reading: EyeReading, classes: tuple[str, ...]) -> int:
    label, confidence = reading.among(classes)
    if label == NO_GESTURE or confidence < reading.threshold:
        return len(classes)
    return classes.index(label)


def evaluate(model: GestureModel, split: dict[str, np.ndarray]) -> Evaluation:
    """Confusions of ``model`` on ``split`` (see the module doc)."""
    truth, reads = readings(model, split)
    confusion = np.zeros((len(CLASSES), len(CLASSES) + 1), np.int64)
    gestures = np.zeros((4, 5), np.int64)
    feedback = np.zeros((2, 3), np.int64)
    for true, reading in zip(truth, reads, strict=True):
        column = (
            len(CLASSES) if reading.confidence < model.threshold else CLASSES.index(reading.label)
        )
        confusion[true, column] += 1
        name = CLASSES[true]
        if name in GESTURE_CLASSES:
            gestures[GESTURE_CLASSES.index(name), _in_context(reading, GESTURE_CLASSES)] += 1
        elif name in FEEDBACK_CLASSES:
            feedback[FEEDBACK_CLASSES.index(name), _in_context(reading, FEEDBACK_CLASSES)] += 1
    return Evaluation(confusion, gestures, feedback, len(truth))
