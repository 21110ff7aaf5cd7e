"""What a click on the scene frame points at: a ray from the camera through the pixel.

:class:`Picker` keeps its own copy of the scene, set to the state of the frame the participant
saw (:meth:`Picker.show`), and casts :func:`mujoco.mj_ray` from the scene camera through the
clicked pixel. The camera model is MuJoCo's: the camera looks along its local -z with +y up,
``fovy`` is the vertical field of view and the horizontal one follows the frame's aspect. Pixel
coordinates are continuous image coordinates: x from 0 (left edge) to ``width`` (right edge), y
from 0 (top edge, the first row of the frame) to ``height`` (bottom edge), so image y runs
against the camera's +y. A ray that first meets any geom of a leg's body points at that leg; one
that meets the table top within :data:`SPOT_RADIUS` of a spot points at the spot; anything else
raises :class:`~robin_sim.live.inputs.LiveInputError` saying, in plain words, what was clicked
and what can be (legs and spots numbered from 1, as the page shows them).
"""

from __future__ import annotations

import math
import threading

import mujoco
import numpy as np

from pil.task.world import Target
from robin_sim.live.inputs import LiveInputError
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout, build_model
from robin_sim.render.renderer import camera_id
from robin_sim.render.worker import FrameState, apply_state

SPOT_RADIUS = 0.05  # m: a table-top hit this close to a spot points at it (spots lie 0.12 apart)
# Words in a hit geom's or body's name -> what the participant is told they clicked on.
PLAIN_PARTS = (
    ("bin", "the bin"),
    ("floor", "the floor"),
    ("table", "the table"),
    ("human", "your hand"),
    ("person", "your hand"),
    ("head", "Robin's head"),
    ("palm", "Robin's hand"),
    ("finger", "Robin's hand"),
    ("torso", "Robin's body"),
    ("arm", "Robin's arm"),
    ("wall", "the wall"),
)
# the renderer's default geom groups less group 1, the articulated person's (the participant's
# own stand-in): a click goes through the person's arm to the leg or spot behind it
VISIBLE_GROUPS = np.array([1, 0, 1, 0, 0, 0], np.uint8)


class Picker:
    """Resolves clicks on ``camera``'s ``width`` x ``height`` frames of ``layout``'s scene."""

    def __init__(
        self, layout: SceneLayout, width: int, height: int, camera: str = names.DEFAULT_CAMERA
    ) -> None:
        self.layout, self.width, self.height = layout, width, height
        self.model = build_model(layout)
        self.data = mujoco.MjData(self.model)
        mujoco.mj_forward(self.model, self.data)
        self.camera = camera_id(self.model, camera)
        self._lock = threading.Lock()
        self._leg_of_body = {
            self.model.body(names.leg_body(k)).id: k for k in range(len(layout.legs))
        }
        self._table_top = self.model.geom(names.TABLE_TOP_GEOM).id
        self._spots = np.array(
            [[x, y, spec.TABLE_TOP_Z] for x, y in layout.spots], dtype=float
        ).reshape(-1, 3)

    def show(self, state: FrameState) -> None:
        """Set the scene to ``state`` (the frame the participant sees now)."""
        with self._lock:
            apply_state(self.model, self.data, state)

    # --- the camera model ----------------------------------------------------------------------
    def _pose(self) -> tuple[np.ndarray, np.ndarray, float]:
        position = self.data.cam_xpos[self.camera].copy()
        axes = self.data.cam_xmat[self.camera].reshape(3, 3).copy()  # columns: x, y, z
        half = math.tan(math.radians(float(self.model.cam_fovy[self.camera])) / 2)
        return position, axes, half

    def ray(self, x: float, y: float) -> tuple[np.ndarray, np.ndarray]:
        """(origin, unit direction) of the ray through image point (x, y)."""
        position, axes, half = self._pose()
        aspect = self.width / self.height
        local = np.array(
            [(2 * x / self.width - 1) * half * aspect, (1 - 2 * y / self.height) * half, -1.0]
        )
        direction = axes @ local
        return position, direction / np.linalg.norm(direction)

    def project(self, point: np.ndarray) -> tuple[float, float]:
        """Image point (x, y) of world ``point`` (in front of the camera)."""
        position, axes, half = self._pose()
        local = axes.T @ (np.asarray(point, float) - position)
        if local[2] >= 0:
            raise ValueError(f"point {point} lies behind the camera")
        aspect = self.width / self.height
        u, v = local[0] / -local[2], local[1] / -local[2]
        return (u / (half * aspect) + 1) * self.width / 2, (1 - v / half) * self.height / 2

    def spot_pixels(self) -> list[tuple[float, float]]:
        """Image points of the table spots (for drawing them on the frame)."""
        with self._lock:
            return [self.project(spot) for spot in self._spots]

    def leg_pixels(self) -> list[tuple[float, float, int]]:
        """(x, y, leg) of each leg on the frame now shown (legs behind the camera left out)."""
        with self._lock:
            seen = []
            for body, leg in self._leg_of_body.items():
                try:
                    x, y = self.project(self.data.xpos[body])
                except ValueError:
                    continue
                if 0 <= x < self.width and 0 <= y < self.height:
                    seen.append((x, y, leg))
            return seen

    # --- picking -------------------------------------------------------------------------------
    def pick(self, x: float, y: float) -> Target:
        """The leg or spot under image point (x, y); else :class:`LiveInputError`."""
        with self._lock:
            origin, direction = self.ray(x, y)
            geom = np.array([-1], np.int32)
            distance = mujoco.mj_ray(
                self.model, self.data, origin, direction, VISIBLE_GROUPS, 1, -1, geom
            )
            hit = int(geom[0])
            if distance >= 0 and hit >= 0:
                leg = self._leg_of_body.get(int(self.model.geom_bodyid[hit]))
                if leg is not None:
                    return Target("leg", leg)
                if hit == self._table_top and len(self._spots):
                    point = origin + distance * direction
                    gaps = np.linalg.norm(self._spots[:, :2] - point[:2], axis=1)
                    spot = int(np.argmin(gaps))
                    if gaps[spot] <= SPOT_RADIUS:
                        return Target("spot", spot)
            what = "nothing (the background)" if hit < 0 else self._name(hit)
        raise LiveInputError(
            f"That click was on {what}, not on a leg or a spot. Click one of the numbered "
            f"legs (1-{len(self._leg_of_body)}) or spots (1-{len(self._spots)}, the rings on "
            "the table)."
        )

    def _name(self, geom: int) -> str:
        """What a participant would call the thing the click hit."""
        if geom == self._table_top:
            return "the table away from the spots"
        name = mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_GEOM, geom) or ""
        body = (
            mujoco.mj_id2name(self.model, mujoco.mjtObj.mjOBJ_BODY, self.model.geom_bodyid[geom])
            or ""
        )
        words = f"{name} {body}".lower()
        for part, plain in PLAIN_PARTS:
            if part in words:
                return plain
        return "something else"
