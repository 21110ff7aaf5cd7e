"""Find the person's hand in one eye view: near the looked-at depth, skin-coloured, connected.

The head is aimed at the hand (the robot tracks where the hand is), so the hand lies near the
image centre and near the looked-at depth. A pixel is a hand candidate when its depth lies in a
slab around that depth and its colour ratios fall in the range of human skin (green/red and
blue/red, which do not change with the light's intensity). The table has a skin-like colour
too, so a pixel whose point lies on the table top (less than ``TABLE_TOP_MARGIN`` above it, by
the depth and the eye's pose) is none, and the hand is what lies close to the candidates'
median depth in a central window (the hand floats in front of the table; the robot's own arm
can hide it from in front): the connected part with most pixels in that window and the parts
within a hand's reach of it.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from robin_sim.model.robot_spec import TABLE_TOP_Z

GREEN_RED = (0.55, 0.995)  # range of G/R for skin (light to dark tones, any light)
BLUE_RED = (0.30, 0.98)  # range of B/R
SLAB = (-0.15, 0.12)  # m around the looked-at depth where the hand may lie
MIN_RED = 20  # 8-bit: darker pixels carry no colour
HAND_DEPTH = 0.08  # m: hand pixels lie this close to the hand's median depth
HAND_REACH = 0.12  # m: parts of the hand lie this close to its main part's centre
MIN_PIXELS = 25  # a smaller region is no hand
SEED_RADIUS = 0.25  # share of the image side: radius of the central window
MAX_DEPTH = 2.5  # m
# m above the table top below which a point is the table's (the depth's noise is 3 mm; issue 41)
TABLE_TOP_MARGIN = 0.02


@dataclass(frozen=True, slots=True)
class HandRegion:
    """The hand found in one view: its mask, box (x, y, w, h) and median depth (m)."""

    mask: np.ndarray  # (H, W) bool
    box: tuple[int, int, int, int]
    depth: float

    @property
    def pixels(self) -> int:
        """Number of hand pixels."""
        return int(self.mask.sum())


def skin_mask(rgb: np.ndarray) -> np.ndarray:
    """Skin-like pixels of ``rgb`` (H, W, 3 uint8), after a 3x3 smoothing against noise."""
    smooth = cv2.blur(rgb, (3, 3)).astype(np.float32)
    r, g, b = smooth[..., 0], smooth[..., 1], smooth[..., 2]
    safe = np.maximum(r, 1.0)
    gr, br = g / safe, b / safe
    mask = (r >= MIN_RED) & (gr >= GREEN_RED[0]) & (gr <= GREEN_RED[1])
    mask &= (br >= BLUE_RED[0]) & (br <= BLUE_RED[1])
    return mask


def find_hand(
    rgb: np.ndarray,
    depth: np.ndarray,
    looked_at: float,
    focal: float,
    heights: np.ndarray,
) -> HandRegion | None:
    """The hand region of one view, or None when no candidate lies near the centre.

    ``looked_at``: depth (m along the optical axis) of the point the head is aimed at;
    ``focal``: the focal length in pixels (to turn the hand's reach into pixels); ``heights``:
    each pixel's world z (m; :class:`~robin_sim.vision.eyes.EyeView`): points on the table top
    are no candidates.
    """
    near = (depth > looked_at + SLAB[0]) & (depth < min(looked_at + SLAB[1], MAX_DEPTH))
    near &= heights >= TABLE_TOP_Z + TABLE_TOP_MARGIN
    candidates: np.ndarray = (skin_mask(rgb) & near).astype(np.uint8)
    candidates = cv2.morphologyEx(candidates, cv2.MORPH_CLOSE, np.ones((3, 3), np.uint8))
    height, width = candidates.shape
    yy, xx = np.mgrid[0:height, 0:width]
    cy, cx = (height - 1) / 2, (width - 1) / 2
    window = np.hypot(yy - cy, xx - cx) <= SEED_RADIUS * max(height, width)
    central = (candidates > 0) & window
    if central.sum() < MIN_PIXELS:
        return None
    hand_depth = float(np.median(depth[central]))
    keep = ((candidates > 0) & (np.abs(depth - hand_depth) < HAND_DEPTH)).astype(np.uint8)
    count, labels, _, centroids = cv2.connectedComponentsWithStats(keep, connectivity=8)
    if count < 2:
        return None
    inside = np.bincount(labels[window], minlength=count)
    inside[0] = 0
    main = int(np.argmax(inside))
    if inside[main] < MIN_PIXELS // 2:
        return None
    reach = HAND_REACH * focal / hand_depth
    near_main = np.hypot(*(centroids[1:] - centroids[main]).T) <= reach
    chosen = np.flatnonzero(near_main) + 1
    mask = np.isin(labels, chosen)
    if mask.sum() < MIN_PIXELS:
        return None
    x, y, w, h = cv2.boundingRect(mask.astype(np.uint8))
    return HandRegion(mask, (x, y, w, h), float(np.median(depth[mask])))
