"""Tests of robin_sim.render.video: H.264 MP4s that decode back, even after an interruption."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import av
import numpy as np
import pytest

from pil.errors import RobinPilError
from robin_sim.model.scene_file import offscreen_buffer
from robin_sim.render.frame_spec import check_size
from robin_sim.render.video import Mp4Writer, VideoError, probe_video

WIDTH, HEIGHT, FPS = 320, 240, 30


def pattern(index: int) -> np.ndarray:
    """A frame with a bright bar moving to the right on a coloured background."""
    frame = np.zeros((HEIGHT, WIDTH, 3), np.uint8)
    frame[..., 0] = 40
    frame[..., 2] = (index * 5) % 200
    left = (index * 7) % (WIDTH - 40)
    frame[:, left : left + 40] = 230
    return frame


def decode(path: Path) -> list[np.ndarray]:
    with av.open(str(path)) as container:
        return [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]


@pytest.mark.slow
def test_mp4_decodes_back_as_h264_yuv420p(tmp_path: Path) -> None:
    path = tmp_path / "clip.mp4"
    with Mp4Writer(path, WIDTH, HEIGHT, fps=FPS) as writer:
        for i in range(45):
            writer.write(pattern(i))
    assert writer.frames_written == 45
    info = probe_video(path)
    assert info["codec"] == "h264"
    assert info["pix_fmt"] == "yuv420p"
    assert (info["width"], info["height"], info["frames"]) == (WIDTH, HEIGHT, 45)
    assert info["fps"] == pytest.approx(FPS)
    frames = decode(path)
    assert min(float(f.std()) for f in frames) > 20  # not blank
    for i in (0, 22, 44):  # lossy but close: mean absolute error in grey levels
        assert np.abs(frames[i].astype(int) - pattern(i).astype(int)).mean() < 6


@pytest.mark.slow
def test_keyboard_interrupt_inside_the_context_leaves_a_playable_file(tmp_path: Path) -> None:
    path = tmp_path / "interrupted.mp4"
    with pytest.raises(KeyboardInterrupt), Mp4Writer(path, WIDTH, HEIGHT, fps=FPS) as writer:
        for i in range(40):
            writer.write(pattern(i))
        raise KeyboardInterrupt
    assert writer.closed
    info = probe_video(path)
    assert (info["codec"], info["frames"]) == ("h264", 40)
    assert info["mean_level"] > 20


@pytest.mark.slow
def test_killed_process_leaves_every_finished_second_playable(tmp_path: Path) -> None:
    path = tmp_path / "killed.mp4"
    code = (
        "import os, signal, numpy as np\n"
        "from robin_sim.render.video import Mp4Writer\n"
        f"writer = Mp4Writer({str(path)!r}, {WIDTH}, {HEIGHT}, fps={FPS})\n"
        "for i in range(100):\n"
        f"    writer.write(np.full(({HEIGHT}, {WIDTH}, 3), 60 + i, np.uint8))\n"
        "os.kill(os.getpid(), signal.SIGKILL)  # no close, no cleanup\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=120)
    assert result.returncode == -9
    info = probe_video(path)
    # one fragment per second (key frame interval = fps); at least the first ~2 s survive
    assert info["codec"] == "h264"
    assert 2 * FPS - 1 <= info["frames"] <= 100


def test_odd_size_is_refused_at_the_edge_with_a_suggestion() -> None:
    """A size is checked once, where a command takes it (the writer below takes it as it is)."""
    with pytest.raises(RobinPilError, match=r"641x480.*642x480"):
        check_size(641, 480)
    with pytest.raises(RobinPilError, match=r"1282x720 .* off-screen buffer 1280x720"):
        check_size(1282, 720)
    assert check_size(1280, 720) == (1280, 720)
    assert offscreen_buffer() == (1280, 720)  # models/scene.xml


def test_missing_folder_is_named(tmp_path: Path) -> None:
    with pytest.raises(VideoError, match="not found"):
        Mp4Writer(tmp_path / "nowhere" / "clip.mp4", WIDTH, HEIGHT)


@pytest.mark.slow
def test_wrong_frame_is_refused_and_loses_nothing_written(tmp_path: Path) -> None:
    path = tmp_path / "clip.mp4"
    with (
        pytest.raises(VideoError, match=r"\(240, 320, 3\) uint8"),
        Mp4Writer(path, WIDTH, HEIGHT) as writer,
    ):
        for i in range(10):
            writer.write(pattern(i))
        writer.write(np.zeros((HEIGHT, WIDTH), np.uint8))
    assert probe_video(path)["frames"] == 10
    with pytest.raises(VideoError, match="closed"):
        writer.write(pattern(0))


@pytest.mark.slow
def test_rendered_frames_make_a_video(tmp_path: Path) -> None:
    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()
    import mujoco

    from robin_sim.render.renderer import FrameClock, FrameRenderer

    model = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><light pos="0 0 3"/><geom type="plane" size="2 2 .1"/>'
        '<body pos="0 0 1"><freejoint/><geom type="sphere" size=".1" rgba="1 0 0 1"/></body>'
        '<camera name="front" pos="0 -2 1" xyaxes="1 0 0 0 .3 1"/></worldbody></mujoco>'
    )
    data = mujoco.MjData(model)
    clock = FrameClock(fps=FPS, tick_dt=0.01)
    path = tmp_path / "render.mp4"
    with FrameRenderer(model, WIDTH, HEIGHT) as renderer, Mp4Writer(path, WIDTH, HEIGHT) as video:
        while data.time < 0.5:
            frames = clock.frames_due(data.time)
            if frames:
                image = renderer.render(data)
                for _ in range(frames):
                    video.write(image)
            for _ in range(5):
                mujoco.mj_step(model, data)
    info = probe_video(path)
    assert info["frames"] == video.frames_written == 15  # ticks 0 .. 0.49 s: frames 0 .. 14/30 s
    assert os.path.getsize(path) > 1000
    first, last = decode(path)[0], decode(path)[-1]
    assert np.abs(first.astype(int) - last.astype(int)).mean() > 0.5  # the ball fell
