"""Speed of the default study's computation (4 rates x 20 reps x 5 systems, 10 tables).

Runs :func:`pil.experiments.study.run_study` with the paper's setup several times (no files, no
figures)
and prints median / min / max seconds, robot decisions per second, and the ratio against a
baseline measured in the same process: a bare loop making as many ``random.Random`` draws and
dict look-ups as there were decisions. Usage: ``python bench/bench_study.py [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import random
import statistics
import time

import smoke  # bench/smoke.py: --smoke

from pil.experiments.study import StudyConfig, run_study


def count_decisions(rows: list[dict]) -> int:
    """Robot actions executed: every test run plus each distinct (shared) training run once."""
    total = sum(int(r["actions"]) for r in rows)
    trainings: dict[tuple[int, float], int] = {}
    for r in rows:
        if r["system"] in ("c1", "c3"):
            trainings[(r["rep"], r["rate"])] = int(r["train_actions"])
        elif r["system"] in ("c2", "c4"):
            trainings[(r["rep"], 1.0)] = int(r["train_actions"])
    return total + sum(trainings.values())


def baseline(decisions: int) -> float:
    """Seconds for ``decisions`` random draws plus dict look-ups in a bare loop."""
    rng = random.Random(0)
    table = {i: i for i in range(40)}
    start = time.perf_counter()
    hits = 0
    for _ in range(decisions):
        hits += table[int(rng.random() * 40)]
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--reps", type=int, default=StudyConfig.reps, help="study repetitions")
    args = smoke.parse_args(parser, repeats=1, reps=1)
    config = StudyConfig(reps=args.reps)
    times, base_times = [], []
    decisions = 0
    for _ in range(args.repeats):
        start = time.perf_counter()
        rows = run_study(config)
        times.append(time.perf_counter() - start)
        decisions = count_decisions(rows)
        base_times.append(baseline(decisions))
    med, base = statistics.median(times), statistics.median(base_times)
    print(f"default study: {config.runs()} runs, {decisions} robot decisions per study")
    print(f"{'what':<28}{'median s':>10}{'min s':>10}{'max s':>10}{'decisions/s':>14}")
    print(
        f"{'study computation':<28}{med:>10.3f}{min(times):>10.3f}{max(times):>10.3f}"
        f"{decisions / med:>14,.0f}"
    )
    print(
        f"{'baseline (draw + lookup)':<28}{base:>10.4f}{min(base_times):>10.4f}"
        f"{max(base_times):>10.4f}{decisions / base:>14,.0f}"
    )
    print(f"ratio study / baseline: {med / base:.1f}x")


if __name__ == "__main__":
    main()
