"""The table spots ("location" targets) drawn and numbered on video frames.

A spot is a point on the table top; :func:`spot_pixels` projects the layout's spots through a
camera of a simulation as it is now (its pose from ``data``, its field of view from the model),
and :func:`draw_spots` draws a ring and the spot's number at each: from 0 on an episode's
video (the index a "location" target and the log use), from :data:`PAGE_FIRST_SPOT` on the
live page and its replay (as the page names them to the participant). Projection is the
pinhole model MuJoCo renders with.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import cv2
import mujoco
import numpy as np

from robin_sim.model import robot_spec as spec

SPOT_RING = (255, 255, 255)  # RGB: white, unlike any leg (red, green, blue, yellow)
SPOT_SHADOW = (30, 30, 30)
PAGE_FIRST_SPOT = 1  # the live page numbers the spots from 1, as it names them


def project(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera: int,
    points: np.ndarray,
    size: tuple[int, int],
) -> np.ndarray:
    """Image points (x, y) of world ``points`` (n, 3) seen by ``camera`` at ``size`` (w, h);
    NaN for a point behind the camera."""
    width, height = size
    position = data.cam_xpos[camera]
    axes = data.cam_xmat[camera].reshape(3, 3)  # columns: the camera's x, y, z in the world
    half = math.tan(math.radians(float(model.cam_fovy[camera])) / 2)
    local = (np.asarray(points, float) - position) @ axes
    depth = -local[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(depth > 0, local[:, 0] / depth, np.nan) / (half * width / height)
        v = np.where(depth > 0, local[:, 1] / depth, np.nan) / half
    return np.stack([(u + 1) * width / 2, (1 - v) * height / 2], axis=1)


def spot_pixels(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera: int,
    spots: Sequence[tuple[float, float]],
    size: tuple[int, int],
) -> tuple[tuple[float, float], ...]:
    """Image points of the table spots ``spots`` (x, y on the table top)."""
    if not spots:
        return ()
    points = np.array([[x, y, spec.TABLE_TOP_Z] for x, y in spots], dtype=float)
    return tuple((float(x), float(y)) for x, y in project(model, data, camera, points, size))


def draw_spots(frame: np.ndarray, pixels: Iterable[tuple[float, float]], *, first: int = 0) -> None:
    """A ring and its number (from ``first``) at each spot (skipping points off the frame),
    in place."""
    height, width = frame.shape[:2]
    scale = height / 480
    axes = (max(3, round(11 * scale)), max(2, round(5 * scale)))  # the table seen at a slant
    ring, font = max(2, round(2 * scale)), 0.5 * scale
    for k, (x, y) in enumerate(pixels):
        if not (math.isfinite(x) and math.isfinite(y)) or not (0 <= x < width and 0 <= y < height):
            continue
        centre = (round(x), round(y))
        cv2.ellipse(frame, centre, axes, 0, 0, 360, SPOT_SHADOW, ring + 2, cv2.LINE_AA)
        cv2.ellipse(frame, centre, axes, 0, 0, 360, SPOT_RING, ring, cv2.LINE_AA)
        text = str(k + first)
        (text_w, text_h), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, font, ring - 1)
        label = (centre[0] - axes[0] - round(4 * scale) - text_w, centre[1] + text_h // 2)
        for colour, weight in ((SPOT_SHADOW, ring + 1), (SPOT_RING, max(1, ring - 1))):
            cv2.putText(
                frame, text, label, cv2.FONT_HERSHEY_SIMPLEX, font, colour, weight, cv2.LINE_AA
            )
