"""The slow track: an entrant runs the physical episode with Robin's eye cameras in MuJoCo."""

from __future__ import annotations

import math

import pytest

from pil.bench.entrants import reference
from pil.bench.suite import load_suite
from robin_sim.cli.bench_physical import run_physical_track


@pytest.mark.slow
def test_an_entrant_runs_the_physical_episode() -> None:
    suite = load_suite()
    track = suite.track("physical")
    (condition,) = suite.track_conditions("physical", quick=True)
    seed = suite.seeds("dev", quick=True)[0]
    row = run_physical_track(suite, track, condition, seed, reference("pil-next-best"), True)
    assert row["failed"] == "", row["failed"]
    assert row["scripted"] == 4  # one handover: pointing, grasp, give me, release
    assert row["actions"] >= row["scripted"] and row["gestures"] >= row["scripted"]
    assert sum(row["curve"]) == row["actions"]  # every action counted on its table
    assert row["sim_time_s"] > 0 and not math.isnan(row["curve_area"])
