"""``robin-pil baselines``: bandit and TAMER tuned on held-out seeds, paired against PIL.

Writes ``baselines.csv`` (the evaluation runs), ``tuning.csv``, ``tests.csv`` and
``summary.md`` (:mod:`pil.experiments.baselines`); learner only, never imports MuJoCo.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pil.experiments.paper import rates_text
from robin_sim.cli.options import RATES_LABEL, progress_bar

DEFAULT_OUT = Path("out/baselines")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The table's options (defaults: the paper's rates, 20 + 10 repetitions, seed 0)."""
    parser.add_argument(
        "--rates", default=rates_text(), help="detection rates (default: %(default)s)"
    )
    parser.add_argument(
        "--reps",
        default=20,
        help="evaluation repetitions (default: "
        "%(default)s; the seeds of robin-pil study --seed SEED)",
    )
    parser.add_argument(
        "--tuning-reps",
        default=10,
        help="held-out repetitions each tuning setting runs on (default: %(default)s)",
    )
    parser.add_argument("--seed", default=0, help="master seed, >= 0 (default: %(default)s)")
    parser.add_argument(
        "--tables", default=None, help="test tables per run (default: the scenario's, 10)"
    )
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Tune, run the table and write it; bad input raises a RobinPilError (exit code 2)."""
    from pil.experiments.baselines import BaselineConfig, run_baselines
    from pil.experiments.baselines_report import write_outputs
    from pil.outdir import check_out_dir

    # as given: parsed once, by the config (the edge)
    config = BaselineConfig(
        rates=tuple(args.rates.split(",")),
        reps=args.reps,
        tuning_reps=args.tuning_reps,
        seed=args.seed,
        params={} if args.tables is None else {"tables": args.tables},
        labels={
            "rate": RATES_LABEL,
            "rates": "--rates",
            "reps": "--reps",
            "tuning_reps": "--tuning-reps",
            "seed": "--seed",
            "tables": "--tables",
        },
    )
    check_out_dir(args.out)  # before the computation, not after it
    with progress_bar(config.runs(), "baselines", args) as bar:
        result = run_baselines(config, progress=bar.update)
    written = write_outputs(result, config, args.out)
    chosen = ", ".join(f"{k} {v.setting.name}" for k, v in result.best.items())
    print(
        f"{len(result.rows)} evaluation runs; tuned: {chosen}; wrote "
        + ", ".join(str(p) for p in written)
    )
    return 0
