"""Two things the quick bench and the leaderboard's tables must not blur (issue 39).

* An entrant's family with the anchors is Holm-adjusted over its declared size, which is the
  ``family_size`` the tables show: a comparison without a p (no pairs, or every pair differs
  by the same) counts as p = 1, as a focus comparison that did not run does
  (:func:`pil.experiments.stats.holm` with ``size``), so the multiplier is the size shown.
* The quick ``two-people`` track is not the quick ``meaning-change`` track: with two tables
  both are "A, then B means location by give me"; the quick two-people track has a third
  table, A's again, so the runs differ.
"""

from __future__ import annotations

import math
import random

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pil.bench.analysis import comparisons
from pil.bench.run import Entrant, _run
from pil.bench.suite import load_suite
from pil.bench.tracks import _scripts, table_mappings
from pil.experiments.stats import PAIRED_T, WILCOXON, holm
from pil.types import Gesture

SUITE = load_suite()
SEEDS = SUITE.seeds("dev", quick=True)


def _rows(entrant: str, differences: dict[str, list[float]]) -> list[dict]:
    """Journal-shaped rows: each anchor at 100 actions per seed, the entrant 100 + the given
    difference."""
    rows = []
    for condition, diffs in differences.items():
        for seed, diff in enumerate(diffs):
            for agent, actions in [(a, 100.0) for a in SUITE.anchors] + [(entrant, 100 + diff)]:
                rows.append(
                    {
                        "track": "assembly",
                        "condition": condition,
                        "agent": agent,
                        "seed": seed,
                        "actions": actions,
                        "failed": "",
                    }
                )
    return rows


def test_the_multiplier_is_the_family_size_shown():
    rng = random.Random(3)
    spread = {c: [rng.gauss(-8, 4) for _ in range(8)] for c in ("eyes", "teacher")}
    rows = _rows("mine", {"d60": [5.0] * 8, **spread})  # d60: no spread, no p
    found = comparisons(SUITE, rows, "assembly", "mine", quick=True)
    declared = len(SUITE.anchors) * len(SUITE.track_conditions("assembly", quick=True))
    assert {r["family_size"] for r in found} == {declared}
    for test in (PAIRED_T, WILCOXON):
        family = [r for r in found if r["test"] == test]
        tested = sorted((r["p"], r["p_holm"]) for r in family if not math.isnan(r["p"]))
        assert len(tested) < declared  # the no-spread comparisons have no p ...
        p, adjusted = tested[0]
        assert adjusted == pytest.approx(min(1.0, declared * p))  # ... and still count


@given(
    ps=st.lists(st.one_of(st.floats(0, 1), st.just(math.nan)), min_size=1, max_size=12),
    missing=st.integers(0, 5),
)
def test_holm_over_a_declared_size_counts_what_has_no_p_as_one(ps, missing):
    """holm(ps, size) is Holm over the declared family with every comparison without a p (NaN,
    or not among ps) at p = 1: never smaller than Holm over the ps alone."""
    size = len(ps) + missing
    padded = [1.0 if math.isnan(p) else p for p in ps] + [1.0] * missing
    full = holm(padded)
    for p, adjusted, alone, expected in zip(ps, holm(ps, size=size), holm(ps), full, strict=False):
        if math.isnan(p):
            assert math.isnan(adjusted)
        else:
            assert adjusted == pytest.approx(expected) and adjusted >= alone - 1e-12


def _give_me(track: str, draw: int) -> list[set[str]]:
    """Per table of the quick track, what "give me" means (the actions it asks for)."""
    script = _scripts(SUITE.track(track), True, draw)["script"]
    mappings = table_mappings(script)
    return [
        {a.value for s, a in mappings[t].items() if s.gesture is Gesture.GIVE_ME}
        for t in sorted(mappings)
    ]


def test_the_quick_two_people_track_returns_to_the_first_person():
    for draw in (1, 2, 3):
        assert _give_me("meaning-change", draw) == [{"human"}, {"location"}]
        assert _give_me("two-people", draw) == [{"human"}, {"location"}, {"human"}]


def test_quick_meaning_change_and_two_people_runs_differ():
    entrant = Entrant("pil-next-best", "pil-next-best")
    for condition in SUITE.track_conditions("two-people", quick=True):
        for seed in SEEDS:
            change = _run(SUITE, ("meaning-change", condition, entrant, seed, True))
            people = _run(SUITE, ("two-people", condition, entrant, seed, True))
            assert change["actions"] != people["actions"] or change["curve"] != people["curve"]
