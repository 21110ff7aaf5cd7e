"""Facts read from the scene's MJCF file itself (``models/scene.xml``, with the files it
``<include>``s), without compiling it.

The one reader of figures the file states that code elsewhere needs before (or without) a
model: the off-screen buffer a frame must fit, and where a named site sits in its body. Each
is read once per process (the file ships with the package and does not change under it).
"""

from __future__ import annotations

import functools
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np

from pil.errors import RobinPilError
from robin_sim.model.names import SCENE_XML


@functools.cache
def _scene() -> ElementTree.Element:
    """The scene file's root element (``<mujoco>``)."""
    return ElementTree.parse(SCENE_XML).getroot()


@functools.cache
def _files() -> tuple[ElementTree.Element, ...]:
    """The scene file's root and those of the files it includes (their includes too), in order."""
    roots, pending = [], [Path(SCENE_XML)]
    while pending:
        path = pending.pop(0)
        root = ElementTree.parse(path).getroot()
        roots.append(root)
        pending += [path.parent / i.get("file", "") for i in root.iter("include")]
    return tuple(roots)


def offscreen_buffer() -> tuple[int, int]:
    """The scene's off-screen buffer (width, height): its ``<visual><global offwidth
    offheight>``, the largest frame any of its cameras renders."""
    found = _scene().find("visual/global")
    if found is None:
        raise RobinPilError(f"{SCENE_XML}: no <visual><global> element")
    return int(found.get("offwidth", "640")), int(found.get("offheight", "480"))


def site_offset(name: str) -> np.ndarray:
    """Where site ``name`` sits in its body's frame (its ``pos``), m."""
    sites = (root.find(f".//site[@name='{name}']") for root in _files())
    found = next((site for site in sites if site is not None), None)
    if found is None:
        raise RobinPilError(f"{SCENE_XML}: no site named {name!r}")
    return np.array([float(v) for v in found.get("pos", "0 0 0").split()])


__all__ = ["offscreen_buffer", "site_offset"]
