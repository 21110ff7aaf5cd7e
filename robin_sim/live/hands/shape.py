"""A gesture from the hand's shape alone, before a person's own examples are known.

On a normalised hand (:func:`~.landmarks.normalised`: wrist at the origin, palm size 1, image
axes, y down) each finger's extension is the distance of its tip from the wrist over that of
its middle joint: well above 1 when straight, below when curled. Soft memberships (0..1) of
each gesture follow from the extensions, the thumb's direction and the hand's direction:

* open hand (four fingers straight): fingers up is **release** (an opened hand), otherwise the
  palm held out is **give me**;
* only the index straight: **pointing**;
* no finger straight, the thumb out and up: **thumb up**; out and down: **thumb down**;
  otherwise a fist: **grasp**.

The reading's certainty is the winner's membership times its lead over the runner-up.
"""

from __future__ import annotations

import numpy as np

GESTURE_NAMES = ("give_me", "grasp", "release", "thumb_up", "thumb_down", "pointing")
FINGERS = ((5, 6, 8), (9, 10, 12), (13, 14, 16), (17, 18, 20))  # knuckle, middle joint, tip
THUMB = (2, 4)  # its knuckle and tip
STRAIGHT = (1.05, 0.12)  # extension ratio at which a finger counts half straight, and its width
THUMB_OUT = (0.55, 0.15)  # thumb tip's distance beyond the index knuckle (palm sizes)
VERTICAL = (0.5, 0.15)  # |y| of the thumb's unit direction at which it counts half vertical
FINGERS_UP = (-0.45, 0.15)  # y of the hand's unit direction (wrist to middle knuckle)


def _soft(value: float, centre: float, width: float) -> float:
    return float(1.0 / (1.0 + np.exp(-(value - centre) / width)))


def extensions(shape: np.ndarray) -> np.ndarray:
    """Each finger's tip-to-wrist over middle-joint-to-wrist distance (index to little)."""
    norms = np.linalg.norm(shape[:, :2], axis=1)
    return np.array([norms[tip] / max(norms[mid], 1e-6) for _, mid, tip in FINGERS])


def memberships(shape: np.ndarray) -> dict[str, float]:
    """How much the shape looks like each gesture (0..1)."""
    straight = [_soft(e, *STRAIGHT) for e in extensions(shape)]
    curled = [1.0 - s for s in straight]
    knuckle, tip = shape[THUMB[0], :2], shape[THUMB[1], :2]
    out = _soft(float(np.linalg.norm(shape[THUMB[1], :2] - shape[5, :2])), *THUMB_OUT)
    direction = (tip - knuckle) / max(float(np.linalg.norm(tip - knuckle)), 1e-6)
    up = _soft(-float(direction[1]), *VERTICAL)
    down = _soft(float(direction[1]), *VERTICAL)
    hand = shape[9, :2] / max(float(np.linalg.norm(shape[9, :2])), 1e-6)
    raised = _soft(-float(hand[1]), -FINGERS_UP[0], FINGERS_UP[1])
    open_hand = min(straight)
    fist = min(curled)
    return {
        "give_me": open_hand * (1.0 - raised),
        "release": open_hand * raised,
        "pointing": min(straight[0], *curled[1:]),
        "thumb_up": fist * out * up,
        "thumb_down": fist * out * down,
        "grasp": fist * (1.0 - out * max(up, down)),
    }


def read_shape(shape: np.ndarray) -> tuple[str, float]:
    """(gesture, certainty in [0, 1]) of a normalised hand."""
    scores = memberships(shape)
    ranked = sorted(scores.items(), key=lambda item: item[1], reverse=True)
    (best, top), (_, second) = ranked[0], ranked[1]
    return best, float(top * (1.0 - second / max(top, 1e-9)) ** 0.5)
