"""One physical run as a flat results row: what ``robin-pil sweep --kind physical`` runs.

A run is an episode without video (:func:`robin_sim.episode.run.run_episode`), its step log and
summary written to a temporary folder that is removed afterwards; the row is the summary's
flat fields plus the fraction of legs delivered.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from pil.task.params import ASSEMBLY, ParamSpec
from robin_sim.episode.config import EpisodeConfig, EpisodeTask
from robin_sim.episode.run import run_episode

PHYSICAL_PARAMS: dict[str, ParamSpec] = {
    "tables": ASSEMBLY["tables"],
    "verify": ParamSpec("verify", "bool", False, "render checks after grasps and deliveries"),
}


def _config(
    system: str, rate: float, seed: int, out: Path, params: dict[str, Any]
) -> EpisodeConfig:
    options = dict(params)
    tables = PHYSICAL_PARAMS["tables"].parse(options.pop("tables", None), "tables")
    verify = PHYSICAL_PARAMS["verify"].parse(options.pop("verify", False), "verify")
    scenario = options.pop("scenario", None)
    return EpisodeConfig(
        tables=tables, rate=rate, seed=seed, system=system, scenario=scenario, out=out,
        video=False, verify=verify, progress=False, params=options,
    ).checked()  # fmt: skip


def check_physical(system: str, rate: float, seed: int, **params: Any) -> None:
    """Everything a physical run checks before it starts (parameters, the scenario, its
    layout's legs and spots); a sweep calls it before its first run."""
    EpisodeTask.of(_config(system, rate, seed, Path("."), params))


def run_physical(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """One physical run without video, as a flat results row (the sweep's physical kind).

    ``params`` are :data:`PHYSICAL_PARAMS` and any of :data:`pil.task.parts.PARAMS`; the step log
    and summary go to a temporary folder that is removed afterwards.
    """
    with tempfile.TemporaryDirectory(prefix="robin-physical-") as folder:
        summary = run_episode(_config(system, rate, seed, Path(folder), params))
    row = {key: value for key, value in summary.items() if not isinstance(value, dict)}
    row.pop("system_name", None)
    row["legs_delivered_fraction"] = summary["legs_delivered"] / summary["legs_total"]
    return row
