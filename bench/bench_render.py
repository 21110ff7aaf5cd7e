"""Rendering and H.264 encoding speed against raw physics, measured in one run.

    python bench/bench_render.py [--model models/scene.xml] [--frames 20] [--repeats 5]

Prints a table: frames per second for 640x480 renders of each camera with and without shadows,
the 320x240 segmentation + depth views of :mod:`robin_sim.render.checks` (a check takes 1-5 of
them),
PyAV libx264 encoding at 640x480 / 30 fps, and raw ``mj_step`` steps per second of the same
model; each figure is the median of ``--repeats`` runs. The ratio columns say what one second
of 30 fps video costs next to one second of simulated physics (``1 / timestep`` steps).
Without ``--model`` the project scene is used when it exists, else a small built-in scene.
"""

from __future__ import annotations

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

BACKEND = ensure_gl_backend()  # before mujoco is imported

import argparse  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from robin_sim.model.names import SCENE_XML  # noqa: E402
from robin_sim.render.renderer import CloseUpRenderer, FrameRenderer, camera_names  # noqa: E402
from robin_sim.render.video import Mp4Writer  # noqa: E402

WIDTH, HEIGHT, FPS = 640, 480, 30
FALLBACK_SCENE = """
<mujoco model="bench">
  <option timestep="0.002" integrator="implicitfast"/>
  <visual><global offwidth="640" offheight="480"/></visual>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    <geom type="plane" size="3 3 .1" rgba=".6 .6 .6 1"/>
    <geom type="box" size="0.4 0.5 0.02" pos="0.4 0 0.73" rgba=".7 .5 .3 1"/>
    <body pos="0.4 0 1"><freejoint/><geom type="capsule" size="0.02 0.1" rgba="1 0 0 1"/></body>
    <body pos="0.5 0.2 1.2"><freejoint/><geom type="box" size="0.05 0.05 0.05"/></body>
    <camera name="front" pos="1.6 0 1.5" xyaxes="0 1 0 -0.5 0 0.87"/>
    <camera name="side" pos="0.4 -1.6 1.5" xyaxes="1 0 0 0 0.5 0.87"/>
    <camera name="head" pos="-0.3 0 1.6" xyaxes="0 -1 0 0.8 0 0.6"/>
  </worldbody>
</mujoco>
"""


def median_rate(action: Callable[[], None], count: int, repeats: int) -> float:
    """Median over ``repeats`` of ``count`` calls of ``action`` per second."""
    rates = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(count):
            action()
        rates.append(count / (time.perf_counter() - start))
    return statistics.median(rates)


def load_model(path: str | None) -> tuple[mujoco.MjModel, str]:
    if path is None and SCENE_XML.exists():
        path = str(SCENE_XML)
    if path is None:
        return mujoco.MjModel.from_xml_string(FALLBACK_SCENE), "built-in bench scene"
    return mujoco.MjModel.from_xml_path(path), path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", help="MJCF scene to render (default: the project scene)")
    parser.add_argument("--frames", type=int, default=10, help="frames per timed run")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per figure")
    args = smoke.parse_args(parser, frames=2, repeats=1)
    model, source = load_model(args.model)
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    for _ in range(200):  # let things settle so renders show a typical scene
        mujoco.mj_step(model, data)

    def step() -> None:
        mujoco.mj_step(model, data)

    steps_per_s = median_rate(step, 2000, args.repeats)
    sim_second_s = (1.0 / model.opt.timestep) / steps_per_s  # wall time of 1 s of physics
    rows: list[tuple[str, float]] = []
    frames: list[np.ndarray] = []
    for camera in camera_names(model):
        for shadows in (True, False):
            with FrameRenderer(model, WIDTH, HEIGHT, camera, shadows=shadows) as renderer:
                renderer.render(data)  # first frame compiles shaders: not timed
                rate = median_rate(lambda r=renderer: r.render(data), args.frames, args.repeats)
                frames.append(renderer.render(data))
            rows.append((f"render {camera}, shadows {'on' if shadows else 'off'}", rate))

    with CloseUpRenderer(model, 320, 240) as close_up:
        lookat = np.array(model.stat.center)
        close_up.observe(data, lookat, 90.0, -55.0, 0.6)  # not timed

        def view() -> None:
            close_up.observe(data, lookat, 90.0, -55.0, 0.6)

        rows.append(
            (
                "close-up 320x240 segmentation + depth (verify)",
                median_rate(view, args.frames, args.repeats),
            )
        )

    with tempfile.TemporaryDirectory() as folder:
        counter = iter(range(10**9))

        def encode_all() -> None:
            with Mp4Writer(Path(folder) / f"{next(counter)}.mp4", WIDTH, HEIGHT, FPS) as video:
                for i in range(args.frames * 3):
                    video.write(frames[i % len(frames)])

        encode_rate = median_rate(encode_all, 1, args.repeats) * args.frames * 3
    rows.append((f"encode libx264 {WIDTH}x{HEIGHT} @ {FPS} fps", encode_rate))

    print(f"model: {source}; GL backend: {BACKEND}; timestep {model.opt.timestep} s")
    print(f"raw mj_step: {steps_per_s:,.0f} steps/s ({1 / sim_second_s:.1f}x real time)")
    print(f"median of {args.repeats} runs; {WIDTH}x{HEIGHT}")
    header = (
        f"{'what':48s} {'frames/s':>9s} {'mj_steps per frame':>19s} {'30 fps cost / physics':>22s}"
    )
    print(header)
    print("-" * len(header))
    for name, rate in rows:
        per_frame = steps_per_s / rate
        cost = (FPS / rate) / sim_second_s  # wall time of 1 s of video / of 1 s of physics
        print(f"{name:48s} {rate:9.1f} {per_frame:19.0f} {cost:21.1f}x")


if __name__ == "__main__":
    main()
