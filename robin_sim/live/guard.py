"""Who may talk to the live server: the Host and Origin allow-list and the headers of every reply.

A page on another site can reach a server on 127.0.0.1 through DNS rebinding: its own name
(``evil.example``) is made to resolve to 127.0.0.1, so the browser sends the page's requests
here with ``Host: evil.example:PORT`` and a matching ``Origin``. Comparing Origin with the
request's own Host lets that through; :class:`HostCheck` instead compares both with the names
this server is known by: loopback (``localhost``, ``127.0.0.1``, ``[::1]``, ...) and the
``--host`` given, always with the bound port. A wildcard bind (``0.0.0.0``, ``::``) also takes
the machine's own names and any IP literal (a rebinding attack needs a DNS name; such a server
needs the access token anyway). Anything else is answered 421 (Host) or 403 (Origin) before a
handler runs, and logged in one line per distinct value.

:data:`SECURITY_HEADERS` go on every response the application makes, the WebSocket handshake
and the refusals included: no framing (``X-Frame-Options: DENY``, CSP ``frame-ancestors
'none'``), only the page's own scripts and styles, no sniffing, no referrer, no caching.
"""

from __future__ import annotations

import ipaddress
import logging
import re
import socket
from collections.abc import Awaitable, Callable
from typing import Any
from urllib.parse import urlsplit

from aiohttp import web

LOG = logging.getLogger(__name__)
LOOPBACK_NAMES = ("localhost",)
WILDCARDS = ("0.0.0.0", "::", "")
SECURITY_HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' blob: data:; "
    "connect-src 'self'; style-src 'self'; script-src 'self'; object-src 'none'; "
    "base-uri 'none'; form-action 'none'; frame-ancestors 'none'",
    "X-Frame-Options": "DENY",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}
# With --webcam the page compiles the hand tracker's WebAssembly (served here): only that is
# added; scripts still come from this server alone, and eval stays refused.
WASM_SCRIPT_SRC = ("script-src 'self'", "script-src 'self' 'wasm-unsafe-eval'")
# host[:port], the host a name or a bracketed IPv6 literal: nothing else (no userinfo, no path)
NETLOC = re.compile(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+)(?::([0-9]{1,5}))?")
MAX_LOGGED = 20  # distinct refused values logged; later ones are counted, not logged
Handler = Callable[[web.Request], Awaitable[web.StreamResponse]]


def is_loopback(host: str) -> bool:
    """Whether ``host`` is reachable only from this machine."""
    if host.lower() in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def _ip(host: str) -> ipaddress.IPv4Address | ipaddress.IPv6Address | None:
    try:
        return ipaddress.ip_address(host.strip("[]"))
    except ValueError:
        return None


class HostCheck:
    """The names (with the bound port) that a request's Host and a page's Origin may carry."""

    def __init__(self, host: str | None = None) -> None:
        self.given = None if host is None else host.strip().strip("[]").lower()
        self.port: int | None = None  # set by bind_to once the socket is bound
        self.bound: str | None = None
        self.names: set[str] = set(LOOPBACK_NAMES)
        if self.given is not None and _ip(self.given) is None:
            self.names.add(self.given)
        self.wildcard = self.given in WILDCARDS
        if self.wildcard:
            self.names.update(n.lower() for n in (socket.gethostname(), socket.getfqdn()) if n)

    def bind_to(self, address: tuple[Any, ...]) -> None:
        """Take the bound address and port (the listening socket's ``getsockname()``)."""
        self.bound, self.port = str(address[0]).lower(), int(address[1])
        if self.given is None and not is_loopback(self.bound):
            self.wildcard = self.bound in WILDCARDS

    def allows(self, netloc: str | None) -> bool:
        """Whether ``netloc`` (``host[:port]``) names this server."""
        match = NETLOC.fullmatch(netloc or "")
        if match is None or self.port is None:
            return False
        host, port = match.group(1).lower(), int(match.group(2) or 80)
        if port != self.port:
            return False
        ip = _ip(host)
        if ip is None:
            return not host.startswith("[") and host in self.names
        if host.startswith("[") != (ip.version == 6):
            return False  # IPv6 literals come in brackets, IPv4 ones without
        plain = str(ip)
        return ip.is_loopback or self.wildcard or plain in (self.bound, self.given)

    def allows_origin(self, origin: str) -> bool:
        """Whether a page's ``Origin`` (scheme://host[:port]) is this server's own page."""
        try:
            parts = urlsplit(origin)
        except ValueError:
            return False
        if parts.scheme != "http" or parts.path or parts.query or parts.fragment:
            return False
        return self.allows(parts.netloc)

    def shown(self) -> str:
        """The allowed names, for the log."""
        names = [*sorted(self.names), "127.0.0.1", "[::1]"]
        if self.given is not None and _ip(self.given) is not None:
            names.append(self.given)
        return ", ".join(f"{n}:{self.port}" for n in dict.fromkeys(names))


class RefusalLog:
    """One warning line per distinct refused value, up to :data:`MAX_LOGGED` of them."""

    def __init__(self) -> None:
        self.seen: set[str] = set()
        self.refused = 0

    def note(self, what: str, value: str, allowed: str) -> None:
        self.refused += 1
        key = f"{what}:{value[:100]}"
        if key in self.seen or len(self.seen) > MAX_LOGGED:
            return
        self.seen.add(key)
        if len(self.seen) > MAX_LOGGED:
            LOG.warning("more refused requests; no longer logged one by one")
            return
        LOG.warning(
            "refused a request with %s %r: not this server (allowed: %s)",
            what,
            value[:100],
            allowed,
        )


class Guard:
    """The middleware that refuses foreign Host and Origin values, and the reply headers."""

    def __init__(
        self,
        host: str | None = None,
        on_request: Callable[[web.Request], None] | None = None,
        *,
        wasm: bool = False,
    ) -> None:
        """``wasm``: the page may compile WebAssembly from this server (``--webcam``)."""
        self.hosts = HostCheck(host)
        self.headers = dict(SECURITY_HEADERS)
        if wasm:
            policy = self.headers["Content-Security-Policy"]
            self.headers["Content-Security-Policy"] = policy.replace(*WASM_SCRIPT_SRC)
        self.log = RefusalLog()
        self.on_request = on_request  # told of every whole request (before any check)

    @web.middleware
    async def middleware(self, request: web.Request, handler: Handler) -> web.StreamResponse:
        """421 for a Host that is not this server, 403 for another site's page."""
        if self.on_request is not None:
            self.on_request(request)
        host = request.headers.get("Host")
        if not self.hosts.allows(host):
            self.log.note("Host", str(host), self.hosts.shown())
            return _refusal(
                421,
                "421: this server answers only to its own address (e.g. http://127.0.0.1:PORT/)\n",
            )
        origin = request.headers.get("Origin")
        if origin is not None and not self.hosts.allows_origin(origin):
            self.log.note("Origin", origin, self.hosts.shown())
            return _refusal(403, "403: requests from other sites' pages\n")
        return await handler(request)

    async def add_headers(self, request: web.Request, response: web.StreamResponse) -> None:
        """``on_response_prepare``: the security headers on every response."""
        response.headers.update(self.headers)

    def install(self, app: web.Application) -> None:
        """Put the headers on every response of ``app`` (the middleware is given to it)."""
        app.on_response_prepare.append(self.add_headers)


def _refusal(status: int, text: str) -> web.Response:
    """A short refusal that also closes the connection (a refused client keeps nothing open)."""
    response = web.Response(status=status, text=text)
    response.force_close()
    return response
