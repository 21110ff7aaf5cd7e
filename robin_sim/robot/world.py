"""``PhysicalWorld``: the learner's :class:`pil.task.world.World` executed by Robin in MuJoCo.

Targets map to the scene: ``Target("leg", k)`` is leg ``k`` (grasped where physics has it now),
``Target("spot", k)`` is the layout's table spot ``k``; "human" goes to the person's palm, held
out (where the robot sees it; the layout's handover point when it is not out). The hand state is
read from contacts (:mod:`robin_sim.control.hand_state`), never kept as a flag; where each leg
lies, whether it can be grasped there and laying it out are the legs' own
(:attr:`PhysicalWorld.legs`, :class:`robin_sim.robot.table_legs.TableLegs`).

The world holds the person's mocap hand as a part of the scene (:attr:`PhysicalWorld.human`) but
never moves it: the person's body (:mod:`robin_sim.person.body`) does. An "open" after "human"
lets the leg go where "human" brought it (the palm, or the handover point, where the person
then slides the palm under it). After a wanted "open" lets a leg go onto the palm (or a spot),
the robot's hand rises clear and goes back to its home pose (:meth:`PhysicalWorld.rest_hand`:
out of the line from its eyes to the person's pointing hand); the person then carries a
delivered leg away.
:meth:`PhysicalWorld.start_table` lays out a new table's legs: the legs are put back at the
layout's poses (a scene change between tables, done only while the hand is empty and never
during an action) and the arm returns home.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal

import mink
import mujoco
import numpy as np

from pil.errors import RobinPilError
from pil.task.world import Outcome, Target, Watcher
from pil.types import Action, Hand
from robin_sim.control.hand_state import HandSensor
from robin_sim.control.human_hand import HumanHand
from robin_sim.control.simulator import HandTargets, Simulator
from robin_sim.control.trajectory import DEFAULT_SPEED, lift_traverse_descend, through
from robin_sim.figure.articulated import has_articulated_hand
from robin_sim.figure.posture import Posture
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout, build_spec
from robin_sim.robot.actions import (
    ActionResult,
    Context,
    MoveAction,
    RobotAction,
)
from robin_sim.robot.contacts import PersonContacts
from robin_sim.robot.head import HeadController
from robin_sim.robot.motion import never
from robin_sim.robot.planning import CLEARANCE_Z, PALM_OUT_RADIUS, ReleasePlace, make_action
from robin_sim.robot.table_legs import TableLegs
from robin_sim.robot.targets import reach_text

REST_RISE_Z = 1.0  # m: an empty hand going home rises to at least this height first


class PhysicalWorld:
    """Executes the learner's actions with Robin's left arm in MuJoCo (see the module doc)."""

    def __init__(
        self,
        layout: SceneLayout | None = None,
        *,
        speed: float = DEFAULT_SPEED,
        control_dt: float = 0.02,
        sleep: bool = False,
    ) -> None:
        self.layout = layout or SceneLayout()
        self.spec = build_spec(self.layout, sleep=sleep)  # sleep: see build_spec
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
        # the articulated person (kinematic, no contacts): the hand's blends into poses play out
        # at every tick; the body follows the hand whenever a render looks (a view hook)
        self.posture = Posture(self.model, self.data) if has_articulated_hand(self.model) else None
        if self.posture is not None:
            posture = self.posture
            self.sim.add_controller(lambda s: posture.tick(s.time + s.control_dt))

            def view() -> None:  # the hand fitted around what is near it, then the body
                if posture.hand is not None:
                    posture.hand.prepare_view()
                posture.update(self.sim.time)

            self.sim.add_view_hook(view)
            posture.update()
            mujoco.mj_kinematics(self.model, self.data)
        self.person_contacts = PersonContacts(self.sim)
        self.head = HeadController(self.sim, self._gaze_sources())  # gaze: head joints only
        self.sensor = HandSensor(self.model, names.ACTIVE_SIDE)
        self.speed = speed
        self.legs = TableLegs(self.sim, self.layout)  # where physics has each leg
        self._home_pose = self.sim.commanded_site_pose()
        self.release: ReleasePlace | None = None  # where an open would let the held leg go
        self.last_release: ReleasePlace | None = None  # where the last "open" let a leg go
        self._result_hooks: list[Callable[[ActionResult], None]] = []
        self.last_result: ActionResult | None = None
        self.history: list[ActionResult] = []
        self.delivered: list[int] = []
        self.ctx = Context(
            self.sim, self.hand, self.held_leg, self.legs.position, self.legs.speed, reach_text()
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

    def add_result_hook(self, hook: Callable[[ActionResult], None]) -> Callable[[], None]:
        """Call ``hook(result)`` right after each action that succeeded and was let stand,
        before the person takes a delivered leg away; returns a function removing it."""
        self._result_hooks.append(hook)
        return lambda: self._result_hooks.remove(hook)

    # --- the clock ----------------------------------------------------------------------------
    def run(self, seconds: float) -> None:
        """Let ``seconds`` of simulated time pass (observers keep being called)."""
        self.sim.run(seconds)

    # --- the World protocol --------------------------------------------------------------------
    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        """Run ``action`` on ``target`` tick by tick, as the robot would (see :mod:`actions`).

        ``watcher`` (the person) is asked at every control tick whether to stop; after the
        action's end it may still reject the result, which the robot then takes back. "human"
        goes to the palm where the person holds it out (the handover point if not).
        """
        action = Action.parse(action)
        release = self.release if action is Action.OPEN and self.held_leg() is not None else None
        robot_action = make_action(self, action, target, release)
        robot_action.prepare(self.ctx)  # raises UnreachableTargetError before anything moves
        self._attend(action, release)
        stop = never if watcher is None else (lambda: watcher.stop_now(None))
        result = robot_action.run(self.ctx, stop)
        if watcher is not None and not result.interrupted:
            # also after an action the robot undid by itself (nothing more to take back then)
            window = watcher.result_window(None, undone=result.undone)
            rejected = window > 0.0 and self._rejected_in(window, watcher)
            if rejected and not result.undone:
                result = robot_action.undo(self.ctx, result)
        if result.succeeded and not result.interrupted:
            if action is Action.OPEN:
                self.last_release = release
            for hook in tuple(self._result_hooks):  # before anything else moves
                hook(result)
            self._after(action, result, robot_action, release)
        elif result.dropped is not None:
            self.release = None  # the leg is gone from the hand
            if self.held_leg() is None:
                self.rest_hand()  # an empty hand left over the palm hides the pointing hand
        self.last_result = result
        self.history.append(result)
        return result.outcome()

    def _rejected_in(self, window: float, watcher: Watcher) -> bool:
        """Let up to ``window`` s pass while ``watcher`` judges the result: True when the thumb
        went down (the robot takes the action back), False when it ran out or the person let
        the result stand."""
        ended = self.sim.step_until(lambda _: watcher.stop_now(None) or watcher.settled(), window)
        return ended and not watcher.settled()

    def start_table(self, table: int) -> None:
        """Lay out table ``table``'s legs at the layout poses; the arm goes home first."""
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
        for k in range(self.legs.count):  # a scene change between tables
            self.legs.lay(k)
        self.release = None
        self.sim.run(0.3)

    # --- gaze ----------------------------------------------------------------------------------
    def _gaze_sources(self) -> dict[str, Callable[[], np.ndarray]]:
        """The moving points the head may follow (:mod:`robin_sim.robot.head`)."""
        grasp_site = self.data.site(names.grasp_site(names.ACTIVE_SIDE))
        return {
            "person hand": self.human.palm_centre,
            "palm": self.human.palm_centre,
            "robot hand": lambda: grasp_site.xpos.copy(),
        }

    def _attend(self, action: Action, release: ReleasePlace | None) -> None:
        """The head looks at the palm during a handover (moving to it or opening over it),
        else at the robot's own hand."""
        over_palm = release is not None and release.kind == "palm"
        self.head.attend_to("palm" if action is Action.HUMAN or over_palm else "robot hand")

    # --- the person's side ----------------------------------------------------------------------
    def palm_is_out(self) -> bool:
        """True when the person's palm is held out at the handover point."""
        handover = np.array(self.layout.handover)
        return bool(np.linalg.norm(self.human.palm_centre() - handover) <= PALM_OUT_RADIUS)

    def put_leg_back(self, leg: int) -> None:
        """The person puts leg ``leg`` back at its layout place on the table (a person
        intervention: the only scene change besides laying out a table)."""
        if self.held_leg() == leg:
            raise RobinPilError(f"leg {leg} is in the robot's hand; it cannot be put back")
        self.legs.lay(leg)
        self.sim.run(0.3)

    def _after(
        self,
        action: Action,
        result: ActionResult,
        robot_action: RobotAction,
        release: ReleasePlace | None,
    ) -> None:
        """Remember where an open would let go, and which legs went to the person's palm."""
        if action in (Action.HUMAN, Action.LOCATION) and result.succeeded:
            assert isinstance(robot_action, MoveAction)
            point = robot_action.release_point  # the palm it went to, or where it waits
            kind: Literal["palm", "spot"] = "palm" if action is Action.HUMAN else "spot"
            self.release = None if point is None else ReleasePlace(point, kind)
        elif action is Action.OBJECT and result.succeeded:
            self.release = None
        elif action is Action.OPEN and result.succeeded and release is not None:
            self.release = None
            if release.kind == "palm" and "leg" in result.measurements:
                self.delivered.append(int(result.measurements["leg"]))
            if "leg" in result.measurements:
                self.rest_hand()

    def rest_hand(self) -> float:
        """Move the empty hand back to its home pose; returns the time it took (s).

        After letting a leg go on the palm or a spot the hand has only risen clear, and there,
        between Robin's eyes and the person's drawn-back pointing hand, it hid that hand
        above the left legs and spots from both eyes (``bench/bench_pointing_view.py``); at
        home it hides none. The same after an action that lost the held leg (an open the person
        stopped too late): the hand rises to :data:`REST_RISE_Z` if it is lower, then goes
        straight home, away from the person's palm."""
        start = self.sim.commanded_site_pose()
        if np.linalg.norm(start.translation() - self._home_pose.translation()) < 1e-3:
            return 0.0
        waypoints = [start]
        here = start.translation()
        if here[2] < REST_RISE_Z - 1e-3:  # a hand low over the palm rises first, clear of it
            up = np.array([here[0], here[1], REST_RISE_Z])
            waypoints.append(mink.SE3.from_rotation_and_translation(start.rotation(), up))
        began = self.sim.time
        self.sim.execute(self.sim.plan(through([*waypoints, self._home_pose], self.speed)))
        return self.sim.time - began
