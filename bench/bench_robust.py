"""The robust PIL rule against the paper's rules and the reference agents (issue 38's analysis).

Run:

    python bench/bench_robust.py --out out/robust          # eval seeds, about 2 minutes

(``python bench/regenerate.py --only robust`` runs it into ``bench/results``.)

Every agent runs the benchmark's assembly track (:func:`pil.bench.tracks.run_track`, the
suite file's seeds, cap and conditions; tuned agents with the parameters of
``bench/results/leaderboard/tuned.json``) under the suite's conditions and under each thumb
noise of the ``teacher`` condition alone (``silence only``, ``misread only``, ``missed only``,
``late only``: the same gesture reading, one component of its feedback). It writes into
``--out``:

* ``runs.csv``: one row per run (agent, condition, seed, actions, gestures, failed, and for
  ``pil-robust`` the actions on which it asked for a thumb);
* ``summary.csv``: per agent and condition the runs, failed runs, mean actions of the
  finished runs with their 95 % t interval, mean gestures and asks;
* ``tracks.csv``: as ``summary.csv`` for ``pil-robust`` and tuned TAMER on the benchmark's
  other learner-only tracks (meaning change, transfer, two people) under their conditions;
* ``tests.csv``: the comparisons issue 38 declares, each family Holm-adjusted: ``beats``
  (pil-robust against each reference agent under ``eyes`` and ``teacher``, paired t by seed),
  ``no worse`` (against ``pil-paper`` with right thumbs at d = 0.4-1.0: the one-sided paired
  test that pil-robust needs at most 5 actions more, :func:`pil.bench.equivalence.tost_paired`)
  and ``vs tamer`` (against tuned TAMER with right thumbs, paired t). A failed run counts at
  the cap (cap x the scripted instructions) instead of dropping its pair.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import smoke  # bench/smoke.py: --smoke

from pil.bench.entrants import reference
from pil.bench.equivalence import tost_paired
from pil.bench.suite import Condition, Suite, load_suite
from pil.bench.tracks import run_track
from pil.experiments.stats import holm, mean_ci, paired
from pil.robust import RobustLearner

ROOT = Path(__file__).resolve().parent.parent
TUNED = ROOT / "bench" / "results" / "leaderboard" / "tuned.json"
ROBUST = "pil-robust"
REFERENCES = ("tamer", "policy-shaping", "coach", "thompson", "egreedy")
AGENTS = (ROBUST, "pil-paper", "pil-next-best", *REFERENCES, "oracle")
RIGHT_THUMBS = ("d40", "d60", "d80", "d100")
NOISY = ("eyes", "teacher")
ALONE = "only"  # "silence only": one component of the teacher condition's thumbs
MARGIN = 5.0  # actions: "no worse than pil-paper"
OTHER_TRACKS = ("meaning-change", "transfer", "two-people")  # pil-robust and tuned TAMER only


def with_components(suite: Suite) -> Suite:
    """The suite with each feedback component of ``teacher`` as a condition of its own."""
    teacher = suite.conditions["teacher"]
    alone = {
        f"{key} {ALONE}": Condition(f"{key} {ALONE}", teacher.gestures, {key: value})
        for key, value in teacher.feedback.items()
    }
    return replace(suite, conditions={**suite.conditions, **alone})


def factories(tuned: Path) -> dict[str, Callable[[int], Any]]:
    """Each agent's factory (tuned parameters where ``tuned`` has them)."""
    params = json.loads(tuned.read_text()) if tuned.is_file() else {}
    return {a: reference(a, params.get(a, {}).get("params", {})) for a in AGENTS}


class Built:
    """A factory that keeps the agent it built last (to read the robust rule's asks)."""

    def __init__(self, make: Callable[[int], Any]) -> None:
        self.make, self.last = make, None

    def __call__(self, seed: int) -> Any:
        self.last = self.make(seed)
        return self.last


def run_all(
    suite: Suite,
    conditions: Sequence[str],
    seeds: Sequence[int],
    tuned: Path,
    track_name: str = "assembly",
    agents: Sequence[str] = AGENTS,
):
    """Every (agent, condition, seed) run on the track: the journal's row plus the asks."""
    track = suite.track(track_name)
    made = factories(tuned)
    rows = []
    for condition in conditions:
        for agent in agents:
            for seed in seeds:
                built = Built(made[agent])
                row = run_track(suite, track, condition, seed, built, False)
                asked = built.last.asked if isinstance(built.last, RobustLearner) else ""
                rows.append({"agent": agent, "condition": condition, "seed": seed, **row})
                rows[-1]["asked"] = asked
    return rows


def actions_at_cap(rows: list[dict[str, Any]], cap: float) -> dict[tuple[str, str, int], float]:
    """Actions per run; a failed run counts at the cap."""
    return {
        (r["agent"], r["condition"], r["seed"]): cap * r["scripted"]
        if r["failed"]
        else r["actions"]
        for r in rows
    }


def _pair(actions, a: str, b: str, condition: str, seeds):
    return [actions[(a, condition, s)] for s in seeds], [actions[(b, condition, s)] for s in seeds]


def tests(rows, cap: float, seeds) -> list[dict[str, Any]]:
    """The declared families (module docstring), Holm-adjusted within each."""
    actions = actions_at_cap(rows, cap)
    out: list[dict[str, Any]] = []
    families = {
        "beats": [(ref, c) for c in NOISY for ref in REFERENCES],
        "vs tamer": [("tamer", c) for c in RIGHT_THUMBS],
    }
    for family, pairs in families.items():
        found = []
        for other, condition in pairs:
            a, b = _pair(actions, ROBUST, other, condition, seeds)
            t = paired(a, b)[0]
            found.append({"family": family, "other": other, "condition": condition, **t})
        for row, p in zip(found, holm([r["p"] for r in found]), strict=True):
            row["p_holm"] = p
        out += found
    found = []
    for condition in RIGHT_THUMBS:
        a, b = _pair(actions, ROBUST, "pil-paper", condition, seeds)
        t = paired(a, b)[0]
        test = tost_paired(a, b, MARGIN)
        found.append(
            {
                "family": "no worse",
                "other": "pil-paper",
                "condition": condition,
                **t,
                "test": f"non-inferiority (margin {MARGIN:g})",
                "p": test["noninferior_p"],
            }
        )
    for row, p in zip(found, holm([r["p"] for r in found]), strict=True):
        row["p_holm"] = p
    return out + found


def summary(rows, conditions, agents: Sequence[str] = AGENTS) -> list[dict[str, Any]]:
    """Per agent and condition: runs, failed, mean actions (finished runs) and interval."""
    out = []
    for condition in conditions:
        for agent in agents:
            mine = [r for r in rows if r["agent"] == agent and r["condition"] == condition]
            done = [r for r in mine if not r["failed"]]
            mean, low, high = (
                mean_ci([float(r["actions"]) for r in done]) if done else (math.nan,) * 3
            )
            asked = [r["asked"] for r in mine if r["asked"] != ""]
            out.append(
                {
                    "agent": agent,
                    "condition": condition,
                    "runs": len(mine),
                    "failed": len(mine) - len(done),
                    "mean": round(mean, 1),
                    "ci_low": round(low, 1),
                    "ci_high": round(high, 1),
                    "gestures": round(statistics.fmean(r["gestures"] for r in done), 1)
                    if done
                    else math.nan,
                    "asked": round(statistics.fmean(asked), 1) if asked else "",
                }
            )
    return out


def _cell(value: Any) -> Any:
    """Floats at four significant digits (p-values too), the rest as they are."""
    return f"{value:.4g}" if isinstance(value, float) else value


def write(path: Path, rows: list[dict[str, Any]], columns: Sequence[str]) -> None:
    """``rows`` as CSV with ``columns``."""
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, columns, extrasaction="ignore")
        writer.writeheader()
        writer.writerows({k: _cell(v) for k, v in row.items()} for row in rows)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="eval", help="the suite's seed block (dev, eval)")
    parser.add_argument("--count", type=int, default=0, help="only the first N seeds (0: all)")
    parser.add_argument("--tuned", type=Path, default=TUNED)
    parser.add_argument("--out", type=Path, default=Path("out/robust"))
    args = smoke.parse_args(parser, argv, count=1, seeds="dev")
    start = time.perf_counter()
    suite = with_components(load_suite())
    conditions = [c for c in suite.track("assembly").conditions] + [
        c for c in suite.conditions if c.endswith(f" {ALONE}")
    ]
    seeds = suite.seeds(args.seeds)[: args.count or None]
    rows = run_all(suite, conditions, seeds, args.tuned)
    args.out.mkdir(parents=True, exist_ok=True)
    cap = suite.cap_of("assembly")
    write(
        args.out / "runs.csv",
        rows,
        ("agent", "condition", "seed", "actions", "gestures", "failed", "asked"),
    )
    table = summary(rows, conditions)
    write(args.out / "summary.csv", table, list(table[0]))
    found = tests(rows, cap, seeds) if len(seeds) > 1 else []
    columns = (
        "family",
        "other",
        "condition",
        "test",
        "n",
        "mean_diff",
        "ci_low",
        "ci_high",
        "effect_size",
        "p",
        "p_holm",
    )
    write(args.out / "tests.csv", found, columns)
    other = []
    for name in OTHER_TRACKS:
        track = suite.track(name)
        ran = run_all(suite, track.conditions, seeds, args.tuned, name, (ROBUST, "tamer"))
        other += [{"track": name, **r} for r in summary(ran, track.conditions, (ROBUST, "tamer"))]
    write(args.out / "tracks.csv", other, ["track", *list(table[0])])
    for row in table:
        if row["agent"] == ROBUST:
            what = f"{row['mean']} actions, {row['failed']} failed, {row['asked']} asks"
            print(f"{row['condition']:>15}: {what}")
    print(f"{len(rows)} runs in {time.perf_counter() - start:.0f} s; results in {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
