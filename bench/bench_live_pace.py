"""The live session's pace: from a participant's input to Robin's first motion, and the lag.

    python bench/bench_live_pace.py [--repeats 3] [--seconds 40] [--loads 0,4,8]

**Input to first motion** (simulated seconds, so the machine's speed does not enter): a real
:class:`~robin_sim.live.session.LiveSession` (no video) with a participant who makes type A's
four gestures in turn (click the leg, grasp, give me, release: ``tests/live_driver.py``),
stopping wrong moves with a thumb down. For each gesture: the simulated time from the input's
arrival (``inputs.jsonl``) to the robot starting its action (``events.jsonl``, ``acts``). The
baseline, measured in the same run: the same session with the scripted person's tempo
(:data:`robin_sim.person.body.SCRIPTED`, what the live body did before: the hand travels and
holds each gesture as the study's person does).

**Lag under load**: at 1x real time, 640x480 at 15 frames/s with the eye inset, the robot
moving (the participant clicks a leg, then idles through the robot's tries) for ``--seconds``
of wall time while ``N`` busy processes (``--loads``) compete for the cores. Measured: the wall
time physics fell behind its pace (``behind_s``), the frames per second streamed and the
stream's level at the end, with the stream's adaptation on (shipped) and, as the baseline,
off (:class:`~robin_sim.live.quality.StreamGovernor`). Medians of ``--repeats`` runs.
"""

from __future__ import annotations

import smoke  # bench/smoke.py: --smoke

from robin_sim.render.gl_backend import ensure_gl_backend

BACKEND = ensure_gl_backend()  # before mujoco is imported

import argparse  # noqa: E402
import contextlib  # noqa: E402
import json  # noqa: E402
import multiprocessing  # noqa: E402
import os  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from live_driver import Driver  # noqa: E402

import robin_sim.live.run as live_run  # noqa: E402
from robin_sim.live.inputs import LiveInputError  # noqa: E402
from robin_sim.live.session import LiveConfig, LiveSession  # noqa: E402
from robin_sim.person.body import LIVE, SCRIPTED  # noqa: E402

TYPE_A = (("pointing", "object"), ("grasp", "close"), ("give_me", "human"), ("release", "open"))


def read_jsonl(path: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def input_to_motion(tempo: Any, out: Path) -> dict[str, float]:
    """One type-A handover; per gesture, sim s from its input to the robot's first action."""
    live_run.LIVE = tempo  # the bench swaps the body's tempo to measure the baseline
    try:
        session = LiveSession(
            LiveConfig(out_root=out, scenario="one_handover", video=False, speed=5.0, fps=2.0)
        )
        session.start()
        driver = Driver(session)
        try:
            for gesture, meant in TYPE_A:
                driver.my_turn()
                if gesture == "pointing":
                    driver.point_at_leg(0)
                else:
                    driver.gesture(gesture)
                with contextlib.suppress(LiveInputError):  # a thumb too late on a busy machine
                    driver.judge(meant)
        finally:
            session.stop("ended")
    finally:
        live_run.LIVE = LIVE
    inputs = [
        e
        for e in read_jsonl(session.out_dir / "inputs.jsonl")
        if e["accepted"] and e["raw"].get("type") in ("point", "gesture")
    ]
    acts = [e for e in read_jsonl(session.out_dir / "events.jsonl") if e["event"] == "acts"]
    delays: dict[str, float] = {}
    times = [e["sim_time"] for e in inputs] + [float("inf")]
    for (gesture, _), given, after in zip(TYPE_A, times, times[1:], strict=False):
        first = next((e["sim_time"] for e in acts if given <= e["sim_time"] < after), None)
        if first is not None:  # else the step went back to the participant: nothing acted
            delays[gesture] = first - given
    return delays


def burn() -> None:  # pragma: no cover - a busy process for the load runs
    while True:
        pass


def lag_under_load(load: int, adaptive: bool, seconds: float, out: Path) -> dict[str, float]:
    """A session at 1x with the robot moving and ``load`` busy processes beside it."""
    burners = [multiprocessing.Process(target=burn, daemon=True) for _ in range(load)]
    for process in burners:
        process.start()
    try:
        config = LiveConfig(out_root=out, video=True, speed=1.0, fps=15.0, adaptive_stream=adaptive)
        session = LiveSession(config)
        session.start()
        driver = Driver(session)
        try:
            driver.my_turn()
            driver.point_at_leg(0)
            started = time.monotonic()
            while time.monotonic() - started < seconds and not session.done.is_set():
                status = session.status()
                if status["phase"] == "waiting_for_gesture":  # keep the robot busy
                    driver.point_at_leg(int(time.monotonic()) % 4)
                time.sleep(0.2)
            status = session.status()
            pacing = session.pacing()
        finally:
            session.stop("ended")
    finally:
        for process in burners:
            process.terminate()
            process.join()
    stream = status["stream"] or {}
    return {
        "behind_s": pacing["behind_s"] or 0.0,
        "slips": pacing["slips"] or 0,
        "stream_fps": pacing["stream_fps"] or 0.0,
        "level": stream.get("level", 0),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=40.0, help="wall s per load run")
    parser.add_argument("--loads", default="0,4,8", help="busy processes beside the session")
    args = smoke.parse_args(parser, repeats=1, seconds=4.0, loads="0")
    loads = [int(v) for v in args.loads.split(",")]
    out = Path(tempfile.mkdtemp(prefix="bench-live-pace-"))
    print(f"machine: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; GL {BACKEND}")
    delays: dict[str, list[dict[str, float]]] = {"live": [], "scripted": []}
    for _ in range(args.repeats):
        for name, tempo in (("live", LIVE), ("scripted", SCRIPTED)):
            delays[name].append(input_to_motion(tempo, out))
    print("\ninput to Robin's first motion, sim s (median of", args.repeats, "runs)")
    print(f"{'gesture':<10} {'live':>6} {'baseline: scripted tempo':>25} {'ratio':>6}")
    for gesture, _ in TYPE_A:
        live = statistics.median(d[gesture] for d in delays["live"] if gesture in d)
        base = statistics.median(d[gesture] for d in delays["scripted"] if gesture in d)
        print(f"{gesture:<10} {live:>6.2f} {base:>25.2f} {live / base:>6.2f}")
    print(f"\nlag at 1x, 15 frames/s with the eye inset, {args.seconds:g} s of wall time each")
    print(
        f"{'load':>4} {'adaptive: behind s':>19} {'slips':>5} {'fps':>5} {'level':>5}   "
        f"{'baseline fixed: behind s':>24} {'slips':>5} {'fps':>5}"
    )
    for load in loads:
        runs: dict[bool, list[dict[str, float]]] = {True: [], False: []}
        for _ in range(args.repeats):
            for adaptive in (True, False):
                runs[adaptive].append(lag_under_load(load, adaptive, args.seconds, out))

        def med(adaptive: bool, key: str, runs: dict[bool, list[dict[str, float]]] = runs) -> float:
            return statistics.median(r[key] for r in runs[adaptive])

        print(
            f"{load:>4} {med(True, 'behind_s'):>19.2f} {med(True, 'slips'):>5.0f} "
            f"{med(True, 'stream_fps'):>5.1f} {med(True, 'level'):>5.0f}   "
            f"{med(False, 'behind_s'):>24.2f} {med(False, 'slips'):>5.0f} "
            f"{med(False, 'stream_fps'):>5.1f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
