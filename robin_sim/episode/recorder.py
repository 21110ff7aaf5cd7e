"""Records an episode to MP4: frames at video rate from the simulator's tick hook, with overlay.

The recorder is an observer of :class:`robin_sim.control.simulator.Simulator`: after each control
tick it
asks the :class:`~robin_sim.render.renderer.FrameClock` whether a frame is due in simulated time,
and
only then hands the state to the render pool; finished frames get the overlay and are encoded.
The time waited on rendering and the time spent encoding are kept apart so that the episode's
wall time can be split (physics + control, rendering, encoding).

The eye inset (the robot's left eye, :mod:`robin_sim.render.inset`) is rendered by the render
workers with the frame it belongs to (:class:`~robin_sim.render.worker.SecondView`: the same
state, the worker's second renderer, no floor reflection, round shapes of half the slices) and
refreshed at :data:`EYE_FPS`; the frames in between repeat the last view. Its cost is mostly
geometry, not pixels: a quarter of a 640x480 frame's CPU time at full detail, a seventh with
the coarse shapes, about 5 % of an episode's CPU time at 30 fps (``bench/bench_eye_inset.py``).
With ``readings`` (the vision detector of ``--detector vision``) the inset shows, for a moment
after each reading, what the robot read: its eye's view with the hand's box and the reading,
instead of the live eye. The last frame shows the overlay as the episode ended (the legs
delivered by its last step).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from types import TracebackType
from typing import Protocol

import numpy as np

from robin_sim.closing import ClosesOnExit
from robin_sim.control.simulator import Simulator
from robin_sim.episode.view import EpisodeView
from robin_sim.model.names import EYE_CAMERA
from robin_sim.model.scene import SceneLayout
from robin_sim.render.inset import HELD_EYE, INSET_LABEL, draw_eye_inset, inset_size
from robin_sim.render.overlay import OverlayInfo, draw_overlay
from robin_sim.render.pool import FrameState, RenderedFrame, RenderPool
from robin_sim.render.renderer import FrameClock, camera_id
from robin_sim.render.spots import spot_pixels
from robin_sim.render.state_log import StateLog, layout_dict
from robin_sim.render.video import Mp4Writer
from robin_sim.render.worker import SecondView


class ReadingInsets(Protocol):
    """What the eye inset shows instead of the live eye at a time (the vision detector)."""

    def inset_at(self, time: float, size: tuple[int, int]) -> np.ndarray | None:
        """The picture of a reading made shortly before ``time``, at ``size``; else None."""
        ...


READING_LABEL = "robot's left eye: reading"
EYE_FPS = 10.0  # the eye inset's refresh rate, at most (the video's rate if lower)


@dataclass
class VideoTiming:
    """Wall-clock seconds waited on rendering, spent on overlay + encoding, and frame counts."""

    render_s: float = 0.0
    encode_s: float = 0.0
    frames_rendered: int = 0
    frames_written: int = 0


class VideoRecorder(ClosesOnExit):
    """Writes ``sim``'s view from ``camera`` to ``path`` while the simulator runs.

    Frames are rendered by a :class:`~robin_sim.render.pool.RenderPool` (worker processes
    with their own copy of the scene built from ``layout``; ``render_workers=0`` renders in
    this process) and come back in order, with the eye view when one was due; the overlay and
    the inset are drawn and the frame encoded here.
    """

    def __init__(
        self,
        sim: Simulator,
        view: EpisodeView,
        path: Path,
        *,
        layout: SceneLayout | None = None,
        width: int = 640,
        height: int = 480,
        fps: int = 30,
        camera: str = "front",
        shadows: bool = False,
        render_workers: int | None = None,
        eye_inset: bool = True,
        readings: ReadingInsets | None = None,
        states: Path | None = None,
    ) -> None:
        self.view = view
        # the state of every frame (``states``: where to save them for robin-pil replay)
        self.states: StateLog | None = None
        if states is not None:
            meta = {
                "kind": "episode",
                "layout": layout_dict(layout),
                "size": [width, height],
                "fps": fps,
                "camera": camera,
                "shadows": shadows,
                "reflections": True,
                "eye_inset": eye_inset,
                "overlay": True,
                "spots": [],
            }
            self.states = StateLog(states, meta)
        self.readings = readings
        self.eye_size = inset_size(width, height) if eye_inset else None
        self.eye_every = max(1, round(fps / EYE_FPS))  # video frames per eye view
        self._last_eye: np.ndarray | None = None
        self._submitted = 0
        self._last_legs = -1  # legs delivered shown by the last frame submitted
        self.timing = VideoTiming()
        second = None if self.eye_size is None else SecondView(EYE_CAMERA, self.eye_size)
        self.pool = RenderPool(
            layout, width, height, camera, shadows, workers=render_workers, second=second
        )
        try:
            self.writer = Mp4Writer(path, width, height, fps)
        except BaseException:
            self.pool.close()
            raise
        self._sim = sim
        self._camera, self._size = camera_id(sim.model, camera), (width, height)
        self._spots = (layout or SceneLayout()).spots  # ringed and numbered on every frame
        self.clock = FrameClock(fps, sim.control_dt)
        self._start_time = sim.time
        self._remove: Callable[[], None] | None = sim.add_observer(self._on_tick)

    def _on_tick(self, sim: Simulator) -> None:
        due = self.clock.frames_due(sim.time - self._start_time)
        if due == 0:
            return
        started = time.perf_counter()
        self._submit(sim, due)
        self.timing.render_s += time.perf_counter() - started  # waits only when the pool is full
        self._write(self.pool.ready())

    def _submit(self, sim: Simulator, due: int) -> None:
        """Hand the state now to the pool, standing for ``due`` video frames."""
        spots = spot_pixels(sim.model, sim.data, self._camera, self._spots, self._size)
        info = replace(self.view.info, sim_time=sim.time, spots=spots)
        sim.prepare_view()  # the person's body follows its hand (robin_sim.figure.posture)
        state = FrameState.capture(sim.model, sim.data)
        reading = None
        if self.readings is not None and self.eye_size is not None:
            reading = self.readings.inset_at(sim.time, self.eye_size)
        with_eye = self.eye_size is not None and reading is None
        with_eye = with_eye and self._submitted % self.eye_every == 0  # the first frame has one
        self.pool.submit(state, (info, due, reading), with_second=with_eye)
        if self.states is not None:
            eye = None if self.eye_size is None else INSET_LABEL if with_eye else HELD_EYE
            self._keep(state, due, info, READING_LABEL if reading is not None else eye)
        self._submitted += 1
        self._last_legs = info.legs_delivered

    def _keep(self, state: FrameState, due: int, info: OverlayInfo, eye: str | None) -> None:
        """Note a frame's state and what is drawn on it for the states file (``eye``: the
        inset's label, :data:`~robin_sim.render.inset.HELD_EYE` when it repeats the last view)."""
        assert self.states is not None
        shown = {k: v for k, v in asdict(info).items() if k != "sim_time"}  # the state's
        self.states.add(state, due, {"info": shown, "eye": eye})

    def _write(self, frames: Iterable[RenderedFrame]) -> None:
        waited = time.perf_counter()
        for frame in frames:
            started = time.perf_counter()
            self.timing.render_s += started - waited  # waiting for a frame still rendering
            info, due, reading = frame.payload
            draw_overlay(frame.pixels, info)
            self._draw_eye(frame, reading)
            for _ in range(due):
                self.writer.write(frame.pixels)
            self.timing.frames_rendered += 1
            self.timing.frames_written += due
            waited = time.perf_counter()
            self.timing.encode_s += waited - started

    def _draw_eye(self, frame: RenderedFrame, reading: np.ndarray | None) -> None:
        """Paste the reading's picture, the eye view rendered with ``frame``, or the last one."""
        if frame.second is not None:
            self._last_eye = frame.second
        if reading is not None:
            draw_eye_inset(frame.pixels, reading, READING_LABEL)
        elif self._last_eye is not None:
            draw_eye_inset(frame.pixels, self._last_eye, INSET_LABEL)

    def close(self) -> None:
        """Stop recording, write the frames still rendering and finish the MP4 (idempotent).

        A video stopped before its first frame (e.g. Ctrl-C during start-up) gets one frame of
        the scene as it is, so that every video written plays; one whose last frame shows fewer
        legs delivered than the episode ended with gets one more frame showing them.
        """
        self._finish(None)

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self._finish(exc)

    def _finish(self, failure: BaseException | None) -> None:
        """:meth:`close`, where ``failure`` (if any) ended the recording: then the states
        file's own failure (a full disk again) does not hide it."""
        if self._remove is None:
            return
        self._remove()
        self._remove = None
        try:
            empty = self.pool.in_flight == 0 and self.timing.frames_written == 0
            if empty or self.view.info.legs_delivered != self._last_legs:
                self._submit(self._sim, 1)
            self._write(self.pool.drain())
        except BaseException as error:
            failure = failure or error
            raise
        finally:
            self.pool.close()
            started = time.perf_counter()
            self.writer.close()
            self.timing.encode_s += time.perf_counter() - started
            if self.states is not None:
                try:
                    self.states.save()
                except OSError:
                    if failure is None:
                        raise
