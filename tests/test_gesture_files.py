"""train-gestures' files: chunks keyed by seed, damaged chunks and models, capped options."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from robin_sim.cli.main import main
from robin_sim.vision.build import pending
from robin_sim.vision.build_config import BuildConfig
from robin_sim.vision.classifier import GestureModel, ModelFileError, load_shipped, shipped_path
from robin_sim.vision.crops import CROP_SIDE
from robin_sim.vision.dataset import CHUNK, chunk_path, load_split, save_chunk
from robin_sim.vision.features import FEATURE_COUNT

MAX_SAMPLES = 100_000  # robin_sim.vision.build_config.MAX_SAMPLES
CPUS = len(os.sched_getaffinity(0))


def write_chunk(folder: Path, split: str, k: int, seed: int) -> Path:
    """A chunk file in the format render_chunk writes (two eyes per sample)."""
    rows = 2 * CHUNK
    samples = np.repeat(np.arange(k * CHUNK, (k + 1) * CHUNK), 2)
    path = chunk_path(folder, split, k)
    save_chunk(
        path,
        {
            "mask": np.zeros((rows, CROP_SIDE, CROP_SIDE), np.uint8),
            "shading": np.zeros((rows, CROP_SIDE, CROP_SIDE), np.uint8),
            "relief": np.zeros((rows, CROP_SIDE, CROP_SIDE), np.uint8),
            "size": np.zeros((rows, 3), np.float32),
            "label": samples % 7,
            "sample": samples,
            "eye": np.tile([0, 1], CHUNK),
            "found": np.ones(rows, bool),
            "iou": np.ones(rows),
            "condition": np.zeros((rows, 4)),
            "seed": np.int64(seed),
        },
    )
    return path


def test_chunks_of_another_seed_are_rendered_anew(tmp_path: Path) -> None:
    seed0 = BuildConfig(samples=CHUNK, seed=0, out=tmp_path, workers=1)
    for split, k in pending(seed0):
        write_chunk(seed0.chunks, split, k, seed=0)
    assert pending(seed0) == []
    seed5 = BuildConfig(samples=CHUNK, seed=5, out=tmp_path, workers=1)
    assert pending(seed5) == [("train", 0), ("heldout", 0)]  # none reused
    from robin_sim.vision.dataset import ChunkError

    with pytest.raises(ChunkError, match="drawn with seed 0, not 5"):
        load_split(seed5.chunks, "train", CHUNK, seed=5)
    loaded = load_split(seed0.chunks, "train", CHUNK, seed=0)
    assert len(loaded["label"]) == 2 * CHUNK
    assert loaded["features"].shape == (2 * CHUNK, FEATURE_COUNT)  # computed from the crops


def test_a_truncated_chunk_is_a_clear_error_and_rendered_anew(tmp_path: Path) -> None:
    from robin_sim.vision.dataset import ChunkError, chunk_ready, read_chunk

    path = write_chunk(tmp_path, "train", 0, seed=0)
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    assert not chunk_ready(path, 0)
    with pytest.raises(ChunkError, match="damaged or incomplete"):
        read_chunk(path, 0)
    config = BuildConfig(samples=CHUNK, seed=0, out=tmp_path.parent / tmp_path.name, workers=1)
    (tmp_path / "chunks").mkdir()
    shutil.move(path, chunk_path(config.chunks, "train", 0))
    assert ("train", 0) in pending(config)


def broken_models(tmp_path: Path) -> dict[str, Path]:
    model = load_shipped()
    cut = tmp_path / "cut.npz"
    data = shipped_path().read_bytes()
    cut.write_bytes(data[: len(data) // 2])
    transposed = GestureModel(
        model.mean, model.scale, tuple(w.T for w in model.weights), model.biases, model.threshold
    )
    nan = GestureModel(
        model.mean,
        model.scale,
        (model.weights[0] * np.nan, *model.weights[1:]),
        model.biases,
        model.threshold,
    )
    return {
        "cut": cut,
        "transposed": transposed.save(tmp_path / "transposed.npz"),
        "nan": nan.save(tmp_path / "nan.npz"),
    }


@pytest.mark.parametrize(
    ("kind", "needle"),
    [
        ("cut", "damaged or not a model file"),
        ("transposed", f"do not take {FEATURE_COUNT} inputs"),
        ("nan", "NaN or infinite"),
    ],
)
def test_a_damaged_gesture_model_is_refused_clearly(tmp_path: Path, kind: str, needle: str) -> None:
    with pytest.raises(ModelFileError, match=needle) as caught:
        GestureModel.load(broken_models(tmp_path)[kind])
    assert "train-gestures" in str(caught.value)
    assert load_shipped().problem() == ""


def test_the_vision_detector_refuses_a_nan_model(tmp_path: Path) -> None:
    from robin_sim.person.body import PhysicalBody
    from robin_sim.robot.world import PhysicalWorld
    from robin_sim.vision.detector import VisionDetector

    model = load_shipped()
    nan = GestureModel(
        model.mean,
        model.scale,
        model.weights,
        (model.biases[0], model.biases[1] * np.nan),
        model.threshold,
    )
    world = PhysicalWorld()
    body = PhysicalBody(world)
    with pytest.raises(ModelFileError, match="NaN or infinite"):
        VisionDetector(world.sim, display=body.display, seed=3, gesture_model=nan)


@pytest.mark.parametrize(
    ("option", "needle"),
    [
        (["--samples", "10000000"], f"to {MAX_SAMPLES}, got 10000000"),
        (["--samples", "3"], "from 28"),
        (["--workers", "1000"], f"--workers must be a whole number from 1 to {CPUS}"),
        (["--workers", "0"], "got 0"),
        (["--seed=-1"], "--seed must be a whole number from 0"),
        (["--out", "/proc/robin-pil-x"], "cannot be written"),
        (["--out", "/tmp/" + "x" * 300], "cannot be written"),
    ],
)
def test_train_gestures_refuses_bad_options_with_exit_2(
    option: list[str], needle: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(
        ["train-gestures", "--quiet", "--samples", "28", "--out", str(tmp_path / "g"), *option]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert err.count("\n") == 0 and needle in err, err
    assert not (tmp_path / "g").exists()
