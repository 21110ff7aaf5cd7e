"""Tests of robin_sim.render.pool: ordered frames from worker processes equal direct renders."""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

import os  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from robin_sim.model import names, person_joints  # noqa: E402
from robin_sim.model.scene import SceneLayout, build_model  # noqa: E402
from robin_sim.person.gestures import GestureDisplay  # noqa: E402
from robin_sim.render.overlay import OverlayInfo, draw_overlay  # noqa: E402
from robin_sim.render.pool import (  # noqa: E402
    FrameState,
    RenderPool,
    RenderPoolError,
)
from robin_sim.render.renderer import FrameRenderer, UnknownCameraError  # noqa: E402

WIDTH, HEIGHT = 320, 240  # small frames keep the tests quick; the bench uses 640x480
POSES = ("neutral", "pointing", "give_me", "grasp", "thumb_up", "release")
# Two legs, not the default four: a pool must build its scene from the layout it is given.
LAYOUT = SceneLayout(legs=((0.45, -0.1, 0.3), (0.55, 0.15, 1.2)))


def rollout(layout: SceneLayout | None, frames: int) -> tuple[mujoco.MjModel, list[FrameState]]:
    """Step the scene at 30 fps video rate: the left arm swings, the person's hand moves and
    changes pose each frame; returns the model and one captured state per frame."""
    model = build_model(layout)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    display = GestureDisplay(model, data)
    arm = [model.actuator(a).id for a in names.arm_actuators(names.ACTIVE_SIDE)]
    steps_per_frame = round(1 / 30 / model.opt.timestep)
    states = []
    for k in range(frames):
        display.show(POSES[k % len(POSES)])
        data.ctrl[arm[:2]] = data.qpos[model.actuator_trnid[arm[:2], 0]] + 0.4
        data.mocap_pos[0] += [-0.01, 0.005, 0.0]
        for _ in range(steps_per_frame):
            mujoco.mj_step(model, data)
        states.append(FrameState.capture(model, data))
    return model, states


def direct_renders(model: mujoco.MjModel, states: list[FrameState]) -> list[np.ndarray]:
    """Each state rendered in this process with a plain FrameRenderer after mj_forward.

    The renderer renders one frame first: a new renderer's first frame differs from later ones
    by up to 2 levels (see render_pool.warmed_renderer).
    """
    data = mujoco.MjData(model)
    frames = []
    with FrameRenderer(model, WIDTH, HEIGHT, "front") as renderer:
        mujoco.mj_forward(model, data)
        renderer.render(data)
        for state in states:
            data.qpos[:], data.mocap_pos[:], data.mocap_quat[:] = (
                state.qpos[: model.nq],
                state.mocap_pos,
                state.mocap_quat,
            )
            data.userdata[:] = state.qpos[model.nq :]  # the person's joints follow
            model.geom_rgba[:] = state.geom_rgba
            person_joints.pose(model, data)
            mujoco.mj_forward(model, data)
            frames.append(renderer.render(data))
    return frames


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, list[FrameState], list[np.ndarray]]:
    model, states = rollout(LAYOUT, 9)
    return model, states, direct_renders(model, states)


def _ctrl_c_as_in_a_terminal() -> None:
    """In the child: let SIGINT raise KeyboardInterrupt even if this test was started from a
    shell that ignores it for background jobs (the ignore would be inherited)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.slow
@pytest.mark.timeout(120)
@pytest.mark.parametrize(("workers", "threads"), [(0, None), (2, None), (2, 1)])
def test_frames_come_back_in_order_and_equal_direct_renders(
    scene, workers: int, threads: int | None
) -> None:
    _, states, expected = scene
    got = []
    with RenderPool(
        LAYOUT, WIDTH, HEIGHT, "front", workers=workers, render_threads=threads
    ) as pool:
        for k, state in enumerate(states):
            assert pool.submit(state, payload=f"p{k}") == k
            assert pool.in_flight <= pool.max_in_flight  # backpressure: 2 per worker
            got.extend(pool.ready())
        got.extend(pool.drain())
    assert [f.index for f in got] == list(range(len(states)))
    assert [f.payload for f in got] == [f"p{k}" for k in range(len(states))]
    assert [f.time for f in got] == [s.time for s in states]
    for frame, reference in zip(got, expected, strict=True):
        assert frame.pixels.shape == (HEIGHT, WIDTH, 3)
        np.testing.assert_array_equal(frame.pixels, reference)  # llvmpipe is deterministic
    moved = np.mean(got[0].pixels != got[-1].pixels)
    assert moved > 0.001  # the arm and the hand really moved between the first and last frame


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_gesture_pose_change_shows_in_worker_frames() -> None:
    model, states = rollout(None, 1)
    data = mujoco.MjData(model)
    data.qpos[:], data.userdata[:] = states[0].qpos[: model.nq], states[0].qpos[model.nq :]
    display = GestureDisplay(model, data)  # the articulated hand: the pose is in userdata
    with RenderPool(None, WIDTH, HEIGHT, "side", workers=1) as pool:
        for pose in ("neutral", "thumb_up", "neutral"):
            display.show(pose)
            pool.submit(
                FrameState(
                    states[0].time,
                    np.concatenate([data.qpos, data.userdata]),  # the person's joints last
                    states[0].mocap_pos,
                    states[0].mocap_quat,
                    model.geom_rgba.copy(),
                )
            )
        neutral, thumb_up, neutral_again = (f.pixels for f in pool.drain())
    np.testing.assert_array_equal(neutral, neutral_again)
    assert np.sum(np.any(neutral != thumb_up, axis=2)) > 20  # pixels of the thumb-up hand


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_worker_error_names_the_frame_and_closes_the_pool(scene) -> None:
    _, states, expected = scene
    good = OverlayInfo(step=1, sim_time=0.5, action="give")
    pool = RenderPool(LAYOUT, WIDTH, HEIGHT, "front", workers=2, finish=draw_overlay)
    got = []
    failure = r"frame 3 \(t = .*AttributeError"
    with pytest.raises(RenderPoolError, match=failure) as caught, pool:
        for k, state in enumerate(states[:5]):
            pool.submit(state, good if k != 3 else "not an OverlayInfo")
            got.extend(pool.ready())
        got.extend(pool.drain())
    assert "draw_overlay" in caught.value.worker_traceback
    assert [f.index for f in got] == list(range(len(got))) and len(got) <= 3
    for frame in got:  # the hook ran in the worker: direct render + overlay
        np.testing.assert_array_equal(
            frame.pixels, draw_overlay(expected[frame.index].copy(), good)
        )
    assert not any(p.is_alive() for p in pool._processes)
    with pytest.raises(RenderPoolError, match="closed"):
        pool.submit(states[0])


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_killed_worker_is_reported_with_the_frame(scene) -> None:
    _, states, _ = scene
    with RenderPool(LAYOUT, WIDTH, HEIGHT, "front", workers=2) as pool:
        os.kill(pool.worker_pids[1], signal.SIGKILL)
        with pytest.raises(RenderPoolError, match=r"worker 1 .*exited .*frame 1"):
            for state in states[:4]:
                pool.submit(state)
                list(pool.ready())
            list(pool.drain())
        assert not any(p.is_alive() for p in pool._processes)


CTRL_C_CHILD = textwrap.dedent(
    """
    import sys
    from robin_sim.render.gl_backend import ensure_gl_backend
    ensure_gl_backend()
    sys.path.insert(0, {tests!r})
    from test_render_pool import LAYOUT, rollout
    from robin_sim.render.pool import RenderPool

    if __name__ == "__main__":
        _, states = rollout(LAYOUT, 2)
        with RenderPool(LAYOUT, 640, 480, "front", workers=2) as pool:
            print("workers", *pool.worker_pids, flush=True)
            while True:  # until Ctrl-C
                for state in states:
                    pool.submit(state)
                    list(pool.ready())
    """
)


@pytest.mark.slow
@pytest.mark.timeout(120)
def test_ctrl_c_ends_the_program_and_its_workers(tmp_path) -> None:
    script = tmp_path / "ctrl_c_child.py"
    script.write_text(CTRL_C_CHILD.format(tests=os.path.dirname(__file__)))
    child = subprocess.Popen(
        [sys.executable, str(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, like a program in a terminal
        preexec_fn=_ctrl_c_as_in_a_terminal,
    )
    line = child.stdout.readline()
    assert line.startswith("workers"), child.stderr.read()
    pids = [int(p) for p in line.split()[1:]]
    time.sleep(1.0)  # frames are being rendered
    os.killpg(child.pid, signal.SIGINT)  # Ctrl-C reaches the whole process group
    _, stderr = child.communicate(timeout=60)
    assert child.returncode != 0 and "KeyboardInterrupt" in stderr
    for pid in pids:
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)


def test_bad_arguments_are_reported_before_any_worker_starts(scene) -> None:
    _, states, _ = scene
    with pytest.raises(UnknownCameraError, match="valid choices: 'front'"):
        RenderPool(None, WIDTH, HEIGHT, "top", workers=2)
    with pytest.raises(RenderPoolError, match="workers must be"):
        RenderPool(None, WIDTH, HEIGHT, workers=-1)
    wrong_legs = pytest.raises(RenderPoolError, match=r"qpos has shape .* SceneLayout")
    with RenderPool(None, WIDTH, HEIGHT, workers=0) as pool, wrong_legs:  # four legs
        pool.submit(states[0])  # a two-leg state
