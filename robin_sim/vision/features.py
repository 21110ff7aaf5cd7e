"""Features of a hand region: silhouette and shading HOG, Hu moments, physical size.

The crop is the region's box made square (plus a margin) and resized to :data:`CROP` pixels,
so the features do not depend on the hand's distance; its physical size (m, from the depth
and the focal length) is kept as three features of its own.
"""

from __future__ import annotations

import cv2
import numpy as np

from robin_sim.vision.segment import HandRegion

CROP = 32  # pixels, square crop side
MARGIN = 0.12  # share of the box side added around it
CELL = 8  # pixels per HOG cell side
BINS = 9  # unsigned orientation bins over 180 degrees
_CELLS = CROP // CELL
HOG_COUNT = (_CELLS - 1) ** 2 * 4 * BINS  # 2x2-cell blocks, stride one cell
FEATURE_COUNT = 2 * HOG_COUNT + 7 + 3


def hog(image: np.ndarray) -> np.ndarray:
    """Histogram of oriented gradients of a CROP x CROP image (Dalal-Triggs layout).

    Gradients by Sobel; per 8x8 cell a 9-bin histogram of unsigned orientation weighted by
    magnitude (linear between the two nearest bins); 2x2-cell blocks L2-normalised, clipped
    at 0.2 and renormalised (L2-Hys). OpenCV 5 no longer ships a HOG descriptor.
    """
    img = image.astype(np.float32)
    gx = cv2.Sobel(img, cv2.CV_32F, 1, 0, ksize=1)
    gy = cv2.Sobel(img, cv2.CV_32F, 0, 1, ksize=1)
    magnitude = np.hypot(gx, gy)
    angle = (np.degrees(np.arctan2(gy, gx)) % 180.0) / (180.0 / BINS)
    low = np.floor(angle).astype(int) % BINS
    frac = angle - np.floor(angle)
    cell_of = (np.arange(CROP) // CELL)[:, None] * _CELLS + (np.arange(CROP) // CELL)[None, :]
    hist = np.zeros((_CELLS * _CELLS, BINS), np.float64)
    np.add.at(hist, (cell_of.ravel(), low.ravel()), (magnitude * (1 - frac)).ravel())
    np.add.at(hist, (cell_of.ravel(), ((low + 1) % BINS).ravel()), (magnitude * frac).ravel())
    grid = hist.reshape(_CELLS, _CELLS, BINS)
    blocks = []
    for i in range(_CELLS - 1):
        for j in range(_CELLS - 1):
            v = grid[i : i + 2, j : j + 2].ravel()
            v = v / (np.linalg.norm(v) + 1e-6)
            v = np.minimum(v, 0.2)
            blocks.append(v / (np.linalg.norm(v) + 1e-6))
    return np.concatenate(blocks)


def crop(image: np.ndarray, box: tuple[int, int, int, int]) -> np.ndarray:
    """The square crop of ``image`` around ``box``, resized to CROP x CROP (zero padded)."""
    x, y, w, h = box
    side = int(np.ceil(max(w, h) * (1 + 2 * MARGIN))) + 1
    cx, cy = x + w / 2, y + h / 2
    x0, y0 = round(cx - side / 2), round(cy - side / 2)
    pad = side
    padded = cv2.copyMakeBorder(image, pad, pad, pad, pad, cv2.BORDER_CONSTANT, value=0)
    window = padded[y0 + pad : y0 + pad + side, x0 + pad : x0 + pad + side]
    return cv2.resize(window, (CROP, CROP), interpolation=cv2.INTER_AREA)


def hand_features(rgb: np.ndarray, region: HandRegion, focal: float) -> np.ndarray:
    """Feature vector (FEATURE_COUNT,) of the hand ``region`` in ``rgb``."""
    mask8 = region.mask.astype(np.uint8) * 255
    gray = cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY)
    shading = np.where(region.mask, gray, 0).astype(np.uint8)
    mask_crop = crop(mask8, region.box)
    shade_crop = crop(shading, region.box)
    peak = max(int(shade_crop.max()), 1)
    shade_crop = (shade_crop.astype(np.float32) * (255.0 / peak)).astype(np.uint8)  # light-free
    silhouette = hog(mask_crop)
    texture = hog(shade_crop)
    hu = cv2.HuMoments(cv2.moments(mask_crop, binaryImage=True)).ravel()
    hu = -np.sign(hu) * np.log10(np.abs(hu) + 1e-30)
    hu = np.clip(hu, -30, 30) / 10
    metres = region.depth / focal
    _, _, w, h = region.box
    size = np.array([w * metres, h * metres, np.sqrt(region.pixels) * metres]) * 10
    return np.concatenate([silhouette, texture, hu, size]).astype(np.float32)
