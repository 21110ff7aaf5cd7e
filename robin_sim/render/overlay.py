"""Text and a policy bar chart drawn on video frames with OpenCV.

:func:`draw_overlay` writes two dark text panels along the bottom edge: in the bottom left
corner the run's progress (:func:`progress_lines`: the step and simulation time, the handover
and its type, the legs delivered), and left of the policy panel what happens now
(:func:`overlay_lines`: the state, the gesture the person made and their feedback, the gesture
the robot detected (and the corrected one when the correction replaced it), the chosen action
and the action the person means). When :attr:`OverlayInfo.policy` is given, a panel at the
bottom right shows the learned P(a|s) of the five actions for the current state as horizontal
bars; with :attr:`OverlayInfo.spots`, the table spots are ringed and numbered
(:mod:`robin_sim.render.spots`). Sized for 640x480 and scaled with the frame height.

Where: in the front camera's view the person's head and hands sweep the top left and the
middle of the frame (measured over the one-handover and the main job's episodes: head and
hands never below 372 of 480 rows, :mod:`robin_sim.render.person_view`); the bottom band
shows the floor, the table's and the robot's legs. :func:`panel_boxes` gives every panel's
pixels; ``tests/test_overlay_clear.py`` checks them against the person on every frame of an
episode.
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
TEXT_FONT_SCALE = 0.42  # at 480 rows; the text panels' line height and padding below
TEXT_LINE_H, TEXT_PAD = 16, 5
Box = tuple[int, int, int, int]  # x0, y0, x1, y1 (exclusive) in pixels


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


def _text(value: object) -> str:
    return "-" if value is None else str(value)


def progress_lines(info: OverlayInfo) -> list[str]:
    """The lines of the bottom left panel: step, time, handover and its type, legs."""
    lines = [f"step {info.step}", f"t = {info.sim_time:6.2f} s"]
    if info.handover is not None:
        kind = "" if info.handover_type is None else f", type {info.handover_type}"
        lines.append(f"handover {info.handover + 1}{kind}")
    lines.append(f"legs delivered: {info.legs_delivered}/{info.legs_total}")
    return lines


def overlay_lines(info: OverlayInfo) -> list[str]:
    """The lines of the panel of what happens now, top to bottom."""
    detected = _text(info.detected_gesture)
    if info.detected_gesture is None and info.true_gesture is not None:
        detected = "(not detected)"
    if info.corrected_gesture is not None and info.corrected_gesture != info.detected_gesture:
        detected += f" -> {info.corrected_gesture} (corrected)"
    lines = [
        f"person:   {_text(info.true_gesture)}   feedback: {_text(info.feedback)}",
        f"detected: {detected}",
        f"action:   {_text(info.action)}",
        f"meant:    {_text(info.intended)}",
    ]
    if info.state is not None:
        lines.insert(0, f"state: {info.state}")
    return lines


def _darken(frame: np.ndarray, x0: int, y0: int, x1: int, y1: int) -> None:
    """Darken the rectangle [x0, x1) x [y0, y1) of ``frame`` in place."""
    region = frame[y0:y1, x0:x1]
    region[:] = (region.astype(np.float32) * (1.0 - PANEL_ALPHA)).astype(np.uint8)


def _text_metrics(height: int) -> tuple[float, int, int, int]:
    """Font scale, thickness, line height and padding of the text panels at ``height`` rows."""
    scale = height / 480.0
    thickness = max(1, round(scale))
    return TEXT_FONT_SCALE * scale, thickness, round(TEXT_LINE_H * scale), round(TEXT_PAD * scale)


def _text_size(lines: list[str], height: int) -> tuple[int, int]:
    """Width and height of a text panel of ``lines`` on a frame of ``height`` rows."""
    font_scale, thickness, line_h, pad = _text_metrics(height)
    width = max(cv2.getTextSize(line, FONT, font_scale, thickness)[0][0] for line in lines)
    return 2 * pad + width, 2 * pad + line_h * len(lines)


def policy_panel_box(shape: tuple[int, ...]) -> Box:
    """(x0, y0, x1, y1) of the P(a|s) panel on a frame of ``shape`` (bottom right)."""
    h, w = shape[:2]
    scale = h / 480.0
    font_scale, thickness = 0.45 * scale, max(1, round(scale))
    row_h, pad = round(18 * scale), round(6 * scale)
    names = [action.value for action in ACTIONS]
    label_w = max(cv2.getTextSize(n, FONT, font_scale, thickness)[0][0] for n in names)
    value_w = cv2.getTextSize("1.00", FONT, font_scale, thickness)[0][0]
    panel_w = pad + label_w + pad + round(110 * scale) + pad + value_w + pad
    panel_h = pad + row_h * (len(names) + 1) + pad
    return max(0, w - panel_w), max(0, h - panel_h), w, h


def text_panel_boxes(shape: tuple[int, ...], info: OverlayInfo) -> tuple[Box, Box]:
    """(x0, y0, x1, y1) of the progress panel (bottom left corner) and of the panel of what
    happens now (on the bottom edge, ending where the P(a|s) panel starts, drawn or not)."""
    h, w = shape[:2]
    pw, ph = _text_size(progress_lines(info), h)
    progress = (0, max(0, h - ph), min(w, pw), h)
    nw, nh = _text_size(overlay_lines(info), h)
    right = policy_panel_box(shape)[0]
    return progress, (max(0, right - nw), max(0, h - nh), right, h)


def panel_boxes(shape: tuple[int, ...], info: OverlayInfo) -> list[Box]:
    """Every panel :func:`draw_overlay` darkens for ``info`` on a frame of ``shape``."""
    boxes = list(text_panel_boxes(shape, info))
    if info.policy is not None:
        boxes.append(policy_panel_box(shape))
    return boxes


def _draw_text_panel(frame: np.ndarray, lines: list[str], box: Box) -> None:
    font_scale, thickness, line_h, pad = _text_metrics(frame.shape[0])
    x0, y0, x1, y1 = box
    _darken(frame, x0, y0, x1, y1)
    for i, line in enumerate(lines):
        y = y0 + pad + line_h * (i + 1) - round(4 * frame.shape[0] / 480.0)
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
    x0, y0, x1, y1 = policy_panel_box(frame.shape)
    _darken(frame, x0, y0, x1, y1)
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
    progress, now = text_panel_boxes(frame.shape, info)
    _draw_text_panel(frame, progress_lines(info), progress)
    _draw_text_panel(frame, overlay_lines(info), now)
    if info.policy is not None:
        _draw_policy_panel(frame, info.policy, info.action, scale)
    return frame
