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
from dataclasses import replace
from pathlib import Path
from typing import Any

from pil.errors import InvalidChoiceError, RobinPilError
from pil.experiments.systems import check_system, run_checked
from pil.task.detector import CAMERAS
from pil.task.params import ASSEMBLY, PARAMS, RUN_OPTIONS, ParamSpec
from pil.task.spec import DETECTOR_SPECS, PHYSICAL, build_run_spec
from robin_sim.episode.config import DEFAULT_TABLES, NO_VIDEO, EpisodeSpec
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


def _spec(system: str, rate: float, seed: int, params: dict[str, Any]) -> EpisodeSpec:
    """The episode of a sweep's grid row, whose values the grid parsed by
    :data:`PHYSICAL_PARAMS` and the run parameters (typed: nothing is parsed again)."""
    options = dict(params)
    verify = bool(options.pop("verify", PHYSICAL_PARAMS["verify"].default))
    scenario = options.pop("scenario", None)
    given = {name: options.pop(name) for name in CONDITION_PARAMS if name in options}
    if options.get("tables") is None:
        options.pop("tables", None)
        if scenario is None:
            options["tables"] = DEFAULT_TABLES  # as the episode: one table of the assembly
    run = build_run_spec(
        system=system, rate=rate, seed=seed, scenario=scenario, values=options, world=PHYSICAL
    )
    vision = run.detector.model == CAMERAS
    if given and not vision:
        raise RobinPilError(
            f"{', '.join(given)} are the eye cameras' parameters and need --detector {CAMERAS} "
            f"(or --param detector={CAMERAS})"
        )
    defaults = {name: spec.default for name, spec in CONDITION_PARAMS.items()}
    conditions = VisionSettings(**{**defaults, **given}) if vision else None
    return EpisodeSpec(run, conditions, NO_VIDEO, verify, False, Path("."))


def check_physical(system: str, rate: float, seed: int, **params: Any) -> None:
    """What a sweep grid cannot check value by value, for a row it parsed: the scenario, its
    layout's legs and spots, the camera conditions' detector; a sweep calls it once per
    distinct cell before its first run."""
    from robin_sim.episode.assemble import layout_of  # imports MuJoCo

    layout_of(_spec(system, rate, seed, params).run.scenario)


# relative cost of what a physical run does, in simulated seconds (bench/README.md): an
# approved action moves (object 1.9, close 0.8, human 7.6, open with the carry to the bin 11.6:
# about 5.5 on average), a rejected one is shown for 30 % of its path and taken back
APPROVED_S, REJECTED_S = 5.5, 1.5


def expected_cost(system: str, rate: float, seed: int, **params: Any) -> float:
    """Expected simulated seconds of a physical run, from its learner-only twin.

    The physical episode makes the same decisions as the learner-only run with the same
    arguments (when every action succeeds physically), which takes milliseconds: its action
    counts predict the physical run's length.
    """
    options = {k: v for k, v in params.items() if k not in PHYSICAL_PARAMS}
    if params.get("detector") not in (None, CAMERAS):
        options["detector"] = params["detector"]  # the eye cameras' twin: the exact detector
    tables = params.get("tables")  # parsed by the grid
    if tables is None and options.get("scenario") is None:
        tables = 1  # as the episode: one table of the paper's assembly
    row = run_checked(system, rate, seed, tables=tables, **options)
    rejected = row["rejected"]
    return APPROVED_S * (row["actions"] - rejected) + REJECTED_S * rejected


def run_physical(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """One physical run without video, as a flat results row (the sweep's physical kind).

    ``params`` are :data:`PHYSICAL_PARAMS` and any of :data:`pil.task.params.PARAMS`, given as
    text or typed: each is parsed here by its spec (a sweep's worker runs
    :func:`run_physical_checked` on values its grid parsed); the step log and summary go to a
    temporary folder that is removed afterwards.
    """
    from pil.task.params import RATE, SEED

    specs = {**PARAMS, **RUN_OPTIONS, **PHYSICAL_PARAMS}
    for name in params:
        if name not in specs:
            raise InvalidChoiceError("physical parameter", name, specs)
    parsed = {name: specs[name].parse(value) for name, value in params.items()}
    check_system(system)
    rate, seed = RATE.parse(rate, "detection rate"), SEED.parse(seed, "seed")
    return run_physical_checked(system, rate, seed, **parsed)


def run_physical_checked(system: str, rate: float, seed: int, **params: Any) -> dict[str, Any]:
    """:func:`run_physical` of a sweep grid's row, whose values the grid parsed (typed,
    trusted): what a sweep's worker runs, so no value is checked again there."""
    spec = _spec(system, rate, seed, params)
    if spec.run.detector.model == CAMERAS:
        from robin_sim.render.gl_backend import ensure_gl_backend

        ensure_gl_backend()  # the eye cameras render
    with tempfile.TemporaryDirectory(prefix="robin-physical-") as folder:
        summary = run_episode(replace(spec, out=Path(folder)))
    row = {key: value for key, value in summary.items() if not isinstance(value, dict)}
    row.pop("system_name", None)
    row["legs_delivered_fraction"] = summary["legs_delivered"] / summary["legs_total"]
    for key, value in summary.get("vision", {}).items():
        if not isinstance(value, dict):
            row[VISION_PREFIX + key] = value
    return row
