"""The live server's checks that need no server: Host / Origin allow-list, messages that used to
raise something other than LiveInputError, protocol placeholders with a format, the write check."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from robin_sim.live.guard import HostCheck
from robin_sim.live.inputs import LiveInputError, parse_input
from robin_sim.live.preflight import check_writable
from robin_sim.live.protocol import ProtocolError, load_protocol

PORT = 8123


def loopback_check() -> HostCheck:
    check = HostCheck("127.0.0.1")
    check.bind_to(("127.0.0.1", PORT))
    return check


@pytest.mark.parametrize(
    "netloc",
    [
        f"127.0.0.1:{PORT}",
        f"localhost:{PORT}",
        f"LocalHost:{PORT}",
        f"[::1]:{PORT}",
        f"127.0.0.2:{PORT}",
    ],
)
def test_loopback_names_with_the_port_are_allowed(netloc: str) -> None:
    assert loopback_check().allows(netloc)


@pytest.mark.parametrize(
    "netloc",
    [
        f"evil.example:{PORT}",  # DNS rebinding: a foreign name resolved to 127.0.0.1
        f"localhost.evil.example:{PORT}",
        f"127.0.0.1:{PORT + 1}",  # another port: another server
        "127.0.0.1",  # port 80
        f"localhost.:{PORT}",
        f"user@127.0.0.1:{PORT}",
        f"127.0.0.1:{PORT}/x",
        f"::1:{PORT}",  # an IPv6 literal without brackets
        f"[127.0.0.1]:{PORT}",
        f"192.168.1.5:{PORT}",  # a loopback server is not reached by a LAN address
        f"{socket.gethostname()}:{PORT}",
        "",
        None,
    ],
)
def test_anything_else_is_refused(netloc: str | None) -> None:
    assert not loopback_check().allows(netloc)


def test_origin_must_be_this_server_not_the_requests_own_host() -> None:
    check = loopback_check()
    assert check.allows_origin(f"http://127.0.0.1:{PORT}")
    assert check.allows_origin(f"http://localhost:{PORT}")
    for origin in (
        f"http://evil.example:{PORT}",
        "null",
        f"https://127.0.0.1:{PORT}",
        f"http://127.0.0.1:{PORT}/path",
        "http://127.0.0.1",
        "file://",
    ):
        assert not check.allows_origin(origin), origin


def test_a_named_host_and_a_wildcard_bind() -> None:
    named = HostCheck("robin.lab")
    named.bind_to(("192.168.1.5", PORT))
    assert named.allows(f"robin.lab:{PORT}") and named.allows(f"192.168.1.5:{PORT}")
    assert named.allows(f"localhost:{PORT}") and not named.allows(f"evil.example:{PORT}")
    assert not named.allows(f"10.0.0.9:{PORT}")
    anywhere = HostCheck("0.0.0.0")
    anywhere.bind_to(("0.0.0.0", PORT))  # any IP literal (rebinding needs a name) and our names
    assert anywhere.allows(f"10.0.0.9:{PORT}") and anywhere.allows(f"[fe80::1]:{PORT}")
    assert anywhere.allows(f"{socket.gethostname()}:{PORT}")
    assert not anywhere.allows(f"evil.example:{PORT}")
    assert not anywhere.allows(f"10.0.0.9:{PORT + 1}")


@pytest.mark.parametrize(
    ("raw", "named"),
    [
        ('{"type": "point", "x": ' + "9" * 400 + ', "y": 10}', "outside"),  # OverflowError
        ('{"type": "point", "x": -' + "9" * 400 + ', "y": 10}', "outside"),
        ("[" * 3000, "nested too deeply"),  # RecursionError in json.loads
        ('{"type": "point", "x": ' + "[" * 3000 + "]" * 3000 + ', "y": 1}', "too long"),
        ('{"type": "point", "x": ' + "[" * 900 + "]" * 900 + ', "y": 1}', "number"),
    ],
)
def test_every_decode_failure_is_a_live_input_error(raw: str, named: str) -> None:
    with pytest.raises(LiveInputError, match=named) as caught:
        parse_input(raw, 640, 480)
    assert len(str(caught.value)) < 300  # the 400 digits are not echoed back in full


def protocol_with(tmp_path: Path, instructions: str) -> Path:
    path = tmp_path / "protocol.yaml"
    body = f"conditions: [pil]\nblocks:\n  - {{types: [A]}}\ninstructions: {instructions!r}\n"
    path.write_text(body)
    return path


@pytest.mark.parametrize(
    "text", ["Block {block:>100000000}", "{label!r} and {block}", "{blocks:,}", "{types:.3}"]
)
def test_placeholders_take_no_format(tmp_path: Path, text: str) -> None:
    with pytest.raises(ProtocolError, match=r"has a format; write it bare") as caught:
        load_protocol(protocol_with(tmp_path, text))
    assert "instructions" in str(caught.value) and len(str(caught.value)) < 400


def test_bare_placeholders_load_and_long_texts_are_refused(tmp_path: Path) -> None:
    protocol = load_protocol(protocol_with(tmp_path, "Block {block} of {blocks}: {label}"))
    assert protocol.blocks_for("P01")[0].instructions == "Block 1 of 1: Robot A"
    with pytest.raises(ProtocolError, match="too long"):
        load_protocol(protocol_with(tmp_path, "x" * 5000))


def test_write_check_leaves_nothing_and_refuses_a_file(tmp_path: Path) -> None:
    check_writable(tmp_path / "live" / "P01")
    assert list(tmp_path.iterdir()) == []  # nothing made, nothing left
    (tmp_path / "file").write_text("kept")
    with pytest.raises(Exception, match="is a file, not a folder"):
        check_writable(tmp_path / "file" / "P01")
    assert (tmp_path / "file").read_text() == "kept"


def test_accept_out_of_descriptors_is_one_line_once(caplog) -> None:
    import asyncio
    import errno
    import logging

    from robin_sim.live.connections import Connections, Limits

    connections = Connections(Limits())
    loop = asyncio.new_event_loop()
    try:
        caplog.set_level(logging.WARNING)
        for _ in range(50):  # what asyncio reports on every failed accept() retry
            connections.loop_exception(
                loop,
                {
                    "message": "socket.accept() out of system resource",
                    "exception": OSError(errno.EMFILE, "Too many open files"),
                },
            )
    finally:
        loop.close()
    assert len(caplog.records) == 1 and not caplog.records[0].exc_info
    assert "Too many open files" in caplog.records[0].getMessage()


def test_the_cap_follows_a_low_descriptor_limit() -> None:
    import resource

    from robin_sim.live.connections import ACCEPT_BURST, RESERVED_FDS, Limits

    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (256, hard))
    try:
        cap = Limits(max_connections=500).connection_cap()
    finally:
        resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))
    assert cap == 256 - RESERVED_FDS - 4 * ACCEPT_BURST
    assert Limits(max_connections=10).connection_cap() == 10
