"""A whole sweep, start to end: check the request, connect, run what is left, merge, report.

``robin-pil sweep`` only parses its options into a :class:`SweepRequest` and calls
:func:`run_sweep`; everything else is here (learner-generic, no MuJoCo): the grid
(:mod:`pil.experiments.sweep_grid`), where runs execute (:mod:`pil.experiments.sweep_backends`,
:mod:`pil.experiments.sweep_exec`), the resumable store (:mod:`pil.experiments.sweep_store`)
and the report (:mod:`pil.experiments.results_report`). Messages go to ``say``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.experiments.paper import PAPER_REPS, rates_text
from pil.task.detector import CAMERAS
from pil.task.params import ASSEMBLY_DEFAULTS

EXIT_CLUSTER_LOST = 3  # the Dask cluster went away mid-sweep; rerun to resume


@dataclass(frozen=True)
class SweepRequest:
    """A sweep as given (text from a command line, or values from Python); checked by
    :func:`run_sweep` before anything runs."""

    out: Path = Path("sweep")
    kind: str = "learner"
    systems: str | None = None  # comma-separated; None: the grid's default systems
    rates: str | None = None  # comma-separated; None: the paper's (1.0 for the eye cameras)
    reps: Any = PAPER_REPS
    tables: Any = None
    params: tuple[str, ...] = field(default_factory=tuple)  # "NAME=V1,V2" texts
    detector: str | None = None
    seed: Any = 0
    run_function: str | None = None
    workers: Any = None
    scheduler: str | None = None
    connect_timeout: Any = 10.0
    report: bool = True
    progress: bool = True


def say(message: str) -> None:
    """A sweep's message on stderr."""
    print(f"robin-pil sweep: {message}", file=sys.stderr)


def run_sweep(request: SweepRequest, say: Callable[[str], None] = say) -> int:
    """Validate, connect, run what is left of the grid, merge, report: 0 when all runs pass,
    1 when some failed, :data:`EXIT_CLUSTER_LOST` when the cluster went away."""
    from pil.experiments.sweep_backends import CONNECT_TIMEOUT, WORKERS, check_address, make_backend
    from pil.experiments.sweep_exec import ClusterLostError, execute
    from pil.experiments.sweep_grid import DEFAULT_SYSTEMS, build_grid, longest_first, split_list
    from pil.experiments.sweep_kinds import load_kind
    from pil.experiments.sweep_store import RunStore, make_record
    from pil.outdir import check_out_dir

    if request.scheduler and request.workers is not None:
        raise RobinPilError("give --workers (local pool) or --scheduler (Dask), not both")
    workers = WORKERS.parse(request.workers, "--workers")
    timeout = CONNECT_TIMEOUT.parse(request.connect_timeout, "--connect-timeout")
    if request.scheduler is not None:
        check_address(request.scheduler)
    target = load_kind(request.kind, request.run_function)
    params = with_detector(list(request.params), request.detector)
    rates = split_list(rates_or_default(request.rates, params), "--rates")  # parsed by the grid
    tables = request.tables
    if tables is None and not any(p.strip().startswith("tables=") for p in params):
        spec = target.params.get("tables")  # the kind's default; None: the function's
        tables = ASSEMBLY_DEFAULTS["tables"] if spec is None else spec.default
    systems = request.systems
    grid = build_grid(
        target,
        systems=DEFAULT_SYSTEMS if systems is None else split_list(systems, "--systems"),
        rates=rates,
        reps=request.reps,
        params=params,
        tables=tables,
        base_seed=request.seed,
    )
    specs = grid.runs()
    id_columns = list(specs[0].columns())
    manifest = {"kind": target.name, "function": target.function, "seed": grid.base_seed}
    out = Path(request.out)
    backend = make_backend(workers, request.scheduler, timeout)
    try:
        check_out_dir(out)  # after connecting: an unreachable scheduler leaves no folder
        with RunStore(out, manifest) as store:
            done = store.finished_ids()
            todo = longest_first([spec for spec in specs if spec.run_id not in done], target)
            say(
                f"{len(specs)} runs in the grid, {len(specs) - len(todo)} already done, "
                f"{len(todo)} to run on {backend.name} ({backend.slots()} slots) -> {out}"
            )
            bar = progress_bar(len(specs), len(specs) - len(todo), not request.progress)
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
                    say(message)

            try:
                tally = execute(
                    specs=todo,
                    run=target.run,  # each run's typed spec, parsed once by the grid
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
        say(
            f"{lost_cluster}. {finished} of {len(specs)} runs are finished and kept in "
            f"{out}; start the scheduler and its workers again and rerun the same command "
            "to resume"
        )
        return EXIT_CLUSTER_LOST
    say(f"{tally.ok} runs done, {tally.failed} failed after a retry; results: {results}")
    for run_id in tally.failed_ids[:10]:
        say(f"  failed: {run_id}")
    if request.report and tally.ok + len(specs) - len(todo) > 0:
        from pil.experiments.results_report import write_report

        try:
            for path in write_report(results, out / "report"):
                say(f"report: {path}")
        except RobinPilError as error:  # the runs are done and kept; only the report is not
            say(f"no report: {error}; see 'robin-pil report --help'")
    return 1 if tally.failed else 0


def with_detector(params: list[str], detector: str | None) -> list[str]:
    """The ``--param`` texts with ``--detector`` added as ``detector=...``."""
    if detector is None:
        return list(params)
    if any(p.partition("=")[0].strip() == "detector" for p in params):
        raise RobinPilError("give the detector either with --detector or --param detector=...")
    return [*params, f"detector={detector}"]


def rates_or_default(rates: str | None, params: list[str]) -> str:
    """``--rates``, or its default: the paper's rates, or 1.0 when every run reads with the eye
    cameras (whose rate is measured, not drawn: several rates would only repeat the runs)."""
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


def progress_bar(total: int, initial: int, quiet: bool) -> Any:
    """The sweep's bar over runs (on stderr; ``quiet``: none)."""
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
