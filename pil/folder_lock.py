"""One robin-pil command at a time writes an output folder.

:class:`FolderLock` takes an exclusive ``fcntl.flock`` on the folder itself (no lock file is
left behind); the kernel releases it when the process ends, even after ``kill -9``, so a
crashed run never leaves a folder locked. The sweep store, the episode and the studies take
this same lock, so an episode and a sweep cannot write one folder at once either.
"""

from __future__ import annotations

import os
from pathlib import Path

from pil.errors import RobinPilError, quote

try:  # POSIX only; elsewhere folders are not locked
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]


class FolderInUseError(RobinPilError):
    """Another running robin-pil command holds the folder's lock."""


class FolderLock:
    """An exclusive lock on ``folder`` (which must exist) while the context is open."""

    def __init__(self, folder: str | os.PathLike[str], label: str = "--out") -> None:
        self.folder = Path(folder)
        self.label = label
        self._handle: int | None = None

    def __enter__(self) -> FolderLock:
        self.acquire()
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.release()

    def acquire(self) -> None:
        """Take the lock now; :class:`FolderInUseError` at once if another process holds it."""
        if self._handle is not None:
            return
        handle = os.open(self.folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
        if fcntl is not None:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(handle)
                raise FolderInUseError(
                    f"{self.label} {quote(str(self.folder))} is in use by another running "
                    "robin-pil command (an episode, study or sweep writing there); wait for it "
                    "to end or give another folder"
                ) from None
        self._handle = handle

    def release(self) -> None:
        """Release the lock (idempotent): closing the descriptor drops the flock."""
        if self._handle is not None:
            os.close(self._handle)
            self._handle = None
