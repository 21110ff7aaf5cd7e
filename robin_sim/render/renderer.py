"""Off-screen frames of a MuJoCo model from a named camera, at video rate.

:class:`FrameRenderer` wraps :class:`mujoco.Renderer` with the project's errors (unknown camera,
frame larger than the model's off-screen buffer) and a shadow switch. :class:`FrameClock` says
how many video frames are due at a given simulation time, so an episode renders once per video
frame from its per-control-tick callback, never once per physics step. :class:`CloseUpRenderer`
gives segmentation and depth views of a free camera aimed at a point, as an :class:`Observation`
that projects world points to pixels and lifts pixels back to world points (used by
:mod:`robin_sim.render.checks`).

Renders show body positions from ``data``'s last forward pass (``mj_step`` runs one first).

Call :func:`robin_sim.render.gl_backend.ensure_gl_backend` before importing this module in a
program.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from pil.errors import InvalidChoiceError, RobinPilError
from robin_sim.closing import ClosesOnExit
from robin_sim.model.names import DEFAULT_CAMERA
from robin_sim.render.frame_spec import check_fits


class RenderError(RobinPilError):
    """A frame that cannot be rendered as asked (size, closed renderer)."""


class UnknownCameraError(InvalidChoiceError):
    """A camera name that the model does not define."""


def camera_names(model: mujoco.MjModel) -> tuple[str, ...]:
    """Names of the model's cameras, in model order."""
    return tuple(
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_CAMERA, i) or f"#{i}"
        for i in range(model.ncam)
    )


def camera_id(model: mujoco.MjModel, camera: str) -> int:
    """Id of the camera named ``camera``; :class:`UnknownCameraError` lists the valid names."""
    index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, camera)
    if index < 0:
        raise UnknownCameraError("camera", camera, camera_names(model))
    return index


def open_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """MuJoCo's renderer of ``width`` x ``height`` frames; MuJoCo's own refusal of a frame
    larger than the model's off-screen buffer becomes one :class:`RenderError` naming both
    (the commands check their sizes at their edge:
    :func:`robin_sim.render.frame_spec.check_size`)."""
    try:
        return mujoco.Renderer(model, height, width)
    except ValueError as error:
        buffer = (int(model.vis.global_.offwidth), int(model.vis.global_.offheight))
        try:
            check_fits(width, height, buffer)
        except RobinPilError as too_large:
            raise RenderError(str(too_large)) from None
        raise RenderError(f"cannot render {width}x{height} frames: {error}") from None


class FrameRenderer(ClosesOnExit):
    """RGB frames (H, W, 3) uint8 of one camera of ``model``.

    ``shadows=False`` roughly doubles the frame rate of software (llvmpipe) rendering;
    ``reflections=False`` (no mirror pass for the reflective floor) saves another third. Use as a
    context manager or call :meth:`close`; the OpenGL context is freed there.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        width: int = 640,
        height: int = 480,
        camera: str = DEFAULT_CAMERA,
        shadows: bool = True,
        reflections: bool = True,
    ) -> None:
        self.camera = camera
        self.camera_id = camera_id(model, camera)
        self.width = width
        self.height = height
        self.shadows = shadows
        self._renderer: mujoco.Renderer | None = open_renderer(model, width, height)
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = shadows
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = reflections

    def render(self, data: mujoco.MjData) -> np.ndarray:
        """The camera's view of ``data`` (positions from its last forward pass)."""
        if self._renderer is None:
            raise RenderError(f"renderer of camera {self.camera!r} is closed")
        self._renderer.update_scene(data, self.camera_id)
        return self._renderer.render()

    def close(self) -> None:
        """Free the OpenGL resources; idempotent."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


class FrameClock:
    """Video frame schedule in simulation time: frame ``k`` shows time ``k / fps``.

    The episode calls :meth:`frames_due` once per control tick (period ``tick_dt``); it returns
    how many frames to emit now (0 or 1 when ticks are faster than frames; a frame rendered once
    is written several times when ticks are slower), so the video plays at real time.
    """

    def __init__(self, fps: float, tick_dt: float) -> None:
        if not math.isfinite(fps) or fps <= 0:
            raise RenderError(f"video frame rate must be a positive number, got {fps!r}")
        if not math.isfinite(tick_dt) or tick_dt <= 0:
            raise RenderError(f"control tick period must be positive seconds, got {tick_dt!r}")
        self.fps = float(fps)
        self.tick_dt = float(tick_dt)
        self.frames_emitted = 0

    def next_frame_time(self) -> float:
        """Simulation time of the next frame to emit."""
        return self.frames_emitted / self.fps

    def frames_due(self, sim_time: float) -> int:
        """Number of frames to emit at ``sim_time`` (and count them as emitted)."""
        # A tick that lands within 1e-6 of a tick period before a frame time takes that frame,
        # so float round-off in sim time never drops or delays a frame.
        last_due = math.floor(sim_time * self.fps + 1e-6 * self.tick_dt * self.fps)
        due = max(0, last_due + 1 - self.frames_emitted)
        self.frames_emitted += due
        return due


@dataclass(frozen=True, slots=True)
class Observation:
    """One view: body id per pixel (-1 background), depth per pixel (m) and the camera."""

    body: np.ndarray  # (H, W) int
    depth: np.ndarray  # (H, W) float, metres along the view axis
    position: np.ndarray  # camera centre (3,)
    rotation: np.ndarray  # rows: right, up, forward (3, 3)
    focal: tuple[float, float]  # fx, fy in pixels
    centre: tuple[float, float]  # cx, cy in pixel-index coordinates

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pixel coordinates (N, 2) as (column, row) and depths (N,) of world ``points``."""
        local = (np.atleast_2d(points) - self.position) @ self.rotation.T
        depth = local[:, 2]
        u = self.centre[0] + self.focal[0] * local[:, 0] / depth
        v = self.centre[1] - self.focal[1] * local[:, 1] / depth
        return np.stack([u, v], axis=1), depth

    def lift(self, mask: np.ndarray) -> np.ndarray:
        """World points (N, 3) of the pixels in ``mask`` (row-major order)."""
        rows, cols = np.nonzero(mask)
        z = self.depth[rows, cols]
        x = (cols - self.centre[0]) * z / self.focal[0]
        y = -(rows - self.centre[1]) * z / self.focal[1]
        return np.stack([x, y, z], axis=1) @ self.rotation + self.position


class CloseUpRenderer(ClosesOnExit):
    """Segmentation and depth views of a free camera aimed at a point (for
    :mod:`robin_sim.render.checks`).

    Every geom group is drawn (visual and collision geoms each map to their body), sites are
    not. Reuse one across many views; close it (or use it as a context manager) when done.
    """

    def __init__(self, model: mujoco.MjModel, width: int = 320, height: int = 240) -> None:
        self.model = model
        self.width, self.height = width, height
        self._renderer: mujoco.Renderer | None = open_renderer(model, width, height)
        self._option = mujoco.MjvOption()
        self._option.geomgroup[:] = 1  # collision and visual geoms: each maps to its body
        self._option.sitegroup[:] = 0  # sites are markers, not matter

    def observe(
        self,
        data: mujoco.MjData,
        lookat: np.ndarray,
        azimuth: float,
        elevation: float,
        distance: float,
    ) -> Observation:
        """Segmentation and depth of a free camera aimed at ``lookat``."""
        if self._renderer is None:
            raise RenderError("close-up renderer is closed")
        camera = mujoco.MjvCamera()
        camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        camera.lookat[:] = lookat
        camera.azimuth, camera.elevation, camera.distance = azimuth, elevation, distance
        renderer = self._renderer
        renderer.update_scene(data, camera, self._option)
        renderer.enable_segmentation_rendering()
        segmentation = renderer.render()
        renderer.disable_segmentation_rendering()
        renderer.enable_depth_rendering()
        depth = renderer.render().astype(np.float64)
        renderer.disable_depth_rendering()
        is_geom = (segmentation[..., 1] == mujoco.mjtObj.mjOBJ_GEOM) & (segmentation[..., 0] >= 0)
        body = np.where(is_geom, self.model.geom_bodyid[np.maximum(segmentation[..., 0], 0)], -1)
        return self._with_camera(body, depth)

    def _with_camera(self, body: np.ndarray, depth: np.ndarray) -> Observation:
        assert self._renderer is not None, "the renderer is closed"
        eyes = self._renderer.scene.camera  # left and right eye; a mono render uses their mean
        position = (np.array(eyes[0].pos) + np.array(eyes[1].pos)) / 2
        forward = np.array(eyes[0].forward, dtype=float)
        up = np.array(eyes[0].up, dtype=float)
        right = np.cross(forward, up)
        eye = eyes[0]
        near, top, bottom = eye.frustum_near, eye.frustum_top, eye.frustum_bottom
        half_height = (top - bottom) / 2
        half_width = (
            eye.frustum_width / 2
            if eye.frustum_width > 0
            else (half_height * self.width / self.height)
        )
        left = eye.frustum_center - half_width
        fx = self.width * near / (2 * half_width)
        fy = self.height * near / (2 * half_height)
        cx = -self.width * left / (2 * half_width) - 0.5  # pixel index of the optical axis
        cy = self.height * top / (2 * half_height) - 0.5
        rotation = np.stack([right, up, forward])
        return Observation(body, depth, position, rotation, (fx, fy), (cx, cy))

    def close(self) -> None:
        """Free the OpenGL context; idempotent."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
