"""``robin-pil live``: a browser page where a person takes the scripted person's place.

Every option is checked, the protocol read, each session validated and the port bound before
anything starts; the URL is printed (and opened unless ``--no-browser``). The server stops when
the run ends: after the last session, when the controlling tab closes (saved ``closed``) or on
Ctrl-C / SIGTERM (saved ``interrupted``, exit code 130).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.detector import EXACT
from robin_sim.cli.options import parse_port
from robin_sim.live.limits import RECONNECT_GRACE_S, RECONNECT_GRACES, WatchdogLimits

DEFAULT_PARTICIPANT = "P01"
MAX_SESSION_PREFIX = 14  # --session: room for "-block10-proactive" in a 32-character name


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The live command's options."""
    parser.add_argument(
        "--port", default="8000", help="TCP port (default: %(default)s; 0: any free port)"
    )
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default: %(default)s); any other than loopback needs the "
        "access token printed in the URL",
    )
    parser.add_argument(
        "--system",
        default="pil",
        help=_system_help() + " (with --protocol: each block's condition)",
    )
    parser.add_argument(
        "--scenario",
        default=None,
        help="assembly YAML or shipped scenario name (default: scenarios/assembly.yaml)",
    )
    parser.add_argument(
        "--participant",
        default=None,
        help="participant id, [A-Za-z0-9_-]{1,32} (default: P01; with --study: the next free "
        "id, and one given is checked: an id in the study's registry is never reused)",
    )
    parser.add_argument(
        "--study",
        type=Path,
        default=None,
        metavar="DIR",
        help="run the next participant of the study in DIR (robin-pil study-init makes one): "
        "its protocol, design, screens and limits, the participant registered and assigned "
        "(default: none)",
    )
    parser.add_argument(
        "--protocol",
        default=None,
        help="study protocol: a YAML file or a shipped protocol's name (reactive_vs_proactive); "
        "the participant's blocks run one after another (default: none, one free session)",
    )
    parser.add_argument(
        "--out", type=Path, default=Path("out/live"), help="sessions folder (default: %(default)s)"
    )
    parser.add_argument(
        "--session",
        default=None,
        help="name of this run's session folder under OUT/PARTICIPANT (with --protocol: the "
        "prefix of its blocks' folders, NAME-block1-...); default: the UTC start time, or "
        "block1-... with --protocol. Give a new one to run a participant again",
    )
    parser.add_argument("--speed", default="1", help="sim seconds per wall second (default 1)")
    parser.add_argument(
        "--reconnect-grace",
        default=str(RECONNECT_GRACE_S),
        help="seconds a participant's page that lost its connection is waited for (default: "
        "%(default)s); it comes back by itself and the session holds meanwhile; none back in "
        "time: the session is saved 'closed'",
    )
    parser.add_argument(
        "--max-attempts",
        default=str(WatchdogLimits.attempts),
        help="robot actions on one gesture of the participant's before the step goes back to "
        "them (default: %(default)s)",
    )
    parser.add_argument(
        "--max-step-seconds",
        default=str(WatchdogLimits.seconds),
        help="simulated seconds on one gesture before the step goes back to the participant "
        "(default: %(default)s)",
    )
    parser.add_argument(
        "--seed",
        default="0",
        help="the study seed (default: %(default)s): each block's seed is derived from it, the "
        "participant and the block (a protocol's 'seeds: shared' gives every block this seed)",
    )
    parser.add_argument("--no-browser", action="store_true", help="print the URL only")
    parser.add_argument("--no-video", action="store_true", help="no MP4 of the session")
    parser.add_argument(
        "--webcam",
        action="store_true",
        help="read the participant's own hand on the page's camera (tracked in the browser; no "
        "frame leaves it); clicks and keys still work (docs/webcam.md)",
    )
    parser.add_argument(
        "--detector",
        default=EXACT,
        help="exact (default): gestures as clicked, keyed or decided from the landmarks; "
        "vision (needs --webcam): Robin reads the gestures with its own eye cameras from the "
        "simulated hand that the participant's landmarks drive (docs/webcam.md)",
    )
    parser.add_argument(
        "--no-calibration",
        action="store_true",
        help="with --webcam: skip asking for each gesture once at the start (the hand's shape "
        "alone is read until the participant's own gestures are learnt)",
    )


def _system_help() -> str:
    from pil.task.systems import SYSTEM_SPECS

    return f"the learner system (default: %(default)s), one of {', '.join(SYSTEM_SPECS)}"


def parse_number(text: str, option: str, kind: type) -> Any:
    """``option``'s text as a number of ``kind`` (its range: :class:`LiveConfig` checks it)."""
    try:
        return kind(text)
    except ValueError:
        what = "a whole number" if kind is int else "a number"
        raise RobinPilError(f"{option} must be {what}, got {quote(text)}") from None


def parse_grace(text: str) -> float:
    """``--reconnect-grace`` in seconds, within :data:`RECONNECT_GRACES`."""
    low, high = RECONNECT_GRACES
    seconds = parse_number(text, "--reconnect-grace", float)
    if not low <= seconds <= high:  # NaN fails too
        raise RobinPilError(f"--reconnect-grace must lie in [{low:g}, {high:g}] s, got {text}")
    return float(seconds)


def session_configs(args: argparse.Namespace) -> list[Any]:
    """The run's checked sessions: one, or one per protocol block of the participant. The
    options are checked once (:meth:`LiveConfig.checked`); each block only checks its own
    values (:meth:`LiveConfig.for_block`), its seed derived from ``--seed``."""
    from robin_sim.live.files import block_folder
    from robin_sim.live.session import LiveConfig

    session = parse_session(getattr(args, "session", None))
    attempts: Any = getattr(args, "max_attempts", "10")
    step_seconds: Any = getattr(args, "max_step_seconds", "120")
    base = LiveConfig(
        participant=DEFAULT_PARTICIPANT if args.participant is None else args.participant,
        system=args.system,
        scenario=args.scenario,
        out_root=args.out,
        session=session,
        speed=args.speed,  # text: checked once, by the session's config
        video=not args.no_video,
        webcam=bool(getattr(args, "webcam", False)),
        calibrate=not getattr(args, "no_calibration", False),
        detector=str(getattr(args, "detector", EXACT)),
        study_seed=args.seed,  # text, as --speed; the block seeds derive from it
        max_attempts=attempts,  # text, as --speed
        max_step_seconds=step_seconds,
    )
    if getattr(args, "no_calibration", False) and not base.webcam:
        raise RobinPilError("--no-calibration is for --webcam sessions; add --webcam or drop it")
    base = base.checked()  # the options as given, once (before a protocol file is read)
    if args.protocol is None:
        return [base]
    from robin_sim.live.protocol import load_protocol

    protocol = load_protocol(args.protocol)
    scenario = args.scenario if args.scenario is not None else protocol.scenario
    configs, previous = [], base
    for block in protocol.blocks_for(base.participant):
        # each block from the one before: every block sets the same fields, and the scenario
        # file the first block read is read no more
        previous = previous.for_block(
            system=block.condition,
            scenario=scenario,
            handover_types=tuple(block.handover_types),
            block=block.index,
            protocol=str(args.protocol),
            instructions=block.instructions,
            session=block_folder(session, block.index, block.condition),
            seed=base.study_seed if protocol.seeds == "shared" else None,  # None: derived
        )
        configs.append(previous)
    return configs


def parse_session(text: str | None) -> str | None:
    """``--session`` as a folder name (None: the default names)."""
    if text is None:
        return None
    from robin_sim.live.config import NAME_PATTERN

    if not NAME_PATTERN.fullmatch(text) or len(text) > MAX_SESSION_PREFIX:
        raise RobinPilError(
            f"--session {quote(text)} is not a valid name; use 1-"
            f"{MAX_SESSION_PREFIX} letters, digits, '_' or '-'"
        )
    return text


def planned_folders(configs: list[Any]) -> Callable[[str], list[Path]]:
    """The run's session folders if ``--session`` were ``name`` (for the restart advice)."""

    from robin_sim.live.files import block_folder

    def folders(name: str) -> list[Path]:
        base = Path(configs[0].out_root) / configs[0].participant
        if configs[0].protocol is None:
            return [base / name]
        return [base / block_folder(name, c.block or 0, c.system) for c in configs]

    return folders


def questionnaires_of(args: argparse.Namespace) -> tuple[Any, ...]:
    """The protocol's questionnaires (answered after each block); none without a protocol."""
    if args.protocol is None:
        return ()
    from robin_sim.live.protocol import load_protocol

    return load_protocol(args.protocol).questionnaires


def run(args: argparse.Namespace) -> int:
    """Check everything, serve the page until the run ends; 130 when interrupted."""
    import asyncio
    import logging
    import sys
    import webbrowser

    from pil.extras import require_extra

    require_extra("live")  # aiohttp: before anything is checked or bound
    port = parse_port(args.port)
    host = str(args.host).strip()
    from robin_sim.render.gl_backend import ensure_gl_backend

    ensure_gl_backend()  # before MuJoCo is imported
    from robin_sim.live.conductor import Conductor
    from robin_sim.live.preflight import check_free, check_writable
    from robin_sim.live.server import LiveServer, bind, is_loopback, new_token

    grace = parse_grace(getattr(args, "reconnect_grace", str(RECONNECT_GRACE_S)))
    study = None
    if getattr(args, "study", None) is not None:
        from robin_sim.cli.live_study import study_conductor

        study, conductor = study_conductor(args, session_configs(args)[0])
        configs = study.configs
    else:
        configs = session_configs(args)
        check_free(configs, planned_folders(configs))  # the advice names a free --session
        check_writable(configs[0].out_root / configs[0].participant)  # before it is served
        conductor = Conductor(configs, questionnaires_of(args))  # every session validated here
    token = None if is_loopback(host) else new_token()
    try:
        sock = bind(host, port)
    except BaseException as problem:
        if study is not None:  # the id was never shown to anyone: it is free again
            study.release(f"the server could not start: {problem}")
        raise
    bound_port = sock.getsockname()[1]
    shown_host = f"[{host}]" if ":" in host else host
    url = f"http://{shown_host}:{bound_port}/" + ("" if token is None else f"?token={token}")
    logging.basicConfig(level=logging.WARNING, format="robin-pil live: %(message)s")
    print(f"robin-pil live: serving {url}", flush=True)
    if token is not None:
        print("robin-pil live: every request needs the token in that URL", flush=True)
    experimenter = new_token()
    print(
        f"robin-pil live: experimenter's view http://{shown_host}:{bound_port}/experimenter"
        f"?token={experimenter}",
        flush=True,
    )
    if not args.no_browser:
        webbrowser.open(url)
    server = LiveServer(
        conductor,
        token=token,
        experimenter_token=experimenter,
        host=host,
        reconnect_grace_s=grace,
    )
    outcome = asyncio.run(server.serve(sock))
    for result in conductor.results:
        print(
            f"robin-pil live: session {result.get('session')}: {result.get('status')}, "
            f"{result.get('legs_delivered')}/{result.get('legs_total')} legs",
            flush=True,
        )
    where = args.out if study is None else study.study.folder
    if study is not None:
        print(f"robin-pil live: participant {study.participant} ({study.group}): {outcome}")
    saved = f"saved under {where}" if conductor.results else "no session had started"
    print(f"robin-pil live: run {outcome}; {saved}", file=sys.stderr, flush=True)
    return 130 if outcome == "interrupted" else 0
