"""The analysis the suite file fixes in advance, applied to a journal's rows.

Families are declared, not built from what ran: an entrant's family on a track is its
comparison with each anchor of the suite (``analysis.anchors``, less itself) in each of the
track's conditions, one family per test. Its Holm-adjusted p therefore depends on the
entrant's and the anchors' runs only, never on which other entrants ran. Holm's multiplier is
the declared size (``family_size``): a comparison without a p (no pairs, or every pair differs
by the same) counts as p = 1, as in the focus family (:mod:`pil.bench.focus`). Each comparison is
paired by seed over *complete pairs*: a seed where either run failed is dropped from that
comparison (``dropped``), never replaced by an unpaired test. Beside it: TOST against the
equivalence anchor with the suite's margin (:mod:`pil.bench.equivalence`), and the mixed model
over all conditions (:mod:`pil.bench.mixed`).

:func:`summaries` gives the leaderboard's numbers per (track, agent, condition): the mean of
the primary metric with its 95 % interval, the failure rate, regret against the oracle (paired
by seed), the learning curve's area and the track's own measure (recovery, savings).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from pil.bench.equivalence import tost_paired
from pil.bench.mixed import agent_effect
from pil.bench.suite import Suite
from pil.experiments.stats import CONFIDENCE, holm, paired

ORACLE = "oracle"
ANCHORS = "anchors"  # the ``family`` of an entrant's comparisons with the anchors
BENCH_TEST_COLUMNS = (
    "track",
    "entrant",
    "anchor",
    "condition",
    "measure",
    "family",  # anchors: the entrant's family with the anchors; focus: analysis.focus
    "test",
    "n",
    "dropped",  # seeds left out because a run failed (anchors' family)
    "at_cap",  # failed runs counted at the cap instead (focus family)
    "mean_diff",
    "ci_low",
    "ci_high",
    "effect_size",
    "p",
    "p_holm",
    "family_size",
    "note",  # why a comparison has no p (stats.paired's note: no pairs, no spread)
)


def _by_seed(rows: Sequence[Mapping[str, Any]], agent: str, condition: str, metric: str):
    return {
        int(r["seed"]): float(r[metric])
        for r in rows
        if r["agent"] == agent and r["condition"] == condition and metric in r
    }


def _pairs(rows, a: str, b: str, condition: str, metric: str):
    """Complete pairs (seed order) and how many seeds were dropped for a failed run."""
    xa, xb = _by_seed(rows, a, condition, metric), _by_seed(rows, b, condition, metric)
    seeds = sorted(set(xa) & set(xb))
    kept = [s for s in seeds if not (math.isnan(xa[s]) or math.isnan(xb[s]))]
    return [xa[s] for s in kept], [xb[s] for s in kept], len(seeds) - len(kept)


def comparisons(
    suite: Suite, rows: Sequence[Mapping[str, Any]], track: str, entrant: str, quick: bool = False
) -> list[dict[str, Any]]:
    """The entrant's declared family on ``track``: paired t and Wilcoxon against every anchor
    in every condition, Holm within each test (module docstring)."""
    metric = suite.primary
    rows = [r for r in rows if r["track"] == track]
    out: list[dict[str, Any]] = []
    for anchor in suite.anchors:
        if anchor == entrant:
            continue
        for condition in suite.track_conditions(track, quick):
            a, b, dropped = _pairs(rows, entrant, anchor, condition, metric)
            for result in paired(a, b):  # no pairs: untested rows, each saying why
                out.append(
                    {
                        "track": track,
                        "entrant": entrant,
                        "anchor": anchor,
                        "condition": condition,
                        "measure": metric,
                        "family": ANCHORS,
                        "dropped": dropped,
                        "at_cap": 0,
                        **result,
                    }
                )
    for test in suite_tests():  # the declared family: a comparison without a p counts as 1
        members = [r for r in out if r["test"] == test]
        adjusted = holm([r["p"] for r in members], size=len(members))
        for r, p in zip(members, adjusted, strict=True):
            r["p_holm"] = p
            r["family_size"] = len(members)
    return [{c: r[c] for c in BENCH_TEST_COLUMNS} for r in out]


def suite_tests() -> tuple[str, str]:
    """The paired tests every comparison runs (:func:`pil.experiments.stats.paired`)."""
    from pil.experiments.stats import PAIRED_T, WILCOXON

    return (PAIRED_T, WILCOXON)


def equivalence(
    suite: Suite, rows: Sequence[Mapping[str, Any]], track: str, entrant: str, quick: bool = False
) -> list[dict[str, Any]]:
    """TOST of the entrant against the equivalence anchor per condition, and the mixed model
    over all conditions (condition ``all``)."""
    anchor, metric = suite.equivalence_anchor, suite.primary
    if entrant == anchor:
        return []
    rows = [r for r in rows if r["track"] == track]
    out = []
    complete = []
    for condition in suite.track_conditions(track, quick):
        a, b, dropped = _pairs(rows, entrant, anchor, condition, metric)
        found = tost_paired(a, b, suite.margin)
        out.append(
            {
                "track": track,
                "entrant": entrant,
                "anchor": anchor,
                "condition": condition,
                "dropped": dropped,
                **found,
            }
        )
        seeds = _complete_seeds(rows, entrant, anchor, condition, metric)
        complete += [
            r
            for r in rows
            if r["track"] == track
            and r["condition"] == condition
            and r["agent"] in (entrant, anchor)
            and int(r["seed"]) in seeds
        ]
    fit = agent_effect(complete, entrant, anchor, metric)
    out.append(
        {
            "track": track,
            "entrant": entrant,
            "anchor": anchor,
            "condition": "all",
            "mixed_coef": fit["coef"],
            "mixed_low": fit["ci_low"],
            "mixed_high": fit["ci_high"],
            "mixed_p": fit["p"],
            "mixed_note": fit["note"],
        }
    )
    return out


def _complete_seeds(rows, a: str, b: str, condition: str, metric: str) -> set[int]:
    xa, xb = _by_seed(rows, a, condition, metric), _by_seed(rows, b, condition, metric)
    return {s for s in set(xa) & set(xb) if not (math.isnan(xa[s]) or math.isnan(xb[s]))}


def mean_ci(values: Sequence[float]) -> tuple[float, float, float]:
    """Mean and its t-based 95 % interval over the values that are not NaN (NaN bounds for
    fewer than two values)."""
    from scipy.special import stdtrit

    kept = [float(v) for v in values if not math.isnan(v)]
    if not kept:
        return math.nan, math.nan, math.nan
    mean = statistics.fmean(kept)
    if len(kept) < 2:
        return mean, math.nan, math.nan
    half = float(stdtrit(len(kept) - 1, 0.5 + CONFIDENCE / 2)) * statistics.stdev(kept)
    half /= math.sqrt(len(kept))
    return mean, mean - half, mean + half


_ci = mean_ci


def summaries(
    suite: Suite, rows: Sequence[Mapping[str, Any]], track: str, quick: bool = False
) -> list[dict]:
    """Per agent and condition of ``track``: the leaderboard's numbers (module docstring)."""
    metric = suite.primary
    here = [r for r in rows if r["track"] == track]
    agents = list(dict.fromkeys(str(r["agent"]) for r in here))
    out = []
    for agent in agents:
        for condition in suite.track_conditions(track, quick):
            mine = [r for r in here if r["agent"] == agent and r["condition"] == condition]
            if not mine:
                continue
            values = [float(r[metric]) for r in mine]
            mean, low, high = _ci(values)
            oracle = _by_seed(here, ORACLE, condition, metric)
            regret = [
                float(r[metric]) - oracle[int(r["seed"])] for r in mine if int(r["seed"]) in oracle
            ]
            row = {
                "track": track,
                "agent": agent,
                "condition": condition,
                "runs": len(mine),
                "failed": sum(bool(r["failed"]) for r in mine),
                "stalled": sum(bool(r.get("stalled")) for r in mine),
                "mean": mean,
                "ci_low": low,
                "ci_high": high,
                "regret": _ci(regret)[0] if regret else math.nan,
                "curve_area": _ci([float(r["curve_area"]) for r in mine])[0],
            }
            for extra in ("recovery", "savings"):
                if extra in mine[0]:
                    got = [float(r[extra]) for r in mine]
                    row[extra] = _ci(got)[0]
                    row[f"{extra}_missing"] = sum(math.isnan(v) for v in got)
            out.append(row)
    return out


def curves(rows: Sequence[Mapping[str, Any]], track: str) -> dict[tuple[str, str], list[float]]:
    """The mean per-table actions curve of each (agent, condition) on ``track`` (runs that
    finished)."""
    found: dict[tuple[str, str], list[list[float]]] = {}
    for r in rows:
        if r["track"] == track and not r["failed"]:
            found.setdefault((str(r["agent"]), str(r["condition"])), []).append(r["curve"])
    return {
        key: [statistics.fmean(column) for column in zip(*members, strict=True)]
        for key, members in found.items()
    }
