"""The output folder of a command, checked before anything is computed or written.

:func:`check_out_dir` refuses a path that is a file, lies under a file, or cannot be written
(``/proc/x``, a read-only disk) with one :class:`OutDirError` naming it, and creates the folder
(with a probe file written and removed) only when it can be used.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from pil.errors import RobinPilError, quote


class OutDirError(RobinPilError):
    """An output folder that is a file, lies under a file or cannot be written."""


def check_out_dir(path: str | os.PathLike[str], label: str = "--out") -> Path:
    """``path`` as a folder that exists and can be written; raise :class:`OutDirError` if not."""
    out = Path(path)
    shown = quote(str(out))
    if not str(out).strip():
        raise OutDirError(f"{label}: empty path; give a folder to write the results to")
    for parent in [out, *out.parents]:
        if parent.exists() or parent.is_symlink():
            if not parent.is_dir():
                where = (
                    "is a file" if parent == out else f"lies under the file {quote(str(parent))}"
                )
                raise OutDirError(f"{label} {shown} {where}; give a folder (new or existing)")
            break
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out, prefix=".robin-pil-probe-"):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        raise OutDirError(
            f"{label} {shown} cannot be written ({reason}); give a folder you can write to"
        ) from None
    return out
