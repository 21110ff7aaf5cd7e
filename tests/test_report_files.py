"""``robin-pil report`` on hostile files: every bad number refused before anything is written,
session folders without a readable summary listed, an unwritable --out one clear line."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest
from test_sessions_report import summary, write

from robin_sim.cli.main import main

GOOD = "system,rate,gestures,actions\npil,1.0,3,4\nc1,1.0,4,6\npil,1.0,3,5\nc1,1.0,5,6\n"


def refused(argv: list[str], capsys: pytest.CaptureFixture[str], *needles: str) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("robin-pil report: error: "), err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


@pytest.mark.parametrize(
    ("cell", "column"),
    [
        ("nan", "gestures"),
        ("inf", "gestures"),
        ("-inf", "actions"),
        ("9" * 400, "gestures"),
        ("1e400", "actions"),
        ("abc", "rate"),
    ],
)
def test_a_bad_csv_cell_is_refused_and_nothing_is_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], cell: str, column: str
) -> None:
    rows = GOOD.splitlines()
    header = rows[0].split(",")
    cells = rows[2].split(",")
    cells[header.index(column)] = cell
    results = tmp_path / "results.csv"
    results.write_text("\n".join([rows[0], rows[1], ",".join(cells), *rows[3:]]) + "\n")
    out = tmp_path / "report"
    refused(["report", str(results), "--out", str(out)], capsys, repr(column))
    assert not out.exists()  # no empty folder, no summary.md of a refused file


def test_a_good_csv_still_reports(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    results = tmp_path / "results.csv"
    results.write_text(GOOD)
    assert main(["report", str(results), "--out", str(tmp_path / "r")]) == 0
    assert "pil" in (tmp_path / "r" / "summary.md").read_text()


def test_an_unwritable_or_too_long_out_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    results = tmp_path / "results.csv"
    results.write_text(GOOD)
    for out in ("/proc/robin-pil-x", str(tmp_path / ("x" * 300)), str(results / "sub")):
        refused(["report", str(results), "--out", out], capsys, "--out")


@pytest.mark.parametrize("text", ["NaN", "Infinity", "-Infinity", "9" * 400, "9" * 5000])
def test_a_bad_number_in_a_session_summary_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str
) -> None:
    write(tmp_path / "live", summary("P01", "s1", "pil", {}))
    path = write(tmp_path / "live", summary("P02", "s1", "pil", {}))
    path.write_text(path.read_text().replace('"gestures": 14', f'"gestures": {text}'))
    out = tmp_path / "report"
    refused(["report", str(tmp_path / "live"), "--out", str(out)], capsys, "P02")
    assert not out.exists()


def test_dangling_and_killed_sessions_are_listed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    live = tmp_path / "live"
    for k, condition in enumerate(["pil", "pil", "proactive", "proactive"]):
        write(live, summary(f"P0{k}", "s1", condition, {"gestures": 10 + k}))
    dangling = live / "P05" / "s1"
    dangling.mkdir(parents=True)
    (dangling / "summary.json").symlink_to(tmp_path / "gone.json")
    killed = live / "P06" / "s1"
    killed.mkdir(parents=True)
    (killed / "inputs.jsonl").write_text(json.dumps({"t": 0}) + "\n")
    out = tmp_path / "report"
    assert main(["report", str(live), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "P05/s1" in err and "does not exist" in err
    assert "P06/s1" in err and "killed" in err
    report = (out / "report.md").read_text()
    assert "## Not reported" in report and "`P05/s1`" in report and "`P06/s1`" in report


def test_a_device_or_fifo_as_results_is_refused_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fifo = tmp_path / "results.csv"
    os.mkfifo(fifo)
    started = time.monotonic()
    for path in ("/dev/zero", str(fifo)):
        refused(["report", path, "--out", str(tmp_path / "r")], capsys, "not a regular file")
    assert time.monotonic() - started < 10
    assert not (tmp_path / "r").exists()


def test_a_folder_of_killed_sessions_only_says_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    killed = tmp_path / "live" / "P01" / "s1"
    killed.mkdir(parents=True)
    (killed / "inputs.jsonl").write_text("{}\n")
    refused(["report", str(tmp_path / "live")], capsys, "nothing to report", "P01/s1", "killed")


# --- files found inside the folder (issue 26): each refused with one line naming it, at once


def _live_with_answers(root: Path, scores: dict[str, object] | None = None) -> Path:
    """Two sessions of two conditions, each with a questionnaires.jsonl beside its summary."""
    for participant, condition in (("P01", "pil"), ("P02", "proactive")):
        path = write(root, summary(participant, "s1", condition, {}))
        entry = {
            "participant": participant,
            "condition": condition,
            "questionnaire": "trust",
            "kind": "likert",
            "answers": {"q1": 4},
            "scores": {"q1": 4, "mean": 4.0},
            "ranges": {"q1": [1, 5], "mean": [1, 5]},
        }
        (path.parent / "questionnaires.jsonl").write_text(json.dumps(entry) + "\n")
    if scores is not None:
        answers = root / "P02" / "s1" / "questionnaires.jsonl"
        entry = json.loads(answers.read_text())
        answers.write_text(json.dumps({**entry, "scores": scores}) + "\n")
    return root / "P02" / "s1"


@pytest.mark.parametrize("name", ["summary.json", "questionnaires.jsonl"])
def test_a_file_inside_the_folder_linked_to_dev_zero_is_refused_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str
) -> None:
    session = _live_with_answers(tmp_path / "live")
    (session / name).unlink()
    (session / name).symlink_to("/dev/zero")
    started = time.monotonic()
    out = tmp_path / "report"
    refused(["report", str(tmp_path / "live"), "--out", str(out)], capsys, name, "regular file")
    assert time.monotonic() - started < 5  # it read nothing (before: 6.5 GB in 10 s)
    assert not out.exists()


@pytest.mark.parametrize("name", ["summary.json", "questionnaires.jsonl"])
def test_a_fifo_inside_the_folder_does_not_hang_the_report(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str
) -> None:
    import threading

    session = _live_with_answers(tmp_path / "live")
    (session / name).unlink()
    os.mkfifo(session / name)
    codes: list[int] = []
    argv = ["report", str(tmp_path / "live"), "--out", str(tmp_path / "report")]
    worker = threading.Thread(target=lambda: codes.append(main(argv)), daemon=True)
    worker.start()
    worker.join(10)
    hung = worker.is_alive()
    if hung:  # release the blocked open, so that the test run goes on
        with open(session / name, "w") as writer:
            writer.write("{}")
        worker.join(10)
    assert not hung, "the report blocked on a FIFO"
    assert codes == [2]
    assert "not a regular file" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("scores", "needle"),
    [
        ({"q1": 999, "mean": 4.0}, "'q1' is 999, outside its scale 1 to 5"),
        ({"q1": 4, "mean": float("nan")}, "NaN"),
        ({"q1": 4, "mean": "4"}, "'mean' is '4', not a number"),
    ],
)
def test_a_score_off_its_scale_or_not_a_number_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], scores: dict[str, object], needle: str
) -> None:
    _live_with_answers(tmp_path / "live", scores)
    out = tmp_path / "report"
    refused(["report", str(tmp_path / "live"), "--out", str(out)], capsys, "P02", needle)
    assert not out.exists()  # the sessions report is not written either


def test_good_answers_are_reported(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    _live_with_answers(tmp_path / "live")
    assert main(["report", str(tmp_path / "live"), "--out", str(tmp_path / "r")]) == 0
    assert "| trust | q1 |" in (tmp_path / "r" / "questionnaires.md").read_text()


def test_a_results_csv_with_every_row_twice_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    header = "run_id,system,rate,rep,seed,total_gestures,total_actions\n"
    body = "".join(
        f"{system}-r{rep},{system},1.0,{rep},{rep},{10 + rep + (system == 'c1')},{20 + rep}\n"
        for rep in range(3)
        for system in ("pil", "c1")
    )
    results = tmp_path / "results.csv"
    results.write_text(header + body)
    assert main(["report", str(results), "--out", str(tmp_path / "ok")]) == 0
    results.write_text(header + body + body)
    out = tmp_path / "report"
    refused(["report", str(results), "--out", str(out)], capsys, "pil-r0", "appears twice")
    assert not out.exists()
    study = tmp_path / "runs.csv"  # a study's rows have no run_id: system, rate, rep, seed
    study.write_text("rep,system,rate,seed,total_gestures,total_actions\n0,pil,1.0,7,3,4\n" * 2)
    refused(["report", str(study), "--out", str(out)], capsys, "rep=0", "appears twice")


def test_the_same_session_in_two_folders_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import shutil

    session = _live_with_answers(tmp_path / "live")
    shutil.copytree(session, session.parent / "s1-copy")
    refused(["report", str(tmp_path / "live")], capsys, "s1-copy", "P02/s1")


@pytest.mark.parametrize("kind", ["dev-zero", "fifo"])
def test_the_study_registry_and_the_sweep_store_read_no_device(tmp_path: Path, kind: str) -> None:
    from pil.experiments.sweep_store import (
        JOURNAL,
        MANIFEST,
        RunStore,
        SweepStoreError,
        read_journal,
    )
    from robin_sim.lab.registry import Registry, RegistryError

    def hostile(path: Path) -> Path:
        path.parent.mkdir(parents=True, exist_ok=True)
        os.mkfifo(path) if kind == "fifo" else path.symlink_to("/dev/zero")
        return path

    started = time.monotonic()
    hostile(tmp_path / "study" / "registry.json")
    with pytest.raises(RegistryError, match="not a regular file"):
        Registry(tmp_path / "study", "s").entries()
    with pytest.raises(SweepStoreError, match="not a regular file"):
        read_journal(hostile(tmp_path / "sweep" / JOURNAL))
    hostile(tmp_path / "sweep2" / MANIFEST)
    with (
        pytest.raises(SweepStoreError, match="not a regular file"),
        RunStore(tmp_path / "sweep2", {"kind": "x"}),
    ):
        pass
    assert time.monotonic() - started < 5
