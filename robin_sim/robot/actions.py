"""The robot's five actions as objects: a target, a done condition, success checks, a time limit.

Every action is prepared first (:meth:`RobotAction.prepare`: the arm motion is planned with IK
and a target out of reach raises :class:`~robin_sim.robot.targets.UnreachableTargetError` before
anything moves), then run as the robot would run it, tick by tick (:meth:`RobotAction.run`). At
every control tick the action asks ``stop`` (the person's thumb down); when it says stop the
robot halts where it is and takes the action back from there. An action that ran to its end
can still be taken back (:meth:`RobotAction.undo`) when the person rejects its result.

Undo design: arm motions are played as recorded joint-target sequences (:class:`JointPlan`), so
taking one back replays the executed part backwards to the exact start targets; finger motions
ramp back to the targets they had. What physics did meanwhile stays done: a leg that slipped
out of opening fingers has dropped where physics took it (``ActionResult.dropped``).
A wanted action that fails physically (a grasp that closes on nothing, a blocked motion) is
undone the same way and reported.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

import mink
import numpy as np

from pil.task.world import Outcome
from pil.types import Action, Hand
from robin_sim.control.ik import JointPlan
from robin_sim.control.simulator import Simulator
from robin_sim.control.trajectory import DEFAULT_SPEED, lift_traverse_descend, pose, through
from robin_sim.robot.motion import (
    FINGER_UNDO_TIME,
    HALT_SETTLE,
    Stop,
    fingers_settled,
    hold_fingers,
    never,
    play,
    ramp_fingers,
)
from robin_sim.robot.targets import check_reached

ARRIVAL_TOLERANCE = 0.015  # m between the measured grasp site and the motion's goal
RETURN_TOLERANCE = 0.005  # m between the grasp site before an action and after its undo
RETREAT_HEIGHT = 0.10  # m the hand rises after letting go of a leg
# s: before a held leg is let go anywhere but over a place it was carried to (the palm, a spot),
# the two fingertips ease open (about 0.2 rad, visibly) while the proximal joints and the thumb
# keep the grip (the leg slips about 2 mm), so that a person can stop an open they did not mean.
# Over a place the hand opens at once: easing first tilts the leg and spoils the placement
# (measured: up to 2.4 cm off the spot instead of at most 1.2 cm).
EASE_RAMP, EASE_HOLD, OPEN_RAMP = 0.4, 0.3, 0.6
HEIGHT_TOLERANCE = 0.01  # m: a released leg's centre vs radius above its supporting surface
GRASP_SETTLE = 0.3  # s a closed hand waits, at most, for the sensor to read a grasp


@dataclass
class Context:
    """What the actions read from the world: the simulator and physics-based hand sensing."""

    sim: Simulator
    hand_state: Callable[[], Hand]  # read from contacts (never a flag)
    held_leg: Callable[[], int | None]  # index of the leg in the hand, if any
    leg_position: Callable[[int], np.ndarray]  # centre of leg k (measured)
    leg_speed: Callable[[int], float]  # linear speed of leg k's centre, m/s
    reach_region: str  # described in unreachable-target errors


@dataclass(frozen=True, kw_only=True)
class ActionResult:
    """What one action did, with measurements for the episode log."""

    action: Action
    succeeded: bool
    undone: bool
    detail: str
    started: float  # simulated time, s
    ended: float
    measurements: dict[str, float] = field(default_factory=dict)
    interrupted: bool = False  # the person stopped it
    dropped: int | None = None  # a held leg that left the hand meanwhile

    def outcome(self) -> Outcome:
        """The learner-facing summary."""
        return Outcome(self.succeeded, self.detail, self.undone, self.interrupted, self.dropped)


def leg_offset_in_site(ctx: Context, leg: int) -> np.ndarray:
    """Position of leg ``leg``'s centre in the grasp-site frame (measured)."""
    site = ctx.sim.site_pose()
    return site.inverse().apply(ctx.leg_position(leg))


class RobotAction(ABC):
    """Base class: ``prepare``, then ``run`` (interruptible), and ``undo`` after a late stop."""

    action: Action
    time_limit: float = 10.0

    def prepare(self, ctx: Context) -> None:  # noqa: B027 - optional hook
        """Plan the motion; raise UnreachableTargetError if the target is out of reach."""

    @abstractmethod
    def run(self, ctx: Context, stop: Stop = never) -> ActionResult:
        """Carry the action out, stopping and taking it back when ``stop()`` says so."""

    @abstractmethod
    def undo(self, ctx: Context, result: ActionResult) -> ActionResult:
        """Take back an action that ran to its end (``result``): the person rejected it."""

    def report(
        self,
        ok: bool,
        undone: bool,
        detail: str,
        start: float,
        ctx: Context,
        *,
        interrupted: bool = False,
        dropped: int | None = None,
        measurements: Mapping[str, float] | None = None,
    ) -> ActionResult:
        """An :class:`ActionResult` of this action from ``start`` until now."""
        return ActionResult(
            action=self.action,
            succeeded=ok,
            undone=undone,
            detail=detail,
            started=start,
            ended=ctx.sim.time,
            measurements=dict(measurements or {}),
            interrupted=interrupted,
            dropped=dropped,
        )

    def undone_after_stop(self, result: ActionResult, ctx: Context, detail: str) -> ActionResult:
        """``result`` marked as stopped by the person after its end and taken back."""
        return ActionResult(
            action=self.action,
            succeeded=False,
            undone=True,
            detail=f"rejected at its end; {detail}",
            started=result.started,
            ended=ctx.sim.time,
            measurements=result.measurements,
            interrupted=True,
            dropped=result.dropped,
        )


def _lost(ctx: Context, held: int | None) -> int | None:
    """``held`` if that leg is no longer in the hand (it dropped), else None."""
    return held if held is not None and ctx.held_leg() != held else None


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
        open_hand: bool = False,
    ) -> None:
        self.action, self.target_name, self.goal = action, target_name, goal
        self.clearance_z, self.speed = clearance_z, speed
        self.release_point = release_point  # where a held leg's centre should end, if any
        # a grasp approach: an empty hand that is not open (e.g. closed again after a leg
        # slipped out of it) opens on the way, or it would arrive closed beside the leg
        self.open_hand = open_hand
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

    def run(self, ctx: Context, stop: Stop = never) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        if self.plan is None:
            self.prepare(ctx)
        assert self.plan is not None
        self._start_q, start_site = sim.arm_command, sim.site_pose().translation()
        held = ctx.held_leg()
        offset = None if held is None else leg_offset_in_site(ctx, held)
        opened = sim.hand.targets.open
        if self.open_hand and held is None and not np.allclose(sim.hand.command, opened):
            sim.hand.move_to(opened, sim.time, OPEN_RAMP)  # while the arm lifts
        played = play(sim, self.plan, stop)
        if played is not None:  # the person stopped it: halt, then back from where it is
            halted = sim.site_pose().translation()
            sim.run(HALT_SETTLE)
            coast = float(np.linalg.norm(sim.site_pose().translation() - halted))
            done = JointPlan(self.plan.q[:played], self.plan.dt, 0.0, 0.0)
            sim.execute(done.reversed_from(self._start_q))
            sim.run(0.3)
            back = float(np.linalg.norm(sim.site_pose().translation() - start_site))
            dropped = _lost(ctx, held)
            detail = (
                f"stopped by the person after {played * self.plan.dt:.2f} s towards "
                f"{self.target_name}; moved back"
            )
            if dropped is not None:
                detail += f"; leg {dropped} dropped on the way"
            m = {"stopped_after_s": played * self.plan.dt, "stop_coast_m": coast}
            return self.report(
                False,
                True,
                detail,
                start,
                ctx,
                interrupted=True,
                dropped=dropped,
                measurements={"return_error_m": back, **m},
            )
        error = float(np.linalg.norm(sim.site_pose().translation() - self.goal.translation()))
        m = {"site_error_m": error, "duration_s": sim.time - start}
        lost = _lost(ctx, held)
        if lost is not None:  # a drop cannot be undone; the arm can
            where = ", ".join(f"{v:.2f}" for v in ctx.leg_position(lost))
            sim.execute(self.plan.reversed_from(self._start_q))
            detail = f"leg {lost} dropped on the way (now at {where}); arm moved back"
            return self.report(False, False, detail, start, ctx, dropped=lost, measurements=m)
        if held is not None:
            m["slip_m"] = float(np.linalg.norm(leg_offset_in_site(ctx, held) - offset))
        if error > ARRIVAL_TOLERANCE or sim.time - start > self.time_limit:
            sim.execute(self.plan.reversed_from(self._start_q))
            sim.run(0.3)
            m["return_error_m"] = float(np.linalg.norm(sim.site_pose().translation() - start_site))
            detail = f"stopped {error * 100:.1f} cm from {self.target_name}; moved back"
            return self.report(False, True, detail, start, ctx, measurements=m)
        return self.report(True, False, f"reached {self.target_name}", start, ctx, measurements=m)

    def undo(self, ctx: Context, result: ActionResult) -> ActionResult:
        assert self.plan is not None
        held = ctx.held_leg()
        ctx.sim.execute(self.plan.reversed_from(self._start_q))
        ctx.sim.run(0.3)
        undone = self.undone_after_stop(result, ctx, f"moved back from {self.target_name}")
        lost = _lost(ctx, held)
        return undone if lost is None else replace(undone, dropped=lost)


class CloseAction(RobotAction):
    """Close the hand; succeeds when physics shows a leg held between the fingers."""

    action = Action.CLOSE
    time_limit = 2.5

    def run(self, ctx: Context, stop: Stop = never) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        self._before = sim.hand.command
        if not ramp_fingers(sim, sim.hand.targets.closed, 0.8, stop, self.time_limit):
            detail = "stopped by the person; fingers opened again"
            return self.report(False, True, detail, start, ctx, interrupted=True)
        # one judgement of "held", the hand sensor's (the learner reads the same): contacts
        # may take a moment to settle into a grasp that moves with the hand
        leg = ctx.held_leg()
        if leg is None and sim.step_until(lambda _: ctx.held_leg() is not None, GRASP_SETTLE):
            leg = ctx.held_leg()
        if leg is not None:
            return self.report(True, False, f"holding leg {leg}", start, ctx)
        sim.hand.open(sim.time)
        sim.step_until(fingers_settled, self.time_limit)
        leg = ctx.held_leg()  # the opening fingers may have caught a leg after all
        if leg is not None:
            return self.report(
                True, False, f"holding leg {leg} (caught as the fingers opened)", start, ctx
            )
        return self.report(False, True, "closed on nothing; opened again", start, ctx)

    def undo(self, ctx: Context, result: ActionResult) -> ActionResult:
        ctx.sim.hand.move_to(self._before, ctx.sim.time, FINGER_UNDO_TIME)
        ctx.sim.step_until(fingers_settled, self.time_limit)
        return self.undone_after_stop(result, ctx, "fingers back as they were")


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

    def run(self, ctx: Context, stop: Stop = never) -> ActionResult:
        sim, start = ctx.sim, ctx.sim.time
        leg = ctx.held_leg()
        self._before, self._retreat = sim.hand.command, None
        announced = (
            leg is None
            or self.release_point is not None
            or (  # fingertips first
                ramp_fingers(sim, sim.hand.eased(), EASE_RAMP, stop, self.time_limit)
                and hold_fingers(sim, EASE_HOLD, stop, self._before)
            )
        )
        opened = announced and ramp_fingers(
            sim, sim.hand.targets.open, OPEN_RAMP, stop, self.time_limit, self._before
        )
        if not opened:
            dropped = _lost(ctx, leg)
            detail = "stopped by the person; fingers closed again"
            if dropped is not None:
                detail += f", but leg {dropped} had slipped out (dropped)"
            return self.report(
                False, dropped is None, detail, start, ctx, interrupted=True, dropped=dropped
            )
        if leg is None:
            ok = ctx.hand_state() is Hand.FREE
            return self.report(ok, False, "hand open", start, ctx)
        up = sim.commanded_site_pose()
        top = pose(up.translation() + np.array([0.0, 0.0, RETREAT_HEIGHT]), up.rotation().wxyz)
        self._retreat = sim.plan(through([up, top], DEFAULT_SPEED))
        self._up_q = sim.arm_command
        played = play(sim, self._retreat, stop)
        if played is not None:  # stopped while rising: back down, fingers closed again
            sim.run(HALT_SETTLE)
            done = JointPlan(self._retreat.q[:played], self._retreat.dt, 0.0, 0.0)
            sim.execute(done.reversed_from(self._up_q))
            sim.hand.move_to(self._before, sim.time, FINGER_UNDO_TIME)
            sim.step_until(fingers_settled, self.time_limit)
            dropped = _lost(ctx, leg)
            detail = "stopped by the person while rising; hand back down and closed"
            return self.report(
                False, dropped is None, detail, start, ctx, interrupted=True, dropped=dropped
            )
        sim.step_until(lambda _: ctx.leg_speed(leg) < self.rest_speed, 2.0)
        speed = ctx.leg_speed(leg)
        centre = ctx.leg_position(leg)
        m = {"leg": float(leg), "leg_speed_mps": speed}
        m |= {"leg_x": float(centre[0]), "leg_y": float(centre[1]), "leg_z": float(centre[2])}
        if ctx.hand_state() is not Hand.FREE:
            return self.report(
                False, False, f"leg {leg} still in the hand", start, ctx, measurements=m
            )
        if self.release_point is None:
            return self.report(True, False, f"let go of leg {leg}", start, ctx, measurements=m)
        point = np.asarray(self.release_point, float)
        miss = float(np.linalg.norm(centre[:2] - point[:2]))
        height = float(centre[2] - point[2])
        m |= {"release_error_m": miss, "height_above_surface_m": height}
        lying = abs(height - self.rest_height) <= HEIGHT_TOLERANCE
        ok = miss <= self.tolerance and speed < self.rest_speed and lying
        verdict = "at rest" if speed < self.rest_speed else "still moving"
        where = "" if lying else f", {height * 100:.1f} cm above the surface (fell off)"
        detail = f"leg {leg} {miss * 100:.1f} cm from {self.place}, {verdict}{where}"
        return self.report(ok, False, detail, start, ctx, measurements=m)

    def undo(self, ctx: Context, result: ActionResult) -> ActionResult:
        sim = ctx.sim
        if self._retreat is not None:
            sim.execute(self._retreat.reversed_from(self._up_q))
        sim.hand.move_to(self._before, sim.time, FINGER_UNDO_TIME)
        sim.step_until(fingers_settled, self.time_limit)
        undone = self.undone_after_stop(result, ctx, "hand back down and closed")
        leg = result.measurements.get("leg")
        if leg is not None and ctx.held_leg() != int(leg):
            return replace(undone, undone=False, dropped=int(leg))
        return undone
