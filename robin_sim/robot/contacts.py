"""Contacts between Robin and the person, counted at every control tick (a safety figure).

:class:`PersonContacts` watches ``data.contact`` after each tick and counts *contact events*: a
pair (robot geom, person geom) touching at a tick where it did not touch at the tick before.
The robot is every body under ``torso``; the person is the ``human`` body, the mocap hand with
its forearm, and the collision palm welded to it. A leg lying on the palm is not the person.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.control.simulator import Simulator
from robin_sim.model import names


def _subtree(model: mujoco.MjModel, root: str) -> np.ndarray:
    """A mask over bodies: ``root`` and all its descendants."""
    top = model.body(root).id
    inside = np.zeros(model.nbody, bool)
    for body in range(model.nbody):
        b = body
        while b > 0 and b != top:
            b = int(model.body_parentid[b])
        inside[body] = b == top
    return inside


class PersonContacts:
    """Counts robot-person contact events in ``sim`` (see the module doc)."""

    def __init__(self, sim: Simulator) -> None:
        model = sim.model
        robot = _subtree(model, names.TORSO_BODY)
        person = np.zeros(model.nbody, bool)
        for root in names.PERSON_BODIES:
            person |= _subtree(model, root)
        self._robot = robot[model.geom_bodyid]
        self._person = person[model.geom_bodyid]
        self._touching: set[tuple[int, int]] = set()
        self.events = 0
        self.pairs: list[tuple[str, str, float]] = []  # first contact of each event: names, time
        sim.add_observer(self._after_tick)

    def _after_tick(self, sim: Simulator) -> None:
        n = sim.data.ncon
        if n == 0:
            self._touching.clear()
            return
        g1, g2 = sim.data.contact.geom1[:n], sim.data.contact.geom2[:n]
        hits = (self._robot[g1] & self._person[g2]) | (self._person[g1] & self._robot[g2])
        now = {(int(a), int(b)) for a, b in zip(g1[hits], g2[hits], strict=True)}
        for a, b in now - self._touching:
            self.events += 1
            model = sim.model
            self.pairs.append((model.geom(a).name, model.geom(b).name, round(sim.time, 3)))
        self._touching = now
