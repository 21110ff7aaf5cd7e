"""Tests of robin_sim.render.overlay: the text panel and the P(a|s) bar chart."""

from __future__ import annotations

import numpy as np
import pytest

from pil.errors import RobinPilError
from robin_sim.render.overlay import (
    BAR_COLOUR,
    CHOSEN_BAR_COLOUR,
    OverlayInfo,
    draw_overlay,
    overlay_lines,
)

INFO = OverlayInfo(
    step=12,
    sim_time=34.5,
    true_gesture="give me",
    detected_gesture="grasp",
    corrected_gesture="give me",
    action="human",
    feedback="not ok",
    legs_delivered=3,
    legs_total=40,
    state="<give me, object, occupied>",
)
POLICY = {"open": 0.1, "close": 0.05, "object": 0.15, "human": 0.6, "location": 0.1}


def background() -> np.ndarray:
    return np.full((480, 640, 3), (120, 160, 200), np.uint8)


def test_lines_name_every_field() -> None:
    text = "\n".join(overlay_lines(INFO))
    for part in (
        "step 12",
        "34.50 s",
        "give me",
        "grasp -> give me (corrected)",
        "human",
        "not ok",
        "3/40",
        "<give me, object, occupied>",
    ):
        assert part in text
    undetected = overlay_lines(OverlayInfo(step=1, sim_time=0.0, true_gesture="pointing"))
    assert any("(not detected)" in line for line in undetected)


def test_text_panel_changes_its_box_near_the_top_left_only() -> None:
    from robin_sim.render.overlay import TEXT_PANEL_LEFT, text_panel_box

    frame = draw_overlay(background(), INFO)
    changed = np.any(frame != background(), axis=2)
    x0, y0, x1, y1 = text_panel_box(frame.shape, overlay_lines(INFO))
    assert x0 == round(TEXT_PANEL_LEFT * frame.shape[1]) > 100 and y0 == 0  # the head is left
    assert 200 < x1 - x0 < 320 and 100 < y1 < 170
    assert changed[y0:y1, x0:x1].mean() > 0.9  # darkened panel with text
    outside = changed.copy()
    outside[y0:y1, x0:x1] = False
    assert not outside.any()  # nothing drawn elsewhere without a policy or spots
    panel = frame[y0:y1, x0:x1].astype(int).sum(axis=2)
    assert np.sum(panel > 600) > 500  # white text pixels on the dark panel


def test_policy_panel_draws_bars_proportional_to_probability() -> None:
    frame = draw_overlay(background(), OverlayInfo(**{**_fields(INFO), "policy": POLICY}))
    corner = frame[330:, 420:]
    assert np.any(corner != background()[330:, 420:])
    chosen = np.all(corner == CHOSEN_BAR_COLOUR, axis=2).sum()  # "human", the chosen action
    others = np.all(corner == BAR_COLOUR, axis=2).sum()  # four bars of 0.4 in total
    assert chosen > 0 and others > 0
    assert chosen / others == pytest.approx(0.6 / 0.4, rel=0.2)


def test_overlay_scales_with_the_frame() -> None:
    small = draw_overlay(np.zeros((240, 320, 3), np.uint8), INFO)
    assert np.any(small[:75, :125] > 0)
    assert not np.any(small[120:, 200:])


def test_bad_inputs_are_refused() -> None:
    with pytest.raises(RobinPilError, match=r"unknown actions.*'jump'"):
        draw_overlay(background(), OverlayInfo(step=0, sim_time=0.0, policy={"jump": 1.0}))
    with pytest.raises(RobinPilError, match="uint8"):
        draw_overlay(np.zeros((48, 64, 3), np.float32), INFO)
    with pytest.raises(RobinPilError, match="writable"):
        draw_overlay(background()[:, ::2], INFO)


def _fields(info: OverlayInfo) -> dict[str, object]:
    return {name: getattr(info, name) for name in info.__slots__}
