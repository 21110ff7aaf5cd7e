"""``robin-pil replay``: the states logged while a run records, re-rendered to the same frames.

Sessions run in MuJoCo and render with EGL for real; the replay's frames are decoded from both
MP4s with PyAV and compared pixel by pixel (the episode's replay is checked in
``tests/test_episode.py``, on the one-handover episode that test runs anyway).
"""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from replay_rig import COMPARED, decoded_frames, frames_match

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.cli.main import main  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.state_log import STATES_NAME, StateLog, load_states  # noqa: E402
from robin_sim.render.worker import FrameState  # noqa: E402


def test_states_round_trip_with_geometry_changes_kept_only_where_they_change(
    tmp_path: Path,
) -> None:
    model = build_model()
    data = mujoco.MjData(model)
    log = StateLog(tmp_path / STATES_NAME, {"layout": {}, "size": [8, 8]})
    for step in range(5):
        data.qpos[0] = 0.1 * step
        if step == 3:
            model.geom_rgba[2, 3] = 0.25
        log.add(FrameState.capture(model, data), copies=1 + step % 2, overlay={"step": step})
    assert log.save() == tmp_path / STATES_NAME and log.save() is None  # once
    recorded = load_states(tmp_path / STATES_NAME)
    assert [s.qpos[0] for s in recorded.states] == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
    assert [s.geom_rgba[2, 3] for s in recorded.states][2:] == pytest.approx([1.0, 0.25, 0.25])
    assert list(recorded.copies) == [1, 2, 1, 2, 1] and recorded.video_frames == 7
    assert [o["step"] for o in recorded.overlays] == [0, 1, 2, 3, 4]
    with np.load(tmp_path / STATES_NAME) as raw:
        assert list(raw["geom_frames"]) == [0, 3]
    part = recorded.between(0.0, 0.0)
    assert len(part.states) == 5  # all at simulated time 0 here


@pytest.mark.parametrize(
    ("make", "expected"),
    [
        (lambda d: d / "missing", "does not exist"),
        (lambda d: (d / "file.txt").write_text("x") and d / "file.txt", "is a file"),
        (lambda d: d, "is not a run's folder"),
        (lambda d: (d / "summary.json").write_text("{}") and d, "has no states.npz"),
        (
            lambda d: ((d / "a").mkdir(), (d / "a" / STATES_NAME).write_text("x"), d)[-1],
            "holds 1 recorded runs",
        ),
    ],
)
def test_bad_dir_is_refused_with_exit_2(tmp_path: Path, capsys, make, expected: str) -> None:
    folder = make(tmp_path)
    before = sorted(p.name for p in tmp_path.rglob("*"))
    assert main(["replay", str(folder)]) == 2
    err = capsys.readouterr().err
    assert expected in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written


def test_unreadable_states_and_viewer_without_display(tmp_path: Path, capsys, monkeypatch) -> None:
    (tmp_path / STATES_NAME).write_text("not a zip")
    assert main(["replay", str(tmp_path)]) == 2
    assert "not a readable states file" in capsys.readouterr().err
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["replay", str(tmp_path), "--viewer"]) == 2
    assert "--viewer needs a display" in capsys.readouterr().err
    assert main(["replay", str(tmp_path), "--out", str(tmp_path / "x.avi")]) == 2
    assert "ending in .mp4" in capsys.readouterr().err


@pytest.mark.slow
def test_replay_of_a_live_session_renders_the_frames_of_its_video(tmp_path: Path, capsys) -> None:
    import time

    from robin_sim.live.config import LiveConfig
    from robin_sim.live.session import LiveSession

    session = LiveSession(
        LiveConfig(
            scenario="one_handover",
            out_root=tmp_path,
            session="s1",
            speed=3.0,
            fps=10,
            width=160,
            height=120,
        )
    )
    session.start()
    try:
        deadline = time.monotonic() + 90
        while (
            session.latest_frame() is None or session.latest_frame().seq < 20
        ) and time.monotonic() < deadline:
            time.sleep(0.1)
    finally:
        summary = session.stop("ended")
    folder = session.out_dir
    assert summary["video"]["frames"] >= 20
    capsys.readouterr()
    assert main(["replay", str(folder), "--out", str(tmp_path / "again.mp4")]) == 0
    original = decoded_frames(folder / "episode.mp4", 999)
    replayed = decoded_frames(tmp_path / "again.mp4", 999)
    assert len(replayed) == len(original) == summary["video"]["frames"]
    for k in range(0, len(original), max(1, len(original) // COMPARED)):
        assert frames_match(original[k], replayed[k]), k


def _get(port: int, target: str, host: str | None = None) -> tuple[int, dict[str, str], bytes]:
    import http.client

    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    connection.putrequest("GET", target, skip_host=True)
    connection.putheader("Host", host or f"127.0.0.1:{port}")
    connection.endheaders()
    response = connection.getresponse()
    body = response.read()
    connection.close()
    return response.status, {k.lower(): v for k, v in response.getheaders()}, body


def test_the_scrub_page_serves_each_frame_rendered_again(tmp_path: Path) -> None:
    import cv2
    from replay_rig import recorded_run, serving

    from robin_sim.replay.render import ReplayRenderer
    from robin_sim.replay.serve import JPEG_QUALITY

    path = recorded_run(tmp_path)
    with ReplayRenderer(load_states(path)) as renderer:
        expected = [renderer.render(k).astype(np.int16) for k in (0, 5)]
    with serving(path) as port:
        status, headers, body = _get(port, "/meta")
        assert status == 200 and json.loads(body)["frames"] == 6
        assert json.loads(body)["times"] == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
        for k, pixels in zip((0, 5), expected, strict=True):
            status, headers, body = _get(port, f"/frame/{k}")
            assert status == 200 and headers["content-type"] == "image/jpeg"
            shown = cv2.imdecode(np.frombuffer(body, np.uint8), cv2.IMREAD_COLOR)[:, :, ::-1]
            assert shown.shape == (120, 160, 3)
            # the same pixels JPEG-encoded here give the same bytes: the frame is the render's
            ok, again = cv2.imencode(
                ".jpg",
                cv2.cvtColor(pixels.astype(np.uint8), cv2.COLOR_RGB2BGR),
                [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY],
            )
            assert ok and again.tobytes() == body
        assert np.abs(expected[0] - expected[1]).mean() > 2.0  # the frames differ: it can fail
        assert headers["x-frame-options"] == "DENY"
        assert "frame-ancestors 'none'" in headers["content-security-policy"]
        for target in ("/frame/6", "/frame/-1", "/frame/" + "9" * 400, "/frame/x"):
            assert _get(port, target)[0] == 404, target
        status, _, body = _get(port, "/", host=f"evil.example:{port}")  # DNS rebinding
        assert status == 403 and b"127.0.0.1" in body
        assert _get(port, "/", host=f"localhost:{port}")[0] == 200
