"""``study-verify`` names every kind of damaged archive with exit 2 (issue 39)."""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path

import pytest

from robin_sim.cli.main import main


@pytest.fixture
def archive(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> Path:
    folder = tmp_path / "study"
    assert main(["study-init", str(folder)]) == 0
    assert main(["study-export", str(folder)]) == 0
    printed = capsys.readouterr().out.splitlines()
    path = Path(printed[-1])
    assert printed[-2].startswith("archive SHA-256 ")
    return path


def verified(path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(["study-verify", str(path)])
    out, err = capsys.readouterr()
    return code, out, err


def rewritten(source: Path, target: Path, change: dict[str, bytes | None]) -> Path:
    """A copy of ``source`` with members replaced (or left out, for None)."""
    with zipfile.ZipFile(source) as old, zipfile.ZipFile(target, "w") as new:
        for name in old.namelist():
            data = change.get(name, old.read(name))
            if data is not None:
                new.writestr(name, data)
    return target


def test_a_whole_archive_passes_and_its_digest_is_printed(
    archive: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, _ = verified(archive, capsys)
    assert code == 0 and "files match the manifest" in out
    assert "archive SHA-256 " in out
    manifest = json.loads(zipfile.ZipFile(archive).read("manifest.json"))
    assert len(manifest["scenario"]["sha256"]) == 64  # the shipped scenario's file, hashed


@pytest.mark.parametrize("kind", ["fifo", "dev-zero"])
def test_an_archive_that_is_not_a_regular_file_is_named(
    tmp_path: Path, kind: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "study.zip"
    if kind == "fifo":
        os.mkfifo(path)
    else:
        path.symlink_to("/dev/zero")
    code, _, err = verified(path, capsys)
    assert code == 2 and "not a regular file" in err and "study.zip" in err


def test_a_manifest_with_a_list_of_files_is_named(
    archive: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = rewritten(archive, tmp_path / "bad.zip", {"manifest.json": b'{"files": []}'})
    code, _, err = verified(bad, capsys)
    assert code == 2 and "'files' must map each file" in err


def test_a_flipped_byte_in_a_member_names_the_member(
    archive: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with zipfile.ZipFile(archive) as zipped:
        info = zipped.getinfo("study.yaml")
    data = bytearray(archive.read_bytes())
    start = info.header_offset + 30 + len(info.filename.encode()) + len(info.extra)
    data[start + info.compress_size // 2] ^= 0xFF  # inside the member's compressed data
    flipped = tmp_path / "flipped.zip"
    flipped.write_bytes(bytes(data))
    code, _, err = verified(flipped, capsys)
    assert code == 2 and "study.yaml: " in err and "Traceback" not in err


def test_a_file_listed_twice_in_the_archive_is_refused(
    archive: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    twice = tmp_path / "twice.zip"
    with zipfile.ZipFile(archive) as old, zipfile.ZipFile(twice, "w") as new:
        for name in old.namelist():
            new.writestr(name, old.read(name))
        with pytest.warns(UserWarning, match="Duplicate name"):
            new.writestr("study.yaml", b"design: between\n")
    code, _, err = verified(twice, capsys)
    assert code == 2 and "study.yaml stands twice" in err
