"""``robin-pil sweep``: a resumable grid of runs on a local process pool or a Dask cluster.

Example: ``robin-pil sweep --rates 0.4,0.6,0.8,1.0 --reps 20 --systems pil,c1,c2,c3,c4
--param discard=0,0.3 --out results/`` runs 800 learner-only runs on every core, writes each
run's row the moment it ends, and finishes with ``results.csv`` and a report. The same command
again resumes: finished runs are skipped, failed ones are tried again.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.experiments.paper import PAPER_REPS, rates_text
from robin_sim.cli.options import add_progress_switch, systems_help

EXIT_CLUSTER_LOST = 3  # the Dask cluster went away mid-sweep; rerun to resume

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
        choices=("learner", "physical"),
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
    """Validate, connect, run what is left of the grid, merge, report. 0 when all runs pass."""
    from pil.experiments.sweep_backends import (
        CONNECT_TIMEOUT,
        WORKERS,
        check_address,
        make_backend,
    )
    from pil.experiments.sweep_exec import ClusterLostError, execute
    from pil.experiments.sweep_grid import (
        DEFAULT_SYSTEMS,
        build_grid,
        load_target,
        longest_first,
        split_list,
    )
    from pil.experiments.sweep_store import RunStore, make_record
    from pil.outdir import check_out_dir
    from pil.task.params import RATE

    if args.scheduler and args.workers is not None:
        raise RobinPilError("give --workers (local pool) or --scheduler (Dask), not both")
    workers = WORKERS.parse(args.workers, "--workers")
    timeout = CONNECT_TIMEOUT.parse(args.connect_timeout, "--connect-timeout")
    if args.scheduler is not None:
        check_address(args.scheduler)
    target = load_target(args.kind, args.run_function)
    params = _with_detector(args.param, args.detector)
    rates_given = _rates_text(args.rates, params)
    rates = [RATE.parse(text, "--rates") for text in split_list(rates_given, "--rates")]
    tables = args.tables
    if tables is None and not any(p.strip().startswith("tables=") for p in params):
        spec = target.params.get("tables")  # the kind's default; None: the function's
        tables = 10 if spec is None else spec.default
    grid = build_grid(
        target,
        systems=DEFAULT_SYSTEMS if args.systems is None else split_list(args.systems, "--systems"),
        rates=rates,
        reps=args.reps,
        params=params,
        tables=tables,
        base_seed=args.seed,
    )
    specs = grid.runs()
    id_columns = list(specs[0].columns())
    manifest = {"kind": target.kind, "function": target.function, "seed": grid.base_seed}
    backend = make_backend(workers, args.scheduler, timeout)
    try:
        check_out_dir(args.out)  # after connecting: an unreachable scheduler leaves no folder
        with RunStore(args.out, manifest) as store:
            done = store.finished_ids()
            todo = longest_first([spec for spec in specs if spec.run_id not in done], target)
            _say(
                f"{len(specs)} runs in the grid, {len(specs) - len(todo)} already done, "
                f"{len(todo)} to run on {backend.name} ({backend.slots()} slots) -> {args.out}"
            )
            bar = _progress(len(specs), len(specs) - len(todo), args.no_progress)
            failed = retried = 0
            lost_cluster = ""

            def record(spec: Any, outcome: dict[str, Any], attempt: int, final: bool) -> None:
                nonlocal failed, retried
                store.append(make_record(spec.columns(), outcome, attempt))
                if outcome["status"] != "ok":
                    failed, retried = failed + final, retried + (not final)
                    bar.set_postfix(failed=failed, retrying=retried, refresh=False)
                if final:
                    bar.update(1)

            notices: dict[str, float] = {}

            def waiting(message: str) -> None:  # once a minute at most, per message
                if time.monotonic() - notices.get(message, -1e9) > 60:
                    notices[message] = time.monotonic()
                    bar.clear()
                    _say(message)

            try:
                tally = execute(
                    specs=todo,
                    function=target.function,
                    backend=backend,
                    on_outcome=record,
                    first_attempt=lambda run_id: store.attempts(run_id) + 1,
                    on_wait=waiting,
                )
            except ClusterLostError as lost:
                lost_cluster = f"{lost}"
            finally:
                bar.close()
                results = store.write_results([s.run_id for s in specs], id_columns)
            finished = len(store.finished_ids())
    finally:
        backend.close()
    if lost_cluster:
        _say(
            f"{lost_cluster}. {finished} of {len(specs)} runs are finished and kept in "
            f"{args.out}; start the scheduler and its workers again and rerun the same command "
            "to resume"
        )
        return EXIT_CLUSTER_LOST
    _say(f"{tally.ok} runs done, {tally.failed} failed after a retry; results: {results}")
    for run_id in tally.failed_ids[:10]:
        _say(f"  failed: {run_id}")
    if not args.no_report and tally.ok + len(specs) - len(todo) > 0:
        from pil.experiments.results_report import write_report

        try:
            for path in write_report(results, args.out / "report"):
                _say(f"report: {path}")
        except RobinPilError as error:  # the runs are done and kept; only the report is not
            _say(f"no report: {error}; see 'robin-pil report --help'")
    return 1 if tally.failed else 0


def _with_detector(params: list[str], detector: str | None) -> list[str]:
    """The ``--param`` texts with ``--detector`` added as ``detector=...``."""
    if detector is None:
        return list(params)
    if any(p.partition("=")[0].strip() == "detector" for p in params):
        raise RobinPilError("give the detector either with --detector or --param detector=...")
    return [*params, f"detector={detector}"]


def _rates_text(rates: str | None, params: list[str]) -> str:
    """``--rates``, or its default: the paper's rates, or 1.0 when every run reads with the eye
    cameras (whose rate is measured, not drawn: several rates would only repeat the runs)."""
    from pil.task.detector import CAMERAS

    detectors = [
        [value.strip() for value in p.partition("=")[2].split(",")]
        for p in params
        if p.partition("=")[0].strip() == "detector"
    ]
    cameras_only = bool(detectors) and detectors[0] == [CAMERAS]
    if rates is None:
        return "1.0" if cameras_only else rates_text()
    if cameras_only and len(rates.split(",")) > 1:
        raise RobinPilError(
            f"--rates {rates}: with --detector {CAMERAS} the eye cameras measure the detection "
            "rate and the runs draw none; give one rate (or none) and sweep the camera "
            "conditions instead, e.g. --param lighting=1,0.25 --param camera_noise=0,12"
        )
    return rates


def _progress(total: int, initial: int, quiet: bool) -> Any:
    from tqdm import tqdm

    return tqdm(
        total=total,
        initial=initial,
        unit="run",
        desc="sweep",
        file=sys.stderr,
        disable=quiet,
        dynamic_ncols=True,
        smoothing=0.1,
    )


def _say(message: str) -> None:
    print(f"robin-pil sweep: {message}", file=sys.stderr)
