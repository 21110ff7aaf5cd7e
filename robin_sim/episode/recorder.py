"""Records an episode to MP4: frames at video rate from the simulator's tick hook, with overlay.

The recorder is an observer of :class:`robin_sim.control.simulator.Simulator`: after each control
tick it
asks the :class:`~robin_sim.render.renderer.FrameClock` whether a frame is due in simulated time,
and
only then hands the state to the render pool; finished frames get the overlay and are encoded.
The time waited on rendering and the time spent encoding are kept apart so that the episode's
wall time can be split (physics + control, rendering, encoding). With ``readings`` (the vision
detector of ``--detector vision``) the eye inset shows, for a moment after each reading, what
the robot read: its eye's view with the hand's box and the reading, instead of the live eye.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Protocol

import numpy as np

from robin_sim.closing import ClosesOnExit
from robin_sim.control.simulator import Simulator
from robin_sim.episode.view import EpisodeView
from robin_sim.model.scene import SceneLayout
from robin_sim.render.inset import INSET_LABEL, EyeInset, draw_eye_inset
from robin_sim.render.overlay import OverlayInfo, draw_overlay
from robin_sim.render.pool import FrameState, RenderedFrame, RenderPool
from robin_sim.render.renderer import FrameClock
from robin_sim.render.state_log import StateLog, layout_dict
from robin_sim.render.video import Mp4Writer


@dataclass
class ReadingInsets(Protocol):
    """What the eye inset shows instead of the live eye at a time (the vision detector)."""

    def inset_at(self, time: float, size: tuple[int, int]) -> np.ndarray | None:
        """The picture of a reading made shortly before ``time``, at ``size``; else None."""
        ...


READING_LABEL = "robot's left eye: reading"


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
    this process) and come back in order; the overlay is drawn and the frame encoded here.
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
            self.states = StateLog(states, {
                "kind": "episode", "layout": layout_dict(layout), "size": [width, height],
                "fps": fps, "camera": camera, "shadows": shadows, "reflections": True,
                "eye_inset": eye_inset, "overlay": True, "spots": [],
            })  # fmt: skip
        self.eye: EyeInset | None = None
        self.readings = readings
        # eye views (and their labels) of frames still rendering
        self._eye_views: deque[tuple[np.ndarray, str]] = deque()
        self.timing = VideoTiming()
        self.pool = RenderPool(layout, width, height, camera, shadows, workers=render_workers)
        try:
            self.writer = Mp4Writer(path, width, height, fps)
        except BaseException:
            self.pool.close()
            raise
        self._sim = sim
        if eye_inset:
            self._start_eye_inset(layout, width, height, shadows)
        self.clock = FrameClock(fps, sim.control_dt)
        self._start_time = sim.time
        self._remove: Callable[[], None] | None = sim.add_observer(self._on_tick)

    def _on_tick(self, sim: Simulator) -> None:
        due = self.clock.frames_due(sim.time - self._start_time)
        if due == 0:
            return
        started = time.perf_counter()
        info = replace(self.view.info, sim_time=sim.time)
        state = FrameState.capture(sim.model, sim.data)
        self._keep(state, due, info, self._render_eye(state))
        self.pool.submit(state, (info, due))
        self.timing.render_s += time.perf_counter() - started  # waits only when the pool is full
        self._write(self.pool.ready())

    def _write(self, frames: Iterable[RenderedFrame]) -> None:
        waited = time.perf_counter()
        for frame in frames:
            started = time.perf_counter()
            self.timing.render_s += started - waited  # waiting for a frame still rendering
            info, due = frame.payload
            draw_overlay(frame.pixels, info)
            self._draw_eye(frame.pixels)
            for _ in range(due):
                self.writer.write(frame.pixels)
            self.timing.frames_rendered += 1
            self.timing.frames_written += due
            waited = time.perf_counter()
            self.timing.encode_s += waited - started

    # --- the eye inset (robin_sim.render.inset) -------------------------------------------------
    def _start_eye_inset(
        self, layout: SceneLayout | None, width: int, height: int, shadows: bool
    ) -> None:
        try:
            self.eye = EyeInset(layout, width, height, shadows)
        except BaseException:
            self.writer.close()
            self.pool.close()
            raise

    def _render_eye(self, state: FrameState) -> str | None:
        """Render the eye's view of a frame's state (once per video frame, in this process), or
        take the picture of a reading just made; the inset's label (None: no inset)."""
        if self.eye is None:  # its time counts in VideoTiming.render_s (see _on_tick)
            return None
        if self.readings is not None:
            picture = self.readings.inset_at(self._sim.time, self.eye.size)
            if picture is not None:
                self._eye_views.append((picture, READING_LABEL))
                return READING_LABEL
        self._eye_views.append((self.eye.render(state), INSET_LABEL))
        return INSET_LABEL

    def _keep(self, state: FrameState, due: int, info: OverlayInfo, eye: str | None) -> None:
        """Note a frame's state and what is drawn on it for the states file."""
        if self.states is not None:
            shown = {k: v for k, v in asdict(info).items() if k != "sim_time"}  # the state's
            self.states.add(state, due, {"info": shown, "eye": eye})

    def _draw_eye(self, pixels: np.ndarray) -> None:
        """Paste the eye view of the frame coming back (frames return in submission order)."""
        if self.eye is not None:
            draw_eye_inset(pixels, *self._eye_views.popleft())

    def close(self) -> None:
        """Stop recording, write the frames still rendering and finish the MP4 (idempotent).

        A video stopped before its first frame (e.g. Ctrl-C during start-up) gets one frame of
        the scene as it is, so that every video written plays.
        """
        if self._remove is None:
            return
        self._remove()
        self._remove = None
        try:
            if self.pool.in_flight == 0 and self.timing.frames_written == 0:
                sim = self._sim
                info = replace(self.view.info, sim_time=sim.time)
                state = FrameState.capture(sim.model, sim.data)
                # every frame submitted has its eye view
                self._keep(state, 1, info, self._render_eye(state))
                self.pool.submit(state, (info, 1))
            self._write(self.pool.drain())
        finally:
            if self.eye is not None:
                self.eye.close()
            self.pool.close()
            started = time.perf_counter()
            self.writer.close()
            self.timing.encode_s += time.perf_counter() - started
            if self.states is not None:
                self.states.save()
