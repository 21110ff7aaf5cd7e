"""The content key of a rendered data set: what the samples' pictures depend on, hashed.

A rendered chunk (:mod:`robin_sim.vision.render_set`) depends on the compiled scene (the
person's body and hand, Robin, the table, the lights), the hand poses file, the eye cameras
(size, field of view, noise), the person's posture solver, the head's aiming, the actions and
the person's moves that reach the held-leg arm state, the data set's
sample spec (places, ranges, chunk size) and the crops it stores. :func:`render_key` hashes all
of them: the compiled scene's XML, every file under ``models/`` (meshes and textures the XML
names), the source of every module that shapes a picture (:data:`SOURCES`), the data files of
the figure, the classes (by value: a sample's label indexes them) and the MuJoCo version. A
cache folder named by the key (:func:`cache_folder`) is reused only while all of it is
unchanged: a changed body, pose, camera or spec gives a new key, so the data set is rendered
anew; the seed names a folder of its own below the key.

The key is conservative: any edit of a listed source file (a comment too) re-renders. The
features are not in the key: they are computed from the stored crops when a split is loaded.
"""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path

import mujoco

ROBIN_SIM_DIR = Path(__file__).resolve().parents[1]  # robin_sim/
ROOT = ROBIN_SIM_DIR.parent
# every module whose code changes what a rendered sample shows or stores
SOURCES = (
    "figure",  # the articulated hand, its poses, the posture solver
    "model",  # the scene, the person's joints
    "person",  # the gestures; the body's moves that reach the held-leg arm state
    "robot",  # the actions that reach it
    "control",  # the head's aiming, the controllers
    "render/renderer.py",
    "render/frame_spec.py",
    "render/gl_backend.py",
    "vision/dataset.py",
    "vision/render_set.py",
    "vision/eyes.py",
    "vision/condition_params.py",
    "vision/segment.py",
    "vision/crops.py",
    "vision/arm_states.py",
    "vision/reader.py",
)
KEY_LENGTH = 16  # hex digits of the sha256 kept in the folder name


def _files(entry: Path) -> list[Path]:
    if entry.is_dir():
        return sorted(
            p
            for p in entry.rglob("*")
            if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"
        )
    return [entry]


def key_inputs() -> list[Path]:
    """The files the key hashes (besides the compiled scene's XML), in a fixed order."""
    files = [f for name in SOURCES for f in _files(ROBIN_SIM_DIR / name)]
    return files + _files(ROOT / "models")


def content_key(scene_xml: str, files: list[Path], root: Path = ROOT) -> str:
    """Hash of the MuJoCo version, ``scene_xml`` and each file's name (relative to ``root``)
    and bytes, in the order given (hex, :data:`KEY_LENGTH` digits)."""
    digest = hashlib.sha256()
    digest.update(f"mujoco {mujoco.__version__}\n".encode())
    digest.update(scene_xml.encode())
    for path in files:
        digest.update(f"\n{path.relative_to(root).as_posix()}\n".encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:KEY_LENGTH]


def scene_xml() -> str:
    """The compiled default scene as MuJoCo writes it back (every body, geom and light)."""
    from robin_sim.model.scene import build_spec

    spec = build_spec()
    spec.compile()
    return str(spec.to_xml())


@cache
def render_key() -> str:
    """The content key of this checkout's rendered samples (:func:`content_key` of the
    compiled scene, the classes in the order a sample's label indexes them, and
    :func:`key_inputs`)."""
    from robin_sim.vision.classifier import CLASSES

    return content_key(f"{scene_xml()}\nclasses {CLASSES}", key_inputs())


def cache_folder(root: Path, seed: int) -> Path:
    """Where the chunks of ``seed`` rendered by this checkout live under the cache ``root``."""
    return root / render_key() / f"seed{seed}"
