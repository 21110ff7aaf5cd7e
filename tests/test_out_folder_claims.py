"""One command at a time writes an output folder, and a folder's files belong to one run.

A second episode, study or sweep into a folder that another process is writing is refused
(exit 2, one line) before it writes anything; a run killed with ``kill -9`` leaves its own
summary (``running``), never the previous run's ``finished`` one beside its partial log.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from robin_sim.cli.main import main

ROOT = Path(__file__).parents[1]
EARLIER = {"summary.json": '{"status": "finished", "seed": 7}\n', "episode.jsonl": "{}\n" * 3}
HOLDER = (
    "import sys, time; from pil.folder_lock import FolderLock\n"
    "with FolderLock(sys.argv[1]):\n    print('held', flush=True); time.sleep(60)\n"
)


def env() -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": "egl"}


@pytest.fixture()
def earlier(tmp_path: Path) -> Path:
    out = tmp_path / "out"
    out.mkdir()
    for name, text in EARLIER.items():
        (out / name).write_text(text)
    return out


@pytest.fixture()
def held(earlier: Path) -> Iterator[Path]:
    """``earlier`` locked by another process for the test's duration."""
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(earlier)], env=env(), stdout=subprocess.PIPE, text=True
    )
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        yield earlier
    finally:
        holder.kill()
        holder.wait()


def refused_in_use(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert err.count("\n") == 0 and "is in use by another running robin-pil command" in err, err


def assert_untouched(out: Path) -> None:
    assert {p.name: p.read_text() for p in out.iterdir()} == EARLIER


def test_an_episode_into_a_folder_in_use_is_refused(
    held: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    refused_in_use(
        [
            "episode",
            "--scenario",
            "one_handover",
            "--no-video",
            "--no-verify",
            "--quiet",
            "--out",
            str(held),
        ],
        capsys,
    )
    assert_untouched(held)


def test_a_study_and_a_sweep_into_a_folder_in_use_are_refused(
    held: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    refused_in_use(
        [
            "study",
            "--reps",
            "1",
            "--rates",
            "1.0",
            "--tables",
            "1",
            "--no-progress",
            "--out",
            str(held),
        ],
        capsys,
    )
    refused_in_use(
        ["people", "--reps", "1", "--rates", "1.0", "--no-progress", "--out", str(held)], capsys
    )
    refused_in_use(
        [
            "sweep",
            "--reps",
            "1",
            "--systems",
            "pil",
            "--rates",
            "1.0",
            "--workers",
            "1",
            "--quiet",
            "--no-report",
            "--out",
            str(held),
        ],
        capsys,
    )
    assert_untouched(held)


def test_the_lock_is_released_when_its_holder_is_killed(earlier: Path) -> None:
    from pil.folder_lock import FolderLock

    holder = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(earlier)], env=env(), stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
    holder.send_signal(signal.SIGKILL)
    holder.wait()
    with FolderLock(earlier):
        pass
    assert not any(p.name.startswith(".") for p in earlier.iterdir())  # no lock file left


@pytest.mark.slow
def test_a_killed_episode_leaves_its_own_summary_and_a_second_run_is_refused(
    earlier: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["episode", "--scenario", "one_handover", "--no-video", "--no-verify", "--quiet"]
    first = subprocess.Popen(
        [sys.executable, "-m", "robin_sim.cli.main", *argv, "--seed", "0", "--out", str(earlier)],
        env=env(),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    log = earlier / "episode.jsonl"
    deadline = time.monotonic() + 240
    try:
        while time.monotonic() < deadline and first.poll() is None:  # its first step logged
            if log.exists() and log.read_text().count("\n") >= 1 and log.read_text() != "{}\n" * 3:
                break
            time.sleep(0.05)
        assert first.poll() is None, "the episode ended before its first step was seen"
        refused_in_use([*argv, "--seed", "1", "--out", str(earlier)], capsys)
        first.send_signal(signal.SIGKILL)
    finally:
        first.kill()
        first.wait()
    summary = json.loads((earlier / "summary.json").read_text())
    assert summary["status"] == "running" and summary["seed"] == 0, summary
    lines = log.read_text().splitlines()
    assert lines and all(json.loads(line)["t"] >= 0 for line in lines)
    assert summary["scenario"] == "one_handover"
