"""The robot hand's state read back from physics: which table leg (if any) the hand holds.

A leg counts as held when, in ``data.contact``, it touches at least two distinct parts of the
hand among the thumb, finger 1, finger 2 and the palm, the thumb or the palm being one of
them (an opposed grasp), AND it moves with the hand: the leg's velocity differs from the
velocity of the palm's frame at the leg's centre by less than ``max_slip_speed``. Nothing is
kept between calls; there is no flag to forget to reset.

For a control loop build a :class:`HandSensor` once per model and call it every tick; the
module functions build one per call (a few microseconds more).
"""

from __future__ import annotations

import mujoco
import numpy as np

from pil.types import Hand
from robin_sim.model import names
from robin_sim.model.names import Side

MAX_SLIP_SPEED = 0.05  # m/s between the leg and the hand above which the leg is not held
PALM = "palm"
PARTS: tuple[str, ...] = (*names.FINGERS, PALM)  # f1, f2, thumb, palm
_THUMB = PARTS.index(names.THUMB)
_PALM = PARTS.index(PALM)


class HandSensor:
    """Reads one hand's grasp from a model's contacts (build once per model, call each tick)."""

    def __init__(self, model: mujoco.MjModel, side: Side = names.ACTIVE_SIDE) -> None:
        self.model = model
        self.side = side
        self.palm_id = model.body(names.hand_body(side)).id
        self.part_of_body = np.full(model.nbody, -1, dtype=np.int64)
        self.part_of_body[self.palm_id] = _PALM
        for k, finger in enumerate(names.FINGERS):
            for body in names.finger_bodies(side, finger):
                self.part_of_body[model.body(body).id] = k
        self.leg_of_body = np.full(model.nbody, -1, dtype=np.int64)
        self.leg_body_ids: list[int] = []
        while (
            bid := mujoco.mj_name2id(
                model, mujoco.mjtObj.mjOBJ_BODY, names.leg_body(len(self.leg_body_ids))
            )
        ) >= 0:
            self.leg_of_body[bid] = len(self.leg_body_ids)
            self.leg_body_ids.append(bid)
        self._vel = np.zeros(6)

    def touching(self, data: mujoco.MjData) -> dict[int, frozenset[str]]:
        """For each leg in contact with this hand: the hand parts (``PARTS``) it touches."""
        if data.ncon == 0:
            return {}
        bodies = self.model.geom_bodyid[data.contact.geom[: data.ncon]]
        parts = self.part_of_body[bodies]
        legs = self.leg_of_body[bodies]
        found: dict[int, set[str]] = {}
        for a, b in ((0, 1), (1, 0)):
            hits = np.flatnonzero((parts[:, a] >= 0) & (legs[:, b] >= 0))
            for row in hits:
                found.setdefault(int(legs[row, b]), set()).add(PARTS[parts[row, a]])
        return {leg: frozenset(p) for leg, p in found.items()}

    def slip_speed(self, data: mujoco.MjData, leg: int) -> float:
        """Speed (m/s) of leg ``leg``'s centre relative to the palm frame moving rigidly."""
        body = self.leg_body_ids[leg]
        mujoco.mj_objectVelocity(self.model, data, mujoco.mjtObj.mjOBJ_BODY, body, self._vel, 0)
        leg_lin = self._vel[3:].copy()
        mujoco.mj_objectVelocity(
            self.model, data, mujoco.mjtObj.mjOBJ_BODY, self.palm_id, self._vel, 0
        )
        offset = data.xpos[body] - data.xpos[self.palm_id]
        palm_lin = self._vel[3:] + np.cross(self._vel[:3], offset)
        return float(np.linalg.norm(leg_lin - palm_lin))

    def grasped_leg(
        self, data: mujoco.MjData, max_slip_speed: float = MAX_SLIP_SPEED
    ) -> int | None:
        """Index of the leg held in an opposed grasp that moves with the hand, else None."""
        best: tuple[int, float] | None = None
        for leg, parts in self.touching(data).items():
            if not is_opposed(parts):
                continue
            slip = self.slip_speed(data, leg)
            if slip < max_slip_speed and (best is None or slip < best[1]):
                best = (leg, slip)
        return None if best is None else best[0]

    def hand(self, data: mujoco.MjData) -> Hand:
        """``Hand.OCCUPIED`` while a leg is held, else ``Hand.FREE``."""
        return Hand.FREE if self.grasped_leg(data) is None else Hand.OCCUPIED


def is_opposed(parts: frozenset[str] | set[str]) -> bool:
    """Two distinct hand parts touch, one of them the thumb or the palm."""
    return len(parts) >= 2 and (names.THUMB in parts or PALM in parts)


def grasped_leg(model: mujoco.MjModel, data: mujoco.MjData, side: Side = "l") -> int | None:
    """Index of the table leg that hand ``side`` holds (see the module docstring), else None."""
    return HandSensor(model, side).grasped_leg(data)


def read_hand_state(model: mujoco.MjModel, data: mujoco.MjData, side: Side = "l") -> Hand:
    """The learner's hand state H for hand ``side``, read from the contacts in ``data``."""
    return HandSensor(model, side).hand(data)
