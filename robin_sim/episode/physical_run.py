"""One physical run as a flat results row: what ``robin-pil sweep --kind physical`` runs.

A run is an episode without video (:func:`robin_sim.episode.run.run_episode`), its step log and
summary written to a temporary folder that is removed afterwards; the row is the summary's
flat fields plus the fraction of legs delivered. With ``detector=vision`` Robin reads every
gesture and thumb with its eye cameras under the camera conditions ``lighting`` and
``camera_noise`` (sweepable parameters); the row then carries the summary's ``vision`` block's
numbers as ``vision_*`` columns (``vision_detection_rate``: the measured d).
"""

from __future__ import annotations

import tempfile
from collections.abc import MutableMapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError
from pil.experiments.run_row import spec_row
from pil.experiments.sweep_kinds import BOUND_AS, GridRow, SweepKind, scenario_of
from pil.task.assemble import cached
from pil.task.detector import CAMERAS, EXACT
from pil.task.params import ASSEMBLY, PARAMS, RUN_OPTIONS, ParamSpec
from pil.task.spec import DETECTOR_SPECS, PHYSICAL, SYMBOLIC, build_run_spec
from pil.task.systems import SYSTEM_SPECS
from robin_sim.episode.config import DEFAULT_TABLES, NO_VIDEO, EpisodeSpec, sim_time_limit
from robin_sim.episode.run import run_episode
from robin_sim.vision.condition_params import CONDITION_PARAMS, VisionSettings

PHYSICAL_PARAMS: dict[str, ParamSpec] = {
    "tables": ASSEMBLY["tables"],
    "verify": ParamSpec("verify", "bool", False, "render checks after grasps and deliveries"),
    # a physical run may read with the eye cameras, under camera conditions
    "detector": DETECTOR_SPECS[PHYSICAL],
    **CONDITION_PARAMS,
}
VISION_PREFIX = "vision_"  # the vision block's numbers in a results row


def parse_physical(row: GridRow, cache: MutableMapping[Any, Any]) -> EpisodeSpec:
    """The episode of a sweep's grid row, whose values the grid parsed by
    :data:`PHYSICAL_PARAMS` and the run parameters (typed: nothing is parsed again; the
    scenario file read once per cell)."""
    made = cached(cache, ("physical", row.cell), lambda: _cell_spec(dict(row.params), cache))
    return replace(made, run=made.run.for_run(row.system, row.rate, row.seed))


def _cell_spec(options: dict[str, Any], cache: MutableMapping[Any, Any]) -> EpisodeSpec:
    """The episode of a cell's typed values (system pil, rate 1, seed 0: set per row)."""
    verify = bool(options.pop("verify", PHYSICAL_PARAMS["verify"].default))
    name = options.pop("scenario", None)
    scenario = scenario_of(name, cache)
    given = {name: options.pop(name) for name in CONDITION_PARAMS if name in options}
    if options.get("tables") is None:
        options.pop("tables", None)
        if name is None:
            options["tables"] = DEFAULT_TABLES  # as the episode: one table of the assembly
    run = build_run_spec(
        system="pil", rate=1.0, seed=0, scenario=scenario, values=options, world=PHYSICAL
    )
    vision = run.detector.model == CAMERAS
    if given and not vision:
        raise RobinPilError(
            f"{', '.join(given)} are the eye cameras' parameters and need --detector {CAMERAS} "
            f"(or --param detector={CAMERAS})"
        )
    defaults = {name: spec.default for name, spec in CONDITION_PARAMS.items()}
    conditions = VisionSettings(**{**defaults, **given}) if vision else None
    limit = sim_time_limit(run.scenario)
    return EpisodeSpec(run, conditions, NO_VIDEO, verify, False, Path("."), limit)


def check_physical(spec: EpisodeSpec) -> None:
    """What a sweep grid cannot check value by value: the scenario's layout's legs and spots;
    a sweep calls it once per distinct cell before its first run."""
    from robin_sim.episode.physical_assembly import layout_of  # imports MuJoCo

    layout_of(spec.run.scenario)


# relative cost of what a physical run does, in simulated seconds (bench/README.md): an
# approved action moves (object 1.9, close 0.8, human 7.6, open with the carry to the bin 11.6:
# about 5.5 on average), a rejected one is shown for 30 % of its path and taken back
APPROVED_S, REJECTED_S = 5.5, 1.5


def physical_cost(spec: EpisodeSpec) -> float:
    """Expected simulated seconds of a physical run, from its learner-only twin.

    The physical episode makes the same decisions as the learner-only run of the same spec
    (when every action succeeds physically), which takes milliseconds: its action counts
    predict the physical run's length. The eye cameras' twin reads with the exact detector.
    """
    run = spec.run
    if run.detector.model == CAMERAS:
        run = replace(run, detector=replace(run.detector, model=EXACT))
    row = spec_row(replace(run, world=SYMBOLIC))
    rejected = row["rejected"]
    return APPROVED_S * (row["actions"] - rejected) + REJECTED_S * rejected


def physical_row(spec: EpisodeSpec) -> dict[str, Any]:
    """One physical run without video, as a flat results row (the sweep's physical kind):
    the step log and summary go to a temporary folder that is removed afterwards."""
    if spec.run.detector.model == CAMERAS:
        from robin_sim.render.gl_backend import ensure_gl_backend

        ensure_gl_backend()  # the eye cameras render
    with tempfile.TemporaryDirectory(prefix="robin-physical-") as folder:
        summary = run_episode(replace(spec, out=Path(folder)))
    row = {key: value for key, value in summary.items() if not isinstance(value, dict)}
    row.pop("system_name", None)
    row["ended"] = row.pop("status")  # finished, or time_limit (a sweep's status: ok / failed)
    row["legs_delivered_fraction"] = summary["legs_delivered"] / summary["legs_total"]
    for key, value in summary.get("vision", {}).items():
        if not isinstance(value, dict):
            row[VISION_PREFIX + key] = value
    return row


PHYSICAL_RUNS = SweepKind(
    name="physical",
    function=BOUND_AS["physical"],
    params=dict(sorted({**PARAMS, **RUN_OPTIONS, **PHYSICAL_PARAMS}.items())),
    systems=tuple(SYSTEM_SPECS),
    parse=parse_physical,
    run=physical_row,
    check=check_physical,
    cost=physical_cost,
)
