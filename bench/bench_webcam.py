"""The webcam channel's speed: hand tracker readings per second in headless chromium, and the
server's landmark-to-decision latency.

Run: ``python bench/bench_webcam.py [--runs 3] [--readings 12] [--wait 300]``.

1. **Server.** Every reading of ``tests/data/hands/landmarks.npz`` (what the tracker read from
   real footage), as the page's JSON message, through :func:`parse_input` and
   :meth:`HandReader.read`: read by the hand's shape, and again with a calibrated person's
   appearance model (one example per gesture). Timed per reading, from the raw message to the
   decision. Baseline, same run: :func:`parse_input` of a click message. Printed: the median
   over the runs of each per-reading median and 95th percentile, and their ratio to the click.
2. **Browser.** A real ``--webcam`` session (no calibration) behind the live server, Debian's
   headless chromium with its fake camera playing ``tests/data/hands/thumb_up.mp4``. From the
   page's own record (``window.robinLive.webcam.sentAt``): readings per second over the
   ``--readings`` after the first, and the seconds from opening the page to the first reading
   (tracker start-up). A run that gets fewer readings within ``--wait`` s reports what came.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from robin_sim.live.conductor import Conductor  # noqa: E402
from robin_sim.live.hands.landmarks import features, normalised  # noqa: E402
from robin_sim.live.hands.reader import HandReader  # noqa: E402
from robin_sim.live.inputs import parse_input  # noqa: E402
from robin_sim.live.server import LiveServer, bind  # noqa: E402
from robin_sim.live.session import LiveConfig  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HANDS = ROOT / "tests" / "data" / "hands"
sys.path.insert(0, str(ROOT / "tests" / "browser"))
from webcam_rig import camera_browser, write_y4m  # noqa: E402

CLICK = json.dumps({"type": "point", "x": 320, "y": 240})


def messages() -> tuple[list[str], dict[str, np.ndarray]]:
    """The footage's readings as the page's messages, and one example per gesture."""
    with np.load(HANDS / "landmarks.npz") as data:
        rows = {key: data[key] for key in data.files}
    raws, seeds = [], {}
    for k, points in enumerate(rows["landmarks"]):
        found = not np.isnan(points).any()
        side = str(rows["handedness"][k]) if found else None
        raws.append(
            json.dumps(
                {
                    "type": "hand",
                    "landmarks": np.round(points, 5).tolist() if found else None,
                    "handedness": side,
                    "score": float(rows["score"][k]) if found else 0.0,
                    "aspect": float(rows["aspect"][k]),
                }
            )
        )
        label = str(rows["label"][k])
        if found and label not in seeds:
            seeds[label] = features(normalised(points, side, float(rows["aspect"][k])))
    return raws, seeds


def accuracy() -> dict[str, float]:
    """How well the footage's readings are read (the same figures tests/test_webcam_accuracy.py
    holds to floors): by the shape rules (right and sure); by one-shot calibration (each
    gesture's first reading) on the held-out readings; and adapting, each held-out reading
    predicted, then confirmed (added) as an approved action would (prequential)."""
    from robin_sim.live.hands.appearance import Appearance
    from robin_sim.live.hands.reader import THRESHOLD
    from robin_sim.live.hands.shape import read_shape

    with np.load(HANDS / "landmarks.npz") as data:
        rows = {key: data[key] for key in data.files}
    found = [k for k, p in enumerate(rows["landmarks"]) if not np.isnan(p).any()]
    shapes = {
        k: normalised(rows["landmarks"][k], str(rows["handedness"][k]), float(rows["aspect"][k]))
        for k in found
    }
    labels = {k: str(rows["label"][k]) for k in found}
    sure = 0
    for k in found:
        label, certainty = read_shape(shapes[k])
        sure += label == labels[k] and float(rows["score"][k]) * certainty >= THRESHOLD
    one_shot, adapting, seen = Appearance(), Appearance(), set()
    held = []
    for k in found:
        if labels[k] in seen:
            held.append(k)
        else:
            seen.add(labels[k])
            one_shot.seed(labels[k], features(shapes[k]))
            adapting.seed(labels[k], features(shapes[k]))
    right = sum(one_shot.predict(features(shapes[k]))[0] == labels[k] for k in held)
    online = 0
    for k in held:
        online += adapting.predict(features(shapes[k]))[0] == labels[k]
        adapting.add(labels[k], features(shapes[k]))
    return {
        "found": len(found) / len(rows["label"]),
        "shape": sure / len(found),
        "one_shot": right / len(held),
        "adapting": online / len(held),
        "held_out": float(len(held)),
    }


def per_reading_ms(raws: list[str], reader: HandReader | None) -> list[float]:
    """ms per message: parsed, and read by ``reader`` (None: parsed only)."""
    times = []
    for k, raw in enumerate(raws):
        started = time.perf_counter()
        item = parse_input(raw, 640, 480)
        if reader is not None:
            assert item.hand is not None
            reader.read(item.hand, float(k))
        times.append((time.perf_counter() - started) * 1000.0)
    return times


def server_run(raws: list[str], seeds: dict[str, np.ndarray]) -> dict[str, float]:
    click = per_reading_ms([CLICK] * len(raws), None)
    shape = per_reading_ms(raws, HandReader(640, 480))
    learnt = HandReader(640, 480)
    for label, example in seeds.items():
        learnt.appearance.seed(label, example)
    learnt.calibrated = True
    person = per_reading_ms(raws, learnt)
    figures = {"click_ms": statistics.median(click)}
    for name, times in (("shape", shape), ("appearance", person)):
        figures[f"{name}_median_ms"] = statistics.median(times)
        figures[f"{name}_p95_ms"] = float(np.percentile(times, 95))
    return figures


def browser_run(folder: Path, readings: int, wait_s: float) -> dict[str, float]:
    """Readings/s of the tracker on the page of a real --webcam session."""
    folder.mkdir(parents=True, exist_ok=True)
    y4m = write_y4m(HANDS / "thumb_up.mp4", folder / "thumb.y4m")
    config = LiveConfig(
        scenario="one_handover",
        out_root=folder / "live",
        webcam=True,
        calibrate=False,
        video=False,
    )
    server = LiveServer(Conductor([config]))
    sock = bind("127.0.0.1", 0)
    port = sock.getsockname()[1]
    thread = threading.Thread(
        target=lambda: asyncio.run(server.serve(sock, handle_signals=False)), daemon=True
    )
    thread.start()
    try:
        with camera_browser(y4m) as browser:
            page = browser.new_page()
            opened = time.monotonic()
            page.goto(f"http://127.0.0.1:{port}/")
            first: float | None = None
            deadline = time.monotonic() + wait_s
            count = 0
            while time.monotonic() < deadline:
                count = page.evaluate("() => window.robinLive.webcam?.sentAt.length || 0")
                if count and first is None:
                    first = time.monotonic() - opened
                if count >= readings + 1:
                    break
                page.wait_for_timeout(250)
            stamps = page.evaluate("() => window.robinLive.webcam?.sentAt || []")
            page.close()
    finally:
        server.stop_soon()
        thread.join(60)
    rate = (len(stamps) - 1) / ((stamps[-1] - stamps[0]) / 1000.0) if len(stamps) > 1 else 0.0
    return {
        "readings": float(len(stamps)),
        "readings_per_s": rate,
        "start_up_s": float("nan") if first is None else first,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--readings", type=int, default=12)
    parser.add_argument("--wait", type=float, default=300.0, help="s a browser run waits at most")
    parser.add_argument("--no-browser", action="store_true", help="the server's latency only")
    args = smoke.parse_args(parser, runs=1, readings=2, wait=240.0)
    raws, seeds = messages()
    read = accuracy()
    print(
        f"accuracy on the footage's readings: hand found {read['found']:.1%}; shape rules "
        f"{read['shape']:.1%} right and sure; one-shot calibration {read['one_shot']:.1%} of "
        f"{read['held_out']:.0f} held out; adapting (each confirmed) {read['adapting']:.1%}"
    )
    server = [server_run(raws, seeds) for _ in range(args.runs)]
    print(f"server: {len(raws)} readings a run, {args.runs} runs (medians over the runs)")
    click = statistics.median(r["click_ms"] for r in server)
    print(f"  baseline: a click message parsed  {click:.4f} ms")
    for name in ("shape", "appearance"):
        median = statistics.median(r[f"{name}_median_ms"] for r in server)
        p95 = statistics.median(r[f"{name}_p95_ms"] for r in server)
        print(
            f"  landmarks -> decision ({name:10s}) median {median:.3f} ms, p95 {p95:.3f} ms "
            f"({median / click:.0f}x the click)"
        )
    if args.no_browser:
        return 0
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for run in range(args.runs):
            rows.append(browser_run(Path(folder) / f"run{run}", args.readings, args.wait))
            row = rows[-1]
            print(
                f"  browser run {run + 1}: {row['readings']:.0f} readings, "
                f"{row['readings_per_s']:.2f} readings/s, first after {row['start_up_s']:.1f} s",
                flush=True,
            )
    rate = statistics.median(r["readings_per_s"] for r in rows)
    start = statistics.median(r["start_up_s"] for r in rows)
    print(
        f"browser: headless chromium, fake camera, {rate:.2f} readings/s (median of "
        f"{len(rows)}), first reading {start:.1f} s after the page opened"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
