"""Render video frames in worker processes, in submission order, while physics runs on.

Software rendering (llvmpipe) of a 640x480 frame takes 50-400 ms; meanwhile the episode's
physics, overlay and H.264 encoding wait. :class:`RenderPool` starts ``workers`` processes
(``spawn``), each with its own scene (:func:`robin_sim.model.scene.build_model`) and a
:class:`~robin_sim.render.renderer.FrameRenderer`, so rendering overlaps the main process's work.
Per
frame the main process sends a :class:`FrameState` (time, ``qpos``, mocap poses, and
``geom_rgba``, whose alphas the gesture display changes) and an opaque payload; a worker
applies it to its own ``MjData`` (``mj_fwdPosition``) and renders. Frames come back strictly
in submission order, at most ``in_flight_per_worker`` per worker outstanding, as pickled
arrays over pipes (0.9 MB at 640x480, 1-5 ms). ``workers=0`` renders in-process, same API.

A frame shows the state's own ``qpos`` and is pixel-identical to a warmed-up
:class:`FrameRenderer`'s render of it, whichever worker renders it. Workers ignore SIGINT and
SIGTERM from their first instruction on (they start with both ignored, inherited through
``exec``; :mod:`robin_sim.render.worker_start`): a Ctrl-C sent to the
whole process group reaches only the main process, which finishes the frames in flight and
ends the workers with :meth:`RenderPool.close`.
"""

from __future__ import annotations

import contextlib
import multiprocessing
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any, NoReturn

import mujoco

from pil.cpus import cpu_count
from robin_sim.closing import ClosesOnExit
from robin_sim.model.scene import SceneLayout, build_model
from robin_sim.render.gl_backend import ensure_gl_backend
from robin_sim.render.renderer import FrameRenderer, camera_id
from robin_sim.render.worker import (
    FRAME_TIMEOUT_S,
    START_TIMEOUT_S,
    STOP_TIMEOUT_S,
    FinishHook,
    FrameState,
    RenderedFrame,
    RenderPoolError,
    SecondView,
    apply_state,
    check_state,
    second_renderer,
    warmed_renderer,
)
from robin_sim.render.worker_start import blocked_for_children, start_worker


def default_render_workers() -> int:
    """Render workers when none are given: 2, or 0 (in-process) on a machine with one CPU.

    On 2 CPUs two workers recorded 1.3-1.6x the frames/s of in-process rendering (see
    ``bench/bench_render_pool.py``): llvmpipe leaves a CPU partly idle within one frame.
    """
    return 2 if cpu_count() >= 2 else 0


@dataclass(frozen=True, slots=True)
class _Pending:
    index: int
    time: float
    payload: Any
    worker: int


class RenderPool(ClosesOnExit):
    """Renders :class:`FrameState` s of ``layout``'s scene in ``workers`` processes, in order.

    Submit with :meth:`submit`; take finished frames with :meth:`ready` (never waits) after
    each submit and :meth:`drain` (waits for all) at the end. ``finish(frame, payload)``, a
    module-level function, runs on each frame where it was rendered (e.g. to draw an overlay).
    ``workers=0`` renders inside :meth:`submit`; ``None`` picks :func:`default_render_workers`.
    ``render_threads`` sets each worker's
    llvmpipe thread count (``LP_NUM_THREADS``; default: Mesa's, one per CPU). Use as a
    context manager or call :meth:`close`; frames not drained by then are dropped.
    """

    def __init__(
        self,
        layout: SceneLayout | None = None,
        width: int = 640,
        height: int = 480,
        camera: str = "front",
        shadows: bool = True,
        *,
        workers: int | None = None,
        in_flight_per_worker: int = 2,
        finish: FinishHook | None = None,
        render_threads: int | None = None,
        reflections: bool = True,
        second: SecondView | None = None,
    ) -> None:
        workers = default_render_workers() if workers is None else workers
        for name, value, least in (
            ("workers", workers, 0),
            ("in_flight_per_worker", in_flight_per_worker, 1),
            ("render_threads", 1 if render_threads is None else render_threads, 1),
        ):
            if isinstance(value, bool) or not isinstance(value, int) or value < least:
                raise RenderPoolError(f"{name} must be a whole number >= {least}, got {value!r}")
        ensure_gl_backend()  # workers inherit the choice through the environment
        self.workers = workers
        self.max_in_flight = workers * in_flight_per_worker
        self._finish = finish
        self._model = build_model(layout)  # validates the camera before any process starts
        self._data = mujoco.MjData(self._model)
        camera_id(self._model, camera)
        self._local: FrameRenderer | None = None
        self._local_second: FrameRenderer | None = None
        self.second = second
        if second is not None:
            camera_id(self._model, second.camera)
        if workers == 0:
            self._local = warmed_renderer(
                self._model, (width, height), camera, shadows, reflections
            )
            if second is not None:
                self._local_second = second_renderer(self._model, second, shadows)
        self._pending: deque[_Pending] = deque()
        self._ready: deque[RenderedFrame] = deque()
        self._submitted = 0
        self._closed = False
        self._processes: list[multiprocessing.process.BaseProcess] = []
        self._conns: list[Connection] = []
        if workers == 0:
            return
        context = multiprocessing.get_context("spawn")
        try:
            for _ in range(workers):
                parent, child = context.Pipe()
                process = context.Process(
                    target=start_worker,
                    args=(
                        child,
                        layout,
                        (width, height),
                        camera,
                        shadows,
                        finish,
                        render_threads,
                        reflections,
                        second,
                    ),
                    daemon=True,
                )
                with blocked_for_children():  # the worker starts deaf to Ctrl-C
                    process.start()
                child.close()
                self._processes.append(process)
                self._conns.append(parent)
            for worker in range(workers):
                self._receive(worker, START_TIMEOUT_S, "while starting")
        except BaseException:
            self.close()
            raise

    @property
    def worker_pids(self) -> tuple[int, ...]:
        """Process ids of the workers (empty with ``workers=0``)."""
        return tuple(p.pid or -1 for p in self._processes)

    @property
    def in_flight(self) -> int:
        """Frames submitted to workers and not yet back (at most :attr:`max_in_flight`)."""
        return len(self._pending)

    def submit(self, state: FrameState, payload: Any = None, *, with_second: bool = False) -> int:
        """Queue ``state`` for rendering (``with_second``: its :class:`SecondView` too); return
        its frame index. Waits while the pool is full."""
        if self._closed:
            raise RenderPoolError("the render pool is closed; start a new one")
        check_state(self._model, state)
        index = self._submitted
        if self._local is not None:
            try:
                apply_state(self._model, self._data, state)
                pixels = self._local.render(self._data)
                small = self._local_second
                view = small.render(self._data) if with_second and small is not None else None
                if self._finish is not None:
                    self._finish(pixels, payload)
            except Exception as exc:
                raise RenderPoolError(
                    f"frame {index} (t = {state.time:.3f} s) failed: {type(exc).__name__}: {exc}"
                ) from exc
            self._ready.append(RenderedFrame(index, state.time, pixels, payload, view))
            self._submitted += 1
            return index
        while len(self._pending) >= self.max_in_flight:
            self._collect_oldest()
        worker = index % self.workers
        try:
            message = (index, state, payload if self._finish else None, with_second)
            self._conns[worker].send(message)
        except OSError:
            process = self._processes[worker]
            process.join(1.0)
            self._fail(
                RenderPoolError(
                    f"render worker {worker} (pid {process.pid}) exited (code "
                    f"{process.exitcode}) before frame {index} (t = {state.time:.3f} s)"
                )
            )
        self._pending.append(_Pending(index, state.time, payload, worker))
        self._submitted += 1
        return index

    def ready(self) -> Iterator[RenderedFrame]:
        """Frames finished so far, in submission order, without waiting for more."""
        while True:
            while self._ready:
                yield self._ready.popleft()
            if not self._pending or not self._conns[self._pending[0].worker].poll():
                return
            self._collect_oldest()

    def drain(self) -> Iterator[RenderedFrame]:
        """Every outstanding frame, in submission order, waiting for each."""
        while self._ready or self._pending:
            while self._ready:
                yield self._ready.popleft()
            if self._pending:
                self._collect_oldest()

    def _collect_oldest(self) -> None:
        oldest = self._pending[0]
        when = f"on frame {oldest.index} (t = {oldest.time:.3f} s)"
        pixels, view = self._receive(oldest.worker, FRAME_TIMEOUT_S, when, oldest.index)
        self._pending.popleft()
        self._ready.append(RenderedFrame(oldest.index, oldest.time, pixels, oldest.payload, view))

    def _receive(self, worker: int, timeout: float, when: str, index: int = -1) -> Any:
        """The next reply of ``worker``; raises :class:`RenderPoolError` (and closes) on trouble."""
        conn, process = self._conns[worker], self._processes[worker]
        name = f"render worker {worker} (pid {process.pid})"
        if not wait([conn, process.sentinel], timeout):
            self._fail(RenderPoolError(f"{name} sent nothing for {timeout:.0f} s {when}"))
        try:
            kind, got, body, worker_traceback = conn.recv()
        except (EOFError, OSError):
            process.join(1.0)
            self._fail(RenderPoolError(f"{name} exited (code {process.exitcode}) {when}"))
        if kind == "error":
            self._fail(RenderPoolError(f"{name} failed {when}: {body}", worker_traceback))
        if got != index:
            self._fail(RenderPoolError(f"{name} sent frame {got} {when}; expected {index}"))
        return body

    def _fail(self, error: RenderPoolError) -> NoReturn:
        self.close()
        raise error

    def close(self) -> None:
        """End the workers (waits for idle ones, stops busy ones) and free GL; idempotent."""
        if self._closed:
            return
        self._closed = True
        abandon = bool(self._pending)  # busy workers may block sending frames nobody reads
        self._pending.clear()
        self._ready.clear()
        for conn, process in zip(self._conns, self._processes, strict=True):
            if not abandon:
                with contextlib.suppress(OSError):
                    conn.send(None)
                process.join(STOP_TIMEOUT_S)
            if process.is_alive():  # busy, or stuck: it ignores SIGTERM, so kill it
                process.kill()
                process.join(STOP_TIMEOUT_S)
        for conn in self._conns:
            conn.close()
        for local in (self._local, self._local_second):
            if local is not None:
                local.close()
        self._local = self._local_second = None
