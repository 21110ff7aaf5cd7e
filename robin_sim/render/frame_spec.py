"""A video's frame size and rate, and their checks: one source for every run that films.

H.264 in yuv420p halves the colour resolution, so both sides must be even. The episode
(:mod:`robin_sim.episode.config`), the live page (:mod:`robin_sim.live.config`) and the MP4
writer (:class:`robin_sim.render.video.Mp4Writer`) check with these; the live page narrows the
ranges (:func:`narrowed`). Nothing here imports MuJoCo or PyAV.
"""

from __future__ import annotations

from dataclasses import replace

from pil.errors import RobinPilError
from pil.task.params import ParamSpec

FPS = ParamSpec("fps", "int", 30, "video frame rate", 1, 240)
SIDE = ParamSpec("size", "int", 640, "video width or height in pixels", 2, 1_000_000)


def narrowed(spec: ParamSpec, high: int) -> ParamSpec:
    """``spec`` with at most ``high`` (e.g. the live stream's frame rate)."""
    return replace(spec, high=high)


def check_even(width: int, height: int, label: str = "video size") -> tuple[int, int]:
    """(width, height) if both are even, else an error suggesting the nearest even size."""
    if width % 2 or height % 2:
        raise RobinPilError(
            f"{label} must be even in both dimensions for H.264 yuv420p, got {width}x{height}; "
            f"use e.g. {width + width % 2}x{height + height % 2}"
        )
    return width, height


def check_size(
    width: object, height: object, what: str = "video", side: ParamSpec = SIDE
) -> tuple[int, int]:
    """Both sides parsed by ``side`` (named "WHAT width" / "WHAT height"), then even."""
    w, h = (side.parse(v, f"{what} {n}") for v, n in ((width, "width"), (height, "height")))
    return check_even(w, h, f"{what} size")
