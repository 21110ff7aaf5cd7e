"""The overlay's panels never cover the person's head or hands in the front view.

One real one-handover episode (MuJoCo physics, EGL renders, its states file): on every recorded
frame the person's head and both hands are projected into the front camera
(:mod:`robin_sim.render.person_view`) and every panel the overlay darkens for that frame's text
(:func:`robin_sim.render.overlay.panel_boxes`) and the eye inset with its label must lie clear of
them, at the video's size and at 640x480. The projected boxes are checked to hold the parts'
rendered pixels (segmentation renders), so the check is of what a viewer sees.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from pil.task.scenario import SCENARIOS_DIR  # noqa: E402
from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402
from robin_sim.model import names  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.inset import inset_region  # noqa: E402
from robin_sim.render.overlay import OverlayInfo, panel_boxes  # noqa: E402
from robin_sim.render.person_view import overlaps, part_boxes, person_parts  # noqa: E402
from robin_sim.render.renderer import camera_id  # noqa: E402
from robin_sim.render.state_log import STATES_NAME, RecordedStates, load_states  # noqa: E402
from robin_sim.render.worker import apply_state  # noqa: E402

WIDTH, HEIGHT = 160, 120
SIZES = ((WIDTH, HEIGHT), (640, 480))
GESTURES = {"pointing", "give me", "grasp", "release"}


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> RecordedStates:
    out = tmp_path_factory.mktemp("clear")
    config = EpisodeConfig(
        scenario=SCENARIOS_DIR / "one_handover.yaml",
        out=out,
        width=WIDTH,
        height=HEIGHT,
        fps=10,
        verify=False,
        progress=False,
    )
    summary = run_episode(config)
    assert summary["status"] == "finished" and summary["legs_to_person"] == 1
    return load_states(out / STATES_NAME)


def _clashes(
    model: mujoco.MjModel, data: mujoco.MjData, info: OverlayInfo, size: tuple[int, int]
) -> list[str]:
    width, height = size
    parts = part_boxes(model, data, camera_id(model, names.DEFAULT_CAMERA), size)
    panels = [*panel_boxes((height, width, 3), info), inset_region(width, height)]
    return [
        f"{name} {part} under panel {panel}"
        for name, part in parts.items()
        for panel in panels
        if overlaps(part, panel)
    ]


@pytest.mark.slow
def test_no_panel_covers_the_head_or_a_hand_on_any_frame(recorded: RecordedStates) -> None:
    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    shown: set[str] = set()
    in_view = 0
    for state, overlay in zip(recorded.states, recorded.overlays, strict=True):
        assert overlay is not None
        info = OverlayInfo(**{**overlay["info"], "sim_time": state.time})
        shown.add(str(info.true_gesture))
        apply_state(model, data, state)
        for size in SIZES:
            clashes = _clashes(model, data, info, size)
            assert not clashes, f"t = {state.time:.2f} s at {size}: {clashes}"
        boxes = part_boxes(model, data, camera_id(model, names.DEFAULT_CAMERA), (WIDTH, HEIGHT))
        in_view += all(b[0] >= 0 and b[2] <= WIDTH and b[1] >= 0 for b in boxes.values())
    assert shown >= GESTURES  # every gesture's frames were checked
    assert in_view >= 0.9 * len(recorded.states)  # the head and hands are in the picture


@pytest.mark.slow
def test_the_projected_boxes_hold_the_rendered_head_and_hands(recorded: RecordedStates) -> None:
    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    parts = person_parts(model)
    camera = camera_id(model, names.DEFAULT_CAMERA)
    renderer = mujoco.Renderer(model, HEIGHT * 2, WIDTH * 2)
    renderer.enable_segmentation_rendering()
    try:
        picks = np.linspace(0, len(recorded.states) - 1, 8).astype(int)
        for k in picks:
            apply_state(model, data, recorded.states[k])
            renderer.update_scene(data, camera=camera)
            seg = renderer.render()
            boxes = part_boxes(model, data, camera, (WIDTH * 2, HEIGHT * 2), parts)
            for name, geoms in parts.items():
                mask = np.isin(seg[..., 0], geoms) & (seg[..., 1] == mujoco.mjtObj.mjOBJ_GEOM)
                rows, cols = np.nonzero(mask)
                assert len(rows) > 0 or name == "left hand", (k, name)  # seen
                x0, y0, x1, y1 = boxes[name]
                inside = (cols >= np.floor(x0)) & (cols < np.ceil(x1))
                inside &= (rows >= np.floor(y0)) & (rows < np.ceil(y1))
                assert inside.all(), (k, name, int((~inside).sum()))
    finally:
        renderer.close()
