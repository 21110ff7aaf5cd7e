"""vision-conditions: PIL's runs per measured condition are kept, and each condition is tested
against the first one, paired by repetition (the same master seed for every condition)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from scipy.stats import ttest_rel

from pil.experiments.report import load_rows
from robin_sim.vision.conditions import study_costs, write_outputs

SHIPPED = Path(__file__).resolve().parents[1] / "robin_sim" / "vision" / "data" / "measured.json"


def _dimmer(path: Path) -> Path:
    """The shipped error model with a third of each correct reading discarded instead."""
    errors = json.loads(SHIPPED.read_text())
    for k, row in enumerate(errors["confusion"]):
        moved = row[k] / 3
        row[k] -= moved
        row[-1] += moved
    path.write_text(json.dumps(errors))
    return path


@pytest.mark.slow
def test_conditions_are_compared_paired_by_repetition(tmp_path: Path) -> None:
    rows = [
        {
            "lighting": 1.0,
            "camera_noise": 0.0,
            "detection_rate": 0.84,
            "discarded": 0.1,
            "feedback_misread": 0.0,
            "hands_found": 1.0,
            "measured_file": str(SHIPPED),
        },
        {
            "lighting": 0.25,
            "camera_noise": 0.0,
            "detection_rate": 0.56,
            "discarded": 0.4,
            "feedback_misread": 0.0,
            "hands_found": 1.0,
            "measured_file": str(_dimmer(tmp_path / "dim.json")),
        },
    ]
    rows, dice, runs = study_costs(rows, reps=4, seed=0)
    written = write_outputs(tmp_path, rows, dice, 4, runs)
    assert {p.name for p in written} >= {"conditions_runs.csv", "tests.csv", "conditions.md"}
    back = load_rows(tmp_path / "conditions_runs.csv")
    tests = load_rows(tmp_path / "tests.csv")
    assert {(t["system_a"], t["system_b"], t["pairing"]) for t in tests} == {
        ("l1-n0", "l0.25-n0", "rep+seed")
    }
    for measure in ("gestures", "actions"):
        (t,) = [t for t in tests if t["measure"] == measure and t["test"] == "paired t"]

        def side(condition: str, measure: str = measure) -> list[float]:
            cell = sorted(
                (r for r in back if r["condition"] == condition), key=lambda r: int(r["rep"])
            )
            return [float(r[measure]) for r in cell]

        assert float(t["p"]) == pytest.approx(ttest_rel(side("l1-n0"), side("l0.25-n0")).pvalue)
        assert float(t["mean_diff"]) < 0  # the dimmer condition costs more
    assert "## Each condition against l1-n0" in (tmp_path / "conditions.md").read_text()
