"""Physical episodes: video, log, summary, agreement with the learner-only run, corrections.

These run Robin in MuJoCo for real (no mocks) and render with EGL; they are marked slow.
"""

from __future__ import annotations

from pathlib import Path

import av
import pytest
from replay_rig import check_episode_replay

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from pil.task.assemble import assemble  # noqa: E402
from pil.task.runner import steps  # noqa: E402
from pil.task.scenario import SCENARIOS_DIR  # noqa: E402
from pil.task.spec import parse_run_spec  # noqa: E402
from pil.task.world import SymbolicWorld  # noqa: E402
from robin_sim.episode.log import read_step_log  # noqa: E402
from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402

ONE_HANDOVER = SCENARIOS_DIR / "one_handover.yaml"
DECISION_KEYS = (
    "t",
    "gesture_count",
    "true_gesture",
    "detected_gesture",
    "corrected_gesture",
    "state",
    "action",
    "feedback",
    "delivered",
    "legs_delivered",
)


def _learner_only(config: EpisodeConfig) -> list[dict]:
    params = {**config.params, "tables": config.tables}
    spec = parse_run_spec(
        system=config.system,
        rate=config.rate,
        seed=config.seed,
        scenario=config.scenario,
        params=params,
    )
    parts = assemble(spec)
    records = steps(parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options)
    return [record.to_dict() for record in records]


@pytest.mark.slow
def test_one_handover_writes_a_decodable_video_log_and_summary(tmp_path: Path, capsys) -> None:
    config = EpisodeConfig(
        scenario=ONE_HANDOVER, out=tmp_path, width=160, height=120, fps=15, progress=False
    )
    summary = run_episode(config)
    assert summary["status"] == "finished"
    assert summary["legs_delivered"] == 1 and summary["legs_to_person"] == 1
    assert summary["physical_failures"] == 0
    assert summary["video"]["path"] == "episode.mp4"  # relative to the run's folder
    with av.open(str(tmp_path / summary["video"]["path"])) as container:
        stream = container.streams.video[0]
        assert stream.codec_context.name == "h264"
        frames = [frame.to_ndarray(format="rgb24") for frame in container.decode(stream)]
        assert stream.codec_context.pix_fmt == "yuv420p"
    assert len(frames) == summary["video"]["frames"]
    # frames at video rate over the simulated time (one frame per 1/fps s, give or take one)
    assert abs(len(frames) - summary["sim_time_s"] * 15) <= 2
    assert frames[0].shape == (120, 160, 3)
    for frame in frames[:: max(1, len(frames) // 5)]:
        assert frame.std() > 10.0  # not blank: a scene, not a flat colour
    log = read_step_log(tmp_path / "episode.jsonl")
    assert len(log) == summary["actions"] + summary["repeats"]
    assert all(entry["hand_physics"] in ("free", "occupied") for entry in log)
    assert all(len(entry["leg_positions"]) == 4 for entry in log)
    times = [entry["sim_time"] for entry in log]
    assert times == sorted(times)
    checks = [entry["render_check"] for entry in log if "render_check" in entry]
    assert {c["check"] for c in checks} == {"in hand", "on palm"}
    assert all(c["agrees"] for c in checks), checks
    assert all(20 <= c["pixels"] <= c["leg_pixels"] for c in checks), checks  # MIN_PIXELS = 20
    check_episode_replay(tmp_path, summary, capsys)  # robin-pil replay: the same frames


@pytest.mark.slow
def test_the_default_episode_delivers_every_leg_without_touching_the_person(
    tmp_path: Path,
) -> None:
    """The main job (one table, seed 0) without video: all four legs, no robot-person contact,
    every handover within its time, the person's parameters in the summary."""
    summary = run_episode(EpisodeConfig(out=tmp_path, video=False, progress=False))
    assert summary["status"] == "finished" and summary["legs_delivered"] == 4
    assert summary["person_contacts"] == 0 and summary["timeouts"] == 0
    assert summary["handover_success_rate"] == 1.0
    assert summary["person"]["reaction_time"] == 0.5
    handovers = summary["handovers"]
    assert [h["delivered"] for h in handovers] == [True] * 4
    assert all(0.0 < h["seconds"] <= summary["handover_timeout_s"] for h in handovers)
    assert sum(h["actions"] for h in handovers) == summary["actions"]
    assert summary["interrupted_actions"] == sum(h["interrupted"] for h in handovers) > 0
    log = read_step_log(tmp_path / "episode.jsonl")
    stopped = [e for e in log if e["interrupted"]]
    assert all(e["feedback"] == "not ok" for e in stopped)
    # the person stops what they did not mean, or a meant action during which the leg dropped
    assert all(e["action"] != e["intended_action"] or e["dropped"] is not None for e in stopped)


@pytest.mark.slow
def test_physical_decisions_equal_the_learner_only_run(tmp_path: Path) -> None:
    config = EpisodeConfig(
        tables=1, seed=3, out=tmp_path, video=False, verify=False, progress=False
    )
    summary = run_episode(config)
    assert summary["status"] == "finished" and summary["physical_failures"] == 0
    physical = read_step_log(tmp_path / "episode.jsonl")
    symbolic = _learner_only(config)
    assert [{k: e[k] for k in DECISION_KEYS} for e in physical] == [
        {k: e[k] for k in DECISION_KEYS} for e in symbolic
    ]
    assert summary["legs_delivered"] == 4


@pytest.mark.slow
def test_episode_at_60_percent_runs_to_the_end_with_corrections(tmp_path: Path) -> None:
    config = EpisodeConfig(
        tables=1, rate=0.6, seed=1, out=tmp_path, video=False, verify=False, progress=False
    )
    summary = run_episode(config)
    assert summary["status"] == "finished"
    assert summary["legs_delivered"] == 4
    log = read_step_log(tmp_path / "episode.jsonl")
    misread = [e for e in log if e["detected_gesture"] != e["true_gesture"]]
    assert misread, "at 60 % some gestures must be misread or discarded"
    assert summary["corrections"] + summary["repeats"] > 0
    corrected = {e["gesture_count"] for e in log if e["corrected_gesture"] is not None}
    assert summary["corrections"] == len(corrected)


def test_bad_input_is_refused_before_anything_runs(tmp_path: Path) -> None:
    with pytest.raises(Exception, match=r"\(0, 1\]"):
        run_episode(EpisodeConfig(rate=1.5, out=tmp_path, video=False))
    with pytest.raises(Exception, match="system"):
        run_episode(EpisodeConfig(system="c9", out=tmp_path, video=False))
    with pytest.raises(Exception, match="tables"):
        run_episode(EpisodeConfig(tables=0, out=tmp_path, video=False))
    assert not (tmp_path / "episode.jsonl").exists()


@pytest.mark.slow
def test_a_vision_episode_reads_gestures_and_thumbs_with_the_eye_cameras(tmp_path: Path) -> None:
    """``--detector vision``: every gesture and every thumb after a finished action is read
    from the eye cameras; readings are logged with their confidence and summarised."""
    config = EpisodeConfig(
        scenario=ONE_HANDOVER,
        out=tmp_path,
        video=False,
        verify=False,
        progress=False,
        params={"detector": "vision"},
    )
    summary = run_episode(config)
    assert summary["status"] == "finished" and summary["legs_delivered"] == 1
    vision = summary["vision"]
    assert vision["gestures_read"] == summary["gestures"]
    assert 0.0 < vision["detection_rate"] <= 1.0
    assert sum(sum(row.values()) for row in vision["confusion"].values()) == (
        vision["gestures_read"] + vision["feedback_read"]
    )
    log = read_step_log(tmp_path / "episode.jsonl")
    readings = [r for entry in log for r in entry["vision"]]
    assert len(readings) == vision["gestures_read"] + vision["feedback_read"]
    assert all(0.0 <= r["confidence"] <= 1.0 for r in readings)
    stopped = [e for e in log if e["interrupted"]]
    assert all(e["feedback_read"] == "not ok" for e in stopped)  # the robot saw the stop


def test_camera_conditions_need_the_vision_detector(tmp_path: Path) -> None:
    with pytest.raises(Exception, match="need --detector vision"):
        run_episode(EpisodeConfig(out=tmp_path, video=False, params={"lighting": 0.3}))
    assert not (tmp_path / "summary.json").exists()
