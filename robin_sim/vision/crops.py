"""The hand's crops: what the features are computed from, and what a rendered data set keeps.

A found hand region becomes three square crops of :data:`CROP_SIDE` pixels (its box made square
plus a margin, zero padded, resized by area): the silhouette (0/255), the shading (grey level
inside the silhouette, as seen) and the relief (depth inside the silhouette relative to the
hand's median depth, :data:`RELIEF_RANGE` m mapped onto 1-255; 0 outside), plus the hand's
physical size (box width and height and the square root of its area, m). The features
(:mod:`robin_sim.vision.features`) are computed from these alone, both when Robin reads and
from a data set's stored crops, so a change of features needs no new rendering.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from robin_sim.vision.segment import HandRegion

CROP_SIDE = 64  # pixels, square crop side (the features resize it further)
MARGIN = 0.12  # share of the box side added around it
RELIEF_RANGE = 0.08  # m either side of the hand's median depth kept in the relief crop


@dataclass(frozen=True, slots=True)
class HandCrops:
    """Square crops (CROP_SIDE x CROP_SIDE uint8) of one hand region and its size (3,) in m."""

    mask: np.ndarray
    shading: np.ndarray
    relief: np.ndarray
    size: np.ndarray


def square(image: np.ndarray, box: tuple[int, int, int, int], side: int = CROP_SIDE) -> np.ndarray:
    """The square crop of ``image`` around ``box`` plus the margin, resized to ``side``
    (zero padded where it leaves the image)."""
    x, y, w, h = box
    window_side = int(np.ceil(max(w, h) * (1 + 2 * MARGIN))) + 1
    cx, cy = x + w / 2, y + h / 2
    x0, y0 = round(cx - window_side / 2), round(cy - window_side / 2)
    pad = window_side
    padded = cv2.copyMakeBorder(image, pad, pad, pad, pad, cv2.BORDER_CONSTANT, value=0)
    window = padded[y0 + pad : y0 + pad + window_side, x0 + pad : x0 + pad + window_side]
    return cv2.resize(window, (side, side), interpolation=cv2.INTER_AREA)


def hand_crops(rgb: np.ndarray, depth: np.ndarray, region: HandRegion, focal: float) -> HandCrops:
    """The crops of ``region`` in one eye's ``rgb`` and ``depth`` (``focal`` in pixels)."""
    mask = region.mask
    gray = cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY)
    shading = np.where(mask, gray, 0).astype(np.uint8)
    offset = np.clip((depth - region.depth) / RELIEF_RANGE, -1.0, 1.0)
    relief = np.where(mask, np.rint(128 + 127 * offset), 0).astype(np.uint8)
    metres = region.depth / focal
    _, _, w, h = region.box
    size = np.array([w * metres, h * metres, np.sqrt(region.pixels) * metres], np.float32)
    return HandCrops(
        mask=square(mask.astype(np.uint8) * 255, region.box),
        shading=square(shading, region.box),
        relief=square(relief, region.box),
        size=size,
    )
