"""Which source the running code came from: its git commit and whether the tree had changes."""

from __future__ import annotations

import subprocess
from dataclasses import dataclass
from pathlib import Path

SOURCE_ROOT = Path(__file__).resolve().parents[1]  # the checkout (or site-packages) above pil/


@dataclass(frozen=True, slots=True)
class SourceCommit:
    """A checkout's commit (None outside git, e.g. an installed wheel) and its changes."""

    id: str | None
    dirty: bool | None

    def label(self) -> str:
        """``<sha>``, ``<sha>-dirty`` or ``unknown``."""
        if self.id is None:
            return "unknown"
        return self.id + ("-dirty" if self.dirty else "")


def source_commit(where: Path = SOURCE_ROOT) -> SourceCommit:
    """The commit of the git checkout at ``where`` (tracked changes make it dirty)."""
    unknown = SourceCommit(None, None)
    if not (where / ".git").exists():
        return unknown
    try:
        head, status = (
            subprocess.run(
                ["git", "-C", str(where), *command],
                capture_output=True,
                text=True,
                timeout=10,
                check=True,
            )
            for command in (
                ("rev-parse", "HEAD"),
                ("status", "--porcelain", "--untracked-files=no"),
            )
        )
    except (OSError, subprocess.SubprocessError):
        return unknown
    return SourceCommit(head.stdout.strip(), bool(status.stdout.strip()))
