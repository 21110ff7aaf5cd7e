"""``robin-pil bench``: an agent written outside the package runs on the quick tracks and gets
leaderboard rows with intervals; its Holm p does not depend on who else ran; the eval seeds
cannot be tuned on; bad input is one message and exit code 2; an interrupted run resumes to
the same rows."""

from __future__ import annotations

import json
import math
import re
import textwrap
from pathlib import Path

import pytest

from pil.bench.analysis import comparisons
from pil.bench.journal import Journal, read_runs, sorted_runs
from pil.bench.run import Entrant, run_bench
from pil.bench.suite import load_suite
from pil.experiments.stats import holm
from robin_sim.cli.main import main

ENTRANT = "my_bench_agent:make"
INTERVAL = re.compile(r"(\S+) (\d+\.\d) \[(\d+\.\d), (\d+\.\d)\]")
# An actor of the environment's observations, written outside the package: a greedy table
# of the rewards per (observation, action) that tries each action in turn.
AGENT_SOURCE = textwrap.dedent(
    """
    import random


    class TableActor:
        def __init__(self, seed):
            self.rng = random.Random(seed)
            self.values = {}
            self.key = None

        def select_action(self, observation):
            self.key = tuple(int(observation[k]) for k in ("gesture", "previous_action", "hand"))
            row = self.values.setdefault(self.key, [0.5] * 5)
            best = max(row)
            return self.rng.choice([i for i, v in enumerate(row) if v == best])

        def observe(self, action, reward):
            self.values[self.key][action] = float(reward)


    def make(seed):
        return TableActor(seed)
    """
)


@pytest.fixture(scope="module")
def bench_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """One quick run of the outside agent and random (with the anchors and the oracle)."""
    folder = tmp_path_factory.mktemp("entrant")
    (folder / "my_bench_agent.py").write_text(AGENT_SOURCE)
    out = folder / "results"
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(folder)
        patch.syspath_prepend(str(folder))
        import contextlib
        import io

        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            code = main(
                [
                    "bench",
                    "--agent",
                    ENTRANT,
                    "--agent",
                    "random",
                    "--quick",
                    "--out",
                    str(out),
                    "--no-progress",
                ]
            )
    assert code == 0
    return out, printed.getvalue()


def check_outside_agent_rows(bench_run):
    """The outside agent's rows: one per quick track, each with real intervals."""
    out, printed = bench_run
    suite = load_suite()
    lines = [line for line in printed.splitlines() if ENTRANT in line]
    assert [line.split()[0] for line in lines] == list(suite.quick_tracks())
    for line in lines:
        shown = INTERVAL.findall(line)  # condition mean [low, high]
        assert len(shown) >= 1
        for condition, mean, low, high in shown:
            assert condition in suite.conditions
            assert float(low) <= float(mean) <= float(high) and float(low) < float(high)
        assert "vs pil-next-best:" in line and "p_holm" in line
    stamp = json.loads((out / "stamp.json").read_text())
    assert stamp["suite_version"] == suite.version and stamp["block"] == "dev"
    assert stamp["commit"] and stamp["quick"] is True
    rows = read_runs(out, suite)
    agents = {r["agent"] for r in rows}
    assert agents == {ENTRANT, "random", "pil-next-best", "pil-paper", "oracle"}
    conditions = sum(len(suite.track_conditions(t, quick=True)) for t in suite.quick_tracks())
    assert len(rows) == 5 * 3 * conditions


def test_an_outside_agent_gets_rows_and_holm_p_whoever_else_ran(bench_run):
    """An agent written to a temporary folder gets a leaderboard row with intervals on every
    quick track, and its Holm p is the same with and without another entrant. (One test: with
    pytest-xdist a second one could rebuild the module's run on the other worker.)"""
    check_outside_agent_rows(bench_run)
    out, _printed = bench_run
    suite = load_suite()
    rows = read_runs(out, suite)
    without = [r for r in rows if r["agent"] != "random"]
    for track in suite.quick_tracks():
        everyone = comparisons(suite, rows, track, ENTRANT, quick=True)
        fewer = comparisons(suite, without, track, ENTRANT, quick=True)
        assert _same(everyone, fewer)
        declared = len(suite.anchors) * len(suite.track_conditions(track, quick=True))
        assert {r["family_size"] for r in everyone} == {declared}
        # Holm over exactly the declared family, per test (no p: counts as p = 1)
        for test in ("paired t", "wilcoxon signed-rank"):
            family = [r for r in everyone if r["test"] == test]
            adjusted_ps = holm([r["p"] for r in family], size=declared)
            for r, adjusted in zip(family, adjusted_ps, strict=True):
                assert r["p_holm"] == adjusted or math.isnan(adjusted)


def _same(a: list[dict], b: list[dict]) -> bool:
    if len(a) != len(b):
        return False
    for x, y in zip(a, b, strict=True):
        for key in x:
            u, v = x[key], y[key]
            if isinstance(u, float) and math.isnan(u):
                if not (isinstance(v, float) and math.isnan(v)):
                    return False
            elif u != v:
                return False
    return True


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["--tune", "--seeds", "eval"], "--seeds dev"),
        (["--agent", "random", "--track", "nowhere"], "assembly"),
        (["--agent", "random", "--seeds", "test"], "dev, eval"),
        (["--agent", "no_such_module_here:make"], "cannot import"),
        (["--leaderboard", "--track", "physical"], "not part of the reference"),
        (["--agent", "random", "--workers", "0"], "--workers"),
    ],
)
def test_bad_input_is_one_message_and_exit_2(argv, named, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["bench", *argv, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and named in err[0] and "Traceback" not in err[0]
    assert not out.exists()  # refused before anything ran


def test_an_interrupted_run_resumes_to_the_same_rows(tmp_path):
    suite = load_suite()
    seeds = suite.seeds("dev", quick=True)
    entrants = [Entrant("pil-next-best", "pil-next-best"), Entrant("tamer", "tamer")]
    conditions = ("d60", "teacher")  # both quick conditions

    def go(out: Path, stop_after: int | None = None) -> list[dict]:
        done = []

        def progress(n: int) -> None:
            done.append(n)
            if stop_after is not None and len(done) >= stop_after:
                raise KeyboardInterrupt

        journal = Journal(out, suite, "dev", True)
        return run_bench(
            suite, entrants, ["assembly"], journal, seeds, progress=progress, conditions=conditions
        )

    with pytest.raises(KeyboardInterrupt):
        go(tmp_path / "a", stop_after=5)
    assert len(read_runs(tmp_path / "a", suite)) == 5
    resumed = go(tmp_path / "a")
    whole = go(tmp_path / "b")
    assert len(whole) == len(entrants) * len(conditions) * len(seeds)
    assert sorted_runs(resumed) == sorted_runs(whole)  # same seeds -> the same rows
    with pytest.raises(Exception, match="give a new --out"):
        Journal(tmp_path / "a", suite, "eval", True)


def test_an_entrant_file_that_makes_no_agent_is_refused_before_any_run(tmp_path, capsys):
    entrant = tmp_path / "not_an_agent.py"
    entrant.write_text("def make(seed):\n    return object()\n")
    out = tmp_path / "out"
    argv = ["bench", "--agent", f"{entrant}:make", "--quick", "--out", str(out), "--no-progress"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "neither an agent" in err and "select_action" in err and not out.exists()


def test_a_folder_another_command_writes_is_refused(tmp_path):
    from pil.folder_lock import FolderInUseError, FolderLock

    suite = load_suite()
    journal = Journal(tmp_path, suite, "dev", True)
    entrant = [Entrant("random", "random")]
    with FolderLock(tmp_path), pytest.raises(FolderInUseError):
        run_bench(suite, entrant, ["assembly"], journal, suite.seeds("dev", True)[:1])
    assert read_runs(tmp_path, suite) == []
