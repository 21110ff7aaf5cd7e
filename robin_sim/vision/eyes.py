"""Robin's eye cameras as the gesture reader sees them: RGB and depth under a condition.

:class:`EyeCameras` renders the two eye cameras (``head_left_eye``, ``head_right_eye``) with
the narrow field of view of a foveal camera (the KIT head pairs a wide and a narrow camera in
each eye; the model's eye cameras are the wide ones, so the renderer narrows them for the
duration of a render only). A :class:`EyeCondition` scales the scene's light, turns its main light,
adds Gaussian sensor noise (sd in 8-bit units) and blur; the depth image gets noise too
(``depth_noise`` m).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import mujoco
import numpy as np

from pil.errors import RobinPilError
from robin_sim.closing import ClosesOnExit
from robin_sim.model import names
from robin_sim.render.renderer import open_renderer
from robin_sim.vision.condition_params import CONDITION_PARAMS

FOVEAL_FOVY = 20.0  # degrees
EYE_SIZE = 112  # pixels, square eye images
DEPTH_NOISE = 0.003  # m, sd of the depth image's noise


class ConditionError(RobinPilError):
    """A camera condition out of range (lighting, noise, blur)."""


@dataclass(frozen=True, slots=True)
class EyeCondition:
    """What the eyes see under: light scale (1 = the scene's), light turn, noise and blur."""

    lighting: float = 1.0  # scale of every light's intensity (and the headlight's)
    light_turn: float = 0.0  # rad the main light's direction turns about the vertical
    light_tilt: float = 0.0  # rad it tilts away from straight down
    camera_noise: float = 0.0  # sd of the pixel noise, 8-bit units
    blur: float = 0.0  # sd of the Gaussian blur, pixels (0: none)

    def __post_init__(self) -> None:
        lighting, noise = CONDITION_PARAMS["lighting"], CONDITION_PARAMS["camera_noise"]
        for name, value, low, high in (
            ("lighting", self.lighting, lighting.low, lighting.high),
            ("camera_noise", self.camera_noise, noise.low, noise.high),
            ("blur", self.blur, 0.0, 10.0),
        ):
            if not np.isfinite(value) or not (-np.inf if low is None else low) <= value <= (
                np.inf if high is None else high
            ):
                raise ConditionError(f"{name} must lie in [{low:g}, {high:g}], got {value!r}")


@dataclass(frozen=True, slots=True)
class EyeView:
    """One eye's image: RGB (H, W, 3) uint8, depth (H, W) m, its focal length in pixels, and
    the height (H, W, world z in m) of each pixel's point, from the depth and the eye's pose
    (Robin knows where its eyes are): what lies on the table top is told apart by it."""

    rgb: np.ndarray
    depth: np.ndarray
    focal: float
    height: np.ndarray


def pixel_rays(size: int, focal: float) -> tuple[np.ndarray, np.ndarray]:
    """Per pixel of a ``size`` x ``size`` image, its ray's right and up components per metre of
    depth (``focal`` in pixels; image rows downwards): fixed for a camera, computed once."""
    v, u = np.mgrid[0:size, 0:size]
    return (u + 0.5 - size / 2) / focal, -(v + 0.5 - size / 2) / focal


def pixel_heights(
    depth: np.ndarray,
    rays: tuple[np.ndarray, np.ndarray],
    position: np.ndarray,
    frame: np.ndarray,
) -> np.ndarray:
    """World z (m) of each pixel's point: ``depth`` (m along the optical axis) along ``rays``
    (:func:`pixel_rays`) seen from a camera at ``position`` with orientation ``frame`` (3x3,
    MuJoCo's: looking along -z, y up)."""
    right, up = rays
    frame = np.asarray(frame).reshape(3, 3)
    # z of position + frame @ (right * d, up * d, -d): only frame's last row matters
    return position[2] + depth * (frame[2, 0] * right + frame[2, 1] * up - frame[2, 2])


class EyeCameras(ClosesOnExit):
    """Renders both eye cameras of ``model`` at ``size`` x ``size`` pixels."""

    def __init__(self, model: mujoco.MjModel, size: int = EYE_SIZE, fovy: float = FOVEAL_FOVY):
        self.model, self.size, self.fovy = model, size, fovy
        self.cameras = tuple(model.camera(c).id for c in names.HEAD_CAMERAS)
        self.focal = size / (2 * np.tan(np.radians(fovy) / 2))
        self._rays = pixel_rays(size, self.focal)
        self._renderer: mujoco.Renderer | None = open_renderer(model, size, size)
        self._renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
        self._option = mujoco.MjvOption()  # default groups: what a video frame shows

    def render(
        self,
        data: mujoco.MjData,
        condition: EyeCondition = EyeCondition(),
        rng: np.random.Generator | None = None,
    ) -> tuple[EyeView, EyeView]:
        """Left and right eye views of ``data`` under ``condition`` (noise drawn from ``rng``)."""
        if self._renderer is None:
            raise RobinPilError("eye cameras are closed")
        rng = rng if rng is not None else np.random.default_rng(0)
        renderer = self._renderer
        saved = self._apply(condition)
        try:
            views = []
            for cam in self.cameras:
                renderer.update_scene(data, cam, self._option)
                rgb = renderer.render().copy()
                renderer.enable_depth_rendering()
                depth = renderer.render().astype(np.float64)
                renderer.disable_depth_rendering()
                depth += rng.normal(0.0, DEPTH_NOISE, depth.shape)
                height = pixel_heights(depth, self._rays, data.cam_xpos[cam], data.cam_xmat[cam])
                rgb = self._degrade(rgb, condition, rng)
                views.append(EyeView(rgb, depth, self.focal, height))
        finally:
            self._restore(saved)
        return views[0], views[1]

    def _apply(self, condition: EyeCondition) -> tuple[np.ndarray, ...]:
        model = self.model
        head = model.vis.headlight
        saved = (
            model.cam_fovy[list(self.cameras)].copy(),
            model.light_diffuse.copy(),
            model.light_specular.copy(),
            model.light_dir.copy(),
            np.array(head.diffuse),
            np.array(head.ambient),
        )
        model.cam_fovy[list(self.cameras)] = self.fovy
        model.light_diffuse[:] *= condition.lighting
        model.light_specular[:] *= condition.lighting
        head.diffuse[:] = saved[4] * condition.lighting
        head.ambient[:] = saved[5] * condition.lighting
        if model.nlight and (condition.light_turn or condition.light_tilt):
            c, s = np.cos(condition.light_tilt), np.sin(condition.light_tilt)
            turn = condition.light_turn
            model.light_dir[0] = (s * np.cos(turn), s * np.sin(turn), -c)
        return saved

    def _restore(self, saved: tuple[np.ndarray, ...]) -> None:
        model = self.model
        model.cam_fovy[list(self.cameras)] = saved[0]
        model.light_diffuse[:], model.light_specular[:], model.light_dir[:] = saved[1:4]
        model.vis.headlight.diffuse[:] = saved[4]
        model.vis.headlight.ambient[:] = saved[5]

    @staticmethod
    def _degrade(rgb: np.ndarray, condition: EyeCondition, rng: np.random.Generator) -> np.ndarray:
        if condition.blur > 0:
            rgb = cv2.GaussianBlur(rgb, (0, 0), condition.blur)
        if condition.camera_noise > 0:
            noisy = rgb + rng.normal(0.0, condition.camera_noise, rgb.shape)
            rgb = np.clip(noisy, 0, 255).astype(np.uint8)
        return rgb

    def close(self) -> None:
        """Free the OpenGL context; idempotent."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
