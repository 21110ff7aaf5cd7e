"""The replay tests' rig: decoded frames compared within a stated tolerance, the replay of an
episode's folder checked against its video, and a small recorded run served on the page."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import av
import mujoco
import numpy as np

from robin_sim.live.server import bind
from robin_sim.model.scene import build_model
from robin_sim.render.state_log import STATES_NAME, StateLog, layout_dict, load_states
from robin_sim.render.worker import FrameState
from robin_sim.replay.serve import serve_replay

# Tolerance: both videos are H.264 (crf 23) of the frames; identical renders encode identically,
# so any difference comes from the render. Allowed: a mean of 0.5 levels, 8 levels at most in
# 99.9 % of the values (antialiased edges of a moved part would exceed both).
MEAN_LEVELS, PIXEL_LEVELS, PIXEL_SHARE = 0.5, 8, 0.999
COMPARED = 12  # frames compared
# The last frames of a stream are coded with fewer frames ahead of them (x264's veryfast
# rc-lookahead is 10), so a replay cut at --to ends with frames the full video coded otherwise:
# measured on the one-handover episode cut at 6.0 s, its last 7 of 91 frames differ (up to 3.9
# levels mean), and cut at 7.0 s the same frames match and its own last 6 differ.
ENCODER_TAIL = 10


def decoded_frames(path: Path, count: int) -> list[np.ndarray]:
    """The first ``count`` frames of an MP4, RGB as int16 (for differences)."""
    with av.open(str(path)) as container:
        frames = []
        for frame in container.decode(container.streams.video[0]):
            frames.append(frame.to_ndarray(format="rgb24").astype(np.int16))
            if len(frames) == count:
                break
    return frames


def frames_match(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two decoded frames are the same render, within the tolerance above."""
    difference = np.abs(a - b)
    return bool(
        difference.mean() <= MEAN_LEVELS and (difference <= PIXEL_LEVELS).mean() >= PIXEL_SHARE
    )


def check_episode_replay(out: Path, summary: dict, capsys: object, seconds: float = 6.0) -> None:
    """``robin-pil replay out --to seconds`` gives the frames of the episode's own video."""
    import json

    from robin_sim.cli.main import main

    assert sorted(p.name for p in out.iterdir()) == [
        "episode.jsonl",
        "episode.mp4",
        STATES_NAME,
        "summary.json",
    ]
    assert "states" not in json.dumps(summary)  # the summary is as before: no new field
    recorded = load_states(out / STATES_NAME)
    assert recorded.video_frames == summary["video"]["frames"]
    # compact: the articulated person adds 64 joint positions to every frame
    assert (out / STATES_NAME).stat().st_size < 60_000 + 700 * len(recorded.states)
    capsys.readouterr()  # type: ignore[attr-defined]
    assert main(["replay", str(out), "--to", str(seconds)]) == 0
    result = json.loads(capsys.readouterr().out)  # type: ignore[attr-defined]
    assert result["path"] == str(out / "replay.mp4")
    replayed = decoded_frames(out / "replay.mp4", 10_000)
    original = decoded_frames(out / "episode.mp4", len(replayed))
    assert len(replayed) == result["video_frames"] >= COMPARED + ENCODER_TAIL
    compared = len(replayed) - ENCODER_TAIL
    picked = range(0, compared, compared // COMPARED)
    assert not np.array_equal(original[0], original[picked[-1]])  # Robin moves meanwhile
    for k in picked:
        assert frames_match(original[k], replayed[k]), k
    # frames apart in time do not match: the comparison can fail
    assert not frames_match(original[picked[-1]], replayed[0])
    assert main(["replay", str(out)]) == 2  # replay.mp4 exists: never overwritten
    assert "exists already" in capsys.readouterr().err  # type: ignore[attr-defined]


META = {
    "kind": "episode",
    "layout": layout_dict(None),
    "size": [160, 120],
    "fps": 10,
    "camera": "front",
    "shadows": False,
    "reflections": False,
    "eye_inset": True,
    "overlay": False,
    "spots": [],
}


def recorded_run(folder: Path, frames: int = 6, spacing: float = 0.1) -> Path:
    """A states file of ``frames`` states of the scene, ``spacing`` s apart (0.1: every frame
    at 10 fps; more: a lowered stream's sparse states), the robot's first joint turning."""
    model = build_model()
    data = mujoco.MjData(model)
    log = StateLog(folder / STATES_NAME, META)
    for k in range(frames):
        data.time = spacing * k
        data.qpos[:] = model.qpos0
        data.qpos[model.jnt_qposadr[1]] += 0.25 * k  # a visible motion
        mujoco.mj_forward(model, data)
        log.add(FrameState.capture(model, data))
    path = log.save()
    assert path is not None
    return path


@contextmanager
def serving(path: Path, annotations: dict | None = None) -> Iterator[int]:
    """Serve ``path``'s replay page (with ``annotations``' steps and markers) on a free
    loopback port; the port."""
    recorded = load_states(path)
    sock = bind("127.0.0.1", 0)
    loop = asyncio.new_event_loop()
    stop = asyncio.Event()
    thread = threading.Thread(
        target=loop.run_until_complete,
        args=(serve_replay(recorded, sock, stop, annotations),),
        daemon=True,
    )
    thread.start()
    try:
        yield sock.getsockname()[1]
    finally:
        loop.call_soon_threadsafe(stop.set)
        thread.join(30)
        loop.close()
