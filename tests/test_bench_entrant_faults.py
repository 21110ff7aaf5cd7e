"""An entrant that fails (issue 39): whatever its code does (exits, raises, returns no action,
takes too long), ``robin-pil bench`` ends with one line naming the agent, the track, the
condition, the seed and what the entrant did, and exit code 2; the runs finished before are
kept. A decision that takes longer than ``--decision-timeout`` is stopped."""

from __future__ import annotations

import contextlib
import io
import textwrap
from pathlib import Path

import pytest

from pil.bench.entrants import EntrantError
from pil.bench.journal import read_runs
from pil.bench.suite import load_suite
from pil.task.seeds import sub_seeds
from robin_sim.cli.main import main

SUITE = load_suite()
SEEDS = SUITE.seeds("dev", quick=True)
# what a factory is given for each run seed (the run's learner sub-seed)
LEARNER = [sub_seeds(s).phase("test").learner for s in SEEDS]

ACTOR = """
import time


class Actor:
    def __init__(self, seed):
        self.seed = seed

    def select_action(self, observation):
        {select}
        return 0

    def observe(self, action, reward):
        {observe}


def make(seed):
    {make}
    return Actor(seed)
"""


def _entrant(folder: Path, select: str = "pass", observe: str = "pass", make: str = "pass") -> str:
    path = folder / "entrant.py"
    path.write_text(textwrap.dedent(ACTOR).format(select=select, observe=observe, make=make))
    return f"{path}:make"


def _bench(spec: str, out: Path, *more: str) -> tuple[int, list[str], str]:
    argv = ["bench", "--agent", spec, "--track", "assembly", "--quick", "--no-progress"]
    err, printed = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(printed):
        try:
            code = main([*argv, "--out", str(out), *more])
        except SystemExit as error:  # argparse refuses an option's value
            code = int(error.code or 0)
    return code, err.getvalue().strip().splitlines(), printed.getvalue()


def _says(lines: list[str], *words: str) -> str:
    assert len(lines) == 1 and "Traceback" not in lines[0], lines
    for word in words:
        assert word in lines[0], (word, lines[0])
    return lines[0]


@pytest.mark.parametrize(
    ("where", "code", "said"),
    [
        ("make", "raise SystemExit(0)", "SystemExit"),
        ("select", "return None", "returned None"),
        ("select", "return 'push'", "returned 'push'"),
        ("select", "return 7", "returned 7"),
        ("select", "raise ValueError('no idea')", "ValueError: no idea"),
        ("select", "raise SystemExit(0)", "SystemExit"),
        ("observe", "1 / 0", "ZeroDivisionError"),
    ],
)
def test_an_entrant_that_fails_in_a_run_is_named_with_its_run(where, code, said, tmp_path):
    # the first quick seed runs as usual, the second fails: the line names that one
    if where == "make":
        parts = {"make": f"if seed == {LEARNER[1]}:\n        {code}"}
    else:
        parts = {where: f"if self.seed == {LEARNER[1]}:\n            {code}"}
    spec = _entrant(tmp_path, **parts)
    out = tmp_path / "out"
    status, err, _ = _bench(spec, out)
    assert status == 2
    _says(err, spec, "track assembly", f"seed {SEEDS[1]}", said)
    rows = read_runs(out, SUITE)
    assert rows and all(r["seed"] != SEEDS[1] or r["agent"] != spec for r in rows)


@pytest.mark.parametrize(
    ("spec", "said"),
    [("builtins:exit", "SystemExit"), ("sys:exit", "SystemExit")],
)
def test_an_entrant_that_exits_is_refused_before_any_run(spec, said, tmp_path):
    out = tmp_path / "out"
    status, err, _ = _bench(spec, out)
    assert status == 2 and not out.exists()
    _says(err, spec, said)


def test_an_entrant_file_that_exits_at_import_is_refused(tmp_path):
    path = tmp_path / "leaves.py"
    path.write_text("raise SystemExit(0)\n")
    status, err, _ = _bench(f"{path}:make", tmp_path / "out")
    assert status == 2
    _says(err, str(path), "SystemExit")


def test_a_slow_decision_is_stopped_at_the_limit_and_named(tmp_path):
    # sleeps far past the limit on the second seed; the limit stops it
    spec = _entrant(tmp_path, select=f"if self.seed == {LEARNER[1]}:\n            time.sleep(3600)")
    status, err, _ = _bench(spec, tmp_path / "out", "--decision-timeout", "0.5")
    assert status == 2
    _says(err, spec, f"seed {SEEDS[1]}", "select_action", "0.5 s", "--decision-timeout")


def test_a_slow_decision_that_swallows_the_stop_is_still_stopped(tmp_path):
    swallow = (
        f"while self.seed == {LEARNER[0]}:\n"
        "            try:\n"
        "                time.sleep(3600)\n"
        "            except BaseException:\n"
        "                pass"
    )
    spec = _entrant(tmp_path, select=swallow)
    status, err, _ = _bench(spec, tmp_path / "out", "--decision-timeout", "0.2")
    assert status == 2
    _says(err, spec, f"seed {SEEDS[0]}", "0.2 s")


def _bench_fd(spec: str, out: Path, capfd: pytest.CaptureFixture[str], *more: str):
    """As :func:`_bench`, reading what every process wrote to the file descriptors (the
    workers' too)."""
    argv = ["bench", "--agent", spec, "--track", "assembly", "--quick", "--no-progress"]
    capfd.readouterr()
    code = main([*argv, "--out", str(out), *more])
    return code, capfd.readouterr().err.strip().splitlines()


def test_an_entrant_failing_in_a_worker_process_is_named(tmp_path, capfd):
    spec = _entrant(tmp_path, select=f"if self.seed == {LEARNER[2]}:\n            return None")
    status, err = _bench_fd(spec, tmp_path / "out", capfd, "--workers", "2")
    assert status == 2
    _says(err, spec, f"seed {SEEDS[2]}", "returned None")  # one line: the workers say nothing


def test_a_slow_decision_in_a_worker_process_is_stopped(tmp_path, capfd):
    spec = _entrant(tmp_path, select=f"if self.seed == {LEARNER[2]}:\n            time.sleep(3600)")
    argv = ("--workers", "2", "--decision-timeout", "1")
    status, err = _bench_fd(spec, tmp_path / "out", capfd, *argv)
    assert status == 2
    _says(err, spec, f"seed {SEEDS[2]}", "1 s")


@pytest.mark.parametrize("workers", ["1", "2"])
@pytest.mark.parametrize(
    ("ends", "said"),
    [
        ("import os; os._exit(3)", "exit status 3"),
        ("import os, signal; os.kill(os.getpid(), signal.SIGKILL)", "killed by SIGKILL"),
    ],
)
def test_an_entrant_that_ends_its_process_is_named(ends, said, workers, tmp_path, capfd):
    """No guard in a process outlives it: the bench watches the process and names the run."""
    spec = _entrant(tmp_path, select=f"if self.seed == {LEARNER[2]}:\n            {ends}")
    out = tmp_path / "out"
    status, err = _bench_fd(spec, out, capfd, "--workers", workers)
    assert status == 2
    _says(err, spec, "track assembly", f"seed {SEEDS[2]}", said)
    rows = read_runs(out, SUITE)
    assert rows and all(r["seed"] != SEEDS[2] for r in rows)  # the runs before it are kept
    assert {r["seed"] for r in rows} >= {SEEDS[0], SEEDS[1]}


def test_an_agent_of_the_protocol_that_raises_is_named(tmp_path):
    path = tmp_path / "proto.py"
    path.write_text(
        textwrap.dedent(
            """
            from pil.bench.agents import RandomAgent


            class Broken(RandomAgent):
                def feedback(self, state, action, ok):
                    raise KeyError("lost")


            def make(seed):
                return Broken(seed)
            """
        )
    )
    status, err, _ = _bench(f"{path}:make", tmp_path / "out")
    assert status == 2
    _says(err, f"{path}:make", "feedback", "KeyError", f"seed {SEEDS[0]}")


@pytest.mark.parametrize("value", ["0", "-1", "nan", "1_0", "٣", "100000"])
def test_the_decision_timeout_is_checked(value, tmp_path):
    status, err, _ = _bench("random", tmp_path / "out", "--decision-timeout", value)
    assert status == 2 and "--decision-timeout" in err[-1]


def test_a_well_behaved_entrant_is_unchanged_by_the_guard(tmp_path):
    """The same rows with any limit: the guard only watches."""
    spec = _entrant(tmp_path)
    rows = []
    for limit in ("10", "3600"):
        out = tmp_path / limit
        assert _bench(spec, out, "--decision-timeout", limit)[0] == 0
        rows.append(
            sorted(
                (r["agent"], r["condition"], r["seed"], r["actions"]) for r in read_runs(out, SUITE)
            )
        )
    assert rows[0] == rows[1] and len(rows[0]) == 4 * 3 * len(SEEDS)


def test_the_time_limit_lets_interrupts_through():
    from pil.bench.guard import TimeLimit

    limit = TimeLimit(5.0)

    def interrupted() -> None:
        raise KeyboardInterrupt

    with limit, pytest.raises(KeyboardInterrupt):
        limit.call("select_action", interrupted)
    with limit, pytest.raises(EntrantError, match="select_action raised RuntimeError: x"):
        limit.call("select_action", _raise_runtime)


def _raise_runtime() -> None:
    raise RuntimeError("x")
