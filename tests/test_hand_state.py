"""The hand state read from contacts: free before a grasp, occupied after a real one, free after
opening. Runs real physics on the hand test bench; nothing is written to the leg's state."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from hand_bench import HandBench

from pil.types import Hand
from robin_sim.control.hand_state import HandSensor, grasped_leg, is_opposed, read_hand_state
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import build_model


class Bench(HandBench):
    """The hand test bench, reading the grasped leg while the hand moves up or down."""

    def move_z(self, delta: float, speed: float = 0.2) -> list[int | None]:
        """Move the hand vertically; returns the grasped leg read at every step."""
        seen: list[int | None] = []
        self.on_step.append(lambda: seen.append(self.sensor.grasped_leg(self.data)))
        try:
            self.move(2, delta, speed)
        finally:
            self.on_step.pop()
        return seen

    def lower_to_leg(self) -> None:
        self.descend_to_leg()


def test_free_before_occupied_after_grasp_free_after_opening() -> None:
    bench = Bench()
    model, data = bench.model, bench.data
    assert read_hand_state(model, data) is Hand.FREE
    bench.lower_to_leg()
    assert read_hand_state(model, data) is Hand.FREE  # open fingers around the leg
    assert grasped_leg(model, data) is None

    bench.data.ctrl[bench.hand] = spec.HAND_CLOSED_CTRL
    bench.run(spec.HAND_CLOSE_TIME)
    assert grasped_leg(model, data) == 0
    assert read_hand_state(model, data, "l") is Hand.OCCUPIED

    seen = bench.move_z(0.15)
    assert all(leg == 0 for leg in seen)  # held at every step of the lift
    assert data.body(names.leg_body(0)).xpos[2] > spec.GRASP_HEIGHT + 0.14

    bench.data.ctrl[bench.hand] = spec.HAND_OPEN_CTRL
    bench.run(spec.HAND_OPEN_TIME)
    assert bench.sensor.touching(data) == {}
    assert read_hand_state(model, data) is Hand.FREE
    bench.run(1.0)  # the leg fell back onto the table
    assert data.body(names.leg_body(0)).xpos[2] == pytest.approx(spec.GRASP_HEIGHT, abs=2e-3)


def test_closing_on_nothing_is_free() -> None:
    bench = Bench()
    bench.move_z(0.1)  # well above the leg
    bench.data.ctrl[bench.hand] = spec.HAND_CLOSED_CTRL
    bench.run(spec.HAND_CLOSE_TIME)
    assert bench.sensor.touching(bench.data) == {}
    assert read_hand_state(bench.model, bench.data) is Hand.FREE


def test_thumb_alone_pushing_the_leg_is_not_a_grasp() -> None:
    """Fingers 1 and 2 swing wide, the thumb closes and pushes the leg: one part touches."""
    bench = Bench()
    bench.lower_to_leg()
    for joint in ("l_f1_prox", "l_f2_prox"):
        bench.data.ctrl[bench.model.actuator(joint).id] = -1.2
    bench.run(0.3)
    for joint in ("l_thumb_prox", "l_thumb_dist"):
        index = names.hand_actuators("l").index(joint)
        bench.data.ctrl[bench.model.actuator(joint).id] = spec.HAND_CLOSED_CTRL[index]
    touched = set()
    for _ in range(500):
        mujoco.mj_step(bench.model, bench.data)
        touched |= set().union(*bench.sensor.touching(bench.data).values())
        assert bench.sensor.grasped_leg(bench.data) is None
    assert touched == {"thumb"}  # the thumb did reach the leg


def test_opposed_rule() -> None:
    assert is_opposed({"thumb", "f1"})
    assert is_opposed({"palm", "f2"})
    assert is_opposed({"thumb", "palm"})
    assert not is_opposed({"f1", "f2"})
    assert not is_opposed({"thumb"})


def test_scene_at_home_is_free_for_both_hands() -> None:
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    mujoco.mj_step(model, data)
    for side in names.SIDES:
        sensor = HandSensor(model, side)
        assert len(sensor.leg_body_ids) == 4
        assert sensor.touching(data) == {}
        assert sensor.hand(data) is Hand.FREE


def test_slip_speed_is_zero_for_a_leg_held_still() -> None:
    bench = Bench()
    bench.lower_to_leg()
    bench.data.ctrl[bench.hand] = spec.HAND_CLOSED_CTRL
    bench.run(spec.HAND_CLOSE_TIME)
    bench.move_z(0.1)
    bench.run(0.3)
    assert bench.sensor.slip_speed(bench.data, 0) < 1e-3
    assert np.isfinite(bench.sensor.slip_speed(bench.data, 0))
