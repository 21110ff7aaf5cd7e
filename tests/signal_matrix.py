"""The signal matrix of issue 26: every long command x {SIGINT, SIGTERM} x a time after the
start x {SIGINT default (a terminal's job), SIGINT ignored at start (a shell's background job)}.

Each cell starts the command (small, fast settings) as a real process in its own process
group, sends the signal to the whole group at the set time, and checks: exit 130 within 5 s
(or 0 when the command had finished before the signal came), no traceback, its finished work
kept, no process of its group left (read from ``/proc``), and a rerun that resumes (finishes
the rest, or, for the commands that serve or run for minutes, starts again and is stopped in
turn). The suite runs one cell (``tests/test_signal_matrix.py``); the whole matrix, 72
cells, by hand::

    MUJOCO_GL=egl PYTHONPATH=tests python tests/signal_matrix.py [--only study,sweep]
"""

from __future__ import annotations

import argparse
import json
import re
import signal
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from signal_rig import lines, signal_when, start

TIMES = (0.5, 2.0, 5.0)
SIGNALS = (signal.SIGINT, signal.SIGTERM)


@dataclass(frozen=True)
class Command:
    """A command of the matrix: its arguments (``--out`` added), what it keeps, how a rerun
    is checked (``"finish"``: run to the end; ``"restart"``: started, then stopped)."""

    argv: tuple[str, ...]
    kept: Callable[[Path], int]  # finished pieces of work in OUT
    rerun: str = "finish"


def _runs(out: Path) -> int:
    return len(list((out / "runs").glob("*.json")))


def _ok_runs(out: Path) -> int:
    try:
        text = (out / "runs.jsonl").read_text()
    except OSError:
        return 0
    return sum('"status": "ok"' in line or '"status":"ok"' in line for line in text.splitlines())


COMMANDS: dict[str, Command] = {
    "study": Command(("study", "--quiet"), lambda out: lines(out / "reps.jsonl")),
    "sweep": Command(
        (
            "sweep",
            *("--rates", "0.4,1.0", "--systems", "pil,c1", "--reps", "80"),
            *("--workers", "2", "--no-report", "--quiet"),
        ),
        _ok_runs,
    ),
    "people": Command(("people", "--reps", "80", "--quiet"), lambda out: lines(out / "reps.jsonl")),
    "people-appearance": Command(
        (
            "people",
            "--appearance",
            *("--reps", "1", "--tables", "1", "--person", "usual", "--workers", "2", "--quiet"),
        ),
        _runs,
        rerun="restart",
    ),
    "episode": Command(
        (
            "episode",
            *("--scenario", "one_handover", "--size", "160x120", "--fps", "10"),
            *("--no-verify", "--quiet"),
        ),
        lambda out: int((out / "summary.json").exists()),
    ),
    "live": Command(
        (
            "live",
            *("--no-browser", "--port", "0", "--scenario", "one_handover"),
            *("--participant", "P01"),
        ),
        lambda out: 0,
        rerun="restart",
    ),
}


def _resumed(stderr: str) -> int | None:
    """How many finished pieces a rerun said it kept (None: it said nothing of them)."""
    found = re.search(r"resuming: (\d+) finished", stderr) or re.search(
        r"(\d+) already done", stderr
    )
    return None if found is None else int(found.group(1))


def _episode_problems(out: Path) -> list[str]:
    """An interrupted episode's promise: a summary marked interrupted, MP4 = its frames."""
    from robin_sim.render.video import probe_video

    path = out / "summary.json"
    if not path.exists():
        return []  # interrupted before its folder was claimed: nothing to keep
    summary = json.loads(path.read_text())
    if summary["status"] not in ("interrupted", "finished"):
        return [f"summary {summary['status']}"]
    frames = summary.get("video", {}).get("frames")
    try:
        decoded = probe_video(out / "episode.mp4")["frames"]
    except Exception:
        decoded = None
    return [] if frames == decoded else [f"MP4 frames {decoded} vs summary {frames}"]


def cell(
    name: str, how: signal.Signals, at: float, ignored: bool, folder: Path
) -> tuple[str, list[str]]:
    """One cell of the matrix: how the run ended (``exit 130 after 1.2 s``, or ``finished``
    before the signal) and what broke the promise (empty: nothing)."""
    command = COMMANDS[name]
    out = folder / "out"
    run = start([*command.argv, "--out", str(out)], sigint_ignored=ignored)
    outcome = signal_when(run, how, after_s=at)
    problems = outcome.problems(finished_ok=True)
    if "Traceback" in outcome.stderr:  # what it was, for the record
        problems.append(outcome.stderr.strip().splitlines()[-1][:200])
    ended = (
        f"exit {outcome.code} after {outcome.seconds:3.1f} s"
        if outcome.signalled
        else f"finished (exit {outcome.code}) first"
    )
    kept = command.kept(out)
    if name == "episode":
        problems += _episode_problems(out)
    if name == "sweep" and kept and not (out / "results.csv").exists():
        problems.append("no results.csv")
    again = start([*command.argv, "--out", str(out)], sigint_ignored=ignored)
    if command.rerun == "restart":
        rerun = signal_when(again, signal.SIGTERM, after_s=3.0)
        problems += [f"rerun: {p}" for p in rerun.problems(finished_ok=True)]
    else:
        rerun = signal_when(again, signal.SIGTERM, after_s=600.0)  # never sent: to the end
        if rerun.code != 0:
            problems.append(f"rerun exit {rerun.code}: {rerun.stderr.strip()[-300:]}")
        said = _resumed(rerun.stderr)
        if kept and name != "episode" and said != kept:
            problems.append(f"rerun kept {said}, {kept} were finished")
    return ended, problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default=",".join(COMMANDS), help="commands, comma separated")
    parser.add_argument(
        "--sigint", default="both", choices=("both", "default", "ignored"), help="at start"
    )
    options = parser.parse_args()
    names = [n.strip() for n in options.only.split(",")]
    starts = {"both": (False, True), "default": (False,), "ignored": (True,)}[options.sigint]
    failures = total = 0
    with tempfile.TemporaryDirectory() as root:
        for name in names:
            for ignored in starts:
                for how in SIGNALS:
                    for at in TIMES:
                        began = time.monotonic()
                        folder = Path(root) / f"{name}-{how.name}-{at}-{ignored}"
                        ended, problems = cell(name, how, at, ignored, folder)
                        total += 1
                        failures += bool(problems)
                        print(
                            f"{name:18} {how.name:7} {at:3.1f} s  SIGINT "
                            f"{'ignored' if ignored else 'default'}  {ended:21}  "
                            f"cell {time.monotonic() - began:5.1f} s  "
                            f"{'; '.join(problems) or 'ok'}",
                            flush=True,
                        )
    print(f"{failures} of {total} cells broke the promise")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
