"""``--seeds K``: K whole studies, each kept in seed_<n>/, and their headlines over seeds."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from pil.experiments.paper_comparison import training_figures
from pil.experiments.report import load_rows
from pil.experiments.stats import mean_ci
from robin_sim.cli.main import main

pytestmark = pytest.mark.slow  # three small studies, then the same again

SMALL = [
    "--reps",
    "3",
    "--tables",
    "2",
    "--rates",
    "0.4,1.0",
    "--systems",
    "pil,proactive,c1,c2",
    "--no-progress",
]


@pytest.fixture(scope="module")
def seeds(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("seeds")
    assert main(["study", "--seeds", "3", "--seed", "4", *SMALL, "--out", str(out)]) == 0
    return out


def test_each_seed_is_the_whole_study_of_that_seed(seeds: Path, tmp_path: Path) -> None:
    assert sorted(p.name for p in seeds.iterdir() if p.is_dir()) == ["seed_4", "seed_5", "seed_6"]
    assert main(["study", "--seed", "5", *SMALL, "--out", str(tmp_path)]) == 0
    for name in ("runs.csv", "tests.csv", "claim_runs.csv"):
        assert (seeds / "seed_5" / name).read_bytes() == (tmp_path / name).read_bytes()


def test_the_eight_figures_over_seeds_are_the_seeds_means(seeds: Path) -> None:
    with (seeds / "seeds.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 3 * 2 * 2  # seeds x rates x (gestures, actions)
    per_seed = {s: training_figures(load_rows(seeds / f"seed_{s}" / "runs.csv")) for s in (4, 5, 6)}
    for row in rows:
        ours = per_seed[int(row["seed"])][float(row["rate"])][row["measure"]]
        assert float(row["ours"]) == pytest.approx(ours)
    actions = [per_seed[s][0.4]["actions"] for s in (4, 5, 6)]
    mean, low, high = mean_ci(actions)
    text = (seeds / "summary.md").read_text()
    assert f"| 40 % | actions | {mean:.1f} [{low:.1f}, {high:.1f}] | 222 |" in text
    assert "## The paper's claim over seeds" in text
    assert "| test tables only; discarded corrected |" in text
    assert "## Proactive vs reactive PIL over seeds" in text


def test_comparisons_over_seeds_average_the_seeds_tests(seeds: Path) -> None:
    over = load_rows(seeds / "seeds_tests.csv")
    row = next(
        r
        for r in over
        if (r["measure"], r["reading"], r["rate"], r["system_b"])
        == ("actions", "test tables only", "0.4", "c1")
    )
    diffs = []
    for s in (4, 5, 6):
        (t,) = [
            t
            for t in load_rows(seeds / f"seed_{s}" / "tests.csv")
            if (t["measure"], t["reading"], t["rate"], t["system_b"], t["test"])
            == ("actions", "test tables only", "0.4", "c1", "paired t")
        ]
        diffs.append(float(t["mean_diff"]))
    assert float(row["mean_diff"]) == pytest.approx(mean_ci(diffs)[0])
    assert float(row["ci_low"]) == pytest.approx(mean_ci(diffs)[1])
    assert row["seeds"] == "3"


def test_a_finished_seed_is_reused_and_other_settings_refused(
    seeds: Path, capsys: pytest.CaptureFixture
) -> None:
    runs = seeds / "seed_4" / "runs.csv"
    before = runs.stat().st_mtime_ns
    assert main(["study", "--seeds", "3", "--seed", "4", *SMALL, "--out", str(seeds)]) == 0
    assert runs.stat().st_mtime_ns == before  # read back, not re-run
    summary = (seeds / "summary.md").read_text()
    other = [*SMALL[:3], "3", *SMALL[4:]]  # 3 tables instead of 2
    assert main(["study", "--seeds", "3", "--seed", "4", *other, "--out", str(seeds)]) == 2
    err = capsys.readouterr().err
    assert "seed_4 holds a study with other settings" in err and len(err.splitlines()) == 1
    assert (seeds / "summary.md").read_text() == summary and runs.stat().st_mtime_ns == before


@pytest.mark.parametrize("value", ["0", "x", "1001"])
def test_bad_seed_counts_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture, value: str) -> None:
    assert main(["study", "--seeds", value, *SMALL, "--out", str(tmp_path / "never")]) == 2
    assert "--seeds must be a whole number from 1 to 1000" in capsys.readouterr().err
    assert not (tmp_path / "never").exists()


def test_a_small_study_over_seeds(tmp_path: Path) -> None:
    argv = [
        "people",
        "--systems",
        "pil",
        "--reps",
        "3",
        "--rates",
        "1.0",
        "--tables",
        "4",
        "--seeds",
        "2",
        "--out",
        str(tmp_path),
        "--no-progress",
    ]
    assert main(argv) == 0
    for seed in (0, 1):
        assert (tmp_path / f"seed_{seed}" / "people.csv").is_file()
    over = load_rows(tmp_path / "seeds_tests.csv")
    diffs = [
        float(
            next(
                t
                for t in load_rows(tmp_path / f"seed_{s}" / "tests.csv")
                if t["measure"] == "actions" and t["test"] == "paired t"
            )["mean_diff"]
        )
        for s in (0, 1)
    ]
    row = next(r for r in over if r["measure"] == "actions")
    assert float(row["mean_diff"]) == pytest.approx(sum(diffs) / 2)
    assert "over 2 seeds" in (tmp_path / "seeds.md").read_text()
