"""Sweep throughput: runs/s at 1 and 2 local workers, the speed-up, and Dask's overhead per run.

    python bench/bench_sweep.py [--repeats 5] [--learner-reps 4] [--physical-runs 4]

Each figure is the median of ``--repeats`` rounds of timed sweeps through the real pipeline (the
executor, the journal with one fsync per row, ``results.csv``), after a warm-up that starts
the workers and imports the run function there. Learner-only runs use the paper's grid
(5 systems x 4 rates, 10 tables); physical runs (``robin_sim.episode.physical_run:PHYSICAL_RUNS``:
PIL at 100 %, one table of ``--physical-legs`` legs, ``--physical-runs`` seeds: the handover
types differ, so the runs differ in length) are timed in the grid's order and longest expected
first (the order ``robin-pil sweep`` uses, :func:`pil.experiments.sweep_grid.longest_first`).
Dask runs on a ``LocalCluster`` on loopback with the same number of single-threaded worker
processes; its
overhead per run is (Dask time - local time) / runs. "Workers busy" is the share of the
workers' time spent inside runs: near 100 % means the sweep machinery keeps them fed, and the
speed-up is then bounded only by the free cores (the load average is printed alongside).
The journal's cost per row (write + flush + fsync) is measured on its own as a reference.
"""

from __future__ import annotations

import argparse
import importlib
import os
import statistics
import tempfile
import time
from pathlib import Path

import smoke  # bench/smoke.py: --smoke

from pil.experiments.sweep_backends import Backend, DaskBackend, LocalBackend
from pil.experiments.sweep_exec import execute
from pil.experiments.sweep_grid import (
    DEFAULT_RATES,
    DEFAULT_SYSTEMS,
    GridRow,
    build_grid,
    longest_first,
)
from pil.experiments.sweep_kinds import KINDS, SweepKind, import_object, load_kind
from pil.experiments.sweep_store import RunStore, make_record


def timed_sweep(backend: Backend, kind: SweepKind, specs: list[GridRow]) -> tuple[float, float]:
    """(seconds for one sweep of ``specs`` on a warm ``backend``, seconds spent inside runs)."""
    errors: list[str] = []
    busy = 0.0

    def record(spec: GridRow, outcome: dict, attempt: int, final: bool) -> None:
        nonlocal busy
        store.append(make_record(spec.columns(), outcome, attempt))
        busy += outcome.get("wall_s") or 0.0
        if outcome["error"]:
            errors.append(outcome["error"])

    with tempfile.TemporaryDirectory() as directory, RunStore(directory, {"bench": 1}) as store:
        started = time.perf_counter()
        tally = execute(specs, kind.run, backend, record)
        store.write_results([s.run_id for s in specs], list(specs[0].columns()))
        seconds = time.perf_counter() - started
    if tally.failed:
        raise RuntimeError(f"{tally.failed} runs failed, e.g. {tally.failed_ids[0]}: {errors[0]}")
    return seconds, busy


def warm_up(backend: Backend, kind: SweepKind) -> None:
    """Start the workers and import the kind's module in them."""
    path = KINDS.get(kind.name, kind.function)
    futures = [backend.executor().submit(import_object, path) for _ in range(backend.slots())]
    for future in futures:
        future.result()


def median_sweep(
    backend: Backend, kind: SweepKind, specs: list[GridRow], repeats: int
) -> tuple[float, float]:
    """Median (seconds, share of worker time spent in runs) over ``repeats`` sweeps."""
    try:
        warm_up(backend, kind)
        workers = backend.slots()
        timings = [timed_sweep(backend, kind, specs) for _ in range(repeats)]
    finally:
        backend.close()
    seconds = statistics.median(t for t, _ in timings)
    busy = statistics.median(b / (t * workers) for t, b in timings)
    return seconds, busy


def journal_seconds_per_row(rows: int = 200) -> float:
    """Seconds to append one row to the journal (write, flush, fsync)."""
    record = make_record({"run_id": "pil|x"}, {"status": "ok", "metrics": {"a": 1.0}}, 1)
    with tempfile.TemporaryDirectory() as directory, RunStore(directory, {"bench": 1}) as store:
        started = time.perf_counter()
        for _ in range(rows):
            store.append(record)
        return (time.perf_counter() - started) / rows


def specs_for(
    kind: str,
    reps: int,
    tables: int,
    params: tuple[str, ...] = (),
    systems: tuple[str, ...] = DEFAULT_SYSTEMS,
    rates: tuple[float, ...] = DEFAULT_RATES,
) -> tuple[SweepKind, list[GridRow]]:
    """The sweep kind ``kind`` and the runs of its grid."""
    target = load_kind(kind)
    grid = build_grid(target, systems=systems, rates=rates, reps=reps, tables=tables, params=params)
    return target, grid.runs()


def bench_kind(
    label: str,
    kind: SweepKind,
    specs: list[GridRow],
    repeats: int,
    dask: str | None,
    ordered: list[GridRow] | None = None,
):
    """Table rows for one run kind: 1 worker, 2 workers (grid order, and ``ordered`` if
    given: longest expected run first), Dask with 2 workers (in the order the sweep uses).

    The executors take turns, one sweep each per round, and every ratio is the median over
    rounds of that round's ratio: load from other processes then hits all of them alike.
    """
    n = len(specs)
    sweeps: dict[str, list[GridRow]] = {
        "local, 1 worker": specs,
        "local, 2 workers, grid order": specs,
    }
    if ordered is not None:
        sweeps["local, 2 workers, longest first"] = ordered
    last = list(sweeps)[-1]
    if dask is not None:
        sweeps["Dask, 2 workers"] = ordered or specs
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in sweeps}
    for _ in range(repeats):
        for name, runs in sweeps.items():
            if name.startswith("Dask"):
                backend: Backend = DaskBackend(dask)  # type: ignore[arg-type]
            else:
                backend = LocalBackend(1 if "1 worker" in name else 2)
            times[name].append(median_sweep(backend, kind, runs, 1))
    one = [t for t, _ in times["local, 1 worker"]]
    rows = []
    for name, measured in times.items():
        seconds = statistics.median(t for t, _ in measured)
        busy = statistics.median(b for _, b in measured) if "Dask" not in name else float("nan")
        speedup = statistics.median(o / t for o, (t, _) in zip(one, measured, strict=True))
        if name.startswith("Dask"):
            pairs = zip(measured, times[last], strict=True)
            overhead_ms = statistics.median(1000 * (d - loc) / n for (d, _), (loc, _) in pairs)
            name = f"{name} ({overhead_ms:+.0f} ms/run vs {last.removeprefix('local, ')})"
        rows.append((label, name, n, seconds, busy, f"{speedup:.2f} x"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="timed sweeps per figure")
    parser.add_argument("--learner-reps", type=int, default=4, help="reps of the 5x4 grid")
    parser.add_argument("--physical-runs", type=int, default=16, help="physical runs per sweep")
    parser.add_argument("--physical-repeats", type=int, default=3)
    parser.add_argument("--physical-legs", type=int, default=1, help="legs per physical run")
    parser.add_argument("--no-dask", action="store_true")
    args = smoke.parse_args(
        parser, repeats=1, learner_reps=1, physical_runs=1, physical_repeats=1, no_dask=True
    )

    load_before = os.getloadavg()
    cluster = None
    if not args.no_dask:
        from distributed import LocalCluster

        cluster = LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        )
    address = None if cluster is None else cluster.scheduler_address
    try:
        kind, specs = specs_for("learner", args.learner_reps, 10)
        rows = bench_kind("learner", kind, specs, args.repeats, address)
        try:
            importlib.import_module("robin_sim.episode.physical_run").PHYSICAL_RUNS  # noqa: B018
        except (ImportError, AttributeError) as error:
            physical_note = (
                f"physical: not measured (robin_sim.episode.physical_run.PHYSICAL_RUNS: {error})"
            )
        else:
            physical_note = ""
            legs = (f"legs_per_table={args.physical_legs}",)  # PIL at 100 %: runs of like length
            kind, specs = specs_for("physical", args.physical_runs, 1, legs, ("pil",), (1.0,))
            ordered = longest_first(specs, kind)
            try:
                rows += bench_kind("physical", kind, specs, args.physical_repeats, address, ordered)
            except RuntimeError as error:
                physical_note = f"physical: not measured ({error})"
    finally:
        if cluster is not None:
            cluster.close()

    print("| kind | executor | runs | s (median) | s/run | runs/s | speed-up | workers busy |")
    print("|---|---|---|---|---|---|---|---|")
    for kind, executor, n, seconds, busy, speedup in rows:
        busy_text = "n/a" if busy != busy else f"{100 * busy:.0f} %"
        print(
            f"| {kind} | {executor} | {n} | {seconds:.2f} | {seconds / n:.3f} | "
            f"{n / seconds:.1f} | {speedup} | {busy_text} |"
        )
    print(
        f"\nmedians of {args.repeats} (learner) / {args.physical_repeats} (physical) sweeps; "
        "workers busy = time inside runs / (sweep time x workers)"
    )
    print(f"load average before / after: {load_before} / {os.getloadavg()}")
    print(f"\njournal row (write + flush + fsync): {1000 * journal_seconds_per_row():.2f} ms")
    if physical_note:
        print(physical_note)
    print(f"machine: {Path('/proc/cpuinfo').read_text().count('processor')} CPUs")


if __name__ == "__main__":
    main()
