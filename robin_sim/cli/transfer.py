"""``robin-pil transfer``: a second task (tidying) from scratch vs from saved associations.

Writes ``transfer.csv``, ``transfer.md`` (mean ± sd, Welch t-tests of scratch against table)
and ``transfer.png``; without ``--table`` also ``assembly_table.json`` (the first
repetition's assembly table, reusable with ``--table``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.cli.study import _rates, _systems

DEFAULT_OUT = Path("out/transfer")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The transfer study's options."""
    parser.add_argument("--table", type=Path, default=None,
                        help="start every transferred run from this saved table (default: "
                        "each repetition's own assembly run)")  # fmt: skip
    parser.add_argument(
        "--systems", default=None, help="comma-separated PIL systems (default: pil,pil-halve)"
    )
    parser.add_argument(
        "--rates", default="0.6,0.8,1.0", help="detection rates (default: %(default)s)"
    )
    parser.add_argument("--reps", type=int, default=20, help="repetitions (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="master seed (default: %(default)s)")
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run the paired runs and write the outputs; bad input raises before anything runs."""
    from tqdm import tqdm

    from pil.experiments.outdir import check_output_folder
    from pil.experiments.transfer import TRANSFER_SYSTEMS, run_transfer_study, write_transfer
    from pil.table_io import load_table

    if args.seed < 0:
        raise RobinPilError(f"--seed must be a whole number >= 0, got {args.seed}")
    if args.reps < 1:
        raise RobinPilError(f"--reps must be >= 1, got {args.reps}")
    rates = _rates(args.rates)
    systems = TRANSFER_SYSTEMS if args.systems is None else _systems(args.systems)
    for system in systems:
        if system not in ("pil", "pil-halve"):
            raise RobinPilError(f"--systems: transfer runs PIL learners; {system!r} is not one "
                                "(valid choices: 'pil', 'pil-halve')")  # fmt: skip
    if args.table is not None:
        load_table(args.table)  # a corrupt or missing file fails here, before anything runs
    check_output_folder(args.out)
    save_first = None if args.table is not None else args.out / "assembly_table.json"
    if save_first is not None:
        args.out.mkdir(parents=True, exist_ok=True)
    with tqdm(total=len(rates) * len(systems) * args.reps, desc="transfer", unit="pair",
              file=sys.stderr, disable=args.no_progress) as bar:  # fmt: skip
        rows = run_transfer_study(systems, rates, args.reps, args.seed, table_file=args.table,
                                  save_first=save_first, progress=bar.update)  # fmt: skip
    source = f"the saved table {args.table}" if args.table else "each repetition's assembly table"
    written = write_transfer(rows, args.out, source)
    if save_first is not None:
        written.append(save_first)
    print(f"{len(rows)} runs; wrote " + ", ".join(str(p) for p in written))
    return 0
