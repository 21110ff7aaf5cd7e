"""The output folder of a command, checked before anything is computed or written.

:func:`check_out_dir` refuses a path that is a file, lies under a file, or cannot be written
(``/proc/x``, a read-only disk) with one :class:`OutDirError` naming it, and creates the folder
(with a probe file written and removed) only when it can be used. :func:`claimed_out_dir`
also holds the folder's :class:`~pil.folder_lock.FolderLock` while a command writes it.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from pil.errors import RobinPilError, quote
from pil.folder_lock import FolderLock


class OutDirError(RobinPilError):
    """An output folder that is a file, lies under a file or cannot be written."""


def check_out_dir(path: str | os.PathLike[str], label: str = "--out") -> Path:
    """``path`` as a folder that exists and can be written; raise :class:`OutDirError` if not."""
    out = Path(path)
    shown = quote(str(out))
    if not str(out).strip():
        raise OutDirError(f"{label}: empty path; give a folder to write the results to")
    try:
        for parent in [out, *out.parents]:
            if parent.exists() or parent.is_symlink():
                if not parent.is_dir():
                    where = (
                        "is a file"
                        if parent == out
                        else f"lies under the file {quote(str(parent))}"
                    )
                    raise OutDirError(f"{label} {shown} {where}; give a folder (new or existing)")
                break
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out, prefix=".robin-pil-probe-"):
            pass
    except OSError as error:  # a 300-character name part: ENAMETOOLONG, from exists() too
        reason = error.strerror or type(error).__name__
        raise OutDirError(
            f"{label} {shown} cannot be written ({reason}); give a folder you can write to"
        ) from None
    return out


@contextmanager
def claimed_out_dir(path: str | os.PathLike[str], label: str = "--out") -> Iterator[Path]:
    """:func:`check_out_dir`, then the folder's lock held until the block ends (a second
    command into the same folder is refused with :class:`~pil.folder_lock.FolderInUseError`)."""
    out = check_out_dir(path, label)
    with FolderLock(out, label):
        yield out
