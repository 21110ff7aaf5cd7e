"""While the participant's hand is mirrored, the person holds it up where Robin reads signs.

A participant shows a sign to the webcam at face height, but the scripted body's hand at rest
hangs by the hip (mocap about 1.22, 0.28, 0.92 m). The mirror (:mod:`.mirror`) turns that hand
as the participant's is turned, so a fist held up (fingers up) hung there with the forearm
folded back over it, and Robin's eyes read it as a thumb down. :class:`ShowHand` raises the
idle hand to the place where the scripted person holds a sign up to be read, the data set's
"drawn back, raised" place (:func:`robin_sim.vision.dataset.drawn_back` of the rest place:
``PERSON_CLEAR_X`` from Robin, ``POINT_RAISE`` higher), as soon as a participant's reading
drives the hand and the hand is idle at rest. It is a planned motion of the person's mocap
hand (:meth:`~robin_sim.control.human_hand.HumanHand.follow`) at the body's own speed, as every
move the scripted person makes: the body's next move (a palm held out, a pointing) starts from
there, and a hand the body brings back to rest is raised again while the mirror drives it.
"""

from __future__ import annotations

import mink
import numpy as np

from robin_sim.control.human_hand import HumanHand
from robin_sim.control.simulator import Simulator
from robin_sim.live.mirror import HandMirror
from robin_sim.vision.dataset import drawn_back

AT_REST = 0.005  # m: the hand counts as at rest within this of its rest place


class ShowHand:
    """Raises the idle, mirrored hand from rest to where signs are read (module doc)."""

    def __init__(self, hand: HumanHand, mirror: HandMirror, speed: float) -> None:
        self.hand, self.mirror, self.speed = hand, mirror, speed
        rest = hand.rest_pose
        self.rest = rest.translation().copy()
        self.place = mink.SE3.from_rotation_and_translation(rest.rotation(), drawn_back(self.rest))
        self.raised = 0  # times the hand was raised

    def tick(self, sim: Simulator) -> None:
        """Start the raise when the mirror drives an idle hand at rest (a controller)."""
        if not self.mirror.active or self.hand.busy(sim.time):
            return
        if float(np.linalg.norm(self.hand.pose().translation() - self.rest)) > AT_REST:
            return
        self.hand.follow([self.place], sim.time, self.speed)
        self.raised += 1
