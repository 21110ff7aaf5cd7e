"""Inputs that used to pass the first checks and fail late (or with a traceback).

Each is refused up front (exit 2, one line, nothing written), or now works.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from robin_sim.cli.main import main

ROOT = Path(__file__).parents[1]
SWEEP = ["sweep", "--reps", "1", "--systems", "pil", "--quiet", "--no-report"]


def refused(argv: list[str], capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith(f"robin-pil {argv[0]}: error: "), err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


def test_rate_0_is_refused_before_the_episode_starts(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "out"
    started = time.monotonic()
    for argv in (
        ["episode", "--rate", "0", "--no-video", "--quiet"],
        ["episode", "--rate", "0.0", "--no-video", "--quiet"],
        ["study", "--rates", "0,1.0", "--reps", "1", "--no-progress"],
        ["people", "--rates", "0", "--reps", "1", "--no-progress"],
        [*SWEEP, "--rates", "0"],
    ):
        refused([*argv, "--out", str(out)], capsys, "(0, 1]", "never")
    assert time.monotonic() - started < 20
    assert not out.exists()
    refused(["episode", "--rate", "1.5", "--out", str(out)], capsys, "(0, 1]", "'1.5'")


def test_a_missing_measured_file_is_refused_before_the_first_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sweep"
    broken = tmp_path / "broken.json"
    broken.write_text("{")
    for value, needle in (("/nonexistent", "no such file"), (str(broken), "not readable JSON")):
        argv = [*SWEEP, "--rates", "1.0", "--workers", "1", "--out", str(out)]
        refused([*argv, "--param", f"detector=exact,measured:{value}"], capsys, needle, value)
        assert not out.exists()
    refused(
        [
            "episode",
            "--no-video",
            "--quiet",
            "--detector",
            "measured:/nonexistent",
            "--out",
            str(out),
        ],
        capsys,
        "no such file",
    )
    assert not out.exists()


def test_a_tls_scheduler_without_tls_settings_is_one_line_at_once(tmp_path: Path) -> None:
    started = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            *SWEEP,
            "--scheduler",
            "tls://127.0.0.1:1",
            "--connect-timeout",
            "1",
            "--out",
            str(tmp_path / "s"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT), "HOME": str(tmp_path)},
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().count("\n") == 0 and "Traceback" not in done.stderr, done.stderr
    assert "TLS settings" in done.stderr and "tcp://" in done.stderr
    assert time.monotonic() - started < 30
    assert not (tmp_path / "s").exists()


def test_people_with_one_table_runs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "people"
    argv = ["people", "--tables", "1", "--reps", "2", "--rates", "1.0", "--systems", "pil"]
    assert main([*argv, "--no-progress", "--out", str(out)]) == 0, capsys.readouterr().err
    with (out / "people.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert {row["mode"] for row in rows} == {"shared", "per-person"}
    assert all(row["tables"] == "1" and row["legs"] == "4" for row in rows)
    assert all(int(row["actions"]) >= int(row["gestures"]) > 0 for row in rows)


def test_devices_and_fifos_as_input_files_are_refused_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    out = tmp_path / "out"
    started = time.monotonic()
    for path in ("/dev/zero", str(fifo)):
        refused(
            [
                "transfer",
                "--table",
                path,
                "--reps",
                "1",
                "--rates",
                "1.0",
                "--no-progress",
                "--out",
                str(out),
            ],
            capsys,
            "not a regular file",
        )
        refused(
            [
                *SWEEP,
                "--rates",
                "1.0",
                "--workers",
                "1",
                "--out",
                str(out),
                "--param",
                f"detector=measured:{path}",
            ],
            capsys,
            "not a regular file",
        )
    assert time.monotonic() - started < 20
    assert not out.exists()
