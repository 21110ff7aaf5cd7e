"""Whole live sessions with random and adversarial participants, audited (not a pytest file).

    python tests/live_soak.py --sessions 20 --moves 150 [--out DIR]

Each session is a real one (physics, the learner, the files) at ``--speed``; its participant
(:class:`live_monkey.Monkey`) mixes the guide's moves with clicks anywhere, gestures and
thumbs out of turn, early and late, wrong moves let stand, "That was wrong", idle periods, junk
and End; every fourth session has a webcam and is also shown the real footage's hands
(``tests/data/hands``), every third runs the proactive robot. Prints one line per session
(with its take-backs and wrong moves let stand) and the totals of lock-ups (the participant
stranded included), loops and lost or doubled steps (:class:`live_monkey.Audit`); exits 1 if
any is not 0.
"""

from __future__ import annotations

import argparse
import random
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from live_monkey import Audit, Monkey, play

from robin_sim.live.session import LiveConfig, LiveSession

MAX_ATTEMPTS = 8


def one(index: int, out: Path, moves: int, speed: float) -> Audit:
    webcam, proactive = index % 4 == 3, index % 3 == 2
    config = LiveConfig(
        participant=f"P{index + 1:02d}",
        system="proactive" if proactive else "pil",
        out_root=out,
        seed=index,
        video=False,
        speed=speed,
        fps=3.0,
        feedback_window=2.0,
        webcam=webcam,
        calibrate=index % 8 == 3,
        max_attempts=MAX_ATTEMPTS,
    )
    session = LiveSession(config)
    session.start()
    rng = random.Random(1000 + index)
    monkey = Monkey.with_footage(session, rng) if webcam else Monkey(session, rng)
    try:
        play(session, monkey, moves)
        monkey.idle(3.0)
    finally:
        session.stop("ended")
    return Audit.of(session, monkey, MAX_ATTEMPTS)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sessions", type=int, default=20)
    parser.add_argument("--moves", type=int, default=150)
    parser.add_argument("--speed", type=float, default=10.0)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    out = args.out or Path(tempfile.mkdtemp(prefix="live-soak-"))
    totals = {"lockups": 0, "loops": 0, "lost_or_doubled": 0}
    seen = {"let_stand": 0, "taken_back": 0, "actions": 0, "gestures": 0}
    print(
        f"{'session':>7} {'status':>9} {'actions':>7} {'gestures':>8} {'stood':>5} "
        f"{'back':>4} {'lock':>4} {'loop':>4} {'lost':>4} {'wall s':>6}  problems"
    )
    for index in range(args.sessions):
        started = time.monotonic()
        audit = one(index, out, args.moves, args.speed)
        for key in totals:
            totals[key] += getattr(audit, key)
        for key in seen:
            seen[key] += getattr(audit, key)
        print(
            f"{index + 1:>7} {audit.status:>9} {audit.actions:>7} {audit.gestures:>8} "
            f"{audit.let_stand:>5} {audit.taken_back:>4} "
            f"{audit.lockups:>4} {audit.loops:>4} {audit.lost_or_doubled:>4} "
            f"{time.monotonic() - started:>6.0f}  {'; '.join(audit.problems)}",
            flush=True,
        )
    print(f"totals over {args.sessions} sessions: {totals}; {seen}; sessions under {out}")
    return 0 if not any(totals.values()) else 1


if __name__ == "__main__":
    raise SystemExit(main())
