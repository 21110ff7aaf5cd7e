"""A gesture from the hand's shape alone, before a person's own examples are known.

On a normalised hand (:func:`~.landmarks.normalised`: wrist at the origin, palm size 1, image
axes, y down) each finger's extension is the distance of its tip from the wrist over that of
its middle joint: about 1.3 when straight, below 1 when curled. The thumb's lead is how far
its tip lies above every other point of the hand (thumb up), or below (thumb down), in palm
sizes. Soft memberships (0..1) of each gesture follow:

* the four fingers straight (an open hand): fingers up is **release** (an opened hand), any
  other way is **give me** (the palm held out);
* the thumb's tip above all the rest, middle, ring and little fingers curled: **thumb up**;
  below all the rest: **thumb down** (the index is left out: the tracker often reads it
  half-straight in a thumb up);
* only the index straight, the thumb not leading: **pointing**;
* all four curled, the thumb not leading: a fist, **grasp**.

The reading's certainty is the winner's membership times the square root of its lead over the
runner-up (0 when two gestures fit equally).
"""

from __future__ import annotations

import numpy as np

from pil.types import SIGN_NAMES, SIGN_OF, Feedback, Gesture
from robin_sim.live.hands.landmarks import THUMB_TIP

# the six signs (pil.types), pointing last: the reader's order (its calibration's too)
POINTING_SIGN = SIGN_OF[Gesture.POINTING]  # the sign that moves the cursor
GESTURE_NAMES: tuple[str, ...] = (*(n for n in SIGN_NAMES if n != POINTING_SIGN), POINTING_SIGN)
FINGER_JOINTS = ((5, 6, 8), (9, 10, 12), (13, 14, 16), (17, 18, 20))  # knuckle, middle joint, tip
STRAIGHT = (1.12, 0.06)  # extension at which a finger counts half straight, and the softness
THUMB_LEAD = (0.25, 0.1)  # palm sizes the thumb's tip leads the rest by to count half a thumb
FINGERS_UP = (0.45, 0.15)  # -y of the hand's unit direction (wrist to middle knuckle)


def _soft(value: float, centre: float, width: float) -> float:
    return float(1.0 / (1.0 + np.exp(-(value - centre) / width)))


def extensions(shape: np.ndarray) -> np.ndarray:
    """Each finger's tip-to-wrist over middle-joint-to-wrist distance (index to little)."""
    norms = np.linalg.norm(shape[:, :2], axis=1)
    return np.array([norms[tip] / max(norms[mid], 1e-6) for _, mid, tip in FINGER_JOINTS])


def thumb_leads(shape: np.ndarray) -> tuple[float, float]:
    """(up, down): how far the thumb's tip lies above / below every finger point (palm sizes)."""
    ys = shape[5:, 1]
    tip = float(shape[THUMB_TIP, 1])
    return float(ys.min()) - tip, tip - float(ys.max())


def memberships(shape: np.ndarray) -> dict[str, float]:
    """How much the shape looks like each gesture (0..1)."""
    straight = [_soft(e, *STRAIGHT) for e in extensions(shape)]
    curled = [1.0 - s for s in straight]
    lead_up, lead_down = thumb_leads(shape)
    up, down = _soft(lead_up, *THUMB_LEAD), _soft(lead_down, *THUMB_LEAD)
    thumb = max(up, down)
    hand = shape[9, :2] / max(float(np.linalg.norm(shape[9, :2])), 1e-6)
    raised = _soft(-float(hand[1]), *FINGERS_UP)
    open_hand = min(straight)
    three_curled = min(curled[1:])
    return {
        SIGN_OF[Gesture.GIVE_ME]: open_hand * (1.0 - raised),
        SIGN_OF[Gesture.RELEASE]: open_hand * raised,
        SIGN_OF[Feedback.OK]: three_curled * up,
        SIGN_OF[Feedback.NOT_OK]: three_curled * down,
        SIGN_OF[Gesture.POINTING]: min(straight[0], three_curled) * (1.0 - thumb),
        SIGN_OF[Gesture.GRASP]: min(curled) * (1.0 - thumb),
    }


def read_shape(shape: np.ndarray) -> tuple[str, float]:
    """(gesture, certainty in [0, 1]) of a normalised hand."""
    scores = memberships(shape)
    ranked = sorted(scores.items(), key=lambda item: item[1], reverse=True)
    (best, top), (_, second) = ranked[0], ranked[1]
    return best, float(top * (1.0 - second / max(top, 1e-9)) ** 0.5)
