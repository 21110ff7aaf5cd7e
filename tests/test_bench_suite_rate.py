"""A suite file's detection rate is checked by the one rate spec (issue 39)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pil.bench.suite import SUITE_FILE, SuiteError, load_suite
from pil.task.params import MIN_RATE


@pytest.mark.parametrize("rate", ["0.0", "0.0005", f"{MIN_RATE / 2}", "1.5"])
def test_a_condition_at_a_rate_the_study_refuses_is_refused(tmp_path: Path, rate: str) -> None:
    text = SUITE_FILE.read_text(encoding="utf-8")
    assert "d40: {gestures: {model: independent, rate: 0.4}}" in text
    changed = text.replace("rate: 0.4}}", f"rate: {rate}}}}}", 1)
    suite = tmp_path / "suite.yaml"
    suite.write_text(changed, encoding="utf-8")
    with pytest.raises(SuiteError, match=r"conditions\.d40\.gestures\.rate"):
        load_suite(suite)


def test_the_shipped_rates_pass_the_one_check() -> None:
    assert load_suite().conditions["d40"].gestures["rate"] == 0.4
