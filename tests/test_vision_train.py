"""Tests of train-gestures: reproducible from its seed, resumable, bad input, the shipped model."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robin_sim.vision.build import pending, render_all, train_and_report
from robin_sim.vision.build_config import MIN_SAMPLES, BuildConfig
from robin_sim.vision.classifier import CLASSES, GestureModel, ModelFileError, load_shipped
from robin_sim.vision.dataset import (
    CHUNK,
    HANDOVER_HAND,
    SPLITS,
    chunk_path,
    sample_spec,
)


def _arrays(model: GestureModel) -> list[np.ndarray]:
    return [model.mean, model.scale, *model.weights, *model.biases]


@pytest.mark.slow
def test_same_seed_rebuilds_the_same_model_and_runs_resume(tmp_path: Path) -> None:
    first = BuildConfig(samples=MIN_SAMPLES, seed=5, out=tmp_path / "a", workers=2)
    assert render_all(first) == 2  # one training and one held-out chunk
    result = train_and_report(first)
    again = BuildConfig(samples=MIN_SAMPLES, seed=5, out=tmp_path / "b", workers=1)
    render_all(again)
    train_and_report(again)
    a = GestureModel.load(first.out / "gesture_model.npz")
    b = GestureModel.load(again.out / "gesture_model.npz")
    for x, y in zip(_arrays(a), _arrays(b), strict=True):
        np.testing.assert_array_equal(x, y)
    # resumable: a finished chunk is kept, a lost one is rendered again (and only that one)
    chunk_path(first.chunks, "heldout", 0).unlink()
    assert pending(first) == [("heldout", 0)]
    assert render_all(first) == 1 and not pending(first)
    report = (first.out / "report.md").read_text()
    assert "held-out" in report and (first.out / "confusion.png").stat().st_size > 1000
    measured = json.loads((first.out / "measured.json").read_text())
    assert len(measured["confusion"]) == 4 and all(len(r) == 5 for r in measured["confusion"])
    assert 0.0 <= result["heldout_accuracy"] <= 1.0
    other = BuildConfig(samples=MIN_SAMPLES, seed=6, out=tmp_path / "c", workers=2)
    render_all(other)
    train_and_report(other)
    c = GestureModel.load(other.out / "gesture_model.npz")
    assert not np.array_equal(a.weights[0], c.weights[0])


def test_splits_vary_every_factor_across_its_range_and_hold_out_light() -> None:
    """Training samples span every skin tone, pose jitter up to more than twice the usual and
    hands held up to 16 cm above their place (the factor bench's levels lie inside), a quarter
    each above a place, drawn back and raised, at the handover point and in the working box;
    the held-out split's light is never in the training ranges."""
    from robin_sim.vision.factors import FACTORS

    def inside(value: float, intervals: tuple[tuple[float, float], ...]) -> bool:
        return any(lo <= value <= hi for lo, hi in intervals)

    train = [sample_spec(0, "train", i) for i in range(600)]
    skin = np.array([s.skin for s in train])
    jitter = np.array([s.jitter for s in train])
    lift = np.array([s.lift for s in train])
    assert skin.min() < 0.05 and skin.max() > 3.95
    assert np.histogram(skin, bins=4, range=(0, 4))[0].min() > 100  # every tone, evenly
    assert jitter.min() < 0.05 and jitter.max() > 2.4 and (jitter > 2.0).sum() > 50
    assert lift.min() < -0.03 and lift.max() > 0.15 and (lift > 0.12).sum() > 50
    drawn_back = [s for s in train if abs(s.hand[0] - 0.95) < 0.07 and s.hand[2] > 1.0]
    assert len(drawn_back) > 110  # where Robin reads a pointing in an episode
    at_palm = [s for s in train if np.linalg.norm(s.hand - HANDOVER_HAND) < 0.08]
    assert len(at_palm) > 110  # where the palm is held out: give me, release, thumbs
    labels = {s.label for s in at_palm}
    assert labels == set(range(len(CLASSES)))  # every class is shown there too
    ranges = SPLITS["train"]
    trained = {"skin": ranges.skin, "jitter": (ranges.jitter,), "lift": (ranges.lift,)}
    for field, levels in FACTORS.values():  # the bench's levels lie in the trained ranges
        assert all(inside(level, trained[field]) for level in levels), field
    for i in range(200):
        held = sample_spec(0, "heldout", i)
        assert not inside(held.lighting, SPLITS["train"].lighting)
        assert not inside(held.light_tilt, ((0.0, 0.5 - 1e-9),))
    a, b = sample_spec(0, "train", 7), sample_spec(0, "train", 7)  # same seed, same sample
    assert a.seed == b.seed and np.array_equal(a.hand, b.hand) and a.skin == b.skin
    assert a.jitter == b.jitter and a.lift == b.lift
    assert [sample_spec(0, "train", i).label for i in range(7)] == list(range(7))
    assert CHUNK > 0


def test_the_handover_place_puts_the_palm_where_the_person_holds_it_out() -> None:
    """The data set's handover hand puts the model's palm site on the scene's handover point,
    within the person's jitter of where ``PhysicalBody`` holds the palm out for "give me"."""
    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()
    import mujoco

    from robin_sim.model import names
    from robin_sim.model.scene import DEFAULT_HANDOVER, build_model
    from robin_sim.person.body import PALM_JITTER

    model = build_model()
    data = mujoco.MjData(model)
    mocap = int(model.body_mocapid[model.body(names.HUMAN_MOCAP_BODY).id])
    data.mocap_pos[mocap] = HANDOVER_HAND
    mujoco.mj_kinematics(model, data)
    np.testing.assert_allclose(data.site(names.HUMAN_PALM_SITE).xpos, DEFAULT_HANDOVER, atol=1e-9)
    assert PALM_JITTER < 0.02  # the data set's spread (sd 2 cm) covers the person's


def test_the_data_sets_places_are_the_scenes() -> None:
    """The data set draws hands where the scene has its legs and spots (one source: the
    layout's defaults), with the values the shipped model's data were drawn with."""
    from robin_sim.vision.dataset import PLACES

    legs = [[0.44, y, 0.77] for y in (0.19, 0.31, 0.43, 0.55)]
    spots = [[0.68, y, 0.76] for y in (0.13, 0.25, 0.37, 0.49)]
    np.testing.assert_allclose(PLACES, legs + spots, atol=1e-12)
    np.testing.assert_allclose(HANDOVER_HAND, [0.63, 0.0, 0.868], atol=1e-12)


def test_a_factor_level_fixes_one_field_of_every_sample() -> None:
    """The factor bench's override sets the field; ``lift`` raises the hand where it is held;
    the condition sweep holds jitter at 1 and lift at 0."""
    from dataclasses import replace

    from robin_sim.vision.factors import FACTORS

    for i in range(50):
        spec = sample_spec(0, "heldout", i)
        for field, levels in FACTORS.values():
            fixed = replace(spec, **{field: levels[-1]})
            assert getattr(fixed, field) == levels[-1]
        lifted = replace(spec, lift=0.12)
        np.testing.assert_allclose(lifted.held_at, spec.hand + np.array([0.0, 0.0, 0.12]))
        swept = sample_spec(0, "sweep", i)
        assert swept.jitter == 1.0 and swept.lift == 0.0
        np.testing.assert_array_equal(swept.held_at, swept.hand)


def test_train_gestures_rejects_too_few_samples_with_exit_2(tmp_path: Path) -> None:
    out = tmp_path / "g"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            "train-gestures",
            "--samples",
            "3",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert "train-gestures: error: --samples must be a whole number from 28" in done.stderr
    assert not out.exists()


def test_shipped_model_is_small_and_loads(tmp_path: Path) -> None:
    model = load_shipped()
    assert model.weights[-1].shape[1] == len(CLASSES) and 0 < model.threshold < 1
    assert model.samples >= 1000
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a model")
    with pytest.raises(ModelFileError, match="cannot read gesture model"):
        GestureModel.load(bad)


@pytest.mark.slow
def test_vision_conditions_measures_and_studies_each_condition(tmp_path: Path) -> None:
    from robin_sim.vision.conditions import run_conditions

    written = run_conditions(
        tmp_path, samples=MIN_SAMPLES, reps=2, lighting=(1.0,), noise=(0.0, 120.0)
    )
    assert sorted(p.name for p in written) == sorted(
        ["conditions.csv", "conditions_runs.csv", "conditions.md", "tests.csv", "conditions.png"]
    )
    rows = (tmp_path / "conditions.csv").read_text().splitlines()
    assert len(rows) == 3  # header and the two conditions
    for noise in ("0", "120"):
        data = json.loads((tmp_path / f"measured-l1-n{noise}.json").read_text())
        assert all(abs(sum(r) - 1) < 1e-4 for r in data["confusion"])
    clean, noisy = (
        json.loads((tmp_path / f"measured-l1-n{n}.json").read_text()) for n in ("0", "120")
    )

    def rate(d: dict) -> float:
        return sum(row[i] for i, row in enumerate(d["confusion"])) / 4

    assert rate(noisy) < rate(clean)  # heavy sensor noise lowers the measured detection rate


def test_vision_conditions_rejects_bad_lists_with_exit_2(tmp_path: Path) -> None:
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "robin_sim.cli.main",
            "vision-conditions",
            "--lighting",
            "dim",
            "--out",
            str(tmp_path / "v"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert "robin-pil vision-conditions: error: --lighting: give numbers" in done.stderr


@pytest.mark.slow
def test_interrupted_training_keeps_finished_chunks_and_resumes(tmp_path: Path) -> None:
    import signal
    import time

    out = tmp_path / "g"
    command = [
        sys.executable,
        "-m",
        "robin_sim.cli.main",
        "train-gestures",
        "--samples",
        "96",
        "--out",
        str(out),
        "--workers",
        "1",
        "--quiet",
    ]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 240

    def finished() -> list[Path]:  # whole chunk files (a chunk being written is *.partial.npz)
        return [p for p in (out / "chunks").glob("train-*.npz") if "partial" not in p.name]

    while not finished() and time.monotonic() < deadline:
        time.sleep(0.2)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 130, err
    assert "interrupted; finished work is kept" in err
    kept = sorted(p.name for p in (out / "chunks").glob("*.npz"))
    assert kept and not any("partial" in name for name in kept)
    assert not (out / "gesture_model.npz").exists()
    config = BuildConfig(samples=96, out=out, workers=1)
    assert len(pending(config)) == 3 - len(kept)  # two training chunks and one held-out
    before = {name: (out / "chunks" / name).stat().st_mtime_ns for name in kept}
    done = subprocess.run(command, capture_output=True, text=True, check=False, timeout=600)
    assert done.returncode == 0, done.stderr
    assert all((out / "chunks" / n).stat().st_mtime_ns == t for n, t in before.items())
    assert (out / "gesture_model.npz").exists() and not pending(config)
