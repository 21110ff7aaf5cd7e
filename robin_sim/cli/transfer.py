"""``robin-pil transfer``: a second task (tidying) from scratch vs from saved associations.

Writes ``transfer.csv``, ``transfer.md`` (mean ± sd, paired tests of scratch against table),
``tests.csv`` and ``transfer.png``; without ``--table`` also ``assembly_table.json`` (the first
repetition's assembly table, reusable with ``--table``). With ``--seeds K`` K such studies in
``OUT/seed_<n>/`` and their comparisons over seeds (``seeds.md``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from robin_sim.cli.options import add_run_options, progress_bar, run_options

DEFAULT_OUT = Path("out/transfer")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The transfer study's options."""
    from pil.experiments.paper import rates_text
    from pil.experiments.transfer import TRANSFER_RATES, TRANSFER_SYSTEMS

    parser.add_argument(
        "--table",
        type=Path,
        default=None,
        help="start every transferred run from this saved table (default: "
        "each repetition's own assembly run)",
    )
    add_run_options(
        parser,
        rates=rates_text(TRANSFER_RATES),
        out=DEFAULT_OUT,
        systems=TRANSFER_SYSTEMS,
        accepts=TRANSFER_SYSTEMS,
    )


def run(args: argparse.Namespace) -> int:
    """Run the paired runs and write the outputs; bad input raises before anything runs."""
    from pil.experiments.transfer import TRANSFER_SYSTEMS, run_transfer_study, write_transfer
    from pil.outdir import claimed_out_dir
    from pil.table_io import load_table

    rates, systems = run_options(args, TRANSFER_SYSTEMS, only=TRANSFER_SYSTEMS)
    if args.table is not None:
        load_table(args.table)  # a corrupt or missing file fails here, before anything runs
    # before the computation; the folder stays locked until the files are written
    with claimed_out_dir(args.out):
        source = (
            f"the saved table {args.table}" if args.table else "each repetition's assembly table"
        )
        if args.seeds > 1:
            from robin_sim.cli.options import run_seed_studies

            def one(seed: int, step: object) -> list:
                folder = args.out / f"seed_{seed}"
                folder.mkdir(parents=True, exist_ok=True)
                first = None if args.table is not None else folder / "assembly_table.json"
                return run_transfer_study(
                    systems,
                    rates,
                    args.reps,
                    seed,
                    table_file=args.table,
                    save_first=first,
                    progress=step,
                )

            settings = {
                "study": "transfer",
                "table": str(args.table),
                "rates": list(rates),
                "reps": args.reps,
                "systems": list(systems),
            }
            return run_seed_studies(
                args,
                "transfer",
                settings,
                one,
                lambda _seed, rows, folder: write_transfer(rows, folder, source),
                within=("rate", "system"),
                title="Transfer to a second task",
                runs_per_seed=len(rates) * len(systems) * args.reps,
            )
        save_first = None if args.table is not None else args.out / "assembly_table.json"
        if save_first is not None:
            args.out.mkdir(parents=True, exist_ok=True)
        with progress_bar(len(rates) * len(systems) * args.reps, "transfer", args) as bar:
            rows = run_transfer_study(
                systems,
                rates,
                args.reps,
                args.seed,
                table_file=args.table,
                save_first=save_first,
                progress=bar.update,
            )
        written = write_transfer(rows, args.out, source)
        if save_first is not None:
            written.append(save_first)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
