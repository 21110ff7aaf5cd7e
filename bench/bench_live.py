"""The live page's stream: frames/s a browser receives and draws, and physics-to-screen latency.

Run: ``python bench/bench_live.py [--runs 3] [--seconds 10] [--speed 1]``.
Each run starts a real session (default scenario, 640x480 at 15 frames/s, eye inset, MP4 on)
twice: once with no browser attached, counting the frames the engine itself produces (the
baseline), and once behind the live server with headless chromium (Debian's /usr/bin/chromium)
on the page. In both the participant points at leg 0 once the robot waits, so the robot moves
while it is measured. The page's own record (``window.robinLive``) gives the frames received
and drawn and, for each drawn frame, the wall-clock time from the physics state's rendering
(the frame's ``captured_ms``) to the ``drawImage`` in the page's animation frame. Printed: the
median over the runs of each figure, and drawn frames/s as a ratio of the engine's own rate.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import sys
import tempfile
import threading
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.episode.config import EpisodeConfig  # noqa: E402
from robin_sim.episode.physical_assembly import layout_of  # noqa: E402
from robin_sim.live.conductor import Conductor  # noqa: E402
from robin_sim.live.inputs import LiveInput  # noqa: E402
from robin_sim.live.picking import Picker  # noqa: E402
from robin_sim.live.server import LiveServer, bind  # noqa: E402
from robin_sim.live.session import LiveConfig, LiveSession  # noqa: E402
from robin_sim.model import names  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
WARMUP_S = 2.0


def leg_pixel(config: LiveConfig) -> tuple[float, float]:
    """Leg 0's centre in the frame (the engine's picking camera model)."""
    layout = layout_of(EpisodeConfig(scenario=config.scenario, video=False).spec().run.scenario)
    picker = Picker(layout, config.width, config.height)
    return picker.project(picker.data.xpos[picker.model.body(names.leg_body(0)).id])


def wait_phase(get_status: Any, phase: str, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while get_status().get("phase") != phase:
        if time.monotonic() > deadline:
            raise RuntimeError(f"no phase {phase} in {timeout} s")
        time.sleep(0.05)


def engine_alone(config: LiveConfig, seconds: float) -> dict[str, float]:
    """Frames/s the session produces with nothing attached but a counter."""
    session = LiveSession(config)
    stamps: list[float] = []
    session.subscribe(lambda frame: stamps.append(time.monotonic()))
    session.start()
    try:
        wait_phase(session.status, "waiting_for_gesture")
        x, y = leg_pixel(config)
        session.submit(LiveInput("point", x=x, y=y))
        time.sleep(WARMUP_S)
        start = time.monotonic()
        time.sleep(seconds)
        end = time.monotonic()
    finally:
        session.stop("ended")
    return {"engine_fps": sum(start <= t < end for t in stamps) / (end - start)}


def with_browser(config: LiveConfig, seconds: float, browser: Any) -> dict[str, float]:
    """Frames/s received and drawn by headless chromium, and the latency of drawn frames."""
    conductor = Conductor([config])
    server = LiveServer(conductor)
    sock = bind("127.0.0.1", 0)
    port = sock.getsockname()[1]
    thread = threading.Thread(
        target=lambda: asyncio.run(server.serve(sock, handle_signals=False)), daemon=True
    )
    thread.start()
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function(
            "() => window.robinLive.status && "
            "window.robinLive.status.phase === 'waiting_for_gesture'",
            timeout=120_000,
        )
        x, y = leg_pixel(config)
        box = page.locator("#scene").bounding_box()
        page.mouse.click(
            box["x"] + (x + 0.5) * box["width"] / config.width,
            box["y"] + (y + 0.5) * box["height"] / config.height,
        )
        page.wait_for_timeout(WARMUP_S * 1000)
        read = (
            "() => [performance.now(), window.robinLive.received, window.robinLive.drawn, "
            "window.robinLive.latencies.length]"
        )
        t0, received0, drawn0, _ = page.evaluate(read)
        page.wait_for_timeout(seconds * 1000)
        t1, received1, drawn1, count = page.evaluate(read)
        latencies = page.evaluate("() => window.robinLive.latencies")
        window = latencies[len(latencies) - (drawn1 - drawn0) :] if count else []
    finally:
        page.close()
        server.stop_soon()
        thread.join(60)
    elapsed = (t1 - t0) / 1000.0
    return {
        "received_fps": (received1 - received0) / elapsed,
        "drawn_fps": (drawn1 - drawn0) / elapsed,
        "latency_median_ms": statistics.median(window),
        "latency_p95_ms": statistics.quantiles(window, n=20)[-1],
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--speed", type=float, default=1.0)
    args = smoke.parse_args(parser, runs=1, seconds=1.0)
    from playwright.sync_api import sync_playwright

    rows: list[dict[str, float]] = []
    with tempfile.TemporaryDirectory() as folder, sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=CHROMIUM, headless=True, args=["--no-sandbox"]
        )
        for run in range(args.runs):
            base = LiveConfig(out_root=Path(folder), speed=args.speed)
            row = engine_alone(replace(base, session=f"alone{run}"), args.seconds)
            row |= with_browser(replace(base, session=f"page{run}"), args.seconds, browser)
            rows.append(row)
            print(
                f"run {run + 1}: " + ", ".join(f"{k} {v:.1f}" for k, v in row.items()),
                file=sys.stderr,
            )
        browser.close()
    median = {key: statistics.median(row[key] for row in rows) for key in rows[0]}
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    print(
        f"\nlive stream, 640x480 at 15 frames/s, speed {args.speed:g}x, "
        f"{args.runs} runs of {args.seconds:g} s (median); load average {load} on "
        f"{os.cpu_count()} CPUs\n"
    )
    print(f"| {'figure':<34} | {'median':>8} | {'runs':<24} |")
    print(f"|{'-' * 36}|{'-' * 10}|{'-' * 26}|")
    for key, value in median.items():
        runs = ", ".join(f"{row[key]:.1f}" for row in rows)
        print(f"| {key:<34} | {value:8.1f} | {runs:<24} |")
    ratio = median["drawn_fps"] / median["engine_fps"]
    print(f"| {'drawn / engine frames/s (ratio)':<34} | {ratio:8.2f} | {'':<24} |")
    print("\ntargets (issue 11): >= 15 frames/s drawn, latency < 200 ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
