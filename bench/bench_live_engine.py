"""The live session's stream at real time: frames per second and latency from physics to frame.

    python bench/bench_live_engine.py [--seconds 8] [--repeats 3] [--fps 15]

Each timed run is a real :class:`robin_sim.live.session.LiveSession` at 1x real time, 640x480:
it starts, the participant clicks leg 0 (the robot moves while frames stream), and after
``--seconds`` of wall time from that click the session is stopped. Measured per run: frames
published per wall second, the latency from capturing the physics state to the published
JPEG (median and 95th percentile), and the wall time physics fell behind its pace. Cases:

* the stream as shipped: scene + eye inset rendered in the physics thread, no floor reflection
* the same with the reflection (as the episode's video has it)
* the eye inset rendered in a worker process meanwhile, or the scene in 2 render workers
  (:class:`robin_sim.render.pool.RenderPool`)
* the baseline, measured in the same run: the scene alone, in-process, without the eye inset

Before the rounds, the cost of each part of a frame is timed in this process (median of 20):
the scene and the eye inset with and without the floor's reflection, JPEG and H.264.

"ms a frame" is the wall time the physics thread spends on one frame (rendering, inset, JPEG,
MP4): 1000 / it is the frame rate the stream could reach. Figures are medians of ``--repeats``
runs (the cases take turns in each round, so load from other processes hits all alike),
printed as a table with the ratio to the baseline.
"""

from __future__ import annotations

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

BACKEND = ensure_gl_backend()  # before mujoco is imported

import argparse  # noqa: E402
import os  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import cv2  # noqa: E402
import mujoco  # noqa: E402
from live_driver import Driver  # noqa: E402

from robin_sim.live.session import LiveConfig, LiveSession  # noqa: E402
from robin_sim.model.names import DEFAULT_CAMERA, EYE_CAMERA  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.inset import inset_size  # noqa: E402
from robin_sim.render.renderer import FrameRenderer  # noqa: E402
from robin_sim.render.video import Mp4Writer  # noqa: E402

CASES: dict[str, dict[str, object]] = {
    "scene + eye in-process, no reflection (shipped)": {},
    "the same with the floor's reflection": {"reflections": True},
    "eye in a worker process": {"eye_worker": True},
    "scene in 2 render workers": {"render_workers": 2},
    "baseline: scene only, in-process": {"eye_inset": False},
}


def one_run(root: Path, name: str, seconds: float, fps: int, **options: object) -> dict:
    """One session of ``seconds`` wall time after the first click; its live figures."""
    config = LiveConfig(scenario="one_handover", out_root=root, session=name, fps=fps, **options)  # type: ignore[arg-type]
    session = LiveSession(config)
    session.start()
    driver = Driver(session)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        time.sleep(seconds)
    finally:
        summary = session.stop("interrupted")
    return summary["live"] | {"real_time_factor": summary["real_time_factor"]}


def part_costs(frames: int = 20) -> dict[str, float]:
    """Median ms of each part of a frame, timed one after the other in this process."""
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    costs: dict[str, float] = {}

    def timed(name: str, work) -> object:
        times, out = [], None
        for _ in range(frames):
            started = time.perf_counter()
            out = work()
            times.append(time.perf_counter() - started)
        costs[name] = statistics.median(times) * 1000
        return out

    pixels = None
    for reflections in (True, False):
        what = "with" if reflections else "without"
        for camera, size in ((DEFAULT_CAMERA, (640, 480)), (EYE_CAMERA, inset_size(640, 480))):
            with FrameRenderer(model, *size, camera, False, reflections) as renderer:
                renderer.render(data)  # warm-up
                label = "scene 640x480" if camera == DEFAULT_CAMERA else "eye inset 160x120"
                image = timed(f"{label}, {what} reflection", lambda r=renderer: r.render(data))
                pixels = image if camera == DEFAULT_CAMERA else pixels
    bgr = cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR)
    timed("JPEG (cv2.imencode, quality 80)", lambda: cv2.imencode(".jpg", bgr))
    with tempfile.TemporaryDirectory() as tmp, Mp4Writer(Path(tmp) / "v.mp4", 640, 480, 15) as mp4:
        timed("H.264 (libx264, one frame)", lambda: mp4.write(pixels))
    return costs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=8.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--fps", type=int, default=15)
    args = smoke.parse_args(parser, seconds=1.0, repeats=1)
    costs = part_costs()
    print("| part of a frame | ms |\n|---|---|")
    for name, ms in costs.items():
        print(f"| {name} | {ms:.1f} |")
    results: dict[str, list[dict]] = {case: [] for case in CASES}
    with tempfile.TemporaryDirectory() as tmp:
        for round_ in range(args.repeats):
            for k, (case, options) in enumerate(CASES.items()):
                live = one_run(Path(tmp), f"r{round_}c{k}", args.seconds, args.fps, **options)
                results[case].append(live)
                print(
                    f"round {round_ + 1} {case}: {live['stream_fps']} frames/s, "
                    f"latency {live['latency_ms']} ms, behind {live['behind_s']} s",
                    flush=True,
                )

    def median(case: str, key: str, sub: str | None = None) -> float:
        values = [r[key][sub] if sub else r[key] for r in results[case]]
        return statistics.median(values)

    base = median(list(CASES)[-1], "stream_fps")
    print(
        f"\n{BACKEND} rendering, {os.cpu_count()} CPUs, 640x480, target {args.fps} frames/s at 1x"
        f" real time; medians of {args.repeats} runs of {args.seconds:.0f} s\n"
    )
    print(
        "| case | frames/s | vs baseline | latency median ms | latency p95 ms | behind s "
        "| ms a frame (physics thread) |"
    )
    print("|---|---|---|---|---|---|---|")
    for case in CASES:
        fps = median(case, "stream_fps")
        latency = median(case, "latency_ms", "median"), median(case, "latency_ms", "p95")
        behind = median(case, "behind_s")
        busy = median(case, "frame_ms")
        print(
            f"| {case} | {fps:.1f} | {fps / base:.2f}x | {latency[0]:.0f} | {latency[1]:.0f} "
            f"| {behind:.2f} | {busy:.0f} |"
        )


if __name__ == "__main__":
    main()
