"""The reference leaderboard in the docs is its results folder, rendered: the page matches
what `render` makes of `bench/results/leaderboard/`, its tables match the runs journal, and it
names the suite version and the commit that made the runs."""

from __future__ import annotations

import csv
import json
import math
import re
import statistics
from pathlib import Path

import pytest

from pil.bench.journal import read_runs
from pil.bench.leaderboard import render
from pil.bench.suite import load_suite
from pil.experiments.stats import holm

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "bench" / "results" / "leaderboard"
PAGE = ROOT / "docs" / "leaderboard.md"


@pytest.fixture(scope="module")
def runs() -> list[dict]:
    return read_runs(FOLDER, load_suite())


def _table(name: str) -> list[dict[str, str]]:
    with open(FOLDER / name, encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def test_the_page_is_its_results_folder_rendered():
    suite = load_suite()
    assert PAGE.read_text(encoding="utf-8") == render(suite, FOLDER), (
        "docs/leaderboard.md differs from its results: regenerate it with "
        "robin-pil bench --leaderboard"
    )


def test_the_page_names_the_suite_the_seeds_and_the_commit(runs):
    suite = load_suite()
    stamp = json.loads((FOLDER / "stamp.json").read_text())
    page = PAGE.read_text(encoding="utf-8")
    assert stamp["suite_version"] == suite.version and stamp["suite_sha256"] == suite.sha256
    assert stamp["block"] == "eval" and stamp["quick"] is False
    assert re.fullmatch(r"[0-9a-f]{40}", stamp["commit"]), "made from a committed tree"
    assert f"commit `{stamp['commit']}`" in page
    assert {int(r["seed"]) for r in runs} == set(suite.seeds("eval"))
    assert {r["agent"] for r in runs} == set(suite.agents)
    assert {r["track"] for r in runs} == set(suite.quick_tracks())  # all but the slow one


def test_the_summary_is_the_journal_s_means(runs):
    groups: dict[tuple[str, str, str], list[dict]] = {}
    for r in runs:
        groups.setdefault((r["track"], r["agent"], r["condition"]), []).append(r)
    summary = _table("summary.csv")
    assert len(summary) == len(groups)
    for row in summary:
        members = groups[(row["track"], row["agent"], row["condition"])]
        done = [float(r["actions"]) for r in members if not math.isnan(float(r["actions"]))]
        assert int(row["runs"]) == len(members)
        assert int(row["failed"]) == sum(bool(r["failed"]) for r in members)
        if done:
            assert float(row["mean"]) == pytest.approx(statistics.fmean(done), rel=1e-5)


def test_a_family_s_holm_p_is_recomputed_from_the_journal(runs):
    from scipy.stats import ttest_rel

    suite = load_suite()
    tests = [t for t in _table("tests.csv") if t["test"] == "paired t"]
    for track, entrant in (("assembly", "tamer"), ("meaning-change", "pil-paper")):
        family = [t for t in tests if t["track"] == track and t["entrant"] == entrant]
        assert len(family) == int(family[0]["family_size"])
        raw = []
        for t in family:
            by = {}
            for r in runs:
                if r["track"] == track and r["condition"] == t["condition"]:
                    by.setdefault(r["agent"], {})[int(r["seed"])] = float(r["actions"])
            a, b = by[entrant], by[t["anchor"]]
            seeds = [s for s in sorted(a) if not (math.isnan(a[s]) or math.isnan(b[s]))]
            assert int(t["n"]) == len(seeds) and int(t["dropped"]) == len(a) - len(seeds)
            if len(seeds) > 1 and len({a[s] - b[s] for s in seeds}) > 1:
                raw.append(float(ttest_rel([a[s] for s in seeds], [b[s] for s in seeds]).pvalue))
            else:
                raw.append(math.nan)
        for t, adjusted in zip(family, holm(raw, size=len(family)), strict=True):
            if math.isnan(adjusted):
                assert t["p_holm"] == ""
            else:
                assert float(t["p_holm"]) == pytest.approx(adjusted, rel=1e-4)
        assert len(family) == len(suite.anchors) * len(suite.track(track).conditions) - (
            len(suite.track(track).conditions) if entrant in suite.anchors else 0
        )


def test_the_focus_family_and_noninferiority_recompute_from_the_journal(runs):
    """tests.csv's focus rows and noninferiority.csv are the journal's runs with every failed
    run at the cap (the track's cap x its scripted gestures): nothing dropped."""
    from scipy.stats import ttest_rel

    suite = load_suite()
    focus, test = suite.focus, suite.noninferiority
    assert focus is not None and test is not None

    def values(agent: str, track: str, condition: str) -> dict[int, float]:
        return {
            int(r["seed"]): suite.cap_of(track) * float(r["scripted"])
            if r["failed"]
            else float(r["actions"])
            for r in runs
            if r["agent"] == agent and r["track"] == track and r["condition"] == condition
        }

    rows = [t for t in _table("tests.csv") if t["family"] == "focus" and t["test"] == "paired t"]
    assert len(rows) == focus.size and {int(t["family_size"]) for t in rows} == {focus.size}
    for t in rows[:: max(1, len(rows) // 8)]:
        a = values(focus.entrant, t["track"], t["condition"])
        b = values(t["anchor"], t["track"], t["condition"])
        assert int(t["n"]) == len(a) == len(b) and int(t["dropped"]) == 0
        diffs = [a[s] - b[s] for s in sorted(a)]
        assert float(t["mean_diff"]) == pytest.approx(statistics.fmean(diffs), rel=1e-5)
        if len(set(diffs)) > 1:
            p = float(ttest_rel([a[s] for s in sorted(a)], [b[s] for s in sorted(a)]).pvalue)
            assert float(t["p"]) == pytest.approx(p, rel=1e-4)
    found = {r["condition"]: r for r in _table("noninferiority.csv")}
    assert set(found) == {*test.conditions, "all"}
    for condition in test.conditions:
        a = values(test.entrant, test.track, condition)
        b = values(test.anchor, test.track, condition)
        mean = statistics.fmean(a[s] - b[s] for s in a)
        assert float(found[condition]["mean_diff"]) == pytest.approx(mean, rel=1e-5)
