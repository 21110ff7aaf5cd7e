"""The render worker's side of :class:`robin_sim.render.pool.RenderPool`: frame states and the loop.

A :class:`FrameState` is what a frame needs of the simulation; :func:`apply_state` writes it
into a worker's own model and data; :func:`worker_main` is the loop each worker process runs
(build the scene, warm a renderer up, then render each state it receives).
"""

from __future__ import annotations

import contextlib
import os
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any

import mujoco
import numpy as np

from pil.signal_policy import deaf_from_now
from robin_sim.model.person_joints import has_figure, pose
from robin_sim.model.scene import SceneLayout, build_model
from robin_sim.render.gl_backend import ensure_gl_backend
from robin_sim.render.renderer import FrameRenderer, RenderError, camera_id

FinishHook = Callable[[np.ndarray, Any], object]  # finish(frame, payload), edits frame in place
START_TIMEOUT_S = 120.0  # a worker must have its scene and renderer ready by then
FRAME_TIMEOUT_S = 300.0  # the oldest outstanding frame must arrive by then
STOP_TIMEOUT_S = 10.0  # an idle worker must exit by then after being told to stop
MIN_DIVISIONS = 6  # slices and stacks of a coarse SecondView's round shapes, at least


class RenderPoolError(RenderError):
    """A frame that a render worker (or the in-process renderer) could not produce."""

    def __init__(self, message: str, worker_traceback: str = "") -> None:
        super().__init__(message)
        self.worker_traceback = worker_traceback


@dataclass(frozen=True, slots=True)
class FrameState:
    """What a frame needs of the simulation: time, joint positions, mocap poses, geom colours
    and geom shapes."""

    time: float
    qpos: np.ndarray  # the scene's qpos, then the person's joints (data.userdata)
    mocap_pos: np.ndarray
    mocap_quat: np.ndarray
    geom_rgba: np.ndarray  # (ngeom, 4); the gesture display changes alphas at run time
    # (ngeom, 3), (ngeom, 4), (ngeom, 3): the person's hand poses are shaped at run time
    # (robin_sim.figure.hand_poses), so a worker's freshly built model needs them too
    geom_pos: np.ndarray | None = None
    geom_quat: np.ndarray | None = None
    geom_size: np.ndarray | None = None

    @classmethod
    def capture(cls, model: mujoco.MjModel, data: mujoco.MjData) -> FrameState:
        """Copy the state of ``model``/``data`` now (later changes do not reach the frame)."""
        copies = (
            np.concatenate([data.qpos, data.userdata]),  # the person's joints: userdata
            data.mocap_pos,
            data.mocap_quat,
            model.geom_rgba,
            model.geom_pos,
            model.geom_quat,
            model.geom_size,
        )
        return cls(float(data.time), *(array.copy() for array in copies))


@dataclass(frozen=True, slots=True)
class SecondView:
    """A second, smaller view of the same state, rendered with the frames that ask for it
    (the episode's eye inset): by the same worker, from the same ``MjData``, at its own size."""

    camera: str
    size: tuple[int, int]  # (width, height)
    reflections: bool = False  # off: halves a small view's cost, which is mostly geometry
    # spheres, capsules and cylinders built of half the model's slices and stacks (its
    # <visual><quality numslices numstacks>): at a small size the same picture, drawn with a
    # third less work (the rest of a small view's cost does not depend on its size)
    coarse: bool = True


@dataclass(frozen=True, slots=True)
class RenderedFrame:
    """Frame ``index`` (0-based submission order) of time ``time``, with its payload (and the
    pool's :class:`SecondView` of the same state, when the frame asked for it)."""

    index: int
    time: float
    pixels: np.ndarray  # (H, W, 3) uint8, writable
    payload: Any
    second: np.ndarray | None = None  # (h, w, 3) uint8


def apply_state(model: mujoco.MjModel, data: mujoco.MjData, state: FrameState) -> None:
    """Write ``state`` into ``model``/``data`` and compute the positions a render shows."""
    data.time = state.time
    data.qpos[:] = state.qpos[: model.nq]
    data.userdata[:] = state.qpos[model.nq :]  # the person's joints (model.person_joints)
    data.mocap_pos[:] = state.mocap_pos
    data.mocap_quat[:] = state.mocap_quat
    model.geom_rgba[:] = state.geom_rgba
    if state.geom_pos is not None:
        model.geom_pos[:] = state.geom_pos
        model.geom_quat[:] = state.geom_quat
        model.geom_size[:] = state.geom_size
    if has_figure(model):
        pose(model, data)
    mujoco.mj_fwdPosition(model, data)


def warmed_renderer(
    model: mujoco.MjModel,
    size: tuple[int, int],
    camera: str,
    shadows: bool,
    reflections: bool = True,
) -> FrameRenderer:
    """A :class:`FrameRenderer` that has rendered one frame already.

    The first frame of a new renderer differs from later renders of the same state by up to 2
    levels in some pixels (llvmpipe); after one warm-up render, frames depend only on the state,
    so a video is the same whichever worker renders which frame.
    """
    renderer = FrameRenderer(model, size[0], size[1], camera, shadows, reflections)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    renderer.render(data)
    return renderer


def second_renderer(model: mujoco.MjModel, view: SecondView, shadows: bool) -> FrameRenderer:
    """A warmed renderer of ``view`` (its camera checked against ``model``; ``model``'s quality
    is as it was on return: a renderer builds its shapes when it is made)."""
    camera_id(model, view.camera)
    quality = model.vis.quality
    full = quality.numslices, quality.numstacks
    if view.coarse:
        quality.numslices, quality.numstacks = (max(MIN_DIVISIONS, n // 2) for n in full)
    try:
        return warmed_renderer(model, view.size, view.camera, shadows, view.reflections)
    finally:
        quality.numslices, quality.numstacks = full


def check_state(model: mujoco.MjModel, state: FrameState) -> None:
    """Raise :class:`RenderPoolError` when ``state`` does not fit the pool's scene."""
    nmocap = model.nmocap
    qpos = ("qpos", (model.nq + model.nuserdata,))  # with the person's joints (userdata)
    shapes = [qpos, ("mocap_pos", (nmocap, 3)), ("mocap_quat", (nmocap, 4))]
    for field, shape in [*shapes, ("geom_rgba", (model.ngeom, 4))]:
        got = np.shape(getattr(state, field))
        if got != shape:
            raise RenderPoolError(
                f"frame state {field} has shape {got} but the pool's scene needs {shape}; "
                "build the pool with the simulation's SceneLayout"
            )


def worker_main(
    conn: Connection,
    layout: SceneLayout | None,
    size: tuple[int, int],
    camera: str,
    shadows: bool,
    finish: FinishHook | None,
    render_threads: int | None,
    reflections: bool = True,
    second: SecondView | None = None,
) -> None:
    """Worker loop: receive (index, state, payload, with_second), reply ("frame", index,
    (pixels, second view or None)) or an error."""
    deaf_from_now()  # the main process handles Ctrl-C and SIGTERM, and ends us
    if render_threads is not None:  # read by Mesa's llvmpipe when the GL context is made
        os.environ["LP_NUM_THREADS"] = str(render_threads)
    try:
        ensure_gl_backend()
        model = build_model(layout)
        data = mujoco.MjData(model)
        renderer = warmed_renderer(model, size, camera, shadows, reflections)
        small = None if second is None else second_renderer(model, second, shadows)
    except Exception as exc:
        conn.send(("error", -1, f"{type(exc).__name__}: {exc}", traceback.format_exc()))
        return
    conn.send(("ready", -1, None, ""))
    with renderer, contextlib.ExitStack() as stack:
        if small is not None:
            stack.enter_context(small)
        while True:
            try:
                message = conn.recv()
            except EOFError:
                return
            if message is None:
                return
            index, state, payload, with_second = message
            try:
                apply_state(model, data, state)
                pixels = renderer.render(data)
                view = small.render(data) if with_second and small is not None else None
                if finish is not None:
                    finish(pixels, payload)
            except Exception as exc:
                conn.send(("error", index, f"{type(exc).__name__}: {exc}", traceback.format_exc()))
                continue
            conn.send(("frame", index, (pixels, view), ""))
