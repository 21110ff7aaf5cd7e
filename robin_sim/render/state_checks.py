"""Reading a ``states.npz`` that may be damaged: every bound checked before it costs anything.

:func:`read_state_arrays` opens the file as :func:`pil.regular_files.open_regular` does (a link
to ``/dev/zero``, a FIFO: refused), reads each zip member's ``.npy`` header before its data (a
member's shape, hence its memory, is bounded: at most :data:`MAX_FRAMES` frames of at most
:data:`MAX_WIDTH` values, texts of at most :data:`MAX_TEXT_BYTES`), loads with
``allow_pickle=False``, then checks what the replay relies on: every per-frame array as long as
``time``, finite values of sane magnitude, time never going back, ``copies`` bounded, indices in
range, and ``meta`` and the overlays strict JSON (:func:`pil.regular_files.parse_json`).
:func:`check_against_model` checks the widths against the scene the layout builds. Every
problem raises :class:`StatesError` naming the file and what is wrong.
"""

from __future__ import annotations

import math
import os
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from pil.errors import RobinPilError, quote
from pil.regular_files import LIMITS, open_regular, parse_json

MAX_FRAMES = 1_000_000  # rendered states: over 9 hours at 30 fps
MAX_WIDTH = 10_000  # values per frame in a row (the scene has about 70 joints, 150 geoms)
MAX_COPIES = 100_000  # video frames one state stands for (nearly an hour at 30 fps)
MAX_VIDEO_FRAMES = 10_000_000  # video frames in all (over 90 hours at 30 fps)
MAX_TEXT_BYTES = 200_000_000  # meta and the overlays' table, as text
MAX_ARRAY_BYTES = 2_000_000_000  # all arrays together, as loaded
MAX_VALUE = 1e6  # no time, position, quaternion, colour or size comes near (m, s, rad)
# name -> (dimensions, kind of numbers: f float, i whole, U text)
ARRAYS: dict[str, tuple[int, str]] = {
    "time": (1, "f"),
    "qpos": (2, "f"),
    "mocap_pos": (3, "f"),
    "mocap_quat": (3, "f"),
    "copies": (1, "i"),
    "overlay_index": (1, "i"),
    "overlays": (0, "U"),
    "geom_frames": (1, "i"),
    "meta": (0, "U"),
    "geom_rgba": (3, "f"),
    "geom_pos": (3, "f"),
    "geom_quat": (3, "f"),
    "geom_size": (3, "f"),
}
KIND_NAMES = {"f": "floating-point numbers", "i": "whole numbers", "U": "a text"}
PER_FRAME = ("time", "qpos", "mocap_pos", "mocap_quat", "copies", "overlay_index")
PER_CHANGE = ("geom_frames", "geom_rgba", "geom_pos", "geom_quat", "geom_size")
# the last axis of the pose and geom arrays (0: the run kept no geom shapes)
LAST_AXIS: dict[str, tuple[int, ...]] = {
    "mocap_pos": (3,),
    "mocap_quat": (4,),
    "geom_rgba": (4,),
    "geom_pos": (3, 0),
    "geom_quat": (4, 0),
    "geom_size": (3, 0),
}


class StatesError(RobinPilError):
    """A states file that is missing, unreadable or of another format."""


def _header(member: Any) -> tuple[tuple[int, ...], np.dtype[Any]]:
    version = np.lib.format.read_magic(member)
    if version == (1, 0):
        shape, _fortran, dtype = np.lib.format.read_array_header_1_0(member)
    elif version == (2, 0):
        shape, _fortran, dtype = np.lib.format.read_array_header_2_0(member)
    else:
        raise ValueError(f"npy format version {version}, not 1.0 or 2.0")
    return tuple(shape), dtype


def _check_header(name: str, shape: tuple[int, ...], dtype: np.dtype[Any]) -> str | None:
    """What is wrong with a member's shape and type, before its data are read (None: fine)."""
    dims, kind = ARRAYS[name]
    if len(shape) != dims:
        return f"{name} has {len(shape)} dimensions, expected {dims}"
    if dtype.hasobject or dtype.kind not in ("iu" if kind == "i" else kind):
        return f"{name} holds {dtype}, expected {KIND_NAMES[kind]}"
    if kind == "U" and dtype.itemsize > MAX_TEXT_BYTES:
        return f"{name} is a text of {dtype.itemsize:,} bytes, more than {MAX_TEXT_BYTES:,}"
    if shape and shape[0] > MAX_FRAMES:
        return f"{name} has {shape[0]:,} rows, more than {MAX_FRAMES:,} (the most a run records)"
    if any(side > MAX_WIDTH for side in shape[1:]):
        return f"{name} has shape {shape}, wider than {MAX_WIDTH:,}"
    return None


def read_state_arrays(path: Path) -> tuple[dict[str, np.ndarray], dict[str, Any], list[Any]]:
    """The checked arrays, ``meta`` and overlays of ``path``; :class:`StatesError` if damaged."""
    try:
        with open_regular(path) as handle:
            if os.fstat(handle.fileno()).st_size > LIMITS["states"]:
                raise ValueError(f"larger than {LIMITS['states']:,} bytes")
            with zipfile.ZipFile(handle) as archive:
                names = {i.filename.removesuffix(".npy"): i for i in archive.infolist()}
                missing = [n for n in ARRAYS if n not in names]
                if missing:
                    raise ValueError(f"no {missing[0]!r} array")
                total = 0
                for name in ARRAYS:
                    with archive.open(names[name]) as member:
                        shape, dtype = _header(member)
                        problem = _check_header(name, shape, dtype)
                        data_bytes = math.prod(shape) * dtype.itemsize
                        if not problem and names[name].file_size != member.tell() + data_bytes:
                            problem = f"{name}'s size in the zip does not match its header"
                    if problem:
                        raise StatesError(f"{path}: {problem}")
                    total += data_bytes
                if total > MAX_ARRAY_BYTES:  # checked before a byte of data is read
                    raise StatesError(
                        f"{path}: its arrays would take {total:,} bytes, more than "
                        f"{MAX_ARRAY_BYTES:,} (a run of 9 hours takes far less)"
                    )
            handle.seek(0)
            with np.load(handle, allow_pickle=False) as data:
                arrays = {name: data[name] for name in ARRAYS}
    except StatesError:
        raise
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as problem:
        reason = problem.strerror if isinstance(problem, OSError) and problem.strerror else problem
        raise StatesError(f"{path}: not a readable states file ({reason})") from None
    meta = _json(path, "meta", arrays["meta"])
    overlays = _json(path, "overlays", arrays["overlays"])
    if not isinstance(meta, dict) or not isinstance(overlays, list):
        raise StatesError(f"{path}: meta must be a JSON object and overlays a JSON list")
    overlays = [_json(path, "an overlay", text) for text in overlays]
    check_arrays(path, arrays, overlays)
    check_meta(path, meta)
    return arrays, meta, overlays


def _json(path: Path, what: str, text: Any) -> Any:
    if not isinstance(text, str | np.ndarray) or (
        isinstance(text, str) and len(text) > MAX_TEXT_BYTES
    ):
        raise StatesError(f"{path}: {what} is not a JSON text")
    try:
        return parse_json(str(text), finite=True)
    except ValueError as error:
        raise StatesError(f"{path}: {what} is damaged: {error}") from None


def check_arrays(path: Path, arrays: Mapping[str, np.ndarray], overlays: list[Any]) -> None:
    """Lengths, values, order and indices (see the module doc)."""
    frames = len(arrays["time"])
    if frames == 0:
        raise StatesError(f"{path}: no recorded frame")
    for group in (PER_FRAME, PER_CHANGE):
        rows = {name: arrays[name].shape[0] for name in group}
        if len(set(rows.values())) > 1:
            listed = ", ".join(f"{n} {r}" for n, r in rows.items())
            raise StatesError(f"{path}: the arrays' lengths do not match ({listed})")
    for name, allowed in LAST_AXIS.items():
        if arrays[name].shape[-1] not in allowed:
            raise StatesError(f"{path}: {name} has shape {arrays[name].shape}")
    if arrays["mocap_pos"].shape[1] != arrays["mocap_quat"].shape[1]:
        raise StatesError(f"{path}: mocap_pos and mocap_quat hold different bodies")
    geoms = {arrays[name].shape[1] for name in PER_CHANGE[1:]}
    if len(geoms) > 1:
        raise StatesError(f"{path}: the geom arrays hold different numbers of geoms")
    for name, (_dims, kind) in ARRAYS.items():
        values = arrays[name]
        if kind == "f" and values.size and not _sane(values):
            worst = values[~np.isfinite(values) | (np.abs(np.nan_to_num(values)) > MAX_VALUE)]
            raise StatesError(
                f"{path}: {name} holds {quote(float(worst.flat[0]))}; every value must be finite "
                f"and at most {MAX_VALUE:g} in size"
            )
    if np.any(np.diff(arrays["time"]) < 0):
        back = int(np.argmax(np.diff(arrays["time"]) < 0)) + 1
        raise StatesError(f"{path}: time goes back at frame {back}; a run's time only increases")
    copies = arrays["copies"]
    if copies.min() < 0 or copies.max() > MAX_COPIES:
        raise StatesError(
            f"{path}: copies must be 0 to {MAX_COPIES:,} video frames a state, got "
            f"{int(copies.min() if copies.min() < 0 else copies.max()):,}"
        )
    if int(copies.sum(dtype=np.int64)) > MAX_VIDEO_FRAMES:
        raise StatesError(f"{path}: more than {MAX_VIDEO_FRAMES:,} video frames in all")
    index = arrays["overlay_index"]
    if index.min() < 0 or index.max() >= len(overlays):
        raise StatesError(f"{path}: overlay_index points past the {len(overlays)} overlays")
    if any(o is not None and not isinstance(o, dict) for o in overlays):
        raise StatesError(f"{path}: an overlay is neither null nor a JSON object")
    changes = arrays["geom_frames"]
    starts = len(changes) and changes[0] == 0
    if not starts or np.any(np.diff(changes) <= 0) or changes[-1] >= frames:
        raise StatesError(f"{path}: geom_frames must rise from 0 and stay below {frames}")


def _sane(values: np.ndarray) -> bool:
    return bool(np.all(np.isfinite(values)) and np.all(np.abs(values) <= MAX_VALUE))


def check_meta(path: Path, meta: Mapping[str, Any]) -> None:
    """The render settings the replay uses: present and of their types."""
    from robin_sim.render.frame_spec import FPS, check_size

    try:
        size = meta["size"]
        if not isinstance(size, list) or len(size) != 2:
            raise RobinPilError(f"size must be [width, height], got {quote(size)}")
        check_size(*size)
        FPS.parse(meta["fps"], "fps")
        for key in ("shadows", "reflections", "eye_inset", "overlay"):
            if not isinstance(meta[key], bool):
                raise RobinPilError(f"{key} must be true or false, got {quote(meta[key])}")
        if not isinstance(meta["camera"], str) or not isinstance(meta["layout"], dict):
            raise RobinPilError("camera must be a name and layout a JSON object")
        spots = meta["spots"]
        if not isinstance(spots, list) or not all(_pair(xy) for xy in spots):
            raise RobinPilError("spots must be a list of [x, y] numbers")
    except KeyError as error:
        raise StatesError(f"{path}: meta has no {error.args[0]!r}") from None
    except RobinPilError as error:
        raise StatesError(f"{path}: meta: {error}") from None


def _pair(xy: Any) -> bool:
    return isinstance(xy, list) and len(xy) == 2 and all(_finite(v) for v in xy)


def _finite(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def check_against_model(path: Path, arrays: Mapping[str, np.ndarray], layout: Any) -> None:
    """The widths of ``qpos``, the mocap and geom arrays against the scene ``layout`` builds."""
    from robin_sim.model.scene import build_model

    model = build_model(layout)
    widths = {
        "qpos": (arrays["qpos"].shape[1], model.nq + model.nuserdata, "joint positions"),
        "mocap_pos": (arrays["mocap_pos"].shape[1], model.nmocap, "mocap bodies"),
        "geom_rgba": (arrays["geom_rgba"].shape[1], model.ngeom, "geoms"),
    }
    for name, (have, want, what) in widths.items():
        if have != want:
            raise StatesError(
                f"{path}: {name} has {have} {what} a frame; the run's scene has {want}"
            )
