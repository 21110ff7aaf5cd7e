"""A mixed model beside the paired tests: the agent's effect over every condition at once.

:func:`agent_effect` fits ``metric ~ C(agent) + C(condition)`` with a random intercept per
seed (``statsmodels`` ``MixedLM``, REML) to two agents' complete pairs: the condition (the
detection rate or noise model) is fixed, the seed random, as the runs of one seed share the
handover order and the readings. It returns the agent's coefficient (entrant - anchor), its
95 % interval and p, or NaNs with the reason when the model cannot be fitted (fewer than
:data:`MIN_SEEDS` seeds, no spread, no convergence).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any

MIN_SEEDS = 5  # a random intercept per seed needs a few seeds (quick runs have 3)


def agent_effect(
    rows: Sequence[Mapping[str, Any]], entrant: str, anchor: str, metric: str
) -> dict[str, Any]:
    """The entrant's effect against the anchor (module docstring)."""
    import pandas as pd
    import statsmodels.formula.api as smf

    out: dict[str, Any] = {
        "coef": math.nan,
        "ci_low": math.nan,
        "ci_high": math.nan,
        "p": math.nan,
        "note": "",
    }
    frame = pd.DataFrame(
        [
            {
                "y": float(r[metric]),
                "agent": "b" if r["agent"] == entrant else "a",
                "condition": str(r["condition"]),
                "seed": str(r["seed"]),
            }
            for r in rows
            if r["agent"] in (entrant, anchor)
        ]
    )
    if frame.empty or frame["agent"].nunique() < 2 or frame["y"].std() == 0:
        out["note"] = "no spread or no pairs"
        return out
    if frame["seed"].nunique() < MIN_SEEDS:
        out["note"] = f"fewer than {MIN_SEEDS} seeds"
        return out
    formula = "y ~ C(agent) + C(condition)" if frame["condition"].nunique() > 1 else "y ~ C(agent)"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = smf.mixedlm(formula, frame, groups=frame["seed"]).fit(reml=True)
    except (ValueError, ArithmeticError, RuntimeError) as error:
        out["note"] = f"not fitted: {error}"
        return out
    name = "C(agent)[T.b]"
    low, high = fit.conf_int().loc[name]
    out.update(
        coef=float(fit.params[name]),
        ci_low=float(low),
        ci_high=float(high),
        p=float(fit.pvalues[name]),
        note="" if fit.converged else "did not converge",
    )
    return out
