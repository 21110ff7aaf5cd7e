"""``robin-pil sweep``: a resumable grid of runs on a local process pool or a Dask cluster.

Example: ``robin-pil sweep --rates 0.4,0.6,0.8,1.0 --reps 20 --systems pil,c1,c2,c3,c4
--param discard=0,0.3 --out results/`` runs 800 learner-only runs on every core, writes each
run's row the moment it ends, and finishes with ``results.csv`` and a report. The same command
again resumes: finished runs are skipped, failed ones are tried again.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pil.experiments.paper import PAPER_REPS, rates_text
from pil.experiments.sweep_kinds import KINDS
from robin_sim.cli.options import add_progress_switch, systems_help

_EPILOG = (
    "Results: DIR/runs.jsonl (every attempt, written as it ends), DIR/results.csv (one row per "
    "run, sorted by run id), DIR/report/ (summary, t-tests, figures). Rerun the same command to "
    "resume. Cluster: start 'dask scheduler' and 'dask worker tcp://HOST:8786' (robin-pil "
    "installed on every worker), then pass --scheduler tcp://HOST:8786."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The sweep's options (the grid, where results go, where runs execute)."""
    parser.epilog = _EPILOG
    grid = parser.add_argument_group("grid")
    grid.add_argument(
        "--kind",
        default="learner",
        choices=tuple(KINDS),
        help="learner-only runs or physical MuJoCo episodes (default: learner)",
    )
    grid.add_argument(
        "--systems",
        default=None,
        help=systems_help("the paper's five, pil and c1..c4"),
    )
    grid.add_argument(
        "--rates",
        default=None,
        help=f"comma-separated detection rates in (0, 1] (default: {rates_text()}; 1.0 with "
        "--detector vision, whose cameras measure the rate)",
    )
    grid.add_argument(
        "--reps", default=PAPER_REPS, help="repetitions per cell (default: %(default)s)"
    )
    grid.add_argument(
        "--tables",
        default=None,
        help="tables per run (default: the kind's: 10 learner, the scenario's physical)",
    )
    grid.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=V1,V2",
        help="sweep a parameter over values (repeatable), e.g. discard=0,0.3",
    )
    grid.add_argument(
        "--detector",
        default=None,
        help="how the runs read the person (as --param detector=...): exact (default), "
        "independent, measured:FILE, or vision (physical runs only: Robin's eye cameras; "
        "sweep their conditions with e.g. --param lighting=1,0.25 --param camera_noise=0,12)",
    )
    grid.add_argument(
        "--seed",
        default=0,
        help="base seed; each run's seed derives from it and the run's parameters",
    )
    grid.add_argument(
        "--run-function",
        default=None,
        metavar="MODULE:FUNCTION",
        help="run a custom function instead of the kind's (advanced; default: the kind's)",
    )
    where = parser.add_argument_group("execution")
    where.add_argument(
        "--out", type=Path, default=Path("sweep"), help="results directory (default: ./sweep)"
    )
    where.add_argument(
        "--workers", default=None, help="local worker processes (default: all cores)"
    )
    where.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="Dask scheduler, e.g. tcp://host:8786 (default: local pool)",
    )
    where.add_argument(
        "--connect-timeout",
        default=10.0,
        metavar="S",
        help="seconds to wait for the scheduler (default: 10)",
    )
    where.add_argument("--no-report", action="store_true", help="skip the report at the end")
    add_progress_switch(where)


def run(args: argparse.Namespace) -> int:
    """Parse the options into a request and run the sweep (:mod:`pil.experiments.sweep_run`)."""
    from pil.experiments.sweep_run import SweepRequest, run_sweep

    request = SweepRequest(
        out=args.out,
        kind=args.kind,
        systems=args.systems,
        rates=args.rates,
        reps=args.reps,
        tables=args.tables,
        params=tuple(args.param),
        detector=args.detector,
        seed=args.seed,
        run_function=args.run_function,
        workers=args.workers,
        scheduler=args.scheduler,
        connect_timeout=args.connect_timeout,
        report=not args.no_report,
        progress=not args.no_progress,
    )
    return run_sweep(request)
