"""Tuning the reference agents on the development seeds, extending grids past their edges.

Every setting of an agent's grid (the product of its axes, ``tuning.grids`` of the suite)
runs on the tuning track under the tuning conditions on the *dev* seed block (the eval block
is never used: :func:`check_block` refuses it). A setting's score is its mean primary metric
over every run, a failed run counting as the cap (a setting is not rewarded for failing). When
the best setting sits on an axis's grid edge, the axis is extended one step beyond it (halved
or doubled on a log axis, by the edge spacing on a linear one, clipped to the axis's hard
bounds) and the new settings run, up to ``tuning.extend`` times; the result says for each
axis whether the optimum lies inside the grid or at a hard bound.
"""

from __future__ import annotations

import itertools
import math
import statistics
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from pil.bench.journal import Journal
from pil.bench.run import Entrant, run_bench
from pil.bench.suite import Axis, Suite, SuiteError

TUNING_BLOCK = "dev"


def check_block(block: str) -> None:
    """Tuning uses the development seeds only; the evaluation block is frozen."""
    if block != TUNING_BLOCK:
        raise SuiteError(
            f"tuning on the {block!r} seeds is refused: the evaluation block is frozen, tune on "
            f"--seeds {TUNING_BLOCK} (valid for tuning: {TUNING_BLOCK})"
        )


def _extend(axis: Axis, values: Sequence[float], best: float) -> float | None:
    """The next value beyond ``best`` when it sits on the grid's edge (None: inside, or at
    the hard bound)."""
    ordered = sorted(values)
    low, high = axis.bounds
    if best == ordered[0] and best > low:
        new = best / 2 if axis.scale == "log" else best - (ordered[1] - ordered[0])
        new = max(low, new)
    elif best == ordered[-1] and best < high:
        new = best * 2 if axis.scale == "log" else best + (ordered[-1] - ordered[-2])
        new = min(high, new)
    else:
        return None
    new = round(new, 6)
    return None if new in ordered else new


def where_optimum(axis: Axis, values: Sequence[float], best: float) -> str:
    """``inside`` the grid, ``at bound`` (the hard bound: no value beyond), or ``at edge``."""
    ordered = sorted(values)
    if ordered[0] < best < ordered[-1]:
        return "inside"
    if best in axis.bounds:
        return "at bound"
    return "at edge"


def tune(
    suite: Suite,
    agent: str,
    journal: Journal,
    *,
    quick: bool = False,
    workers: int = 1,
    progress: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """Tune ``agent`` (module docstring): its chosen parameters, every score, and where each
    axis's optimum lies."""
    check_block(str(journal.stamp["block"]))
    axes = suite.grids[agent]
    values = {a.name: list(a.values) for a in axes}
    seeds = suite.seeds(TUNING_BLOCK, quick)
    cap = suite.cap_of(suite.tuning_track)
    scores: dict[tuple[float, ...], float] = {}
    for _round in range(suite.extend + 1):
        settings = list(itertools.product(*(values[a.name] for a in axes)))
        entrants = [_entrant(agent, axes, s) for s in settings]
        rows = run_bench(
            suite,
            entrants,
            [suite.tuning_track],
            journal,
            seeds,
            workers=workers,
            progress=progress,
            conditions=suite.tuning_conditions,
        )
        tuned_rows = [r for r in rows if r["condition"] in suite.tuning_conditions]
        for setting, entrant in zip(settings, entrants, strict=True):
            mine = [r for r in tuned_rows if r["agent"] == entrant.name]
            scores[setting] = _score(mine, suite.primary, cap)
        best = min(scores, key=lambda s: (scores[s], s))
        grew = False
        for i, axis in enumerate(axes):
            new = _extend(axis, values[axis.name], best[i])
            if new is not None:
                values[axis.name].append(new)
                grew = True
        if not grew:
            break
    best = min(scores, key=lambda s: (scores[s], s))
    return {
        "agent": agent,
        "params": dict(zip((a.name for a in axes), best, strict=True)),
        "score": scores[best],
        "scores": [
            {"agent": agent, "params": _text(axes, s), "score": scores[s], "chosen": s == best}
            for s in sorted(scores)
        ],
        "optimum": {a.name: where_optimum(a, values[a.name], best[i]) for i, a in enumerate(axes)},
        "grid": {a.name: sorted(values[a.name]) for a in axes},
    }


def _score(rows: Sequence[Mapping[str, Any]], metric: str, cap: float) -> float:
    """The mean metric, a failed run counting as ``cap`` x its scripted gestures (the most a
    run may cost)."""
    if not rows:
        return math.inf
    values = [
        cap * float(r["scripted"]) if math.isnan(float(r[metric])) else float(r[metric])
        for r in rows
    ]
    return statistics.fmean(values)


def _text(axes: Sequence[Axis], setting: Sequence[float]) -> str:
    return " ".join(f"{a.name}={v:g}" for a, v in zip(axes, setting, strict=True))


def _entrant(agent: str, axes: Sequence[Axis], setting: Sequence[float]) -> Entrant:
    params = dict(zip((a.name for a in axes), setting, strict=True))
    return Entrant(f"{agent} {_text(axes, setting)}", agent, params)
