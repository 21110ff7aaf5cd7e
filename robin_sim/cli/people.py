"""``robin-pil people``: two people with different mappings, one shared table vs one each.

Writes ``people.csv``, ``people.md`` (mean ± sd, paired tests of shared against per-person),
``tests.csv`` and ``people.png``; with ``--seeds K`` K such studies in ``OUT/seed_<n>/`` and
their comparisons over seeds (``seeds.md``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robin_sim.cli.options import add_run_options, progress_bar, run_options

DEFAULT_OUT = Path("out/people")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The personal-mappings study's options."""
    from pil.experiments.people import PEOPLE_SYSTEMS

    parser.add_argument(
        "--people", default=None, help="people file (default: scenarios/two_people.yaml)"
    )
    parser.add_argument(
        "--tables",
        type=int,
        default=None,
        help="test tables, taken in turns (default: the scenario's, 10)",
    )
    add_run_options(
        parser, rates="0.8,1.0", out=DEFAULT_OUT, systems=PEOPLE_SYSTEMS, accepts=PEOPLE_SYSTEMS
    )


def run(args: argparse.Namespace) -> int:
    """Run both modes and write the outputs; bad input raises before anything runs."""
    from pil.experiments.people import (
        DEFAULT_PEOPLE,
        PEOPLE_SYSTEMS,
        People,
        load_people,
        run_people_study,
        write_people,
    )
    from pil.outdir import claimed_out_dir

    rates, systems = run_options(args, PEOPLE_SYSTEMS, only=PEOPLE_SYSTEMS)
    people = load_people(DEFAULT_PEOPLE if args.people is None else args.people)
    if args.tables is not None:
        people = People(people.scenario.with_changes(tables=args.tables), people.overrides)
    # before the computation; the folder stays locked until the files are written
    with claimed_out_dir(args.out):
        if args.seeds > 1:
            from robin_sim.cli.options import run_seed_studies

            settings = {
                "study": "people",
                "people": str(args.people),
                "tables": people.scenario.tables,
                "rates": list(rates),
                "reps": args.reps,
                "systems": list(systems),
            }
            return run_seed_studies(
                args,
                "people",
                settings,
                lambda seed, step: run_people_study(
                    people, systems, rates, args.reps, seed, progress=step
                ),
                lambda _seed, rows, folder: write_people(rows, folder),
                within=("rate", "system"),
                title="Personal mappings: one shared table vs one per person",
                runs_per_seed=len(rates) * len(systems) * args.reps,
            )
        with progress_bar(len(rates) * len(systems) * args.reps, "people", args) as bar:
            rows = run_people_study(
                people, systems, rates, args.reps, args.seed, progress=bar.update
            )
        written = write_people(rows, args.out)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
