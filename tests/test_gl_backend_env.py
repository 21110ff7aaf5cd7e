"""A shell's rendering variables that do not fit this machine: a working backend with one note,
or one clear error and exit 2, never a traceback.

OSMesa is made unloadable for real: a folder of broken ``libOSMesa.so*`` files first on
``LD_LIBRARY_PATH`` (PyOpenGL tries exactly those names with ``dlopen``).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
RENDER = (
    "from robin_sim.render.gl_backend import ensure_gl_backend\n"
    "print(ensure_gl_backend())\n"
    "import mujoco\n"
    "context = mujoco.GLContext(16, 16)\n"
    "context.make_current()\n"
    "context.free()\n"
)


@pytest.fixture()
def no_osmesa(tmp_path: Path) -> Path:
    for suffix in ["", *(f".{k}" for k in range(10))]:
        (tmp_path / f"libOSMesa.so{suffix}").write_text("not a library\n")
    return tmp_path


def run(argv: list[str], **env: str) -> subprocess.CompletedProcess[str]:
    base = {
        k: v
        for k, v in os.environ.items()
        if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM", "ROBIN_PIL_GL_VERIFIED")
    }
    return subprocess.run(
        [sys.executable, *argv],
        capture_output=True,
        text=True,
        timeout=180,
        env={**base, "PYTHONPATH": str(ROOT), **env},
    )


def test_mujoco_gl_osmesa_without_osmesa_falls_back_to_egl(no_osmesa: Path) -> None:
    done = run(["-c", RENDER], MUJOCO_GL="osmesa", LD_LIBRARY_PATH=str(no_osmesa))
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "egl"
    assert done.stderr.count("MUJOCO_GL=osmesa does not work here") == 1, done.stderr
    assert "Traceback" not in done.stderr


def test_a_leftover_pyopengl_platform_is_corrected_with_a_note() -> None:
    done = run(["-c", RENDER], PYOPENGL_PLATFORM="osmesa")
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "egl"
    assert "PYOPENGL_PLATFORM=osmesa does not match the egl backend" in done.stderr


def test_no_working_backend_is_one_line_exit_2(no_osmesa: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    done = run(
        [
            "-m",
            "robin_sim.cli.main",
            "episode",
            "--scenario",
            "one_handover",
            "--quiet",
            "--out",
            str(out),
        ],
        MUJOCO_GL="osmesa",
        LD_LIBRARY_PATH=str(no_osmesa),
        __EGL_VENDOR_LIBRARY_FILENAMES="/nonexistent/egl_vendor.json",
    )
    assert done.returncode == 2, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("robin-pil episode: error: no headless"), lines
    assert "OSMesa failed" in lines[0] and "EGL failed" in lines[0]
    assert not out.exists()
