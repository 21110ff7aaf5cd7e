"""``robin-pil people``: two people with different mappings, one shared table vs one each.

Writes ``people.csv``, ``people.md`` (mean ± sd, Welch t-tests of shared against per-person)
and ``people.png``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.cli.study import _rates, _systems

DEFAULT_OUT = Path("out/people")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The personal-mappings study's options."""
    parser.add_argument(
        "--people", default=None, help="people file (default: scenarios/two_people.yaml)"
    )
    parser.add_argument(
        "--tables",
        type=int,
        default=None,
        help="test tables, taken in turns (default: the scenario's, 10)",
    )
    parser.add_argument(
        "--systems", default=None, help="comma-separated PIL systems (default: pil,pil-halve)"
    )
    parser.add_argument("--rates", default="0.8,1.0", help="detection rates (default: %(default)s)")
    parser.add_argument("--reps", type=int, default=20, help="repetitions (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="master seed (default: %(default)s)")
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run both modes and write the outputs; bad input raises before anything runs."""
    from tqdm import tqdm

    from pil.experiments.outdir import check_output_folder
    from pil.experiments.people import (
        DEFAULT_PEOPLE,
        PEOPLE_SYSTEMS,
        People,
        load_people,
        run_people_study,
        write_people,
    )

    if args.seed < 0:
        raise RobinPilError(f"--seed must be a whole number >= 0, got {args.seed}")
    if args.reps < 1:
        raise RobinPilError(f"--reps must be >= 1, got {args.reps}")
    rates = _rates(args.rates)
    systems = PEOPLE_SYSTEMS if args.systems is None else _systems(args.systems)
    for system in systems:
        if system not in ("pil", "pil-halve"):
            raise RobinPilError(f"--systems: the people study runs PIL learners; {system!r} is "
                                "not one (valid choices: 'pil', 'pil-halve')")  # fmt: skip
    people = load_people(DEFAULT_PEOPLE if args.people is None else args.people)
    if args.tables is not None:
        people = People(people.scenario.with_changes(tables=args.tables), people.overrides)
    check_output_folder(args.out)
    with tqdm(total=len(rates) * len(systems) * args.reps, desc="people", unit="pair",
              file=sys.stderr, disable=args.no_progress) as bar:  # fmt: skip
        rows = run_people_study(people, systems, rates, args.reps, args.seed,
                                progress=bar.update)  # fmt: skip
    written = write_people(rows, args.out)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
