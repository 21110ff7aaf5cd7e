"""pil.experiments.stats: the test that matches the design, effect sizes, Holm's correction."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import ttest_ind, ttest_rel, wilcoxon

from pil.experiments.hodges_lehmann import hodges_lehmann
from pil.experiments.report import ReportError
from pil.experiments.stats import (
    CONSTANT_NOTE,
    PAIRED_T,
    WELCH,
    WILCOXON,
    compare,
    csv_columns,
    holm,
    mean_ci,
)


def _rows(n: int = 12, shift: float = 3.0, seed: int = 0) -> list[dict]:
    """Paired rows: each rep shares a large random offset, so pairing matters."""
    rng = np.random.default_rng(seed)
    rows = []
    for rep in range(n):
        base = rng.normal(100, 20)
        for rate in (0.4, 1.0):
            rows.append({"system": "pil", "rate": rate, "rep": rep, "g": base + rng.normal(0, 1)})
            rows.append(
                {"system": "c1", "rate": rate, "rep": rep, "g": base + shift + rng.normal(0, 1)}
            )
    return rows


def test_paired_p_equals_scipy_ttest_rel_matched_by_rep():
    rows = _rows()
    results = compare(rows, "pil", metrics=["g"])
    for rate in (0.4, 1.0):
        pil = sorted(
            (r for r in rows if r["system"] == "pil" and r["rate"] == rate), key=lambda r: r["rep"]
        )
        c1 = sorted(
            (r for r in rows if r["system"] == "c1" and r["rate"] == rate), key=lambda r: r["rep"]
        )
        a, b = [r["g"] for r in pil], [r["g"] for r in c1]
        (t_row,) = [r for r in results if r["rate"] == str(rate) and r["test"] == PAIRED_T]
        (w_row,) = [r for r in results if r["rate"] == str(rate) and r["test"] == WILCOXON]
        assert t_row["p"] == pytest.approx(ttest_rel(a, b).pvalue, rel=1e-12)
        assert w_row["p"] == pytest.approx(wilcoxon(a, b).pvalue, rel=1e-12)
        assert t_row["pairing"] == "rep" and t_row["n"] == 12
        assert t_row["mean_diff"] == pytest.approx(np.mean(np.subtract(a, b)))
        assert t_row["ci_low"] < t_row["mean_diff"] < t_row["ci_high"]
        d = np.subtract(a, b)
        assert t_row["effect_size"] == pytest.approx(d.mean() / d.std(ddof=1))
        # the shared offsets hide the shift from an unpaired test, not from the paired one
        assert t_row["p"] < 1e-4 < ttest_ind(a, b, equal_var=False).pvalue


def test_holm_never_below_raw_p_and_family_size_counts():
    results = compare(_rows(), "pil", metrics=["g"])
    assert all(r["p_holm"] >= r["p"] for r in results)
    raw = [r["p"] for r in results if r["test"] == PAIRED_T]
    adjusted = [r["p_holm"] for r in results if r["test"] == PAIRED_T]
    assert min(adjusted) == pytest.approx(min(min(raw) * len(raw), 1.0))


def test_holm_leaves_untestable_out_of_the_family():
    out = holm([0.01, math.nan, 0.04])
    assert math.isnan(out[1])
    assert out[0] == pytest.approx(0.02) and out[2] == pytest.approx(0.04)


def test_a_failed_run_drops_its_pair_only_never_switches_to_welch():
    rows = [r for r in _rows() if not (r["system"] == "c1" and r["rep"] == 0)]
    results = compare(rows, "pil", metrics=["g"])
    assert {r["test"] for r in results} == {PAIRED_T, WILCOXON}
    assert {r["pairing"] for r in results} == {"rep"}
    assert {r["n"] for r in results} == {11}
    assert all("1 run(s) without a partner" in r["note"] for r in results)
    pil = [r["g"] for r in rows if r["system"] == "pil" and r["rate"] == 0.4 and r["rep"] != 0]
    c1 = [r["g"] for r in rows if r["system"] == "c1" and r["rate"] == 0.4]
    (row,) = [r for r in results if r["rate"] == "0.4" and r["test"] == PAIRED_T]
    assert row["p"] == pytest.approx(ttest_rel(pil, c1).pvalue, rel=1e-12)


def test_unpaired_design_uses_welch_and_says_so():
    rows = [{k: v for k, v in r.items() if k != "rep"} for r in _rows()]
    results = compare(rows, "pil", metrics=["g"])
    assert {r["test"] for r in results} == {WELCH}
    assert {r["pairing"] for r in results} == {"none"}
    pil = [r["g"] for r in rows if r["system"] == "pil" and r["rate"] == 0.4]
    c1 = [r["g"] for r in rows if r["system"] == "c1" and r["rate"] == 0.4]
    (row,) = [r for r in results if r["rate"] == "0.4"]
    assert row["p"] == pytest.approx(ttest_ind(pil, c1, equal_var=False).pvalue)


def test_a_constant_nonzero_difference_is_tested_by_neither_test():
    rows = [dict(r, g=round(r["g"])) for r in _rows() if r["system"] == "pil"]
    rows += [dict(r, system="c2", g=r["g"] + 110) for r in rows]
    results = compare(rows, "pil", metrics=["g"])
    assert {r["test"] for r in results} == {PAIRED_T, WILCOXON}
    for r in results:
        assert math.isnan(r["p"]) and math.isnan(r["p_holm"])
        assert math.isnan(r["ci_low"]) and math.isnan(r["ci_high"])  # never a zero-width CI
        assert r["mean_diff"] == -110 and r["note"] == CONSTANT_NOTE


def test_wilcoxon_rows_carry_the_hodges_lehmann_shift_and_its_own_interval():
    rows = _rows(n=15, seed=3)
    results = compare(rows, "pil", metrics=["g"])
    (t_row,) = [r for r in results if r["rate"] == "0.4" and r["test"] == PAIRED_T]
    (w_row,) = [r for r in results if r["rate"] == "0.4" and r["test"] == WILCOXON]
    pil = sorted((r for r in rows if r["system"] == "pil" and r["rate"] == 0.4), key=_rep)
    c1 = sorted((r for r in rows if r["system"] == "c1" and r["rate"] == 0.4), key=_rep)
    d = np.subtract([r["g"] for r in pil], [r["g"] for r in c1])
    walsh = [(d[i] + d[j]) / 2 for i in range(len(d)) for j in range(i, len(d))]
    assert w_row["estimator"] == "hodges-lehmann" and t_row["estimator"] == "mean"
    assert w_row["estimate"] == pytest.approx(np.median(walsh))
    assert (w_row["ci_low"], w_row["ci_high"]) != (t_row["ci_low"], t_row["ci_high"])
    assert w_row["mean_diff"] == t_row["mean_diff"]


def _rep(row: dict) -> int:
    return row["rep"]


@pytest.mark.parametrize("seed", [0, 1])
def test_hodges_lehmann_interval_is_the_signed_rank_tests_inversion(seed):
    """Just inside the interval scipy's exact Wilcoxon test of d - theta keeps theta (p > 0.05);
    just outside it rejects (p <= 0.05)."""
    d = np.random.default_rng(seed).normal(2.0, 3.0, 14)
    _est, low, high = hodges_lehmann(d)
    walsh = np.sort([(d[i] + d[j]) / 2 for i in range(14) for j in range(i, 14)])
    k = int(np.searchsorted(walsh, low))
    eps = 1e-9

    def p(theta: float) -> float:
        return float(wilcoxon(d - theta, method="exact").pvalue)

    assert walsh[k] == low
    assert p(low - eps) <= 0.05 < p(low + eps)
    assert p(high + eps) <= 0.05 < p(high - eps)
    assert math.isnan(hodges_lehmann(d[:5])[1])  # 5 pairs: no 95 % interval exists


def test_a_comparisons_holm_p_does_not_depend_on_what_else_ran():
    rows = _rows()
    rng = np.random.default_rng(7)
    for r in [r for r in rows if r["system"] == "c1"]:
        rows.append(dict(r, system="c3", g=r["g"] + rng.normal(-5, 1)))
    alone = compare([r for r in rows if r["system"] != "c3"], "pil", metrics=["g"])
    together = compare(rows, "pil", metrics=["g"])
    key = ("rate", "test", "system_b")
    want = {tuple(r[k] for k in key): r["p_holm"] for r in alone}
    got = {tuple(r[k] for k in key): r["p_holm"] for r in together if r["system_b"] == "c1"}
    assert got == want


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_holm_equals_statsmodels(seed: int) -> None:
    from statsmodels.stats.multitest import multipletests

    p = [*np.random.default_rng(seed).uniform(0, 0.2, 9).tolist(), 0.5, 0.0001]
    expected = multipletests(p, method="holm")[1]
    assert holm(p) == pytest.approx(list(expected), rel=1e-12)
    padded = multipletests([*p, 1.0, 1.0], method="holm")[1][: len(p)]
    assert holm(p, size=len(p) + 2) == pytest.approx(list(padded), rel=1e-12)


def test_a_declared_family_counts_its_missing_members_as_p_one():
    assert holm([0.01, 0.02], size=4) == pytest.approx([0.04, 0.06])
    assert holm([0.01, math.nan], size=3)[0] == pytest.approx(0.03)


def test_identical_systems_are_untestable_not_significant():
    rows = [dict(r, g=round(r["g"])) for r in _rows() if r["system"] == "pil"]
    rows += [dict(r, system="c2") for r in rows]
    results = compare(rows, "pil", metrics=["g"])
    assert all(math.isnan(r["p"]) and math.isnan(r["p_holm"]) for r in results)
    assert all(r["mean_diff"] == 0 for r in results)


def test_columns_and_unknown_baseline():
    results = compare(_rows(), "pil", metrics=["g"])
    assert list(results[0]) == csv_columns(("rate",))
    with pytest.raises(ReportError, match="valid choices: c1, pil"):
        compare(_rows(), "tamer", metrics=["g"])


def test_mean_ci_matches_the_t_interval():
    from scipy.stats import t

    values = [3.0, 5.0, 4.0, 8.0]
    mean, low, high = mean_ci(values)
    half = t.ppf(0.975, 3) * np.std(values, ddof=1) / 2
    assert (low, high) == pytest.approx((mean - half, mean + half))
    assert math.isnan(mean_ci([2.0])[1])
    assert math.isnan(mean_ci([3.0, 3.0, 3.0])[1])  # no spread: no interval, not [3, 3]
