"""Tests of robin_sim.render.renderer: frames from each camera, clear errors, the frame clock."""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pil.errors import RobinPilError  # noqa: E402
from robin_sim.model.names import SCENE_CAMERAS  # noqa: E402
from robin_sim.render.renderer import (  # noqa: E402
    CloseUpRenderer,
    FrameClock,
    FrameRenderer,
    RenderError,
    UnknownCameraError,
    camera_names,
)

# A table with a red ball and a blue box, seen by the scene's three named cameras.
SCENE = """
<mujoco>
  <visual><global offwidth="640" offheight="480"/></visual>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1" castshadow="true"/>
    <geom name="floor" type="plane" size="3 3 .1" rgba=".6 .6 .6 1"/>
    <geom name="table_top" type="box" size="0.4 0.5 0.02" pos="0.4 0 0.73" rgba=".7 .5 .3 1"/>
    <body name="ball" pos="0.4 0.1 0.9">
      <freejoint/>
      <geom type="sphere" size="0.06" rgba="1 0 0 1"/>
    </body>
    <geom name="block" type="box" size="0.05 0.05 0.05" pos="0.3 -0.2 0.8" rgba="0 0 1 1"/>
    <camera name="front" pos="1.6 0 1.5" xyaxes="0 1 0 -0.5 0 0.87"/>
    <camera name="side" pos="0.4 -1.6 1.5" xyaxes="1 0 0 0 0.5 0.87"/>
    <camera name="head" pos="-0.3 0 1.6" xyaxes="0 -1 0 0.8 0 0.6"/>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(SCENE)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _red_pixels(frame: np.ndarray) -> int:
    r, g, b = (frame[..., i].astype(int) for i in range(3))
    return int(np.sum((r > 120) & (g < 60) & (b < 60)))


@pytest.mark.slow
def test_each_camera_renders_the_scene(scene: tuple[mujoco.MjModel, mujoco.MjData]) -> None:
    model, data = scene
    assert camera_names(model) == SCENE_CAMERAS
    for camera in SCENE_CAMERAS:
        with FrameRenderer(model, 320, 240, camera=camera, shadows=False) as renderer:
            frame = renderer.render(data)
        assert frame.shape == (240, 320, 3)
        assert frame.dtype == np.uint8
        assert frame.std() > 10, f"{camera}: nearly uniform frame"
        assert _red_pixels(frame) > 50, f"{camera}: the red ball is not in view"


@pytest.mark.slow
def test_renders_follow_physics_and_shadows_switch(
    scene: tuple[mujoco.MjModel, mujoco.MjData],
) -> None:
    model, _ = scene
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with FrameRenderer(model, 320, 240, camera="side") as renderer:
        before = renderer.render(data)
        for _ in range(150):  # the ball falls onto the table
            mujoco.mj_step(model, data)
        after = renderer.render(data)
    rows_before = np.nonzero(_red_pixels_mask(before))[0].mean()
    rows_after = np.nonzero(_red_pixels_mask(after))[0].mean()
    assert rows_after > rows_before + 5  # lower in the image (rows grow downwards)
    with FrameRenderer(model, 320, 240, camera="side", shadows=False) as renderer:
        unshadowed = renderer.render(data)
    # the shadows darken the table under the ball and box
    assert after.astype(int).sum() < unshadowed.astype(int).sum()


def _red_pixels_mask(frame: np.ndarray) -> np.ndarray:
    r, g, b = (frame[..., i].astype(int) for i in range(3))
    return (r > 120) & (g < 60) & (b < 60)


@pytest.mark.slow
def test_close_up_projects_and_lifts_in_metres(
    scene: tuple[mujoco.MjModel, mujoco.MjData],
) -> None:
    model, data = scene
    ball = model.body("ball").id
    centre = data.xpos[ball].copy()
    with CloseUpRenderer(model, 320, 240) as close_up:
        on_axis = close_up.observe(data, centre, 30.0, -40.0, 0.6)
        off_axis = close_up.observe(data, centre + np.array([0.0, 0.05, 0.05]), 30.0, -40.0, 0.6)
    for obs in (on_axis, off_axis):
        mask = obs.body == ball
        rows, cols = np.nonzero(mask)
        pixel, depth = obs.project(centre)
        # a sphere's image is centred on its projected centre (within 1 px off the axis) ...
        assert np.hypot(cols.mean() - pixel[0, 0], rows.mean() - pixel[0, 1]) < 1.0
        # ... and its lifted pixels lie on its surface: 0.06 m from the centre, within 2 mm
        radii = np.linalg.norm(obs.lift(mask) - centre, axis=1)
        assert radii.size > 1000
        assert np.abs(radii - 0.06).max() < 0.002
        assert depth[0] == pytest.approx(0.6, abs=0.06)
    assert np.hypot(*(on_axis.project(centre)[0][0] - [159.5, 119.5])) < 0.01  # image centre
    with pytest.raises(RenderError, match="closed"):
        close_up.observe(data, centre, 0.0, -30.0, 0.5)


def test_unknown_camera_lists_the_cameras(scene: tuple[mujoco.MjModel, mujoco.MjData]) -> None:
    model, _ = scene
    with pytest.raises(UnknownCameraError, match=r"'tabletop'.*'front', 'side', 'head'") as info:
        FrameRenderer(model, 320, 240, camera="tabletop")
    assert isinstance(info.value, RobinPilError)


def test_frame_larger_than_buffer_names_the_buffer(
    scene: tuple[mujoco.MjModel, mujoco.MjData],
) -> None:
    model, _ = scene
    with pytest.raises(RenderError, match=r"1280x720 .* buffer 640x480"):
        FrameRenderer(model, 1280, 720)


def test_closed_renderer_refuses(scene: tuple[mujoco.MjModel, mujoco.MjData]) -> None:
    model, data = scene
    renderer = FrameRenderer(model, 64, 48, camera="front")
    renderer.close()
    renderer.close()  # idempotent
    with pytest.raises(RenderError, match="closed"):
        renderer.render(data)


def test_frame_clock_emits_frames_at_video_rate() -> None:
    clock = FrameClock(fps=30, tick_dt=0.02)  # 50 Hz control ticks
    ticks = [clock.frames_due(k * 0.02) for k in range(51)]  # 0 .. 1.0 s
    assert sum(ticks) == 31  # frames at 0, 1/30, ..., 30/30 s
    assert set(ticks) == {0, 1}
    slow = FrameClock(fps=30, tick_dt=0.1)  # ticks slower than frames: frames repeat
    assert [slow.frames_due(k * 0.1) for k in range(4)] == [1, 3, 3, 3]
    assert slow.next_frame_time() == pytest.approx(10 / 30)


def test_frame_clock_rounding_never_drops_a_frame() -> None:
    clock = FrameClock(fps=25, tick_dt=0.002)
    time, frames = 0.0, 0
    for _ in range(5000):  # 10 s of accumulated float time steps
        frames += clock.frames_due(time)
        time += 0.002
    assert frames == 250  # frames at 0, 0.04, ..., 9.96 s (the last tick is at 9.998 s)


@pytest.mark.parametrize(("fps", "tick"), [(0, 0.02), (-30, 0.02), (30, 0.0), (float("nan"), 1)])
def test_frame_clock_rejects_bad_rates(fps: float, tick: float) -> None:
    with pytest.raises(RenderError):
        FrameClock(fps, tick)
