"""What a vision run takes as parameters (``--param lighting=0.3``): the camera conditions,
the person's looks (``skin``, ``pose_jitter``) and whether Robin adapts its gesture model to
the person (``adapt``, :mod:`robin_sim.vision.adapting`).

One source for their names, defaults and ranges: :class:`robin_sim.vision.eyes.EyeCondition`
checks its values against them, the episode's edge parses them apart from the run's
parameters (:func:`robin_sim.episode.config.parse_episode`) and a physical sweep checks them
before its first run.
Nothing here imports MuJoCo.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from pil.task.params import ParamSpec, parse_all

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
    "skin": ParamSpec(
        "skin",
        "float",
        None,
        "the person's skin tone, 0 (lightest) to 4 (darkest) on the five-tone scale",
        0.0,
        4.0,
        optional=True,
        empty="each performance draws a tone (a crowd, not one person)",
    ),
    "pose_jitter": ParamSpec(
        "pose_jitter",
        "float",
        1.0,
        "scale of how much the person's hand poses vary (1: usual, 2: twice as much)",
        0.0,
        2.5,
    ),
    "adapt": ParamSpec(
        "adapt",
        "bool",
        False,
        "Robin adapts its gesture model to the person from their feedback",
    ),
    "discarded_thumb": ParamSpec(
        "discarded_thumb",
        "choice",
        "approve",
        "a thumb the classifier discards: approve (no feedback counts as OK, eq. 1) or ask "
        "(the robot asks for the thumb again, up to twice more)",
        choices=("approve", "ask"),
    ),
}


@dataclass(frozen=True, slots=True)
class VisionSettings:
    """A vision run's settings, typed (parsed once by :func:`parse_conditions`)."""

    lighting: float
    camera_noise: float
    skin: float | None = None  # None: each performance draws a tone
    pose_jitter: float = 1.0
    adapt: bool = False
    discarded_thumb: str = "approve"


def parse_conditions(given: Mapping[str, Any]) -> VisionSettings:
    """The conditions ``given`` (text or numbers; missing: defaults), each checked by its spec
    (:func:`pil.task.params.parse_all`)."""
    return VisionSettings(**parse_all(CONDITION_PARAMS, given, "camera condition"))
