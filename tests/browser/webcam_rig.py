"""The webcam tests' rig: a committed clip as Chromium's fake camera, and a browser that uses it.

Chromium's fake capture device plays a ``.y4m`` file (YUV4MPEG2, 4:2:0) in a loop; the clips
under ``tests/data/hands`` (Apache-2.0 footage, see its README) are turned into one at test
time, flipped vertically for a thumb down. The browser is Debian's chromium (never a download).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import av
import numpy as np

HANDS = Path(__file__).resolve().parents[1] / "data" / "hands"
CHROMIUM = Path("/usr/bin/chromium")


def write_y4m(clip: Path, out: Path, *, vflip: bool = False, fps: int = 25) -> Path:
    """``clip``'s frames as a ``.y4m`` file for the fake camera (flipped upside down if asked)."""
    with av.open(str(clip)) as container:
        frames = [f.to_ndarray(format="rgb24") for f in container.decode(video=0)]
    height, width = frames[0].shape[:2]
    with out.open("wb") as y4m:
        y4m.write(f"YUV4MPEG2 W{width} H{height} F{fps}:1 Ip A1:1 C420jpeg\n".encode())
        for rgb in frames:
            if vflip:
                rgb = np.ascontiguousarray(rgb[::-1])
            yuv = av.VideoFrame.from_ndarray(rgb, format="rgb24").reformat(format="yuv420p")
            y4m.write(b"FRAME\n" + yuv.to_ndarray().tobytes())
    return out


@contextmanager
def camera_browser(y4m: Path | None) -> Iterator[Any]:
    """Headless chromium whose camera plays ``y4m`` (None: a browser with no camera at all,
    whose pages are refused the camera)."""
    from playwright.sync_api import sync_playwright

    assert CHROMIUM.exists(), f"{CHROMIUM} is missing: apt-get install chromium (see .ci/run)"
    args = ["--no-sandbox", "--use-fake-ui-for-media-stream"]
    if y4m is not None:
        args += ["--use-fake-device-for-media-stream", f"--use-file-for-fake-video-capture={y4m}"]
    else:
        args = ["--no-sandbox", "--deny-permission-prompts"]
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=str(CHROMIUM), headless=True, args=args
        )
        try:
            yield browser
        finally:
            browser.close()


def readings(page: Any) -> list[dict[str, Any]]:
    """What the server answered to the page's readings (newest last)."""
    return page.evaluate("() => window.robinLive.webcam.replies")
