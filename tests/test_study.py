"""The study: reproducible runs.csv, summary with t-tests and training figures, figures."""

from __future__ import annotations

from pathlib import Path

import matplotlib.image
import pytest

from pil.errors import RobinPilError
from pil.experiments.report import load_rows
from pil.experiments.study import (
    PAPER_TRAINING,
    STUDY_COLUMNS,
    StudyConfig,
    rep_seeds,
    run_study,
    training_figures,
    write_outputs,
)

SMALL = StudyConfig(rates=(0.6, 1.0), reps=2, params={"tables": 2})


def test_same_seed_gives_a_byte_identical_runs_csv(tmp_path: Path) -> None:
    first = write_outputs(run_study(SMALL), SMALL, tmp_path / "a")
    second = write_outputs(run_study(SMALL), SMALL, tmp_path / "b")
    assert first[0].name == "runs.csv"
    assert first[0].read_bytes() == second[0].read_bytes()
    other = StudyConfig(rates=(0.6, 1.0), reps=2, seed=1, params={"tables": 2})
    write_outputs(run_study(other), other, tmp_path / "c")
    assert (tmp_path / "c" / "runs.csv").read_bytes() != first[0].read_bytes()


def test_outputs_are_written_and_readable(tmp_path: Path) -> None:
    rows = run_study(SMALL)
    assert len(rows) == SMALL.runs() == 2 * 2 * 5
    written = write_outputs(rows, SMALL, tmp_path)
    assert {p.name for p in written} == {
        "runs.csv",
        "claim_runs.csv",
        "tests.csv",
        "summary.md",
        "gestures.png",
        "actions.png",
        "training.png",
    }
    back = load_rows(tmp_path / "runs.csv")
    assert list(back[0]) == list(STUDY_COLUMNS) and len(back) == 20
    summary = (tmp_path / "summary.md").read_text()
    assert "## Paired tests" in summary and "paired t, wilcoxon signed-rank" in summary
    assert "| gestures | training included | 0.6 | pil | c1 | paired t | 2 | rep+seed |" in summary
    assert "| 100 % | 110.0 ± 0.0 | 111 | -0.9 % |" in summary
    for name in ("gestures.png", "actions.png", "training.png"):
        assert matplotlib.image.imread(tmp_path / name).shape[0] > 100
    assert not list(tmp_path.glob("*.partial"))


def test_training_figures_count_each_training_run_once() -> None:
    rows = run_study(SMALL)
    figures = training_figures(rows)
    assert set(figures) == {0.6, 1.0}
    assert figures[1.0]["gestures"] == 110 and figures[1.0]["n"] == 2
    assert set(PAPER_TRAINING) == {0.4, 0.6, 0.8, 1.0}


def test_rep_seeds_are_distinct_and_reproducible() -> None:
    seeds = rep_seeds(0, 20)
    assert len(set(seeds)) == 20 and seeds == rep_seeds(0, 20) and seeds != rep_seeds(1, 20)


def test_bad_config_is_rejected() -> None:
    with pytest.raises(RobinPilError, match="detection rate"):
        StudyConfig(rates=(1.5,))
    with pytest.raises(RobinPilError, match="unknown system"):
        StudyConfig(systems=("pil", "c9"))
    with pytest.raises(RobinPilError, match="reps"):
        StudyConfig(reps=0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"seed": -1}, "seed must be a whole number from 0 to"),
        ({"rates": (0.4, 0.4)}, "given twice"),
    ],
)
def test_study_config_refuses_bad_seeds_and_duplicate_rates(kwargs: dict, message: str) -> None:
    with pytest.raises(RobinPilError, match=message):
        StudyConfig(**kwargs)


def test_default_rule_puts_all_eight_training_figures_within_10_percent() -> None:
    from pil.experiments.paper_comparison import worst_difference
    from pil.experiments.study import training_by_rule

    by_rule = training_by_rule(StudyConfig())  # the paper's setup: 20 reps, seed 0
    assert list(by_rule) == ["next-best", "avoid-last", "with-replacement", "untried-first"]
    assert worst_difference(by_rule["next-best"]) < 10.0
    assert worst_difference(by_rule["untried-first"]) > 10.0  # actions 14-19 % short
    assert all(f[1.0]["gestures"] == 110 for f in by_rule.values())


def test_summary_compares_every_rule_and_checks_the_claim_both_ways(tmp_path: Path) -> None:
    config = StudyConfig(rates=(0.4, 1.0), reps=3, params={"tables": 2})
    rows = run_study(config)
    write_outputs(rows, config, tmp_path)
    text = (tmp_path / "summary.md").read_text()
    assert "**next-best** (used)" in text
    for rule in ("avoid-last", "with-replacement", "untried-first"):
        assert f"| {rule} |" in text
    for discarded in ("repeated", "corrected"):  # the study's reading and the re-run one
        assert f"- training included; discarded {discarded}: PIL costlier" in text
        assert f"- test tables only; discarded {discarded}: PIL costlier" in text
    assert (tmp_path / "claim_runs.csv").exists()
