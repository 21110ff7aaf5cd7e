"""Which robot action a learner's action becomes in the scene, and where it goes.

"object" goes to a leg (grasped where physics has it now; with a leg already in the hand, above
the pointed spot or leg) or keeps the wrist's yaw over a pointed spot; "human" goes to the
person's palm when it is held out (the layout's handover point when not); "location" to the
pointed spot; "open" lets a held leg go at the :class:`ReleasePlace` the last move reached.
Paths lift, traverse at :data:`CLEARANCE_Z` and descend.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Protocol

import mink
import numpy as np

from pil.task.world import Target
from pil.types import Action
from robin_sim.control.human_hand import HumanHand
from robin_sim.control.simulator import Simulator
from robin_sim.control.trajectory import pose
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout
from robin_sim.robot.actions import (
    CloseAction,
    Context,
    MoveAction,
    OpenAction,
    RobotAction,
    leg_offset_in_site,
)
from robin_sim.robot.table_legs import TableLegs
from robin_sim.robot.targets import (
    check_leg,
    grasp_goal,
    location_surface,
    release_goal,
    target_point,
)

CLEARANCE_Z = 0.95  # m: grasp-site height of traverses (a held leg clears legs and the palm)
DROP_GAP = 0.012  # m between a released leg's underside and what it lands on
FREE_HAND_ABOVE = 0.10  # m above the palm / spot an empty hand goes to
PALM_OUT_RADIUS = 0.02  # m: a palm this close to the handover point counts as held out
HANDOVER_TOLERANCE = 0.03  # m, leg centre to palm centre, horizontally
PLACEMENT_TOLERANCE = 0.02  # m, leg centre to the pointed spot, horizontally


@dataclass(frozen=True, slots=True)
class ReleasePlace:
    """Where an "open" would let the held leg go: the person's palm or a table spot."""

    point: np.ndarray  # the surface point below the held leg, m (world frame)
    kind: Literal["palm", "spot"]

    @property
    def tolerance(self) -> float:
        """How far (m, horizontally) the released leg's centre may come to rest from ``point``."""
        return HANDOVER_TOLERANCE if self.kind == "palm" else PLACEMENT_TOLERANCE

    @property
    def name(self) -> str:
        """How messages name the place."""
        return "the palm centre" if self.kind == "palm" else "the spot"


class PlanningScene(Protocol):
    """What planning reads of the world (:class:`robin_sim.robot.world.PhysicalWorld`)."""

    sim: Simulator
    layout: SceneLayout
    human: HumanHand
    ctx: Context
    speed: float
    legs: TableLegs

    def held_leg(self) -> int | None: ...
    def palm_is_out(self) -> bool: ...


def make_action(
    world: PlanningScene, action: Action, target: Target | None, release: ReleasePlace | None
) -> RobotAction:
    """The robot action for ``action`` on ``target`` in ``world`` (an open lets go at
    ``release``); changes nothing."""
    if action is Action.CLOSE:
        return CloseAction()
    if action is Action.OPEN:
        if release is None:
            return OpenAction()
        return OpenAction(
            release.point, release.tolerance, place=release.name, rest_height=spec.LEG_RADIUS
        )
    current = world.sim.commanded_site_pose()
    held = world.held_leg()
    if action is Action.OBJECT:
        if target is not None and target.kind != "leg":  # a spot: keep the wrist's yaw
            where = target_point(target, world.layout, world.legs.position, world.legs.nearest)
            axis, name = current.rotation().as_matrix()[:, 1], "the pointed spot"
        else:
            leg = (
                world.legs.nearest()
                if target is None
                else check_leg(target.index, world.legs.count)
            )
            (where, axis), name = world.legs.grasp_place(leg), f"leg {leg}"
        height = 0.0 if held is None else FREE_HAND_ABOVE
        goal = grasp_goal(where, axis, current, height)
        to_grasp = held is None and name != "the pointed spot"
        return MoveAction(Action.OBJECT, name, goal, CLEARANCE_Z, world.speed, open_hand=to_grasp)
    if action is Action.HUMAN:
        surface = world.human.palm_centre() if world.palm_is_out() else world.layout.handover
        surface = np.asarray(surface, float)
        name = "the person's palm"
    else:
        near = world.sim.site_pose().translation()
        if target is not None and target.kind == "leg":
            near = target_point(target, world.layout, world.legs.position, world.legs.nearest)
        surface = location_surface(target, world.layout, near)
        name = "the pointed spot"
    goal = _release_goal(world, surface, held, current)
    return MoveAction(action, name, goal, CLEARANCE_Z, world.speed, release_point=surface)


def _release_goal(
    world: PlanningScene, surface: np.ndarray, held: int | None, current: mink.SE3
) -> mink.SE3:
    """Site pose above ``surface``: a held leg just above it, an empty hand higher."""
    if held is None:
        return pose(surface + np.array([0.0, 0.0, FREE_HAND_ABOVE]), current.rotation().wxyz)
    centre = surface + np.array([0.0, 0.0, spec.LEG_RADIUS + DROP_GAP])
    return release_goal(centre, leg_offset_in_site(world.ctx, held), current.rotation())
