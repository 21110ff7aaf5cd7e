"""Tests of the sweep executors: a real process pool and a real Dask LocalCluster (loopback).

Failures are real: ``max_actions_per_gesture=1`` makes a learner run raise, and the run
functions of ``tests/sweep_test_runs.py`` end their worker process or fail once.
"""

from __future__ import annotations

import gc
import socket
from pathlib import Path

import pytest
from learner_rows import learner_row

from pil.experiments.sweep_backends import LocalBackend, SchedulerError, make_backend
from pil.experiments.sweep_exec import execute, execute_run
from pil.experiments.sweep_grid import build_grid
from pil.experiments.sweep_kinds import CustomCall, load_kind, run_custom, run_learner
from pil.task.spec import parse_run_spec

TESTS_DIR = str(Path(__file__).resolve().parent)


def kind_of(function: str | None):
    """The learner kind, or a custom function's."""
    return load_kind("learner") if function is None else load_kind("custom", function)


def specs(function: str | None = None, **grid):
    arguments = {"systems": ["pil", "c1"], "rates": [1.0], "reps": 2, "tables": 1, **grid}
    return build_grid(kind_of(function), **arguments).runs()


def run_all(backend, runs, function: str | None = None):
    """Execute ``runs``; return the tally and every (run_id, status, error, metrics, attempt)."""
    seen = []

    def record(spec, outcome, attempt, final):
        seen.append((spec.run_id, outcome["status"], outcome["error"], outcome["metrics"], attempt))

    try:
        tally = execute(runs, kind_of(function).run, backend, record)
    finally:
        backend.close()
    return tally, seen


def by_id(seen):
    """run_id -> list of (status, error, attempt) in the order they came back."""
    out: dict[str, list] = {}
    for run_id, status, error, _, attempt in seen:
        out.setdefault(run_id, []).append((status, error, attempt))
    return out


def test_execute_run_returns_metrics_or_the_error() -> None:
    spec = parse_run_spec(system="pil", rate=1.0, seed=3, params={"tables": 1})
    outcome = execute_run(run_learner, spec)
    assert outcome["status"] == "ok" and outcome["error"] == ""
    assert outcome["metrics"] == learner_row("pil", 1.0, 3, tables=1)
    assert outcome["wall_s"] > 0 and ":" in outcome["host"]
    failing = parse_run_spec(system="pil", rate=1.0, seed=3, params={"max_actions_per_gesture": 1})
    failed = execute_run(run_learner, failing)
    assert failed["status"] == "failed" and failed["metrics"] == {}
    assert "RunnerError: no approved action after 1 actions" in failed["error"]
    call = CustomCall("sweep_test_runs:self_failing_run", "pil", 1.0, 3, (("tables", 1),))
    reported = execute_run(run_custom, call)
    assert (reported["status"], reported["error"]) == ("failed", "gave up")
    assert reported["metrics"]["legs"] == 4  # what the run counted is kept


@pytest.mark.slow
def test_local_pool_runs_the_grid_like_direct_calls() -> None:
    runs = specs()
    tally, seen = run_all(LocalBackend(2), runs)
    assert (tally.ok, tally.failed, tally.attempts) == (len(runs), 0, len(runs))
    got = {run_id: metrics for run_id, _, _, metrics, _ in seen}
    for spec in runs:
        assert got[spec.run_id] == learner_row(
            spec.system, spec.rate, spec.seed, **dict(spec.params)
        )


@pytest.mark.slow
def test_a_failing_run_is_retried_once_and_the_rest_complete() -> None:
    runs = specs(params=["max_actions_per_gesture=1,25"])
    tally, seen = run_all(LocalBackend(2), runs)
    history = by_id(seen)
    failing = [s.run_id for s in runs if dict(s.params)["max_actions_per_gesture"] == 1]
    assert tally.failed == len(failing) == 4 and tally.ok == len(runs) - 4
    assert sorted(tally.failed_ids) == sorted(failing)
    for run_id in failing:
        assert [(status, attempt) for status, _, attempt in history[run_id]] == [
            ("failed", 1),
            ("failed", 2),
        ]
        assert "RunnerError: no approved action" in history[run_id][0][1]
    assert all(history[s.run_id] == [("ok", "", 1)] for s in runs if s.run_id not in failing)


@pytest.mark.slow
def test_a_run_that_fails_once_passes_on_its_retry(tmp_path) -> None:
    function = "sweep_test_runs:flaky_run"
    runs = specs(function, params=[f"marks={tmp_path}"])
    tally, seen = run_all(LocalBackend(2), runs, function)
    assert (tally.ok, tally.failed, tally.attempts) == (len(runs), 0, 2 * len(runs))
    for history in by_id(seen).values():
        assert [(s, a) for s, _, a in history] == [("failed", 1), ("ok", 2)]
        assert "RuntimeError: first attempt" in history[0][1]


@pytest.mark.slow
def test_a_dying_worker_charges_only_its_own_run() -> None:
    function = "sweep_test_runs:paced_run"
    runs = specs(function, systems=["pil", "c1", "c2"], params=["die=c1"])
    tally, seen = run_all(LocalBackend(2), runs, function)
    history = by_id(seen)
    dying = [s.run_id for s in runs if s.system == "c1"]
    assert sorted(tally.failed_ids) == sorted(dying) and tally.ok == len(runs) - len(dying)
    for run_id in dying:
        assert [(s, a) for s, _, a in history[run_id]] == [("failed", 1), ("failed", 2)]
        assert history[run_id][0][1].startswith("worker process died: BrokenProcessPool")
    for spec in runs:
        if spec.system != "c1":  # in flight with a dying run: rerun alone, not charged
            assert history[spec.run_id] == [("ok", "", 1)]


def test_unreachable_scheduler_names_the_address() -> None:
    with socket.socket() as probe:  # a loopback port nobody listens on
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    with pytest.raises(SchedulerError, match=f"cannot reach the Dask scheduler at '{address}'"):
        make_backend(scheduler=address, timeout_s=1.0)
    with pytest.raises(SchedulerError, match="'nonsense://x'"):
        make_backend(scheduler="nonsense://x", timeout_s=1.0)


def test_local_workers_must_be_positive() -> None:
    with pytest.raises(ValueError, match="--workers must be at least 1, got 0"):
        make_backend(workers=0)
    assert make_backend(workers=3).slots() == 3


@pytest.fixture(scope="module")
def cluster():
    """Two single-threaded worker processes on loopback; a killed worker fails its task.

    Each worker holds only the task it runs, so a crash is blamed on that task alone.
    """
    import dask
    from distributed import LocalCluster

    patch = pytest.MonkeyPatch()
    patch.setenv("PYTHONPATH", TESTS_DIR)  # workers import sweep_test_runs
    # Clients other tests left for the garbage collector (a failed connect leaves a half-built
    # one) are collected now: collected inside the new cluster's event-loop thread as it starts,
    # a client's __del__ blocks that thread on distributed's loop lock for its 10 s start limit.
    gc.collect()
    with (
        dask.config.set(
            {
                "distributed.scheduler.allowed-failures": 0,  # fail a task on its first crash
                "distributed.scheduler.worker-saturation": 1.0,  # one task per worker thread
            }
        ),
        LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        ) as local,
    ):
        yield local.scheduler_address
    patch.undo()


@pytest.mark.slow
def test_dask_gives_the_same_outcomes_as_the_local_pool(cluster) -> None:
    runs = specs(params=["max_actions_per_gesture=1,25"])
    local = sorted(run_all(LocalBackend(2), runs)[1])
    dask = sorted(run_all(make_backend(scheduler=cluster), runs)[1])
    assert [row[:2] + row[3:] for row in dask] == [row[:2] + row[3:] for row in local]
    assert sum(status == "failed" for _, status, *_ in dask) == 8  # 4 runs, tried twice
    assert all("RunnerError" in error for _, status, error, *_ in dask if status == "failed")


@pytest.mark.slow
def test_dask_records_a_killed_worker_and_retries_once(cluster) -> None:
    function = "sweep_test_runs:paced_run"
    runs = specs(function, reps=1, params=["die=c1"])
    tally, seen = run_all(make_backend(scheduler=cluster), runs, function)
    history = by_id(seen)
    assert tally.failed_ids == ["c1|rate=1.0|tables=1|die=c1|rep=0000"]
    attempts = history[tally.failed_ids[0]]
    assert [(s, a) for s, _, a in attempts] == [("failed", 1), ("failed", 2)]
    assert "KilledWorker" in attempts[0][1]
    # the other run passes; Dask may lose it once while its worker restarts (then retried)
    other = history["pil|rate=1.0|tables=1|die=c1|rep=0000"]
    assert other[-1][0] == "ok" and len(other) <= 2
