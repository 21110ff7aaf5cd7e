"""What the scripted person's "that was wrong" is worth (issue 38, item 3).

Run: ``python bench/bench_take_back.py [--conditions teacher eyes] [--seeds eval dev]
[--agents pil-paper pil-next-best] [--tables N]``.

The benchmark's assembly track as ``robin-pil bench`` runs it (:func:`pil.bench.tracks.run_track`:
the same script, reader with the condition's thumb noise, world, cap and counting, per run seed
of the suite's blocks), with one change: the scripted person takes back a wrong move the robot
let stand with probability ``take_back`` after ``take_back_delay`` more robot actions
(:class:`pil.task.person.ScriptedPerson`). Arms: off (the benchmark's person), p = 1 and
p = 0.5 before the next gesture, p = 1 after one more action. Prints per agent, condition and
arm the failed runs, the mean actions of finished runs and the take-backs, and each arm
against off paired on the seeds (failed runs at the cap, as issue 38 item 6 asks): the mean
difference with its 95 % CI, Cohen's d_z, the paired t and Wilcoxon p, Holm-adjusted over the
arms of each agent and condition (:mod:`pil.experiments.stats`).
"""

from __future__ import annotations

import argparse
import functools
import statistics
from typing import Any

import smoke  # bench/smoke.py: --smoke

from pil.bench.entrants import as_agent, reference
from pil.bench.noise import make_reader
from pil.bench.suite import load_suite
from pil.bench.tracks import TableWorld, count
from pil.experiments.stats import holm, paired
from pil.task.person import ScriptedPerson
from pil.task.runner import steps
from pil.task.scenario import load_scenario
from pil.task.script import plan_script
from pil.task.seeds import sub_seeds

ARMS: dict[str, tuple[float, int]] = {  # name -> (take_back, take_back_delay)
    "off": (0.0, 0),
    "p1": (1.0, 0),
    "p0.5": (0.5, 0),
    "p1-late": (1.0, 1),
}


@functools.cache
def _suite() -> Any:
    return load_suite()


def one_run(
    agent_name: str, condition: str, seed: int, arm: str, tables: int | None
) -> dict[str, Any]:
    """One run of the assembly track (as run_track) with the arm's person."""
    suite = _suite()
    seeds = sub_seeds(seed).phase("test")
    scenario = load_scenario("assembly")
    scenario = scenario.with_changes(tables=tables or scenario.tables)
    legs = scenario.legs_per_table
    script = plan_script(
        scenario.draw_types(scenario.tables * legs, seeds.draw), legs, scenario.spots
    )
    agent = as_agent(reference(agent_name)(seeds.learner), seeds.learner, "reference")
    reader = make_reader(suite.conditions[condition], seeds.detector, len(script))
    chance, delay = ARMS[arm]
    person = ScriptedPerson(script, seeds.person, take_back=chance, take_back_delay=delay)
    limit = suite.cap_of("assembly") * len(script)
    played = count(steps(agent, person, reader, TableWorld(lambda table: None, reader)), limit)
    return {
        "actions": played.actions,
        "failed": bool(played.failed),
        "taken_back": person.taken_back_count,
        "capped_actions": limit if played.failed else played.actions,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--conditions", nargs="+", default=["teacher", "eyes"])
    parser.add_argument("--agents", nargs="+", default=["pil-paper", "pil-next-best"])
    parser.add_argument("--seeds", nargs="+", default=["eval", "dev"], help="seed blocks")
    parser.add_argument("--tables", type=int, default=None, help="fewer tables (a quick look)")
    args = smoke.parse_args(
        parser, tables=1, seeds=["dev"], agents=["pil-next-best"], conditions=["teacher"]
    )
    suite = _suite()
    seeds = [s for block in args.seeds for s in suite.seeds(block)]
    print(f"assembly track, {len(seeds)} seeds ({' + '.join(args.seeds)}); arms {ARMS}")
    for agent in args.agents:
        for condition in args.conditions:
            rows = {
                arm: [one_run(agent, condition, s, arm, args.tables) for s in seeds] for arm in ARMS
            }
            print(f"\n{agent}, {condition}")
            for arm, runs in rows.items():
                done = [r["actions"] for r in runs if not r["failed"]]
                mean = statistics.fmean(done) if done else float("nan")
                taken = sum(r["taken_back"] for r in runs)
                failed = sum(r["failed"] for r in runs)
                print(
                    f"  {arm:8} failed {failed:2}/{len(runs)}  mean actions of finished "
                    f"{mean:6.1f}  take-backs {taken:5} ({taken / len(runs):.1f} a run)"
                )
            base = [r["capped_actions"] for r in rows["off"]]
            tests = []
            for arm in list(ARMS)[1:]:
                arm_actions = [r["capped_actions"] for r in rows[arm]]
                t_row, w_row = paired(arm_actions, base)
                tests.append((arm, t_row, w_row))
            adjusted = holm([t["p"] for _, t, _ in tests])
            for (arm, t_row, w_row), p_holm in zip(tests, adjusted, strict=True):
                print(
                    f"  {arm:8} - off: {t_row['mean_diff']:+7.1f} actions "
                    f"[{t_row['ci_low']:+.1f}, {t_row['ci_high']:+.1f}], d_z "
                    f"{t_row['effect_size']:+.2f}, t p {t_row['p']:.2g} (Holm {p_holm:.2g}), "
                    f"Wilcoxon p {w_row['p']:.2g}"
                )


if __name__ == "__main__":
    main()
