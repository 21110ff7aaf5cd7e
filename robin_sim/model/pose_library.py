"""The person's hand poses as joint angles, taken from real hands (``data/hand_poses.json``).

The library (made by ``tests/data/hands/make_poses.py`` from the hand tracker's readings of
real footage) holds per pose the joint angles of the model's hand
(:func:`robin_sim.model.names.person_hand_joints`, side prefix dropped) and per joint the spread
of the footage's frames, which a performance's seeded variation draws from.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np

from pil.errors import RobinPilError
from robin_sim.model import names

LIBRARY_FILE = "hand_poses.json"


@dataclass(frozen=True)
class PoseLibrary:
    """Joint angles (rad) and their per-joint spread per pose, in ``joints`` order."""

    joints: tuple[str, ...]  # without the side prefix, e.g. "thumb_cmc_abduct"
    angles: dict[str, np.ndarray]
    sd: dict[str, np.ndarray]
    sources: dict[str, str]

    def pose(self, name: str) -> np.ndarray:
        """A copy of pose ``name``'s joint angles."""
        return self.angles[name].copy()


@cache
def load_library() -> PoseLibrary:
    """The shipped library, checked against the model's joint names and the poses."""
    text = (resources.files("robin_sim.model") / "data" / LIBRARY_FILE).read_text()
    raw = json.loads(text)
    joints = tuple(raw["joints"])
    want = tuple(j.removeprefix("human_r_") for j in names.person_hand_joints("r"))
    if joints != want:
        raise RobinPilError(f"{LIBRARY_FILE}: joints {joints} differ from the model's {want}")
    missing = sorted(set(names.HUMAN_VIS_POSES) - set(raw["poses"]))
    if missing:
        raise RobinPilError(f"{LIBRARY_FILE}: no pose for {missing}")
    poses = raw["poses"]
    return PoseLibrary(
        joints,
        {k: np.array(v["angles"], float) for k, v in poses.items()},
        {k: np.array(v["sd"], float) for k, v in poses.items()},
        {k: str(v["source"]) for k, v in poses.items()},
    )
