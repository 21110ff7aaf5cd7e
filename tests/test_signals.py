"""The twelve signal cases of issue 26, each as a real ``robin-pil`` process in its own group.

One policy for every command (:mod:`pil.signal_policy`): SIGINT and SIGTERM alike, whatever
the inherited disposition, end a command with 130 within 5 s, its finished work kept and no
process of its group left; a rerun resumes. The checks read files and ``/proc`` only
(:mod:`signal_rig`). Cases:

1. ``study`` + SIGTERM: 130 and a message (was: killed, -15, no word);
2. ``sweep`` + SIGTERM: 130 (was -15);
3. ``sweep`` + SIGTERM: ``results.csv`` written from the finished runs (was: not written);
4. ``people`` + SIGTERM: 130 (was -15);
5. ``study`` + Ctrl-C: the finished repetitions are kept (was: "finished work is kept" and
   nothing was);
6. ``study`` interrupted, then rerun: it resumes, to the files of an uninterrupted run (was: no
   resume);
7. ``people --appearance`` + Ctrl-C to the group: 130 within 5 s (was: over 90 s, the pool
   waited for the episodes in flight);
8. ``people --appearance`` + SIGTERM to the process alone: 130 within 5 s (was: the same wait);
9. ``people --appearance`` killed (``kill -9``): its spawn workers end too (were: orphans);
10. ``episode`` + SIGTERM in teardown, its summary already ``finished``: 0 or 130 (was -15);
11. ``episode`` started as a background job (SIGINT ignored) + SIGTERM: 130 and an
    ``interrupted`` summary (was -15: the guard stood aside for an ignored SIGINT);
12. ``sweep`` started as a background job (SIGINT ignored) + SIGINT: 130 and its results
    (was: the signal ignored, the sweep ran on).
"""

from __future__ import annotations

import csv
import json
import os
import signal
import time
from pathlib import Path

import pytest
from signal_rig import EXIT_WITHIN_S, lines, signal_when, start

from robin_sim.cli import main as cli

STUDY = ["study", "--rates", "0.4,1.0", "--systems", "pil", "--reps", "40", "--quiet"]
PEOPLE = ["people", "--reps", "40", "--quiet"]
SWEEP = ["sweep", "--rates", "0.4,1.0", "--systems", "pil,c1", "--reps", "40"]
SWEEP += ["--workers", "2", "--no-report", "--quiet"]
APPEARANCE = ["people", "--appearance", "--reps", "1", "--tables", "1", "--person", "usual"]
APPEARANCE += ["--workers", "2", "--quiet"]
EPISODE = ["episode", "--scenario", "one_handover", "--no-verify", "--quiet"]
KEPT = "interrupted; finished work is kept"


def _reps(out: Path) -> int:
    return lines(out / "reps.jsonl")


def _episode_in_flight(out: Path) -> bool:
    return any((out / "runs").glob("*/summary.json"))


# --- cases 1-4: SIGTERM is Ctrl-C for every command ----------------------------------------
@pytest.mark.parametrize(
    ("argv", "journal"),
    [(STUDY, "reps.jsonl"), (PEOPLE, "reps.jsonl"), (SWEEP, "runs.jsonl")],
    ids=["study", "people", "sweep"],
)
def test_sigterm_ends_a_command_with_130_and_keeps_its_finished_work(
    tmp_path: Path, argv: list[str], journal: str
) -> None:
    out = tmp_path / "out"
    process = start([*argv, "--out", out])
    outcome = signal_when(process, signal.SIGTERM, lambda: lines(out / journal) >= 2, latest_s=5)
    assert outcome.problems() == [], outcome.stderr
    assert KEPT in outcome.stderr
    kept = lines(out / journal)
    assert kept >= 1
    if argv is SWEEP:  # case 3: the results of the finished runs, written on the way out
        with (out / "results.csv").open(newline="") as handle:
            rows = list(csv.DictReader(handle))
        assert len(rows) == kept and {r["status"] for r in rows} == {"ok"}


# --- cases 5-6: a study keeps its finished repetitions and resumes them -----------------------
@pytest.mark.slow
def test_an_interrupted_study_resumes_to_the_files_of_an_uninterrupted_one(
    tmp_path: Path,
) -> None:
    out, reference = tmp_path / "out", tmp_path / "reference"
    process = start([*STUDY, "--out", out])
    outcome = signal_when(process, signal.SIGINT, lambda: _reps(out) >= 2, latest_s=5)
    assert outcome.problems() == [], outcome.stderr
    kept = _reps(out)
    assert 1 <= kept < 40, "the finished repetitions are kept, and the study was unfinished"
    assert cli.main([*STUDY, "--out", str(out)]) == 0
    assert _reps(out) == 40  # the kept ones were not run again
    assert cli.main([*STUDY, "--out", str(reference)]) == 0
    for name in ("runs.csv", "summary.md"):
        assert (out / name).read_bytes() == (reference / name).read_bytes(), name


# --- cases 7-9: the appearance study's pool -------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize(
    ("how", "to_group"),
    [(signal.SIGINT, True), (signal.SIGTERM, False)],
    ids=["ctrl-c-to-the-group", "sigterm-to-the-process"],
)
def test_the_appearance_study_stops_its_episodes_in_flight_within_seconds(
    tmp_path: Path, how: signal.Signals, to_group: bool
) -> None:
    out = tmp_path / "out"
    process = start([*APPEARANCE, "--out", out])
    outcome = signal_when(
        process, how, lambda: _episode_in_flight(out), after_s=0.5, latest_s=90, to_group=to_group
    )
    assert _episode_in_flight(out), "no episode was in flight when the signal came"
    assert outcome.problems() == [], outcome.stderr
    assert outcome.seconds < EXIT_WITHIN_S and KEPT in outcome.stderr


@pytest.mark.slow
def test_the_appearance_workers_die_with_their_parent(tmp_path: Path) -> None:
    out = tmp_path / "out"
    process = start([*APPEARANCE, "--out", out])
    outcome = signal_when(
        process, signal.SIGKILL, lambda: _episode_in_flight(out), latest_s=90, to_group=False
    )
    assert outcome.signalled and outcome.code == -signal.SIGKILL
    assert outcome.orphans == [], "spawn workers outlived their parent"


# --- case 10: a signal in teardown ------------------------------------------------------------
def _finished(out: Path) -> bool:
    try:
        return json.loads((out / "summary.json").read_text())["status"] == "finished"
    except (OSError, ValueError, KeyError):
        return False


@pytest.mark.slow
def test_sigterm_in_teardown_after_a_finished_summary_is_not_a_kill(tmp_path: Path) -> None:
    """SIGTERM sent every few milliseconds from the moment the summary reads ``finished``
    until the process is gone: whichever lands in teardown, the exit is 0 or 130."""
    out = tmp_path / "out"
    process = start([*EPISODE, "--no-video", "--out", out])
    deadline = time.monotonic() + 240
    while not _finished(out):
        assert process.poll() is None, process.output()[1]
        assert time.monotonic() < deadline
        time.sleep(0.002)
    sent = 0
    while process.poll() is None and sent < 20000:
        try:
            os.kill(process.pid, signal.SIGTERM)
        except ProcessLookupError:
            break
        sent += 1
        time.sleep(0.001)
    code = process.process.wait(timeout=30)
    stderr = process.output()[1]
    assert sent >= 1
    assert code in (0, 130), (code, stderr)
    assert "Traceback" not in stderr


# --- cases 11-12: started as a background job (SIGINT ignored) --------------------------------
@pytest.mark.slow
def test_an_episode_started_with_sigint_ignored_still_ends_on_sigterm(tmp_path: Path) -> None:
    out = tmp_path / "out"
    process = start(
        [*EPISODE, "--size", "160x120", "--fps", "10", "--out", out], sigint_ignored=True
    )
    outcome = signal_when(process, signal.SIGTERM, lambda: (out / "summary.json").exists())
    assert outcome.problems() == [], outcome.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "interrupted"


def test_a_sweep_started_with_sigint_ignored_still_ends_on_sigint(tmp_path: Path) -> None:
    out = tmp_path / "out"
    process = start([*SWEEP, "--out", out], sigint_ignored=True)
    outcome = signal_when(
        process, signal.SIGINT, lambda: lines(out / "runs.jsonl") >= 2, latest_s=30
    )
    assert outcome.problems() == [], outcome.stderr
    assert KEPT in outcome.stderr and (out / "results.csv").exists()
