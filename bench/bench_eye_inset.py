"""What the eye inset costs a one-handover episode with video: with and without it, side by side.

    python bench/bench_eye_inset.py [--size 640x480] [--fps 30] [--repeats 3] [--smoke]

Each run is a fresh ``robin-pil episode --scenario one_handover`` process (the same seed, so
the same episode); runs with and without the inset (``--no-eye-inset``) come in pairs, the
order swapped from one pair to the next (without, with; with, without; ...), so that a busy
machine slows both alike. Per case the table gives the median over ``--repeats`` runs of the
episode's wall time, the CPU time of the episode's process and its render workers (user +
system, which a shared machine's load barely changes), the time it waited on rendering
(``summary.json``'s ``video.render_s``) and the wall time per video frame; the last columns
are the ratios of the medians, with the inset over without (the aim: at most 1.10 in wall
time). The load average is printed at the start and the end. ``--smoke`` runs one tiny pair
(160x120 at 5 fps) to check that the bench still works.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

CASES = {"without inset": ["--no-eye-inset"], "with inset": []}


def run_episode(out: Path, size: str, fps: int, extra: list[str]) -> dict:
    """One episode in a fresh process; its summary, with ``cpu_s``: the CPU seconds of the
    process and of its render workers (children it waited for)."""
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
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    summary = json.loads((out / "summary.json").read_text())
    summary["cpu_s"] = sum(getattr(after, f) - getattr(before, f) for f in ("ru_utime", "ru_stime"))
    return summary


def measure(size: str, fps: int, repeats: int) -> dict[str, list[dict]]:
    """Summaries of ``repeats`` runs of each case, in pairs whose order alternates."""
    found: dict[str, list[dict]] = {case: [] for case in CASES}
    with tempfile.TemporaryDirectory() as folder:
        for k in range(repeats):
            for case in list(CASES)[:: 1 if k % 2 == 0 else -1]:
                out = Path(folder) / f"{k}_{case.replace(' ', '_')}"
                summary = run_episode(out, size, fps, CASES[case])
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
    args = smoke.parse_args(parser, size="160x120", fps=5, repeats=1)
    size, fps, repeats = args.size, args.fps, args.repeats
    load = os.getloadavg()
    found = measure(size, fps, repeats)
    print(
        f"one_handover episode, {size} at {fps} fps, median of {repeats} run(s) per case; "
        f"load average {load[0]:.1f} at the start, {os.getloadavg()[0]:.1f} at the end "
        f"({os.cpu_count()} CPUs)"
    )
    print(table(found))


if __name__ == "__main__":
    main()
