"""The eye cameras in use: the pointing hand in view, vision sweeps, the reading in the video.

Real MuJoCo, EGL renders, the shipped gesture model, real sweeps and decoded H.264.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import av
import numpy as np
import pytest

from pil.task.world import Target
from pil.types import Gesture
from robin_sim.cli import main as cli
from robin_sim.render.gl_backend import ensure_gl_backend
from robin_sim.vision.picture import (
    DISCARDED_COLOUR,
    KEPT_COLOUR,
    box_colour,
    placed_box,
    reading_picture,
)

ONE_HANDOVER = Path(__file__).resolve().parents[1] / "scenarios" / "one_handover.yaml"
COMMANDS = {name: cli.COMMANDS[name] for name in ("sweep", "study", "report")}
EYE = 112  # the eye cameras' image side (robin_sim.vision.eyes.EYE_SIZE)
# levels (0..255) by which the box's colour must stand out on its outline over the pixels a
# few pixels inside and outside it, after H.264 (crf 23, yuv420p) in the decoded video
BOX_CONTRAST = 40.0


@pytest.fixture(scope="module", autouse=True)
def _gl() -> None:
    ensure_gl_backend()


@pytest.fixture
def robin(monkeypatch):
    """``robin(*argv)`` -> exit code of ``robin-pil`` run in this process."""
    monkeypatch.setattr(cli, "COMMANDS", COMMANDS)
    return lambda *argv: cli.main([str(a) for a in argv])


# --- the pointing hand is in view -------------------------------------------------------------
@pytest.mark.slow
def test_the_pointing_hand_is_seen_above_every_leg_and_spot() -> None:
    """Drawn back and raised, the pointing hand is found by both eyes and read as pointing
    above each of the table's legs and spots (the left ones were hidden behind Robin's left
    upper arm with the hand held lower), and the person's hand touches nothing of the robot."""
    from robin_sim.model.robot_spec import POINT_OFFSET
    from robin_sim.person.body import PERSON_CLEAR_X, POINT_RAISE, PhysicalBody
    from robin_sim.robot.targets import target_point
    from robin_sim.robot.world import PhysicalWorld
    from robin_sim.vision.detector import VisionDetector

    world = PhysicalWorld()
    world.start_table(0)
    body = PhysicalBody(world)
    detector = VisionDetector(world.sim, display=body.display, seed=3)
    targets = [Target("leg", k) for k in range(4)] + [Target("spot", k) for k in range(4)]
    try:
        for target in targets:
            where = target_point(target, world.layout, world.legs.position, world.legs.nearest)
            body.perform(Gesture.POINTING, target)
            held = world.human.pose().translation()
            assert held[0] == pytest.approx(PERSON_CLEAR_X, abs=1e-6)  # drawn back ...
            assert held[2] == pytest.approx(where[2] + POINT_OFFSET[2] + POINT_RAISE, abs=1e-6)
            read = detector.detect(Gesture.POINTING)
            boxes = detector.records[-1].boxes
            assert all(box is not None for box in boxes), f"{target}: an eye lost the hand"
            assert read is Gesture.POINTING, f"{target}: read {read}"
            body.rest()
    finally:
        detector.close()
    assert world.person_contacts.events == 0


# --- refusals --------------------------------------------------------------------------------
def test_vision_is_refused_where_there_are_no_cameras(robin, capsys, tmp_path) -> None:
    out = tmp_path / "learner"
    assert robin("sweep", "--detector", "vision", "--reps", "1", "--out", out) == 2
    error = capsys.readouterr().err
    assert "robin-pil sweep: error:" in error and "'vision' reads with Robin's eye cameras" in error
    assert "sweep --kind physical" in error and "measured:FILE" in error
    assert not out.exists()
    assert robin("study", "--detector", "vision", "--out", tmp_path / "study") == 2
    error = capsys.readouterr().err
    assert "robin-pil study: error: --detector" in error and "got 'vision'" in error
    assert "measured:FILE" in error
    assert not (tmp_path / "study").exists()


def test_a_vision_sweep_refuses_rates_and_a_second_detector(robin, capsys, tmp_path) -> None:
    out = tmp_path / "out"
    base = ["sweep", "--kind", "physical", "--systems", "pil", "--reps", "1", "--out", out]
    assert robin(*base, "--detector", "vision", "--rates", "0.5,1.0") == 2
    error = capsys.readouterr().err
    assert "the eye cameras measure the detection rate" in error and "lighting=" in error
    assert robin(*base, "--detector", "vision", "--param", "detector=exact") == 2
    assert "either with --detector or --param detector" in capsys.readouterr().err
    assert robin(*base, "--param", "lighting=0.5") == 2
    assert "need --detector vision" in capsys.readouterr().err
    assert robin(*base, "--detector", "vision", "--param", "lighting=9") == 2
    assert "--param lighting must be a number in [0, 5], got '9'" in capsys.readouterr().err
    assert not out.exists()


# --- a physical sweep reads with the eye cameras ---------------------------------------------
@pytest.mark.slow
def test_a_physical_sweep_reads_with_the_eye_cameras(robin, capsys, tmp_path) -> None:
    # the scenario by name: a run's seed comes from its id, which holds the parameter's text
    # (a path would make the seed, and so the run, depend on where the repository lies)
    out = tmp_path / "vision"
    argv = [
        "sweep",
        "--kind",
        "physical",
        "--detector",
        "vision",
        "--systems",
        "pil",
        "--reps",
        "1",
        "--param",
        "scenario=one_handover",
        "--param",
        "lighting=0.5",
        "--workers",
        "1",
        "--quiet",
        "--no-report",
        "--out",
        out,
    ]
    assert robin(*argv) == 0
    with (out / "results.csv").open(newline="") as handle:
        (row,) = list(csv.DictReader(handle))
    assert row["status"] == "ok" and row["detector"] == "vision" and row["rate"] == "1.0"
    assert float(row["lighting"]) == 0.5 and float(row["vision_lighting"]) == 0.5
    assert row["legs_delivered"] == "1"
    assert int(row["vision_gestures_read"]) == int(row["gestures"])
    assert 0.0 < float(row["vision_detection_rate"]) <= 1.0
    wrong = sum(int(row[f"vision_{k}"]) for k in ("discarded", "no_hand", "misread"))
    right = int(row["gestures"]) - wrong  # the four outcomes add up to the gestures
    assert float(row["vision_detection_rate"]) == pytest.approx(right / int(row["gestures"]))
    assert {"vision_feedback_misread", "vision_feedback_read"} <= set(row)
    capsys.readouterr()


# --- the reading in the video's eye inset ----------------------------------------------------
def test_the_reading_picture_draws_the_box_where_the_reading_found_the_hand() -> None:
    view = np.full((EYE, EYE, 3), 90, np.uint8)
    box = (40, 30, 24, 36)
    for discarded in (False, True):
        picture = reading_picture(view, box, "pointing 0.93", discarded, (160, 120))
        assert picture.shape == (120, 160, 3)
        x0, y0, x1, y1 = placed_box(box, EYE, (160, 120))
        assert (x0, y0) == (20 + round(40 * 120 / EYE), round(30 * 120 / EYE))
        colour = DISCARDED_COLOUR if discarded else KEPT_COLOUR
        middle_y, middle_x = (y0 + y1) // 2, (x0 + x1) // 2
        for y, x in ((middle_y, x0), (middle_y, x1), (y0, middle_x), (y1, middle_x)):
            assert tuple(picture[y, x]) == colour  # on the outline
        assert tuple(picture[middle_y, middle_x]) == (90, 90, 90)  # inside: the view
        assert tuple(picture[middle_y, 5]) == (0, 0, 0)  # beside the square view: black


def _ring(picture: np.ndarray, box: tuple[int, int, int, int], grow: int) -> np.ndarray:
    """The pixels on the outline of ``box`` (x0, y0, x1, y1) grown by ``grow`` pixels."""
    x0, y0, x1, y1 = box[0] - grow, box[1] - grow, box[2] + grow, box[3] + grow
    edges = [
        picture[y0, x0 : x1 + 1],
        picture[y1, x0 : x1 + 1],
        picture[y0 : y1 + 1, x0],
        picture[y0 : y1 + 1, x1],
    ]
    return np.concatenate(edges).astype(float)


def _tint(pixels: np.ndarray, colour: tuple[int, int, int]) -> float:
    """How much ``pixels`` lean to ``colour``'s channel over the other two (mean levels)."""
    channel = int(np.argmax(colour))
    others = [c for c in range(3) if c != channel]
    return float(np.mean(pixels[:, channel] - pixels[:, others].mean(axis=1)))


@pytest.mark.slow
def test_the_video_eye_inset_shows_each_reading_with_its_box(tmp_path: Path) -> None:
    """``--detector vision`` with video, one handover: after a reading, the frame's eye inset
    has the reading's colour on the outline of the reading's box and not a few pixels off."""
    from robin_sim.episode.config import EpisodeConfig
    from robin_sim.episode.run import run_episode
    from robin_sim.render.inset import inset_box, inset_size
    from robin_sim.vision.detector import READING_SHOWN

    fps = 5
    config = EpisodeConfig(
        scenario=ONE_HANDOVER,
        out=tmp_path,
        fps=fps,
        verify=False,
        progress=False,
        params={"detector": "vision"},
    )
    summary = run_episode(config)
    assert summary["status"] == "finished"
    log = [json.loads(line) for line in (tmp_path / "episode.jsonl").read_text().splitlines()]
    readings = [r for entry in log for r in entry["vision"]]
    with av.open(str(tmp_path / "episode.mp4")) as container:
        frames = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    x0, y0, _, _ = inset_box(640, 480)
    checked = 0
    for reading, after in zip(readings, [*readings[1:], None], strict=True):
        shown_until = reading["sim_time"] + READING_SHOWN
        if (after is not None and after["sim_time"] < shown_until) or reading["boxes"][0] is None:
            continue  # the next reading replaces it in the inset, or no box to draw
        index = int(np.ceil(reading["sim_time"] * fps)) + 1  # within READING_SHOWN
        if index >= len(frames):
            continue  # read in the episode's last moment: the video ends before it is shown
        frame = frames[index]
        bx0, by0, bx1, by1 = placed_box(tuple(reading["boxes"][0]), EYE, inset_size(640, 480))
        if min(bx0, by0) < 5 or bx1 > 155 or by1 > 115 or min(bx1 - bx0, by1 - by0) < 10:
            continue  # too near the inset's edge or too small for rings inside and outside
        box = (x0 + bx0, y0 + by0, x0 + bx1, y0 + by1)
        colour = box_colour(reading["read"] == "discarded")
        on, inside, outside = (_tint(_ring(frame, box, grow), colour) for grow in (0, -4, 4))
        assert on > inside + BOX_CONTRAST and on > outside + BOX_CONTRAST, (reading, on, inside)
        checked += 1
    assert checked >= 3  # the one handover's gestures and thumbs
