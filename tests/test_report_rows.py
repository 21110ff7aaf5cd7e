"""``robin-pil report`` refuses a results CSV whose rows are not whole runs (issue 39)."""

from __future__ import annotations

from pathlib import Path

import pytest

from robin_sim.cli.main import main

HEADER = "rep,system,rate,seed,gestures,actions,total_gestures,total_actions\n"
ROW = "{rep},{system},0.8,{seed},20,30,20,{actions}\n"


def results(tmp_path: Path, last: str = "", actions: str = "30") -> Path:
    rows = [
        ROW.format(rep=rep, system=system, seed=rep, actions=actions if rep == 1 else 30)
        for rep in range(3)
        for system in ("pil", "c1")
    ]
    path = tmp_path / "runs.csv"
    path.write_text(HEADER + "".join(rows) + last, encoding="utf-8")
    return path


def refused(path: Path, capsys: pytest.CaptureFixture[str], needle: str) -> None:
    out = path.parent / "report"
    assert main(["report", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert needle in err, err
    assert not out.exists()


def test_whole_rows_make_a_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", str(results(tmp_path)), "--out", str(tmp_path / "report")]) == 0
    assert (tmp_path / "report" / "summary.md").exists()


def test_a_last_row_cut_in_half_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    refused(results(tmp_path, "3,pil,0.8,3,2"), capsys, "line 8 has 5 of the header's 8 cells")


def test_a_row_with_an_extra_cell_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    refused(results(tmp_path, "3,pil,0.8,3,20,30,20,30,9\n"), capsys, "line 8 has 9 cells")


def test_a_negative_count_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    refused(results(tmp_path, actions="-50"), capsys, "'-50'; a run's total_actions")


def test_a_file_that_is_no_results_csv_is_named(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "passwd.csv"
    path.write_text("root:x:0:0:root:/root:/bin/bash\nbin:x:1:1:bin:/bin:/sbin/nologin\n")
    refused(path, capsys, "not a results CSV: no 'system' column")
