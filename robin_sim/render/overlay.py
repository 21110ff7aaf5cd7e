"""Text and a policy bar chart drawn on video frames with OpenCV.

:func:`draw_overlay` writes, in a dark panel near the top left: the step and simulation time,
the handover and its type, the gesture the person made, the gesture the robot detected (and the
corrected one when the correction replaced it), the chosen action, the action the person means,
the person's feedback and the legs delivered. The panel starts :data:`TEXT_PANEL_LEFT` of the
width in, so that the person's head (at the left edge of the front camera's view) stays in
sight. When :attr:`OverlayInfo.policy` is given, a panel at the bottom right shows the learned
P(a|s) of the five actions for the current state as horizontal bars; with
:attr:`OverlayInfo.spots`, the table spots are ringed and numbered
(:mod:`robin_sim.render.spots`). Sized for 640x480 and scaled with the frame height.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import cv2
import numpy as np

from pil.errors import RobinPilError
from pil.types import ACTIONS
from robin_sim.render.spots import draw_spots

FONT = cv2.FONT_HERSHEY_SIMPLEX
TEXT_COLOUR = (255, 255, 255)  # RGB frames
DIM_COLOUR = (170, 170, 170)
BAR_COLOUR = (80, 170, 255)
CHOSEN_BAR_COLOUR = (255, 190, 60)
PANEL_ALPHA = 0.6  # darkening of the frame under a panel
TEXT_PANEL_LEFT = 0.18  # of the frame's width: where the text panel starts (the head is left)


@dataclass(frozen=True, slots=True)
class OverlayInfo:
    """What the overlay shows; ``None`` fields print as a dash."""

    step: int
    sim_time: float
    true_gesture: str | None = None
    detected_gesture: str | None = None  # None: not detected (discarded)
    corrected_gesture: str | None = None  # only when the correction changed the gesture
    action: str | None = None
    feedback: str | None = None
    legs_delivered: int = 0
    legs_total: int = 0
    state: str | None = None  # e.g. "<give me, object, free>"
    policy: Mapping[str, float] | None = None  # P(a|s) for each action name
    intended: str | None = None  # the action the person means now
    handover: int | None = None  # the handover (leg) under way, from 0
    handover_type: str | None = None  # its type, e.g. "A"
    spots: tuple[tuple[float, float], ...] = ()  # image points of the table spots


def overlay_lines(info: OverlayInfo) -> list[str]:
    """The text lines of the panel, top to bottom."""

    def text(value: object) -> str:
        return "-" if value is None else str(value)

    detected = text(info.detected_gesture)
    if info.detected_gesture is None and info.true_gesture is not None:
        detected = "(not detected)"
    if info.corrected_gesture is not None and info.corrected_gesture != info.detected_gesture:
        detected += f" -> {info.corrected_gesture} (corrected)"
    lines = [
        f"step {info.step}   t = {info.sim_time:6.2f} s",
        f"person:   {text(info.true_gesture)}",
        f"detected: {detected}",
        f"action:   {text(info.action)}",
        f"meant:    {text(info.intended)}",
        f"feedback: {text(info.feedback)}",
        f"legs delivered: {info.legs_delivered}/{info.legs_total}",
    ]
    if info.handover is not None:
        kind = "" if info.handover_type is None else f", type {info.handover_type}"
        lines.insert(1, f"handover {info.handover + 1}{kind}")
    if info.state is not None:
        lines.insert(1, f"state: {info.state}")
    return lines


def _darken(frame: np.ndarray, x0: int, y0: int, x1: int, y1: int) -> None:
    """Darken the rectangle [x0, x1) x [y0, y1) of ``frame`` in place."""
    region = frame[y0:y1, x0:x1]
    region[:] = (region.astype(np.float32) * (1.0 - PANEL_ALPHA)).astype(np.uint8)


def text_panel_box(shape: tuple[int, ...], lines: list[str]) -> tuple[int, int, int, int]:
    """(x0, y0, x1, y1) of the text panel of ``lines`` on a frame of ``shape``."""
    scale = shape[0] / 480.0
    font_scale, thickness = 0.42 * scale, max(1, round(scale))
    line_h, pad = round(16 * scale), round(5 * scale)
    width = max(cv2.getTextSize(line, FONT, font_scale, thickness)[0][0] for line in lines)
    x0 = round(TEXT_PANEL_LEFT * shape[1])
    return x0, 0, min(shape[1], x0 + 2 * pad + width), min(shape[0], 2 * pad + line_h * len(lines))


def _draw_text_panel(frame: np.ndarray, lines: list[str], scale: float) -> None:
    font_scale, thickness = 0.42 * scale, max(1, round(scale))
    line_h, pad = round(16 * scale), round(5 * scale)
    x0, y0, x1, y1 = text_panel_box(frame.shape, lines)
    _darken(frame, x0, y0, x1, y1)
    for i, line in enumerate(lines):
        y = pad + line_h * (i + 1) - round(4 * scale)
        cv2.putText(
            frame, line, (x0 + pad, y), FONT, font_scale, TEXT_COLOUR, thickness, cv2.LINE_AA
        )


def _draw_policy_panel(
    frame: np.ndarray, policy: Mapping[str, float], chosen: str | None, scale: float
) -> None:
    names = [action.value for action in ACTIONS]
    unknown = sorted(set(policy) - set(names))
    if unknown:
        raise RobinPilError(f"policy has unknown actions {unknown}; valid choices: {names}")
    font_scale = 0.45 * scale
    thickness = max(1, round(scale))
    row_h = round(18 * scale)
    pad = round(6 * scale)
    label_w = max(cv2.getTextSize(n, FONT, font_scale, thickness)[0][0] for n in names)
    bar_w = round(110 * scale)
    value_w = cv2.getTextSize("1.00", FONT, font_scale, thickness)[0][0]
    panel_w = pad + label_w + pad + bar_w + pad + value_w + pad
    panel_h = pad + row_h * (len(names) + 1) + pad
    h, w = frame.shape[:2]
    x0, y0 = max(0, w - panel_w), max(0, h - panel_h)
    _darken(frame, x0, y0, w, h)
    title_y = y0 + pad + row_h - round(5 * scale)
    cv2.putText(
        frame, "P(a|s)", (x0 + pad, title_y), FONT, font_scale, DIM_COLOUR, thickness, cv2.LINE_AA
    )
    for i, name in enumerate(names):
        p = float(np.clip(policy.get(name, 0.0), 0.0, 1.0))
        top = y0 + pad + row_h * (i + 1)
        base = top + row_h - round(5 * scale)
        cv2.putText(
            frame, name, (x0 + pad, base), FONT, font_scale, TEXT_COLOUR, thickness, cv2.LINE_AA
        )
        bx = x0 + pad + label_w + pad
        colour = CHOSEN_BAR_COLOUR if name == chosen else BAR_COLOUR
        cv2.rectangle(frame, (bx, top + 3), (bx + bar_w, top + row_h - 3), DIM_COLOUR, 1)
        if p > 0:
            fill = bx + max(1, round(bar_w * p))
            cv2.rectangle(frame, (bx, top + 3), (fill, top + row_h - 3), colour, -1)
        cv2.putText(
            frame,
            f"{p:.2f}",
            (bx + bar_w + pad, base),
            FONT,
            font_scale,
            TEXT_COLOUR,
            thickness,
            cv2.LINE_AA,
        )


def draw_overlay(frame: np.ndarray, info: OverlayInfo) -> np.ndarray:
    """Draw ``info`` on ``frame`` (H, W, 3) uint8 in place and return it."""
    if frame.ndim != 3 or frame.shape[2] != 3 or frame.dtype != np.uint8:
        raise RobinPilError(
            f"overlay needs an (H, W, 3) uint8 frame, got {frame.shape} {frame.dtype}"
        )
    if not frame.flags.writeable or not frame.flags.c_contiguous:
        raise RobinPilError("overlay needs a writable, contiguous frame (use frame.copy())")
    scale = frame.shape[0] / 480.0
    draw_spots(frame, info.spots)
    _draw_text_panel(frame, overlay_lines(info), scale)
    if info.policy is not None:
        _draw_policy_panel(frame, info.policy, info.action, scale)
    return frame
