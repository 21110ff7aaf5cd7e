"""The source's commit: read from git, dirty with tracked changes, unknown outside git."""

from __future__ import annotations

import subprocess
from pathlib import Path

from pil.provenance import SOURCE_ROOT, SourceCommit, source_commit


def _git(where: Path, *command: str) -> str:
    done = subprocess.run(["git", "-C", str(where), *command], check=True, capture_output=True)
    return done.stdout.decode().strip()


def test_a_checkout_gives_its_head_and_turns_dirty_with_a_tracked_change(tmp_path: Path) -> None:
    _git(tmp_path, "init", "-q")
    (tmp_path / "a.txt").write_text("one\n")
    _git(tmp_path, "add", "a.txt")
    _git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "one")
    head = _git(tmp_path, "rev-parse", "HEAD")
    assert source_commit(tmp_path) == SourceCommit(head, False)
    assert source_commit(tmp_path).label() == head
    (tmp_path / "untracked.txt").write_text("not counted\n")
    assert source_commit(tmp_path).dirty is False
    (tmp_path / "a.txt").write_text("two\n")
    assert source_commit(tmp_path) == SourceCommit(head, True)
    assert source_commit(tmp_path).label() == f"{head}-dirty"


def test_outside_git_the_commit_is_unknown(tmp_path: Path) -> None:
    assert source_commit(tmp_path) == SourceCommit(None, None)
    assert source_commit(tmp_path).label() == "unknown"


def test_the_default_is_the_folder_above_pil() -> None:
    assert (SOURCE_ROOT / "pil" / "provenance.py").is_file()
