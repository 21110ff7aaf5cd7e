"""Test-wide setup: choose the headless OpenGL backend before any test imports mujoco."""

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()
