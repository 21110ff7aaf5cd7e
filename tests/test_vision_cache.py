"""Tests of the render cache: the content key, what it covers, and reuse of rendered chunks."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robin_sim.vision.build import pending
from robin_sim.vision.build_config import MIN_SAMPLES, BuildConfig
from robin_sim.vision.dataset import chunk_path, save_chunk
from robin_sim.vision.render_key import (
    KEY_LENGTH,
    ROOT,
    cache_folder,
    content_key,
    key_inputs,
    render_key,
)

# modules a rendering worker imports that do not shape what a sample shows or stores: the
# learner's package, package inits, the physics controller (a data set is posed kinematically,
# never stepped), the features (computed from the stored crops when a split is loaded), the
# model file's reader (its CLASSES, which a label indexes, are hashed by value) and the key itself
NOT_PICTURES = (
    "pil",
    "robin_sim.closing",
    "robin_sim.control.simulator",
    "robin_sim.control.ik",
    "robin_sim.control.trajectory",
    "robin_sim.vision.features",
    "robin_sim.vision.classifier",
    "robin_sim.vision.render_key",
)


def test_every_module_a_rendering_worker_runs_is_in_the_key() -> None:
    """A worker's code (the render set and all it imports from this project) is hashed by the
    key, so a change of the body, the posture solver, the poses or the cameras re-renders."""
    probe = (
        "import json, sys\n"
        "import robin_sim.vision.render_set\n"
        "print(json.dumps({n: getattr(m, '__file__', None) for n, m in sys.modules.items()\n"
        "    if n.split('.')[0] in ('pil', 'robin_sim')}))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT
    )
    hashed = {p.resolve() for p in key_inputs()}
    missing = [
        name
        for name, file in json.loads(done.stdout).items()
        if file is not None
        and Path(file).resolve() not in hashed
        and Path(file).name != "__init__.py"
        and not any(name == n or name.startswith(n + ".") for n in NOT_PICTURES)
    ]
    assert not missing, f"imported by the renderer but not in the key: {missing}"
    assert (ROOT / "robin_sim" / "model" / "data" / "hand_poses.json").resolve() in hashed
    assert any(p.suffix == ".xml" for p in hashed)  # the scene's files under models/


@settings(max_examples=25, deadline=None)
@given(
    st.binary(min_size=0, max_size=64),
    st.integers(min_value=0, max_value=63),
    st.integers(min_value=1, max_value=255),
)
def test_any_changed_byte_of_an_input_changes_the_key(
    content: bytes, where: int, flip: int
) -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        (root / "a.py").write_bytes(b"pose = 1\n")
        (root / "b.json").write_bytes(content)
        files = [root / "a.py", root / "b.json"]
        key = content_key("<mujoco/>", files, root)
        assert len(key) == KEY_LENGTH and key == content_key("<mujoco/>", files, root)
        assert content_key("<mujoco />", files, root) != key  # another scene
        if content:
            changed = bytearray(content)
            changed[where % len(content)] ^= flip
            (root / "b.json").write_bytes(bytes(changed))
        else:
            (root / "b.json").write_bytes(bytes([flip]))
        assert content_key("<mujoco/>", files, root) != key


def test_a_cache_reuses_chunks_of_its_key_and_seed_only(tmp_path: Path) -> None:
    """Chunks under the checkout's key and seed are reused; the same chunks under another key
    (another body) or for another seed are not: they are pending, to be rendered anew."""
    cache = tmp_path / "c"
    config = BuildConfig(samples=MIN_SAMPLES, seed=3, out=tmp_path / "out", cache=cache)
    assert config.chunks == cache / render_key() / "seed3" == cache_folder(cache, 3)
    assert pending(config) == [("train", 0), ("heldout", 0)]
    arrays: dict[str, np.ndarray | np.generic] = {
        "mask": np.zeros((2, 64, 64), np.uint8),
        "shading": np.zeros((2, 64, 64), np.uint8),
        "relief": np.zeros((2, 64, 64), np.uint8),
        "size": np.zeros((2, 3), np.float32),
        "label": np.zeros(2, np.int64),
        "sample": np.zeros(2, np.int64),
        "eye": np.arange(2),
        "found": np.zeros(2, bool),
        "iou": np.zeros(2),
        "condition": np.zeros((2, 6)),
        "seed": np.int64(3),
    }
    for split in ("train", "heldout"):
        save_chunk(chunk_path(config.chunks, split, 0), arrays)
    assert pending(config) == []
    other_body = cache / ("0" * KEY_LENGTH) / "seed3"
    other_body.parent.mkdir()
    config.chunks.rename(other_body)
    assert pending(config) == [("train", 0), ("heldout", 0)]
    other_body.rename(config.chunks)
    other_seed = BuildConfig(samples=MIN_SAMPLES, seed=4, out=tmp_path / "out", cache=cache)
    assert len(pending(other_seed)) == 2 and pending(config) == []


def test_a_model_of_the_features_before_is_refused_by_name(tmp_path: Path) -> None:
    """A format-2 model (658 features: the shading HOG) cannot read this reader's features:
    loading it names its format and says to retrain."""
    import pytest

    from robin_sim.vision.classifier import CLASSES, FORMAT, GestureModel, ModelFileError

    old = tmp_path / "old.npz"
    rng = np.random.default_rng(0)
    with old.open("wb") as handle:
        np.savez_compressed(
            handle,
            format=np.int64(2),
            classes=np.array(CLASSES),
            mean=np.zeros(658, np.float32),
            scale=np.ones(658, np.float32),
            layers=np.int64(1),
            w0=rng.normal(size=(658, 7)).astype(np.float32),
            b0=np.zeros(7, np.float32),
            threshold=np.float64(0.5),
            seed=np.int64(0),
            samples=np.int64(0),
        )
    assert FORMAT == 4
    with pytest.raises(ModelFileError, match=r"format 2 .*retrain it with 'robin-pil train"):
        GestureModel.load(old)
    same_shape = GestureModel(
        np.zeros(658), np.ones(658), (np.zeros((658, 7)),), (np.zeros(7),), 0.5
    )
    assert "takes 658 features, not the 2458" in same_shape.problem()
