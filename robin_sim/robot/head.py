"""Robin's gaze: the head's pan/tilt targets follow an attention point, tick by tick.

:class:`HeadController` joins the :class:`~robin_sim.control.simulator.Simulator` as a tick
controller. Each tick it aims the left eye camera (``names.EYE_CAMERA``) at the attention
point (:func:`robin_sim.control.gaze.head_angles` taken from the eye's position, so that the
eye's optical axis passes through the point) and moves the head's position targets toward that
aim with a speed and acceleration limit, inside the joint limits read from the model (less a
small margin, so that a joint limit never becomes an active constraint). Only the two head
actuators are written: the arms, hands and legs never feel it.

Attention is either a fixed point (:meth:`HeadController.attend`, e.g. the leg the person
points at) or a named source that moves (:meth:`HeadController.attend_to`, e.g. the person's
palm or the robot's own hand), re-read every tick. Whoever else commands the head (the vision
detector's :func:`~robin_sim.control.gaze.look_at`) is let be: the controller stops writing
until the next ``attend`` call. Nothing here draws random numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from robin_sim.control.gaze import head_angles
from robin_sim.control.simulator import Simulator
from robin_sim.model import names

MAX_SPEED = 2.0  # rad/s, largest speed of a head target
MAX_ACCEL = 8.0  # rad/s^2, largest change of that speed
LIMIT_MARGIN = 0.02  # rad kept clear of each joint limit

PointSource = Callable[[], np.ndarray]


@dataclass(frozen=True, slots=True)
class AttentionChange:
    """From ``time`` (s, simulated) on the head looks at ``kind`` (a source name or a label)."""

    time: float
    kind: str


class HeadController:
    """Moves the head's targets toward the attention point (see the module doc).

    ``sources`` names the moving points :meth:`attend_to` may follow, each a function giving
    the point now (m, world frame).
    """

    def __init__(
        self,
        sim: Simulator,
        sources: Mapping[str, PointSource],
        *,
        max_speed: float = MAX_SPEED,
        max_accel: float = MAX_ACCEL,
    ) -> None:
        model, data = sim.model, sim.data
        self.sim, self.sources = sim, dict(sources)
        self.max_speed, self.max_accel = max_speed, max_accel
        self.actuators = np.array([model.actuator(a).id for a in names.HEAD_ACTUATORS])
        joints = [model.joint(j).id for j in names.HEAD_JOINTS]
        low = np.maximum(model.jnt_range[joints, 0], model.actuator_ctrlrange[self.actuators, 0])
        high = np.minimum(model.jnt_range[joints, 1], model.actuator_ctrlrange[self.actuators, 1])
        self.low, self.high = low + LIMIT_MARGIN, high - LIMIT_MARGIN
        self.eye = model.camera(names.EYE_CAMERA).id
        self._command = data.ctrl[self.actuators].copy()
        self._speed = np.zeros(2)
        self._target: PointSource | None = None
        self._written: np.ndarray | None = None  # what this controller last wrote
        self.kind = "home"
        self.changes: list[AttentionChange] = []
        self._remove: Callable[[], None] | None = sim.add_controller(self._tick)

    # --- attention -----------------------------------------------------------------------------
    def attend(self, point: np.ndarray, kind: str = "point") -> None:
        """Look at the fixed ``point`` (m, world frame); ``kind`` labels it in :attr:`changes`."""
        fixed = np.array(point, float)
        self._set(lambda: fixed, kind)

    def attend_to(self, kind: str) -> None:
        """Follow the moving source ``kind`` (one of :attr:`sources`)."""
        if kind not in self.sources:
            raise ValueError(f"unknown attention {kind!r}; valid choices: {sorted(self.sources)}")
        self._set(self.sources[kind], kind)

    def _set(self, source: PointSource, kind: str) -> None:
        self._target, self.kind = source, kind
        self.changes.append(AttentionChange(self.sim.time, kind))
        self._command = self.sim.data.ctrl[self.actuators].copy()  # start from where it is
        if self._written is None or not np.array_equal(self._command, self._written):
            self._speed = np.zeros(2)  # someone else moved the targets: start at rest
        self._written = self._command.copy()

    def kind_at(self, time: float) -> str:
        """What the head attended at simulated ``time`` ("home" before any attention)."""
        kind = "home"
        for change in self.changes:
            if change.time <= time:
                kind = change.kind
        return kind

    # --- state ---------------------------------------------------------------------------------
    @property
    def aim(self) -> np.ndarray | None:
        """(pan, tilt) that would point the left eye at the attention point now, in limits."""
        if self._target is None:
            return None
        data = self.sim.data
        angles = head_angles(self.sim.model, data, self._target(), data.cam_xpos[self.eye])
        return np.clip(angles, self.low, self.high)

    def close(self) -> None:
        """Leave the simulator's tick (idempotent)."""
        if self._remove is not None:
            self._remove()
            self._remove = None

    # --- the tick ------------------------------------------------------------------------------
    def _tick(self, sim: Simulator) -> None:
        if self._target is None or self._written is None:
            return
        ctrl = sim.data.ctrl
        if not np.array_equal(ctrl[self.actuators], self._written):
            self._target = None  # another part commands the head now; wait for the next attend
            return
        aim = self.aim
        assert aim is not None
        dt = sim.control_dt
        error = aim - self._command
        # the speed from which the head can still stop at the aim, capped by the speed limit
        wanted = np.sign(error) * np.minimum(
            np.minimum(self.max_speed, np.sqrt(2.0 * self.max_accel * np.abs(error))),
            np.abs(error) / dt,
        )
        step = self.max_accel * dt
        self._speed += np.clip(wanted - self._speed, -step, step)
        self._command = np.clip(self._command + self._speed * dt, self.low, self.high)
        ctrl[self.actuators] = self._command
        self._written = self._command.copy()
