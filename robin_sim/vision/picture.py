"""What a reading looks like: the eye's view with the hand's box and the reading written on it.

:func:`reading_picture` draws one :class:`~robin_sim.vision.detector.VisionRecord`'s left-eye
view (square, e.g. 112x112) into a picture of any size: the view scaled to the picture's height
and centred (black at the sides), the hand's box scaled with it, and the reading ("pointing
0.93" or "discarded 0.41", on the bottom line) in the box's colour: green for a kept reading,
red for a discarded one. The episode video's eye inset shows it for a moment after each reading
(:mod:`robin_sim.episode.recorder`).
"""

from __future__ import annotations

import cv2
import numpy as np

KEPT_COLOUR = (0, 200, 0)  # RGB: a reading the robot acts on
DISCARDED_COLOUR = (255, 0, 0)  # RGB: a reading below the threshold (or no hand found)
FONT = cv2.FONT_HERSHEY_PLAIN

Box = tuple[int, int, int, int]  # x, y, width, height in pixels


def box_colour(discarded: bool) -> tuple[int, int, int]:
    """The box's and the text's colour for a kept or a discarded reading."""
    return DISCARDED_COLOUR if discarded else KEPT_COLOUR


def placed_box(box: Box, view_size: int, size: tuple[int, int]) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of ``box`` (pixels of a ``view_size`` square view) in a picture of
    ``size`` (width, height) that shows the view scaled to its height and centred."""
    width, height = size
    scale = height / view_size
    left = (width - height) // 2
    x, y, w, h = box
    return (
        left + round(x * scale),
        round(y * scale),
        left + round((x + w) * scale),
        round((y + h) * scale),
    )


def reading_picture(
    view: np.ndarray,
    box: Box | None,
    text: str,
    discarded: bool,
    size: tuple[int, int] | None = None,
) -> np.ndarray:
    """``view`` (square RGB) at ``size`` (width, height; default its own) with ``box`` and
    ``text`` drawn (see the module doc); a new (height, width, 3) uint8 array."""
    side = view.shape[0]
    width, height = size if size is not None else (view.shape[1], side)
    if width < height:
        raise ValueError(f"a reading picture must be at least as wide as high, got {size}")
    picture = np.zeros((height, width, 3), np.uint8)
    left = (width - height) // 2
    scaled = (
        view
        if height == side
        else cv2.resize(view, (height, height), interpolation=cv2.INTER_LINEAR)
    )
    picture[:, left : left + height] = scaled
    colour = box_colour(discarded)
    thickness = max(1, round(height / 60))
    if box is not None:
        x0, y0, x1, y1 = placed_box(box, side, (width, height))
        cv2.rectangle(picture, (x0, y0), (x1, y1), colour, thickness)
    font_scale = 0.7 * height / 112
    baseline = height - max(2, round(3 * height / 112))  # the bottom line: hands are central
    cv2.putText(picture, text, (left + 2, baseline), FONT, font_scale, colour, 1, cv2.LINE_AA)
    return picture
