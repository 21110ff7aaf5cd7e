"""A sweep against ``dask scheduler`` and ``dask worker`` started as separate processes (loopback).

Kill the scheduler mid-sweep: one clear message saying what happened and how to resume, exit 3,
and no attempt charged to the runs in flight; a rerun against a new scheduler finishes the grid
with every run passing on its first attempt. A scheduler without workers: the sweep says it is
waiting for workers, and goes on once one joins.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

TESTS_DIR = Path(__file__).resolve().parent
DASK = shutil.which("dask") or str(Path(sys.executable).with_name("dask"))
GRID = [
    "--systems",
    "pil,c1",
    "--rates",
    "0.6,1.0",
    "--reps",
    "4",
    "--tables",
    "1",
    "--run-function",
    "sweep_test_runs:paced_run",
    "--param",
    "delay=0.5",
    "--no-report",
    "--quiet",
]
ENV = {**os.environ, "PYTHONPATH": str(TESTS_DIR)}


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start(*argv: str) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        argv,
        env=ENV,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )


def stop(process: subprocess.Popen[bytes]) -> None:
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGKILL)
    process.wait(timeout=30)


def scheduler(port: int) -> subprocess.Popen[bytes]:
    process = start(DASK, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard")
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        with socket.socket() as probe:
            if probe.connect_ex(("127.0.0.1", port)) == 0:
                return process
        time.sleep(0.1)
    stop(process)
    raise AssertionError("dask scheduler did not start")


def worker(port: int) -> subprocess.Popen[bytes]:
    return start(
        DASK,
        "worker",
        f"tcp://127.0.0.1:{port}",
        "--nthreads",
        "2",
        "--no-dashboard",
        "--host",
        "127.0.0.1",
    )


def sweep(out: Path, port: int) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            "sweep",
            *GRID,
            "--scheduler",
            f"tcp://127.0.0.1:{port}",
            "--connect-timeout",
            "20",
            "--out",
            str(out),
        ],
        env=ENV,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )


def journal(out: Path) -> list[dict]:
    path = out / "runs.jsonl"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.endswith("}")]


@pytest.fixture()
def processes() -> Iterator[list[subprocess.Popen[bytes]]]:
    started: list[subprocess.Popen[bytes]] = []
    yield started
    for process in started:
        stop(process)


def test_a_killed_scheduler_is_reported_and_the_sweep_resumes(tmp_path, processes) -> None:
    port, out = free_port(), tmp_path / "sweep"
    processes += [scheduler(port)]
    processes += [worker(port)]
    run = sweep(out, port)
    processes.append(run)
    deadline = time.monotonic() + 120
    while len(journal(out)) < 3:
        assert run.poll() is None and time.monotonic() < deadline
        time.sleep(0.05)
    processes[0].send_signal(signal.SIGKILL)  # the scheduler dies; its worker is left behind
    _, stderr = run.communicate(timeout=120)
    text = stderr.decode()
    assert run.returncode == 3, text
    assert "lost the connection to the Dask scheduler" in text and "rerun the same" in text
    assert "Traceback" not in text and "ConnectionPool" not in text
    records = journal(out)
    assert records and all(r["status"] == "ok" for r in records)  # in-flight runs not charged
    assert len(records) < 16
    stop(processes[1])

    processes += [scheduler(port)]
    processes += [worker(port)]
    again = sweep(out, port)
    processes.append(again)
    _, stderr = again.communicate(timeout=180)
    assert again.returncode == 0, stderr.decode()
    records = journal(out)
    assert sorted(r["run_id"] for r in records) == sorted({r["run_id"] for r in records})
    assert len(records) == 16 and all(r["attempt"] == 1 and r["status"] == "ok" for r in records)


def test_a_scheduler_without_workers_says_it_is_waiting(tmp_path, processes) -> None:
    port, out = free_port(), tmp_path / "sweep"
    processes += [scheduler(port)]
    run = sweep(out, port)
    processes.append(run)
    os.set_blocking(run.stderr.fileno(), False)
    seen, deadline = b"", time.monotonic() + 60
    while b"waiting for Dask workers" not in seen:
        assert run.poll() is None and time.monotonic() < deadline, seen.decode()
        seen += run.stderr.read() or b""
        time.sleep(0.1)
    assert f"dask worker tcp://127.0.0.1:{port}".encode() in seen
    processes += [worker(port)]
    os.set_blocking(run.stderr.fileno(), True)
    _, rest = run.communicate(timeout=180)
    assert run.returncode == 0, (seen + rest).decode()
    assert len(journal(out)) == 16
