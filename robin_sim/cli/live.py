"""``robin-pil live``: a browser page where a person takes the scripted person's place.

Every option is checked, the protocol read, each session validated and the port bound before
anything starts; the URL is printed (and opened unless ``--no-browser``). The server stops when
the run ends: after the last session, when the controlling tab closes (saved ``closed``) or on
Ctrl-C / SIGTERM (saved ``interrupted``, exit code 130).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The live command's options."""
    parser.add_argument("--port", default="8000", help="TCP port (default: %(default)s; 0: any "
                        "free port)")  # fmt: skip
    parser.add_argument(
        "--host", default="127.0.0.1",
        help="address to listen on (default: %(default)s); any other than loopback needs the "
        "access token printed in the URL",
    )  # fmt: skip
    parser.add_argument("--system", default="pil", help=_system_help() + " (with --protocol: "
                        "each block's condition)")  # fmt: skip
    parser.add_argument("--scenario", default=None, help="assembly YAML or shipped scenario name "
                        "(default: scenarios/assembly.yaml)")  # fmt: skip
    parser.add_argument("--participant", default="P01", help="participant id, [A-Za-z0-9_-]{1,32} "
                        "(default: %(default)s)")  # fmt: skip
    parser.add_argument(
        "--protocol",
        default=None,
        help="study protocol: a YAML file or a shipped protocol's name (reactive_vs_proactive); "
        "the participant's blocks run one after another (default: none, one free session)",
    )
    parser.add_argument("--out", type=Path, default=Path("out/live"),
                        help="sessions folder (default: %(default)s)")  # fmt: skip
    parser.add_argument("--speed", default="1", help="sim seconds per wall second (default 1)")
    parser.add_argument("--no-browser", action="store_true", help="print the URL only")
    parser.add_argument("--no-video", action="store_true", help="no MP4 of the session")


def _system_help() -> str:
    from pil.experiments.systems import SYSTEM_SPECS

    return f"the learner system (default: %(default)s), one of {', '.join(SYSTEM_SPECS)}"


def parse_port(text: str) -> int:
    """``--port`` as a whole number in [0, 65535]."""
    try:
        port = int(str(text).strip())
    except ValueError:
        raise RobinPilError(f"--port must be a whole number from 1 to 65535 (0: any free "
                            f"port), got {quote(text)}") from None  # fmt: skip
    if not 0 <= port <= 65535:
        raise RobinPilError(f"--port must lie from 1 to 65535 (0: any free port), got {port}")
    return port


def parse_speed(text: str) -> float:
    """``--speed`` as a number (its range is the engine's: :class:`LiveConfig` checks it)."""
    try:
        return float(text)
    except ValueError:
        raise RobinPilError(f"--speed must be a number from 0.1 to 10 (1 = real time), got "
                            f"{quote(text)}") from None  # fmt: skip


def session_configs(args: argparse.Namespace) -> list[Any]:
    """The run's checked sessions: one, or one per protocol block of the participant."""
    from robin_sim.live.session import LiveConfig

    base = LiveConfig(
        participant=args.participant, system=args.system, scenario=args.scenario,
        out_root=args.out, speed=parse_speed(args.speed), video=not args.no_video,
    ).checked()  # fmt: skip
    if args.protocol is None:
        return [base]
    from robin_sim.live.protocol import load_protocol

    protocol = load_protocol(args.protocol)
    scenario = args.scenario if args.scenario is not None else protocol.scenario
    return [
        replace(
            base, system=block.condition, scenario=scenario,
            handover_types=tuple(block.handover_types), block=block.index,
            protocol=str(args.protocol), instructions=block.instructions,
            session=f"block{block.index + 1}-{block.condition}",
        ).checked()
        for block in protocol.blocks_for(base.participant)
    ]  # fmt: skip


def run(args: argparse.Namespace) -> int:
    """Check everything, serve the page until the run ends; 130 when interrupted."""
    import asyncio
    import logging
    import sys
    import webbrowser

    port = parse_port(args.port)
    host = str(args.host).strip()
    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()  # before MuJoCo is imported
    from robin_sim.live.conductor import Conductor
    from robin_sim.live.server import LiveServer, bind, is_loopback, new_token

    conductor = Conductor(session_configs(args))  # every session validated here
    token = None if is_loopback(host) else new_token()
    sock = bind(host, port)
    bound_port = sock.getsockname()[1]
    shown_host = f"[{host}]" if ":" in host else host
    url = f"http://{shown_host}:{bound_port}/" + ("" if token is None else f"?token={token}")
    logging.basicConfig(level=logging.WARNING, format="robin-pil live: %(message)s")
    print(f"robin-pil live: serving {url}", flush=True)
    if token is not None:
        print("robin-pil live: every request needs the token in that URL", flush=True)
    if not args.no_browser:
        webbrowser.open(url)
    outcome = asyncio.run(LiveServer(conductor, token=token).serve(sock))
    for result in conductor.results:
        print(
            f"robin-pil live: session {result.get('session')}: {result.get('status')}, "
            f"{result.get('legs_delivered')}/{result.get('legs_total')} legs",
            flush=True,
        )
    saved = f"saved under {args.out}" if conductor.results else "no session had started"
    print(f"robin-pil live: run {outcome}; {saved}", file=sys.stderr, flush=True)
    return 130 if outcome == "interrupted" else 0
