"""One hand reading from the page, checked, and its landmarks normalised for reading gestures.

The page sends each tracker reading as ``{"type": "hand", "landmarks": [[x, y, z] * 21] |
null, "handedness": "Left" | "Right" | null, "score": s, "aspect": w / h}``: MediaPipe's 21
landmarks in the camera image's own coordinates (x, y from 0 to 1 across the width and down the
height, z relative depth on x's scale), the tracker's handedness and its score, and the image's
aspect ratio. ``landmarks`` null is a reading in which no hand was found.

:func:`normalised` makes the shape comparable across people, places and hands: isotropic units
(x and z times the aspect), relative to the wrist, divided by the palm's size, and mirrored for
one handedness so a left and a right hand make the same numbers.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

POINTS = 21
HANDEDNESS = ("Left", "Right")
X_RANGE = (-1.0, 2.0)  # a landmark may lie a little outside the image (a finger beyond the edge)
Z_RANGE = (-2.0, 2.0)
ASPECT_RANGE = (0.25, 4.0)
WRIST, THUMB_TIP, INDEX_TIP = 0, 4, 8
KNUCKLES = (5, 9, 13, 17)  # the knuckles: their mean distance from the wrist is the palm's size
MIRRORED = "Left"  # the handedness whose x is flipped (either would do; one is needed)


class HandError(ValueError):
    """A hand reading that does not fit the contract (the message says which part)."""


@dataclass(frozen=True, slots=True)
class HandInput:
    """One checked reading: ``points`` (21, 3) in image coordinates, or None (no hand)."""

    points: np.ndarray | None
    handedness: str | None
    score: float
    aspect: float

    @property
    def found(self) -> bool:
        return self.points is not None

    def as_dict(self) -> dict[str, Any]:
        """The message as the page sends it (landmarks rounded as sent)."""
        marks = None if self.points is None else np.round(self.points, 5).tolist()
        return {
            "type": "hand",
            "landmarks": marks,
            "handedness": self.handedness,
            "score": self.score,
            "aspect": self.aspect,
        }


def _number(value: object, what: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise HandError(f"hand: {what} must be a number in [{low}, {high}], got {value!r:.40}")
    number = float(value)
    if not math.isfinite(number) or not low <= number <= high:
        raise HandError(f"hand: {what} = {value!r:.40} is outside [{low}, {high}]")
    return number


def check_hand(message: Mapping[str, Any]) -> HandInput:
    """The reading in ``message`` (its fields already known to be exactly the contract's);
    :class:`HandError` names the first part that is wrong."""
    aspect = _number(message["aspect"], "aspect", *ASPECT_RANGE)
    score = _number(message["score"], "score", 0.0, 1.0)
    marks, side = message["landmarks"], message["handedness"]
    if marks is None:
        if side is not None:
            raise HandError("hand: handedness must be null when landmarks is null (no hand)")
        return HandInput(None, None, score, aspect)
    if side not in HANDEDNESS:
        raise HandError(f"hand: handedness {side!r:.20} is unknown; valid: 'Left', 'Right'")
    if not isinstance(marks, list) or len(marks) != POINTS:
        got = len(marks) if isinstance(marks, list) else type(marks).__name__
        raise HandError(f"hand: landmarks must be a list of {POINTS} [x, y, z] points, got {got}")
    points = np.empty((POINTS, 3))
    for k, point in enumerate(marks):
        if not isinstance(point, list) or len(point) != 3:
            raise HandError(f"hand: landmark {k} must be [x, y, z], got {point!r:.40}")
        for j, (value, axis) in enumerate(zip(point, "xyz", strict=True)):
            low, high = Z_RANGE if axis == "z" else X_RANGE
            points[k, j] = _number(value, f"landmark {k} {axis}", low, high)
    return HandInput(points, str(side), score, aspect)


def normalised(points: np.ndarray, handedness: str | None, aspect: float) -> np.ndarray:
    """(21, 3): wrist at the origin, palm size 1, isotropic, one handedness mirrored; image
    axes kept (y down), so a thumb up and a thumb down differ."""
    shape = np.asarray(points, float).copy()
    shape[:, 0] *= aspect
    shape[:, 2] *= aspect
    shape -= shape[WRIST]
    size = float(np.mean(np.linalg.norm(shape[list(KNUCKLES)], axis=1)))
    shape /= max(size, 1e-6)
    if handedness == MIRRORED:
        shape[:, 0] *= -1
    return shape


def features(shape: np.ndarray) -> np.ndarray:
    """The feature vector of a normalised shape: x and y of the 20 points after the wrist
    (the tracker's depth is the least reliable coordinate and is left out)."""
    return np.asarray(shape, float)[1:, :2].ravel()
