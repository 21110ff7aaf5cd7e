"""The person's torso for a reach: a step, a waist turn and a spine lean, as little as will do.

The torso is two segments (``person.xml``): the abdomen turns and leans at the waist
(``human_waist_lean``), the chest leans again on it (``human_chest_lean``), about the same
axis, so the chest's tilt from vertical is the sum of the two lean joints. :class:`Torso` calls
that sum *the lean* and shares it between the joints in proportion to their upper limits, as a
spine bends along its length; the lean's limit is the sum of those limits.

:meth:`Torso.best` finds the step, turn and lean that bring the right shoulder near enough to a
wrist to reach it and cost least: each term is squared and divided by its scale, so that
:data:`LEAN_SCALE` rad of lean, :data:`STEP_SCALE` m of step and :data:`TURN_SCALE` rad of turn
cost the same, and a wrist :data:`REACH_SCALE` m beyond the comfortable reach
(:data:`COMFORT` of the arm's length) costs as much again; a wrist beyond the arm's length costs
steeply (:data:`GAP_SCALE`). A step is cheaper than the lean that reaches as far, so the person
steps towards the table first and leans for the rest (and to reach down). The search is a
vectorised grid over the three, refined around its best by halving a 3 x 3 x 3 stencil
(deterministic; about 1 000 poses costed in a handful of array operations).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from robin_sim.model import names
from robin_sim.model.person_joints import Figure, figure

LEAN_SCALE = 0.5  # rad of lean that cost as much as ...
STEP_SCALE = 1.0  # ... m of step towards the table (a step of 0.1 m reaches as far as 0.2 rad
TURN_SCALE = 0.8  # of lean and costs a sixteenth as much), and rad of waist turn
COMFORT = 0.98  # of the arm's length (upper arm and forearm): reached without a step
REACH_SCALE = 0.04  # m beyond the comfortable reach that cost as much as LEAN_SCALE of lean
GAP_SCALE = 0.004  # m beyond the arm's length: as much again
GRID = (7, 9, 10)  # values of step, turn and lean the search starts from
REFINE = 4  # rounds of the halving stencil around the best
_UNIT_GRID = np.stack(
    np.meshgrid(*[np.linspace(0.0, 1.0, n) for n in GRID], indexing="ij"), axis=-1
).reshape(-1, 3)
_STENCIL = np.stack(np.meshgrid(*[[-1.0, 0.0, 1.0]] * 3, indexing="ij"), -1).reshape(-1, 3)


@dataclass(frozen=True)
class TorsoPose:
    """Step (m, along x), waist turn and lean (rad: the chest's tilt from vertical)."""

    step: float
    turn: float
    lean: float


def lean_of(values: np.ndarray) -> float:
    """The lean in the person's joint values (``data.userdata``): the chest's tilt from vertical
    (rad), the sum of the lean joints (:data:`~robin_sim.model.names.PERSON_LEAN_JOINTS`, about
    one axis), positive forwards."""
    return float(values[figure().adr(names.PERSON_LEAN_JOINTS)].sum())


def lean_limit() -> float:
    """The most the person can lean: the sum of the lean joints' upper limits (rad)."""
    return float(figure().ranges(names.PERSON_LEAN_JOINTS)[:, 1].sum())


def _axis(fig: Figure, name: str, want: tuple[float, float, float]) -> np.ndarray:
    axis = fig.joint(name).axis
    if not np.allclose(axis, want):
        raise ValueError(f"person joint {name} has axis {axis.tolist()}; the torso needs {want}")
    return axis.copy()


class Torso:
    """The torso's geometry read from the model, and the search for its pose (module doc)."""

    def __init__(self, model: mujoco.MjModel, fig: Figure, upper: float, fore: float) -> None:
        step, turn, waist, chest = names.TORSO_JOINTS
        _axis(fig, step, (1.0, 0.0, 0.0))
        self.turn_axis = _axis(fig, turn, (0.0, 0.0, 1.0))
        self.lean_axis = _axis(fig, waist, (0.0, -1.0, 0.0))
        _axis(fig, chest, (0.0, -1.0, 0.0))
        self.step_range = fig.joint(step).range.copy()
        self.turn_range = fig.joint(turn).range.copy()
        self.lean_limit = lean_limit()
        self.share = float(fig.joint(waist).range[1] / self.lean_limit)  # the abdomen's share
        body = model.body
        self.hip = body(names.PERSON_BODY).pos + body(names.PERSON_TORSO_BODY).pos  # the waist
        self.chest = body(names.PERSON_CHEST_BODY).pos.copy()  # in the abdomen
        self.shoulder = body(names.person_arm_bodies("r")[0]).pos.copy()  # in the chest
        self.reach = upper + fore

    def lean_joints(self, lean: float) -> tuple[float, float]:
        """The waist's and the chest's lean joints for a lean (they sum to it)."""
        return self.share * lean, (1.0 - self.share) * lean

    def chest_frame(self, pose: TorsoPose) -> tuple[np.ndarray, np.ndarray]:
        """World origin and rotation of the chest."""
        turn = axis_rotation(self.turn_axis, pose.turn)
        abdomen = turn @ axis_rotation(self.lean_axis, self.share * pose.lean)
        origin = self.hip + np.array([pose.step, 0.0, 0.0]) + abdomen @ self.chest
        return origin, turn @ axis_rotation(self.lean_axis, pose.lean)

    def shoulders(self, step: np.ndarray, turn: np.ndarray, lean: np.ndarray) -> np.ndarray:
        """(n, 3) world positions of the right shoulder for arrays of step, turn and lean."""
        a = self.share * lean
        c, p = self.chest, self.shoulder
        # about -y by angle q: (x, z) -> (x cos q - z sin q, x sin q + z cos q)
        vx = c[0] * np.cos(a) - c[2] * np.sin(a) + p[0] * np.cos(lean) - p[2] * np.sin(lean)
        vz = c[0] * np.sin(a) + c[2] * np.cos(a) + p[0] * np.sin(lean) + p[2] * np.cos(lean)
        vy = np.full_like(vx, c[1] + p[1])
        x = vx * np.cos(turn) - vy * np.sin(turn)
        y = vx * np.sin(turn) + vy * np.cos(turn)
        return np.column_stack([x + step, y, vz]) + self.hip

    def cost(
        self,
        wrist: np.ndarray,
        step: np.ndarray,
        turn: np.ndarray,
        lean: np.ndarray,
        comfort: float = COMFORT,
    ) -> np.ndarray:
        """Each pose's cost for reaching ``wrist`` (module doc; ``comfort``: the share of the
        arm's length reached without cost)."""
        d = np.linalg.norm(wrist - self.shoulders(step, turn, lean), axis=1)
        over = np.maximum(d - comfort * self.reach, 0.0) / REACH_SCALE
        gap = np.maximum(d - self.reach, 0.0) / GAP_SCALE
        upright = (lean / LEAN_SCALE) ** 2 + (step / STEP_SCALE) ** 2 + (turn / TURN_SCALE) ** 2
        return upright + over**2 + gap**2

    def cost_of(self, wrist: np.ndarray, pose: TorsoPose) -> float:
        """One pose's cost for reaching ``wrist``."""
        step, turn, lean = (np.array([v]) for v in (pose.step, pose.turn, pose.lean))
        return float(self.cost(wrist, step, turn, lean)[0])

    def best(
        self, wrist: np.ndarray, least_lean: float = 0.0, comfort: float = COMFORT
    ) -> tuple[TorsoPose, float]:
        """The cheapest pose for reaching ``wrist`` with a lean of at least ``least_lean`` (and
        the shoulder within ``comfort`` of the arm's length), and its cost."""
        low = np.array([self.step_range[0], self.turn_range[0], min(least_lean, self.lean_limit)])
        high = np.array([self.step_range[1], self.turn_range[1], self.lean_limit])
        grid = low + _UNIT_GRID * (high - low)
        spacing = (high - low) / (np.array(GRID) - 1)
        costs = self.cost(wrist, grid[:, 0], grid[:, 1], grid[:, 2], comfort)
        best = grid[int(np.argmin(costs))]
        least = float(costs.min())
        stencil = _STENCIL
        for _ in range(REFINE):
            spacing = spacing / 2.0
            trial = np.clip(best + stencil * spacing, low, high)
            costs = self.cost(wrist, trial[:, 0], trial[:, 1], trial[:, 2], comfort)
            k = int(np.argmin(costs))
            if costs[k] < least:
                best, least = trial[k], float(costs[k])
        return TorsoPose(float(best[0]), float(best[1]), float(best[2])), least


def axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` (rad) about the unit ``axis``."""
    quat = np.zeros(4)
    mujoco.mju_axisAngle2Quat(quat, axis, angle)
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, quat)
    return mat.reshape(3, 3)
