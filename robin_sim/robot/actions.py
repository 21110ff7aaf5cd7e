"""The robot's five actions as objects: a target, a done condition, success checks, a time limit.

Every action is prepared first (:meth:`RobotAction.prepare`: the arm motion is planned with IK
and a target out of reach raises :class:`~robin_sim.robot.targets.UnreachableTargetError` before
anything moves), then either performed (:meth:`RobotAction.perform`, the person wants it) or shown
and taken back (:meth:`RobotAction.show_and_undo`, the person does not want it).

Undo design: arm motions are played as recorded joint-target sequences (:class:`JointPlan`), so
taking one back replays the executed part backwards to the exact start targets; a shown motion
stops after ``SHOW_FRACTION`` of its path, long enough for the person to see where it goes.
Finger actions are shown by a partial closing that opens again; while a leg is held, an
unwanted open or close only nudges the two fingertips (the thumb and the proximal joints keep
squeezing), so the person sees the fingers move and nothing drops.
A wanted action that fails physically (a grasp that closes on nothing, a blocked motion) is
undone the same way and reported; a drop cannot be undone and is reported as such.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field

import mink
import numpy as np

from pil.task.world import Outcome
from pil.types import Action, Hand
from robin_sim.control.ik import JointPlan
from robin_sim.control.simulator import Simulator
from robin_sim.control.trajectory import DEFAULT_SPEED, lift_traverse_descend, pose, through
from robin_sim.robot.targets import check_reached

SHOW_FRACTION = 0.3  # share of an unwanted motion shown before it is taken back
SHOW_PAUSE = 0.3  # s the robot waits at the shown point
ARRIVAL_TOLERANCE = 0.015  # m between the measured grasp site and the motion's goal
RETURN_TOLERANCE = 0.005  # m between the grasp site before an action and after its undo
FINGER_REST_SPEED = 0.05  # rad/s: fingers count as settled below this joint speed
RETREAT_HEIGHT = 0.10  # m the hand rises after letting go of a leg
HEIGHT_TOLERANCE = 0.01  # m: a released leg's centre vs radius above its supporting surface
FINGER_NUDGE = 0.3  # rad the two fingers' distal joints move to show open/close while holding


@dataclass
class Context:
    """What the actions read from the world: the simulator and physics-based hand sensing."""

    sim: Simulator
    hand_state: Callable[[], Hand]  # read from contacts (never a flag)
    held_leg: Callable[[], int | None]  # index of the leg in the hand, if any
    leg_position: Callable[[int], np.ndarray]  # centre of leg k (measured)
    leg_speed: Callable[[int], float]  # linear speed of leg k's centre, m/s
    reach_region: str  # described in unreachable-target errors


@dataclass(frozen=True)
class ActionResult:
    """What one action did, with measurements for the episode log."""

    action: Action
    succeeded: bool
    undone: bool
    detail: str
    started: float  # simulated time, s
    ended: float
    measurements: dict[str, float] = field(default_factory=dict)

    def outcome(self) -> Outcome:
        """The learner-facing summary."""
        return Outcome(succeeded=self.succeeded, detail=self.detail, undone=self.undone)


def leg_offset_in_site(ctx: Context, leg: int) -> np.ndarray:
    """Position of leg ``leg``'s centre in the grasp-site frame (measured)."""
    site = ctx.sim.site_pose()
    return site.inverse().apply(ctx.leg_position(leg))


def fingers_settled(sim: Simulator) -> bool:
    """True when the finger ramp has ended and the finger joints have nearly stopped."""
    if sim.hand.busy(sim.time):
        return False
    speeds = sim.data.qvel[sim.hand.joint_dofs]
    return bool(np.max(np.abs(speeds)) < FINGER_REST_SPEED)


class RobotAction(ABC):
    """Base class: ``prepare`` then ``perform`` (wanted) or ``show_and_undo`` (unwanted)."""

    action: Action
    time_limit: float = 10.0

    def prepare(self, ctx: Context) -> None:  # noqa: B027 - optional hook
        """Plan the motion; raise UnreachableTargetError if the target is out of reach."""

    @abstractmethod
    def perform(self, ctx: Context) -> ActionResult:
        """Carry the action out and check whether it achieved its purpose."""

    @abstractmethod
    def show_and_undo(self, ctx: Context, fraction: float = SHOW_FRACTION) -> ActionResult:
        """Show the start of the action, then return the world to its state before it."""

    def report(
        self, ok: bool, undone: bool, detail: str, start: float, ctx: Context, **m: float
    ) -> ActionResult:
        """An :class:`ActionResult` of this action from ``start`` until now."""
        return ActionResult(self.action, ok, undone, detail, start, ctx.sim.time, dict(m))


class MoveAction(RobotAction):
    """Move the grasp site to ``goal`` along lift-traverse-descend (object, human, location)."""

    def __init__(
        self,
        action: Action,
        target_name: str,
        goal: mink.SE3,
        clearance_z: float,
        speed: float = DEFAULT_SPEED,
        release_point: np.ndarray | None = None,
    ) -> None:
        self.action, self.target_name, self.goal = action, target_name, goal
        self.clearance_z, self.speed = clearance_z, speed
        self.release_point = release_point  # where a held leg's centre should end, if any
        self.plan: JointPlan | None = None

    def prepare(self, ctx: Context) -> None:
        sim = ctx.sim
        path = lift_traverse_descend(
            sim.commanded_site_pose(), self.goal, self.clearance_z, self.speed
        )
        plan = sim.plan(path)
        check_reached(plan, self.target_name, self.goal, ctx.reach_region)
        self.plan = plan
        self.time_limit = plan.duration + 1.0

    def perform(self, ctx: Context) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        if self.plan is None:
            self.prepare(ctx)
        assert self.plan is not None
        start_q, start_site = sim.arm_command, sim.site_pose().translation()
        held = ctx.held_leg()
        offset = None if held is None else leg_offset_in_site(ctx, held)
        sim.execute(self.plan)
        error = float(np.linalg.norm(sim.site_pose().translation() - self.goal.translation()))
        m = {"site_error_m": error, "duration_s": sim.time - start}
        if held is not None and ctx.held_leg() != held:  # a drop cannot be undone; the arm can
            where = ", ".join(f"{v:.2f}" for v in ctx.leg_position(held))
            sim.execute(self.plan.reversed_from(start_q))
            detail = f"leg {held} dropped on the way (now at {where}); arm moved back"
            return self.report(False, False, detail, start, ctx, **m)
        if held is not None:
            m["slip_m"] = float(np.linalg.norm(leg_offset_in_site(ctx, held) - offset))
        if error > ARRIVAL_TOLERANCE or sim.time - start > self.time_limit:
            sim.execute(self.plan.reversed_from(start_q))
            sim.run(0.3)
            m["return_error_m"] = float(np.linalg.norm(sim.site_pose().translation() - start_site))
            detail = f"stopped {error * 100:.1f} cm from {self.target_name}; moved back"
            return self.report(False, True, detail, start, ctx, **m)
        return self.report(True, False, f"reached {self.target_name}", start, ctx, **m)

    def show_and_undo(self, ctx: Context, fraction: float = SHOW_FRACTION) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        if self.plan is None:
            self.prepare(ctx)
        assert self.plan is not None
        start_q, start_site = sim.arm_command, sim.site_pose().translation()
        shown = self.plan.prefix(fraction)
        sim.execute(shown)
        sim.run(SHOW_PAUSE)
        sim.execute(shown.reversed_from(start_q))
        sim.run(0.3)
        back = float(np.linalg.norm(sim.site_pose().translation() - start_site))
        ok = back <= RETURN_TOLERANCE
        detail = f"showed {fraction:.0%} towards {self.target_name}, moved back"
        return self.report(ok, True, detail, start, ctx, return_error_m=back)


class CloseAction(RobotAction):
    """Close the hand; succeeds when physics shows a leg held between the fingers."""

    action = Action.CLOSE
    time_limit = 2.5

    def perform(self, ctx: Context) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        sim.hand.close(sim.time)
        settled = sim.step_until(fingers_settled, self.time_limit)
        leg = ctx.held_leg()
        if leg is not None:
            return self.report(
                True, False, f"holding leg {leg}", start, ctx, settled=float(settled)
            )
        sim.hand.open(sim.time)
        sim.step_until(fingers_settled, self.time_limit)
        return self.report(False, True, "closed on nothing; opened again", start, ctx)

    def show_and_undo(self, ctx: Context, fraction: float = SHOW_FRACTION) -> ActionResult:
        if ctx.held_leg() is not None:  # already gripping: squeeze a little, then relax
            return _twitch(ctx, self, FINGER_NUDGE, "squeezed the held leg briefly")
        return _show_fingers(ctx, self, fraction, "fingers closed partly and opened again")


class OpenAction(RobotAction):
    """Open the hand; with a leg held, let it go onto ``release_point`` and rise clear.

    Success: the hand is free and, when a release point (on the supporting surface) is given,
    the leg lies at rest (speed < ``rest_speed``) within ``tolerance`` of it horizontally, its
    centre ``rest_height`` (± ``HEIGHT_TOLERANCE``) above that surface, i.e. lying on it.
    """

    action = Action.OPEN
    time_limit = 4.0

    def __init__(
        self,
        release_point: np.ndarray | None = None,
        tolerance: float = 0.03,
        rest_speed: float = 0.01,
        place: str = "the release point",
        rest_height: float = 0.02,
    ) -> None:
        self.release_point, self.tolerance, self.rest_speed = release_point, tolerance, rest_speed
        self.place, self.rest_height = place, rest_height

    def perform(self, ctx: Context) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        leg = ctx.held_leg()
        sim.hand.open(sim.time)
        sim.step_until(fingers_settled, self.time_limit)
        if leg is None:
            ok = ctx.hand_state() is Hand.FREE
            return self.report(ok, False, "hand open", start, ctx)
        up = sim.commanded_site_pose()
        top = pose(up.translation() + np.array([0.0, 0.0, RETREAT_HEIGHT]), up.rotation().wxyz)
        sim.execute(sim.plan(through([up, top], DEFAULT_SPEED)))
        sim.step_until(lambda _: ctx.leg_speed(leg) < self.rest_speed, 2.0)
        speed = ctx.leg_speed(leg)
        centre = ctx.leg_position(leg)
        m = {"leg": float(leg), "leg_speed_mps": speed}
        m |= {"leg_x": float(centre[0]), "leg_y": float(centre[1]), "leg_z": float(centre[2])}
        if ctx.hand_state() is not Hand.FREE:
            return self.report(False, False, f"leg {leg} still in the hand", start, ctx, **m)
        if self.release_point is None:
            return self.report(True, False, f"let go of leg {leg}", start, ctx, **m)
        point = np.asarray(self.release_point, float)
        miss = float(np.linalg.norm(centre[:2] - point[:2]))
        height = float(centre[2] - point[2])
        m |= {"release_error_m": miss, "height_above_surface_m": height}
        lying = abs(height - self.rest_height) <= HEIGHT_TOLERANCE
        ok = miss <= self.tolerance and speed < self.rest_speed and lying
        verdict = "at rest" if speed < self.rest_speed else "still moving"
        where = "" if lying else f", {height * 100:.1f} cm above the surface (fell off)"
        detail = f"leg {leg} {miss * 100:.1f} cm from {self.place}, {verdict}{where}"
        return self.report(ok, False, detail, start, ctx, **m)

    def show_and_undo(self, ctx: Context, fraction: float = SHOW_FRACTION) -> ActionResult:
        if ctx.held_leg() is not None:  # a small opening of two fingertips; the thumb holds
            return _twitch(ctx, self, -FINGER_NUDGE, "eased two fingertips and closed them again")
        return _show_fingers(ctx, self, fraction, "fingers moved and opened again")


def _show_fingers(ctx: Context, action: RobotAction, fraction: float, detail: str) -> ActionResult:
    """An empty hand's unwanted open or close: ``fraction`` of the way, a pause, and back."""
    sim, start = ctx.sim, ctx.sim.time
    before = sim.hand.command
    sim.hand.move_to(sim.hand.blend(fraction), sim.time, 0.4)
    sim.run(0.4 + SHOW_PAUSE)
    sim.hand.move_to(before, sim.time, 0.4)
    sim.step_until(fingers_settled, action.time_limit)
    return action.report(True, True, detail, start, ctx)


def _twitch(ctx: Context, action: RobotAction, amount: float, detail: str) -> ActionResult:
    """Show open/close on a held leg: nudge two fingertips by ``amount`` rad and back.

    The thumb and the proximal joints keep squeezing, so the leg stays held (measured: it
    moves < 5 mm in the hand meanwhile and returns to within 0.1 mm).
    """
    sim, start = ctx.sim, ctx.sim.time
    leg = ctx.held_leg()
    assert leg is not None
    offset, before = leg_offset_in_site(ctx, leg), sim.hand.command
    sim.hand.move_to(sim.hand.nudged(amount), sim.time, 0.3)
    sim.run(0.3 + SHOW_PAUSE)
    sim.hand.move_to(before, sim.time, 0.3)
    sim.step_until(fingers_settled, action.time_limit)
    moved = float(np.linalg.norm(leg_offset_in_site(ctx, leg) - offset))
    ok = ctx.held_leg() == leg
    return action.report(
        ok, True, detail if ok else f"leg {leg} slipped out", start, ctx, leg_moved_m=moved
    )
