"""Live sessions with real physics and rendering, driven from the test thread.

Speeds of 3x real time keep the tests short (the pacing never runs ahead; a busy machine only
makes them slower); frames at 10 per wall second at that speed.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import av
import cv2
import numpy as np
import pytest
from live_driver import Driver

from pil.experiments.sessions_report import load_sessions, write_sessions_report
from robin_sim.episode.log import read_step_log
from robin_sim.live.config import LiveConfig
from robin_sim.live.files import SessionExistsError
from robin_sim.live.inputs import LiveInput, LiveInputError
from robin_sim.live.pacing import MAX_LAG_S
from robin_sim.live.session import LiveSession
from robin_sim.model.names import ACTIVE_SIDE, grasp_site

pytestmark = pytest.mark.slow
SPEED, FPS = 3.0, 10
TYPE_A = (("point", "object"), ("grasp", "close"), ("give_me", "human"), ("release", "open"))


def _config(tmp_path: Path, **changes: object) -> LiveConfig:
    values = dict(
        scenario="one_handover",
        out_root=tmp_path,
        session="s1",
        speed=SPEED,
        fps=FPS,
        feedback_window=6.0,  # 2 s of wall time for the test thread's thumb, also when busy
        adaptive_stream=False,  # every frame: these tests time the stream itself
    )
    return LiveConfig(**{**values, **changes})  # type: ignore[arg-type]


def _frames(session: LiveSession) -> list:
    frames: list = []
    session.subscribe(lambda frame: frames.append((frame, time.monotonic())))
    return frames


def test_a_whole_type_a_handover_by_clicks_gestures_and_thumbs(tmp_path: Path) -> None:
    session = LiveSession(_config(tmp_path))
    frames = _frames(session)
    session.start()
    driver = Driver(session)
    seen: dict[str, list[str]] = {}
    try:
        for gesture, wanted in TYPE_A:
            driver.my_turn()
            if gesture == "point":
                driver.point_at_leg(0)
            else:
                driver.gesture(gesture)
            # the last action is approved by silence: no thumb within the feedback window
            seen[gesture] = driver.judge(wanted, silent=gesture == "release")
        assert session.done.wait(120), session.status()
    finally:
        summary = session.stop()
    out = session.out_dir
    assert summary["status"] == "finished", summary
    assert summary["legs_delivered"] == 1 and summary["legs_to_person"] == 1
    steps = read_step_log(out / "log.jsonl")
    assert [s["action"] for s in steps] == [a for actions in seen.values() for a in actions]
    assert summary["actions"] == len(steps) and summary["gestures"] == 4
    assert summary["rejected"] == sum(len(a) - 1 for a in seen.values())
    approved = [s for s in steps if s["feedback"] != "not ok"]
    assert [s["action"] for s in approved] == [a for _, a in TYPE_A]
    assert approved[-1]["feedback"] == "none" and approved[-1]["delivered"]  # silence is OK
    assert approved[0]["target"] == {"kind": "leg", "index": 0}
    assert [s["intended_action"] for s in approved] == [a for _, a in TYPE_A]
    # the learner learnt: the last state decided in now prefers the approved "open"
    status = session.status()
    assert status["phase"] == "done" and status["status"] == "finished"
    assert status["task"] == {
        "handover": 0,
        "handover_type": "A",
        "handover_steps": [
            "pointing -> object",
            "grasp -> close",
            "give me -> human",
            "release -> open",
        ],
    }
    policy = status["policy"]
    assert policy["state"] == "release / human / occupied"
    assert max(policy["actions"], key=policy["actions"].get) == "open"
    assert policy["actions"]["open"] > 0.2  # more than the uniform prior of 5 actions
    inputs = [json.loads(line) for line in (out / "inputs.jsonl").read_text().splitlines()]
    thumbs = sum(len(a) for a in seen.values()) - 1  # the silent one had none
    assert len(inputs) == 4 + thumbs and all(i["accepted"] for i in inputs)
    assert inputs[0]["raw"]["type"] == "point" and inputs[0]["sim_time"] > 0
    assert all(i["wall"] > 1e9 and i["error"] == "" for i in inputs)
    # the pace of a conversation (issue 25): from each instruction's arrival to the robot's
    # first motion (the "acts" event) at most 1 s of simulated time (deterministic: sim time)
    given = [i["sim_time"] for i in inputs if i["raw"]["type"] in ("point", "gesture")]
    events = [json.loads(line) for line in (out / "events.jsonl").read_text().splitlines()]
    acts = [e["sim_time"] for e in events if e["event"] == "acts"]
    assert len(given) == 4
    for at in given:
        first = min(t for t in acts if t >= at)
        assert first - at <= 1.0, (at, first)
    saved = json.loads((out / "summary.json").read_text())
    live = saved["live"]
    assert live["participant"] == "P01" and live["condition"] == "pil"
    assert live["handover_types"] == ["A"] and live["inputs"] == len(inputs)
    arrived = np.array([at for _, at in frames])
    frames = [frame for frame, _ in frames]
    assert live["frames_streamed"] == len(frames) == frames[-1].seq
    assert [f.seq for f in frames] == list(range(1, len(frames) + 1))
    # paced: physics never runs ahead of SPEED x the wall clock. The pace's reference only moves
    # forward; a frame is captured at most one tick (20 ms sim) before its pace and physics lags
    # it by at most MAX_LAG_S, so from the first frame on this holds (10 ms for the clock):
    sim = np.array([f.sim_time for f in frames])
    captured = np.array([f.captured for f in frames])
    slack = MAX_LAG_S + 0.02 / SPEED + 0.01
    assert np.all((sim - sim[0]) / SPEED <= captured - captured[0] + slack)
    assert all(f.captured <= at for f, at in zip(frames, arrived, strict=True))
    # frames are due every SPEED / FPS s of sim time, and show the scene (not blank)
    gaps = np.diff([f.sim_time for f in frames])
    assert np.median(gaps) == pytest.approx(SPEED / FPS, abs=0.021)  # one control tick
    assert gaps.max() <= SPEED / FPS + 0.021
    for frame in frames[:: max(1, len(frames) // 5)]:
        image = cv2.imdecode(np.frombuffer(frame.jpeg, np.uint8), cv2.IMREAD_COLOR)
        assert image.shape == (480, 640, 3) and float(image.std()) > 20.0
    with av.open(str(out / "episode.mp4")) as video:
        decoded = sum(1 for _ in video.decode(video=0))
    assert decoded == saved["video"]["frames"] >= len(frames)
    # the session is a dataset the sessions report reads (robin-pil report DIR)
    (row,) = load_sessions(tmp_path)
    assert (row["participant"], row["session"], row["condition"]) == ("P01", "s1", "pil")
    assert row["counted"] and row["status"] == "finished"
    for measure in ("gestures", "actions", "rejected", "legs_delivered"):
        assert row[measure] == saved[measure], measure
    written = write_sessions_report([row], tmp_path, tmp_path / "report")
    assert {p.name for p in written} == {
        "sessions.csv",
        "session_tests.csv",
        "report.md",
        "sessions.png",
    }


def _started(tmp_path: Path) -> tuple[LiveSession, Driver]:
    session = LiveSession(_config(tmp_path, seed=1))  # seed 1: the first action is "human"
    session.start()
    return session, Driver(session)


def _first_move(session: LiveSession, driver: Driver) -> tuple[np.ndarray, np.ndarray, dict]:
    """Point at leg 1 and wait until the robot acts: the grasp site (a live view), where it
    started, and the status then."""
    driver.my_turn()
    hand = session.body.world.data.site(grasp_site(ACTIVE_SIDE)).xpos
    start = hand.copy()
    driver.point_at_leg(1)
    return hand, start, driver.wait(lambda s: s["action"] is not None, "the robot to act")


def test_thumb_down_interrupts_a_move_and_stop_mid_move_saves_a_playable_video(
    tmp_path: Path,
) -> None:
    session, driver = _started(tmp_path)
    try:
        hand, start, moving = _first_move(session, driver)
        session.receive({"type": "thumb", "value": "down"})
        driver.wait(lambda s: s["actions"] >= 1, "the stopped action to be logged")
        undone_to = hand.copy()
        driver.my_turn()
        with pytest.raises(LiveInputError, match="no robot action to judge"):
            session.receive({"type": "thumb", "value": "up"})
        driver.point_at_leg(1)
        driver.wait(lambda s: s["action"] is not None, "the robot to act again")
        with pytest.raises(LiveInputError, match="not your turn"):
            session.receive({"type": "gesture", "gesture": "grasp"})
        summary = session.stop("interrupted")
    finally:
        session.stop()
    out = session.out_dir
    first = read_step_log(out / "log.jsonl")[0]
    assert first["action"] == moving["action"] and first["interrupted"]
    assert first["feedback"] == "not ok" and first["feedback_read"] == "not ok"
    assert first["hand_physics"] == "free"
    assert "stopped" in first["detail"], first["detail"]
    # the robot took the move back: its hand is within 2 cm of where it started
    assert np.linalg.norm(undone_to - start) < 0.02, (start, undone_to)
    assert summary["status"] == "interrupted" and summary["interrupted_actions"] == 1
    assert summary == json.loads((out / "summary.json").read_text())
    assert session.stop("failed") == summary  # idempotent: the first status stands
    inputs = [json.loads(line) for line in (out / "inputs.jsonl").read_text().splitlines()]
    assert [i["accepted"] for i in inputs] == [True, True, False, True, False]
    assert summary["video"]["path"] == "episode.mp4"  # relative: the same on every machine
    with av.open(str(out / summary["video"]["path"])) as video:
        decoded = [f.to_ndarray(format="rgb24") for f in video.decode(video=0)]
    assert len(decoded) == summary["video"]["frames"] > 10
    assert float(decoded[-1].std()) > 20.0


def test_thumb_down_after_a_move_takes_the_finished_action_back(tmp_path: Path) -> None:
    session, driver = _started(tmp_path)
    try:
        hand, start, _ = _first_move(session, driver)
        ended = driver.wait(lambda s: s["phase"] == "waiting_for_thumb", "the move's end")
        assert ended["last_action"] == "human"
        moved = hand.copy()  # the finished move: at the person's palm, far from the start
        session.receive({"type": "thumb", "value": "down"})
        driver.wait(lambda s: s["actions"] >= 1, "the rejected action to be logged")
        undone_to = hand.copy()
    finally:
        session.stop()
    first = read_step_log(session.out_dir / "log.jsonl")[0]
    assert first["action"] == "human" and first["interrupted"]
    assert first["feedback"] == "not ok" and first["feedback_read"] == "not ok"
    assert "rejected at its end" in first["detail"], first["detail"]
    # the robot took the finished move back: its hand went at least 10 cm and came back to
    # within 2 cm of where it started
    assert np.linalg.norm(moved - start) > 0.10, (start, moved)
    assert np.linalg.norm(undone_to - start) < 0.02, (start, undone_to)


def test_an_existing_session_folder_is_refused(tmp_path: Path) -> None:
    (tmp_path / "P01" / "s1").mkdir(parents=True)
    with pytest.raises(SessionExistsError, match="exists already"):
        LiveSession(_config(tmp_path))
    assert not any((tmp_path / "P01" / "s1").iterdir())  # nothing written into it


def test_end_saves_the_session_as_ended_and_nothing_more_is_taken(tmp_path: Path) -> None:
    session = LiveSession(_config(tmp_path))
    session.start()
    try:
        Driver(session).my_turn()
        session.receive('{"type": "end"}')
        assert session.done.wait(60)
        with pytest.raises(LiveInputError, match="the session has ended"):
            session.receive({"type": "gesture", "gesture": "grasp"})
    finally:
        summary = session.stop()
    assert summary["status"] == "ended" and summary["actions"] == 0
    assert session.status()["phase"] == "done" and session.status()["status"] == "ended"
    saved = json.loads((session.out_dir / "summary.json").read_text())
    # the summary counts the session's messages; the one after it was saved is refused, and
    # inputs.jsonl has it after them with why (as the answers to a questionnaire after a block)
    assert saved["live"]["inputs"] == 1 and saved["live"]["inputs_rejected"] == 0
    lines = [json.loads(x) for x in (session.out_dir / "inputs.jsonl").read_text().splitlines()]
    assert [(x["accepted"], x["error"][:21]) for x in lines] == [
        (True, ""),
        (False, "the session has ended"),
    ]


def test_an_error_in_the_physics_thread_saves_the_session_as_failed(tmp_path: Path) -> None:
    session = LiveSession(_config(tmp_path))
    seen: list = []

    def breaks(frame: object) -> None:
        seen.append(frame)
        if len(seen) == 5:
            raise RuntimeError("the page's socket broke")

    session.subscribe(breaks)
    session.start()
    assert session.done.wait(60)
    summary = session.stop()
    assert summary["status"] == "failed" and "the page's socket broke" in summary["error"]
    assert json.loads((session.out_dir / "summary.json").read_text()) == summary
    with av.open(str(session.out_dir / "episode.mp4")) as video:
        assert sum(1 for _ in video.decode(video=0)) == summary["video"]["frames"] >= 4


def test_a_session_stopped_before_it_started_writes_nothing(tmp_path: Path) -> None:
    session = LiveSession(_config(tmp_path))
    assert session.stop("closed")["status"] == "closed" and session.done.is_set()
    assert not (tmp_path / "P01").exists()
    with pytest.raises(LiveInputError, match="the session has ended"):
        session.submit(LiveInput("end"))


def test_end_during_a_move_gives_the_robot_no_verdict(tmp_path: Path) -> None:
    session = LiveSession(_config(tmp_path, seed=1))  # seed 1: the first action is "human"
    session.start()
    driver = Driver(session)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        driver.wait(lambda s: s["action"] is not None, "the robot to act")
        session.receive({"type": "end"})
        assert session.done.wait(60)
    finally:
        summary = session.stop()
    assert summary["status"] == "ended"
    assert summary["actions"] == 0 and read_step_log(session.out_dir / "log.jsonl") == []
