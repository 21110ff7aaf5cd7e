"""Episode speed: wall time split into physics + control, rendering and encoding.

Run: ``python bench/bench_episode.py [--repeats 3] [--scenario scenarios/one_handover.yaml]``.
Runs the same episode (seed 0) without video and with video (640x480, 30 fps, front camera),
``--repeats`` times each, and prints medians: wall and simulated seconds, real-time factor,
the wall time split (physics + control + narration = wall - waiting on renders - overlay and
encoding), video frames per wall second and encoding frames/s, and the ratio of the controlled
episode's physics rate to the raw ``mj_step`` rate of the same scene measured in the same run.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

import mujoco  # noqa: E402

from pil.task.scenario import SCENARIOS_DIR  # noqa: E402
from robin_sim.episode.run import EpisodeConfig, run_episode  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402


def raw_step_rate(seconds: float = 2.0) -> float:
    """``mj_step`` steps/s of the default scene from its home keyframe (the ceiling)."""
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        for _ in range(100):
            mujoco.mj_step(model, data)
        steps += 100
    return steps / (time.perf_counter() - start)


def one_run(
    scenario: Path,
    video: bool,
    workers: int | None,
    eye_inset: bool = True,
    size: tuple[int, int] = (640, 480),
    fps: int = 30,
) -> dict[str, float]:
    """One episode; the timings the summary reports."""
    with tempfile.TemporaryDirectory() as folder:
        config = EpisodeConfig(
            scenario=scenario,
            out=Path(folder),
            video=video,
            verify=False,
            progress=False,
            render_workers=workers,
            eye_inset=eye_inset,
            width=size[0],
            height=size[1],
            fps=fps,
        )
        summary = run_episode(config)
    wall, sim = summary["wall_time_s"], summary["sim_time_s"]
    row = {"wall_s": wall, "sim_s": sim, "rtf": sim / wall, "render_s": 0.0, "encode_s": 0.0}
    if video:
        v = summary["video"]
        row.update(render_s=v["render_s"], encode_s=v["encode_s"], frames=v["frames"])
    row["physics_s"] = wall - row["render_s"] - row["encode_s"]
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scenario", type=Path, default=SCENARIOS_DIR / "one_handover.yaml")
    parser.add_argument("--size", default="640x480", help="video size WxH")
    parser.add_argument("--fps", type=int, default=30, help="video frame rate")
    args = smoke.parse_args(parser, repeats=1, size="160x120", fps=5)
    size = tuple(int(side) for side in args.size.split("x"))
    ceiling = raw_step_rate()
    cases = {
        "no video": (False, None, False),
        "video, 2 render workers": (True, None, True),
        "video, 2 render workers, --no-eye-inset": (True, None, False),
        "video, in-process render": (True, 0, True),
    }
    print(
        f"scenario {args.scenario.name}, video {args.size} at {args.fps} fps, median of "
        f"{args.repeats} runs"
    )
    print(f"raw mj_step of the scene: {ceiling:,.0f} steps/s ({ceiling * 0.002:.1f}x real time)")
    header = (
        "case",
        "wall s",
        "sim s",
        "x real time",
        "physics+control s",
        "render wait s",
        "encode s",
        "frames/s overall",
        "encode fps",
        "physics / raw mj_step",
    )
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for name, (video, workers, inset) in cases.items():
        runs = [
            one_run(args.scenario, video, workers, inset, size, args.fps)  # type: ignore[arg-type]
            for _ in range(args.repeats)
        ]
        med = {key: statistics.median(r[key] for r in runs) for key in runs[0]}
        frames = med.get("frames", 0.0)
        overall_fps = frames / med["wall_s"]
        encode_fps = frames / med["encode_s"] if med["encode_s"] else float("nan")
        physics_rate = med["sim_s"] / 0.002 / med["physics_s"]
        cells = (
            name,
            f"{med['wall_s']:.1f}",
            f"{med['sim_s']:.1f}",
            f"{med['rtf']:.2f}",
            f"{med['physics_s']:.1f}",
            f"{med['render_s']:.1f}",
            f"{med['encode_s']:.1f}",
            f"{overall_fps:.1f}" if video else "-",
            f"{encode_fps:.1f}" if video else "-",
            f"{physics_rate / ceiling:.2f}",
        )
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
