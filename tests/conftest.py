"""Test-wide setup: choose the headless OpenGL backend before any test imports mujoco; leave
the signal handling of the test process as each test found it."""

from __future__ import annotations

import signal
import warnings
from collections.abc import Iterator

import pytest

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

_WATCHED = (signal.SIGINT, signal.SIGTERM)


@pytest.fixture(autouse=True)
def _signals_as_found(request: pytest.FixtureRequest) -> Iterator[None]:
    """Restore SIGINT / SIGTERM handling (dispositions and the main thread's mask) after each
    test, and warn naming a test that changed it: an ignored or blocked signal is inherited by
    every process started later, and the interrupt tests' episodes would not hear Ctrl-C."""
    handlers = {s: signal.getsignal(s) for s in _WATCHED}
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    yield
    changed = {s.name for s in _WATCHED if signal.getsignal(s) != handlers[s]}
    if signal.pthread_sigmask(signal.SIG_BLOCK, []) != mask:
        changed.add("mask")
    if changed:
        for signum, handler in handlers.items():
            if handler is not None:
                signal.signal(signum, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        warnings.warn(
            f"{request.node.nodeid} left {sorted(changed)} changed (restored)", stacklevel=1
        )
