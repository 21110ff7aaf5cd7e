"""The live stream's frames: rendered from the physics state, JPEG-encoded, published, recorded.

:class:`FrameStream` renders the scene camera (no shadows; by default no floor reflection
either, which saves a third of the render time, see the README) through a
:class:`~robin_sim.render.pool.RenderPool` (``render_workers=0``: in the physics thread; N:
worker processes; the bench measured in-process best), pastes the robot's eye inset
(:mod:`robin_sim.render.inset`; ``eye_worker``: rendered meanwhile in a process of its own)
and rings marking the table spots, encodes each frame as JPEG (``cv2.imencode``) and hands it
to every subscriber as a :class:`Frame`; the same pixels go into the MP4 (:class:`Mp4Writer`:
fragmented, so it plays however the session stops). Build and use it in the physics thread:
its OpenGL contexts belong to the thread that made them.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import mujoco
import numpy as np

from robin_sim.closing import ClosesOnExit
from robin_sim.model.names import DEFAULT_CAMERA, EYE_CAMERA
from robin_sim.model.scene import LEG_COLORS, SceneLayout
from robin_sim.render.inset import EyeInset, draw_eye_inset, inset_size
from robin_sim.render.pool import FrameState, RenderedFrame, RenderPool
from robin_sim.render.spots import PAGE_FIRST_SPOT, draw_spots
from robin_sim.render.state_log import StateLog, layout_dict
from robin_sim.render.video import Mp4Writer

JPEG_QUALITY = 80


@dataclass(frozen=True, slots=True)
class Frame:
    """One streamed frame."""

    seq: int  # 1, 2, 3, ... per session
    jpeg: bytes  # the scene frame with the eye inset, JPEG
    sim_time: float  # the physics time it shows
    captured: float  # time.monotonic() when that physics state was captured


@dataclass
class StreamStats:
    """What the stream did: frames, their latency from capture to publication, time spent."""

    frames: int = 0
    video_frames: int = 0
    latency_s: list[float] = field(default_factory=list)  # per frame, capture to publication
    render_s: float = 0.0
    encode_s: float = 0.0  # JPEG and MP4
    first_at: float | None = None  # time.monotonic() of the first and the last publication
    last_at: float | None = None

    @property
    def fps(self) -> float | None:
        """Frames published per wall second, first to last (None before the second)."""
        if self.first_at is None or self.last_at is None or self.last_at <= self.first_at:
            return None
        return (self.frames - 1) / (self.last_at - self.first_at)

    def latency_ms(self, quantile: float) -> float | None:
        """A quantile of the latencies in ms (None before the first frame)."""
        if not self.latency_s:
            return None
        return round(float(np.quantile(self.latency_s, quantile)) * 1000, 1)


class FrameHub:
    """Subscribers and the latest frame; thread-safe."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._subscribers: list[Callable[[Frame], None]] = []
        self.latest: Frame | None = None

    def subscribe(self, callback: Callable[[Frame], None]) -> Callable[[], None]:
        """Call ``callback(frame)`` for every new frame; returns the unsubscribe function."""
        with self._lock:
            self._subscribers.append(callback)

        def unsubscribe() -> None:
            with self._lock:
                if callback in self._subscribers:
                    self._subscribers.remove(callback)

        return unsubscribe

    def publish(self, frame: Frame) -> None:
        """Make ``frame`` the latest and hand it to every subscriber."""
        with self._lock:
            self.latest = frame
            callbacks = tuple(self._subscribers)
        for callback in callbacks:
            callback(frame)


def draw_leg_numbers(frame: np.ndarray, labels: Iterable[tuple[float, float, int]]) -> None:
    """Each leg's number (from 1) in its own colour beside it, in place; ``labels`` holds
    (x, y, leg) with (x, y) the leg's pixel."""
    scale = frame.shape[0] / 480
    radius = max(4, round(8 * scale))
    for x, y, leg in labels:
        r, g, b, _ = LEG_COLORS[leg % len(LEG_COLORS)]
        colour = (round(r * 255), round(g * 255), round(b * 255))
        centre = (round(x), round(y))  # a badge on the leg itself
        cv2.circle(frame, centre, radius + 1, (20, 20, 20), -1, cv2.LINE_AA)
        cv2.circle(frame, centre, radius, colour, -1, cv2.LINE_AA)
        _label(
            frame,
            str(leg + 1),
            (centre[0] - round(4 * scale), centre[1] + round(5 * scale)),
            (255, 255, 255),
            scale,
        )


def _label(
    frame: np.ndarray, text: str, at: tuple[int, int], colour: tuple[int, int, int], scale: float
) -> None:
    """``text`` at ``at`` in ``colour`` with a dark outline (readable on any background)."""
    size = 0.5 * scale
    cv2.putText(
        frame,
        text,
        at,
        cv2.FONT_HERSHEY_SIMPLEX,
        size,
        (20, 20, 20),
        max(2, round(4 * scale)),
        cv2.LINE_AA,
    )
    cv2.putText(
        frame,
        text,
        at,
        cv2.FONT_HERSHEY_SIMPLEX,
        size,
        colour,
        max(1, round(1.5 * scale)),
        cv2.LINE_AA,
    )


class FrameStream(ClosesOnExit):
    """Renders, encodes, publishes and records frames of ``layout``'s scene (see module doc)."""

    def __init__(
        self,
        layout: SceneLayout,
        hub: FrameHub,
        width: int,
        height: int,
        *,
        video: Path | None,
        video_fps: int,
        eye_inset: bool = True,
        render_workers: int = 0,
        eye_worker: bool = False,
        reflections: bool = False,
        spots: Iterable[tuple[float, float]] = (),
        on_state: Callable[[FrameState], None] | None = None,
        legs: Callable[[], Iterable[tuple[float, float, int]]] | None = None,
        states: Path | None = None,
    ) -> None:
        self.hub, self.stats = hub, StreamStats()
        self.spots = tuple(spots)
        self.states: StateLog | None = None  # every frame's state, for robin-pil replay
        if states is not None:
            self.states = StateLog(
                states,
                {
                    "kind": "live",
                    "layout": layout_dict(layout),
                    "size": [width, height],
                    "fps": video_fps,
                    "camera": DEFAULT_CAMERA,
                    "shadows": False,
                    "reflections": reflections,
                    "eye_inset": eye_inset,
                    "overlay": False,
                    "spots": [list(map(float, xy)) for xy in self.spots],
                    "leg_numbers": legs is not None,
                },
            )
        self.on_state = on_state  # e.g. the picker follows the frames
        self.legs = legs  # (x, y, leg) of each leg once on_state has seen the frame's state
        self._waiting: deque[FrameState] = deque()  # frames still rendering
        self._eyes: deque[np.ndarray] = deque()  # eye views rendered in this process
        self._closed = False
        self.pool = RenderPool(
            layout,
            width,
            height,
            DEFAULT_CAMERA,
            False,
            workers=render_workers,
            reflections=reflections,
        )
        self.eye: EyeInset | None = None
        self.eye_pool: RenderPool | None = None  # the eye rendered in a worker process
        self.writer: Mp4Writer | None = None
        try:
            if eye_inset and eye_worker:
                self.eye_pool = RenderPool(
                    layout,
                    *inset_size(width, height),
                    EYE_CAMERA,
                    False,
                    workers=1,
                    reflections=reflections,
                )
            elif eye_inset:
                self.eye = EyeInset(layout, width, height, False, reflections)
            if video is not None:
                self.writer = Mp4Writer(video, width, height, video_fps)
        except BaseException:
            self.close()
            raise

    def capture(
        self, model: mujoco.MjModel, data: mujoco.MjData, copies: int = 1, *, inset: bool = True
    ) -> None:
        """Render the state now (``copies``: how many video frames it stands for; ``inset``
        False leaves the eye inset out of this frame: a busy machine)."""
        started = time.perf_counter()
        captured = time.monotonic()
        state = FrameState.capture(model, data)
        if self.states is not None:
            self.states.add(state, copies)
        self._waiting.append(state)
        inset = inset and (self.eye_pool is not None or self.eye is not None)
        if inset and self.eye_pool is not None:  # renders while this process renders the scene
            self.eye_pool.submit(state)
        elif inset and self.eye is not None:
            self._eyes.append(self.eye.render(state))
        self.pool.submit(state, (captured, copies, inset))
        self.stats.render_s += time.perf_counter() - started
        self._finish(self.pool.ready())

    def _finish(self, frames: Iterable[RenderedFrame]) -> None:
        for rendered in frames:
            started = time.perf_counter()
            captured, copies, inset = rendered.payload
            pixels = rendered.pixels
            state = self._waiting.popleft()  # frames come back in submission order
            eye = self._next_eye() if inset else None
            if eye is not None:
                draw_eye_inset(pixels, eye)
            if self.on_state is not None:
                self.on_state(state)
            draw_spots(pixels, self.spots, first=PAGE_FIRST_SPOT)
            if self.legs is not None:
                draw_leg_numbers(pixels, self.legs())
            ok, jpeg = cv2.imencode(
                ".jpg",
                cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR),
                [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY],
            )
            if not ok:  # pragma: no cover - OpenCV fails only on a bad image
                raise RuntimeError("JPEG encoding of a live frame failed")
            self.stats.frames += 1
            frame = Frame(self.stats.frames, jpeg.tobytes(), float(state.time), captured)
            self.hub.publish(frame)
            published = time.monotonic()
            self.stats.latency_s.append(published - captured)
            if self.stats.first_at is None:
                self.stats.first_at = published
            self.stats.last_at = published
            if self.writer is not None:
                for _ in range(copies):
                    self.writer.write(pixels)
                self.stats.video_frames += copies
            self.stats.encode_s += time.perf_counter() - started

    def _next_eye(self) -> np.ndarray | None:
        """The eye view of the oldest frame (waiting for the eye's worker if need be)."""
        if self.eye_pool is not None:
            return next(self.eye_pool.drain()).pixels
        return self._eyes.popleft() if self._eyes else None

    def close(self) -> None:
        """Publish the frames still rendering, finish the MP4 and free the renderers
        (idempotent). A video without frames gets one black frame, so that it plays."""
        if self._closed:
            return
        self._closed = True
        try:
            self._finish(self.pool.drain())
            if self.writer is not None and self.stats.video_frames == 0:
                self.writer.write(np.zeros((self.writer.height, self.writer.width, 3), np.uint8))
                self.stats.video_frames += 1
        finally:
            if self.eye is not None:
                self.eye.close()
            if self.eye_pool is not None:
                self.eye_pool.close()
            self.pool.close()
            if self.writer is not None:
                self.writer.close()
            if self.states is not None:
                self.states.save()
