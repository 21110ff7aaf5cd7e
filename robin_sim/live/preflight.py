"""Checks a live run makes before it serves: the sessions folder is writable, no folder is taken.

Both fail with one :class:`~pil.errors.RobinPilError` that says what to do, so the page is never
served for a run that would fail once the participant connects. Nothing lasting is written: the
write check makes and removes one empty temporary file in the nearest folder that exists.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

from pil.errors import RobinPilError, quote
from robin_sim.live.config import LiveConfig
from robin_sim.live.files import SessionExistsError, session_folder

PATH_LIMIT = 4200  # paths are shown whole (the system's own limit is 4096)
RETRY_NAMES = ("retry", *(f"retry{n}" for n in range(2, 100)))  # suggested --session names


def check_writable(folder: Path, option: str = "--out") -> None:
    """``folder`` (made later if missing) can take new files; else one clear error."""
    folder = Path(folder)
    existing = folder
    try:
        while not existing.exists() and existing != existing.parent:
            existing = existing.parent
        is_dir = existing.is_dir()
    except OSError as error:  # a folder on the way that may not be looked into
        raise RobinPilError(
            f"{option} {_shown(folder)} cannot be reached: "
            f"{error.strerror or error}; choose a folder you can write "
            "to"
        ) from None
    if not is_dir:
        raise RobinPilError(
            f"{option} {_shown(folder)}: {_shown(existing)} is a file, "
            "not a folder; choose a folder you can write to"
        )
    try:
        handle, name = tempfile.mkstemp(prefix=".robin-pil-write-check-", dir=existing)
    except OSError as error:
        where = "" if existing == folder else f" (its folder {_shown(existing)})"
        raise RobinPilError(
            f"{option} {_shown(folder)}{where} is not writable: "
            f"{error.strerror or error}; choose a folder you can write "
            "to"
        ) from None
    os.close(handle)
    os.unlink(name)


def check_free(configs: Sequence[LiveConfig], folders_named: Callable[[str], list[Path]]) -> None:
    """Every session's folder is free; else the error names the taken one and the way out,
    ``--session NAME`` with a name whose folders (``folders_named(name)``) are all free."""
    for config in configs:
        try:
            session_folder(config)
        except SessionExistsError:
            taken = Path(config.out_root) / config.participant / str(config.session)
            name = next(
                (n for n in RETRY_NAMES if not any(f.exists() for f in folders_named(n))),
                "retry100",
            )
            shown = ", ".join(f.name for f in folders_named(name)[:2])
            raise RobinPilError(
                f"session folder {_shown(taken)} exists already (a session is never "
                f"overwritten); to run again beside it, add --session {name} (folders {shown}"
                f"{', ...' if len(folders_named(name)) > 2 else ''})"
            ) from None


def _shown(path: Path) -> str:
    return quote(str(path), PATH_LIMIT)
