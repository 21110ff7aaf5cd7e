"""One physical run as a flat results row: what ``robin-pil sweep --kind physical`` runs.

A run is an episode without video (:func:`robin_sim.episode.run.run_episode`), its step log and
summary written to a temporary folder that is removed afterwards; the row is the summary's
flat fields plus the fraction of legs delivered.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from pil.task.parts import check_params
from robin_sim.episode.run import EpisodeConfig, run_episode

PHYSICAL_PARAMS: dict[str, Any] = {"tables": None, "verify": False}


def run_physical(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """One physical run without video, as a flat results row (the sweep's physical kind).

    ``params`` are :data:`PHYSICAL_PARAMS` and any of :data:`pil.task.parts.PARAMS`; the step log
    and summary go to a temporary folder that is removed afterwards.
    """
    options = {**PHYSICAL_PARAMS, **params}
    tables, verify = options.pop("tables"), bool(options.pop("verify"))
    tables = None if tables is None else int(tables)
    check_params(options)
    with tempfile.TemporaryDirectory(prefix="robin-physical-") as folder:
        config = EpisodeConfig(
            tables=tables, rate=rate, seed=seed, system=system, out=Path(folder), video=False,
            verify=verify, progress=False, params=options,
        )  # fmt: skip
        summary = run_episode(config)
    row = {key: value for key, value in summary.items() if not isinstance(value, dict)}
    row.pop("system_name", None)
    row["legs_delivered_fraction"] = summary["legs_delivered"] / summary["legs_total"]
    return row
