"""``live --webcam --detector vision``: Robin reads the mirrored hand with its own eye cameras.

:class:`EyeWatch` runs on the physics thread (a controller of the simulator, after the
:class:`~robin_sim.live.mirror.HandMirror`): after each landmark reading the mirror applied,
at most every :data:`LOOK_GAP_S` simulated seconds, both eyes render the scene with the head
aimed at the person's palm (in a copy of the state: the session's head, arms and legs are not
moved) and the eye-camera model reads the hand (:func:`robin_sim.vision.reader.read_views`,
the same reader as the vision episodes). Each look is recorded with its class of all seven and
its confidence. While the participant's gesture is awaited, a look whose best class of all
seven is an instruction gesture (give me, grasp, release) that clears the model's threshold is
offered as the participant's gesture (a thumb or no gesture offers nothing): the learner
learns from what Robin saw, not from the landmarks' decision.

What stays with the landmarks: pointing (its target is the page's fingertip cursor, which
Robin's eyes cannot give) and the thumbs that judge an action (the feedback channel; Robin's
looks during an action are recorded, not acted on).

A look is not offered while the landmarks' newest reading with a hand is a thumb
(:func:`offer_from`; ``Look.withheld``): the thumbs belong to the landmarks, and a thumb up
held at the palm after a give me was read by the eyes as release in 18 of 27 looks of the
footage (``bench/bench_mirror_eyes.py --at-palm``). This assumes the landmarks read a thumb
only when a thumb is shown (they read the footage's fist, palm and thumbs right); a hand they
misread as a thumb holds the eyes' offers back until they read it otherwise, and the count
says how often.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from pil.types import Gesture
from robin_sim.control.simulator import Simulator
from robin_sim.live.inputs import GESTURE_BY_KEY
from robin_sim.live.mirror import HandMirror
from robin_sim.live.participant import Gesturing, LiveParticipant
from robin_sim.model import names
from robin_sim.vision.classifier import load_shipped
from robin_sim.vision.dataset import THUMB_SIGNS
from robin_sim.vision.eyes import EyeCameras, EyeCondition
from robin_sim.vision.reader import aim_and_see, read_views

LOOK_GAP_S = 0.2  # s (simulated) at least between two looks
# what Robin's eyes may offer as the participant's gesture (pointing needs the cursor's target)
EYE_GESTURES: dict[str, Gesture] = GESTURE_BY_KEY  # give me, grasp, release (by sign name)
KEPT_LOOKS = 500


def offer_from(
    label: str, confidence: float, threshold: float, phase: str, landmarks: str | None
) -> tuple[Gesture | None, bool]:
    """What a look of ``label`` (of all seven) at ``confidence`` offers as the participant's
    gesture in ``phase``, ``landmarks`` being the landmarks' label of their newest reading with
    a hand, and whether an offer was withheld because the landmarks read a thumb (module
    doc)."""
    if phase != "waiting_for_gesture" or label not in EYE_GESTURES or confidence < threshold:
        return None, False
    if landmarks in THUMB_SIGNS:
        return None, True
    return EYE_GESTURES[label], False


@dataclass(frozen=True)
class Look:
    """One look: when (sim s), the reading of all seven classes, and what was offered."""

    sim_time: float
    label: str
    confidence: float
    found: bool  # an eye found a hand
    offered: str | None  # the gesture offered to the participant (None: none)
    withheld: bool = False  # an offer held back: the landmarks read a thumb

    def as_dict(self) -> dict[str, Any]:
        return {
            "sim_time": round(self.sim_time, 4),
            "label": self.label,
            "confidence": round(self.confidence, 4),
            "found": self.found,
            "offered": self.offered,
            "withheld": self.withheld,
        }


class EyeWatch:
    """Robin's eyes on the mirrored hand of a live session (see the module doc)."""

    def __init__(
        self, model: mujoco.MjModel, data: mujoco.MjData, mirror: HandMirror, seed: int = 0
    ) -> None:
        self.model, self.data, self.mirror = model, data, mirror
        self.participant: LiveParticipant | None = None  # set once the participant exists
        # the landmarks' label of the newest reading with a hand (the session's webcam); None: none
        self.landmarks: Callable[[], str | None] = lambda: None
        self.eyes = EyeCameras(model)
        self.gesture_model = load_shipped()
        self.view = mujoco.MjData(model)
        self.rng = np.random.default_rng([seed, 31])
        self._seen = 0  # the mirror's readings looked at
        self._last = -np.inf
        self.looks: list[Look] = []
        self.counts: Counter[str] = Counter()
        self.offered = 0
        self.withheld = 0  # offers held back: the landmarks read a thumb
        self.last_view: np.ndarray | None = None

    def tick(self, sim: Simulator) -> None:
        """Look when the mirror applied a reading since the last look (a controller)."""
        if self.mirror.readings == self._seen or sim.time - self._last < LOOK_GAP_S:
            return
        self._seen, self._last = self.mirror.readings, sim.time
        sim.prepare_view()  # the person's arm follows the hand before the eyes look
        self.look(sim.time)

    def look(self, now: float) -> Look:
        """Render both eyes aimed at the palm (in a copy of the state) and read the hand."""
        view = self.view
        mujoco.mj_copyData(view, self.model, self.data)
        mujoco.mj_kinematics(self.model, view)
        target = view.site(names.HUMAN_PALM_SITE).xpos.copy()
        views, depths = aim_and_see(self.eyes, view, target, EyeCondition(), self.rng)
        reading = read_views(self.gesture_model, views, depths)
        self.last_view = views[0].rgb
        offered, withheld = None, False
        participant = self.participant
        if participant is not None:
            gesture, withheld = offer_from(  # of all seven classes
                reading.label,
                reading.confidence,
                reading.threshold,
                participant.phase,
                self.landmarks(),
            )
            if gesture is not None:
                participant.offer(Gesturing(gesture))
                offered = reading.label
                self.offered += 1
            self.withheld += withheld
        look = Look(
            now,
            reading.label,
            reading.confidence,
            any(b is not None for b in reading.boxes),
            offered,
            withheld,
        )
        self.looks.append(look)
        del self.looks[:-KEPT_LOOKS]
        self.counts[look.label] += 1
        return look

    def summary(self) -> dict[str, Any]:
        """What Robin's eyes read of the mirrored hand over the session."""
        return {
            "looks": sum(self.counts.values()),
            "read": dict(self.counts),
            "offered": self.offered,
            "withheld": self.withheld,
        }

    def close(self) -> None:
        """Free the eye cameras' OpenGL context."""
        self.eyes.close()
