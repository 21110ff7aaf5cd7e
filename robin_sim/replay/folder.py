"""Which folder ``robin-pil replay DIR`` replays, checked before anything is rendered."""

from __future__ import annotations

import os
from pathlib import Path

from pil.errors import RobinPilError, quote
from pil.experiments.sessions_load import SUMMARY_NAME
from robin_sim.render.state_log import STATES_NAME

MAX_LISTED = 8  # recorded runs named when DIR holds several


class ReplayError(RobinPilError):
    """A folder or output that cannot be replayed as asked."""


def states_file(folder: Path) -> Path:
    """``folder``'s states file; :class:`ReplayError` naming the problem and what to give."""
    folder = Path(folder)
    if not folder.exists():
        raise ReplayError(
            f"DIR {quote(str(folder))} does not exist; give an episode's --out "
            "folder or a live session's folder"
        )
    if not folder.is_dir():
        raise ReplayError(
            f"DIR {quote(str(folder))} is a file; give the folder that holds {STATES_NAME} "
            "(an episode's --out folder or a live session's)"
        )
    path = folder / STATES_NAME
    if path.is_file():
        return path
    if os.path.lexists(path):  # a link to /dev/zero, a FIFO, a folder, a dangling link
        raise ReplayError(
            f"{quote(str(path))} is not a regular file (a link to a device or to nothing, a "
            f"FIFO or a folder); a run writes {STATES_NAME} as a file: replay another run"
        )
    inside = sorted(p.parent for p in folder.glob(f"**/{STATES_NAME}"))
    if inside:
        names = ", ".join(quote(str(p)) for p in inside[:MAX_LISTED])
        more = f" and {len(inside) - MAX_LISTED} more" if len(inside) > MAX_LISTED else ""
        raise ReplayError(
            f"DIR {quote(str(folder))} holds {len(inside)} recorded runs; give "
            f"one of them: {names}{more}"
        )
    if (folder / SUMMARY_NAME).is_file():
        raise ReplayError(
            f"DIR {quote(str(folder))} has no {STATES_NAME}: the run was made "
            "without video (--no-video, --no-video on live) or by a version "
            "without replay; run it again with video to replay it"
        )
    raise ReplayError(
        f"DIR {quote(str(folder))} is not a run's folder (no {SUMMARY_NAME}, no {STATES_NAME}); "
        "give an episode's --out folder or a live session's"
    )


def output_file(out: Path) -> Path:
    """Where the replayed MP4 goes: a new ``.mp4`` file in an existing folder."""
    out = Path(out)
    if out.suffix.lower() != ".mp4":
        raise ReplayError(f"--out {quote(str(out))}: give a file name ending in .mp4")
    if out.exists():
        raise ReplayError(
            f"--out {quote(str(out))} exists already; a replay never overwrites "
            "a file: give another name"
        )
    if not out.parent.is_dir():
        raise ReplayError(f"--out {quote(str(out))}: folder {quote(str(out.parent))} not found")
    return out
