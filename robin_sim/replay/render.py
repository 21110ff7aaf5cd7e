"""Re-render a recorded run's frames from its states and write them to an MP4.

Each state of ``states.npz`` is rendered with the run's own settings (camera, size, shadows,
reflections), and gets what the run drew on it: the episode's overlay and eye inset, or the live
stream's eye inset and spot rings. Frames come out pixel-identical to the run's (the renderers
are deterministic after their warm-up), so the MP4 matches the original up to H.264 encoding.
One exception: frames where the vision detector's inset showed a reading get the live eye view.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robin_sim.render.inset import INSET_LABEL, EyeInset, draw_eye_inset
from robin_sim.render.overlay import OverlayInfo, draw_overlay
from robin_sim.render.pool import RenderPool
from robin_sim.render.state_log import RecordedStates
from robin_sim.render.video import Mp4Writer


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
        return {"path": str(self.path), "frames_rendered": self.frames_rendered,
                "video_frames": self.video_frames, "fps": self.fps, "size": list(self.size),
                "wall_s": round(self.wall_s, 3), "approximate": self.approximate}  # fmt: skip


def replayed_frames(recorded: RecordedStates, workers: int = 0) -> Iterator[tuple[np.ndarray, int]]:
    """Each recorded frame re-rendered and drawn on as the run drew it, with its copies."""
    from robin_sim.live.frames import draw_spots

    meta = recorded.meta
    width, height = meta["size"]
    layout = recorded.layout
    shadows, reflections = bool(meta["shadows"]), bool(meta["reflections"])
    eye = EyeInset(layout, width, height, shadows, reflections) if meta["eye_inset"] else None
    spots = [tuple(xy) for xy in meta["spots"]]
    try:
        with RenderPool(layout, width, height, meta["camera"], shadows, workers=workers,
                        reflections=reflections) as pool:  # fmt: skip
            eyes: list[np.ndarray] = []

            def finish(frames: Iterator) -> Iterator[tuple[np.ndarray, int]]:
                for frame in frames:
                    overlay, copies = frame.payload
                    pixels = frame.pixels
                    if meta["overlay"] and overlay is not None:
                        info = OverlayInfo(**{**overlay["info"], "sim_time": frame.time})
                        draw_overlay(pixels, info)
                    if eye is not None:
                        draw_eye_inset(pixels, eyes.pop(0), INSET_LABEL)
                    if spots:
                        draw_spots(pixels, spots)
                    yield pixels, copies

            for state, copies, overlay in zip(recorded.states, recorded.copies,
                                              recorded.overlays, strict=True):  # fmt: skip
                if eye is not None:
                    eyes.append(eye.render(state))
                pool.submit(state, (overlay, int(copies)))
                yield from finish(pool.ready())
            yield from finish(pool.drain())
    finally:
        if eye is not None:
            eye.close()


def replay_to_mp4(recorded: RecordedStates, out: Path, workers: int = 0) -> ReplayResult:
    """Write ``recorded``'s frames, re-rendered, to the MP4 ``out``."""
    started = time.perf_counter()
    meta = recorded.meta
    width, height = meta["size"]
    rendered = written = 0
    with Mp4Writer(out, width, height, int(meta["fps"])) as writer:
        for pixels, copies in replayed_frames(recorded, workers):
            for _ in range(copies):
                writer.write(pixels)
            rendered += 1
            written += copies
    approximate = sum(1 for o in recorded.overlays if o and o.get("eye") not in (None, INSET_LABEL))
    return ReplayResult(out, rendered, written, int(meta["fps"]), (width, height),
                        time.perf_counter() - started, approximate)  # fmt: skip
