"""Interruptible motion: joint plans and finger ramps played tick by tick, asking ``stop``.

The robot's actions (:mod:`robin_sim.robot.actions`) run through these so that the person can
stop them at any control tick: :func:`play` halts the arm where it is, :func:`ramp_fingers`
ramps the fingers back to where they were.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from robin_sim.control.ik import JointPlan
from robin_sim.control.simulator import Simulator

FINGER_REST_SPEED = 0.05  # rad/s: fingers count as settled below this joint speed
HALT_SETTLE = 0.2  # s the arm is given to come to rest after a stop, before the undo
FINGER_UNDO_TIME = 0.4  # s the fingers take to ramp back after a stop
Stop = Callable[[], bool]  # the person's thumb down, asked once per control tick


def never() -> bool:
    """A ``stop`` that never stops (nobody watching)."""
    return False


def fingers_settled(sim: Simulator) -> bool:
    """True when the finger ramp has ended and the finger joints have nearly stopped."""
    if sim.hand.busy(sim.time):
        return False
    speeds = sim.data.qvel[sim.hand.joint_dofs]
    return bool(np.max(np.abs(speeds)) < FINGER_REST_SPEED)


def play(sim: Simulator, plan: JointPlan, stop: Stop) -> int | None:
    """Play ``plan`` tick by tick; None when it ran to its end, else the ticks played when
    ``stop()`` said stop (the arm then holds its last targets)."""
    if stop():
        return 0
    sim.play(plan)
    played = 0
    while sim.moving:
        sim.tick()
        played += 1
        if stop():
            sim.halt()
            return played
    return None


def ramp_fingers(
    sim: Simulator,
    goal: np.ndarray,
    duration: float,
    stop: Stop,
    limit: float,
    back_to: np.ndarray | None = None,
) -> bool:
    """Ramp the fingers to ``goal`` and wait until they settle; False when ``stop()`` said stop
    on the way (the fingers then ramp back to ``back_to``, default where they were)."""
    before = sim.hand.command if back_to is None else back_to
    if stop():
        return _fingers_back(sim, before, limit)
    sim.hand.move_to(goal, sim.time, duration)
    end = sim.time + limit
    while sim.time < end - 1e-9:
        sim.tick()
        if stop():
            return _fingers_back(sim, before, limit)
        if fingers_settled(sim):
            break
    return True


def hold_fingers(sim: Simulator, seconds: float, stop: Stop, back_to: np.ndarray) -> bool:
    """Keep the fingers as they are for ``seconds``; False (fingers back to ``back_to``) when
    ``stop()`` said stop meanwhile."""
    end = sim.time + seconds
    while sim.time < end - 1e-9:
        sim.tick()
        if stop():
            return _fingers_back(sim, back_to, 2.0)
    return True


def _fingers_back(sim: Simulator, targets: np.ndarray, limit: float) -> bool:
    sim.hand.move_to(targets, sim.time, FINGER_UNDO_TIME)
    sim.step_until(fingers_settled, limit)
    return False
