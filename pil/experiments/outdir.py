"""Check an output folder before a long computation, so a bad ``--out`` fails first."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from pil.errors import RobinPilError


class OutputFolderError(RobinPilError):
    """An output folder that is a file, lies under a file, or cannot be written."""


def check_output_folder(out: str | os.PathLike[str]) -> Path:
    """``out`` as a Path if it is (or can be made) a writable folder; nothing is created.

    The folder itself, or its nearest existing parent, must be a folder in which a file can be
    created (checked by creating and removing a temporary file, which works for any user).
    """
    path = Path(out)
    probe = path
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        where = "is a file" if probe == path else f"lies under {str(probe)!r}, which is a file"
        raise OutputFolderError(f"output folder {str(path)!r} {where}; give a folder path")
    try:
        with tempfile.TemporaryFile(dir=probe, prefix=".robin-pil-probe-"):
            pass
    except OSError as error:
        raise OutputFolderError(
            f"output folder {str(path)!r} cannot be written ({probe}: {error.strerror or error}); "
            "give a folder you can write to"
        ) from None
    return path
