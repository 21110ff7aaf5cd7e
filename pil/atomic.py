"""Write a file whole or not at all: a temporary file beside it, fsync, then a rename.

A reader (or a crash, or Ctrl-C) never sees a half-written file, and a failed write leaves an
existing file at the path exactly as it was. The file gets ordinary permissions (0666 less the
umask), not the private ones of a temporary file.

:func:`write_text_reserved` is for a file rewritten while its run goes on (a summary): each
version is padded with trailing whitespace to a reserved size, so that when the disk is full
and no temporary file can be written, the final version still fits over the old one in place.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path


def write_text_atomic(path: str | Path, text: str, *, make_folder: bool = True) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically and return the path.

    The folder is created if missing, unless ``make_folder`` is False (then a missing folder
    raises ``FileNotFoundError``).
    """
    path = Path(path)
    if make_folder:
        path.parent.mkdir(parents=True, exist_ok=True)
    handle, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as tmp:
            tmp.write(text)
            tmp.flush()
            os.fsync(tmp.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_name, 0o666 & ~umask)
        os.replace(tmp_name, path)
    except BaseException:
        Path(tmp_name).unlink(missing_ok=True)
        raise
    return path


FULL_DISK = (errno.ENOSPC, errno.EDQUOT)


def write_text_reserved(path: str | Path, text: str, reserve: int = 0) -> Path:
    """Write ``text`` atomically, padded with spaces to ``reserve`` bytes; when the disk is
    full, overwrite the existing file in place if the text fits in it (not atomic, but it needs
    no new space). ``text`` must allow trailing whitespace (JSON does)."""
    path = Path(path)
    data = text.encode("utf-8")
    padded = text + " " * max(0, reserve - len(data))
    try:
        return write_text_atomic(path, padded)
    except OSError as error:
        if error.errno not in FULL_DISK or not path.is_file():
            raise
        if path.stat().st_size < len(data):
            raise
        with open(path, "r+b") as handle:  # the old file's blocks: no new space needed
            handle.write(data + b" " * (path.stat().st_size - len(data)))
            handle.flush()
            os.fsync(handle.fileno())
    return path
