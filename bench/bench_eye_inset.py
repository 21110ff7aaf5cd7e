"""What the eye inset costs a video frame, against the same frame without it, in one run.

    python bench/bench_eye_inset.py [--frames 30] [--repeats 5]

States come from a real PhysicalWorld while the person points at each leg and the head follows
(so the eye view changes). Per frame, three cases are timed on the same states: the 640x480
front-camera render with the overlay (the frame without inset), the 160x120 left-eye render of
:class:`robin_sim.render.inset.EyeInset` alone, and the frame with the inset (main render,
overlay, eye render, paste). Each figure is the median over ``--repeats`` runs of ``--frames``
frames; the ratio is with-inset over without, measured in the same run. All rendering here is
in this process (the episode renders the main frame in worker processes; the eye view is always
rendered in the main process, once per video frame).
"""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

BACKEND = ensure_gl_backend()  # before mujoco is imported

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import mujoco  # noqa: E402

from pil.task.world import Target  # noqa: E402
from pil.types import Gesture  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.person.body import PhysicalBody  # noqa: E402
from robin_sim.render.inset import EyeInset, draw_eye_inset  # noqa: E402
from robin_sim.render.overlay import OverlayInfo, draw_overlay  # noqa: E402
from robin_sim.render.pool import FrameState  # noqa: E402
from robin_sim.render.worker import apply_state, warmed_renderer  # noqa: E402
from robin_sim.robot.world import PhysicalWorld  # noqa: E402

WIDTH, HEIGHT = 640, 480


def states(count: int) -> list[FrameState]:
    """``count`` frame states, 0.2 s apart, while the person points at the legs in turn."""
    world = PhysicalWorld()
    body = PhysicalBody(world)
    found: list[FrameState] = []
    leg = 0
    while len(found) < count:
        body.perform(Gesture.POINTING, Target("leg", leg % world.leg_count))
        leg += 1
        for _ in range(5):
            world.run(0.2)
            found.append(FrameState.capture(world.model, world.data))
    return found[:count]


def median_ms(
    action: Callable[[FrameState], None], frames: list[FrameState], repeats: int
) -> float:
    """Median over ``repeats`` runs of the mean ms per frame of ``action``."""
    runs = []
    for _ in range(repeats):
        started = time.perf_counter()
        for state in frames:
            action(state)
        runs.append(1e3 * (time.perf_counter() - started) / len(frames))
    return statistics.median(runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    frames = states(args.frames)
    model = build_model(None)
    data = mujoco.MjData(model)
    main_renderer = warmed_renderer(model, (WIDTH, HEIGHT), "front", False)
    eye = EyeInset(None, WIDTH, HEIGHT)
    info = OverlayInfo(step=1, sim_time=0.0)

    def without(state: FrameState) -> None:
        apply_state(model, data, state)
        draw_overlay(main_renderer.render(data), info)

    def eye_only(state: FrameState) -> None:
        eye.render(state)

    def with_inset(state: FrameState) -> None:
        apply_state(model, data, state)
        frame = draw_overlay(main_renderer.render(data), info)
        draw_eye_inset(frame, eye.render(state))

    plain = median_ms(without, frames, args.repeats)
    eye_ms = median_ms(eye_only, frames, args.repeats)
    inset = median_ms(with_inset, frames, args.repeats)
    print(f"GL backend {BACKEND}; {args.frames} frames, median of {args.repeats} runs")
    print("| case | ms per frame | vs. without inset |")
    print("|---|---|---|")
    print(f"| 640x480 frame + overlay, no inset | {plain:.1f} | 1.00x |")
    print(f"| 160x120 eye view alone | {eye_ms:.1f} | {eye_ms / plain:.2f}x |")
    print(f"| 640x480 frame + overlay + eye inset | {inset:.1f} | {inset / plain:.2f}x |")
    main_renderer.close()
    eye.close()


if __name__ == "__main__":
    main()
