"""A recorded run on a web page with a timeline to scrub: ``robin-pil replay DIR --serve``.

The server (aiohttp, 127.0.0.1 only) serves the page (``GET /``, ``/static/replay.js``), the run's
frame times (``GET /meta``), what happened when (``GET /events``: the steps, gestures, thumbs,
notes, events and questionnaires of :func:`robin_sim.replay.annotations.timeline`) and any frame
as JPEG (``GET /frame/N``), rendered on demand by a
:class:`~robin_sim.replay.render.ReplayRenderer` in one thread of its own (its OpenGL contexts
stay there). Requests whose ``Host`` is not this loopback address are refused (403: no DNS
rebinding), and the page may not be framed by another site.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import json
import socket
from collections import OrderedDict
from pathlib import Path
from typing import Any

import cv2
from aiohttp import web

from robin_sim.render.state_log import RecordedStates

STATIC_DIR = Path(__file__).with_name("static")
JPEG_QUALITY = 85
CACHED_FRAMES = 64  # JPEGs kept for scrubbing back and forth
HEADERS = {
    "Content-Security-Policy": "default-src 'self'; img-src 'self' blob:; style-src 'self' "
    "'unsafe-inline'; script-src 'self'; frame-ancestors 'none'",
    "X-Frame-Options": "DENY",
    "X-Content-Type-Options": "nosniff",
    "Cache-Control": "no-store",
}


class FrameSource:
    """JPEGs of the recorded frames, rendered one at a time in a thread of their own."""

    def __init__(self, recorded: RecordedStates) -> None:
        self.recorded = recorded
        self._executor = concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="replay-gl")
        self._renderer: Any = None
        self._cache: OrderedDict[int, bytes] = OrderedDict()

    def jpeg(self, index: int) -> bytes:
        """Frame ``index`` as JPEG (in the render thread)."""
        if index in self._cache:
            self._cache.move_to_end(index)
            return self._cache[index]
        if self._renderer is None:
            from robin_sim.replay.render import ReplayRenderer

            self._renderer = ReplayRenderer(self.recorded)
        pixels = self._renderer.render(index)
        ok, data = cv2.imencode(
            ".jpg",
            cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR),
            [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY],
        )
        if not ok:  # pragma: no cover - OpenCV fails only on a bad image
            raise RuntimeError(f"JPEG encoding of frame {index} failed")
        self._cache[index] = data.tobytes()
        if len(self._cache) > CACHED_FRAMES:
            self._cache.popitem(last=False)
        return self._cache[index]

    async def frame(self, index: int) -> bytes:
        loop = asyncio.get_running_loop()
        return await loop.run_in_executor(self._executor, self.jpeg, index)

    def close(self) -> None:
        def free() -> None:
            if self._renderer is not None:
                self._renderer.close()

        self._executor.submit(free).result()
        self._executor.shutdown()


def replay_app(
    recorded: RecordedStates,
    source: FrameSource,
    port: int,
    annotations: dict[str, Any] | None = None,
) -> web.Application:
    """The page's application; only ``Host`` 127.0.0.1:``port`` / localhost:``port`` pass.
    ``annotations``: the timeline's markers and steps (none without)."""
    hosts = {f"127.0.0.1:{port}", f"localhost:{port}"}
    t0 = recorded.states[0].time
    meta = {
        "kind": recorded.meta.get("kind"),
        "size": recorded.meta["size"],
        "fps": recorded.meta["fps"],
        "frames": len(recorded.states),
        "times": [round(s.time - t0, 4) for s in recorded.states],
    }

    @web.middleware
    async def guard(request: web.Request, handler: Any) -> web.StreamResponse:
        if request.host not in hosts:
            return web.Response(
                status=403, text=f"403: this server answers only http://127.0.0.1:{port}/\n"
            )
        response = await handler(request)
        response.headers.update(HEADERS)
        return response

    async def index(_: web.Request) -> web.Response:
        return web.Response(
            text=(STATIC_DIR / "replay.html").read_text(encoding="utf-8"), content_type="text/html"
        )

    async def script(_: web.Request) -> web.Response:
        return web.Response(
            text=(STATIC_DIR / "replay.js").read_text(encoding="utf-8"),
            content_type="text/javascript",
        )

    async def meta_json(_: web.Request) -> web.Response:
        return web.Response(text=json.dumps(meta), content_type="application/json")

    marks = json.dumps(annotations or {"markers": [], "steps": []})

    async def events_json(_: web.Request) -> web.Response:
        return web.Response(text=marks, content_type="application/json")

    async def frame(request: web.Request) -> web.Response:
        text = request.match_info["index"]
        if not text.isdigit() or len(text) > 9 or int(text) >= len(recorded.states):
            raise web.HTTPNotFound(text=f"404: frames are 0 to {len(recorded.states) - 1}\n")
        return web.Response(body=await source.frame(int(text)), content_type="image/jpeg")

    app = web.Application(middlewares=[guard])
    app.router.add_get("/", index)
    app.router.add_get("/static/replay.js", script)
    app.router.add_get("/meta", meta_json)
    app.router.add_get("/events", events_json)
    app.router.add_get("/frame/{index}", frame)
    return app


async def serve_replay(
    recorded: RecordedStates,
    sock: socket.socket,
    stop: asyncio.Event | None = None,
    annotations: dict[str, Any] | None = None,
) -> None:
    """Serve on the listening ``sock`` until ``stop`` is set (or the task is cancelled)."""
    port = sock.getsockname()[1]
    source = FrameSource(recorded)
    runner = web.AppRunner(
        replay_app(recorded, source, port, annotations),
        access_log=None,
        handle_signals=False,
        shutdown_timeout=1.0,
    )
    await runner.setup()
    try:
        await web.SockSite(runner, sock).start()
        await (stop or asyncio.Event()).wait()
    finally:
        await runner.cleanup()
        source.close()
