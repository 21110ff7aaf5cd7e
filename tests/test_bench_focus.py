"""Suite 1.2's declared analysis: the focus family is the declared one whoever ran, a failed run
counts at the cap instead of dropping its pair, the non-inferiority test looks the right way
with the right margin, stalled runs are counted apart from failed ones, and each dose-response
condition changes one thumb-noise component only."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pil.bench.analysis import comparisons, summaries
from pil.bench.counting import count
from pil.bench.equivalence import noninferior_paired
from pil.bench.focus import FOCUS, focus_comparisons, noninferiority
from pil.bench.noise import FeedbackChannel, make_reader
from pil.bench.suite import Condition, load_suite
from pil.bench.tracks import run_track
from pil.experiments.stats import holm
from pil.task.records import StepRecord
from pil.types import Action, Feedback, Gesture

SEEDS = list(range(12))


def _rows(agent: str, track: str, condition: str, base: float, step: float, failed=()) -> list:
    """Synthetic journal rows: ``base + step * seed`` actions, NaN (failed) on ``failed``."""
    out = []
    for seed in SEEDS:
        bad = seed in failed
        out.append(
            {
                "track": track,
                "condition": condition,
                "agent": agent,
                "seed": seed,
                "actions": math.nan if bad else base + step * seed + (seed % 3),
                "failed": "passed the cap" if bad else "",
                "stalled": False,
                "scripted": 220,
                "curve_area": 1.0,
            }
        )
    return out


def _focus_rows(suite, opponents) -> list:
    rows = []
    focus = suite.focus
    for track, condition in focus.cells:
        rows += _rows(focus.entrant, track, condition, 250.0, 1.0)
        for k, opponent in enumerate(opponents):
            rows += _rows(opponent, track, condition, 260.0 + k, 1.3)
    return rows


def test_the_focus_family_is_the_declared_one_whoever_ran():
    suite = load_suite()
    focus = suite.focus
    assert focus is not None and focus.entrant == "pil-robust"
    assert set(focus.against) >= {"tamer", "policy-shaping", "isabl", "pil-paper", "random"}
    assert focus.size == len(focus.against) * len(focus.cells)
    everyone = focus_comparisons(suite, _focus_rows(suite, focus.against))
    fewer = focus_comparisons(suite, _focus_rows(suite, focus.against[:2]))
    assert {r["family_size"] for r in everyone} == {focus.size} and everyone[0]["family"] == FOCUS
    assert len(everyone) == 2 * focus.size  # t and Wilcoxon for every declared comparison
    for test in ("paired t", "wilcoxon signed-rank"):
        members = [r for r in everyone if r["test"] == test]
        expected = holm([r["p"] for r in members], size=focus.size)
        assert [r["p_holm"] for r in members] == pytest.approx(expected, nan_ok=True)
    key = ("anchor", "condition", "test")
    full = {tuple(r[k] for k in key): r["p_holm"] for r in everyone}
    assert {r["family_size"] for r in fewer} == {focus.size}  # declared, not what ran
    for r in fewer:  # what did not run counts as p = 1: a Holm p never shrinks for it
        assert r["p_holm"] >= full[tuple(r[k] for k in key)] - 1e-15
    others = _focus_rows(suite, focus.against) + _rows("oracle", "assembly", "eyes", 200.0, 1.0)
    assert focus_comparisons(suite, others) == everyone  # an agent outside the family: no change
    only_opponents = [r for r in _focus_rows(suite, ["tamer"]) if r["agent"] == "tamer"]
    assert focus_comparisons(suite, only_opponents) == []  # the entrant did not run


def test_a_failed_run_counts_at_the_cap_instead_of_dropping_its_pair():
    suite = load_suite()
    rows = _rows("pil-robust", "assembly", "eyes", 250.0, 1.0)
    rows += _rows("tamer", "assembly", "eyes", 260.0, 1.0, failed=(3, 7))
    found = [r for r in focus_comparisons(suite, rows) if r["test"] == "paired t"]
    (row,) = found
    cap = suite.cap_of("assembly") * 220
    robust = [r["actions"] for r in rows if r["agent"] == "pil-robust"]
    tamer = [
        cap if math.isnan(r["actions"]) else r["actions"] for r in rows if r["agent"] == "tamer"
    ]
    assert row["n"] == len(SEEDS) and row["dropped"] == 0 and row["at_cap"] == 2
    assert row["mean_diff"] == pytest.approx(sum(robust) / 12 - sum(tamer) / 12)
    assert "counted at the cap" in row["note"]
    # the anchors' family of the same runs drops those seeds instead
    rows_anchor = [dict(r, agent="pil-paper") if r["agent"] == "tamer" else r for r in rows]
    dropped = comparisons(suite, rows_anchor, "assembly", "pil-robust")
    eyes = [r for r in dropped if r["condition"] == "eyes" and r["anchor"] == "pil-paper"]
    assert eyes[0]["dropped"] == 2 and eyes[0]["n"] == len(SEEDS) - 2 and eyes[0]["at_cap"] == 0


@settings(max_examples=40, deadline=None)
@given(st.floats(-30.0, 30.0), st.floats(0.5, 4.0))
def test_noninferiority_looks_one_way_with_its_margin(shift, spread):
    """Worse by less than the margin (with a tight spread) passes, worse by more fails, better
    always passes: p < 0.05 exactly when the one-sided upper bound lies below the margin."""
    base = [300.0 + 7 * k for k in range(20)]
    noise = [spread * ((k * 7919) % 11 - 5) / 5 for k in range(20)]
    entrant = [b + shift + e for b, e in zip(base, noise, strict=True)]
    found = noninferior_paired(entrant, base, 5.0, 0.05)
    assert (found["p"] < 0.05) == (found["upper"] < 5.0)
    if shift + spread < 5.0 - 1.0:
        assert found["p"] < 0.05
    if shift - spread > 5.0 + 1.0:
        assert found["p"] > 0.5
    # a larger margin never makes it harder
    assert noninferior_paired(entrant, base, 8.0, 0.05)["p"] <= found["p"] + 1e-12


def test_the_declared_noninferiority_is_robust_against_paper_with_right_thumbs():
    suite = load_suite()
    test = suite.noninferiority
    assert test is not None and (test.entrant, test.anchor, test.margin) == (
        "pil-robust",
        "pil-paper",
        5.0,
    )
    assert test.conditions == ("d40", "d60", "d80", "d100")
    rows = []
    for condition in test.conditions:
        rows += _rows("pil-robust", "assembly", condition, 303.0, 1.0)
        rows += _rows("pil-paper", "assembly", condition, 300.0, 1.0)
    found = {r["condition"]: r for r in noninferiority(suite, rows)}
    assert all(found[c]["noninferior"] == "yes" for c in test.conditions)  # worse by 3 < 5
    assert found["all"]["noninferior"] == "yes"
    worse = [
        dict(r, actions=r["actions"] + 6.0)
        if r["agent"] == "pil-robust" and r["condition"] == "d80"
        else r
        for r in rows
    ]
    found = {r["condition"]: r for r in noninferiority(suite, worse)}
    assert found["d80"]["noninferior"] == "no" and found["all"]["noninferior"] == "no"


def _record(gestures: int, action: Action | None) -> StepRecord:
    return StepRecord(
        t=0,
        gesture_count=gestures,
        table=0,
        handover=0,
        handover_type="x",
        step=0,
        true_gesture=Gesture.POINTING,
        detected_gesture=None,
        intended_action=Action.OBJECT,
        legs_delivered=0,
        action=action,
        feedback=None if action is None else Feedback.OK,
    )


@settings(max_examples=80, deadline=None)
@given(st.lists(st.booleans(), min_size=1, max_size=120), st.integers(1, 30))
def test_a_run_is_stalled_after_k_gestures_in_a_row_without_an_action(acted, k):
    records, t = [], 0
    for n, act in enumerate(acted, start=1):
        t += act
        records.append(_record(n, Action.OBJECT if act else None)._replace(t=t))
    played = count(records, limit=1e9, stall_after=k)
    runs = [len(m.group()) for m in re.finditer(r"0+", "".join("1" if a else "0" for a in acted))]
    assert played.longest_wait == max(runs, default=0)
    assert played.stalled == (max(runs, default=0) >= k)
    assert not played.failed  # stalled is apart from failed
    assert not count(records, limit=1e9).stalled  # no K: measured, never called stalled


def test_stalled_runs_are_counted_apart_in_the_summary():
    suite = load_suite()
    rows = _rows("tamer", "assembly", "eyes", 260.0, 1.0, failed=(1,))
    rows[4]["stalled"] = True
    rows[1]["stalled"] = True
    (row,) = [s for s in summaries(suite, rows, "assembly") if s["condition"] == "eyes"]
    assert row["failed"] == 1 and row["stalled"] == 2


def test_a_reader_that_never_sees_a_gesture_does_not_stall_the_loop():
    """Every gesture discarded: the loop proposes an action after its repeat requests, so the
    robot never waits K gestures (a real run, pil-next-best)."""
    suite = load_suite()
    blind = Condition("blind", {"model": "independent", "rate": 0.0})
    patched = dict(suite.conditions, blind=blind)
    from dataclasses import replace

    from pil.bench.entrants import reference

    bench = replace(suite, conditions=patched)
    row = run_track(
        bench,
        suite.track("assembly"),
        "blind",
        suite.seeds("dev")[0],
        reference("pil-next-best"),
        True,
    )
    assert 0 < row["longest_wait"] < suite.stall_after and row["stalled"] is False


def test_each_dose_condition_changes_one_component_only():
    suite = load_suite()
    conditions = suite.track_conditions("thumb-noise")
    base = suite.conditions["d80"]
    assert conditions[0] == "d80" and not base.feedback
    components = {"silence": "silenced", "missed": "missed", "late": "late", "misread": "misread"}
    for name in conditions[1:]:
        component, percent = re.fullmatch(r"([a-z]+)-(\d+)", name).groups()
        spec = suite.conditions[name]
        assert spec.gestures == base.gestures
        assert dict(spec.feedback) == {component: int(percent) / 100}
        channel = make_reader(spec, 5, 100)
        assert isinstance(channel, FeedbackChannel)
        for k in range(3000):
            channel.read_feedback(Feedback.OK if k % 2 else Feedback.NOT_OK)
        moved = {key for key, n in channel.counts.items() if n}
        assert moved == {components[component]}
    assert {re.sub(r"-\d+$", "", c) for c in conditions[1:]} == set(components)
    assert {c.split("-")[1] for c in conditions[1:]} == {"2", "5", "10", "20"}


def test_missed_alone_is_silence_alone_to_a_robot_that_never_asks():
    """To a robot that never asks for a thumb a missed thumb is no thumb: missed-p gives the
    very runs of silence-p (docs/bench.md says why the dose track runs both)."""
    from pil.bench.entrants import reference

    suite = load_suite()
    for agent in ("pil-paper", "tamer"):
        for seed in suite.seeds("dev")[:3]:
            rows = [
                run_track(suite, suite.track("thumb-noise"), c, seed, reference(agent), True)
                for c in ("silence-20", "missed-20")
            ]
            assert rows[0] == rows[1]


def test_the_dose_track_is_shown_per_component_with_d80_as_its_zero():
    from pil.bench.leaderboard_focus import dose_levels, marks

    suite = load_suite()
    levels = dose_levels(suite.track_conditions("thumb-noise"))
    assert set(levels) == {"silence", "missed", "late", "misread"}
    for component, found in levels.items():
        assert found == [(0, "d80"), *((p, f"{component}-{p}") for p in (2, 5, 10, 20))]
    assert dose_levels(suite.track_conditions("assembly")) == {}  # not a dose-response
    assert marks({"failed": 2.0, "stalled": 1.0}) == " (2✗ 1⏸)"
    assert marks({"failed": 0.0, "stalled": math.nan}) == ""
