"""``robin-pil adapt``: the person changes a gesture's meaning mid-task (learner only).

Writes ``adaptation.csv``, ``adaptation.md`` (mean ± sd, Welch t-tests of PIL against every
other system, how many runs adapted) and ``adaptation.png``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pil.errors import RobinPilError
from robin_sim.cli.study import _rates, _systems

DEFAULT_OUT = Path("out/adapt")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The adaptation study's options."""
    parser.add_argument(
        "--change",
        default=None,
        help="mapping change file (default: scenarios/mapping_change.yaml)",
    )
    parser.add_argument(
        "--systems",
        default=None,
        help="comma-separated systems (default: pil,pil-halve,c1,c2,c3,c4,bandit,tamer)",
    )
    parser.add_argument("--rates", default="0.8,1.0", help="detection rates (default: %(default)s)")
    parser.add_argument("--reps", type=int, default=20, help="repetitions (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="master seed (default: %(default)s)")
    parser.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default: %(default)s)"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args: argparse.Namespace) -> int:
    """Run the paired runs and write the outputs; bad input raises before anything runs."""
    from tqdm import tqdm

    from pil.experiments.adaptation import (
        ADAPT_SYSTEMS,
        DEFAULT_CHANGE,
        load_change,
        run_adaptation_study,
        write_adaptation,
    )
    from pil.experiments.outdir import check_output_folder

    if args.seed < 0:
        raise RobinPilError(f"--seed must be a whole number >= 0, got {args.seed}")
    if args.reps < 1:
        raise RobinPilError(f"--reps must be >= 1, got {args.reps}")
    rates = _rates(args.rates)
    systems = ADAPT_SYSTEMS if args.systems is None else _systems(args.systems)
    change = load_change(DEFAULT_CHANGE if args.change is None else args.change)
    check_output_folder(args.out)
    total = len(rates) * len(systems) * args.reps
    with tqdm(total=total, desc="adapt", unit="run", file=sys.stderr,
              disable=args.no_progress) as bar:  # fmt: skip
        rows = run_adaptation_study(change, systems, rates, args.reps, args.seed,
                                    progress=bar.update)  # fmt: skip
    written = write_adaptation(rows, change, args.out)
    print(f"{len(rows)} paired runs; wrote " + ", ".join(str(p) for p in written))
    return 0
