"""Write a file whole or not at all: a temporary file beside it, fsync, then a rename.

A reader (or a crash, or Ctrl-C) never sees a half-written file, and a failed write leaves an
existing file at the path exactly as it was. The file gets ordinary permissions (0666 less the
umask), not the private ones of a temporary file.
"""

from __future__ import annotations

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
