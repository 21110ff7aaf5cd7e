"""A person's own gestures, learnt one-shot and on the fly: k nearest neighbours over shapes.

:class:`Appearance` starts from one example per gesture (the calibration at the start of a
session) and takes every reading the participant later confirms (an approved action) or
corrects (the gesture they made instead), so it follows how this person makes each gesture.
Plain NumPy (a few hundred examples at most: a distance to each is quicker than a fitted
index). A reading's confidence is its margin: ``1 - d_best / d_other``, where ``d_best`` is the
distance to the nearest example of the predicted gesture and ``d_other`` to the nearest example
of any other gesture (0: halfway between two gestures; near 1: close to one, far from the rest).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

NEIGHBOURS = 3  # at most; fewer while a gesture has fewer examples
MAX_EXAMPLES = 400  # per gesture: the oldest confirmed ones go first (calibration stays)


class Appearance:
    """The per-person classifier (see the module doc)."""

    def __init__(self) -> None:
        self.examples: dict[str, list[np.ndarray]] = {}
        self.seeded: set[str] = set()  # gestures with a calibration example
        self._model: tuple[np.ndarray, np.ndarray] | None = None  # examples, label indices

    @property
    def gestures(self) -> tuple[str, ...]:
        return tuple(sorted(self.examples))

    @property
    def size(self) -> int:
        return sum(len(v) for v in self.examples.values())

    def seed(self, label: str, features: np.ndarray) -> None:
        """The calibration example of ``label`` (replaces an earlier one)."""
        kept = [f for f in self.examples.get(label, [])[1:]] if label in self.seeded else []
        self.examples[label] = [np.asarray(features, float), *kept]
        self.seeded.add(label)
        self._model = None

    def add(self, label: str, features: np.ndarray) -> None:
        """A confirmed or relabelled reading of ``label``."""
        examples = self.examples.setdefault(label, [])
        examples.append(np.asarray(features, float))
        first = 1 if label in self.seeded else 0
        while len(examples) > MAX_EXAMPLES:
            examples.pop(first)
        self._model = None

    def _fitted(self) -> tuple[np.ndarray, np.ndarray] | None:
        if len(self.examples) < 2:
            return None
        if self._model is None:
            names = self.gestures
            data = np.array([f for label in names for f in self.examples[label]])
            index = np.array([k for k, label in enumerate(names) for _ in self.examples[label]])
            self._model = (data, index)
        return self._model

    def predict(self, features: np.ndarray) -> tuple[str | None, float]:
        """(gesture, margin in [0, 1]); (None, 0.0) with fewer than two gestures known. The
        gesture is the distance-weighted vote of the k nearest examples, k the smaller of
        :data:`NEIGHBOURS` and the fewest examples a gesture has."""
        model = self._fitted()
        if model is None:
            return None, 0.0
        data, index = model
        names = self.gestures
        distances = np.linalg.norm(data - np.asarray(features, float), axis=1)
        k = max(1, min(NEIGHBOURS, min(len(v) for v in self.examples.values())))
        nearest = np.argsort(distances)[:k]
        votes = np.bincount(
            index[nearest], 1.0 / np.maximum(distances[nearest], 1e-9), minlength=len(names)
        )
        best = int(np.argmax(votes))
        own = float(distances[index == best].min())
        other = float(distances[index != best].min())
        return names[best], float(np.clip(1.0 - own / max(other, 1e-9), 0.0, 1.0))

    def predict_many(self, rows: Sequence[np.ndarray]) -> list[tuple[str | None, float]]:
        return [self.predict(row) for row in rows]
