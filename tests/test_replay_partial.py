"""An interrupted replay leaves its video under a partial name; the rerun completes it
(issue 39: it left a playable part under the final name and the rerun refused)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from replay_rig import decoded_frames, recorded_run

from robin_sim.replay.render import partial_path

STATES = 600  # 60 s of states at 10 fps: long enough to be stopped while it writes


@pytest.mark.parametrize("how", [signal.SIGINT, signal.SIGKILL])  # SIGTERM is taken as SIGINT
def test_an_interrupted_replay_leaves_no_final_file_and_reruns(
    tmp_path: Path, how: signal.Signals
) -> None:
    states = recorded_run(tmp_path, frames=STATES)
    out = tmp_path / "replay.mp4"
    command = [sys.executable, "-m", "robin_sim.cli.main", "replay", str(tmp_path)]
    partial = partial_path(out)
    child = subprocess.Popen(command, start_new_session=True, stderr=subprocess.PIPE)
    try:
        while not (partial.exists() and partial.stat().st_size > 0):  # its first fragment
            assert child.poll() is None, child.stderr.read() if child.stderr else ""
            time.sleep(0.05)
        os.killpg(child.pid, how)  # the whole group, as a terminal's Ctrl-C does
        child.wait(timeout=120)
    finally:
        if child.poll() is None:
            os.killpg(child.pid, signal.SIGKILL)
            child.wait()
    assert not out.exists()  # no file under the final name
    assert partial.exists()
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert out.exists() and not partial.exists()
    assert len(decoded_frames(out, STATES + 1)) == STATES
    assert states.exists()
