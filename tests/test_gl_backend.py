"""Tests of robin_sim.render.gl_backend: backend choice, probing in a subprocess, late binding."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from pil.errors import RobinPilError
from robin_sim.render.gl_backend import GLBackendError, ensure_gl_backend

RENDER_ONE_FRAME = """
import mujoco
model = mujoco.MjModel.from_xml_string(
    '<mujoco><worldbody><light pos="0 0 2"/><geom type="sphere" size=".1"/></worldbody></mujoco>')
data = mujoco.MjData(model)
mujoco.mj_forward(model, data)
with mujoco.Renderer(model, 48, 64) as renderer:
    renderer.update_scene(data)
    assert renderer.render().max() > 0, "blank frame"
print(mujoco.rendering.classic.gl_context.GLContext.__module__)
"""


def _run(code: str, **env_changes: str | None) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env.update({k: v for k, v in env_changes.items() if v is not None})
    return subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )


def test_in_process_backend_is_headless() -> None:
    assert ensure_gl_backend() in ("egl", "osmesa")
    assert os.environ["MUJOCO_GL"] in ("egl", "osmesa")


def test_invalid_backend_names_valid_choices(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MUJOCO_GL", "vulkan")
    with pytest.raises(GLBackendError, match=r"'vulkan'.*egl, osmesa") as info:
        ensure_gl_backend()
    assert isinstance(info.value, RobinPilError)


@pytest.mark.slow
def test_unset_backend_is_probed_and_set_before_mujoco_import() -> None:
    code = (
        "from robin_sim.render.gl_backend import ensure_gl_backend\n"
        "import os, sys\n"
        "assert 'mujoco' not in sys.modules\n"
        "print(ensure_gl_backend(), os.environ['MUJOCO_GL'])\n" + RENDER_ONE_FRAME
    )
    result = _run(code)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["egl", "egl", "mujoco.egl"]
    assert result.stderr == ""  # EGL works here: no fallback message


@pytest.mark.slow
def test_mujoco_imported_first_is_bound_late_to_egl() -> None:
    code = (
        "import mujoco\n"
        "assert mujoco.rendering.classic.gl_context.GLContext.__module__ != 'mujoco.egl'\n"
        "from robin_sim.render.gl_backend import ensure_gl_backend\n"
        "print(ensure_gl_backend())\n" + RENDER_ONE_FRAME
    )
    result = _run(code)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["egl", "mujoco.egl"]


@pytest.mark.slow
def test_broken_egl_falls_back_to_osmesa_or_explains_both_failures() -> None:
    # An EGL vendor file that does not exist makes libglvnd find no EGL driver.
    code = (
        "from robin_sim.render.gl_backend import ensure_gl_backend, GLBackendError\n"
        "try:\n"
        "    print(ensure_gl_backend())\n"
        "except GLBackendError as error:\n"
        "    print('ERROR', error)\n"
    )
    result = _run(code, __EGL_VENDOR_LIBRARY_FILENAMES="/nonexistent/egl_vendor.json")
    assert result.returncode == 0, result.stderr
    if result.stdout.startswith("ERROR"):  # this machine has no OSMesa library
        assert "EGL failed" in result.stdout
        assert "OSMesa failed" in result.stdout
    else:
        assert result.stdout.strip() == "osmesa"
        assert result.stderr.count("EGL rendering is unavailable") == 1
