"""Where Robin's arm is when the person points: the arm states of an episode, reached by acting.

The pointing checks (``bench/bench_pointing_view.py``, ``tests/test_vision_view.py``) must see
the person's pointing hand with the arm where it really is during episodes, not only at home.
:func:`arm_states` walks one world through a handover to the palm and one to a spot, with the
person's body doing its part (the palm held out, slid under the held leg, the delivered leg
carried to the bin), and yields at each state the person may point in:

* ``home``: the arm at its home pose (a new table);
* ``object``: the open hand at a leg, ready to grasp it;
* ``close``: the hand closed on that leg, on the table;
* ``human``: the leg held above the person's palm;
* ``open``: after the open over the palm, the hand where it rests then;
* ``location``: a leg held above a table spot;
* ``placed``: after the open over that spot, the hand where it rests then.

Every step is a real action run by physics (:meth:`PhysicalWorld.execute`); nothing is placed
by hand. A step that fails raises, so a check never measures a state that was not reached.

:func:`away_qpos` is a what-if no episode reaches: the active arm swung back behind Robin, out
of its eyes' view, set by ``qpos`` for a kinematic render only. ``bench/bench_hand_hidden.py``
reads the data set's samples with it to measure what the arm at home hides.
"""

from __future__ import annotations

from collections.abc import Iterator

import mujoco
import numpy as np

from pil.errors import RobinPilError
from pil.task.world import Target
from pil.types import Action, Feedback, Gesture
from robin_sim.model import names
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

ARM_STATES = ("home", "object", "close", "human", "open", "location", "placed")
PALM_LEG, SPOT_LEG, SPOT = 0, 3, 1  # the leg handed over, the leg put down, and on which spot
# rad, the active arm's joints swung back behind Robin (the hand at about x -0.87 m, z 1.2 m)
AWAY_ARM_Q = (0.0, -1.5, 0.0, 0.0, 0.0, 0.0, 0.0)


def _act(
    world: PhysicalWorld,
    body: PhysicalBody,
    gesture: Gesture,
    action: Action,
    target: Target | None = None,
) -> None:
    """The person shows ``gesture``, the robot runs ``action``; raises if it did not work."""
    body.perform(gesture, target)
    outcome = world.execute(action, target)
    if not outcome.succeeded:
        raise RobinPilError(f"arm state: {action.value} on {target} failed: {outcome.detail}")
    body.show_feedback(Feedback.OK)
    body.after_feedback(Feedback.OK)


def arm_states(world: PhysicalWorld, body: PhysicalBody) -> Iterator[str]:
    """Bring ``world`` to each of :data:`ARM_STATES` in turn, yielding its name there.

    Between yields the caller may let the person point and Robin read (the arm does not move
    meanwhile); it should end with the person's hand at rest (``body.rest()``).
    """
    world.start_table(0)
    yield "home"
    _act(world, body, Gesture.POINTING, Action.OBJECT, Target("leg", PALM_LEG))
    yield "object"
    _act(world, body, Gesture.GRASP, Action.CLOSE)
    yield "close"
    _act(world, body, Gesture.GIVE_ME, Action.HUMAN)
    yield "human"
    _act(world, body, Gesture.RELEASE, Action.OPEN)
    yield "open"
    _act(world, body, Gesture.POINTING, Action.OBJECT, Target("leg", SPOT_LEG))
    _act(world, body, Gesture.GRASP, Action.CLOSE)
    _act(world, body, Gesture.POINTING, Action.LOCATION, Target("spot", SPOT))
    yield "location"
    _act(world, body, Gesture.RELEASE, Action.OPEN)
    yield "placed"


def on_table(world: PhysicalWorld, target: Target) -> bool:
    """Whether the person can point at ``target`` now: spots always, legs lying on the table
    and not in the robot's hand (a delivered leg is in the bin)."""
    if target.kind == "spot":
        return True
    return world.held_leg() != target.index and world.legs.graspable(target.index)


def reach_held_leg(world: PhysicalWorld, body: PhysicalBody) -> None:
    """Bring ``world`` to the ``human`` state by acting and let the person slide the palm under
    the held leg to show "release"; raises if Robin does not hold the leg there."""
    for state in arm_states(world, body):
        if state == "human":
            break
    body.perform(Gesture.RELEASE, None)
    if world.held_leg() != PALM_LEG:
        raise RobinPilError(f"held-leg state: Robin does not hold leg {PALM_LEG} over the palm")


def held_leg_qpos(model: mujoco.MjModel) -> np.ndarray:
    """``qpos`` for ``model`` (the default scene) with Robin holding a leg above the person's
    palm (:func:`reach_held_leg` in a fresh world); joints are matched by name."""
    world = PhysicalWorld()
    reach_held_leg(world, PhysicalBody(world))
    qpos = np.empty(model.nq)
    for joint in range(model.njnt):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        source = world.model.joint(name)
        size = len(source.qpos0)
        start = model.jnt_qposadr[joint]
        qpos[start : start + size] = world.data.qpos[source.qposadr[0] : source.qposadr[0] + size]
    return qpos


def away_qpos(model: mujoco.MjModel, home: np.ndarray) -> np.ndarray:
    """``home`` (a ``qpos`` of ``model``) with the active arm at :data:`AWAY_ARM_Q`: out of
    Robin's eyes' view (module doc; kinematics only, never simulated)."""
    qpos = home.copy()
    for joint, angle in zip(names.arm_joints(names.ACTIVE_SIDE), AWAY_ARM_Q, strict=True):
        qpos[model.jnt_qposadr[model.joint(joint).id]] = angle
    return qpos
