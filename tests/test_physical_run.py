"""One physical run as a results row (the sweep's physical kind)."""

from __future__ import annotations

import pytest

from pil.errors import InvalidChoiceError
from pil.experiments.sweep_grid import GridRow, parse_param
from robin_sim.episode.physical_run import PHYSICAL_RUNS, physical_row


@pytest.mark.slow
def test_a_physical_run_returns_a_flat_row_with_the_legs_delivered() -> None:
    row = GridRow("pil|x", "pil", 1.0, 0, 4, (("tables", 1), ("legs_per_table", 1)))
    row = physical_row(PHYSICAL_RUNS.parse(row, {}))
    assert row["status"] == "finished" and row["error"] == ""
    assert (row["legs_total"], row["legs_delivered"], row["legs_delivered_fraction"]) == (1, 1, 1.0)
    assert row["physical_failures"] == 0
    assert row["sim_time_s"] > 0
    assert all(not isinstance(value, dict) for value in row.values())


def test_an_unknown_parameter_lists_the_valid_ones() -> None:
    with pytest.raises(InvalidChoiceError, match="discard"):
        parse_param("discrad=0.3", PHYSICAL_RUNS)
