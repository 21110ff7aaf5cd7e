"""How the robot reads the person in an episode: the study's detectors, or its own eye cameras.

``--detector vision`` (``params["detector"] == "vision"``) makes Robin read every gesture and
every thumb from its eye cameras (:class:`robin_sim.vision.detector.VisionDetector`): the
detection rate is then measured, not drawn, and set by the camera conditions ``lighting`` and
``camera_noise`` (``--param lighting=0.3``). Any other detector is the study's
(:mod:`pil.task.detector`), which reads thumbs right.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pil.errors import RobinPilError
from pil.task.parts import derive_seeds
from robin_sim.vision.condition_params import CONDITION_PARAMS

VISION = "vision"
VISION_PARAMS: tuple[str, ...] = tuple(CONDITION_PARAMS)  # the camera conditions' names


def split_params(params: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The run's parameters (the vision detector replaced by the study's exact one, whose draws
    it then ignores) and the camera conditions (None unless the detector is ``vision``)."""
    run = dict(params)
    conditions = {name: run.pop(name) for name in VISION_PARAMS if name in run}
    if str(run.get("detector", "")) != VISION:
        if conditions:
            raise RobinPilError(
                f"{', '.join(conditions)} set the eye cameras' conditions and need "
                f"--detector {VISION}; valid detectors: exact, independent, vision, "
                "measured:FILE"
            )
        return run, None
    run["detector"] = "exact"
    return run, conditions


def vision_detector(world: Any, display: Any, conditions: Mapping[str, Any], seed: int) -> Any:
    """The eye-camera detector for ``world`` (the person's hand shown through ``display``)."""
    from robin_sim.vision.detector import VisionDetector

    detector_seed = derive_seeds(seed)["test_detector"]
    return VisionDetector.from_params(world.sim, conditions, display=display, seed=detector_seed)
