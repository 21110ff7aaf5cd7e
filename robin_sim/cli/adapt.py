"""``robin-pil adapt``: the person changes a gesture's meaning mid-task (learner only).

Writes ``adaptation.csv``, ``adaptation.md`` (mean ± sd, paired tests of PIL against every
other system, how many runs adapted), ``tests.csv`` and ``adaptation.png``; with ``--seeds K``
K such studies in ``OUT/seed_<n>/`` and their comparisons over seeds (``seeds.md``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robin_sim.cli.options import add_run_options, progress_bar, run_options

DEFAULT_OUT = Path("out/adapt")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The adaptation study's options."""
    from pil.experiments.adaptation import ADAPT_RATES, ADAPT_SYSTEMS
    from pil.experiments.paper import rates_text

    parser.add_argument(
        "--change",
        default=None,
        help="mapping change file (default: scenarios/mapping_change.yaml)",
    )
    add_run_options(parser, rates=rates_text(ADAPT_RATES), out=DEFAULT_OUT, systems=ADAPT_SYSTEMS)


def run(args: argparse.Namespace) -> int:
    """Run the paired runs and write the outputs; bad input raises before anything runs."""
    from pil.experiments.adaptation import (
        ADAPT_SYSTEMS,
        DEFAULT_CHANGE,
        load_change,
        run_adaptation_study,
        write_adaptation,
    )
    from pil.outdir import claimed_out_dir

    rates, systems = run_options(args, ADAPT_SYSTEMS)
    change = load_change(DEFAULT_CHANGE if args.change is None else args.change)
    # before the computation; the folder stays locked until the files are written
    with claimed_out_dir(args.out):
        if args.seeds > 1:
            from robin_sim.cli.options import run_seed_studies

            what = [
                change.name,
                change.from_table,
                change.gesture.value,
                change.action.value,
                change.scenario.name,
            ]
            settings = {
                "study": "adapt",
                "change": what,
                "rates": list(rates),
                "reps": args.reps,
                "systems": list(systems),
            }
            return run_seed_studies(
                args,
                "adaptation",
                settings,
                lambda seed, step: run_adaptation_study(
                    change, systems, rates, args.reps, seed, progress=step
                ),
                lambda _seed, rows, folder: write_adaptation(rows, change, folder),
                within=("rate",),
                title="Adaptation to a changed mapping",
                runs_per_seed=len(rates) * len(systems) * args.reps,
            )
        with progress_bar(len(rates) * len(systems) * args.reps, "adapt", args) as bar:
            rows = run_adaptation_study(
                change, systems, rates, args.reps, args.seed, progress=bar.update
            )
        written = write_adaptation(rows, change, args.out)
    print(f"{len(rows)} paired runs; wrote " + ", ".join(str(p) for p in written))
    return 0
