"""The study's analysis (pil.experiments.study_analysis) against scipy and statsmodels."""

from __future__ import annotations

import math

import pandas as pd
import pytest
import statsmodels.formula.api as smf
from scipy.stats import ttest_ind, ttest_rel, wilcoxon
from statsmodels.stats.multitest import multipletests

from pil.experiments.study_analysis import (
    analyse,
    compare_conditions,
    mixed_model,
    needs_mixed,
    order_effects,
)

# six participants, two conditions each, in a counterbalanced order; two blocks of A for P1
WITHIN = [
    ("P1", "A", 1, 10.0), ("P1", "B", 2, 7.0), ("P1", "A", 3, 12.0),
    ("P2", "B", 1, 9.0), ("P2", "A", 2, 14.0),
    ("P3", "A", 1, 11.0), ("P3", "B", 2, 6.0),
    ("P4", "B", 1, 8.0), ("P4", "A", 2, 13.5),
    ("P5", "A", 1, 9.5), ("P5", "B", 2, 8.5),
    ("P6", "B", 1, 5.0), ("P6", "A", 2, 12.5),
]  # fmt: skip


def obs(rows, group="all"):
    return [
        {"participant": p, "group": group, "condition": c, "position": k, "value": v}
        for p, c, k, v in rows
    ]


def test_within_pairs_are_paired_t_and_wilcoxon_on_participant_means() -> None:
    (result,) = compare_conditions(obs(WITHIN), ["A", "B"])
    a = [11.0, 14.0, 11.0, 13.5, 9.5, 12.5]  # P1's A is the mean of its two A blocks
    b = [7.0, 9.0, 6.0, 8.0, 8.5, 5.0]
    assert result["design"] == "within" and result["n"] == 6
    assert result["p"] == pytest.approx(ttest_rel(a, b).pvalue)
    assert result["p_w"] == pytest.approx(wilcoxon(a, b).pvalue)
    ci = ttest_rel(a, b).confidence_interval(0.95)
    assert (result["ci_low"], result["ci_high"]) == pytest.approx((ci.low, ci.high))
    diffs = [x - y for x, y in zip(a, b, strict=True)]
    sd = pd.Series(diffs).std()
    assert result["effect_size"] == pytest.approx(sum(diffs) / len(diffs) / sd)  # d_z


def test_between_pairs_are_welch_with_cohens_d() -> None:
    rows = obs([("P1", "A", 1, 3.0), ("P2", "A", 1, 5.0), ("P3", "A", 1, 4.0),
                ("P4", "B", 1, 8.0), ("P5", "B", 1, 9.5)])  # fmt: skip
    (result,) = compare_conditions(rows, ["A", "B"])
    assert result["design"] == "between" and result["n"] == "3/2" and result["test"] == "welch t"
    assert result["p"] == pytest.approx(ttest_ind([3, 5, 4], [8, 9.5], equal_var=False).pvalue)
    assert math.isnan(result["p_w"])


def test_the_mixed_model_is_statsmodels_mixedlm_with_a_random_intercept() -> None:
    rows = obs(WITHIN)
    model = mixed_model(rows, ["A", "B"])
    assert model["formula"] == "value ~ C(condition) + position"
    frame = pd.DataFrame(rows)
    frame["condition"] = pd.Categorical(frame["condition"], categories=["A", "B"])
    expected = smf.mixedlm(model["formula"], frame, groups=frame["participant"]).fit(reml=True)
    got = {e["term"]: e for e in model["effects"]}
    assert set(got) == {"Intercept", "C(condition)[T.B]", "position"}
    for term, effect in got.items():
        assert effect["coef"] == pytest.approx(expected.fe_params[term])
        assert effect["p"] == pytest.approx(expected.pvalues[term])
    assert got["C(condition)[T.B]"]["coef"] < 0  # B lower than A
    assert model["participants"] == 6 and model["observations"] == len(WITHIN)
    constant = mixed_model(obs([(p, c, k, 4.0) for p, c, k, _ in WITHIN]), ["A", "B"])
    assert "distinct values" in constant["error"]


def test_when_the_design_calls_for_the_mixed_model() -> None:
    once = obs([(p, c, k, v) for p, c, k, v in WITHIN if (p, k) != ("P1", 3)])
    assert not needs_mixed(once, "within")  # one block per condition: paired tests suffice
    assert needs_mixed(obs(WITHIN), "within")  # P1 did two blocks of A
    assert needs_mixed(once, "between") and needs_mixed(once, "mixed")


def test_order_effects_and_holm_over_each_instrument() -> None:
    order = {(o["condition"], o["position"]): o for o in order_effects(obs(WITHIN))}
    firsts = [v for _p, _c, k, v in WITHIN if k == 1]
    assert order[("all", 1)]["n"] == 6 and order[("all", 1)]["mean"] == pytest.approx(
        sum(firsts) / 6
    )
    assert math.isnan(order[("A", 3)]["sd"])  # one value
    other = obs([(p, c, k, v * 0.5 + (k == 1)) for p, c, k, v in WITHIN])
    result = analyse(
        {("blocks", "time"): obs(WITHIN), ("blocks", "actions"): other, ("tlx", "raw"): other},
        "within",
        ["A", "B"],
    )
    blocks = [t for t in result["tests"] if t["instrument"] == "blocks"]
    adjusted = multipletests([t["p"] for t in blocks], method="holm")[1]
    assert [t["p_holm"] for t in blocks] == pytest.approx(list(adjusted))
    tlx = next(t for t in result["tests"] if t["instrument"] == "tlx")
    assert tlx["p_holm"] == pytest.approx(tlx["p"])  # a family of one
    assert len(result["models"]) == 3  # P1's two blocks of A call for it
