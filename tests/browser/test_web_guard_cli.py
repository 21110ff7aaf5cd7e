"""``robin-pil live`` as a real process under attack or misuse: 256 file descriptors and 500
half-open requests, Ctrl-C with frozen tabs, a read-only ``--out``, a protocol placeholder with a
format, and the restart after a kill -9 (its advice names an option that works)."""

from __future__ import annotations

import json
import os
import re
import resource
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from raw_http import get, text_frame, websocket

pytestmark = pytest.mark.slow  # real processes with MuJoCo (a few seconds each to start)

COMMAND = [sys.executable, "-m", "robin_sim.cli.main", "live", "--no-browser", "--port", "0"]
FEW_FDS = 256  # the descriptor limit the issue measured with


def launch(
    argv: list[str], preexec: Callable[[], None] | None = None, prefix: tuple[str, ...] = ()
) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [*prefix, *COMMAND, *argv],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=preexec,
    )


def serving_port(process: subprocess.Popen[str]) -> int:
    assert process.stdout is not None
    line = process.stdout.readline()
    match = re.search(r"serving http://127\.0\.0\.1:(\d+)/", line)
    if match is None:
        process.kill()
        raise AssertionError(f"not serving: {line!r} {process.communicate(timeout=30)}")
    return int(match.group(1))


def stopped(process: subprocess.Popen[str], timeout: float = 60) -> tuple[int, str, str]:
    try:
        out, err = process.communicate(timeout=timeout)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    return process.returncode, out, err


def few_descriptors() -> None:
    resource.setrlimit(resource.RLIMIT_NOFILE, (FEW_FDS, FEW_FDS))


def test_few_descriptors_500_half_open_requests_and_ctrl_c_with_frozen_tabs(tmp_path) -> None:
    out = tmp_path / "live"
    process = launch(
        [
            "--scenario",
            "one_handover",
            "--speed",
            "3",
            "--no-video",
            "--out",
            str(out),
            "--participant",
            "P05",
        ],
        few_descriptors,
    )
    frozen: list[socket.socket] = []
    try:
        port = serving_port(process)
        for _ in range(500):  # half-open: headers never finished
            sock = socket.create_connection(("127.0.0.1", port), timeout=10)
            sock.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Wait: ".encode())
            frozen.append(sock)
        started = time.monotonic()
        status, _, body = get(port, "/")
        assert status == 200 and b"<canvas" in body and time.monotonic() - started < 5
        control = websocket(port, receive_buffer=4096)  # the participant's tab, frozen
        frozen.append(control)
        control.sendall(text_frame('{"type": "gesture", "gesture": "wave"}'))
        frozen.append(websocket(port, receive_buffer=4096))  # a watcher, frozen too
        deadline = time.monotonic() + 90
        while not list(out.glob("P05/*/inputs.jsonl")) or "wave" not in "".join(
            p.read_text() for p in out.glob("P05/*/inputs.jsonl")
        ):
            assert time.monotonic() < deadline and process.poll() is None, "no session ran"
            time.sleep(0.2)
            control.sendall(text_frame('{"type": "gesture", "gesture": "wave"}'))
        time.sleep(2.0)  # frames back up in both frozen sockets
        process.send_signal(signal.SIGINT)
        signalled = time.monotonic()
        code, _, err = stopped(process, timeout=30)
        # saving the session and leaving the process take a few seconds on a loaded machine;
        # the frozen tabs add at most the goodbye's 1 s (before: a minute or more)
        assert time.monotonic() - signalled < 8.0, "Ctrl-C waited on the frozen tabs"
    finally:
        for sock in frozen:
            sock.close()
        if process.poll() is None:
            process.kill()
            process.wait()
    assert code == 130, err
    assert "Traceback" not in err and "EMFILE" not in err and "Too many open files" not in err
    assert len(err.splitlines()) <= 8, err
    (summary,) = out.glob("P05/*/summary.json")
    assert json.loads(summary.read_text())["status"] == "interrupted"


@pytest.fixture
def reachable_dir() -> Iterator[Path]:
    """A temporary folder any user can look into (pytest's own are root's only)."""
    folder = Path(tempfile.mkdtemp(prefix="robin-live-"))
    folder.chmod(0o755)
    yield folder
    for path in folder.rglob("*"):
        path.chmod(0o755)
    shutil.rmtree(folder)


def as_nobody() -> tuple[str, ...]:
    """Root writes into any folder: run as nobody, whom a mode-555 folder stops (util-linux's
    setpriv, which Debian always has)."""
    if os.geteuid() != 0:
        return ()
    return ("setpriv", "--reuid=65534", "--regid=65534", "--clear-groups")


def one_error_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("robin-pil live: error: "), err
    return lines[0]


def test_a_read_only_out_is_refused_before_serving(reachable_dir: Path) -> None:
    read_only = reachable_dir / "ro"
    read_only.mkdir(mode=0o555)
    read_only.chmod(0o555)
    code, out, err = stopped(launch(["--out", str(read_only / "live")], prefix=as_nobody()))
    assert code == 2 and "serving" not in out, (out, err)
    line = one_error_line(err)
    assert "--out" in line and "not writable" in line and str(read_only) in line
    assert list(read_only.iterdir()) == []


def test_a_placeholder_with_a_format_is_refused(tmp_path: Path) -> None:
    protocol = tmp_path / "protocol.yaml"
    protocol.write_text(
        "conditions: [pil]\nblocks:\n  - {types: [A]}\ninstructions: 'Block {block:>100000000}'\n"
    )
    code, out, err = stopped(launch(["--protocol", str(protocol), "--out", str(tmp_path / "o")]))
    assert code == 2 and "serving" not in out
    assert "{block:>100000000}" in one_error_line(err) and not (tmp_path / "o").exists()


def test_the_restart_advice_after_a_kill_works(tmp_path: Path) -> None:
    out = tmp_path / "live"
    argv = [
        "--protocol",
        "reactive_vs_proactive",
        "--participant",
        "P01",
        "--out",
        str(out),
        "--speed",
        "3",
        "--no-video",
    ]
    first = launch(argv)
    port = serving_port(first)
    tab = websocket(port)
    tab.sendall(text_frame('{"type": "start"}'))  # leave block 1's instructions: it starts
    deadline = time.monotonic() + 60
    while not list(out.glob("P01/*/inputs.jsonl")):
        assert time.monotonic() < deadline, "block 1 did not start"
        time.sleep(0.2)
    first.kill()  # kill -9: no summary is written
    first.wait()
    tab.close()
    (killed,) = (out / "P01").iterdir()
    kept = sorted(p.name for p in killed.iterdir())
    code, _, err = stopped(launch(argv))
    line = one_error_line(err)
    assert code == 2 and killed.name in line
    advice = re.search(r"add (--session \S+?)\b", line)
    assert advice, line
    again = launch([*argv, *advice.group(1).split()])
    serving_port(again)  # the advised command serves (its folders are free)
    again.send_signal(signal.SIGINT)
    code, _, err = stopped(again)
    assert code == 130 and "Traceback" not in err, err
    assert sorted(p.name for p in killed.iterdir()) == kept  # nothing of the killed run lost
