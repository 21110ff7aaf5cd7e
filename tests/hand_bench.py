"""Test helper (not a test file): the hand test bench driven by min-jerk slide moves.

The hand hangs palm down on three position-controlled slides (``bench_x/y/z``) above a table
with one leg; nothing but contact forces holds the leg.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np

from robin_sim.control.hand_state import HandSensor
from robin_sim.control.trajectory import min_jerk
from robin_sim.model import names
from robin_sim.model import robot_spec as spec


class HandBench:
    """``models/hand_test_scene.xml`` at its home keyframe, settled for 0.3 s."""

    def __init__(self) -> None:
        self.model = mujoco.MjModel.from_xml_path(str(names.HAND_TEST_SCENE_XML))
        self.data = mujoco.MjData(self.model)
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.model.key(names.HOME_KEY).id)
        self.slides = [self.model.actuator(a).id for a in names.HAND_TEST_SLIDES]
        self.hand = [self.model.actuator(a).id for a in names.hand_actuators("l")]
        self.palm = self.model.body(names.hand_body("l")).id
        self.leg = self.model.body(names.leg_body(0)).id
        self.leg_geom = self.model.geom(names.leg_geom(0)).id
        self.sensor = HandSensor(self.model, "l")
        self.on_step: list[Callable[[], None]] = []  # called after every physics step
        self.run(0.3)

    def step(self) -> None:
        mujoco.mj_step(self.model, self.data)
        for callback in self.on_step:
            callback()

    def run(self, seconds: float) -> None:
        for _ in range(round(seconds / self.model.opt.timestep)):
            self.step()

    def move(self, axis: int, delta: float, speed: float) -> None:
        """Min-jerk move of slide ``axis`` by ``delta`` metres with peak speed ``speed``."""
        act = self.slides[axis]
        start = self.data.ctrl[act]
        steps = max(round(1.875 * abs(delta) / speed / self.model.opt.timestep), 1)
        for k in range(1, steps + 1):
            self.data.ctrl[act] = start + delta * min_jerk(k / steps)
            self.step()

    def command_hand(self, ctrl: tuple[float, ...]) -> None:
        self.data.ctrl[self.hand] = ctrl

    def descend_to_leg(self) -> None:
        """Lower the open hand until the grasp site is at the height of the leg's axis."""
        site = self.data.site(names.grasp_site("l")).xpos
        self.move(2, float(self.data.xpos[self.leg][2] - site[2]), 0.1)
        self.run(0.2)

    def grasp(self) -> None:
        self.descend_to_leg()
        self.command_hand(spec.HAND_CLOSED_CTRL)
        self.run(spec.HAND_CLOSE_TIME)

    def leg_in_palm(self) -> np.ndarray:
        """The leg's centre in the palm frame."""
        rot = self.data.xmat[self.palm].reshape(3, 3)
        return rot.T @ (self.data.xpos[self.leg] - self.data.xpos[self.palm])
