"""A small recorded run for the replay page's tests: real scene states, a few frames, served."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import mujoco

from robin_sim.live.server import bind
from robin_sim.model.scene import build_model
from robin_sim.render.state_log import STATES_NAME, StateLog, layout_dict, load_states
from robin_sim.render.worker import FrameState
from robin_sim.replay.serve import serve_replay

META = {"kind": "episode", "layout": layout_dict(None), "size": [160, 120], "fps": 10,
        "camera": "front", "shadows": False, "reflections": False, "eye_inset": True,
        "overlay": False, "spots": []}  # fmt: skip


def recorded_run(folder: Path, frames: int = 6) -> Path:
    """A states file of ``frames`` states of the scene, the robot's first joint turning."""
    model = build_model()
    data = mujoco.MjData(model)
    log = StateLog(folder / STATES_NAME, META)
    for k in range(frames):
        data.time = 0.1 * k
        data.qpos[:] = model.qpos0
        data.qpos[model.jnt_qposadr[1]] += 0.25 * k  # a visible motion
        mujoco.mj_forward(model, data)
        log.add(FrameState.capture(model, data))
    path = log.save()
    assert path is not None
    return path


@contextmanager
def serving(path: Path) -> Iterator[int]:
    """Serve ``path``'s replay page on a free loopback port; the port."""
    recorded = load_states(path)
    sock = bind("127.0.0.1", 0)
    loop = asyncio.new_event_loop()
    stop = asyncio.Event()
    thread = threading.Thread(target=loop.run_until_complete,
                              args=(serve_replay(recorded, sock, stop),), daemon=True)
    thread.start()
    try:
        yield sock.getsockname()[1]
    finally:
        loop.call_soon_threadsafe(stop.set)
        thread.join(30)
        loop.close()
