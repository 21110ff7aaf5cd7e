"""Video recording speed with frames rendered in-process against a RenderPool of workers.

    python bench/bench_render_pool.py [--frames 24] [--repeats 3] [--workers 0 1 2]

Each timed run is the episode's recording loop for ``--frames`` video frames at 30 fps: step
the project scene's physics for 1/30 s (the left arm swings), capture a FrameState, submit it,
take the finished frames; once without and once with libx264 encoding of every frame (as
:class:`robin_sim.episode.recorder.VideoRecorder` does). Figures are medians of ``--repeats``
runs, printed as a table with raw ``mj_step`` steps/s measured in the same run as the
baseline, and the cost of moving one 640x480 frame through a pipe (what a worker does).
``--threads 0`` keeps Mesa's llvmpipe thread count in the workers (one per CPU).
"""

from __future__ import annotations

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

BACKEND = ensure_gl_backend()  # before mujoco is imported

import argparse  # noqa: E402
import os  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import threading  # noqa: E402
import time  # noqa: E402
from multiprocessing import Pipe  # noqa: E402
from pathlib import Path  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from robin_sim.model import names  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.pool import FrameState, RenderPool  # noqa: E402
from robin_sim.render.video import Mp4Writer  # noqa: E402

WIDTH, HEIGHT, FPS = 640, 480, 30


class Rollout:
    """The project scene stepping at video rate with the left arm swinging back and forth."""

    def __init__(self) -> None:
        self.model = build_model()
        self.data = mujoco.MjData(self.model)
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.model.key(names.HOME_KEY).id)
        self.arm = [self.model.actuator(a).id for a in names.arm_actuators(names.ACTIVE_SIDE)]
        self.home = self.data.ctrl[self.arm].copy()
        self.steps_per_frame = round(1 / FPS / self.model.opt.timestep)
        self.frame = 0

    def advance(self) -> FrameState:
        """Physics for one video frame; the state to render."""
        swing = 0.4 * np.sin(2 * np.pi * self.frame / FPS)
        self.data.ctrl[self.arm[:2]] = self.home[:2] + swing
        for _ in range(self.steps_per_frame):
            mujoco.mj_step(self.model, self.data)
        self.frame += 1
        return FrameState.capture(self.model, self.data)


def cpu_seconds(pool: RenderPool) -> float:
    """CPU time used so far by this process and the pool's workers (Linux /proc)."""
    total = time.process_time()
    ticks = os.sysconf("SC_CLK_TCK")
    for pid in pool.worker_pids:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        total += (int(fields[11]) + int(fields[12])) / ticks  # utime + stime
    return total


def record_rate(
    pool: RenderPool, rollout: Rollout, frames: int, encode: bool
) -> tuple[float, float]:
    """Frames per second of the recording loop (physics, render, optionally encode) and the
    CPU seconds per frame of this process and the workers together."""
    with tempfile.TemporaryDirectory() as folder:
        writer = Mp4Writer(Path(folder) / "bench.mp4", WIDTH, HEIGHT, FPS) if encode else None
        started, cpu_started = time.perf_counter(), cpu_seconds(pool)
        for _ in range(frames):
            pool.submit(rollout.advance())
            for frame in pool.ready():
                if writer is not None:
                    writer.write(frame.pixels)
        for frame in pool.drain():
            if writer is not None:
                writer.write(frame.pixels)
        if writer is not None:
            writer.close()
        wall = time.perf_counter() - started
        return frames / wall, (cpu_seconds(pool) - cpu_started) / frames


def pipe_ms_per_frame(count: int = 30) -> float:
    """Milliseconds to send one pickled 640x480 RGB frame through a pipe and receive it."""
    frame = np.random.default_rng(0).integers(0, 255, (HEIGHT, WIDTH, 3), dtype=np.uint8)
    receiver, sender = Pipe(duplex=False)
    reader = threading.Thread(target=lambda: [receiver.recv() for _ in range(count)])
    started = time.perf_counter()
    reader.start()
    for _ in range(count):
        sender.send(frame)
    reader.join()
    return (time.perf_counter() - started) / count * 1e3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=24, help="video frames per timed run")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per figure")
    parser.add_argument("--workers", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument(
        "--threads", type=int, nargs="+", default=[0, 1], help="llvmpipe threads per worker"
    )
    args = smoke.parse_args(parser, frames=3, repeats=1, workers=[0, 1], threads=[0])
    rollout = Rollout()
    model, data = rollout.model, rollout.data

    def steps_per_s() -> float:
        started = time.perf_counter()
        for _ in range(2000):
            mujoco.mj_step(model, data)
        return 2000 / (time.perf_counter() - started)

    step_rate = statistics.median(steps_per_s() for _ in range(args.repeats))
    configs = [(w, t) for w in args.workers for t in (args.threads if w else [0])]
    rows = []
    for shadows in (True, False):
        for workers, threads in configs:
            with RenderPool(
                None,
                WIDTH,
                HEIGHT,
                "front",
                shadows,
                workers=workers,
                render_threads=threads or None,
            ) as pool:
                record_rate(pool, rollout, 2, encode=False)  # warm-up: not timed
                for encode in (False, True):
                    runs = [
                        record_rate(pool, rollout, args.frames, encode) for _ in range(args.repeats)
                    ]
                    rate = statistics.median(r for r, _ in runs)
                    cpu = statistics.median(c for _, c in runs)
                    rows.append((shadows, workers, threads, encode, rate, cpu))
    pipe_ms = pipe_ms_per_frame()

    real_time_steps = 1 / model.opt.timestep
    print(f"project scene, front camera {WIDTH}x{HEIGHT}, GL backend {BACKEND}, ")
    print(f"{os.cpu_count()} CPUs; median of {args.repeats} runs of {args.frames} frames")
    print(f"raw mj_step: {step_rate:,.0f} steps/s ({step_rate / real_time_steps:.1f}x real time)")
    print(f"pipe transfer of one pickled {WIDTH}x{HEIGHT} RGB frame: {pipe_ms:.2f} ms")
    header = (
        f"{'shadows':8s} {'workers':>7s} {'threads':>8s} {'encode':>7s} {'frames/s':>9s} "
        f"{'speed-up':>9s} {'x real time':>12s} {'CPU s/frame':>12s} {'steps/frame':>12s}"
    )
    print(header)
    print("-" * len(header))
    baseline = {(s, e): r for s, w, _, e, r, _ in rows if w == configs[0][0]}
    for shadows, workers, threads, encode, rate, cpu in rows:
        print(
            f"{'on' if shadows else 'off':8s} {workers:7d} {threads or 'Mesa':>8} "
            f"{'yes' if encode else 'no':>7s} {rate:9.1f} {rate / baseline[shadows, encode]:8.2f}x "
            f"{rate / FPS:11.2f}x {cpu:12.3f} {step_rate / rate:12.0f}"
        )
    print("threads: llvmpipe threads per worker (LP_NUM_THREADS); Mesa: its default, one per CPU")
    print("CPU s/frame: CPU time of this process and the workers per frame (load-independent)")
    print("steps/frame: raw mj_step steps that run in the wall time of one recorded frame")


if __name__ == "__main__":
    main()
