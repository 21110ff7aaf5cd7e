"""What the eye inset costs a one-handover episode with video: with and without it, side by side.

    python bench/bench_eye_inset.py [--size 640x480] [--fps 30] [--repeats 3] [--smoke]

Each run is a fresh ``robin-pil episode --scenario one_handover`` process (the same seed, so
the same episode); runs with and without the inset (``--no-eye-inset``) alternate, so that a
busy machine slows both alike. Per case the table gives the median over ``--repeats`` runs of
the episode's wall time, the time it waited on rendering (``summary.json``'s
``video.render_s``) and the wall time per video frame; the last column is the ratio of the
medians, with the inset over without (the aim: at most 1.10). ``--smoke`` runs one tiny pair
(160x120 at 5 fps) to check that the bench still works.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

CASES = {"without inset": ["--no-eye-inset"], "with inset": []}


def run_episode(out: Path, size: str, fps: int, extra: list[str]) -> dict:
    """One episode in a fresh process; its summary."""
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
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL)
    return json.loads((out / "summary.json").read_text())


def measure(size: str, fps: int, repeats: int) -> dict[str, list[dict]]:
    """Summaries of ``repeats`` runs of each case, the cases alternating."""
    found: dict[str, list[dict]] = {case: [] for case in CASES}
    with tempfile.TemporaryDirectory() as folder:
        for k in range(repeats):
            for case, extra in CASES.items():
                out = Path(folder) / f"{k}_{case.replace(' ', '_')}"
                summary = run_episode(out, size, fps, extra)
                found[case].append(summary)
                print(
                    f"  run {k + 1}/{repeats} {case}: {summary['wall_time_s']:.1f} s wall",
                    file=sys.stderr,
                    flush=True,
                )
    return found


def table(found: dict[str, list[dict]]) -> str:
    """The markdown table of the medians."""
    rows = [
        "| case | wall s | render wait s | frames | ms per frame | vs. without |",
        "|---|---|---|---|---|---|",
    ]
    base = statistics.median(s["wall_time_s"] for s in found["without inset"])
    for case, summaries in found.items():
        wall = statistics.median(s["wall_time_s"] for s in summaries)
        render = statistics.median(s["video"]["render_s"] for s in summaries)
        frames = summaries[0]["video"]["frames"]
        rows.append(
            f"| {case} | {wall:.1f} | {render:.1f} | {frames} | "
            f"{1e3 * wall / frames:.1f} | {wall / base:.2f}x |"
        )
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", default="640x480", help="video size (default: %(default)s)")
    parser.add_argument("--fps", type=int, default=30, help="video rate (default: %(default)s)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per case (default: 3)")
    args = smoke.parse_args(parser, size="160x120", fps=5, repeats=1)
    size, fps, repeats = args.size, args.fps, args.repeats
    found = measure(size, fps, repeats)
    print(f"one_handover episode, {size} at {fps} fps, median of {repeats} run(s) per case")
    print(table(found))


if __name__ == "__main__":
    main()
