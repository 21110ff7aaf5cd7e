"""The robot's eye view inset in the episode video: real MuJoCo, EGL renders, decoded H.264."""

from __future__ import annotations

from pathlib import Path

import av
import mujoco
import numpy as np
import pytest

from pil.task.world import Target
from pil.types import Gesture
from robin_sim.control.simulator import Simulator
from robin_sim.episode.view import EpisodeView
from robin_sim.model import names
from robin_sim.model.scene import build_model
from robin_sim.render.gl_backend import ensure_gl_backend
from robin_sim.render.inset import EyeInset, draw_eye_inset, inset_box, inset_size
from robin_sim.render.pool import FrameState
from robin_sim.render.worker import SecondView, apply_state, second_renderer

WIDTH, HEIGHT = 640, 480
# mean |difference| in 0..255 levels, over the inset's pixels, that H.264 (crf 23, yuv420p) may
# add to a frame; a different picture there (no inset) differs by many times more
CODEC_TOLERANCE = 6.0


@pytest.fixture(scope="module", autouse=True)
def _gl() -> None:
    ensure_gl_backend()


def _decode(path: Path) -> list[np.ndarray]:
    with av.open(str(path)) as container:
        return [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]


def _direct_eye(state: FrameState, reflections: bool = False, coarse: bool = True) -> np.ndarray:
    """The eye camera's view of ``state`` rendered on its own at the inset's size (as the
    video's inset: no floor reflection, coarse round shapes)."""
    model = build_model(None)
    data = mujoco.MjData(model)
    apply_state(model, data, state)
    view = SecondView(names.EYE_CAMERA, inset_size(WIDTH, HEIGHT), reflections, coarse)
    with second_renderer(model, view, False) as r:  # warmed up: later renders are the same
        return r.render(data)


def test_the_video_eye_view_is_the_full_detail_view_within_levels() -> None:
    """The video's eye view draws round shapes with half the slices and stacks: the same
    picture (mean difference under 2 levels of 255, under 1 % of pixels off by more than 32,
    on their edges), and the model the frame is rendered from keeps its full detail."""
    from robin_sim.robot.world import PhysicalWorld

    world = PhysicalWorld()
    states = [FrameState.capture(world.model, world.data)]
    for leg in (2, 0):
        world.head.attend(world.legs.position(leg), "pointed")
        world.run(0.8)
        states.append(FrameState.capture(world.model, world.data))
    model = build_model(None)
    data = mujoco.MjData(model)
    quality = (model.vis.quality.numslices, model.vis.quality.numstacks)
    size = inset_size(WIDTH, HEIGHT)
    coarse = second_renderer(model, SecondView(names.EYE_CAMERA, size), False)
    full = second_renderer(model, SecondView(names.EYE_CAMERA, size, coarse=False), False)
    assert (model.vis.quality.numslices, model.vis.quality.numstacks) == quality
    with coarse, full:
        for state in states:
            apply_state(model, data, state)
            diff = np.abs(coarse.render(data).astype(int) - full.render(data))
            assert diff.mean() < 2.0 and (diff.max(axis=2) > 32).mean() < 0.01


def test_inset_box_is_a_quarter_in_the_top_right() -> None:
    assert inset_size(WIDTH, HEIGHT) == (160, 120)
    x0, y0, x1, y1 = inset_box(WIDTH, HEIGHT)
    assert (x1 - x0, y1 - y0) == (160, 120) and x1 < WIDTH and y0 > 0 and y1 < HEIGHT // 2


def test_drawn_inset_is_the_eye_render_exactly() -> None:
    from robin_sim.robot.world import PhysicalWorld

    world = PhysicalWorld()
    state = FrameState.capture(world.model, world.data)
    with EyeInset(None, WIDTH, HEIGHT) as eye:
        view = eye.render(state)
    direct = _direct_eye(state, reflections=True, coarse=False)
    assert np.abs(view.astype(int) - direct).max() <= 2  # levels: the same render
    frame = np.zeros((HEIGHT, WIDTH, 3), np.uint8)
    draw_eye_inset(frame, view)
    x0, y0, x1, y1 = inset_box(WIDTH, HEIGHT)
    assert np.array_equal(frame[y0:y1, x0:x1], view)
    assert frame[y1 + 2 :, x0:x1].any()  # the label under the inset
    with pytest.raises(ValueError, match=r"needs \(120, 160, 3\)"):
        draw_eye_inset(frame, view[:, :100])


@pytest.mark.slow
@pytest.mark.parametrize(("fps", "workers"), [(10, 0), (30, 1)])
def test_video_frames_carry_the_eye_view(tmp_path: Path, fps: int, workers: int) -> None:
    from robin_sim.episode.recorder import VideoRecorder
    from robin_sim.person.body import PhysicalBody
    from robin_sim.robot.world import PhysicalWorld

    world = PhysicalWorld()
    body = PhysicalBody(world)
    world.head.attend(world.legs.position(2), "pointed")
    world.run(0.8)  # the head turns to the table first
    kwargs = dict(width=WIDTH, height=HEIGHT, fps=fps, render_workers=workers)
    with_inset = VideoRecorder(world.sim, EpisodeView(), tmp_path / "eye.mp4", **kwargs)
    without = VideoRecorder(
        world.sim, EpisodeView(), tmp_path / "plain.mp4", eye_inset=False, **kwargs
    )
    states: list[FrameState] = []

    def keep(sim: Simulator) -> None:  # runs after both recorders: the frames' own states
        if with_inset.clock.frames_emitted > len(states):
            states.append(FrameState.capture(sim.model, sim.data))

    world.sim.add_observer(keep)
    body.perform(Gesture.POINTING, Target("leg", 3))  # the view changes while it records
    with_inset.close()
    without.close()
    eye_frames, plain_frames = _decode(tmp_path / "eye.mp4"), _decode(tmp_path / "plain.mp4")
    assert len(eye_frames) == len(plain_frames) == len(states) >= 10
    x0, y0, x1, y1 = inset_box(WIDTH, HEIGHT)
    every = with_inset.eye_every  # the inset refreshes at EYE_FPS: 1 in 3 frames at 30 fps
    assert every == max(1, round(fps / 10))
    for i in (0, 1, len(states) // 2, len(states) - 1):
        shown = eye_frames[i][y0:y1, x0:x1].astype(float)
        direct = _direct_eye(states[i - i % every])  # rendered with its frame, by the worker
        assert np.abs(shown - direct).mean() < CODEC_TOLERANCE, i
        plain = plain_frames[i][y0:y1, x0:x1].astype(float)
        assert np.abs(shown - plain).mean() > 4 * CODEC_TOLERANCE, i  # the inset is there
        outside = np.abs(
            eye_frames[i][HEIGHT // 2 :].astype(float) - plain_frames[i][HEIGHT // 2 :]
        )
        assert outside.mean() < 1.0, i  # the rest of the frame is the same picture
    first, last = _direct_eye(states[0]), _direct_eye(states[-1])
    assert np.abs(first.astype(float) - last).mean() > 2.0  # the eye view moved with the head
