"""Make the webcam tests' data from the Apache-2.0 footage (``LICENSE`` here; README.md).

Run once, from the repository root, with the footage folder (not needed at test time):

    python tests/data/hands/make_data.py /work/shared/hands

1. ``thumb_up.mp4`` and ``palm.mp4``: two seconds each of the held gesture, 640x360 (the
   browser tests turn them into the fake camera's ``.y4m``, the thumb down by a vertical flip).
2. ``landmarks.npz``: the vendored hand tracker, run in headless Debian chromium on frames of
   the footage (served from this machine's loopback, as the live page does), one reading per
   frame, each found afresh (the tracker reset before every frame: with tracking on from the
   blurred, moving start of the thumb up, it once took the raised thumb for the index finger
   for the whole sequence; the live page's readings of the held clip had the thumb on top).
   Sequences: the fist (grasp), the
   thumb up, the same frames flipped vertically (thumb down), the palm held out (give me) and
   the same rotated by 180 degrees (an open hand, fingers up: release). Arrays: ``landmarks``
   (N, 21, 3; NaN where no hand was found), ``handedness``, ``score``, ``aspect``, ``label``,
   ``sequence``, ``frame``.
"""

from __future__ import annotations

import asyncio
import base64
import sys
import threading
import time
from pathlib import Path

import av
import cv2
import numpy as np
from aiohttp import web

from robin_sim.live.guard import Guard
from robin_sim.live.hands.vendor import VENDOR_DIR, VENDOR_TYPES

HERE = Path(__file__).resolve().parent
SIZE = (640, 360)
# (sequence, source clip, frames, transform, label)
SEQUENCES = (
    ("fist", "fist_then_thumb_up.mp4", range(24, 45), "none", "grasp"),
    ("thumb_up", "fist_then_thumb_up.mp4", range(64, 195, 5), "none", "thumb_up"),
    ("thumb_down", "fist_then_thumb_up.mp4", range(64, 195, 5), "vflip", "thumb_down"),
    ("palm", "open_palm_offered.mp4", range(45, 202, 5), "none", "give_me"),
    ("open_up", "open_palm_offered.mp4", range(45, 202, 5), "rot180", "release"),
)
CLIPS = (
    ("thumb_up.mp4", "fist_then_thumb_up.mp4", 100),
    ("palm.mp4", "open_palm_offered.mp4", 100),
)
CLIP_FRAMES = 50  # two seconds at 25 frames/s


def frames_of(path: Path) -> list[np.ndarray]:
    """Every frame of a clip, RGB, scaled to :data:`SIZE`."""
    with av.open(str(path)) as container:
        return [
            cv2.resize(f.to_ndarray(format="rgb24"), SIZE, interpolation=cv2.INTER_AREA)
            for f in container.decode(video=0)
        ]


def transformed(frame: np.ndarray, how: str) -> np.ndarray:
    if how == "vflip":
        return frame[::-1].copy()
    if how == "rot180":
        return frame[::-1, ::-1].copy()
    return frame


def write_clip(frames: list[np.ndarray], path: Path) -> None:
    """A short H.264 clip (small enough to commit)."""
    with av.open(str(path), "w") as container:
        stream = container.add_stream("libx264", rate=25)
        stream.width, stream.height, stream.pix_fmt = SIZE[0], SIZE[1], "yuv420p"
        stream.options = {"crf": "20", "preset": "slow"}
        for frame in frames:
            for packet in stream.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)


def serve() -> tuple[int, asyncio.AbstractEventLoop]:
    """The harness page and the vendored tracker on a loopback port, with the live server's
    headers (its CSP with WebAssembly allowed, as with ``--webcam``)."""
    guard = Guard("127.0.0.1", wasm=True)
    app = web.Application(middlewares=[guard.middleware])
    guard.install(app)

    async def page(request: web.Request) -> web.Response:
        return web.Response(text=(HERE / "harness.html").read_text(), content_type="text/html")

    async def script(request: web.Request) -> web.Response:
        return web.Response(text=(HERE / "harness.js").read_text(), content_type="text/javascript")

    async def vendor(request: web.Request) -> web.Response:
        name = request.match_info["name"]
        if name not in VENDOR_TYPES:
            raise web.HTTPNotFound()
        return web.Response(body=(VENDOR_DIR / name).read_bytes(), content_type=VENDOR_TYPES[name])

    app.router.add_get("/", page)
    app.router.add_get("/harness.js", script)
    app.router.add_get("/static/vendor/{name}", vendor)
    loop = asyncio.new_event_loop()
    started: list[int] = []

    def main() -> None:
        asyncio.set_event_loop(loop)
        runner = web.AppRunner(app, access_log=None)
        loop.run_until_complete(runner.setup())
        site = web.TCPSite(runner, "127.0.0.1", 0)
        loop.run_until_complete(site.start())
        started.append(site._server.sockets[0].getsockname()[1])  # type: ignore[union-attr]
        guard.hosts.bind_to(("127.0.0.1", started[0]))
        loop.run_forever()

    threading.Thread(target=main, daemon=True).start()
    while not started:
        time.sleep(0.05)
    return started[0], loop


def main(footage: Path) -> None:
    from playwright.sync_api import sync_playwright

    sources = {name: frames_of(footage / name) for name in {s[1] for s in SEQUENCES}}
    for out, source, first in CLIPS:
        write_clip(sources[source][first : first + CLIP_FRAMES], HERE / out)
    port, _ = serve()
    rows: dict[str, list] = {
        k: [] for k in ("landmarks", "handedness", "score", "aspect", "label", "sequence", "frame")
    }
    foreign: list[str] = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path="/usr/bin/chromium", headless=True, args=["--no-sandbox"]
        )
        page = browser.new_page()
        page.on(
            "request",
            lambda r: (
                None if r.url.startswith(f"http://127.0.0.1:{port}/") else foreign.append(r.url)
            ),
        )
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function(
            "() => window.harness.ready || window.harness.error", timeout=300_000
        )
        assert page.evaluate("() => window.harness.error") is None
        started = time.perf_counter()
        for name, source, frames, how, label in SEQUENCES:
            found = 0
            for k in frames:
                page.evaluate("() => window.harness.reset()")
                image = transformed(sources[source][k], how)
                _, jpeg = cv2.imencode(".jpg", image[:, :, ::-1], [cv2.IMWRITE_JPEG_QUALITY, 92])
                url = "data:image/jpeg;base64," + base64.b64encode(jpeg.tobytes()).decode()
                reading = page.evaluate("(url) => window.harness.read(url)", url)
                marks = reading["landmarks"]
                found += marks is not None
                rows["landmarks"].append(np.full((21, 3), np.nan) if marks is None else marks)
                rows["handedness"].append(reading["handedness"] or "")
                rows["score"].append(reading["score"])
                rows["aspect"].append(SIZE[0] / SIZE[1])
                rows["label"].append(label)
                rows["sequence"].append(name)
                rows["frame"].append(k)
            print(f"{name}: hand found in {found} of {len(frames)} frames", flush=True)
        took = time.perf_counter() - started
        browser.close()
    assert not foreign, f"requests left the machine: {foreign}"
    n = len(rows["label"])
    print(f"{n} readings in {took:.0f} s ({n / took:.2f} readings/s)")
    np.savez_compressed(
        HERE / "landmarks.npz",
        landmarks=np.asarray(rows["landmarks"], np.float32),
        handedness=np.asarray(rows["handedness"]),
        score=np.asarray(rows["score"], np.float32),
        aspect=np.asarray(rows["aspect"], np.float32),
        label=np.asarray(rows["label"]),
        sequence=np.asarray(rows["sequence"]),
        frame=np.asarray(rows["frame"], np.int32),
    )


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/hands"))
