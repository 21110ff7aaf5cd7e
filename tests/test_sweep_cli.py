"""Tests of ``robin-pil sweep``: bad input, results and report, resume, kills, Dask parity.

The commands go through the real dispatcher (:func:`robin_sim.cli.main.main`, exit codes and
messages included), given only the ``sweep`` and ``report`` commands so these tests do not
depend on the other commands' modules.
"""

from __future__ import annotations

import contextlib
import csv
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pil.experiments.sweep_store import JOURNAL, RESULTS, read_journal
from robin_sim.cli import main as cli

TESTS_DIR = Path(__file__).resolve().parent
COMMANDS = {name: cli.COMMANDS[name] for name in ("sweep", "report")}
SMALL = ["--systems", "pil,c1", "--rates", "0.6,1.0", "--reps", "2", "--tables", "1"]
ENTRY = (
    "import sys; from robin_sim.cli import main as cli; "
    "cli.COMMANDS = {k: v for k, v in cli.COMMANDS.items() if k in ('sweep', 'report')}; "
    "sys.exit(cli.main(sys.argv[1:]))"
)


@pytest.fixture
def robin(monkeypatch):
    """``robin(*argv)`` -> exit code of ``robin-pil`` run in this process."""
    monkeypatch.setattr(cli, "COMMANDS", COMMANDS)
    return lambda *argv: cli.main([str(a) for a in argv])


def rows(directory: Path) -> list[dict[str, str]]:
    with (directory / RESULTS).open(newline="") as handle:
        return list(csv.DictReader(handle))


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _ctrl_c_as_in_a_terminal() -> None:
    """In the child: let SIGINT raise KeyboardInterrupt even if this test was started from a
    shell that ignores it for background jobs (the ignore would be inherited)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--param", "dicsard=0.3"], "unknown learner parameter 'dicsard'; valid choices: "),
        (["--rates", ""], "empty grid: no detection rates given"),
        (["--rates", "0.4,1.2"], "--rates must be a number in (0, 1], got '1.2'"),
        (["--rates", "0.4,abc"], "--rates must be a number in (0, 1], got 'abc'"),
        (["--systems", "pil,c7"], "unknown system 'c7'; valid choices: 'pil', 'c1', 'c2'"),
        (["--reps", "0"], "--reps must be a whole number from 1 to 100000, got '0'"),
        (["--param", "discard="], "empty grid: --param discard has no values"),
        (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
        (
            ["--connect-timeout", "1", "--scheduler", "tcp://127.0.0.1:PORT"],
            "cannot reach the Dask scheduler at 'tcp://127.0.0.1:PORT' within 1 s",
        ),
    ],
)
def test_bad_input_is_one_clear_error_before_anything_starts(
    robin, capsys, tmp_path, argv, message
) -> None:
    port = str(free_port())
    out = tmp_path / "out"
    argv = [arg.replace("PORT", port) for arg in argv]
    assert robin("sweep", *argv, "--out", out, "--quiet") == 2
    error = capsys.readouterr().err
    assert error.startswith("robin-pil sweep: error: ")
    assert message.replace("PORT", port) in error
    assert error.count("\n") == 1  # one line, no traceback
    assert not out.exists()  # nothing written, nothing started
    if "dicsard" in message:
        assert "'discard'" in error and "'silent_ok'" in error


def test_physical_kind_lists_its_own_parameters_too(robin, capsys, tmp_path) -> None:
    out = tmp_path / "out"
    assert robin("sweep", "--kind", "physical", "--param", "vrify=1", "--out", out) == 2
    error = capsys.readouterr().err
    assert "unknown physical parameter 'vrify'; valid choices: " in error
    assert "'verify'" in error and "'discard'" in error  # the episode's own and the learner's
    assert not out.exists()


@pytest.mark.slow
def test_sweep_writes_rows_and_report_and_resumes(robin, capsys, tmp_path) -> None:
    out = tmp_path / "sweep"
    assert robin("sweep", *SMALL, "--workers", "2", "--out", out) == 0
    results = rows(out)
    assert len(results) == 8 and all(row["status"] == "ok" for row in results)
    ids = [row["run_id"] for row in results]
    assert ids == sorted(ids) and len(set(ids)) == 8
    assert {"total_gestures", "total_actions", "seed", "tables"} <= set(results[0])
    assert (out / "report" / "summary.md").exists()
    assert (out / "report" / "total_gestures.png").stat().st_size > 1000
    err = capsys.readouterr().err
    assert "8 runs in the grid, 0 already done, 8 to run" in err and "8/8" in err
    journal, results_bytes = (out / JOURNAL).read_bytes(), (out / RESULTS).read_bytes()
    assert robin("sweep", *SMALL, "--workers", "1", "--out", out, "--no-report") == 0
    assert "8 already done, 0 to run" in capsys.readouterr().err
    assert (out / JOURNAL).read_bytes() == journal  # nothing ran again
    assert (out / RESULTS).read_bytes() == results_bytes
    more = [arg if arg != "2" else "3" for arg in SMALL]  # --reps 3: the grid grows
    assert robin("sweep", *more, "--out", out, "--no-report", "--quiet") == 0
    assert "12 runs in the grid, 8 already done, 4 to run" in capsys.readouterr().err
    assert [row for row in rows(out) if row["rep"] != "2"] == results


@pytest.mark.slow
def test_failed_runs_are_recorded_retried_and_tried_again_on_rerun(robin, capsys, tmp_path):
    out = tmp_path / "sweep"
    argv = ["sweep", *SMALL, "--param", "max_actions_per_gesture=1,25", "--out", out]
    assert robin(*argv, "--no-report", "--quiet") == 1
    results = rows(out)
    failed = [row for row in results if row["status"] == "failed"]
    assert len(results) == 16 and len(failed) == 8
    assert all(row["max_actions_per_gesture"] == "1" for row in failed)
    assert all("RunnerError: no approved action after 1 actions" in r["error"] for r in failed)
    assert "8 runs done, 8 failed after a retry" in capsys.readouterr().err
    assert robin(*argv, "--quiet") == 1  # failed runs are tried again, twice more
    records, _ = read_journal(out / JOURNAL)
    attempts = [r["attempt"] for r in records if r["run_id"] == failed[0]["run_id"]]
    assert attempts == [1, 2, 3, 4]
    assert sum(r["status"] == "ok" for r in records) == 8  # passed runs never ran again
    assert "8 failed runs left out" in (out / "report" / "summary.md").read_text()


KILL_GRID = [
    "--systems",
    "pil,c1,c2",
    "--rates",
    "0.6,1.0",
    "--reps",
    "5",
    "--tables",
    "1",
    "--run-function",
    "sweep_test_runs:paced_run",
    "--param",
    "delay=0.1",
]


@pytest.mark.slow
@pytest.mark.parametrize("how", [signal.SIGINT, signal.SIGKILL], ids=["sigint", "sigkill"])
def test_a_killed_sweep_resumes_without_repeating_or_losing_runs(robin, tmp_path, how) -> None:
    out, reference = tmp_path / "killed", tmp_path / "reference"
    env = {**os.environ, "PYTHONPATH": str(TESTS_DIR)}
    argv = ["sweep", *KILL_GRID, "--workers", "2", "--no-report", "--quiet"]
    process = subprocess.Popen(
        [sys.executable, "-c", ENTRY, *argv, "--out", str(out)],
        env=env,
        stderr=subprocess.PIPE,
        start_new_session=True,
        preexec_fn=_ctrl_c_as_in_a_terminal,
    )
    try:
        deadline = time.monotonic() + 60
        while _lines(out / JOURNAL) < 6 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert process.poll() is None, "the sweep ended before it could be interrupted"
        os.kill(process.pid, how)
        _, stderr = process.communicate(timeout=30)
        if how == signal.SIGINT:
            assert process.returncode == 130
            assert b"interrupted; finished work is kept" in stderr
        else:
            assert process.returncode == -signal.SIGKILL
            _wait_group_gone(process.pid, timeout=10)  # orphaned workers exit by themselves
    finally:
        if process.poll() is None:
            process.kill()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)  # only this test's own process group
    records, _ = read_journal(out / JOURNAL)
    done_before = {r["run_id"] for r in records if r["status"] == "ok"}
    assert 6 <= len(done_before) < 30
    assert robin(*argv, "--run-function", "sweep_test_runs:paced_run", "--out", out) == 0
    records, _ = read_journal(out / JOURNAL)
    ok_ids = [r["run_id"] for r in records if r["status"] == "ok"]
    assert len(ok_ids) == len(set(ok_ids)) == 30  # nothing repeated, nothing lost
    assert robin(*argv, "--out", reference) == 0
    assert (out / RESULTS).read_bytes() == (reference / RESULTS).read_bytes()


def _lines(path: Path) -> int:
    return path.read_bytes().count(b"\n") if path.exists() else 0


def _wait_group_gone(group: int, timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            os.killpg(group, 0)
        except ProcessLookupError:
            return
        time.sleep(0.1)
    raise AssertionError(f"processes of the killed sweep still alive after {timeout} s")


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        yield cluster.scheduler_address


@pytest.mark.slow
def test_local_pool_and_dask_give_byte_identical_results(robin, tmp_path, scheduler) -> None:
    grid = [*SMALL, "--param", "discard=0,0.3", "--seed", "4", "--no-report", "--quiet"]
    one, two, dask = tmp_path / "one", tmp_path / "two", tmp_path / "dask"
    assert robin("sweep", *grid, "--workers", "1", "--out", one) == 0
    assert robin("sweep", *grid, "--workers", "2", "--out", two) == 0
    assert robin("sweep", *grid, "--scheduler", scheduler, "--out", dask) == 0
    expected = (one / RESULTS).read_bytes()
    assert len(rows(one)) == 16
    assert (two / RESULTS).read_bytes() == expected
    assert (dask / RESULTS).read_bytes() == expected
    hosts = {json.loads(line)["host"] for line in (dask / JOURNAL).read_text().splitlines()}
    assert len(hosts) >= 1  # ran on the cluster's workers, recorded in the journal only


@pytest.mark.slow
def test_physical_kind_runs_real_episodes_and_reports_legs(robin, capsys, tmp_path) -> None:
    """One real physical episode (1 table of 1 leg, about 10-20 s) through the whole sweep."""
    out = tmp_path / "physical"
    argv = [
        "sweep",
        "--kind",
        "physical",
        "--systems",
        "pil",
        "--rates",
        "1.0",
        "--reps",
        "1",
        "--tables",
        "1",
        "--param",
        "legs_per_table=1",
        "--workers",
        "1",
        "--quiet",
        "--out",
        out,
    ]
    assert robin(*argv) == 0
    (row,) = rows(out)
    assert row["run_id"] == "pil|rate=1.0|tables=1|legs_per_table=1|rep=0000"
    assert row["status"] == "ok" and row["error"] == ""
    assert row["legs_delivered"] == "1" and row["physical_failures"] == "0"
    assert float(row["sim_time_s"]) > 10.0  # a real episode takes simulated time
    assert "wall_time_s" not in row  # machine timings live in timings.csv
    timings = (out / "timings.csv").read_text().splitlines()
    assert timings[0] == "run_id,host,wall_s,wall_time_s,real_time_factor"
    assert float(timings[1].split(",")[3]) > 0
    summary = (out / "report" / "summary.md").read_text()
    assert "## Physical outcome per rate" in summary
    assert "| 1.0 | pil | 1 | 100.0 ± 0.0 | 0.0 ± 0.0 |" in summary
    capsys.readouterr()
    assert robin(*argv) == 0  # resumed: nothing to run again
    assert "1 already done, 0 to run" in capsys.readouterr().err
