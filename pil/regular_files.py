"""Reading an input file that must be a regular file of bounded size.

A path given by a user may name a device (``/dev/zero`` never ends), a FIFO (its open blocks
until someone writes) or a folder; :func:`read_regular_text` refuses those at once and reads
at most ``limit`` bytes, so no input file can hang a command or fill its memory.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path


class FileTooLargeError(ValueError):
    """An input file over its size limit (raised by :func:`read_regular_text`)."""


def read_regular_text(path: str | os.PathLike[str], limit: int) -> str:
    """A regular file's UTF-8 text. ``OSError`` when it cannot be opened or is not a regular
    file (``strerror`` "not a regular file"), :class:`FileTooLargeError` when it is larger
    than ``limit`` bytes (nothing more is read), ``UnicodeDecodeError`` when not UTF-8."""
    handle = os.open(Path(path), os.O_RDONLY | os.O_NONBLOCK)  # a FIFO does not block the open
    if not stat.S_ISREG(os.fstat(handle).st_mode):
        os.close(handle)
        raise IsADirectoryError(errno.EISDIR, "not a regular file", str(path))
    with os.fdopen(handle, "rb") as reader:
        data = reader.read(limit + 1)
    if len(data) > limit:
        raise FileTooLargeError(f"larger than {limit:,} bytes")
    return data.decode("utf-8")
