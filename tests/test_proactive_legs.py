"""The proactive path counts the legs it delivers (an anticipated open on the person's palm or
on a spot delivers a leg like any approved open)."""

from __future__ import annotations

import pytest
from learner_rows import learner_row

from pil.task.assemble import assemble
from pil.task.runner import steps
from pil.task.spec import parse_run_spec
from pil.task.world import SymbolicWorld


@pytest.mark.parametrize(("rate", "seed"), [(0.8, 1), (1.0, 1), (1.0, 0)])
def test_every_leg_is_counted_with_anticipations(rate: float, seed: int) -> None:
    row = learner_row("proactive", rate, seed=seed)
    assert row["anticipated_ok"] > 0
    assert row["legs"] == 40  # 10 tables of 4 legs, each delivered once


def test_an_anticipated_delivery_raises_the_leg_count() -> None:
    found = 0
    for seed in (0, 1):
        parts = assemble(parse_run_spec(system="proactive", rate=1.0, seed=seed))
        records = list(
            steps(parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options)
        )
        legs = 0
        for record in records:
            legs += record.delivered
            assert record.legs_delivered == legs  # the running count follows every delivery
            found += record.proactive and record.delivered
        assert legs == 40
    assert found > 0  # the proactive path delivered legs in these runs
