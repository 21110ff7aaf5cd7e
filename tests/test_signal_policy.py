"""The command's signal policy in this process (:mod:`pil.signal_policy`): a real signal to
this very process, through the real ``robin-pil`` dispatcher, with a stand-in command."""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import threading
import time
import types
from pathlib import Path

import pytest

from pil.signal_policy import blocked_for_children
from robin_sim.cli import main as cli


def _command(monkeypatch: pytest.MonkeyPatch, run: object) -> None:
    """``robin-pil probe``: a command whose ``run`` is ``run``."""
    module = types.ModuleType("signal_probe_command")
    module.add_arguments = lambda parser: None  # type: ignore[attr-defined]
    module.run = run  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, module.__name__, module)
    monkeypatch.setattr(cli, "COMMANDS", {"probe": (module.__name__, "a probe")})


def _signal_self(how: signal.Signals) -> None:
    os.kill(os.getpid(), how)
    time.sleep(2)  # the handler runs at once, in this (main) thread
    raise AssertionError("the signal was not raised")


def test_an_error_the_interrupt_caused_is_reported_as_the_interrupt(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """A signal that lands in a C extension's initialisation comes out of the import as
    ``ImportError: initialization failed`` (seen with MuJoCo's): still exit 130, no trace."""

    def run(args: argparse.Namespace) -> int:
        try:
            _signal_self(signal.SIGTERM)
        except KeyboardInterrupt as interrupt:
            raise ImportError("initialization failed") from interrupt
        return 0

    _command(monkeypatch, run)
    assert cli.main(["probe"]) == 130
    assert capsys.readouterr().err == "robin-pil probe: interrupted; finished work is kept\n"


def test_sigterm_with_sigint_ignored_is_ctrl_c_and_the_handlers_come_back(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    before = signal.getsignal(signal.SIGTERM)
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # as a background job starts
    try:
        for how in (signal.SIGINT, signal.SIGTERM):
            _command(monkeypatch, lambda args, how=how: _signal_self(how))
            assert cli.main(["probe"]) == 130
            assert "interrupted; finished work is kept" in capsys.readouterr().err
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # put back: run from Python
        assert signal.getsignal(signal.SIGTERM) is before
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_signal_inside_an_import_is_raised_once_the_import_is_done(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path
) -> None:
    """The commands import their heavy modules as they run: a signal there must not break
    into the module's code (a half-made module; in a C extension an ``ImportError`` and, at
    exit, Python's death by SIGINT, -2)."""
    name = "signal_probe_slow_import"
    (tmp_path / f"{name}.py").write_text(
        "import os, signal, time\n"
        "os.kill(os.getpid(), signal.SIGTERM)\n"
        "time.sleep(0.3)  # the signal came in here\n"
        "WHOLE = True\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, name, raising=False)
    reached = []

    def run(args: argparse.Namespace) -> int:
        module = __import__(name)
        reached.append(module.WHOLE)
        time.sleep(2)  # the signal again, now outside the import
        raise AssertionError("the signal was lost")

    _command(monkeypatch, run)
    assert cli.main(["probe"]) == 130
    assert reached == [True] and sys.modules[name].WHOLE
    assert "interrupted; finished work is kept" in capsys.readouterr().err


def test_a_signal_while_children_start_is_kept_though_another_thread_takes_it() -> None:
    """Inside ``blocked_for_children`` this thread holds both signals back; a SIGTERM sent to
    the process then goes to another thread (here one that sleeps) and must still reach the
    handler: it was lost while the window set the signals to "ignore"."""
    seen: list[int] = []
    other = threading.Thread(target=time.sleep, args=(3,), daemon=True)
    previous = signal.signal(signal.SIGTERM, lambda signum, frame: seen.append(signum))
    try:
        other.start()
        with blocked_for_children():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.2)  # the other thread has taken it by now
        deadline = time.monotonic() + 5
        while not seen and time.monotonic() < deadline:
            time.sleep(0.01)
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert seen == [signal.SIGTERM]


CHILD_MASK = """
import multiprocessing, signal
from pil.signal_policy import blocked_for_children

def report(conn):
    conn.send(sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])))

if __name__ == "__main__":
    context = multiprocessing.get_context("spawn")
    ours, theirs = context.Pipe()  # a pipe, not a queue: no resource tracker started yet
    with blocked_for_children():  # the first spawn of a fresh interpreter
        child = context.Process(target=report, args=(theirs,))
        child.start()
        held = sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, []))
    print(held, ours.recv())
    child.join()
"""


def test_children_start_with_both_signals_held_back_from_the_first_spawn_on(
    tmp_path: Path,
) -> None:
    """The first spawn of an interpreter also starts multiprocessing's resource tracker, which
    unblocks SIGINT and SIGTERM in its caller; the child must still start with both blocked."""
    script = tmp_path / "child_mask.py"
    script.write_text(CHILD_MASK)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=env
    )
    assert done.returncode == 0, done.stderr
    both = [int(signal.SIGINT), int(signal.SIGTERM)]
    assert done.stdout.strip() == f"{both} {both}", done.stdout  # this thread's, the child's
