"""Replay a recorded run in MuJoCo's interactive viewer (needs a display)."""

from __future__ import annotations

import os
import time

from robin_sim.render.state_log import RecordedStates
from robin_sim.replay.folder import ReplayError

DISPLAY_VARIABLES = ("DISPLAY", "WAYLAND_DISPLAY")


def check_display() -> None:
    """:class:`ReplayError` when no display is there for the viewer's window."""
    if not any(os.environ.get(name) for name in DISPLAY_VARIABLES):
        raise ReplayError(
            "--viewer needs a display (neither DISPLAY nor WAYLAND_DISPLAY is "
            "set); without one, render the replay to an MP4: robin-pil replay "
            "DIR [--out FILE.mp4]"
        )


def replay_in_viewer(recorded: RecordedStates, speed: float = 1.0) -> int:
    """Show the recorded states in the passive viewer at ``speed`` x real time, until the last
    frame or the window closes; the frames shown."""
    check_display()
    import mujoco
    import mujoco.viewer

    from robin_sim.model.scene import build_model
    from robin_sim.render.worker import apply_state

    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    shown = 0
    with mujoco.viewer.launch_passive(model, data) as viewer:
        start_wall, start_sim = time.monotonic(), recorded.states[0].time
        for state in recorded.states:
            if not viewer.is_running():
                break
            with viewer.lock():
                apply_state(model, data, state)
            viewer.sync()
            shown += 1
            ahead = (state.time - start_sim) / speed - (time.monotonic() - start_wall)
            if ahead > 0:
                time.sleep(ahead)
    return shown
