"""``robin-pil live``: every bad option is one clear message and exit code 2, before anything
starts (no server, no session folder)."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from robin_sim.cli.main import main


def refused(argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> str:
    out = tmp_path / "live"
    code = main(["live", "--no-browser", "--out", str(out), *argv])
    captured = capsys.readouterr()
    assert code == 2, captured
    assert not out.exists(), "a refused command wrote its folder"
    lines = [line for line in captured.err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("robin-pil live: error: "), captured.err
    assert "serving" not in captured.out
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["--port", "http"], "--port"),
        (["--port", "70000"], "65535"),
        (["--port", "-1"], "65535"),
        (["--speed", "fast"], "speed must be a number from 0.1 to 10.0"),
        (["--speed", "50"], "speed"),
        (["--system", "nope"], "pil"),
        (["--participant", "P 01; rm"], "participant"),
        (["--participant", ""], "participant"),
        (["--scenario", "no_such_scenario"], "scenario"),
    ],
)
def test_bad_option(argv: list[str], named: str, tmp_path: Path, capsys) -> None:
    message = refused(argv, tmp_path, capsys)
    assert named in message


def test_port_in_use(tmp_path: Path, capsys) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        message = refused(["--port", str(port)], tmp_path, capsys)
    assert f"--port {port} is in use" in message and "--port 0" in message


@pytest.mark.parametrize("content", [None, "blocks: [\n", "\xff\xfe not text"])
def test_unreadable_protocol(content: str | None, tmp_path: Path, capsys) -> None:
    path = tmp_path / "protocol.yaml"
    if content is not None:
        path.write_bytes(content.encode("latin-1"))
    message = refused(["--protocol", str(path)], tmp_path, capsys)
    assert "protocol" in message.lower()


def test_protocol_needs_a_numbered_participant(tmp_path: Path, capsys) -> None:
    message = refused(
        ["--protocol", "reactive_vs_proactive", "--participant", "Alice"], tmp_path, capsys
    )
    assert "Alice" in message


def test_an_existing_session_folder_is_never_overwritten(tmp_path: Path, capsys) -> None:
    from robin_sim.live.protocol import load_protocol

    first = load_protocol("reactive_vs_proactive").blocks_for("P01")[0]
    kept = tmp_path / "live" / "P01" / f"block1-{first.condition}"
    kept.mkdir(parents=True)
    (kept / "summary.json").write_text('{"status": "finished"}')
    code = main(
        [
            "live",
            "--no-browser",
            "--out",
            str(tmp_path / "live"),
            "--protocol",
            "reactive_vs_proactive",
            "--participant",
            "P01",
        ]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("robin-pil live: error: "), err
    assert (kept / "summary.json").read_text() == '{"status": "finished"}'
    assert sorted(p.name for p in (tmp_path / "live" / "P01").iterdir()) == [kept.name]


@pytest.mark.parametrize(
    ("host", "loopback"),
    [
        ("127.0.0.1", True),
        ("127.0.0.2", True),
        ("::1", True),
        ("localhost", True),
        ("0.0.0.0", False),
        ("::", False),
        ("192.168.1.5", False),
        ("robin.lab", False),
    ],
)
def test_only_loopback_goes_without_a_token(host: str, loopback: bool) -> None:
    from robin_sim.live.server import is_loopback

    assert is_loopback(host) is loopback
