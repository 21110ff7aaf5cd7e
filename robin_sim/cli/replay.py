"""``robin-pil replay DIR``: re-render a recorded episode or live session from its states.

The run's ``states.npz`` (written beside its log while it ran) is rendered again to an MP4
(``--out``, default ``DIR/replay.mp4``), shown in MuJoCo's viewer (``--viewer``, with a
display), or served on a page with a timeline to scrub (``--serve``, on 127.0.0.1). DIR and
``--out`` are checked before anything is rendered; nothing is overwritten.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from robin_sim.cli.options import decimal_number

REPLAY_NAME = "replay.mp4"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The replay's options."""
    parser.add_argument(
        "dir", type=Path, metavar="DIR", help="an episode's --out folder or a live session's folder"
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help=f"the MP4 to write (default: DIR/{REPLAY_NAME}; never overwritten)",
    )
    parser.add_argument(
        "--viewer",
        action="store_true",
        help="show the run in MuJoCo's viewer instead (needs a display)",
    )
    parser.add_argument(
        "--serve",
        action="store_true",
        help="serve a page with a timeline to scrub, on 127.0.0.1 (Ctrl-C stops)",
    )
    parser.add_argument("--port", default="8001", help="--serve: the port (0: any free one)")
    parser.add_argument(
        "--speed",
        type=decimal_number,
        default=1.0,
        help="--viewer: playback speed x real time (default 1)",
    )
    parser.add_argument(
        "--from",
        dest="start",
        type=decimal_number,
        default=0.0,
        metavar="SECONDS",
        help="start this many simulated seconds into the run (default 0)",
    )
    parser.add_argument(
        "--to",
        dest="end",
        type=decimal_number,
        default=None,
        metavar="SECONDS",
        help="stop this many simulated seconds into the run (default: the end)",
    )
    parser.add_argument(
        "--overlay",
        action="store_true",
        help="burn the episode's overlay (step, gesture, action, feedback, legs) into a live "
        "session's MP4, from its log (an episode's video has it already)",
    )
    parser.add_argument(
        "--render-workers",
        default="0",
        help="processes rendering frames (default 0: in this process)",
    )


def run(args: argparse.Namespace) -> int:
    """Check DIR and the output, then replay."""
    from robin_sim.replay.folder import ReplayError, output_file, states_file

    workers = _workers(args.render_workers)  # the options first: no folder is read for them
    path = states_file(args.dir)
    if not args.speed > 0 or args.speed > 100:
        raise ReplayError(f"--speed must be a number in (0, 100], got {args.speed!r}")
    if not args.start >= 0 or (args.end is not None and not args.end >= args.start):
        raise ReplayError(
            f"--from must be >= 0 and --to >= --from (seconds), got --from "
            f"{args.start!r} --to {args.end!r}"
        )
    if args.viewer and args.serve:
        raise ReplayError("--viewer and --serve: choose one (or neither, for an MP4)")
    if args.viewer:
        from robin_sim.replay.viewer import check_display

        check_display()  # before the states are read
    elif args.serve:
        from robin_sim.cli.options import parse_port

        port = parse_port(args.port)
    else:
        out = output_file(args.out if args.out is not None else path.parent / REPLAY_NAME)
    from robin_sim.render.gl_backend import ensure_gl_backend

    if not args.viewer:
        ensure_gl_backend()  # before MuJoCo is imported
    if args.serve:
        return _serve(load_states_between(path, args.start, args.end), port, path.parent)
    recorded = load_states_between(path, args.start, args.end)
    if getattr(args, "overlay", False) and not recorded.meta.get("overlay"):
        from robin_sim.replay.annotations import with_log_overlay

        recorded = with_log_overlay(recorded, path.parent)
    if args.viewer:
        from robin_sim.replay.viewer import replay_in_viewer

        shown = replay_in_viewer(recorded, args.speed)
        print(json.dumps({"viewer": True, "frames_shown": shown}))
        return 0
    from robin_sim.replay.render import replay_to_mp4

    result = replay_to_mp4(recorded, out, workers)
    print(json.dumps(result.as_dict(), indent=2))
    return 0


def _workers(text: str) -> int:
    """``--render-workers`` checked by the one bound (:mod:`robin_sim.render.worker_count`)."""
    from robin_sim.render.worker_count import RENDER_WORKERS

    workers = RENDER_WORKERS.parse(text, "--render-workers")
    return 0 if workers is None else int(workers)


def load_states_between(path: Path, start: float, end: float | None) -> Any:
    from robin_sim.render.state_log import load_states

    return load_states(path).between(start, end)


def _serve(recorded: Any, port: int, folder: Path) -> int:
    """Serve the scrubbing page, with the run's events on its timeline, until Ctrl-C."""
    import asyncio
    import signal
    import sys

    from robin_sim.live.server import bind
    from robin_sim.replay.annotations import timeline
    from robin_sim.replay.serve import serve_replay

    annotations = timeline(folder, recorded)
    sock = bind("127.0.0.1", port)
    print(
        f"robin-pil replay: serving http://127.0.0.1:{sock.getsockname()[1]}/ (Ctrl-C stops)",
        flush=True,
    )

    async def main() -> None:
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        for signum in (signal.SIGINT, signal.SIGTERM):  # either ends the page's server
            loop.add_signal_handler(signum, stop.set)
        await serve_replay(recorded, sock, stop, annotations)

    asyncio.run(main())
    print("robin-pil replay: stopped", file=sys.stderr)
    return 0
