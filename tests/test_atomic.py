"""Whole-or-nothing file writes."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from pil.atomic import write_text_atomic


def test_writes_the_text_with_ordinary_permissions_and_creates_the_folder(tmp_path: Path) -> None:
    path = write_text_atomic(tmp_path / "new" / "runs.csv", "a,b\n1,2\n")
    assert path.read_text(encoding="utf-8") == "a,b\n1,2\n"
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask
    assert sorted(p.name for p in path.parent.iterdir()) == ["runs.csv"]


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    path = write_text_atomic(tmp_path / "summary.md", "old\n")
    with pytest.raises(UnicodeEncodeError):
        write_text_atomic(path, "half \ud800 written")  # a lone surrogate cannot be encoded
    assert path.read_text(encoding="utf-8") == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["summary.md"]


def test_a_missing_folder_can_be_an_error(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        write_text_atomic(tmp_path / "typo" / "table.json", "{}", make_folder=False)
    assert list(tmp_path.iterdir()) == []
