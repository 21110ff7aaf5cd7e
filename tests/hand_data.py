"""Hand readings for the webcam tests: the tracker's landmarks of real footage, and made-up hands.

``landmarks.npz`` (``tests/data/hands``, made by its ``make_data.py``) holds what the vendored
tracker read in headless chromium from frames of Apache-2.0 footage, with each frame's gesture.
:func:`synthetic_hand` draws a plain hand for gestures the footage lacks (pointing).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from robin_sim.live.hands.landmarks import HandInput

LANDMARKS = Path(__file__).resolve().parent / "data" / "hands" / "landmarks.npz"


def footage() -> dict[str, np.ndarray]:
    with np.load(LANDMARKS) as data:
        return {key: data[key] for key in data.files}


def usable(reads: dict[str, np.ndarray], sequence: str | None = None) -> list[int]:
    """Rows of ``reads`` (:func:`footage`) with a hand and finite landmarks, of ``sequence``
    only when given, in order."""
    rows = (
        range(len(reads["sequence"]))
        if sequence is None
        else (np.flatnonzero(reads["sequence"] == sequence))
    )
    return [
        int(i) for i in rows if np.isfinite(reads["landmarks"][i]).all() and reads["handedness"][i]
    ]


def hand_input(reads: dict[str, np.ndarray], row: int) -> HandInput:
    """Row ``row`` of ``reads`` as the session takes a reading (score 0.95)."""
    points = reads["landmarks"][row].astype(float)
    return HandInput(points, str(reads["handedness"][row]), 0.95, float(reads["aspect"][row]))


def message(
    points: np.ndarray | None,
    handedness: str = "Right",
    score: float = 0.95,
    aspect: float = 16 / 9,
) -> dict[str, Any]:
    """A hand message as the page sends it."""
    if points is None:
        return {
            "type": "hand",
            "landmarks": None,
            "handedness": None,
            "score": 0.0,
            "aspect": aspect,
        }
    return {
        "type": "hand",
        "landmarks": np.round(np.asarray(points, float), 5).tolist(),
        "handedness": handedness,
        "score": score,
        "aspect": aspect,
    }


def synthetic_hand(
    straight: tuple[bool, bool, bool, bool],
    thumb: str = "in",
    at: tuple[float, float] = (0.5, 0.7),
    size: float = 0.1,
) -> np.ndarray:
    """A right hand seen palm-on, fingers up, in image coordinates (aspect 1): ``straight``
    per finger (index to little); ``thumb`` "in" (folded), "up" or "down"."""
    points = np.zeros((21, 3))
    wrist = np.array([at[0], at[1], 0.0])
    points[0] = wrist
    for k, x in enumerate((-0.45, -0.15, 0.15, 0.45)):
        base = 1 + 4 * (k + 1)
        knuckle = wrist + size * np.array([x, -1.0, 0.0])
        points[base] = knuckle
        if straight[k]:
            steps = [np.array([0, -0.45, 0]), np.array([0, -0.8, 0]), np.array([0, -1.1, 0])]
        else:  # curled back towards the palm
            steps = [
                np.array([0, -0.35, -0.2]),
                np.array([0, -0.1, -0.3]),
                np.array([0, 0.15, -0.2]),
            ]
        for j, step in enumerate(steps):
            points[base + 1 + j] = knuckle + size * step
    thumb_base = wrist + size * np.array([-0.5, -0.3, 0.0])
    points[1] = wrist + size * np.array([-0.3, -0.1, 0.0])
    points[2] = thumb_base
    direction = {
        "in": np.array([0.25, -0.3, 0]),
        "up": np.array([-0.05, -0.8, 0]),
        "down": np.array([-0.05, 0.8, 0]),
    }[thumb]
    points[3] = thumb_base + size * direction
    points[4] = thumb_base + size * 2 * direction
    return points
