"""``robin-pil people``: two people with different mappings, one shared table vs one each;
``--appearance``: people who look different to Robin's eye cameras, fixed vs adapted model.

The mappings study writes ``people.csv``, ``people.md`` (mean ± sd, paired tests of shared
against per-person), ``tests.csv`` and ``people.png``, and keeps each finished repetition in
``reps.jsonl`` as it ends (an interrupted study resumes from it); with ``--seeds K`` K such
studies in ``OUT/seed_<n>/`` and their comparisons over seeds (``seeds.md``). The appearance study
(:mod:`robin_sim.appearance`) writes ``appearance_runs.csv``, ``appearance_tables.csv``,
``tests.csv``, ``appearance.md`` and ``appearance.png``. ``--from-sessions DIR``: simulated
people fitted to recorded live sessions (:mod:`robin_sim.cli.people_fit`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pil.errors import RobinPilError
from pil.experiments.paper import PAPER_REPS
from robin_sim.cli import people_fit
from robin_sim.cli.options import add_run_options, progress_bar, run_options, whole_number
from robin_sim.cli.people_fit import MAX_WORKERS

DEFAULT_OUT = Path("out/people")
APPEARANCE_REPS = 5  # repetitions of the appearance study (physical episodes: minutes each)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The personal-mappings study's options."""
    from pil.experiments.paper import rates_text
    from pil.experiments.people import PEOPLE_RATES, PEOPLE_SYSTEMS

    parser.add_argument(
        "--people",
        default=None,
        help="people file (default: scenarios/two_people.yaml; with --appearance "
        "scenarios/people_appearance.yaml)",
    )
    parser.add_argument(
        "--appearance",
        action="store_true",
        help="the appearance study: Robin's eye cameras read people who look different, with "
        "the shipped gesture model (fixed) and one adapting to each person (adapted)",
    )
    people_fit.add_arguments(parser)  # --from-sessions, --sessions-per-person
    parser.add_argument(
        "--person",
        action="append",
        default=None,
        help="with --appearance: only this person of the file, repeatable (default: every person)",
    )
    parser.add_argument(
        "--workers",
        type=whole_number,
        default=2,
        help="with --appearance or --from-sessions: episodes or sessions run at once (0: in "
        "this process) (default: 2)",
    )
    parser.add_argument(
        "--tables",
        type=whole_number,
        default=None,
        help="test tables, taken in turns (default: the scenario's, 10); with --appearance "
        "the tables of each run (default: the file's, 3)",
    )
    add_run_options(
        parser,
        rates=rates_text(PEOPLE_RATES),
        out=DEFAULT_OUT,
        systems=PEOPLE_SYSTEMS,
        accepts=PEOPLE_SYSTEMS,
        reps_help=f"repetitions (default: {PAPER_REPS}; with --appearance "
        f"{APPEARANCE_REPS}, each its own seed, shared by the fixed and adapted runs)",
    )


def run(args: argparse.Namespace) -> int:
    """Run the chosen mode and write the outputs; bad input raises before anything runs."""
    if args.from_sessions is not None:
        return people_fit.run(args)
    if args.appearance:
        return run_appearance(args, APPEARANCE_REPS if args.reps is None else args.reps)
    if args.person is not None:
        raise RobinPilError("--person chooses people of the appearance study: add --appearance")
    if args.reps is None:
        args.reps = PAPER_REPS
    from pil.experiments.people import (
        DEFAULT_PEOPLE,
        PEOPLE_SYSTEMS,
        People,
        journal_settings,
        load_people,
        run_people_study,
        write_people,
    )
    from pil.experiments.rep_journal import RepJournal, report_journal
    from pil.outdir import claimed_out_dir

    rates, systems = run_options(args, PEOPLE_SYSTEMS, only=PEOPLE_SYSTEMS)
    people = load_people(DEFAULT_PEOPLE if args.people is None else args.people)
    if args.tables is not None:
        people = People(people.scenario.with_changes(tables=args.tables), people.overrides)
    # before the computation; the folder stays locked until the files are written
    with claimed_out_dir(args.out):
        if args.seeds > 1:
            from pil.experiments.over_seeds import seed_folder
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
                    people,
                    systems,
                    rates,
                    args.reps,
                    seed,
                    progress=step,
                    journal=RepJournal(
                        seed_folder(args.out, seed),
                        journal_settings(people, systems, rates, seed),
                    ),
                ),
                lambda _seed, rows, folder: write_people(rows, folder),
                within=("rate", "system"),
                title="Personal mappings: one shared table vs one per person",
                runs_per_seed=len(rates) * len(systems) * args.reps,
            )
        journal = RepJournal(args.out, journal_settings(people, systems, rates, args.seed))
        report_journal("people", journal)
        with progress_bar(len(rates) * len(systems) * args.reps, "people", args) as bar:
            rows = run_people_study(
                people, systems, rates, args.reps, args.seed, progress=bar.update, journal=journal
            )
        written = write_people(rows, args.out)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0


def run_appearance(args: argparse.Namespace, reps: int) -> int:
    """The appearance study (``--appearance``); bad input raises before anything runs."""
    from pil.outdir import claimed_out_dir
    from robin_sim.appearance.people import DEFAULT_APPEARANCE, load_appearance
    from robin_sim.appearance.study import plan_study, run_study

    if args.seeds != 1:
        raise RobinPilError(
            "--seeds: the appearance study's repetitions each have their own seed already; "
            "give more with --reps"
        )
    if args.workers < 0 or args.workers > MAX_WORKERS:
        raise RobinPilError(f"--workers must be 0 to {MAX_WORKERS}, got {args.workers}")
    people = load_appearance(DEFAULT_APPEARANCE if args.people is None else args.people)
    plan = plan_study(people, reps=reps, seed=args.seed, tables=args.tables, persons=args.person)
    with (
        claimed_out_dir(args.out) as out,
        progress_bar(len(plan.runs), "appearance", args) as bar,
    ):
        written = run_study(plan, out, workers=args.workers, progress=bar.update)
    print(f"{len(plan.runs)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
