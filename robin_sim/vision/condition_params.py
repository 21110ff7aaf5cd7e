"""The camera conditions a vision run takes as parameters (``--param lighting=0.3``).

One source for their names, defaults and ranges: :class:`robin_sim.vision.eyes.Condition`
checks its values against them, the episode splits them off its parameters
(:mod:`robin_sim.episode.reading`) and a physical sweep checks them before its first run.
Nothing here imports MuJoCo.
"""

from __future__ import annotations

from pil.task.params import ParamSpec

CONDITION_PARAMS: dict[str, ParamSpec] = {
    "lighting": ParamSpec(
        "lighting",
        "float",
        1.0,
        "scale of the scene's light for the eye cameras (1: as built)",
        0.0,
        5.0,
    ),
    "camera_noise": ParamSpec(
        "camera_noise",
        "float",
        0.0,
        "sd of the eye cameras' pixel noise, 8-bit units",
        0.0,
        128.0,
    ),
}
