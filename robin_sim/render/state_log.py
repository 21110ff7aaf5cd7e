"""The states behind a run's video frames, kept compactly so that the run can be replayed.

A :class:`StateLog` takes, for every frame a video records, the
:class:`~robin_sim.render.worker.FrameState` it was rendered from, how many video frames it
stands for, and what was drawn over it (the episode's overlay info, the eye inset's label). On
:meth:`StateLog.save` it writes ``states.npz`` (``numpy.savez_compressed``) beside the run's
log: per frame the time, ``qpos`` (the person's joints after the scene's) and mocap poses; the
geom colours and shapes only where they changed (the gesture display and the hand poses change
them now and then); the overlays as a table of distinct JSON texts with an index per frame; and
a JSON ``meta`` block with the scene layout and the render settings. :func:`load_states` reads
it back. About 1 KB per frame before compression; no physics is touched.
"""

from __future__ import annotations

import json
import os
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pil.errors import naming
from robin_sim.model.scene import SceneLayout
from robin_sim.render.state_checks import StatesError, check_against_model, read_state_arrays
from robin_sim.render.worker import FrameState

__all__ = ["STATES_NAME", "RecordedStates", "StateLog", "StatesError", "load_states"]

STATES_NAME = "states.npz"
# bumped when the file's layout changes (2: the person's joints from userdata; 3: the chest's own
# lean joint, 64 of them; 4: the idle hand baked, 44)
FORMAT = 4
_GEOM = ("geom_rgba", "geom_pos", "geom_quat", "geom_size")


def layout_dict(layout: SceneLayout | None) -> dict[str, Any]:
    """``layout`` (None: the default) as JSON-ready lists."""
    return asdict(layout or SceneLayout())


@dataclass(frozen=True)
class RecordedStates:
    """A loaded states file: the frames' states, their copies and overlays, and ``meta``."""

    states: tuple[FrameState, ...]
    copies: np.ndarray  # video frames each state stands for
    overlays: tuple[dict[str, Any] | None, ...]  # what was drawn over each frame
    meta: dict[str, Any]

    @property
    def layout(self) -> SceneLayout:
        raw = self.meta["layout"]
        return SceneLayout(
            tuple(map(tuple, raw["legs"])),
            tuple(map(tuple, raw["spots"])),
            tuple(raw["handover"]),
            tuple(raw["bin"]),
        )

    @property
    def video_frames(self) -> int:
        return int(self.copies.sum())

    @property
    def duration(self) -> float:
        """Simulated seconds from the first frame to the last."""
        return self.states[-1].time - self.states[0].time if self.states else 0.0

    def between(self, start: float, end: float | None = None) -> RecordedStates:
        """The frames from ``start`` to ``end`` simulated seconds after the first (None: the
        last); :class:`StatesError` when none lies there."""
        t0 = self.states[0].time
        keep = [
            i
            for i, s in enumerate(self.states)
            if start <= s.time - t0 and (end is None or s.time - t0 <= end)
        ]
        if not keep:
            raise StatesError(
                f"no recorded frame lies between {start:g} s and "
                f"{'the end' if end is None else f'{end:g} s'}; the run's frames "
                f"span 0 to {self.duration:.2f} s"
            )
        return RecordedStates(
            tuple(self.states[i] for i in keep),
            self.copies[keep],
            tuple(self.overlays[i] for i in keep),
            self.meta,
        )


class StateLog:
    """Collects frame states as a recorder renders them; :meth:`save` writes them."""

    def __init__(self, path: Path, meta: dict[str, Any]) -> None:
        self.path, self.meta = Path(path), dict(meta)
        self._times: list[float] = []
        self._qpos: list[np.ndarray] = []
        self._mocap_pos: list[np.ndarray] = []
        self._mocap_quat: list[np.ndarray] = []
        self._copies: list[int] = []
        self._overlay_index: list[int] = []
        self._overlays: dict[str, int] = {}
        self._geom_frames: list[int] = []
        self._geom: dict[str, list[np.ndarray]] = {name: [] for name in _GEOM}
        self._saved = False

    def __len__(self) -> int:
        return len(self._times)

    def add(
        self, state: FrameState, copies: int = 1, overlay: dict[str, Any] | None = None
    ) -> None:
        """One rendered frame: its state, the video frames it stands for, what was drawn on it."""
        index = len(self._times)
        self._times.append(state.time)
        self._qpos.append(state.qpos.copy())
        self._mocap_pos.append(state.mocap_pos.copy())
        self._mocap_quat.append(state.mocap_quat.copy())
        self._copies.append(int(copies))
        text = json.dumps(overlay, sort_keys=True, default=str)
        self._overlay_index.append(self._overlays.setdefault(text, len(self._overlays)))
        geom = {name: getattr(state, name) for name in _GEOM}
        last = {name: values[-1] for name, values in self._geom.items() if values}
        changed = not last or any(
            (geom[n] is None) != (last[n] is None)
            or (geom[n] is not None and not np.array_equal(geom[n], last[n]))
            for n in _GEOM
        )
        if changed:
            if any(geom[n] is None for n in _GEOM[1:]):
                geom = {**geom, **{n: state.geom_rgba[:, :0] for n in _GEOM[1:]}}
            self._geom_frames.append(index)
            for name in _GEOM:
                self._geom[name].append(np.array(geom[name], copy=True))

    def save(self) -> Path | None:
        """Write the file (atomically; idempotent); None when no frame was recorded."""
        if self._saved or not self._times:
            return None
        self._saved = True
        arrays: dict[str, Any] = {
            "time": np.asarray(self._times, np.float64),
            "qpos": np.stack(self._qpos),
            "mocap_pos": np.stack(self._mocap_pos),
            "mocap_quat": np.stack(self._mocap_quat),
            "copies": np.asarray(self._copies, np.int32),
            "overlay_index": np.asarray(self._overlay_index, np.int32),
            "overlays": np.asarray(json.dumps(list(self._overlays))),
            "geom_frames": np.asarray(self._geom_frames, np.int32),
            "meta": np.asarray(json.dumps({"format": FORMAT, **self.meta})),
        }
        for name, values in self._geom.items():
            arrays[name] = np.stack(values)
        handle, temp = tempfile.mkstemp(dir=self.path.parent, prefix=".states-", suffix=".npz")
        try:
            with os.fdopen(handle, "wb") as file:
                np.savez_compressed(file, **arrays)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temp, 0o666 & ~umask)  # as the run's other files (mkstemp makes 0600)
            os.replace(temp, self.path)
        except OSError as error:  # a full disk: name the file (a write to a handle names none)
            Path(temp).unlink(missing_ok=True)
            raise naming(error, self.path)  # noqa: B904 (the cause is chained all the same)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise
        return self.path


def load_states(path: Path) -> RecordedStates:
    """Read a states file written by :class:`StateLog`; :class:`StatesError` if it cannot,
    or if it is damaged (:mod:`robin_sim.render.state_checks`: nothing is rendered from it)."""
    arrays, meta, overlays = read_state_arrays(path)
    if meta.get("format") != FORMAT:
        raise StatesError(
            f"{path}: states format {meta.get('format')!r}; this version reads format {FORMAT}"
        )
    geom_frames = list(arrays["geom_frames"])
    states, which = [], -1
    for i, time in enumerate(arrays["time"]):
        while which + 1 < len(geom_frames) and geom_frames[which + 1] <= i:
            which += 1
        shapes = [arrays[name][which] for name in _GEOM[1:]]
        has_shapes = shapes[0].shape[-1] != 0
        states.append(
            FrameState(
                float(time),
                arrays["qpos"][i],
                arrays["mocap_pos"][i],
                arrays["mocap_quat"][i],
                arrays["geom_rgba"][which],
                *(shapes if has_shapes else (None, None, None)),
            )
        )
    index = arrays["overlay_index"]
    recorded = RecordedStates(
        tuple(states), arrays["copies"], tuple(overlays[k] for k in index), meta
    )
    try:
        layout = recorded.layout
    except (KeyError, TypeError, ValueError) as problem:
        raise StatesError(f"{path}: meta: not a scene layout ({problem})") from None
    check_against_model(path, arrays, layout)
    return recorded
