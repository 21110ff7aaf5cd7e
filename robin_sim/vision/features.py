"""Features of a hand region: silhouette and relief HOG at two scales, Hu moments, size.

Computed from the region's crops (:mod:`robin_sim.vision.crops`: square, so the features do
not depend on the hand's distance): a HOG of the silhouette and one of the relief (the hand's
depth about its median) at :data:`CROP` pixels and again at :data:`COARSE_CROP` pixels (the
same 8-pixel cells, so each cell spans half again as much of the hand: the hand's coarse
shape), the silhouette's Hu moments at :data:`HU_CROP` pixels, and the hand's physical size
(m, from the depth and the focal length). Neither the silhouette nor the relief depends on the
light's colour or direction; the shading HOG of format 2 did, and leaving it out read held-out
samples about 2 points better (issue 41: 82.3 % against 80.4 % on held-out samples of seed 0
beyond the paired table's, same training set). The coarse HOGs (format 4) read validation
samples 1.3 points better than format 3 (86.6 % against 85.3 %, issue 41, docs/vision.md).
"""

from __future__ import annotations

import cv2
import numpy as np

from robin_sim.vision.crops import HandCrops, hand_crops
from robin_sim.vision.segment import HandRegion

CROP = 48  # pixels, square side of the images the fine HOGs are computed on
COARSE_CROP = 32  # pixels, square side of the images the coarse HOGs are computed on
HU_CROP = 32  # pixels, square side of the silhouette the Hu moments are computed on
CELL = 8  # pixels per HOG cell side
BINS = 9  # unsigned orientation bins over 180 degrees


def hog_count(side: int) -> int:
    """Length of the HOG of a ``side`` x ``side`` image (2x2-cell blocks, stride one cell)."""
    return (side // CELL - 1) ** 2 * 4 * BINS


HOG_COUNT = hog_count(CROP)
FEATURE_COUNT = 2 * HOG_COUNT + 2 * hog_count(COARSE_CROP) + 7 + 3


def hog(image: np.ndarray) -> np.ndarray:
    """Histogram of oriented gradients of a square image whose side is a multiple of CELL
    (Dalal-Triggs layout).

    Gradients by Sobel; per 8x8 cell a 9-bin histogram of unsigned orientation weighted by
    magnitude (linear between the two nearest bins); 2x2-cell blocks L2-normalised, clipped
    at 0.2 and renormalised (L2-Hys). OpenCV 5 no longer ships a HOG descriptor.
    """
    img = image.astype(np.float32)
    side = img.shape[0]
    cells = side // CELL
    gx = cv2.Sobel(img, cv2.CV_32F, 1, 0, ksize=1)
    gy = cv2.Sobel(img, cv2.CV_32F, 0, 1, ksize=1)
    magnitude = np.hypot(gx, gy)
    angle = (np.degrees(np.arctan2(gy, gx)) % 180.0) / (180.0 / BINS)
    low = np.floor(angle).astype(int) % BINS
    frac = angle - np.floor(angle)
    cell_of = (np.arange(side) // CELL)[:, None] * cells + (np.arange(side) // CELL)[None, :]
    hist = np.zeros((cells * cells, BINS), np.float64)
    np.add.at(hist, (cell_of.ravel(), low.ravel()), (magnitude * (1 - frac)).ravel())
    np.add.at(hist, (cell_of.ravel(), ((low + 1) % BINS).ravel()), (magnitude * frac).ravel())
    grid = hist.reshape(cells, cells, BINS)
    # each 2x2-cell block, row by row: its cells (i, j), (i, j+1), (i+1, j), (i+1, j+1)
    blocks = np.concatenate([grid[:-1, :-1], grid[:-1, 1:], grid[1:, :-1], grid[1:, 1:]], axis=-1)
    blocks = blocks / (np.linalg.norm(blocks, axis=-1, keepdims=True) + 1e-6)
    blocks = np.minimum(blocks, 0.2)
    blocks = blocks / (np.linalg.norm(blocks, axis=-1, keepdims=True) + 1e-6)
    return blocks.ravel()


def _resized(image: np.ndarray, side: int) -> np.ndarray:
    return cv2.resize(image, (side, side), interpolation=cv2.INTER_AREA)


def crop_features(crops: HandCrops) -> np.ndarray:
    """Feature vector (FEATURE_COUNT,) of a hand's crops."""
    silhouette = hog(_resized(crops.mask, CROP))
    relief = hog(_resized(crops.relief, CROP))
    coarse = [hog(_resized(image, COARSE_CROP)) for image in (crops.mask, crops.relief)]
    hu = cv2.HuMoments(cv2.moments(_resized(crops.mask, HU_CROP), binaryImage=True)).ravel()
    hu = -np.sign(hu) * np.log10(np.abs(hu) + 1e-30)
    hu = np.clip(hu, -30, 30) / 10
    size = crops.size.astype(np.float64) * 10
    return np.concatenate([silhouette, relief, *coarse, hu, size]).astype(np.float32)


def hand_features(
    rgb: np.ndarray, depth: np.ndarray, region: HandRegion, focal: float
) -> np.ndarray:
    """Feature vector (FEATURE_COUNT,) of the hand ``region`` in one eye's ``rgb``/``depth``."""
    return crop_features(hand_crops(rgb, depth, region, focal))
