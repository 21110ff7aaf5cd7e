"""The study's tests.csv: paired tests that match runs.csv, Holm over each family, and the
paper's claim read from those same corrected tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from scipy.stats import ttest_rel

from pil.experiments.report import load_rows
from pil.experiments.stats import PAIRED_T, WILCOXON, csv_columns
from pil.experiments.study_tests import READINGS, claim_markdown, claim_verdicts, study_tests
from robin_sim.cli.main import main

pytestmark = pytest.mark.slow  # a real study of 130 short runs


@pytest.fixture(scope="module")
def study(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real small study, run through the command line."""
    out = tmp_path_factory.mktemp("study")
    argv = [
        "study",
        "--reps",
        "10",
        "--tables",
        "3",
        "--rates",
        "0.4,1.0",
        "--out",
        str(out),
        "--no-progress",
    ]
    assert main(argv) == 0
    return out


def test_paired_p_values_equal_ttest_rel_on_runs_csv_matched_by_rep_and_rate(study: Path) -> None:
    runs = load_rows(study / "runs.csv")
    tests = load_rows(study / "tests.csv")
    assert list(tests[0]) == csv_columns(("rate",))
    column_of = {reading: column for column, reading in READINGS.items()}
    checked = 0
    for t in tests:
        key = (t["measure"], t["reading"])
        if t["test"] != PAIRED_T or key not in column_of or t["p"] == "nan":
            continue

        def side(system: str, t: dict = t, column: str = column_of[key]) -> dict[str, float]:
            return {
                r["rep"]: float(r[column])
                for r in runs
                if r["system"] == system and r["rate"] == t["rate"]
            }

        a, b = side(t["system_a"]), side(t["system_b"])
        reps = sorted(a, key=int)
        assert sorted(b, key=int) == reps and int(t["n"]) == len(reps) == 10
        expected = ttest_rel([a[k] for k in reps], [b[k] for k in reps])
        assert float(t["p"]) == pytest.approx(expected.pvalue, rel=1e-9)
        assert float(t["statistic"]) == pytest.approx(expected.statistic, rel=1e-9)
        assert t["pairing"] == "rep+seed"
        checked += 1
    assert checked >= 20


def test_holm_p_is_never_below_the_raw_p(study: Path) -> None:
    tests = load_rows(study / "tests.csv")
    testable = [t for t in tests if t["p"] != "nan"]
    assert len(testable) > 40 and {t["test"] for t in testable} == {PAIRED_T, WILCOXON}
    assert all(float(t["p_holm"]) >= float(t["p"]) for t in testable)
    assert any(float(t["p_holm"]) > float(t["p"]) for t in testable)


def test_the_summary_names_the_test_and_the_pairing(study: Path) -> None:
    text = (study / "summary.md").read_text()
    assert "Tests: paired t, wilcoxon signed-rank; samples paired by rep+seed" in text
    assert "Holm's correction over each test, reading and pair of systems" in text
    assert "| paired t | 10 | rep+seed |" in text and "| welch t |" not in text


def test_the_claim_section_follows_the_corrected_tests(study: Path) -> None:
    tests = [dict(t) for t in load_rows(study / "tests.csv")]
    text = (study / "summary.md").read_text()
    claim = text.split("## The paper's claim")[1].split("## Paired tests")[0]
    assert claim_markdown(tests, "repeated") in claim  # built from the rows of tests.csv
    reading = "test tables only; discarded corrected"
    held, tried = claim_verdicts(tests)[reading]
    assert tried == 4 and held > 0  # 40 %: gestures and actions, vs c1 and c2
    # the raw p of a comparison stays, its Holm-adjusted p crosses 0.05: the verdict follows
    target = next(
        t
        for t in tests
        if t["reading"] == reading
        and t["test"] == PAIRED_T
        and float(t["p_holm"]) < 0.05
        and float(t["mean_diff"]) > 0
    )
    target["p_holm"] = "0.06"
    assert claim_verdicts(tests)[reading] == (held - 1, tried)
    assert float(target["p"]) < 0.05


def test_a_study_without_pil_has_no_tests() -> None:
    rows = [{"system": "c1", "rate": 1.0, "rep": 0, "seed": 1, **dict.fromkeys(READINGS, 1)}]
    assert study_tests(rows) == []


def test_pil_vs_c2_gets_the_same_holm_p_whichever_other_systems_ran() -> None:
    """The family is declared by the pair (pil, c2), not built from what ran."""
    from learner_rows import learner_row

    from pil.experiments.study import rep_seeds
    from pil.experiments.study_tests import study_tests

    rows = [
        {**learner_row(system, rate, seed, tables=1), "rep": rep}
        for rep, seed in enumerate(rep_seeds(0, 5))
        for rate in (0.4, 0.6)
        for system in ("pil", "c1", "c2", "c3")
    ]

    def holm_of(systems: set[str]) -> dict[tuple[str, str, str, str], float]:
        found = study_tests([r for r in rows if r["system"] in systems])
        return {
            (t["reading"], t["rate"], t["measure"], t["test"]): t["p_holm"]
            for t in found
            if t["system_b"] == "c2"
        }

    small, large = holm_of({"pil", "c2"}), holm_of({"pil", "c1", "c2", "c3"})
    assert small == large and len(small) == 16
