"""What the eye inset costs a one-handover episode with video: with and without it, side by side.

    python bench/bench_eye_inset.py [--size 640x480] [--fps 30] [--repeats 3] [--together]
                                    [--smoke]

Each run is a fresh ``robin-pil episode --scenario one_handover`` process (the same seed, so
the same episode); runs with and without the inset (``--no-eye-inset``) come in pairs, the
order swapped from one pair to the next (without, with; with, without; ...), so that a busy
machine slows both alike; ``--together`` runs each pair's two at the same time instead, so that
both see the same load on a shared machine (on an idle one the run left alone at the end gets
more of the machine, which narrows the ratio). Per case the table gives the median over
``--repeats`` runs of the episode's wall time, the CPU time of the episode's process and its
render workers (user + system), the time it waited on rendering (``summary.json``'s
``video.render_s``) and the wall time per video frame; the last columns are the ratios of the
medians, with the inset over without (the aim: at most 1.10 in wall time). The load average is
printed at the start and the end. ``--smoke`` runs one tiny pair (160x120 at 5 fps) to check
that the bench still works.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

CASES = {"without inset": ["--no-eye-inset"], "with inset": []}


def start_episode(out: Path, size: str, fps: int, extra: list[str]) -> subprocess.Popen:
    """One episode started in a fresh process."""
    argv = [
        sys.executable,
        "-m",
        "robin_sim.cli.main",
        "episode",
        "--scenario",
        "one_handover",
        "--size",
        size,
        "--fps",
        str(fps),
        "--no-verify",
        "--no-progress",
        "--json",
        "--out",
        str(out),
        *extra,
    ]
    return subprocess.Popen(argv, stdout=subprocess.DEVNULL)


def finish_episode(process: subprocess.Popen, out: Path) -> dict:
    """The summary of a started episode once it ends, with ``cpu_s``: the CPU seconds of its
    process and of its render workers (children it waited for)."""
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise SystemExit(f"episode into {out} exited with {process.returncode}")
    summary = json.loads((out / "summary.json").read_text())
    summary["cpu_s"] = usage.ru_utime + usage.ru_stime
    return summary


def measure(size: str, fps: int, repeats: int, together: bool) -> dict[str, list[dict]]:
    """Summaries of ``repeats`` runs of each case, in pairs: one after the other, the order
    alternating, or (``together``) both at once."""
    found: dict[str, list[dict]] = {case: [] for case in CASES}
    with tempfile.TemporaryDirectory() as folder:
        for k in range(repeats):
            order = list(CASES)[:: 1 if k % 2 == 0 else -1]
            groups = [order] if together else [[case] for case in order]
            for group in groups:
                outs = {case: Path(folder) / f"{k}_{case.replace(' ', '_')}" for case in group}
                started = {
                    case: start_episode(outs[case], size, fps, CASES[case]) for case in group
                }
                for case, process in started.items():
                    summary = finish_episode(process, outs[case])
                    found[case].append(summary)
                    print(
                        f"  pair {k + 1}/{repeats} {case}: {summary['wall_time_s']:.1f} s wall, "
                        f"{summary['cpu_s']:.1f} s CPU, load {os.getloadavg()[0]:.1f}",
                        file=sys.stderr,
                        flush=True,
                    )
    return found


def table(found: dict[str, list[dict]]) -> str:
    """The markdown table of the medians."""
    rows = [
        "| case | wall s | CPU s | render wait s | frames | ms per frame | wall vs. without "
        "| CPU vs. without |",
        "|---|---|---|---|---|---|---|---|",
    ]
    base = {key: median(found["without inset"], key) for key in ("wall_time_s", "cpu_s")}
    for case, summaries in found.items():
        wall, cpu = median(summaries, "wall_time_s"), median(summaries, "cpu_s")
        render = statistics.median(s["video"]["render_s"] for s in summaries)
        frames = summaries[0]["video"]["frames"]
        rows.append(
            f"| {case} | {wall:.1f} | {cpu:.1f} | {render:.1f} | {frames} | "
            f"{1e3 * wall / frames:.1f} | {wall / base['wall_time_s']:.2f}x | "
            f"{cpu / base['cpu_s']:.2f}x |"
        )
    return "\n".join(rows)


def median(summaries: list[dict], key: str) -> float:
    """The median of ``key`` over ``summaries``."""
    return statistics.median(s[key] for s in summaries)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", default="640x480", help="video size (default: %(default)s)")
    parser.add_argument("--fps", type=int, default=30, help="video rate (default: %(default)s)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per case (default: 3)")
    parser.add_argument(
        "--together",
        action="store_true",
        help="run each pair's two episodes at the same time, so that both see the same load "
        "(on a shared machine); default: one after the other",
    )
    args = smoke.parse_args(parser, size="160x120", fps=5, repeats=1)
    size, fps, repeats = args.size, args.fps, args.repeats
    load = os.getloadavg()
    found = measure(size, fps, repeats, args.together)
    print(
        f"one_handover episode, {size} at {fps} fps, median of {repeats} run(s) per case"
        f"{', each pair at the same time' if args.together else ''}; "
        f"load average {load[0]:.1f} at the start, {os.getloadavg()[0]:.1f} at the end "
        f"({os.cpu_count()} CPUs)"
    )
    print(table(found))


if __name__ == "__main__":
    main()
