"""Tests of ``robin-pil report``: summary, Welch t-tests and figures, grouped by the grid."""

from __future__ import annotations

import csv
import statistics
from pathlib import Path

import pytest
from scipy.stats import ttest_rel

from pil.experiments.results_report import grid_axes, with_physical, write_report
from pil.experiments.sweep_exec import execute_run
from pil.experiments.sweep_grid import build_grid
from pil.experiments.sweep_kinds import load_kind
from pil.experiments.sweep_store import RunStore, make_record, rows_to_csv
from robin_sim.cli import main as cli

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    """A real sweep's results.csv (learner runs executed in this process, written by the store)."""
    target = load_kind("learner")
    grid = build_grid(
        target, systems=["pil", "c1"], rates=[0.6, 1.0], reps=3, params=["discard=0,0.3"], tables=1
    )
    runs = grid.runs()
    directory = tmp_path_factory.mktemp("sweep")
    with RunStore(directory, {"kind": "learner"}) as store:
        for spec in runs:
            store.append(make_record(spec.columns(), execute_run(target.run, spec.spec), 1))
        return store.write_results([s.run_id for s in runs], list(runs[0].columns()))


def read(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


@pytest.mark.slow
def test_report_follows_the_grid(results, tmp_path) -> None:
    written = write_report(results, tmp_path)
    summary = (tmp_path / "summary.md").read_text()
    assert "24 runs summarised; 0 failed runs left out." in summary
    assert "| rate | discard | system | n | total_gestures | total_actions |" in summary
    rows = read(results)
    cell = [
        float(r["total_gestures"])
        for r in rows
        if (r["rate"], r["discard"], r["system"]) == ("0.6", "0.3", "c1")
    ]
    mean, sd = statistics.fmean(cell), statistics.stdev(cell)
    assert f"| 0.6 | 0.3 | c1 | 3 | {mean:.1f} ± {sd:.1f} |" in summary
    assert "## Paired tests: pil against each other system" in summary
    assert "samples paired by rep+seed" in summary
    tests = read(tmp_path / "tests.csv")
    assert len(tests) == 2 * 2 * 4 * 2  # rates x discard values x metrics x (t, Wilcoxon)
    assert {(t["system_a"], t["system_b"], t["pairing"]) for t in tests} == {
        ("pil", "c1", "rep+seed")
    }
    assert list(tests[0])[:4] == ["measure", "reading", "rate", "discard"]
    checked = 0
    for t in tests:  # the sweep's systems of one cell and repetition share the seed: paired
        if t["test"] != "paired t" or t["p"] == "nan":
            continue
        column = {
            ("gestures", "training included"): "total_gestures",
            ("actions", "training included"): "total_actions",
        }.get((t["measure"], t["reading"]), t["measure"])

        def side(system: str, t: dict = t, column: str = column) -> list[float]:
            cell = [
                r
                for r in rows
                if (r["rate"], r["discard"], r["system"]) == (t["rate"], t["discard"], system)
            ]
            return [float(r[column]) for r in sorted(cell, key=lambda r: int(r["rep"]))]

        assert float(t["p"]) == pytest.approx(ttest_rel(side("pil"), side("c1")).pvalue)
        assert float(t["p_holm"]) >= float(t["p"])
        checked += 1
    assert checked >= 4
    figures = [p for p in written if p.suffix == ".png"]
    assert len(figures) == 4 * 2  # one per metric and discard value
    assert tmp_path / "total_gestures_discard=0.3.png" in figures
    assert all(p.read_bytes().startswith(PNG) and p.stat().st_size > 1000 for p in figures)


def test_report_command_writes_next_to_the_csv_by_default(results, monkeypatch, capsys):
    monkeypatch.setattr(cli, "COMMANDS", {"report": cli.COMMANDS["report"]})
    assert cli.main(["report", str(results)]) == 0
    listed = capsys.readouterr().out.split()
    assert str(results.parent / "report" / "summary.md") in listed
    assert cli.main(["report", str(results.parent / "missing.csv")]) == 2
    assert "missing.csv: cannot read the results" in capsys.readouterr().err


def test_failed_runs_are_listed_and_left_out(results, tmp_path) -> None:
    rows = read(results)
    rows[0].update(status="failed", error="RuntimeError: boom", total_gestures="")
    broken = tmp_path / "results.csv"
    broken.write_text(rows_to_csv(rows, list(rows[0])))
    write_report(broken, tmp_path / "report")
    summary = (tmp_path / "report" / "summary.md").read_text()
    assert "23 runs summarised; 1 failed runs left out." in summary
    assert f"- `{rows[0]['run_id']}`: RuntimeError: boom" in summary


def test_physical_runs_get_delivered_fraction_and_failures(tmp_path) -> None:
    columns = [
        "run_id",
        "system",
        "rate",
        "tables",
        "rep",
        "seed",
        "status",
        "error",
        "total_gestures",
        "total_actions",
        "legs",
        "legs_delivered",
        "physical_failures",
    ]
    rows = []
    for rate, delivered in (("0.6", (6, 7)), ("1.0", (8, 8))):
        for system in ("pil", "c1"):
            for rep, legs_delivered in enumerate(delivered):
                rows.append(
                    dict(
                        zip(
                            columns,
                            [
                                f"{system}|rate={rate}|rep={rep}",
                                system,
                                rate,
                                "2",
                                rep,
                                1,
                                "ok",
                                "",
                                10 + rep,
                                12 + rep,
                                8,
                                legs_delivered,
                                8 - legs_delivered,
                            ],
                            strict=True,
                        )
                    )
                )
    path = tmp_path / "results.csv"
    path.write_text(rows_to_csv(rows, columns))
    write_report(path, tmp_path / "report")
    summary = (tmp_path / "report" / "summary.md").read_text()
    assert "## Physical outcome per rate" in summary
    assert "| rate | system | n | legs_delivered_percent | physical_failures |" in summary
    assert "| 0.6 | pil | 2 | 81.2 ± 8.8 | 1.5 ± 0.7 |" in summary  # 6/8 and 7/8 delivered
    assert "| 1.0 | c1 | 2 | 100.0 ± 0.0 | 0.0 ± 0.0 |" in summary
    assert (tmp_path / "report" / "legs_delivered_percent.png").read_bytes().startswith(PNG)
    percents = [r["legs_delivered_percent"] for r in with_physical(rows)]
    assert percents[:2] == [75.0, 87.5]  # 6 and 7 of 2 tables x 4 legs
    rows[0]["legs_per_table"] = "3"  # a swept legs_per_table: 6 of 2 x 3 legs
    assert with_physical(rows[:1])[0]["legs_delivered_percent"] == 100.0
    own = {"legs_delivered": "1", "legs_delivered_fraction": "0.5"}  # no tables column
    assert with_physical([own])[0]["legs_delivered_percent"] == 50.0
    total = {**rows[0], "legs_total": "12"}  # the run's own count of legs wins
    assert with_physical([total])[0]["legs_delivered_percent"] == 50.0


def test_grid_axes_of_a_study_csv_are_the_rate_only() -> None:
    assert grid_axes([{"system": "pil", "rate": "0.6", "discard": "0.3"}]) == ["rate"]
    sweep = [
        {
            "run_id": "a",
            "system": "pil",
            "rate": "0.6",
            "tables": "1",
            "x": str(i),
            "rep": "0",
            "seed": "1",
        }
        for i in range(2)
    ]
    assert grid_axes(sweep) == ["rate", "x"]  # tables takes one value: not an axis
