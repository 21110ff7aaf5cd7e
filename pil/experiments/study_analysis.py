"""A study's conditions compared with the model its design calls for.

An *outcome* is one measure of the blocks (gestures, robot actions, ..., session time) or one
questionnaire score; its *observations* are one value per participant and block: participant,
group, condition, the block's position among the participant's analysed blocks (1, 2, ...),
value. For each outcome:

* **Pairwise tests** (:func:`compare_conditions`): a participant's value in a condition is the
  mean of their blocks in it. Each pair of conditions that at least two participants did both
  is compared within subjects: paired t and Wilcoxon signed-rank, the mean difference with its
  95 % interval and Cohen's d_z (:func:`pil.experiments.stats.paired`); otherwise between
  subjects: Welch's t with the mean difference, its interval and Cohen's d
  (:func:`pil.experiments.stats.welch`). Holm's correction runs over each instrument's
  family (every outcome and pair of the blocks' measures, or of one questionnaire).
* **A linear mixed model** (:func:`mixed_model`, statsmodels ``MixedLM``, REML) with the
  participant as a random intercept: ``value ~ C(condition) + position``, where the design has a
  between factor or a participant did several blocks of a condition. The condition terms are
  the differences to the first condition; ``position`` is the order effect per block.
* **Order effects** (:func:`order_effects`): the mean at each block position, and per
  condition and position.

Pure Python with scipy, statsmodels and pandas (statsmodels' own dependency): no MuJoCo.
"""

from __future__ import annotations

import math
import statistics
import warnings
from collections.abc import Mapping, Sequence
from itertools import combinations
from typing import Any

from pil.experiments.stats import holm, paired, welch

Observation = Mapping[str, Any]
MAX_NOTES = 4  # statsmodels' warnings kept per model (their first sentences)
MIN_PAIRED = 2  # participants who did both conditions for a within-subjects comparison


def participant_means(observations: Sequence[Observation]) -> dict[str, dict[str, float]]:
    """condition -> participant -> the mean of their blocks' values."""
    values: dict[str, dict[str, list[float]]] = {}
    for o in observations:
        values.setdefault(o["condition"], {}).setdefault(o["participant"], []).append(
            float(o["value"])
        )
    return {c: {p: statistics.fmean(v) for p, v in by.items()} for c, by in values.items()}


def compare_conditions(
    observations: Sequence[Observation], conditions: Sequence[str]
) -> list[dict[str, Any]]:
    """Every pair of ``conditions`` (in that order) compared as the module doc says."""
    means = participant_means(observations)
    out = []
    for a, b in combinations([c for c in conditions if c in means], 2):
        both = sorted(set(means[a]) & set(means[b]))
        n: Any
        if len(both) >= MIN_PAIRED:
            xs, ys = [means[a][p] for p in both], [means[b][p] for p in both]
            result, wilcoxon = paired(xs, ys)  # the t-test's row, the Wilcoxon's
            design, n = "within", len(both)
            extra = {"w": wilcoxon["statistic"], "p_w": wilcoxon["p"], "effect": "d_z"}
        else:
            xs, ys = list(means[a].values()), list(means[b].values())
            result = welch(xs, ys)
            design, n = "between", f"{len(xs)}/{len(ys)}"
            extra = {"w": math.nan, "p_w": math.nan, "effect": "d"}
        out.append(
            {
                "a": a,
                "b": b,
                "design": design,
                "test": result["test"],
                "n": n,
                "mean_a": statistics.fmean(xs) if xs else math.nan,
                "mean_b": statistics.fmean(ys) if ys else math.nan,
                "statistic": result["statistic"],
                "p": result["p"],
                "mean_diff": result["mean_diff"],
                "ci_low": result["ci_low"],
                "ci_high": result["ci_high"],
                "effect_size": result["effect_size"],
                **extra,
            }
        )
    return out


def needs_mixed(observations: Sequence[Observation], design: str) -> bool:
    """Whether the design calls for the mixed model: a between factor, or some participant
    with several blocks of one condition."""
    if design in ("between", "mixed"):
        return True
    seen: dict[tuple[str, str], int] = {}
    for o in observations:
        key = (o["participant"], o["condition"])
        seen[key] = seen.get(key, 0) + 1
    return any(n > 1 for n in seen.values())


def mixed_model(
    observations: Sequence[Observation], conditions: Sequence[str] = ()
) -> dict[str, Any]:
    """``value ~ C(condition) + position`` with a random intercept per participant (terms that
    do not vary are left out; the first of ``conditions`` present is the reference). Returns
    the formula, the fixed effects (term, coef, se, ci, p), the participants' variance,
    whether it converged, and statsmodels' warnings; or why it could not be fitted
    (``error``)."""
    import pandas as pd
    import statsmodels.formula.api as smf

    frame = pd.DataFrame(
        {k: [o[k] for o in observations] for k in ("participant", "condition", "position")}
    )
    present = [c for c in conditions if c in set(frame["condition"])]
    extra = sorted(set(frame["condition"]) - set(present))
    frame["condition"] = pd.Categorical(frame["condition"], categories=present + extra)
    frame["value"] = [float(o["value"]) for o in observations]
    participants = frame["participant"].nunique()
    terms = []
    if frame["condition"].nunique() > 1:
        terms.append("C(condition)")
    if frame.groupby("participant")["position"].nunique().max() > 1:
        terms.append("position")
    formula = "value ~ " + (" + ".join(terms) or "1")
    out: dict[str, Any] = {"formula": formula, "observations": len(frame)}
    out["participants"] = participants
    if participants < 2 or len(frame) <= participants or frame["value"].nunique() < 2:
        return {**out, "error": "too few participants, blocks or distinct values for a model"}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            fitted = smf.mixedlm(formula, frame, groups=frame["participant"]).fit(reml=True)
            intervals = fitted.conf_int()
            effects = [
                {
                    "term": str(term),
                    "coef": float(fitted.fe_params[term]),
                    "se": float(fitted.bse_fe[term]),
                    "ci_low": float(intervals.loc[term, 0]),
                    "ci_high": float(intervals.loc[term, 1]),
                    "p": float(fitted.pvalues[term]),
                }
                for term in fitted.fe_params.index
            ]
        except (ValueError, ArithmeticError, IndexError) as error:  # singular, degenerate
            return {**out, "error": f"not fitted: {type(error).__name__}: {error}"}
    variance = float(fitted.cov_re.iloc[0, 0]) if fitted.cov_re.size else math.nan
    notes = sorted({str(w.message).split(". ")[0].rstrip(".") for w in caught})[:MAX_NOTES]
    return {
        **out,
        "effects": effects,
        "participant_variance": variance,
        "residual_variance": float(fitted.scale),
        "converged": bool(fitted.converged),
        "notes": notes,
    }


def order_effects(observations: Sequence[Observation]) -> list[dict[str, Any]]:
    """The mean at each block position (condition ``all``) and per condition and position:
    n, mean and sd (NaN for one value)."""
    cells: dict[tuple[str, int], list[float]] = {}
    for o in observations:
        for condition in ("all", o["condition"]):
            cells.setdefault((condition, int(o["position"])), []).append(float(o["value"]))
    rows = []
    ranked = sorted(cells.items(), key=lambda kv: (kv[0][0] != "all", kv[0]))
    for (condition, position), values in ranked:
        rows.append(
            {
                "condition": condition,
                "position": position,
                "n": len(values),
                "mean": statistics.fmean(values),
                "sd": statistics.stdev(values) if len(values) > 1 else math.nan,
            }
        )
    return rows


def analyse(
    outcomes: Mapping[tuple[str, str], Sequence[Observation]],
    design: str,
    conditions: Sequence[str],
) -> dict[str, list[dict[str, Any]]]:
    """Every outcome ((instrument, variable) -> observations) analysed: ``tests`` (with
    ``p_holm`` and ``p_w_holm`` over each instrument's family), ``models`` and ``order``."""
    tests, models, order = [], [], []
    for (instrument, variable), observations in outcomes.items():
        head = {"instrument": instrument, "outcome": variable}
        tests += [{**head, **r} for r in compare_conditions(observations, conditions)]
        if needs_mixed(observations, design):
            models.append({**head, **mixed_model(observations, conditions)})
        order += [{**head, **r} for r in order_effects(observations)]
    for instrument in dict.fromkeys(t["instrument"] for t in tests):
        family = [t for t in tests if t["instrument"] == instrument]
        for key in ("p", "p_w"):
            for row, adjusted in zip(family, holm([r[key] for r in family]), strict=True):
                row[f"{key}_holm"] = adjusted
    return {"tests": tests, "models": models, "order": order}
