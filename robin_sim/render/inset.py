"""The robot's eye view as a small picture-in-picture in the episode video.

:class:`EyeInset` renders the left eye camera (:data:`robin_sim.model.names.EYE_CAMERA`) of a
:class:`~robin_sim.render.worker.FrameState` at a quarter of the video's width and height
(160x120 at 640x480), in this process, with its own copy of the scene, once per video frame
(never per physics step). :func:`draw_eye_inset` pastes it into the top right corner of a frame,
framed, with a label under it. The inset shows the state's own ``qpos``, so it is
pixel-identical to a direct render of the eye camera at the inset's size.
"""

from __future__ import annotations

import cv2
import mujoco
import numpy as np

from robin_sim.closing import ClosesOnExit
from robin_sim.model.names import EYE_CAMERA
from robin_sim.model.scene import SceneLayout, build_model
from robin_sim.render.overlay import DIM_COLOUR, FONT, TEXT_COLOUR
from robin_sim.render.worker import FrameState, apply_state, warmed_renderer

INSET_FRACTION = 4  # the inset is 1/4 of the frame's width and height
INSET_LABEL = "robot's left eye"
HELD_EYE = "held"  # in a states file: the frame repeats the last eye view


def inset_size(width: int, height: int) -> tuple[int, int]:
    """(width, height) of the inset in a ``width`` x ``height`` frame: 160x120 at 640x480."""
    return max(1, width // INSET_FRACTION), max(1, height // INSET_FRACTION)


def inset_box(width: int, height: int) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the inset's pixels in a ``width`` x ``height`` frame (top right)."""
    w, h = inset_size(width, height)
    margin = max(2, round(6 * height / 480))
    x1 = width - margin
    return x1 - w, margin, x1, margin + h


def inset_region(width: int, height: int, label: str = INSET_LABEL) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of every pixel :func:`draw_eye_inset` changes: the inset, its frame
    and the label's band under it."""
    x0, y0, x1, y1 = inset_box(width, height)
    scale = height / 480.0
    (_, text_h), _ = cv2.getTextSize(label, FONT, 0.4 * scale, max(1, round(scale)))
    return x0 - 2, y0 - 2, x1 + 2, min(height, y1 + 2 + text_h + round(8 * scale))


def draw_eye_inset(frame: np.ndarray, eye: np.ndarray, label: str = INSET_LABEL) -> np.ndarray:
    """Paste ``eye`` (its size from :func:`inset_size`) into ``frame`` in place, framed and
    labelled below; returns ``frame``."""
    height, width = frame.shape[:2]
    x0, y0, x1, y1 = inset_box(width, height)
    if eye.shape != (y1 - y0, x1 - x0, 3):
        raise ValueError(f"eye view has shape {eye.shape}; the inset needs {(y1 - y0, x1 - x0, 3)}")
    scale = height / 480.0
    cv2.rectangle(frame, (x0 - 2, y0 - 2), (x1 + 1, y1 + 1), DIM_COLOUR, 1)
    frame[y0:y1, x0:x1] = eye
    font_scale, thickness = 0.4 * scale, max(1, round(scale))
    (text_w, text_h), _ = cv2.getTextSize(label, FONT, font_scale, thickness)
    band = slice(y1 + 2, min(height, y1 + 2 + text_h + round(8 * scale)))
    region = frame[band, x0 - 2 : x1 + 2]
    region[:] = (region.astype(np.float32) * 0.4).astype(np.uint8)
    base = (max(0, x1 - text_w), y1 + 2 + text_h + round(3 * scale))
    cv2.putText(frame, label, base, FONT, font_scale, TEXT_COLOUR, thickness, cv2.LINE_AA)
    return frame


class EyeInset(ClosesOnExit):
    """Renders the left eye's view of frame states of ``layout``'s scene for the inset."""

    def __init__(
        self,
        layout: SceneLayout | None,
        width: int,
        height: int,
        shadows: bool = False,
        reflections: bool = True,
    ) -> None:
        self.size = inset_size(width, height)
        self._model = build_model(layout)
        self._data = mujoco.MjData(self._model)
        self._renderer = warmed_renderer(self._model, self.size, EYE_CAMERA, shadows, reflections)

    def render(self, state: FrameState) -> np.ndarray:
        """The left eye's view of ``state``, (h, w, 3) uint8."""
        apply_state(self._model, self._data, state)
        return self._renderer.render(self._data)

    def close(self) -> None:
        """Free the renderer (idempotent)."""
        self._renderer.close()
