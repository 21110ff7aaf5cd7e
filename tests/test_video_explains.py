"""The episode video explains itself: the overlay leaves the person's head and hands in sight,
the table spots are ringed and numbered where they are, no garment of the person looks like a
leg, the overlay names the action meant and the handover type, and the last frame counts every
leg the episode delivered. Real MuJoCo renders (EGL) and decoded H.264."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import av
import cv2
import mujoco
import numpy as np
import pytest

from pil.types import ACTIONS
from robin_sim.model import names
from robin_sim.model.scene import LEG_COLORS, SceneLayout, build_model
from robin_sim.render.inset import inset_box
from robin_sim.render.overlay import OverlayInfo, draw_overlay, overlay_lines, progress_lines
from robin_sim.render.person_view import part_boxes
from robin_sim.render.renderer import FrameRenderer, camera_id
from robin_sim.render.spots import spot_pixels

WIDTH, HEIGHT = 640, 480
BUSY = OverlayInfo(
    step=123,
    sim_time=456.78,
    true_gesture="give me",
    detected_gesture="pointing",
    corrected_gesture="give me",
    action="location (anticipating release)",
    intended="human",
    feedback="not ok",
    legs_delivered=39,
    legs_total=40,
    state="<give me, location, occupied>",
    policy={a.value: 0.2 for a in ACTIONS},
    handover=39,
    handover_type="J",
)  # the longest lines the overlay shows


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, mujoco.MjData, np.ndarray]:
    model = build_model(None)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with FrameRenderer(model, WIDTH, HEIGHT, names.DEFAULT_CAMERA, shadows=False) as renderer:
        frame = renderer.render(data)
    return model, data, frame


def test_the_overlay_and_the_inset_leave_the_head_and_hands_in_sight(scene) -> None:
    model, data, frame = scene
    camera = camera_id(model, names.DEFAULT_CAMERA)
    parts = part_boxes(model, data, camera, (WIDTH, HEIGHT))
    drawn = draw_overlay(frame.copy(), BUSY)
    x0, y0, x1, y1 = inset_box(WIDTH, HEIGHT)
    drawn[y0 - 2 : y1 + 20, x0 - 2 : x1 + 2] = 0  # where the eye inset and its label go
    changed = np.any(drawn != frame, axis=2)
    for name, (px0, py0, px1, py1) in parts.items():
        assert 0 <= px0 < px1 <= WIDTH and 0 <= py0 < py1 <= HEIGHT, name  # in the front view
        box = changed[int(py0) : int(np.ceil(py1)), int(px0) : int(np.ceil(px1))]
        assert not box.any(), f"{np.sum(box)} pixels of the {name} covered"


def test_the_spots_are_ringed_and_numbered_where_the_table_has_them(scene) -> None:
    from robin_sim.live.picking import Picker  # an independent projection of the same spots

    model, data, frame = scene
    layout = SceneLayout()
    pixels = spot_pixels(
        model, data, camera_id(model, names.DEFAULT_CAMERA), layout.spots, (WIDTH, HEIGHT)
    )
    assert len(pixels) == len(layout.spots) == 4
    expected = Picker(layout, WIDTH, HEIGHT).spot_pixels()
    np.testing.assert_allclose(pixels, expected, atol=0.5)
    drawn = draw_overlay(frame.copy(), replace(BUSY, spots=pixels, policy=None))
    for x, y in pixels:  # a white ring around each spot, its number beside it
        ring = drawn[round(y) - 8 : round(y) + 9, round(x) - 14 : round(x) + 15]
        label = drawn[round(y) - 8 : round(y) + 9, round(x) - 30 : round(x) - 14]
        assert np.sum(np.all(ring >= 235, axis=2)) >= 40, (x, y)
        assert np.sum(np.all(label >= 235, axis=2)) >= 8, (x, y)
        assert not np.all(frame[round(y), round(x)] >= 235)  # ... on a table that is not white


def test_the_overlay_names_the_action_meant_and_the_handover_type() -> None:
    text = "\n".join(progress_lines(BUSY) + overlay_lines(BUSY))
    assert "meant:    human" in text and "handover 40, type J" in text


def _lab(rgb: tuple[float, ...]) -> np.ndarray:
    return cv2.cvtColor(np.array([[rgb[:3]]], np.float32), cv2.COLOR_RGB2Lab)[0, 0]


def test_no_garment_of_the_person_looks_like_a_leg() -> None:
    model = build_model(None)
    for garment in ("sleeve", "shirt", "trousers"):
        colour = _lab(tuple(model.mat(garment).rgba))
        assert np.hypot(colour[1], colour[2]) <= 12, garment  # greys: next to no chroma
        for leg in LEG_COLORS:
            other = _lab(leg)
            assert np.hypot(other[1], other[2]) >= 30  # every leg colour is a vivid one
            assert np.linalg.norm(colour - other) >= 30, (garment, leg)  # CIE76 ΔE


@pytest.mark.slow
def test_the_last_frame_counts_the_legs_the_episode_delivered(tmp_path: Path) -> None:
    from robin_sim.episode.recorder import VideoRecorder
    from robin_sim.episode.view import EpisodeView
    from robin_sim.robot.world import PhysicalWorld

    world = PhysicalWorld()
    view = EpisodeView()
    view.update(legs_total=4, legs_delivered=3)
    path = tmp_path / "last.mp4"
    recorder = VideoRecorder(
        world.sim, view, path, width=320, height=240, fps=10, render_workers=0, eye_inset=False
    )
    world.run(1.0)
    view.update(legs_delivered=4)  # the last step delivered the fourth leg; then it ends
    recorder.close()
    with av.open(str(path)) as container:
        frames = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    assert len(frames) == recorder.timing.frames_written
    shown = frames[-1].astype(float)
    marks = {}
    for legs in (3, 4):
        black = np.zeros((240, 320, 3), np.uint8)
        marks[legs] = np.any(
            draw_overlay(black, replace(view.info, legs_delivered=legs)) > 128, axis=2
        )
    only_four, only_three = marks[4] & ~marks[3], marks[3] & ~marks[4]
    assert shown[only_four].mean() > shown[only_three].mean() + 40  # "4/4" drawn, not "3/4"
