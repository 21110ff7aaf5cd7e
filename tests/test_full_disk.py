"""A full disk and too-long names: one clear line and exit 2, no half files, a playable video.

The full disk is real: a small tmpfs mounted for the test (``mount -t tmpfs -o size=...``,
which needs root, as the project's CI runs; unprivileged, these tests are skipped and say so).
"""

from __future__ import annotations

import errno
import json
import os
import struct
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest

from robin_sim.cli.main import main
from robin_sim.render.video import Mp4Writer, probe_video

LONG = "x" * 300  # one name part longer than any file system allows (255 bytes)


@pytest.fixture()
def small_disk(tmp_path: Path) -> Iterator[Callable[[int, int], Path]]:
    """``make(size_kb, free_kb)``: a tmpfs of ``size_kb`` filled up to ``free_kb`` free."""
    mounts: list[Path] = []

    def make(size_kb: int, free_kb: int) -> Path:
        point = tmp_path / f"disk{len(mounts)}"
        point.mkdir()
        done = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={size_kb}k", "tmpfs", str(point)],
            capture_output=True,
            text=True,
        )
        if done.returncode != 0:
            pytest.skip(f"cannot mount a small tmpfs here (needs root): {done.stderr.strip()}")
        mounts.append(point)
        if size_kb > free_kb:
            (point / "filler").write_bytes(b"\0" * ((size_kb - free_kb) * 1024))
        return point

    yield make
    for point in mounts:
        subprocess.run(["umount", "-l", str(point)], check=False)


def last_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert lines and "Traceback" not in err, err
    return lines[-1]


def no_half_files(folder: Path) -> None:
    left = [p.name for p in folder.rglob("*") if ".partial" in p.name or p.suffix == ".tmp"]
    assert not left, left


def test_study_on_a_full_disk_is_one_line_exit_2(
    small_disk: Callable[[int, int], Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = small_disk(256, 24) / "study"
    argv = ["study", "--reps", "1", "--rates", "1.0", "--tables", "1", "--no-progress"]
    assert main([*argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("robin-pil study: error: cannot write"), err
    assert "No space left on device" in err and "the disk is full" in err
    no_half_files(out)


def test_sweep_on_a_full_disk_exits_2_not_1(
    small_disk: Callable[[int, int], Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = small_disk(128, 6) / "sweep"
    argv = ["sweep", "--reps", "40", "--systems", "pil", "--rates", "1.0", "--workers", "1"]
    assert main([*argv, "--quiet", "--out", str(out)]) == 2
    line = last_line(capsys.readouterr().err)
    assert line.startswith("robin-pil sweep: error: cannot write") and "disk is full" in line
    no_half_files(out)


def test_a_reserved_summary_is_replaced_in_place_on_a_full_disk(
    small_disk: Callable[[int, int], Path],
) -> None:
    from pil.atomic import write_text_reserved

    disk = small_disk(64, 64)
    path = write_text_reserved(disk / "summary.json", '{"status": "running"}\n', 8192)
    assert path.stat().st_size == 8192
    (disk / "filler").write_bytes(b"\0" * (os.statvfs(disk).f_bavail * os.statvfs(disk).f_frsize))
    with pytest.raises(OSError, match="No space left"):
        (disk / "other").write_bytes(b"x" * 8192)
    write_text_reserved(path, json.dumps({"status": "failed", "error": "disk full"}) + "\n")
    assert json.loads(path.read_text())["status"] == "failed"
    assert not [p for p in disk.iterdir() if p.name.startswith(".")]


def test_writes_that_fill_the_disk_name_their_file(small_disk: Callable[[int, int], Path]) -> None:
    """The states file and the step log name themselves in the error (a write to an open
    handle names no file), and a states file that does not fit leaves no temporary file."""
    from pil.errors import os_error_line
    from robin_sim.episode.log import StepLog
    from robin_sim.render.state_log import StateLog
    from robin_sim.render.worker import FrameState

    disk = small_disk(64, 8)
    states = StateLog(disk / "states.npz", {"layout": {}, "size": [8, 8]})
    rng = np.random.default_rng(0)  # random numbers: they do not compress into 8 KB
    for k in range(200):
        shapes = ((60,), (2, 3), (2, 4), (10, 4))
        states.add(FrameState(k / 30, *(rng.random(shape) for shape in shapes)))
    with pytest.raises(OSError) as caught:
        states.save()
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(disk / "states.npz")
    assert f"cannot write {str(disk / 'states.npz')!r} (No space" in os_error_line(caught.value)
    assert sorted(p.name for p in disk.iterdir()) == ["filler"]
    with StepLog(disk / "episode.jsonl") as log, pytest.raises(OSError) as caught:
        log.write({"text": "x" * 64_000})
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(disk / "episode.jsonl")


def small_video(path: Path, frames: int = 45) -> Path:
    with Mp4Writer(path, 64, 48, fps=15) as writer:
        for k in range(frames):
            writer.write(np.full((48, 64, 3), 4 * k, np.uint8))
    return path


def test_a_torn_video_is_cut_back_to_its_last_whole_fragment(tmp_path: Path) -> None:
    from robin_sim.render.mp4_trim import trim_torn_tail, whole_boxes_end
    from robin_sim.render.video import count_frames

    path = small_video(tmp_path / "v.mp4")
    whole = path.stat().st_size
    assert whole_boxes_end(path) == whole and probe_video(path)["frames"] == 45
    boxes = top_level_boxes(path)
    assert [kind for _, kind in boxes][-3:] == [b"moof", b"mdat", b"mfra"]
    last_moof, last_mdat = boxes[-3][0], boxes[-2][0]
    with path.open("r+b") as handle:
        handle.truncate(last_mdat + 20)  # the last fragment's data cut short, as by a full disk
    assert trim_torn_tail(path) == last_mdat + 20 - last_moof
    assert path.stat().st_size == last_moof
    assert probe_video(path)["frames"] == count_frames(path) == 30  # two whole seconds


def top_level_boxes(path: Path) -> list[tuple[int, bytes]]:
    data, offset, boxes = path.read_bytes(), 0, []
    while offset < len(data):
        size, kind = struct.unpack(">I4s", data[offset : offset + 8])
        boxes.append((offset, kind))
        offset += size
    return boxes


@pytest.mark.slow
def test_an_episode_on_a_full_disk_leaves_a_summary_and_a_playable_video(
    small_disk: Callable[[int, int], Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = small_disk(96, 96) / "ep"
    argv = [
        "episode",
        "--scenario",
        "one_handover",
        "--no-verify",
        "--quiet",
        "--size",
        "160x120",
        "--fps",
        "10",
        "--render-workers",
        "0",
        "--out",
        str(out),
    ]
    assert main(argv) == 2
    line = last_line(capsys.readouterr().err)
    assert (
        line.startswith("robin-pil episode: error: cannot write")
        and str(out / "episode.mp4") in line
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "failed" and "No space left" in summary["error"]
    frames = probe_video(out / "episode.mp4")["frames"]
    assert frames == summary["video"]["frames"] > 0


@pytest.mark.parametrize(
    "argv",
    [
        ["episode", "--no-video", "--quiet"],
        ["study", "--reps", "1", "--rates", "1.0", "--no-progress"],
        ["sweep", "--reps", "1", "--systems", "pil", "--rates", "1.0", "--quiet"],
        ["people", "--reps", "1", "--rates", "1.0", "--no-progress"],
    ],
)
def test_a_too_long_out_name_is_refused_up_front(
    argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([*argv, "--out", str(tmp_path / LONG / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "File name too long" in err, err
