"""The articulated person's body follows its right hand: torso, arms and head.

The right hand hangs from the mocap frame ``human_hand`` that carries the collision palm (so
what Robin sees is where the physics palm is). Before a render looks :class:`Posture` solves the
rest of the body so that the right arm's wrist meets the hand's wrist point
(``human_r_wrist_point``) and writes the person's joint positions (kinematic; nothing pushes
the person):

1. the torso (:mod:`robin_sim.figure.torso`): the step, waist turn and spine lean that bring
   the shoulder near enough to the wrist at least cost, the lean costing most: the person
   stands upright while the arm reaches, steps towards the table first and leans for the rest;
2. the arm reaches from that shoulder in closed form: the elbow on the circle the upper arm
   and forearm lengths allow, swung towards where the forearm would continue the hand's own
   axis; the shoulder's three angles from the upper arm's frame, the elbow's from the two
   segments;
3. the forearm roll and the two wrist axes turn the wrist frame onto the hand's; where their
   limits leave it more than :data:`SWIVEL_TRY` off, other elbow swings about the line from
   shoulder to wrist are tried and the best kept (:attr:`Posture.wrist_error`); where the best
   still leaves it that far off, leaning further (:data:`LEAN_TRIES`) is tried and kept when
   the wrist's gain (:data:`ERROR_SCALE`) is worth more than the lean's cost;
3a. each candidate arm is also scored by how far its capsules come inside
   :data:`~robin_sim.figure.arm_clearance.MARGIN` of a handed-over leg or Robin's geoms
   (:mod:`robin_sim.figure.arm_clearance`; :data:`DEPTH_SCALE`: a clear arm is preferred to a
   wrist turned as the hand is); where the cheapest torso's arm is not clear, the elbow swings,
   the leans of :data:`LEAN_TRIES` and the full step with the waist turned and leant further
   (:data:`CLEAR_LEANS`, :data:`CLEAR_TURNS`) are tried, the cheapest torsos first;
4. the head turns towards the hand; the idle left arm hangs clear of the table and the bin
   (:mod:`robin_sim.figure.idle_arm`).

Where the hand lies out of reach the arm points at it at full stretch and :attr:`Posture.gap`
says how far the arm's wrist stays from the hand's. Segment lengths, offsets and axes are read
from the model. The left hand is half relaxed (the library's neutral pose, baked: model.idle_hand).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from robin_sim.figure.arm_angles import ArmAngles, unit
from robin_sim.figure.arm_clearance import ArmClearance
from robin_sim.figure.articulated import JOINT_LIMIT_MARGIN, ArticulatedHand
from robin_sim.figure.idle_arm import IdleArm
from robin_sim.figure.torso import COMFORT, Torso, TorsoPose, axis_rotation
from robin_sim.model import names
from robin_sim.model.person_joints import figure, pose

# z of the forearm's direction from the wrist to the elbow: the elbow at most this far below
# or above the wrist per metre of forearm
FOREARM_RISE = (-0.45, 0.9)
LOOK = 0.8  # share of the way the head turns towards the hand
# s of simulated time: renders closer together than this share one solve (a solve costs about
# 1.3 ms of CPU in Python, 1.0 with the single box's closed form: at every frame of a live
# session it slowed the loop enough to matter)
VIEW_PERIOD = 0.1
SWIVEL_TRY = 0.35  # rad of wrist error above which other elbow swings are tried
SWIVELS = tuple(np.radians(a) for a in (-150, -120, -90, -60, -30, 30, 60, 90, 120, 150, 180))
LEAN_TRIES = (0.25, 0.5)  # rad of lean added to the cheapest torso's where the wrist is off
# shares of the comfortable reach tried where the arm cannot meet the hand within its joints'
# ranges (reaching across the body): the shoulder brought nearer, the waist turned to it
NEARER = (0.8, 0.6, 0.4)
ERROR_SCALE = 0.7  # rad of wrist error that cost as much as torso.LEAN_SCALE of lean
# m of the arm inside arm_clearance.MARGIN of a leg or Robin that weigh as much as 1 rad of
# wrist error: a clear arm is preferred to a wrist turned as the hand is
DEPTH_SCALE = 0.005
# where the arm is still inside that clearance: torsos leant at least this much more than the
# cheapest (rad; capped at the limit) with the waist turned at least these shares of its
# range's upper end (the shoulder further right, the forearm rising beside a leg held over
# the palm rather than under its end)
CLEAR_LEANS = (0.15, 0.35, 1.0)
CLEAR_TURNS = (0.5, 1.0)


def _quat_mat(quat: np.ndarray) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, quat)
    return mat.reshape(3, 3)


def arm_score(error: float, depth: float) -> float:
    """How bad an arm is: its wrist error (rad) and its depth into the clearance kept from legs
    and Robin (m, :data:`DEPTH_SCALE`)."""
    return error + depth / DEPTH_SCALE


class Posture:
    """Writes the person's torso, arms and head each tick (see the module doc)."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.model, self.data = model, data

        fig = figure()  # the person's joints live in data.userdata (model.person_joints)

        def joint(name: str) -> tuple[int, int, np.ndarray, np.ndarray]:
            j = fig.joint(name)
            return j.adr, -1, j.axis.copy(), j.range.copy()

        arm = [joint(n) for n in names.person_arm_joints("r")]
        self.written = (
            *names.TORSO_JOINTS,
            *names.NECK_JOINTS,
            *names.person_arm_joints("r"),
            *names.person_arm_joints("l"),
        )
        self.written_q = fig.adr(self.written)
        ranges = fig.ranges(self.written)
        self.low, self.high = ranges[:, 0] + JOINT_LIMIT_MARGIN, ranges[:, 1] - JOINT_LIMIT_MARGIN
        body = model.body
        upper, fore, wrist = names.person_arm_bodies("r")
        self.shoulder = body(upper).pos.copy()  # in the chest
        self.upper = float(np.linalg.norm(body(fore).pos))
        self.fore = float(np.linalg.norm(body(wrist).pos))
        self.head = body(names.PERSON_HEAD_BODY).pos.copy()  # in the chest
        self.torso = Torso(model, fig, self.upper, self.fore)
        ranges_r = [(float(r[0]), float(r[1])) for *_, r in arm]
        self.angles = ArmAngles(self.upper, self.fore, ranges_r, [a for _, _, a, _ in arm[4:]])
        self.clearance = ArmClearance(model)
        self.idle_arm = IdleArm(model, fig)
        self.wrist_point = model.site(names.person_wrist_point("r")).pos.copy()
        mocap = body(names.HUMAN_MOCAP_BODY)
        self.mocap = int(mocap.mocapid[0])
        self.turn_q = fig.joint(names.HUMAN_HAND_TURN).adr
        self.gap = 0.0
        self.wrist_error = 0.0
        self.depth = 0.0
        self.crowded = False  # the last solve found legs or Robin's geoms within the arm's reach
        # the chosen arm's shoulder, wrist and elbow circle's radius (ArmClearance.near)
        self.arm_line: tuple[np.ndarray, np.ndarray, float] | None = None
        self._line: tuple[np.ndarray, np.ndarray, float] | None = None
        self.hand: ArticulatedHand | None = None  # its blends play out first, at each tick
        self._last: np.ndarray | None = None
        self._solved_at: float | None = None

    # --- the hand it follows --------------------------------------------------------------
    def hand_frame(self) -> tuple[np.ndarray, np.ndarray]:
        """World position of the hand's wrist point and the hand's rotation."""
        turn = self.data.userdata[self.turn_q : self.turn_q + 4]
        turn = turn if np.any(turn) else np.array([1.0, 0.0, 0.0, 0.0])  # fresh data: none
        rotation = _quat_mat(self.data.mocap_quat[self.mocap]) @ _quat_mat(turn)
        origin = self.data.mocap_pos[self.mocap]
        return origin + rotation @ self.wrist_point, rotation

    # --- solving --------------------------------------------------------------------------
    def solve(self) -> dict[str, float]:
        """Joint positions (by name) that bring the right arm to the hand; sets :attr:`gap`
        and :attr:`wrist_error` (rad the wrist's joints, at their limits, leave the forearm
        turned from the hand)."""
        wrist, hand = self.hand_frame()
        self.crowded = False
        torso, cost = self.torso.best(wrist)
        out, gap, error, depth = self.reach(wrist, hand, torso)
        line = self._line
        score = cost + (arm_score(error, depth) / ERROR_SCALE) ** 2
        tries: list[tuple[float, float]] = []
        if error > SWIVEL_TRY or depth > 0.0:  # lean further where that turns or clears the arm
            tries += [(torso.lean + extra, COMFORT) for extra in LEAN_TRIES]
        if error >= np.pi:  # the arm out of its range: the shoulder nearer (turned towards it)
            tries += [(0.0, share * COMFORT) for share in NEARER]
        others = []
        for least_lean, comfort in tries:
            if least_lean <= self.torso.lean_limit:
                others.append(self.torso.best(wrist, least_lean, comfort)[0])
        if depth > 0.0:  # the arm into a leg or Robin: stepped in full, turned, leant further
            step, high = self.torso.step_range[0], self.torso.turn_range[1]
            limit = self.torso.lean_limit
            others += [
                TorsoPose(float(step), float(share * high), min(torso.lean + extra, limit))
                for extra in CLEAR_LEANS
                for share in CLEAR_TURNS
            ]
        costs = [self.torso.cost_of(wrist, other) for other in others]
        for k in np.argsort(costs, kind="stable"):  # the cheapest torsos first
            if costs[k] >= score:  # the torso alone costs more than the best arm so far
                break
            trial = self.reach(wrist, hand, others[k])
            trial_score = costs[k] + (arm_score(*trial[2:]) / ERROR_SCALE) ** 2
            if trial_score < score:
                (out, gap, error, depth), score, line = trial, trial_score, self._line
        self.gap, self.wrist_error, self.depth, self.arm_line = gap, error, depth, line
        chosen = self._pose(out)
        out.update(self.idle_arm.solve(*self.torso.chest_frame(chosen), chosen.lean))
        return out

    @staticmethod
    def _pose(out: dict[str, float]) -> TorsoPose:
        step, turn, waist, chest = (out[n] for n in names.TORSO_JOINTS)
        return TorsoPose(step, turn, waist + chest)

    def reach(
        self, wrist: np.ndarray, hand: np.ndarray, pose: TorsoPose
    ) -> tuple[dict[str, float], float, float, float]:
        """Joint values (torso, neck, right arm) that reach ``wrist`` turned as ``hand`` from
        the torso ``pose``, the gap left, the wrist's error (:meth:`solve`) and how far the arm
        comes inside the clearance it keeps from legs and Robin
        (:class:`~robin_sim.figure.arm_clearance.ArmClearance`)."""
        origin, torso = self.torso.chest_frame(pose)
        shoulder = origin + torso @ self.shoulder
        reach = wrist - shoulder
        length = float(np.linalg.norm(reach))
        n = unit(reach)
        stretch = float(np.clip(length, abs(self.upper - self.fore) + 1e-3, self.upper + self.fore))
        stretch = min(stretch, self.upper + self.fore - 1e-4)
        gap = max(length - stretch, 0.0)
        # the wrist frame the hand's asks for: forearm along its x (towards the wrist); with the
        # forearm roll at zero the thumb side faces where the elbow bends (mid pronation)
        wanted = np.column_stack([-hand[:, 1], -hand[:, 2], hand[:, 0]])
        along = hand[:, 0].copy()
        along[2] = float(np.clip(along[2], *FOREARM_RISE))
        hint = wrist + self.fore * unit(along) - shoulder
        first = self.angles.solve(torso, shoulder, n, stretch, wanted, hint)
        ends = shoulder + stretch * n
        cos_a = (self.upper**2 + stretch**2 - self.fore**2) / (2 * self.upper * stretch)
        swing = self.upper * math.sqrt(max(1.0 - cos_a * cos_a, 0.0))  # the elbow's circle
        near = self.clearance.near(self.data, shoulder, ends, swing)
        self._line = (shoulder, ends, swing)
        self.crowded |= len(near[2]) > 0
        depth = float(self.clearance.depths(near, shoulder, first[2][None], ends)[0])
        (arm, error, _), best = first, arm_score(first[1], depth)
        if first[1] > SWIVEL_TRY or depth > 0.0:  # try the elbow swung about the reach axis
            solve = self.angles.solve
            trials = [
                solve(torso, shoulder, n, stretch, wanted, axis_rotation(n, angle) @ hint)
                for angle in SWIVELS
            ]
            elbows = np.array([t[2] for t in trials])
            depths = self.clearance.depths(near, shoulder, elbows, ends)
            for (trial_arm, trial_error, _), trial_depth in zip(trials, depths, strict=True):
                score = arm_score(trial_error, float(trial_depth))
                if score < best - 1e-3:
                    arm, error, depth, best = trial_arm, trial_error, float(trial_depth), score
        eyes = origin + torso @ self.head
        look = torso.T @ (wrist - eyes)
        yaw = LOOK * float(np.arctan2(-look[1], -look[0]))
        pitch = LOOK * float(np.arctan2(look[2], np.hypot(look[0], look[1])))
        waist, chest = self.torso.lean_joints(pose.lean)
        out = dict(zip(names.TORSO_JOINTS, (pose.step, pose.turn, waist, chest), strict=True))
        out.update(zip(names.NECK_JOINTS, (yaw, pitch), strict=True))
        out.update(zip(names.person_arm_joints("r"), arm, strict=True))
        return out, gap, error, depth

    def tick(self, now: float) -> None:
        """Play out :attr:`hand`'s blend into a pose at simulated time ``now``."""
        if self.hand is not None:
            self.hand.update(now)

    def update(self, now: float | None = None) -> None:
        """Solve and write the person's joints; nothing to solve while the hand has not moved
        or turned since the last call, nor within :data:`VIEW_PERIOD` of simulated time
        ``now`` after the last solve (a render at most that much behind the hand's arm), unless
        the last solve found a leg or Robin's geoms within the arm's reach or they are now
        (:attr:`crowded`, :attr:`arm_line`: they move while the hand holds still; an arm that
        trailed them by a view period reached 6-19 mm into a leg Robin held over the palm).
        Called before a render looks (no physics needs it)."""
        last, line = self._solved_at, self.arm_line
        crowded = self.crowded or (
            line is not None and len(self.clearance.near(self.data, *line)[2]) > 0
        )
        if not crowded and now is not None and last is not None and 0.0 <= now - last < VIEW_PERIOD:
            return
        key = np.concatenate(
            [
                self.data.mocap_pos[self.mocap],
                self.data.mocap_quat[self.mocap],
                self.data.userdata[self.turn_q : self.turn_q + 4],
            ]
        )
        if not crowded and self._last is not None and np.array_equal(key, self._last):
            return
        self._last = key
        self._solved_at = now
        values = self.solve()
        qpos = self.data.userdata  # the person's joints (model.person_joints)
        wanted = np.array([values[name] for name in self.written])
        qpos[self.written_q] = np.minimum(np.maximum(wanted, self.low), self.high)
        pose(self.model, self.data)
