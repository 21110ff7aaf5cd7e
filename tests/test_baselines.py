"""``robin-pil baselines``: held-out tuning seeds, the table, and its paired tests."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest
from scipy.stats import ttest_rel

from pil.experiments.baseline_grid import (
    SAME_WITH_MEMORY,
    Score,
    Setting,
    at_edge,
    choose_best,
    grid,
    pil_references,
    score,
    split_seeds,
)
from pil.experiments.study import rep_seeds
from pil.exploration import RULES
from robin_sim.cli.main import main


def _read(path: Path) -> list[dict[str, str]]:
    with path.open(newline="") as handle:
        return list(csv.DictReader(handle))


@pytest.mark.parametrize("seed", [0, 1, 12345])
def test_tuning_seeds_are_disjoint_from_the_evaluation_seeds(seed: int) -> None:
    tuning, evaluation = split_seeds(seed, 40, 20)
    assert evaluation == rep_seeds(seed, 20)  # the seeds of robin-pil study --seed SEED
    assert len(set(tuning)) == 40 and not set(tuning) & set(rep_seeds(seed, 500))
    assert split_seeds(seed, 10, 5)[0] == tuning[:10]  # more reps extend, never reshuffle


def test_the_grid_and_the_choice_of_the_best() -> None:
    names = {learner: [s.name for s in grid(learner)] for learner in ("pil", "bandit", "tamer")}
    assert names["bandit"][:3] == ["eps=0,prior=-1.5", "eps=0,prior=-0.9", "eps=0,prior=-0.5"]
    assert "eps=0.1/(1+t/5)+memory" in names["bandit"] and len(names["bandit"]) == 58
    assert names["tamer"][:2] == ["step=0.02", "step=0.05"] and len(names["tamer"]) == 12
    for v in names.values():
        assert sum(n.endswith("+memory") for n in v) == len(v) // 2
    assert len(pil_references()) == 2 * len(RULES) - len(SAME_WITH_MEMORY)
    a, b, c = (Setting("tamer", n) for n in "abc")
    stuck = score(b, [{"total_actions": 200, "total_gestures": 240}] * 3, caps=[22000.0])
    assert stuck.stuck == 1 and stuck.actions == pytest.approx((3 * 200 + 22000) / 4)
    scores = [Score(a, 40, 0, 300.0, 9, 250.0), stuck, Score(c, 40, 0, 300.0, 9, 249.0)]
    assert choose_best(scores).setting is c  # b counts its stuck run at the cap; a, c tie
    tamer = grid("tamer")
    assert at_edge(next(s for s in tamer if s.name == "step=0.02+memory"), tamer) == [
        "step_size=0.02"
    ]
    assert at_edge(next(s for s in tamer if s.name == "step=0.1+memory"), tamer) == []


@pytest.mark.slow
def test_the_command_writes_its_table_and_its_p_values_are_scipys(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    out = tmp_path / "baselines"
    argv = ["--reps", "4", "--tuning-reps", "2", "--tables", "1", "--rates", "0.6,1.0"]
    code = main(["baselines", *argv, "--seed", "3", "--out", str(out), "--no-progress"])
    assert code == 0 and "evaluation runs; tuned: pil " in capsys.readouterr().out
    assert {p.name for p in out.iterdir()} == {
        "baselines.csv",
        "tuning.csv",
        "tests.csv",
        "equivalence.csv",
        "summary.md",
    }
    runs, tests, tuning = (_read(out / f) for f in ("baselines.csv", "tests.csv", "tuning.csv"))
    tuning_seeds, seeds = split_seeds(3, 2, 4)
    assert {int(r["seed"]) for r in runs} == set(seeds)  # evaluation seeds only
    assert not set(tuning_seeds) & set(seeds)
    for learner in ("pil", "bandit", "tamer"):
        mine = [r for r in tuning if r["learner"] == learner]  # means over every run
        (chosen,) = [r for r in tuning if r["learner"] == learner and r["chosen"] == "True"]
        assert chosen in mine and float(chosen["mean_total_actions"]) == min(
            float(r["mean_total_actions"]) for r in mine
        )
        if learner != "pil":  # the tuned variant runs the chosen setting's parameters
            assert {r["setting"] for r in runs if r["variant"] == f"{learner}:tuned"} == {
                chosen["params"]
            }
    paired = [t for t in tests if t["test"] == "paired t" and t["p"] != "nan"]
    assert paired and all(t["pairing"] == "rep" for t in tests)

    def values(test: dict[str, str], variant: str) -> dict[str, float]:
        rate = float(test["rate"])
        return {
            r["rep"]: float(r[test["measure"]])
            for r in runs
            if r["variant"] == variant and float(r["rate"]) == rate
        }

    for t in paired:
        a, b = values(t, t["system_a"]), values(t, t["system_b"])
        assert a.keys() == b.keys() and len(a) == 4
        expected = ttest_rel([a[k] for k in a], [b[k] for k in a]).pvalue
        assert math.isclose(float(t["p"]), expected, rel_tol=1e-9)
        assert float(t["p_holm"]) >= float(t["p"])
        a_name, b_name = t["system_a"], t["system_b"]
        learner = a_name.split(":")[0]
        if learner == "pil":  # PIL with the memory against PIL without it, same rule
            assert a_name == f"{b_name}+memory"
        else:
            assert learner in ("bandit", "tamer")
            assert b_name.startswith("pil:") or b_name == f"{learner}:default"
    summary = (out / "summary.md").read_text()
    assert "paired t" in summary and "Holm" in summary and "held-out" in summary


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--reps", "0"], "--reps must be a whole number from 1 to 100000, got '0'"),
        (["--tuning-reps", "x"], "--tuning-reps must be a whole number"),
        (["--rates", "0.4,1.5"], "must be a number in (0, 1], got '1.5'"),
        (["--tables", "0"], "--tables must be a whole number from 1 to 1000"),
    ],
)
def test_bad_input_exits_2_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture, argv: list[str], message: str
) -> None:
    out = tmp_path / "never"
    assert main(["baselines", *argv, "--out", str(out), "--no-progress"]) == 2
    error = capsys.readouterr().err
    assert error.startswith("robin-pil baselines: error: ") and message in error
    assert error.count("\n") == 1 and not out.exists()
