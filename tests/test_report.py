"""Generic summaries, tests between systems and bar charts over rows read back from a CSV."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import matplotlib.image
import pytest
from scipy.stats import ttest_ind

from pil.experiments.figures import plot_comparison, plot_metric
from pil.experiments.report import (
    ReportError,
    load_rows,
    summarize,
    summary_markdown,
)
from pil.experiments.stats import WELCH, compare
from pil.experiments.stats import tests_markdown as table_of_tests  # not a test: renamed

DATA = {  # (system, discard) -> legs delivered in four runs
    ("pil", "0.1"): [40, 38, 39, 41],
    ("c1", "0.1"): [30, 31, 29, 30],
    ("pil", "0.3"): [35, 36, 34, 35],
    ("c1", "0.3"): [35, 36, 34, 35],
}


@pytest.fixture
def results(tmp_path: Path) -> Path:
    path = tmp_path / "results.csv"
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["system", "discard", "legs", "video"])
        for (system, discard), values in DATA.items():
            for i, v in enumerate(values):
                writer.writerow([system, discard, v, f"run{i}.mp4"])
    return path


def test_summary_over_any_grouping_column(results: Path) -> None:
    rows = load_rows(results)
    assert rows[0]["legs"] == "40"  # strings, as read back
    stats = summarize(rows, ("discard", "system"), ("legs",))
    assert [(s["discard"], s["system"]) for s in stats] == [
        ("0.1", "pil"),
        ("0.1", "c1"),
        ("0.3", "pil"),
        ("0.3", "c1"),
    ]  # numbers by value, text in the order first seen
    pil = stats[0]
    assert pil["n"] == 4 and pil["legs_mean"] == 39.5
    assert math.isclose(pil["legs_sd"], 1.2909944, rel_tol=1e-6)
    text = summary_markdown(rows, ("discard", "system"), ("legs",))
    assert "| 0.1 | pil | 4 | 39.5 ± 1.3 |" in text


def test_rows_without_a_pairing_key_get_welch_tests_matching_scipy(results: Path) -> None:
    rows = load_rows(results)  # no rep column: nothing pairs the runs
    tests = compare(rows, "pil", compare_by="system", within=("discard",), metrics=("legs",))
    assert len(tests) == 2 and {t["test"] for t in tests} == {WELCH}
    expected = ttest_ind(DATA[("pil", "0.1")], DATA[("c1", "0.1")], equal_var=False)
    assert tests[0]["discard"] == "0.1" and tests[0]["system_b"] == "c1"
    assert tests[0]["pairing"] == "none"
    assert math.isclose(tests[0]["p"], expected.pvalue)
    assert math.isclose(tests[0]["statistic"], expected.statistic)
    assert tests[1]["discard"] == "0.3" and math.isclose(tests[1]["p"], 1.0)  # same data
    table = table_of_tests(tests, ("discard",))
    assert " *" in table.splitlines()[2]  # Holm-adjusted p < 0.05 at discard 0.1


def test_identical_constant_groups_give_no_p_value() -> None:
    rows = [
        {"system": s, "rate": "1.0", "rep": str(i), "g": "220"}
        for s in ("pil", "c1")
        for i in range(3)
    ]
    tests = compare(rows, "pil", metrics=("g",))
    assert all(math.isnan(t["p"]) for t in tests)
    assert "n/a" in table_of_tests(tests)


def test_bad_columns_and_baseline_are_named(results: Path) -> None:
    rows = load_rows(results)
    with pytest.raises(ReportError, match="unknown column 'lgs'; valid choices: system"):
        summarize(rows, ("system",), ("lgs",))
    with pytest.raises(ReportError, match="baseline 'c9' not found"):
        compare(rows, "c9", within=("discard",), metrics=("legs",))
    with pytest.raises(ReportError, match=r"holds 'run0\.mp4', not a number"):
        summarize(rows, ("system",), ("video",))
    with pytest.raises(ReportError, match="cannot read"):
        load_rows(results.parent / "missing.csv")


def test_plots_are_valid_pngs(results: Path, tmp_path: Path) -> None:
    rows = load_rows(results)
    path = plot_metric(rows, "legs", tmp_path / "figs" / "legs.png", ("discard", "system"))
    image = matplotlib.image.imread(path)
    assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100
    assert image[..., :3].std() > 0.01  # not a blank canvas
    other = plot_comparison(
        {"40 %": {"gestures": 169.0, "actions": 190.0}},
        {"40 %": {"gestures": 170.0, "actions": 222.0}},
        tmp_path / "cmp.png",
    )
    assert matplotlib.image.imread(other).shape[2] in (3, 4)
    assert not list(tmp_path.rglob("*.partial"))
