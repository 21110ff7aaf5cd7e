"""``PhysicalWorld``: the learner's :class:`pil.task.world.World` executed by Robin in MuJoCo.

Targets map to the scene: ``Target("leg", k)`` is leg ``k`` (grasped where physics has it now),
``Target("spot", k)`` is the layout's table spot ``k``; "human" goes to the person's palm, held
out over the table at the layout's handover point (jittered by up to 1 cm per handover from the
world's seed: the person never holds the hand at exactly the same place). The hand state is read
from contacts (:mod:`robin_sim.control.hand_state`), never kept as a flag.

After a wanted "open" lets a leg go onto the person's palm, the robot's hand rises clear and the
person carries the leg off and tips it into the bin beside the table, so the next handover
finds an empty palm. :meth:`PhysicalWorld.start_table` lays out a new table's legs: the legs are
put back at the layout's poses (a scene change between tables, done only while the hand is
empty and never during an action), the arm returns home and the person's hand to rest.
"""

from __future__ import annotations

from collections.abc import Callable

import mink
import numpy as np

from pil.errors import RobinPilError
from pil.task.world import Intent, Outcome, Target
from pil.types import Action, Hand
from robin_sim.control.hand_state import HandSensor
from robin_sim.control.simulator import HandTargets, Simulator
from robin_sim.control.trajectory import DEFAULT_SPEED, lift_traverse_descend, pose, through
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout, build_spec
from robin_sim.person.hand import HumanHand
from robin_sim.robot.actions import (
    ActionResult,
    CloseAction,
    Context,
    MoveAction,
    OpenAction,
    RobotAction,
    leg_offset_in_site,
)
from robin_sim.robot.targets import (
    check_leg,
    grasp_goal,
    location_surface,
    reach_text,
    release_goal,
    target_point,
)

CLEARANCE_Z = 0.95  # m: grasp-site height of traverses (a held leg clears legs and the palm)
DROP_GAP = 0.012  # m between a released leg's underside and what it lands on
FREE_HAND_ABOVE = 0.10  # m above the palm / spot an empty hand goes to
PERSON_CLEAR_X = 0.95  # m: the person's hand draws back this far before the arm moves
PALM_JITTER = 0.01  # m, largest offset of the person's palm from the handover point
HANDOVER_TOLERANCE = 0.03  # m, leg centre to palm centre, horizontally
PLACEMENT_TOLERANCE = 0.02  # m, leg centre to the pointed spot, horizontally
PLACE_NAMES = {"palm": "the palm centre", "spot": "the spot"}
Release = tuple[np.ndarray, float, str]  # point, tolerance (m), "palm" or "spot"


class PhysicalWorld:
    """Executes the learner's actions with Robin's left arm in MuJoCo (see the module doc)."""

    def __init__(
        self,
        layout: SceneLayout | None = None,
        seed: int = 0,
        *,
        speed: float = DEFAULT_SPEED,
        control_dt: float = 0.02,
    ) -> None:
        self.layout = layout or SceneLayout()
        self.spec = build_spec(self.layout)
        self.model = self.spec.compile()
        targets = HandTargets(np.array(spec.HAND_OPEN_CTRL), np.array(spec.HAND_CLOSED_CTRL))
        limits = dict(
            zip(names.arm_joints(names.ACTIVE_SIDE), spec.ARM_VELOCITY_LIMITS, strict=True)
        )
        self.sim = Simulator(
            self.model, targets, spec=self.spec, control_dt=control_dt, velocity_limits=limits
        )
        self.data = self.sim.data
        self.human = HumanHand(self.model, self.data)
        self.human.attach(self.sim)
        self.sensor = HandSensor(self.model, names.ACTIVE_SIDE)
        self.rng = np.random.default_rng(seed)
        self.speed = speed
        self.leg_count = len(self.layout.legs)
        self._leg_qadr = [
            self.model.jnt_qposadr[self.model.joint(names.leg_joint(k)).id]
            for k in range(self.leg_count)
        ]
        self._leg_dofadr = [
            self.model.jnt_dofadr[self.model.joint(names.leg_joint(k)).id]
            for k in range(self.leg_count)
        ]
        self._home_pose = self.sim.commanded_site_pose()
        self._release: Release | None = None  # where an open would let the held leg go
        self.last_release: Release | None = None  # that of the last "open" executed
        self._result_hooks: list[Callable[[ActionResult], None]] = []
        self._palm_goal = np.array(self.layout.handover, float)
        self.last_result: ActionResult | None = None
        self.history: list[ActionResult] = []
        self.delivered: list[int] = []
        self.ctx = Context(
            self.sim, self.hand, self.held_leg, self.leg_position, self.leg_speed, reach_text()
        )

    # --- what the world shows ------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Simulated time, s."""
        return self.sim.time

    def hand(self) -> Hand:
        """Occupied while physics shows a leg held in an opposed grasp, else free."""
        return self.sensor.hand(self.data)

    def held_leg(self) -> int | None:
        """Index of the leg in the hand, if any (from contacts)."""
        return self.sensor.grasped_leg(self.data)

    def leg_position(self, leg: int) -> np.ndarray:
        """Centre of leg ``leg``, m (world frame)."""
        return self.data.xpos[self.model.body(names.leg_body(leg)).id].copy()

    def leg_positions(self) -> np.ndarray:
        """Centres of all legs, shape (legs, 3)."""
        return np.array([self.leg_position(k) for k in range(self.leg_count)])

    def leg_speed(self, leg: int) -> float:
        """Linear speed of leg ``leg``'s centre, m/s."""
        adr = self._leg_dofadr[leg]
        return float(np.linalg.norm(self.data.qvel[adr : adr + 3]))

    def add_result_hook(self, hook: Callable[[ActionResult], None]) -> Callable[[], None]:
        """Call ``hook(result)`` right after each wanted action, before the person takes a
        delivered leg away; returns a function removing it."""
        self._result_hooks.append(hook)
        return lambda: self._result_hooks.remove(hook)

    # --- the person and the clock (for the episode) -----------------------------------------
    def run(self, seconds: float) -> None:
        """Let ``seconds`` of simulated time pass (observers keep being called)."""
        self.sim.run(seconds)

    def person_points_at(self, target: Target) -> float:
        """The person's hand moves to point at ``target`` and waits there; returns the time.

        A palm held out for a handover draws back and down first, clear of a held leg."""
        where = target_point(target, self.layout, self.leg_position, self._nearest_leg)
        duration = self.human.point_at(where, self.sim.time, self.palm_is_out()) + 0.1
        self.sim.run(duration)
        return duration

    def person_rests(self) -> float:
        """The person's hand goes back to rest; returns the time it took."""
        duration = self.human.rest(self.sim.time) + 0.1
        self.sim.run(duration)
        return duration

    # --- the World protocol --------------------------------------------------------------------
    def execute(self, action: Action, intent: Intent, wanted: bool) -> Outcome:
        """Perform ``action`` (wanted) or show and undo it (unwanted); see :mod:`actions`.

        For a wanted "human" the robot first lifts the hand to the traverse height, then the
        person holds out the palm, then the robot brings the leg over it (so the palm never
        sweeps into the hand that is still at the table).
        """
        action = Action.parse(action)
        palm_out = self.palm_is_out()
        if wanted and action is Action.HUMAN and not palm_out:
            jitter = self.rng.uniform(-PALM_JITTER, PALM_JITTER, size=2)
            self._palm_goal = np.array(self.layout.handover) + np.array([*jitter, 0.0])
        robot_action = self._make(action, intent.target)
        robot_action.prepare(self.ctx)  # raises UnreachableTargetError before anything moves
        if isinstance(robot_action, MoveAction) and not palm_out:  # the pointing hand clears
            self.sim.run(self.human.withdraw(PERSON_CLEAR_X, self.sim.time))  # (arm holds still)
        release = self.last_release if action is Action.OPEN else None
        if wanted and release is not None and release[2] == "palm" and not palm_out:
            self.sim.run(self.human.slide_under(release[0], self.sim.time) + 0.1)  # back under
        if wanted and action is Action.HUMAN and not palm_out:
            self._lift_to(CLEARANCE_Z)
            self.sim.run(self.human.hold_out_palm(self._palm_goal, self.sim.time) + 0.1)
            robot_action = self._make(action, intent.target)
            robot_action.prepare(self.ctx)
        if not wanted:
            result = robot_action.show_and_undo(self.ctx)
        else:
            result = robot_action.perform(self.ctx)
            for hook in tuple(self._result_hooks):  # before the person takes anything away
                hook(result)
            self._after(action, result, robot_action)
        self.last_result = result
        self.history.append(result)
        return result.outcome()

    def start_table(self, table: int) -> None:
        """Lay out table ``table``'s legs at the layout poses; arm home, person's hand at rest."""
        if self.held_leg() is not None:
            raise RobinPilError(
                f"cannot lay out table {table}: the hand still holds leg {self.held_leg()}; "
                "open the hand over the person's palm or a spot first"
            )
        self.sim.hand.open(self.sim.time)
        path = lift_traverse_descend(
            self.sim.commanded_site_pose(), self._home_pose, CLEARANCE_Z, self.speed
        )
        self.sim.execute(self.sim.plan(path))
        self.sim.run(self.human.rest(self.sim.time) + 0.1)
        z = spec.TABLE_TOP_Z + spec.LEG_RADIUS
        for k, (x, y, yaw) in enumerate(self.layout.legs):  # a scene change between tables
            q, v = self._leg_qadr[k], self._leg_dofadr[k]
            self.data.qpos[q : q + 7] = [x, y, z, np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]
            self.data.qvel[v : v + 6] = 0.0
        self._release = None
        self.sim.run(0.3)

    # --- helpers -------------------------------------------------------------------------------
    def palm_is_out(self) -> bool:
        """True when the person's palm is at the handover point (within the jitter)."""
        handover = np.array(self.layout.handover)
        return bool(np.linalg.norm(self.human.palm_centre() - handover) <= 2 * PALM_JITTER)

    def _lift_to(self, height: float) -> None:
        """Raise the grasp site straight up to ``height`` (nothing if it is there already)."""
        here = self.sim.commanded_site_pose()
        if here.translation()[2] < height - 1e-3:
            top = pose([*here.translation()[:2], height], here.rotation().wxyz)
            self.sim.execute(self.sim.plan(through([here, top], self.speed)))

    def _on_table(self, leg: int) -> bool:
        return abs(self.leg_position(leg)[2] - spec.GRASP_HEIGHT) < 0.01

    def _grasp_place(self, leg: int) -> tuple[np.ndarray, np.ndarray]:
        """Centre and axis of ``leg`` where it lies; off the table: its layout place."""
        if self._on_table(leg):
            axis = self.data.xmat[self.model.body(names.leg_body(leg)).id].reshape(3, 3)[:, 0]
            return self.leg_position(leg), axis
        x, y, yaw = self.layout.legs[leg]
        return np.array([x, y, spec.GRASP_HEIGHT]), np.array([np.cos(yaw), np.sin(yaw), 0.0])

    def _nearest_leg(self) -> int:
        """The leg on the table nearest the hand (any leg's layout place if none is left)."""
        pool = [k for k in range(self.leg_count) if self._on_table(k)] or range(self.leg_count)
        site = self.sim.site_pose().translation()
        return min(pool, key=lambda k: float(np.linalg.norm(self._grasp_place(k)[0] - site)))

    def _make(self, action: Action, target: Target | None) -> RobotAction:
        if action is Action.CLOSE:
            return CloseAction()
        if action is Action.OPEN:
            self.last_release = None if self.held_leg() is None else self._release
            if self.last_release is None:
                return OpenAction()
            point, tolerance, kind = self.last_release
            return OpenAction(
                point, tolerance, place=PLACE_NAMES[kind], rest_height=spec.LEG_RADIUS
            )
        current = self.sim.commanded_site_pose()
        held = self.held_leg()
        if action is Action.OBJECT:
            if target is not None and target.kind != "leg":  # a spot: keep the wrist's yaw
                where = target_point(target, self.layout, self.leg_position, self._nearest_leg)
                axis, name = current.rotation().as_matrix()[:, 1], "the pointed spot"
            else:
                leg = (
                    self._nearest_leg()
                    if target is None
                    else check_leg(target.index, self.leg_count)
                )
                (where, axis), name = self._grasp_place(leg), f"leg {leg}"
            height = 0.0 if held is None else FREE_HAND_ABOVE
            goal = grasp_goal(where, axis, current, height)
            return MoveAction(Action.OBJECT, name, goal, CLEARANCE_Z, self.speed)
        if action is Action.HUMAN:
            surface = self.human.palm_centre() if self.palm_is_out() else self._palm_goal
            name = "the person's palm"
        else:
            near = self.sim.site_pose().translation()
            if target is not None and target.kind == "leg":
                near = target_point(target, self.layout, self.leg_position, self._nearest_leg)
            surface = location_surface(target, self.layout, near)
            name = "the pointed spot"
        goal = self._release_goal(surface, held, current)
        return MoveAction(action, name, goal, CLEARANCE_Z, self.speed, release_point=surface)

    def _release_goal(self, surface: np.ndarray, held: int | None, current: mink.SE3) -> mink.SE3:
        """Site pose above ``surface``: a held leg just above it, an empty hand higher."""
        if held is None:
            return pose(surface + np.array([0.0, 0.0, FREE_HAND_ABOVE]), current.rotation().wxyz)
        centre = surface + np.array([0.0, 0.0, spec.LEG_RADIUS + DROP_GAP])
        return release_goal(centre, leg_offset_in_site(self.ctx, held), current.rotation())

    def _after(self, action: Action, result: ActionResult, robot_action: RobotAction) -> None:
        """Remember where an open would let go; the person takes a delivered leg away."""
        if action in (Action.HUMAN, Action.LOCATION) and result.succeeded:
            assert isinstance(robot_action, MoveAction)
            if action is Action.HUMAN:
                self._release = (self.human.palm_centre(), HANDOVER_TOLERANCE, "palm")
            else:
                point = robot_action.release_point
                self._release = None if point is None else (point, PLACEMENT_TOLERANCE, "spot")
        elif action is Action.OBJECT and result.succeeded:
            self._release = None
        elif action is Action.OPEN and result.succeeded and self._release is not None:
            place = self._release[2]
            self._release = None
            if place == "palm" and "leg" in result.measurements:
                self.delivered.append(int(result.measurements["leg"]))
                bin_centre = np.array([*self.layout.bin, 0.0])
                self.sim.run(self.human.take_away(bin_centre, self.sim.time) + 0.2)
