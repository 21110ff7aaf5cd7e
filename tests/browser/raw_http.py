"""Raw-socket clients for the live server's attack tests (loopback only): requests sent byte for
byte, a WebSocket handshake, masked text frames, a socket that never reads."""

from __future__ import annotations

import base64
import os
import socket
import struct


def exchange(port: int, request: bytes, timeout: float = 10.0) -> tuple[int, dict[str, str], bytes]:
    """Send ``request`` as it is, read one reply (to its Content-Length, or to the end); the
    status, headers (lower-case) and body."""
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as sock:
        sock.sendall(request)
        reply = b""
        while chunk := sock.recv(65536):
            reply += chunk
            if b"\r\n\r\n" in reply:
                _, headers, body = parse_reply(reply)
                if len(body) >= int(headers.get("content-length", "-1")) >= 0:
                    break
    return parse_reply(reply)


def parse_reply(reply: bytes) -> tuple[int, dict[str, str], bytes]:
    head, _, body = reply.partition(b"\r\n\r\n")
    lines = head.decode("latin-1").split("\r\n")
    headers = {}
    for line in lines[1:]:
        name, _, value = line.partition(":")
        headers[name.strip().lower()] = value.strip()
    return int(lines[0].split()[1]), headers, body


def get(
    port: int, target: str = "/", host: str | None = None, extra: str = ""
) -> tuple[int, dict[str, str], bytes]:
    """A GET with the given Host (default: 127.0.0.1:port; "" sends none) and extra headers."""
    host = f"127.0.0.1:{port}" if host is None else host
    host_line = f"Host: {host}\r\n" if host else ""
    request = f"GET {target} HTTP/1.1\r\n{host_line}{extra}Connection: close\r\n\r\n"
    return exchange(port, request.encode("latin-1"))


def handshake(path: str, port: int, host: str | None = None, extra: str = "") -> bytes:
    key = base64.b64encode(os.urandom(16)).decode()
    host = f"127.0.0.1:{port}" if host is None else host
    request = (
        f"GET {path} HTTP/1.1\r\nHost: {host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n{extra}\r\n"
    )
    return request.encode()


def websocket(port: int, *, receive_buffer: int | None = None) -> socket.socket:
    """A WebSocket on /ws after its 101 (the rest of the reply is left unread). With a small
    ``receive_buffer`` and no reads, the server's writes back up at once (a frozen tab)."""
    sock = socket.socket()
    if receive_buffer is not None:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, receive_buffer)
    sock.settimeout(30)
    sock.connect(("127.0.0.1", port))
    sock.sendall(handshake("/ws", port))
    assert sock.recv(12) == b"HTTP/1.1 101"
    return sock


def text_frame(text: str) -> bytes:
    """One masked WebSocket text frame, as a browser sends it."""
    payload, mask = text.encode(), os.urandom(4)
    size = len(payload)
    if size < 126:
        head = struct.pack(">BB", 0x81, 0x80 | size)
    elif size < 1 << 16:
        head = struct.pack(">BBH", 0x81, 0x80 | 126, size)
    else:
        head = struct.pack(">BBQ", 0x81, 0x80 | 127, size)
    return head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


def reset(sock: socket.socket) -> None:
    """Close with a TCP reset (a killed tab), not a polite FIN."""
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    sock.close()
