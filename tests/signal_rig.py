"""A ``robin-pil`` command as a real process in its own process group, signalled, and what it
left: exit code, seconds from the signal to the exit, stderr, and the processes of its group
still alive afterwards (orphans), read from ``/proc`` (no psutil).

:func:`start` runs ``python -m robin_sim.cli.main ARGV`` with ``start_new_session`` (the group
is the process's pid, as a terminal's job); ``sigint_ignored`` starts it as a shell starts a
background job (``cmd &`` in a script, ``nohup cmd &``): SIGINT ignored, inherited through
``exec``. :func:`signal_when` waits for a condition (or a time), sends the signal to the group
or to the process alone, and returns an :class:`Outcome`.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

EXIT_WITHIN_S = 5.0  # the promise: exit 130 within 5 s of the signal
GIVE_UP_S = 30.0  # a run still there this long after the signal is killed (and reported)
ORPHAN_GRACE_S = 3.0  # how long the group's other processes may take to end after the exit


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _default_sigint() -> None:
    """As a terminal starts a job in the foreground, even if this process ignores SIGINT
    (started itself as a background job): the disposition would be inherited."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@dataclass
class Started:
    """A started command: its process, and the files its stdout and stderr go to (files, not
    pipes: an orphan holding a pipe open would hold up the read of a process long gone)."""

    process: subprocess.Popen[bytes]
    stdout: Any
    stderr: Any

    @property
    def pid(self) -> int:
        return self.process.pid

    def poll(self) -> int | None:
        return self.process.poll()

    def output(self) -> tuple[str, str]:
        """stdout and stderr so far."""
        texts = []
        for handle in (self.stdout, self.stderr):
            handle.seek(0)
            texts.append(handle.read().decode(errors="replace"))
        return texts[0], texts[1]


def start(argv: Sequence[str], *, sigint_ignored: bool = False, cwd: Path | None = None) -> Started:
    """``robin-pil ARGV`` in its own session and process group."""
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    stdout, stderr = tempfile.TemporaryFile(), tempfile.TemporaryFile()  # noqa: SIM115 (kept by Started)
    process = subprocess.Popen(
        [sys.executable, "-m", "robin_sim.cli.main", *[str(a) for a in argv]],
        stdout=stdout,
        stderr=stderr,
        start_new_session=True,
        preexec_fn=_ignore_sigint if sigint_ignored else _default_sigint,
        cwd=cwd,
        env=env,
    )
    return Started(process, stdout, stderr)


def group_alive(group: int) -> list[int]:
    """The pids of the live (not zombie) processes of process group ``group``."""
    alive = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:  # gone meanwhile
            continue
        fields = stat[stat.rindex(")") + 2 :].split()
        state, pgrp = fields[0], int(fields[2])
        if pgrp == group and state not in ("Z", "X"):
            alive.append(int(entry.name))
    return alive


@dataclass
class Outcome:
    """What a signalled run came to."""

    code: int | None  # None: still running GIVE_UP_S after the signal (then killed)
    seconds: float  # from the signal to the exit
    stdout: str
    stderr: str
    orphans: list[int]  # processes of its group alive ORPHAN_GRACE_S after its exit
    signalled: bool  # False: it had ended before the signal was due

    def problems(self, *, finished_ok: bool = False) -> list[str]:
        """What breaks the promise: exit 130 within 5 s, no traceback, no orphan
        (``finished_ok``: a run that ended with 0 before the signal passes too)."""
        found = []
        if not self.signalled:
            if not (finished_ok and self.code == 0):
                found.append(f"ended with {self.code} before the signal")
        elif self.code is None:
            found.append(f"still running {GIVE_UP_S:g} s after the signal")
        elif self.code != 130:
            found.append(f"exit code {self.code}")
        if self.signalled and self.code is not None and self.seconds > EXIT_WITHIN_S:
            found.append(f"exit after {self.seconds:.1f} s (> {EXIT_WITHIN_S:g} s)")
        if "Traceback" in self.stderr:
            found.append("a traceback")
        if self.orphans:
            found.append(f"orphans {self.orphans}")
        return found


def signal_when(
    run: Started,
    how: signal.Signals | int,
    ready: Callable[[], bool] = lambda: True,
    *,
    after_s: float = 0.0,
    latest_s: float = 120.0,
    to_group: bool = True,
) -> Outcome:
    """Wait ``after_s`` from now, then until ``ready()`` (at most ``latest_s``), send ``how``
    to the group (or the process alone), wait for the exit (at most :data:`GIVE_UP_S`) and
    for the group to empty; a run still there is killed with its group."""
    process = run.process
    group = process.pid
    began = time.monotonic()
    signalled = False
    try:
        while process.poll() is None:
            waited = time.monotonic() - began
            if waited >= after_s and (ready() or waited >= latest_s):
                (os.killpg if to_group else os.kill)(group, how)
                signalled = True
                break
            time.sleep(0.01)
        sent = time.monotonic()
        code: int | None
        try:
            code = process.wait(timeout=GIVE_UP_S if signalled else 120)
        except subprocess.TimeoutExpired:
            code = None
            os.killpg(group, signal.SIGKILL)
            process.wait()
        seconds = time.monotonic() - sent
        deadline = time.monotonic() + ORPHAN_GRACE_S
        while group_alive(group) and time.monotonic() < deadline:
            time.sleep(0.05)
        orphans = group_alive(group)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(group, signal.SIGKILL)  # only this run's own group
        if process.poll() is None:
            process.wait()
    stdout, stderr = run.output()
    return Outcome(code, seconds, stdout, stderr, orphans, signalled)


def lines(path: Path) -> int:
    """Whole lines in ``path`` (0 when it does not exist)."""
    try:
        return path.read_bytes().count(b"\n")
    except OSError:
        return 0
