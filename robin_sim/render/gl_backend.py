"""Choose MuJoCo's headless OpenGL backend before anything renders.

MuJoCo binds its OpenGL context class when ``mujoco`` is first imported, from the ``MUJOCO_GL``
environment variable. Every entry point that renders (the ``episode`` command, the render bench,
the rendering tests) therefore calls :func:`ensure_gl_backend` first, before importing
``mujoco``::

    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()  # sets MUJOCO_GL=egl, or osmesa when EGL cannot make a context
    import mujoco

Rules:

* ``MUJOCO_GL`` set by the user to ``glfw`` or ``glx``: respected as is, nothing is probed.
* Set to ``egl`` or ``osmesa``: probed once (a subprocess, about a second); when it cannot
  make a context, the other headless backend is probed and used with one note on stderr, and
  if neither works, :class:`GLBackendError` (exit 2) names both reasons.
* ``PYOPENGL_PLATFORM`` left over with another value (e.g. ``osmesa`` in a shell where EGL is
  chosen): set to the chosen backend with one note (MuJoCo's EGL and OSMesa modules refuse a
  mismatched value).
* Unset: EGL is probed in a short-lived subprocess (a failing EGL driver can abort the process
  that tries it, so the probe never runs in ours); if it cannot make a context, OSMesa is probed
  the same way and chosen with one message on stderr; if neither works, :class:`GLBackendError`.
  The choice is written to ``os.environ`` so that child processes (sweep workers) inherit it and
  later calls return at once.
* ``mujoco`` imported earlier with another backend bound (e.g. by a library or a test module
  imported first): the EGL/OSMesa context class is bound late, before any renderer exists.
"""

from __future__ import annotations

import os
import subprocess
import sys

from pil.errors import RobinPilError
from pil.signal_policy import blocked_for_children

HEADLESS_BACKENDS: tuple[str, ...] = ("egl", "osmesa")
VALID_BACKENDS: tuple[str, ...] = ("egl", "osmesa", "glfw", "glx")
PROBE_TIMEOUT_S = 30.0
# set to the backend once it has been probed in this process tree (children skip the probe)
VERIFIED = "ROBIN_PIL_GL_VERIFIED"

# Creates and frees a 16x16 context with the backend named in MUJOCO_GL (set by the caller).
_PROBE_CODE = """
import mujoco
context = mujoco.GLContext(16, 16)
context.make_current()
context.free()
"""


class GLBackendError(RobinPilError):
    """No usable OpenGL backend for off-screen rendering."""


def _probe(backend: str) -> str | None:
    """Try ``backend`` in a subprocess; None when it made a context, else the reason."""
    env = dict(os.environ, MUJOCO_GL=backend, PYOPENGL_PLATFORM=backend)
    try:  # deaf to a Ctrl-C or SIGTERM to the group: that is this process's to act on
        with blocked_for_children(spawning=False):
            result = subprocess.run(
                [sys.executable, "-c", _PROBE_CODE],
                env=env,
                capture_output=True,
                text=True,
                timeout=PROBE_TIMEOUT_S,
                check=False,
            )
    except subprocess.TimeoutExpired:
        return f"no context within {PROBE_TIMEOUT_S:.0f} s"
    if result.returncode == 0:
        return None
    lines = [line for line in result.stderr.strip().splitlines() if line.strip()]
    return lines[-1] if lines else f"exit code {result.returncode}"


def _bind_late(backend: str) -> None:
    """Point an already imported ``mujoco`` at the context class of ``backend``."""
    from mujoco.rendering.classic import gl_context

    bound = getattr(gl_context, "GLContext", None)
    if bound is not None and bound.__module__ == f"mujoco.{backend}":
        return
    if "OpenGL" in sys.modules and os.environ.get("PYOPENGL_PLATFORM", "") != backend:
        raise GLBackendError(
            f"mujoco and PyOpenGL were imported before MUJOCO_GL={backend} was set; call "
            "robin_sim.render.gl_backend.ensure_gl_backend() before importing mujoco, or set "
            f"MUJOCO_GL={backend} in the environment"
        )
    os.environ.setdefault("PYOPENGL_PLATFORM", backend)
    if backend == "egl":
        from mujoco.egl import GLContext
    else:
        from mujoco.osmesa import GLContext
    gl_context.GLContext = GLContext


def ensure_gl_backend() -> str:
    """Make sure MuJoCo renders headless; return the backend name (``"egl"`` or ``"osmesa"``).

    Call it before ``import mujoco`` in every entry point that renders. Cheap after the first
    call (the choice lives in ``MUJOCO_GL``).
    """
    chosen = os.environ.get("MUJOCO_GL", "").strip().lower()
    if chosen and chosen not in VALID_BACKENDS:
        valid = ", ".join(VALID_BACKENDS)
        raise GLBackendError(f"MUJOCO_GL={chosen!r} is not a backend; valid choices: {valid}")
    if not chosen or (chosen in HEADLESS_BACKENDS and os.environ.get(VERIFIED) != chosen):
        chosen = _working_backend(chosen or None)
        os.environ["MUJOCO_GL"] = os.environ[VERIFIED] = chosen
    if chosen in HEADLESS_BACKENDS:
        platform = os.environ.get("PYOPENGL_PLATFORM", "").strip().lower()
        if platform and platform != chosen and "OpenGL" not in sys.modules:
            print(
                f"robin-pil: PYOPENGL_PLATFORM={platform} does not match the {chosen} "
                f"backend; using PYOPENGL_PLATFORM={chosen}",
                file=sys.stderr,
            )
            os.environ["PYOPENGL_PLATFORM"] = chosen
        os.environ.setdefault("PYOPENGL_PLATFORM", chosen)
        if "mujoco" in sys.modules:
            _bind_late(chosen)
    return chosen


def _working_backend(asked: str | None) -> str:
    """``asked`` (or EGL) if it makes a context, else the other headless backend with a note;
    :class:`GLBackendError` naming both reasons when neither does."""
    first = asked or "egl"
    second = HEADLESS_BACKENDS[1 - HEADLESS_BACKENDS.index(first)]
    first_problem = _probe(first)
    if first_problem is None:
        return first
    second_problem = _probe(second)
    names = {"egl": "EGL", "osmesa": "OSMesa"}
    if second_problem is not None:
        raise GLBackendError(
            f"no headless OpenGL backend works: {names[first]} failed ({first_problem}); "
            f"{names[second]} failed ({second_problem}). Install the Mesa EGL or OSMesa "
            "libraries (e.g. libegl1, libosmesa6)"
        )
    why = f"MUJOCO_GL={asked} does not work here" if asked else "EGL rendering is unavailable"
    slower = " (slower software rendering)" if second == "osmesa" else ""
    print(f"robin-pil: {why} ({first_problem}); using {names[second]}{slower}", file=sys.stderr)
    return second
