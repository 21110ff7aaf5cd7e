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
    progress_lines,
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
    text = "\n".join(progress_lines(INFO) + overlay_lines(INFO))
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


def test_text_panels_change_their_boxes_on_the_bottom_edge_only() -> None:
    from robin_sim.render.overlay import panel_boxes, progress_lines

    frame = draw_overlay(background(), INFO)
    changed = np.any(frame != background(), axis=2)
    boxes = panel_boxes(frame.shape, INFO)
    assert len(boxes) == 2  # no policy: the progress panel and the panel of what happens now
    (px0, py0, px1, py1), (nx0, ny0, nx1, ny1) = boxes
    assert (px0, py1, ny1) == (0, 480, 480) and px1 <= nx0  # bottom left; then side by side
    assert min(py0, ny0) >= 380 and nx1 < 640 - 150  # the bottom band; left of P(a|s)
    assert 180 < nx1 - nx0 < 260 and 80 < px1 - px0 < 130
    for x0, y0, x1, y1 in boxes:
        assert changed[y0:y1, x0:x1].mean() > 0.9  # darkened panel with text
        panel = frame[y0:y1, x0:x1].astype(int).sum(axis=2)
        assert np.sum(panel > 600) > 150  # white text pixels on the dark panel
    outside = changed.copy()
    for x0, y0, x1, y1 in boxes:
        outside[y0:y1, x0:x1] = False
    assert not outside.any()  # nothing drawn elsewhere without a policy or spots
    assert "handover" not in " ".join(progress_lines(INFO))  # no handover given: no line


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
    assert np.any(small[190:, :60] > 0) and np.any(small[190:, 130:230] > 0)
    assert not np.any(small[:185]) and not np.any(small[:, 250:])


def test_bad_inputs_are_refused() -> None:
    with pytest.raises(RobinPilError, match=r"unknown actions.*'jump'"):
        draw_overlay(background(), OverlayInfo(step=0, sim_time=0.0, policy={"jump": 1.0}))
    with pytest.raises(RobinPilError, match="uint8"):
        draw_overlay(np.zeros((48, 64, 3), np.float32), INFO)
    with pytest.raises(RobinPilError, match="writable"):
        draw_overlay(background()[:, ::2], INFO)


def _fields(info: OverlayInfo) -> dict[str, object]:
    return {name: getattr(info, name) for name in info.__slots__}
