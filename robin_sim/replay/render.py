"""Re-render a recorded run's frames from its states and write them to an MP4.

Each state of ``states.npz`` is rendered with the run's own settings (camera, size, shadows,
reflections), and gets what the run drew on it: the episode's overlay and eye inset, or the
live stream's eye inset, spot rings and leg numbers. Frames come out pixel-identical to the
run's (the renderers are deterministic after their warm-up), so the MP4 matches the original
up to H.264 encoding.
An episode's eye inset is rendered by the render workers as the episode's was (a second view,
refreshed where the run refreshed it, the last view repeated between); a live stream's in this
process. One exception: frames where the vision detector's inset showed a reading get the
live eye view, and a frame rendered alone (scrubbing) gets its own eye view.
"""

from __future__ import annotations

import os
import time
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robin_sim.closing import ClosesOnExit
from robin_sim.model.names import EYE_CAMERA
from robin_sim.render.inset import HELD_EYE, INSET_LABEL, EyeInset, draw_eye_inset, inset_size
from robin_sim.render.overlay import OverlayInfo, draw_overlay
from robin_sim.render.pool import RenderPool
from robin_sim.render.state_log import RecordedStates
from robin_sim.render.video import Mp4Writer
from robin_sim.render.worker import SecondView


@dataclass(frozen=True)
class ReplayResult:
    """What a replay wrote."""

    path: Path
    frames_rendered: int
    video_frames: int
    fps: int
    size: tuple[int, int]
    wall_s: float
    approximate: int  # frames whose inset showed a vision reading (replayed with the live eye)

    def as_dict(self) -> dict[str, object]:
        return {
            "path": str(self.path),
            "frames_rendered": self.frames_rendered,
            "video_frames": self.video_frames,
            "fps": self.fps,
            "size": list(self.size),
            "wall_s": round(self.wall_s, 3),
            "approximate": self.approximate,
        }


class ReplayRenderer(ClosesOnExit):
    """Renders recorded frames as the run drew them; build and use it in one thread (its
    OpenGL contexts belong to it). ``workers`` > 0 renders the scene in worker processes."""

    def __init__(self, recorded: RecordedStates, workers: int = 0) -> None:
        meta = self.meta = recorded.meta
        self.recorded = recorded
        width, height = meta["size"]
        layout = recorded.layout
        shadows, reflections = bool(meta["shadows"]), bool(meta["reflections"])
        self.spots = [tuple(xy) for xy in meta["spots"]]
        self.eye: EyeInset | None = None
        # an episode's inset: the workers' second view, as recorded (robin_sim.episode.recorder)
        second = None
        if meta["eye_inset"] and meta.get("kind") == "episode":
            second = SecondView(EYE_CAMERA, inset_size(width, height))
        self.second = second
        self._last_eye: np.ndarray | None = None
        self.pool = RenderPool(
            layout,
            width,
            height,
            meta["camera"],
            shadows,
            workers=workers,
            reflections=reflections,
            second=second,
        )
        try:
            if meta["eye_inset"] and second is None:
                self.eye = EyeInset(layout, width, height, shadows, reflections)
        except BaseException:
            self.pool.close()
            raise
        self._eyes: deque[np.ndarray] = deque()  # eye views of the frames still rendering
        self.picker: Any = None  # where the legs are seen, for the live stream's leg numbers
        if meta.get("leg_numbers"):
            from robin_sim.live.picking import Picker

            self.picker = Picker(layout, width, height)

    def submit(self, index: int, alone: bool = False) -> None:
        """Start rendering frame ``index`` (``alone``: out of sequence, with its own eye view)."""
        state = self.recorded.states[index]
        if self.eye is not None:
            self._eyes.append(self.eye.render(state))
        overlay = self.recorded.overlays[index]
        held = overlay is not None and overlay.get("eye") == HELD_EYE
        with_eye = self.second is not None and (alone or not held or self._last_eye is None)
        self.pool.submit(state, index, with_second=with_eye)

    def finished(self, wait: bool = False) -> Iterator[tuple[int, np.ndarray]]:
        """(index, pixels) of the frames rendered so far (``wait``: all submitted), in order."""
        from robin_sim.live.frames import draw_leg_numbers
        from robin_sim.render.spots import PAGE_FIRST_SPOT, draw_spots

        for frame in self.pool.drain() if wait else self.pool.ready():
            index, pixels = frame.payload, frame.pixels
            overlay = self.recorded.overlays[index]
            if self.meta["overlay"] and overlay is not None:
                draw_overlay(pixels, OverlayInfo(**{**overlay["info"], "sim_time": frame.time}))
            if self.eye is not None:
                draw_eye_inset(pixels, self._eyes.popleft(), INSET_LABEL)
            if frame.second is not None:
                self._last_eye = frame.second
            if self.second is not None and self._last_eye is not None:
                draw_eye_inset(pixels, self._last_eye, INSET_LABEL)
            if self.spots:
                draw_spots(pixels, self.spots, first=PAGE_FIRST_SPOT)
            if self.picker is not None:
                self.picker.show(self.recorded.states[index])
                draw_leg_numbers(pixels, self.picker.leg_pixels())
            yield index, pixels

    def render(self, index: int) -> np.ndarray:
        """Frame ``index`` alone (waits for it)."""
        self.submit(index, alone=True)
        return next(pixels for _, pixels in self.finished(wait=True))

    def close(self) -> None:
        """Free the renderers (idempotent)."""
        try:
            if self.eye is not None:
                self.eye.close()
        finally:
            self.pool.close()


def replayed_frames(recorded: RecordedStates, workers: int = 0) -> Iterator[tuple[np.ndarray, int]]:
    """Each recorded frame re-rendered and drawn on as the run drew it, with its copies."""
    with ReplayRenderer(recorded, workers) as renderer:
        for index in range(len(recorded.states)):
            renderer.submit(index)
            for done, pixels in renderer.finished():
                yield pixels, int(recorded.copies[done])
        for done, pixels in renderer.finished(wait=True):
            yield pixels, int(recorded.copies[done])


def partial_path(out: Path) -> Path:
    """Where a replay is written until it is complete: ``replay.mp4.part`` beside ``out``
    (an interrupted replay leaves it, playable up to its last second; the final name appears
    only for a complete video, so a rerun is never refused)."""
    return out.with_name(out.name + ".part")


def replay_to_mp4(recorded: RecordedStates, out: Path, workers: int = 0) -> ReplayResult:
    """Write ``recorded``'s frames, re-rendered, to the MP4 ``out`` (through
    :func:`partial_path`, renamed to ``out`` when every frame is written)."""
    started = time.perf_counter()
    meta = recorded.meta
    width, height = meta["size"]
    rendered = written = 0
    partial = partial_path(out)
    with Mp4Writer(partial, width, height, int(meta["fps"])) as writer:
        for pixels, copies in replayed_frames(recorded, workers):
            for _ in range(copies):
                writer.write(pixels)
            rendered += 1
            written += copies
    os.replace(partial, out)
    exact = (None, INSET_LABEL, HELD_EYE)  # what the replay draws as the run did
    approximate = sum(1 for o in recorded.overlays if o and o.get("eye") not in exact)
    return ReplayResult(
        out,
        rendered,
        written,
        int(meta["fps"]),
        (width, height),
        time.perf_counter() - started,
        approximate,
    )
