"""The live server's pages: the participant's page, the experimenter's, their static files.

``GET /`` serves the participant's page, ``GET /experimenter`` the experimenter's (it always
needs its own token, on loopback too), ``GET /static/NAME`` one of the page's own files and, with
``--webcam``, ``GET /static/vendor/NAME`` the hand tracker's, each from a fixed list by exact
name (no path from a request ever reaches the file system). :meth:`Pages.token_check` answers
403 to any request without the access token when the server needs one.
"""

from __future__ import annotations

import asyncio
import html
import json
import secrets
from pathlib import Path
from typing import Any

from aiohttp import web

from pil.types import SIGN_NAMES, sign_label
from robin_sim.live.hands.shape import POINTING_SIGN
from robin_sim.live.hands.vendor import TEXT_TYPES, VENDOR_DIR, VENDOR_TYPES
from robin_sim.live.inputs import (
    GESTURE_KEYS,
    GESTURE_SHORTCUTS,
    TAKE_BACK_LABEL,
    TAKE_BACK_SHORTCUT,
)
from robin_sim.live.take_back import TAKE_BACK_WINDOW_S

STATIC_DIR = Path(__file__).with_name("static")
# what the participant's page takes from the Python source, not retyped (its body's
# data-constants): the six signs' names and labels, the one that moves the cursor, the
# gesture keys a message may name with their keyboard shortcuts, and "That was wrong"'s
PAGE_CONSTANTS = html.escape(
    json.dumps(
        {
            "signs": {name: sign_label(name) for name in SIGN_NAMES},
            "cursor": POINTING_SIGN,
            "gestures": list(GESTURE_KEYS),
            "shortcuts": {key: GESTURE_SHORTCUTS[key] for key in GESTURE_KEYS},
            "take_back": {
                "label": TAKE_BACK_LABEL,
                "key": TAKE_BACK_SHORTCUT,
                "window_s": TAKE_BACK_WINDOW_S,
            },
        }
    )
)
STATIC_TYPES = {  # all /static/ serves
    "live.js": "text/javascript",
    "live.css": "text/css",
    "experimenter.js": "text/javascript",
    "questionnaire.js": "text/javascript",
    "screens.js": "text/javascript",
    "questionnaire.css": "text/css",
    "webcam.js": "text/javascript",
}


class Pages:
    """The HTTP side of the live server (see the module doc)."""

    def __init__(self, token: str | None, experimenter_token: str, *, webcam: bool) -> None:
        self.token, self.experimenter_token, self.webcam = token, experimenter_token, webcam

    def install(self, app: web.Application) -> None:
        """Add the pages' routes to ``app``."""
        app.router.add_get("/", self._index)
        app.router.add_get("/static/{name}", self._static)
        app.router.add_get("/static/vendor/{name}", self._vendor)
        app.router.add_get("/favicon.ico", self._no_icon)
        app.router.add_get("/experimenter", self._experimenter_page)

    @web.middleware
    async def token_check(self, request: web.Request, handler: Any) -> web.StreamResponse:
        """403 without the token (when one is required); Host and Origin: :class:`Guard`."""
        if self.token is not None:
            given = request.query.get("token", "")
            if not (
                secrets.compare_digest(given.encode(), self.token.encode())
                or self.is_experimenter(request)
            ):
                return web.Response(
                    status=403,
                    text="403: this server needs ?token=... (the URL printed when it started)\n",
                )
        return await handler(request)

    def _query(self) -> str:
        return "" if self.token is None else f"?token={self.token}"

    def is_experimenter(self, request: web.Request) -> bool:
        given = request.query.get("token", "")
        return secrets.compare_digest(given.encode(), self.experimenter_token.encode())

    async def _experimenter_page(self, request: web.Request) -> web.Response:
        if not self.is_experimenter(request):
            return web.Response(
                status=403,
                text="403: the experimenter's view needs its own "
                "?token=... (printed when the server started)\n",
            )
        page = (STATIC_DIR / "experimenter.html").read_text(encoding="utf-8")
        page = page.replace("{{CONSTANTS}}", PAGE_CONSTANTS)  # live.js reads them here too
        query = f"?token={self.experimenter_token}"
        return web.Response(text=page.replace("{{QUERY}}", query), content_type="text/html")

    async def _index(self, request: web.Request) -> web.Response:
        page = (STATIC_DIR / "index.html").read_text(encoding="utf-8")
        page = page.replace("{{WEBCAM}}", "on" if self.webcam else "off")
        page = page.replace("{{CONSTANTS}}", PAGE_CONSTANTS)
        return web.Response(text=page.replace("{{QUERY}}", self._query()), content_type="text/html")

    async def _no_icon(self, request: web.Request) -> web.Response:
        return web.Response(status=204)

    async def _static(self, request: web.Request) -> web.Response:
        name = request.match_info["name"]
        if name not in STATIC_TYPES:  # only the page's own files, by exact name
            raise web.HTTPNotFound(text="404: not one of the page's files\n")
        body = (STATIC_DIR / name).read_bytes()
        return web.Response(body=body, content_type=STATIC_TYPES[name], charset="utf-8")

    async def _vendor(self, request: web.Request) -> web.Response:
        """The hand tracker's files (``--webcam`` only), by exact name as well."""
        name = request.match_info["name"]
        if not self.webcam or name not in VENDOR_TYPES:
            raise web.HTTPNotFound(text="404: not one of the page's files\n")
        kind = VENDOR_TYPES[name]
        body = await asyncio.to_thread((VENDOR_DIR / name).read_bytes)
        charset = "utf-8" if kind in TEXT_TYPES else None
        return web.Response(body=body, content_type=kind, charset=charset)
