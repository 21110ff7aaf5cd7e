"""Records an episode to MP4: frames at video rate from the simulator's tick hook, with overlay.

The recorder is an observer of :class:`robin_sim.control.Simulator`: after each control tick it
asks the :class:`~robin_sim.render.FrameClock` whether a frame is due in simulated time, and
only then renders, draws the overlay and encodes. Rendering and encoding times are kept apart
so that the episode's wall time can be split (physics + control, rendering, encoding).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from types import TracebackType
from typing import Self

from robin_sim.control import Simulator
from robin_sim.narration import EpisodeView
from robin_sim.overlay import draw_overlay
from robin_sim.render import FrameClock, FrameRenderer
from robin_sim.video import Mp4Writer


@dataclass
class VideoTiming:
    """Wall-clock seconds spent rendering (with overlay) and encoding, and frame counts."""

    render_s: float = 0.0
    encode_s: float = 0.0
    frames_rendered: int = 0
    frames_written: int = 0


class VideoRecorder:
    """Writes ``sim``'s view from ``camera`` to ``path`` while the simulator runs."""

    def __init__(
        self,
        sim: Simulator,
        view: EpisodeView,
        path: Path,
        *,
        width: int = 640,
        height: int = 480,
        fps: int = 30,
        camera: str = "front",
        shadows: bool = True,
    ) -> None:
        self.view = view
        self.timing = VideoTiming()
        self.renderer = FrameRenderer(sim.model, width, height, camera, shadows=shadows)
        try:
            self.writer = Mp4Writer(path, width, height, fps)
        except BaseException:
            self.renderer.close()
            raise
        self.clock = FrameClock(fps, sim.control_dt)
        self._start_time = sim.time
        self._remove = sim.add_observer(self._on_tick)

    def _on_tick(self, sim: Simulator) -> None:
        due = self.clock.frames_due(sim.time - self._start_time)
        if due == 0:
            return
        started = time.perf_counter()
        frame = self.renderer.render(sim.data)
        draw_overlay(frame, replace(self.view.info, sim_time=sim.time))
        rendered = time.perf_counter()
        for _ in range(due):
            self.writer.write(frame)
        self.timing.render_s += rendered - started
        self.timing.encode_s += time.perf_counter() - rendered
        self.timing.frames_rendered += 1
        self.timing.frames_written += due

    def close(self) -> None:
        """Stop recording and finish the MP4 (idempotent); the file is playable afterwards."""
        if self._remove is not None:
            self._remove()
            self._remove = None
        started = time.perf_counter()
        self.writer.close()
        self.timing.encode_s += time.perf_counter() - started
        self.renderer.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
