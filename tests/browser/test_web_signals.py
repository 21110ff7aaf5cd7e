"""``robin-pil live`` as a real process: Ctrl-C (SIGINT) or SIGTERM while a participant is
connected saves the session (a playable MP4, the log, a summary marked interrupted) and the
process exits with 130."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import aiohttp
import av
import pytest
from page_driver import run_async

pytestmark = pytest.mark.slow


async def connect_then_signal(url: str, pid: int, signum: int, frames: int = 20) -> int:
    """Connect as the participant, take ``frames`` frames, send ``signum`` to the server with
    the socket still open, and read on until the server closes it; the frames received."""
    seen = 0
    async with aiohttp.ClientSession() as http, http.ws_connect(url) as ws:
        while seen < frames:
            message = await ws.receive(timeout=60)
            assert message.type in (aiohttp.WSMsgType.TEXT, aiohttp.WSMsgType.BINARY), message
            seen += message.type == aiohttp.WSMsgType.BINARY
        os.kill(pid, signum)
        while True:
            message = await ws.receive(timeout=60)
            if message.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED):
                return seen
            seen += message.type == aiohttp.WSMsgType.BINARY


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_signal_saves_the_session(signum: signal.Signals, tmp_path: Path) -> None:
    out = tmp_path / "live"
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            "live",
            "--no-browser",
            "--port",
            "0",
            "--scenario",
            "one_handover",
            "--participant",
            "P07",
            "--out",
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        line = process.stdout.readline()
        match = re.search(r"serving (http://127\.0\.0\.1:\d+/)", line)
        assert match, (line, process.stderr.read() if process.poll() is not None else "")
        url = match.group(1).replace("http://", "ws://") + "ws"

        assert run_async(connect_then_signal(url, process.pid, signum)) >= 20
        stdout, stderr = process.communicate(timeout=90)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 130, (stdout, stderr)
    folders = list((out / "P07").iterdir())
    assert len(folders) == 1
    folder = folders[0]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert summary["live"]["participant"] == "P07"
    assert (folder / "log.jsonl").exists() and (folder / "inputs.jsonl").exists()
    with av.open(str(folder / "episode.mp4")) as video:
        decoded = sum(1 for _ in video.decode(video=0))
    assert decoded >= 1, "the MP4 has no playable frame"
    assert "interrupted" in stderr
