"""``robin-pil episode``: one physical episode, rendered headless to MP4 (the project's main job).

With no arguments: one table (4 legs), detection rate 100 %, seed 0, PIL from scratch; writes
``out/episode.mp4``, ``out/episode.jsonl`` and ``out/summary.json``. MuJoCo is imported only
when the command runs, after the headless GL backend is chosen.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.cli.options import add_progress_switch

HOLDS_SIGNALS = True  # run inside main's guard: a Ctrl-C at start-up still leaves the files


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The episode's options."""
    parser.add_argument(
        "--tables",
        default=None,
        help="tables to assemble, 4 legs each (default: 1; with --scenario, the scenario's)",
    )
    parser.add_argument(
        "--rate",
        default=None,
        help="gesture detection rate in (0, 1]; not with --detector vision, whose eye cameras "
        "read what they see (default: 1.0)",
    )
    parser.add_argument("--seed", default=0, help="seed of every random choice (>= 0)")
    parser.add_argument("--system", default="pil", help=_system_help())
    parser.add_argument(
        "--scenario",
        default=None,
        help="assembly YAML or shipped scenario name, e.g. one_handover "
        "(default: scenarios/assembly.yaml)",
    )
    parser.add_argument(
        "--camera", default="front", help="front, side, head, head_left_eye or head_right_eye"
    )
    parser.add_argument("--size", default="640x480", help="video size WxH (even numbers)")
    parser.add_argument("--fps", default=30, help="video frame rate (1-240)")
    parser.add_argument("--no-video", action="store_true", help="physics and log only")
    parser.add_argument("--shadows", action="store_true", help="render shadows (about 3x slower)")
    parser.add_argument(
        "--render-workers",
        default=None,
        help="processes rendering video frames (default 2; 0 renders in this process)",
    )
    parser.add_argument("--no-verify", action="store_true", help="skip the render checks")
    parser.add_argument("--no-policy", action="store_true", help="no P(a|s) panel in the video")
    parser.add_argument(
        "--detector",
        default=None,
        help="how the robot reads the person: exact (default, the study's), independent, "
        "measured:FILE, or vision (its eye cameras; conditions --param lighting=0.3, "
        "--param camera_noise=12; the person's looks --param skin=0, --param pose_jitter=2)",
    )
    parser.add_argument(
        "--adapt",
        action="store_true",
        help="with --detector vision: the gesture model adapts to the person from the robot's "
        "feedback (the same as --param adapt=true)",
    )
    parser.add_argument(
        "--no-eye-inset", action="store_true", help="no inset of the robot's eye view in the video"
    )
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a run parameter, repeatable: e.g. reaction_time=0.8 (s, the person's mean "
        "reaction), reaction_spread=0.1, silent_ok=0.1, patience=3, handover_timeout=120",
    )
    parser.add_argument("--out", type=Path, default=Path("out"), help="output folder")
    add_progress_switch(parser)
    parser.add_argument(
        "--json",
        action="store_true",
        help="print the whole summary as JSON instead of the short one (summary.json holds it)",
    )


def _system_help() -> str:
    """The --system help: every system of the study's registry (no MuJoCo imported)."""
    from pil.task.systems import SYSTEM_SPECS

    names = ", ".join(SYSTEM_SPECS)
    return (
        f"the learner system (default: %(default)s), one of {names} (proactive: acts before "
        "the gesture when it expects it)"
    )


def _params(texts: list[str]) -> dict[str, str]:
    from pil.errors import RobinPilError

    params: dict[str, str] = {}
    for text in texts:
        name, equals, value = text.partition("=")
        if not equals or not name.strip():
            raise RobinPilError(f"--param must look like NAME=VALUE, got {text!r}")
        params[name.strip()] = value.strip()
    return params


def run(args: argparse.Namespace) -> int:
    """Check every option, then run the episode and print its summary."""
    from pil.task.detector import CAMERAS as VISION
    from pil.task.params import RATE
    from robin_sim.episode.config import EpisodeConfig

    video = not args.no_video
    params = _params(args.param)
    if args.detector is not None:
        params["detector"] = args.detector
    if args.adapt:
        if "adapt" in params:
            raise RobinPilError("give --adapt or --param adapt=..., not both")
        params["adapt"] = "true"
    if args.rate is not None and params.get("detector", "").strip() == VISION:
        raise RobinPilError(
            f"--rate sets the simulated detector's rate; --detector {VISION} reads the gestures "
            f"with Robin's eye cameras, whose rate is what they see: give --detector {VISION} "
            "without --rate, or --rate with another detector (default exact)"
        )
    config = EpisodeConfig(
        tables=args.tables,
        rate=RATE.default if args.rate is None else args.rate,
        seed=args.seed,
        system=args.system,
        scenario=args.scenario,
        out=args.out,
        video=video,
        camera=args.camera,
        size=args.size,
        fps=args.fps,
        shadows=args.shadows,
        render_workers=args.render_workers,
        policy_panel=not args.no_policy,
        eye_inset=not args.no_eye_inset,
        verify=not args.no_verify,
        progress=not args.no_progress,
        params=params,
    )
    spec = config.spec()  # every option parsed and checked once, here
    if video or spec.verify or spec.run.detector.model == VISION:
        from robin_sim.render.gl_backend import ensure_gl_backend

        ensure_gl_backend()  # before MuJoCo is imported
    from robin_sim.episode.run import run_episode

    summary = run_episode(spec)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        from robin_sim.cli.episode_text import summary_text

        print(summary_text(summary, config.out))
    return 0
