"""``robin-pil replay``: the states logged while a run records, re-rendered to the same frames.

Sessions run in MuJoCo and render with EGL for real; the replay's frames are decoded from both
MP4s with PyAV and compared pixel by pixel (the episode's replay is checked in
``tests/test_episode.py``, on the one-handover episode that test runs anyway).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import mujoco
import numpy as np
import pytest
from replay_rig import COMPARED, META, decoded_frames, frames_match, recorded_run

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.cli.main import main  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.state_log import (  # noqa: E402
    FORMAT,
    STATES_NAME,
    StateLog,
    StatesError,
    load_states,
)
from robin_sim.render.worker import FrameState  # noqa: E402


def test_states_round_trip_with_geometry_changes_kept_only_where_they_change(
    tmp_path: Path,
) -> None:
    model = build_model()
    data = mujoco.MjData(model)
    log = StateLog(tmp_path / STATES_NAME, META)
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


def _damaged(folder: Path, **changes: object) -> Path:
    """A recorded run's states file with some arrays replaced (a callable gets the old one)."""
    path = recorded_run(folder)
    with np.load(path) as raw:
        arrays = {name: raw[name] for name in raw.files}
    for name, change in changes.items():
        arrays[name] = change(arrays[name]) if callable(change) else np.asarray(change)
    np.savez_compressed(path, **arrays)
    return path


def _deep(levels: int) -> str:
    return '{"a": ' * levels + "1" + "}" * levels


def _with(array: np.ndarray, index: tuple[int, ...], value: float) -> np.ndarray:
    array = array.copy()
    array[index] = value
    return array


@pytest.mark.parametrize(
    ("changes", "expected"),
    [
        ({"qpos": lambda q: q[:, :10]}, "qpos has 10 joint positions a frame; the run's scene"),
        ({"qpos": lambda q: q[:-1]}, "lengths do not match"),
        ({"mocap_quat": lambda q: q[:-2]}, "lengths do not match"),
        ({"meta": _deep(5000)}, "meta is damaged: nested more than"),
        ({"overlays": json.dumps([_deep(5000)])}, "an overlay is damaged"),
        ({"time": np.zeros(3_000_000)}, "time has 3,000,000 rows, more than"),
        ({"copies": lambda c: _with(c, (0,), 10**9)}, "copies must be 0 to"),
        ({"qpos": lambda q: _with(q, (2, 5), np.nan)}, "qpos holds nan"),
        ({"mocap_pos": lambda m: _with(m, (1, 0, 0), 1e308)}, "mocap_pos holds 1e+308"),
        ({"geom_rgba": lambda g: _with(g, (0, 3, 1), np.inf)}, "geom_rgba holds inf"),
        ({"time": lambda t: t[::-1].copy()}, "time goes back at frame 1"),
        ({"qpos": lambda q: q.astype(object)}, "qpos holds object, expected floating"),
        ({"overlay_index": lambda i: i + 5}, "overlay_index points past"),
        ({"meta": json.dumps({**META, "format": 1, "fps": 10**9})}, "meta: fps"),
        (  # an older layout (format 2: one lean joint fewer) is refused by its number
            {"meta": json.dumps({**META, "format": FORMAT - 1})},
            f"states format {FORMAT - 1}; this version reads format {FORMAT}",
        ),
    ],
    ids=lambda v: "" if isinstance(v, str) else str(sorted(v)),
)
def test_a_damaged_states_file_is_refused_before_rendering(
    tmp_path: Path, changes: dict[str, object], expected: str
) -> None:
    path = _damaged(tmp_path, **changes)
    with pytest.raises(StatesError, match=re.escape(expected)):
        load_states(path)


def test_an_array_whose_header_claims_more_than_its_data_is_refused_before_allocation(
    tmp_path: Path,
) -> None:
    import io
    import zipfile

    path = recorded_run(tmp_path)
    header = io.BytesIO()  # 900 000 frames x 9 000 geoms: 259 GB if it were allocated
    np.lib.format.write_array_header_2_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (900_000, 9_000, 4)}
    )
    with zipfile.ZipFile(path) as archive:
        members = {i.filename: archive.read(i) for i in archive.infolist()}
    members["geom_rgba.npy"] = header.getvalue()  # the header alone, no data
    with zipfile.ZipFile(path, "w") as archive:
        for name, data in members.items():
            archive.writestr(name, data)
    with pytest.raises(StatesError, match="geom_rgba's size in the zip does not match its header"):
        load_states(path)


def test_replay_of_a_damaged_states_file_is_one_line(tmp_path: Path, capsys) -> None:
    _damaged(tmp_path, qpos=lambda q: _with(q, (0, 0), np.nan))
    assert main(["replay", str(tmp_path)]) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1 and "qpos holds nan" in lines[0] and STATES_NAME in lines[0]
    assert not (tmp_path / "replay.mp4").exists()


@pytest.mark.parametrize("kind", ["dev-zero", "fifo"])
def test_a_states_file_that_is_no_regular_file_is_refused(tmp_path: Path, capsys, kind) -> None:
    import os

    (tmp_path / "summary.json").write_text("{}")
    if kind == "fifo":
        os.mkfifo(tmp_path / STATES_NAME)
    else:
        (tmp_path / STATES_NAME).symlink_to("/dev/zero")
    assert main(["replay", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "not a regular file" in err and "recorded runs" not in err
    with pytest.raises(StatesError, match="not a regular file"):
        load_states(tmp_path / STATES_NAME)


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
