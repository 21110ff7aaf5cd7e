"""The project's one base error class and its families.

Every error a user can cause (bad input, a corrupt file, an unreachable target) is raised as a
subclass of :class:`RobinPilError`, with a message that names the problem and the valid choices.
A subclass lives next to what raises it (``pil.task.scenario.ScenarioError``,
``pil.table_io.TableFileError``, ...); only families that many modules raise live here.
"""

from __future__ import annotations

import errno
from collections.abc import Iterable
from typing import Any

QUOTE_LIMIT = 80  # characters of a bad value quoted in an error message


def quote(value: Any, limit: int = QUOTE_LIMIT) -> str:
    """``repr(value)`` cut to about ``limit`` characters: a 50 MB value is not echoed whole."""
    if isinstance(value, str) and len(value) > limit:
        return repr(value[:limit]) + f"... ({len(value)} characters)"
    shown = repr(value)
    return shown if len(shown) <= limit else shown[:limit] + f"... ({len(shown)} characters)"


class RobinPilError(ValueError):
    """Base class of every error raised on purpose by robin-pil (``pil`` and ``robin_sim``)."""


class InvalidChoiceError(RobinPilError):
    """A name or value that is not one of the valid choices."""

    def __init__(self, what: str, value: object, choices: Iterable[object]) -> None:
        listed = ", ".join(repr(str(c)) for c in choices)
        super().__init__(f"unknown {what} {quote(value)}; valid choices: {listed}")
        self.what = what
        self.value = value
        self.choices = tuple(choices)


# why a detection rate of 0 is refused where a task must finish (the CLI, sweeps)
NEVER_DETECTED = "at rate 0 no gesture is ever read, so the task can never finish"


# errno -> what to do about it, for a file the program could not write or read
_OS_ADVICE: dict[int, str] = {
    errno.ENOSPC: "the disk is full: free some space and run the command again",
    errno.EDQUOT: "the disk quota is used up: free some space and run the command again",
    errno.ENAMETOOLONG: "a file or folder name is too long: give a shorter --out",
    errno.EROFS: "the disk is read-only: give an --out on a writable disk",
    errno.EACCES: "permission denied: give an --out you can write to",
    errno.EPERM: "permission denied: give an --out you can write to",
    errno.EFBIG: "the file grew too large for its disk",
    errno.EIO: "the disk reported an input/output error",
}


def naming(error: OSError, path: object) -> OSError:
    """``error`` naming ``path`` when it names no file (a write to an open handle, FFmpeg's
    writes): the command line's one line then says which file could not be written."""
    if error.filename is not None:
        return error
    return OSError(error.errno, error.strerror, str(path))


def os_error_line(error: OSError) -> str:
    """One line for an ``OSError`` that reached the command line: the file, the system's
    reason and what to do (files finished before it are kept)."""
    where = quote(str(error.filename), 400) if error.filename is not None else "a file"
    reason = error.strerror or type(error).__name__
    advice = _OS_ADVICE.get(error.errno or 0, "")
    return f"cannot write {where} ({reason}){'; ' + advice if advice else ''}"
