"""The transfer study (robin-pil transfer): tidying from scratch vs from the assembly's table."""

from __future__ import annotations

import statistics
from pathlib import Path

from pil.experiments.transfer import run_transfer_study
from pil.task.scenario import load_scenario
from robin_sim.cli.main import main


def _mean(rows: list[dict], system: str, start: str, column: str) -> float:
    return statistics.fmean(r[column] for r in rows if (r["system"], r["start"]) == (system, start))


def test_transferred_table_saves_actions_but_pays_for_the_changed_meaning() -> None:
    tidy = load_scenario("tidy")
    assert [t.name for t in tidy.types] == ["T1", "T2", "T3", "T4"]
    rows = run_transfer_study(rates=(1.0,), reps=5)
    assert _mean(rows, "pil", "table", "actions") < _mean(rows, "pil", "scratch", "actions")
    assert _mean(rows, "pil-halve", "table", "rejected") < _mean(rows, "pil", "table", "rejected")
    # the assembly taught give me -> human; in T4 (10 of the 40 tidy handovers) it means
    # location, and about 24 approvals from the assembly are not overturned in 10: a refusal each
    for row in rows:
        if (row["system"], row["start"]) == ("pil", "table"):
            assert row["rejected"] >= 10 and row["transferred_approvals"] > 200
    scratch = [r for r in rows if r["start"] == "scratch"]
    assert all(r["transferred_approvals"] == 0 for r in scratch)


def test_transfer_command_from_its_own_saved_table(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    first = tmp_path / "first"
    argv = ["transfer", "--systems", "pil", "--reps", "2", "--rates", "1.0", "--no-progress"]
    assert main([*argv, "--out", str(first)]) == 0
    assert {p.name for p in first.iterdir()} == {
        "transfer.csv",
        "transfer.md",
        "transfer.png",
        "tests.csv",
        "assembly_table.json",
    }
    assert (
        "| actions | - | 1.0 | pil | scratch | table | paired t | 2 | rep+seed |"
        in (first / "transfer.md").read_text()
    )
    second = tmp_path / "second"
    assert main([*argv, "--table", str(first / "assembly_table.json"), "--out", str(second)]) == 0
    assert "the saved table" in (second / "transfer.md").read_text()
    assert not (second / "assembly_table.json").exists()
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    assert main([*argv, "--table", str(bad), "--out", str(tmp_path / "never")]) == 2
    assert main([*argv[:2], "tamer", "--out", str(tmp_path / "never")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert "not valid JSON" in err[-2] and "this study runs PIL learners" in err[-1]
    assert not (tmp_path / "never").exists()
