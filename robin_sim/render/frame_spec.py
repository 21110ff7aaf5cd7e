"""A video's frame size and rate, and their checks: one source for every run that films.

H.264 in yuv420p halves the colour resolution, so both sides must be even, and a frame must fit
the scene's off-screen buffer (:func:`robin_sim.model.scene_file.offscreen_buffer`). The episode
(:mod:`robin_sim.episode.config`), the live page (:mod:`robin_sim.live.config`) and a replay's
recorded settings (:mod:`robin_sim.render.state_checks`) check with these, once, at their edge;
the live page narrows the ranges (:func:`narrowed`). Below the edges nothing checks a size again
(the renderers and the MP4 writer take what they are given). Nothing here imports MuJoCo or PyAV.
"""

from __future__ import annotations

from dataclasses import replace

from pil.errors import RobinPilError
from pil.task.params import ParamSpec
from robin_sim.model.scene_file import offscreen_buffer

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


def check_fits(width: int, height: int, buffer: tuple[int, int], what: str = "frame") -> None:
    """Refuse a ``width`` x ``height`` frame larger than the off-screen ``buffer``."""
    buffer_w, buffer_h = buffer
    if width > buffer_w or height > buffer_h:
        raise RobinPilError(
            f"{what} {width}x{height} is larger than the model's off-screen buffer "
            f"{buffer_w}x{buffer_h}; render at most {buffer_w}x{buffer_h} or raise "
            '<visual><global offwidth="..." offheight="..."/></visual> in the scene'
        )


def check_size(
    width: object,
    height: object,
    what: str = "video",
    side: ParamSpec = SIDE,
    size_label: str | None = None,
) -> tuple[int, int]:
    """Both sides parsed by ``side`` (named "WHAT width" / "WHAT height"), even, and within
    the scene's off-screen buffer (the pair named ``size_label``, default "WHAT size")."""
    w, h = (side.parse(v, f"{what} {n}") for v, n in ((width, "width"), (height, "height")))
    label = f"{what} size" if size_label is None else size_label
    check_even(w, h, label)
    check_fits(w, h, offscreen_buffer(), label)
    return w, h
